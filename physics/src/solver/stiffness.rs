//! The operator of the stable-step estimate (model §6.1), y = M^{-½} K M^{-½} q at the
//! current state, and the buffers every estimate reuses (`solver/stable_step.rs`).

use super::boundary::NONE;
use super::lanczos::{dof_chunks, dof_sum, LanczosWork};
use super::{ElementLoop, Simulation};
use crate::kernels::AssemblyScratch;
use crate::kernels::Planes;
use crate::team::SharedSlice;

/// What the stable-step estimates keep from one estimate to the next, so that an estimate
/// allocates no mesh-sized vector once the first has sized them, and costs per Lanczos iteration
/// one internal-force assembly (the step's own kernel, on the step's thread team) and a few
/// streaming passes over the degrees of freedom.
#[derive(Debug, Default, Clone)]
pub(super) struct EstimateCache {
    /// Prescribed degrees of freedom (node·3 + component) and M^{-½}, 0 on them (they never
    /// change), and ε's length scale, 1e-6 of the smallest reference edge (empty until the
    /// first).
    mask: Vec<bool>,
    sqrt_inv_m: Vec<f64>,
    eps_len: f64,
    /// The pseudo-random part of the start vector (zero on prescribed components) and its
    /// norm, fixed with the mask.
    random: Vec<f64>,
    random_norm: f64,
    /// U + εx and F_int(U + εx), F_int(U) when the step's own is not current.
    up: Planes,
    fp: Planes,
    f0: Planes,
    /// (degree of freedom, W g_N(α)) of the glued nodes' free components in this estimate,
    /// by degree of freedom, the springs of a node on several interfaces summed.
    springs: Vec<(usize, f64)>,
    /// Per-chunk results of the parallel passes.
    parts: AssemblyScratch,
    maxima: Vec<f64>,
    sums: Vec<f64>,
    units: Vec<()>,
    /// The Lanczos start vector and the Lanczos run's vectors.
    pub start: Vec<f64>,
    pub work: LanczosWork,
}

/// y = M^{-½} K M^{-½} q at `sim`'s state (model §6.1): K q matrix-free as the forward
/// difference (F_int(U + ε x) − F_int(U))/ε, x = M^{-½} q, with ε = 1e-6 of the smallest edge
/// over max|x|, plus the interface springs W g_N(α) of glued nodes; prescribed components are
/// removed (rows and columns zero).
pub(super) struct StiffnessOperator<'a> {
    sim: &'a Simulation,
    elements: ElementLoop<'a>,
    /// F_int(U), the base of the difference: the step's own (stage 3 has just computed it at
    /// U) or `cache.f0`.
    forces_current: bool,
    pub cache: &'a mut EstimateCache,
}

impl<'a> StiffnessOperator<'a> {
    /// The operator at `sim`'s state, with the interface springs or without them; with
    /// `forces_current`, F_int(U) is the step's own, otherwise it is assembled here into
    /// `cache`, whose buffers the operator uses.
    pub fn new(
        sim: &'a Simulation,
        springs: bool,
        forces_current: bool,
        cache: &'a mut EstimateCache,
    ) -> Self {
        let elements = ElementLoop {
            model: &sim.model,
            classes: &sim.work.classes,
            blocks: &sim.work.blocks,
            team: sim.work.team.as_ref(),
            prefetch: sim.work.prefetch,
        };
        let nodes = sim.state.u.len();
        if cache.mask.len() != 3 * nodes {
            cache.mask = prescribed_mask(sim);
            cache.sqrt_inv_m = (0..3 * nodes)
                .map(|k| {
                    if cache.mask[k] {
                        0.0
                    } else {
                        sim.setup.inv_mass[k / 3].sqrt()
                    }
                })
                .collect();
            cache.eps_len = 1e-6 * sim.model.mesh.min_edge();
            cache.up = Planes::zeros(nodes);
            cache.fp = Planes::zeros(nodes);
            cache.random = (cache.mask.iter().enumerate())
                .map(|(k, &m)| if m { 0.0 } else { splitmix(k as u64) })
                .collect();
            cache.random_norm = cache.random.iter().map(|x| x * x).sum::<f64>().sqrt();
        }
        if !forces_current {
            if cache.f0.len() == nodes {
                cache.f0.fill_zero();
            } else {
                cache.f0 = Planes::zeros(nodes);
            }
            // (The smallest J is not used here: no corner check.)
            elements.assemble(
                &sim.state.u,
                &mut cache.f0,
                false,
                &mut cache.parts,
                f64::NEG_INFINITY,
            );
        }
        cache.springs.clear();
        for itf in sim.state.interface_nodes.iter().filter(|_| springs) {
            let law = &sim.model.interfaces[itf.interface as usize].law;
            let ks = itf.area * law.spring_stiffness(itf.alpha);
            let i = itf.node as usize;
            let free = (3 * i..3 * i + 3).filter(|&k| !cache.mask[k]);
            cache.springs.extend(free.map(|k| (k, ks)));
        }
        if springs {
            sim.bond_springs(&cache.mask, &mut cache.springs);
        }
        // By degree of freedom (a stable sort: a node's interfaces stay in order), merged.
        cache.springs.sort_by_key(|&(k, _)| k);
        cache.springs.dedup_by(|next, kept| {
            let same = next.0 == kept.0;
            if same {
                kept.1 += next.1;
            }
            same
        });
        StiffnessOperator {
            sim,
            elements,
            forces_current,
            cache,
        }
    }

    /// Sets `cache.start` to the Lanczos start: the previous Ritz vector `warm` (warm start)
    /// plus a deterministic pseudo-random vector so that every mode is represented.
    pub fn start_vector(&mut self, warm: Option<&[f64]>) {
        let team = self.sim.work.team.as_ref();
        let c = &mut *self.cache;
        let n = c.mask.len();
        c.start.resize(n, 0.0);
        let nw = match warm.filter(|w| w.len() == n) {
            Some(w) => dof_sum(team, n, &mut c.sums, |a, b| {
                w[a..b].iter().map(|x| x * x).sum()
            })
            .sqrt(),
            None => 0.0,
        };
        let (r, ns) = (&c.random[..], c.random_norm);
        let start = SharedSlice::new(&mut c.start);
        // SAFETY: range a..b of `start` is touched by this item only.
        dof_chunks(team, n, &mut c.units, |a, b| unsafe {
            let start = start.range(a, b);
            match warm.filter(|_| nw > 0.0) {
                Some(w) => {
                    for (k, sk) in (a..b).zip(start.iter_mut()) {
                        *sk = w[k] / nw + 1e-3 * r[k] / ns;
                    }
                }
                None => start.copy_from_slice(&r[a..b]),
            }
        });
    }

    /// Adds to the start (of norm about 1) a unit pseudo-random vector on the free components
    /// of `element`'s nodes. Under compression the stiffest mode sits at the most compressed
    /// element, which moves with the compression wave: a start from the previous top Ritz
    /// vector alone would need many iterations to reach it (K couples neighbours only, one
    /// layer of elements per iteration), and could stop on a lower, local mode with a small
    /// residual.
    pub fn add_local_start(&mut self, element: usize) {
        let mesh = &self.sim.model.mesh;
        if element >= mesh.element_count() {
            return;
        }
        let conn = mesh.element_nodes(element);
        let (mask, start) = (&self.cache.mask, &mut self.cache.start);
        let dofs = || {
            (conn.iter())
                .flat_map(|&a| (0..3).map(move |i| 3 * a as usize + i))
                .filter(|&k| !mask[k])
        };
        let norm = dofs()
            .map(|k| splitmix(k as u64).powi(2))
            .sum::<f64>()
            .sqrt();
        if norm > 0.0 {
            for k in dofs() {
                start[k] += splitmix(k as u64) / norm;
            }
        }
    }

    /// y = M^{-½} K M^{-½} q; returns qᵀy (summed by chunks in order, the Lanczos α). The
    /// streaming passes run on the step's team, each participant on its own contiguous share
    /// of the degrees of freedom, the share it has in the step's node loops: U + εx and the
    /// zeroed F are written where the element loop's threads read and add to them (written by
    /// one thread, they cost the other a transfer from its cache at every assembly, which
    /// slowed the assembly markedly; docs: performance log).
    pub fn apply(&mut self, q: &[f64], y: &mut [f64]) -> f64 {
        let team = self.sim.work.team.as_ref();
        let c = &mut *self.cache;
        // s = M^{-½} is 0 on the prescribed components, which removes them: x = sq and
        // y = sKx vanish there.
        let s = &c.sqrt_inv_m[..];
        let u = self.sim.state.u.as_slice();
        let f0 = if self.forces_current {
            self.sim.state.f_int.as_slice()
        } else {
            c.f0.as_slice()
        };
        // Degree of freedom k = 3i + c (node i, component c) in the planes of F.
        let nodes = self.sim.state.u.len();
        let at = |p: &[f64], k: usize| p[(k % 3) * nodes + k / 3];
        let n = s.len();
        let x = |k: usize| q[k] * s[k];
        dof_chunks(team, n, &mut c.maxima, |a, b| {
            (a..b).fold(0.0f64, |m, k| m.max(x(k).abs()))
        });
        let xmax = c.maxima.iter().fold(0.0f64, |m, &x| m.max(x));
        if xmax == 0.0 {
            y.fill(0.0);
            return 0.0;
        }
        let eps = c.eps_len / xmax;
        let up = c.up.planes_mut().map(SharedSlice::new);
        let fp = c.fp.planes_mut().map(SharedSlice::new);
        // SAFETY: dofs a..b (nodes a/3..b/3: DOF_GRAIN is a multiple of 3) of `up` and `fp`
        // are touched by this item only.
        dof_chunks(team, n, &mut c.units, |a, b| unsafe {
            let (na, nb) = (a / 3, b / 3);
            for comp in 0..3 {
                for (i, upk) in up[comp].range(na, nb).iter_mut().enumerate() {
                    let k = 3 * (na + i) + comp;
                    *upk = at(u, k) + eps * x(k);
                }
                fp[comp].range(na, nb).fill(0.0);
            }
        });
        self.elements
            .assemble(&c.up, &mut c.fp, false, &mut c.parts, f64::NEG_INFINITY);
        let fp = c.fp.as_slice();
        // K x of the bulk, plus a glued node's spring W g_N(α) x, then M^{-½}; and qᵀy.
        let springs = &c.springs[..];
        let yy = SharedSlice::new(y);
        // SAFETY: range a..b of `y` is touched by this item only.
        dof_sum(team, n, &mut c.sums, |a, b| unsafe {
            let y = yy.range(a, b);
            for (k, yk) in (a..b).zip(y.iter_mut()) {
                *yk = (at(fp, k) - at(f0, k)) / eps * s[k];
            }
            let first = springs.partition_point(|&(k, _)| k < a);
            for &(k, ks) in springs[first..].iter().take_while(|&&(k, _)| k < b) {
                y[k - a] = ((at(fp, k) - at(f0, k)) / eps + ks * x(k)) * s[k];
            }
            q[a..b].iter().zip(y.iter()).map(|(qk, yk)| qk * yk).sum()
        })
    }
}

/// Prescribed degrees of freedom (node·3 + component), true where prescribed.
fn prescribed_mask(sim: &Simulation) -> Vec<bool> {
    let mut mask = vec![false; 3 * sim.state.u.len()];
    for b in &sim.state.boundary.nodes {
        for c in 0..3 {
            if b.prescribed[c] != NONE {
                mask[3 * b.node as usize + c] = true;
            }
        }
    }
    mask
}

/// A deterministic pseudo-random number in [−1, 1) (splitmix64 of the index).
fn splitmix(k: u64) -> f64 {
    let mut z = k.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}
