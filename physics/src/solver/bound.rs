//! A rigorous upper bound of ω_max² = λ_max(M⁻¹K) at the current state (model §6.4),
//! element by element: the guard that lets a cheap, warm-started
//! Lanczos update stand where it would otherwise be converged (`stable_step.rs`).
//!
//! *Derivation.* K is the tangent of F_int at U (total Lagrangian), so for a virtual
//! displacement x, xᵀKx = Σ_e Σ_q w_q det J₀ G_q : A(F_q) : G_q with G_q = Σₐ xₐ ⊗ ∇ₓNₐ(ξ_q) and
//! A = ∂P/∂F, plus, with one-point integration, the hourglass term k Σᵅ |Σₐ γₐᵅ xₐ|² (linear,
//! constant k), plus the glue springs Σᵢ W kᵢ |xᵢ|². Pointwise G:A(F):G ≤ a(F)|G|² with a(F) of
//! [`modulus_bound`]; |G_q|² summed with the weights is Σᵢ x_{e,i}ᵀ L_e x_{e,i}, L_e the element's
//! scalar Laplacian (8×8, the same quadrature), and x_{e,i}ᵀ L_e x_{e,i} ≤ g_e x_{e,i}ᵀ M_e
//! x_{e,i} with g_e = λ_max(M_e^{-½} L_e M_e^{-½}), M_e = ρ diag(∫Nₐ dV) the element's share of
//! the lumped mass (M = Σ_e M_e). Summing over the elements (Irons' element bound):
//!
//!   ω_max² ≤ max_e (a_e g_e + g_hg,e) + max_i W kᵢ/mᵢ,                               (B)
//!
//! a_e = max_q a(F_q), g_hg,e = λ_max(M_e^{-½} K_hg,e M_e^{-½}); the springs add by
//! λ_max(X + Y) ≤ λ_max(X) + λ_max(Y) on M^{-½}(·)M^{-½}. Removing prescribed components
//! (rows and columns) only lowers λ_max (Cauchy interlacing). g_e and g_hg,e depend on the
//! reference geometry only and are computed once per element class; a_e costs one pass over
//! the elements computing F at the integration points (no stress), about an assembly.

use super::Simulation;
use crate::kernels::Planes;
// The AVX builds exist on x86_64 only (wasm32 runs the portable one).
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_imports))]
use crate::kernels::simd::{simd_dispatch, ISA_AVX2, ISA_AVX512};
use crate::material::{with_law, Law, Material};
use crate::mesh::ElementClasses;
use crate::model::Integration;
use crate::tunables::{BOUND_ELEMENT_CHUNK, BOUND_ROUNDING_SLACK};
use nalgebra::{DMatrix, SymmetricEigen};

/// What the bound keeps between calls: g_e and g_hg,e per element class (empty until the
/// first call) and the per-chunk maxima and per-node spring sums of the pass.
#[derive(Debug, Default, Clone)]
pub(super) struct BoundCache {
    class_g: Vec<[f64; 2]>,
    maxima: Vec<f64>,
    node_springs: Vec<f64>,
    spring_nodes: Vec<usize>,
}

/// Upper bound a(F) of the pointwise tangent modulus, G : A(F) : G ≤ a(F) |G|² for every G,
/// A = ∂P/∂F of the model: [`Law::modulus_bound`] of its law (each material's file states its
/// derivation; SVK and the compressible neo-Hookean give 3λ + 2μ at F = I, which a pure
/// dilatation G = I attains), with C = FᵀF formed here, clipped at 0; a non-positive J gives +∞
/// (an inverted element: no bound).
///
/// The rubber models (model §1.10) declare no bound: +∞, and [`Simulation::stiffness_bound`]
/// then certifies no update, so every estimate of the stable step is a converged Lanczos
/// estimate (model §6.4).
#[inline(always)]
pub fn modulus_bound(mat: &Material, f: &[[f64; 3]; 3]) -> f64 {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = f[0][i] * f[0][j] + f[1][i] * f[1][j] + f[2][i] * f[2][j];
        }
    }
    with_law!(mat.model, L => L::modulus_bound(mat, f, &c)).max(0.0)
}

/// max_q a(F_q) over the 8 Gauss points of an element, F_q = I + Σₐ uₐ ⊗ ∇ₓNₐ(ξ_q)
/// (`grad[a][j][q]`), by [`modulus_lanes`].
#[inline(always)]
fn full_modulus(mat: &Material, grad: &[[[f64; 8]; 3]; 8], ue: &[[f64; 3]; 8]) -> f64 {
    let mut f = [[[0.0f64; 8]; 3]; 3];
    for (i, fi) in f.iter_mut().enumerate() {
        fi[i] = [1.0; 8];
    }
    for (a, ua) in ue.iter().enumerate() {
        for (i, fi) in f.iter_mut().enumerate() {
            for (j, fij) in fi.iter_mut().enumerate() {
                for q in 0..8 {
                    fij[q] += ua[i] * grad[a][j][q];
                }
            }
        }
    }
    let a = modulus_lanes(mat, &f);
    a.iter().fold(0.0f64, |m, &x| m.max(x))
}

/// a(F) of [`modulus_bound`] for 8 deformation gradients at once, `f[i][j][lane]` (the 8 Gauss
/// points of an element, or the centres of 8 elements): [`Law::modulus_lanes`], the same
/// arithmetic on lanes. When a lane has a non-positive J it gives +∞: the callers take the
/// maximum, which is then +∞ whatever the others.
#[inline(always)]
fn modulus_lanes(mat: &Material, f: &[[[f64; 8]; 3]; 3]) -> [f64; 8] {
    let mut c = [[[0.0f64; 8]; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for q in 0..8 {
                c[i][j][q] =
                    f[0][i][q] * f[0][j][q] + f[1][i][q] * f[1][j][q] + f[2][i][q] * f[2][j][q];
            }
        }
    }
    with_law!(mat.model, L => L::modulus_lanes(mat, f, &c)).map(|x| x.max(0.0))
}

/// What the bound's element pass reads, shared by its chunks.
pub(super) struct ElementPass<'a> {
    mat: &'a Material,
    full: bool,
    elements: &'a [[u32; 8]],
    classes: &'a ElementClasses,
    /// (g_e, g_hg,e) per class.
    class_g: &'a [[f64; 2]],
    u: &'a Planes,
}

simd_dispatch! {
    /// max_e (a_e g_e + g_hg,e) over chunk `c` of the elements ([`BOUND_ELEMENT_CHUNK`] each), the
    /// element part of (B). Built for AVX-512 and AVX2 like the kernels: the pass vectorises
    /// over the 8 Gauss points, which the baseline x86-64 build did 2 lanes at a time (then a
    /// large share of the stable-step estimates' time; docs: performance log). No fused
    /// operation is written, so every build gives the same bits.
    fn element_pass_chunk / element_pass_chunk_avx2 / element_pass_chunk_avx512
        / element_pass_chunk_builds
        => element_pass_impl(pass: &ElementPass, c: usize) -> f64
}

#[inline(always)]
unsafe fn element_pass_impl<const FMA: bool, const ISA: u8>(pass: &ElementPass, c: usize) -> f64 {
    let ElementPass {
        mat,
        full,
        elements,
        classes,
        class_g,
        u,
    } = *pass;
    let mut worst = 0.0f64;
    let range = c * BOUND_ELEMENT_CHUNK..((c + 1) * BOUND_ELEMENT_CHUNK).min(elements.len());
    let gather = |e: usize| elements[e].map(|n| u.get(n as usize));
    if !full {
        // One point: 8 elements of one class at a time, F at their centres on lanes
        // (a chunk's mixed-class groups and its tail go element by element).
        let mut e = range.start;
        while e + 8 <= range.end {
            let class = classes.class_of[e] as usize;
            if classes.class_of[e + 1..e + 8]
                .iter()
                .any(|&k| k as usize != class)
            {
                worst = worst.max(centre_bound(mat, classes, class_g, e, &gather(e)));
                e += 1;
                continue;
            }
            let b = &classes.centre[class].b;
            let mut f = [[[0.0f64; 8]; 3]; 3];
            for (i, fi) in f.iter_mut().enumerate() {
                fi[i] = [1.0; 8];
            }
            let ue: [[[f64; 3]; 8]; 8] = std::array::from_fn(|l| gather(e + l));
            for a in 0..8 {
                for (i, fi) in f.iter_mut().enumerate() {
                    for (j, fij) in fi.iter_mut().enumerate() {
                        for (l, fl) in fij.iter_mut().enumerate() {
                            *fl += ue[l][a][i] * b[a][j];
                        }
                    }
                }
            }
            let [g, g_hg] = class_g[class];
            for a_e in modulus_lanes(mat, &f) {
                worst = worst.max(a_e * g + g_hg);
            }
            e += 8;
        }
        for e in e..range.end {
            worst = worst.max(centre_bound(mat, classes, class_g, e, &gather(e)));
        }
        return worst;
    }
    for e in range {
        let class = classes.class_of[e] as usize;
        let a_e = full_modulus(mat, &classes.data[class].grad, &gather(e));
        let [g, g_hg] = class_g[class];
        worst = worst.max(a_e * g + g_hg);
    }
    worst
}

/// a_e g_e + g_hg,e of element `e` (nodal displacements `ue`) with one point: a(F) at the
/// centre, F = I + Σₐ uₐ ⊗ bₐ, the arithmetic of the lanes in [`element_pass_impl`].
#[inline(always)]
fn centre_bound(
    mat: &Material,
    classes: &ElementClasses,
    class_g: &[[f64; 2]],
    e: usize,
    ue: &[[f64; 3]; 8],
) -> f64 {
    let class = classes.class_of[e] as usize;
    let b = &classes.centre[class].b;
    let mut f = [[0.0; 3]; 3];
    for (i, fi) in f.iter_mut().enumerate() {
        fi[i] = 1.0;
    }
    for a in 0..8 {
        for (i, fi) in f.iter_mut().enumerate() {
            for (j, fij) in fi.iter_mut().enumerate() {
                *fij += ue[a][i] * b[a][j];
            }
        }
    }
    let [g, g_hg] = class_g[class];
    modulus_bound(mat, &f) * g + g_hg
}

/// λ_max(D^{-½} L D^{-½}) of an 8×8 symmetric L and a positive diagonal D.
fn scaled_lambda_max(l: &[[f64; 8]; 8], d: &[f64; 8]) -> f64 {
    let m = DMatrix::from_fn(8, 8, |a, b| l[a][b] / (d[a] * d[b]).sqrt());
    SymmetricEigen::new(m).eigenvalues.max()
}

/// g_e and g_hg,e of each element class (module doc): λ_max(M_e^{-½} L_e M_e^{-½}) and
/// λ_max(M_e^{-½} K_hg,e M_e^{-½}) (0 with full integration), M_e = ρ s_c diag(∫Nₐ dV) with
/// s_c = `density_factor[c]` (mass scaling, model §6.8; an empty slice: 1 for every class).
pub(super) fn class_bounds(
    mat: &Material,
    classes: &ElementClasses,
    full: bool,
    kappa: f64,
    density_factor: &[f64],
) -> Vec<[f64; 2]> {
    (classes.data.iter().zip(&classes.centre).enumerate())
        .map(|(c, (gd, cd))| {
            let lv = gd.lumped_volumes();
            let rho = mat.density * density_factor.get(c).copied().unwrap_or(1.0);
            let d = lv.map(|v| rho * v);
            let mut l = [[0.0; 8]; 8];
            let mut hg = [[0.0; 8]; 8];
            for a in 0..8 {
                for b in 0..8 {
                    l[a][b] = if full {
                        (0..8)
                            .map(|q| {
                                gd.wdet[q]
                                    * (0..3)
                                        .map(|j| gd.grad[a][j][q] * gd.grad[b][j][q])
                                        .sum::<f64>()
                            })
                            .sum()
                    } else {
                        cd.volume * (0..3).map(|j| cd.b[a][j] * cd.b[b][j]).sum::<f64>()
                    };
                    if !full {
                        let k = crate::element::hex8::hourglass_stiffness(mat, cd, kappa);
                        hg[a][b] = k
                            * (0..4)
                                .map(|al| cd.gamma[al][a] * cd.gamma[al][b])
                                .sum::<f64>();
                    }
                }
            }
            let g_hg = if full {
                0.0
            } else {
                scaled_lambda_max(&hg, &d)
            };
            [scaled_lambda_max(&l, &d), g_hg]
        })
        .collect()
}

/// g_e = λ_max(M_e^{-½} L_e M_e^{-½}) of a tetrahedron of gradients ∇ₓNₐ = `grad` and
/// density ρ (model §1.13): F is constant over it, L_e = V_e ∇ₓNₐ·∇ₓN_b and M_e = ρV_e/4 I, so
/// g_e = (4/ρ) λ_max(Σₐ ∇ₓNₐ ⊗ ∇ₓNₐ) (the 4×4 Gram matrix and the 3×3 one share their nonzero
/// eigenvalues), independent of V_e.
pub(super) fn tet_g(grad: &[[f64; 3]; 4], density: f64) -> f64 {
    let gram =
        nalgebra::Matrix3::from_fn(|i, j| (0..4).map(|a| grad[a][i] * grad[a][j]).sum::<f64>());
    4.0 / density * SymmetricEigen::new(gram).eigenvalues.max()
}

/// max_e a(F_e) g_e over the tetrahedra (model §1.13), the element part of (B) for them, g_e
/// of [`tet_g`] at the tetrahedron's density s_e ρ₀ (s_e = `density_factor[e]`, mass scaling,
/// model §6.8; an empty slice: 1 for every tetrahedron). 0 without tetrahedra. (The nodal
/// pressure is not bounded: a rubber has no bound at all, [`modulus_bound`].)
fn tet_bound(
    mat: &Material,
    mesh: &crate::mesh::Mesh,
    data: &crate::mesh::TetData,
    density_factor: &[f64],
    u: &Planes,
) -> f64 {
    let mut worst = 0.0f64;
    for (t, conn) in mesh.tets.iter().enumerate() {
        let g = &data.grad[t];
        let f = crate::element::tet4::tet_deformation_gradient(g, &conn.map(|n| u.get(n as usize)));
        let rho = mat.density * density_factor.get(t).copied().unwrap_or(1.0);
        worst = worst.max(modulus_bound(mat, &f) * tet_g(g, rho));
    }
    worst
}

impl Simulation {
    /// The element bound (B) of ω_max² at the current state [1/s²] (module doc): a proven
    /// upper bound of λ_max(M⁻¹K), K the tangent with the glue springs W g_N(α) (the operator
    /// the Lanczos estimates, model §6.1), so 2/√bound ≤ h_crit. On the step's team;
    /// deterministic whatever the thread count (a maximum).
    pub fn stiffness_bound(&mut self) -> f64 {
        let mat = self.model.material;
        if mat.rubber.is_some() {
            // No bound declared ([`modulus_bound`]): nothing to certify with.
            return f64::INFINITY;
        }
        if matches!(
            self.model.scheme.integration,
            Integration::Fbar | Integration::ReducedPhysical
        ) {
            // The F-bar and physically stabilised tangents are bounded by the full element's at
            // rest only (model §1.11, §1.12): away from it no bound is proven, so nothing to
            // certify with.
            return f64::INFINITY;
        }
        let mut cache = std::mem::take(&mut self.state.step_control.bound);
        let full = self.model.scheme.integration == Integration::Full;
        let classes = &self.work.classes;
        if cache.class_g.len() != classes.data.len() {
            let kappa = self.model.scheme.hourglass_coefficient;
            cache.class_g = class_bounds(&mat, classes, full, kappa, &self.setup.class_density);
        }
        let elements = &self.model.mesh.elements;
        let pass = ElementPass {
            mat: &mat,
            full,
            elements,
            classes,
            class_g: &cache.class_g,
            u: &self.state.u,
        };
        // SAFETY: the dispatch runs the build the CPU supports; chunk c's range is clamped to
        // the elements, whose nodes are in range of U.
        let chunk = |c: usize| unsafe { element_pass_chunk(&pass, c) };
        let n_chunks = elements.len().div_ceil(BOUND_ELEMENT_CHUNK);
        match self.work.team.as_ref() {
            Some(team) => team.map_into(n_chunks, &mut cache.maxima, chunk),
            None => {
                cache.maxima.clear();
                cache.maxima.extend((0..n_chunks).map(chunk));
            }
        }
        let bulk = cache
            .maxima
            .iter()
            .fold(0.0f64, |m, &x| m.max(x))
            .max(tet_bound(
                &mat,
                &self.model.mesh,
                &classes.tets,
                &self.setup.tet_density,
                &self.state.u,
            ));
        // The glue springs W g_N(α) per node (a node of several interfaces sums them).
        cache.node_springs.resize(self.state.u.len(), 0.0);
        cache.spring_nodes.clear();
        for itf in &self.state.interface_nodes {
            let law = &self.model.interfaces[itf.interface as usize].law;
            let i = itf.node as usize;
            if cache.node_springs[i] == 0.0 {
                cache.spring_nodes.push(i);
            }
            cache.node_springs[i] += itf.area * law.spring_stiffness(itf.alpha);
        }
        let mut springs = 0.0f64;
        for &i in &cache.spring_nodes {
            springs = springs.max(cache.node_springs[i] * self.setup.inv_mass[i]);
            cache.node_springs[i] = 0.0;
        }
        self.state.step_control.bound = cache;
        (bulk + springs) * (1.0 + BOUND_ROUNDING_SLACK)
    }
}

#[cfg(test)]
mod tests;
