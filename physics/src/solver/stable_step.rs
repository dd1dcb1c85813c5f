//! The stable step of PHYSICS.md §6: h_crit = 2/ω_max with ω_max² = λ_max(M⁻¹K) estimated by
//! Lanczos (K·x matrix-free, the directional derivative of F_int, plus the interface springs),
//! re-estimated as the stiffness changes; and the choice of the next step h_{n+3/2}.

use super::boundary::NONE;
use super::state::StableStep;
use super::ElementLoop;
use super::Simulation;
use crate::kernels::ElementSums;

/// Change of the smallest Jacobian since the last h_crit estimate that triggers a new estimate
/// before its scheduled step, once some element is compressed below [`JACOBIAN_COMPRESSED`]
/// (`next_time_step`).
const JACOBIAN_RETRIGGER: f64 = 0.02;
/// Smallest Jacobian below which strain changes re-estimate h_crit between scheduled estimates.
const JACOBIAN_COMPRESSED: f64 = 0.9;

/// The step for a time-step factor: h = factor × h_crit, never above h_crit (PHYSICS.md §6:
/// central differences are unstable above h_crit = 2/ω_max). A factor above 1 is accepted
/// (scene range (0, 2)) and runs at h = h_crit, the stability limit itself, with no margin for
/// the estimate or for stiffening between estimates (a warning says so).
pub(super) fn capped_step(factor: f64, h_crit: f64) -> f64 {
    factor.min(1.0) * h_crit
}

impl Simulation {
    /// Re-estimates h_crit every `h_crit_update_interval` steps and returns h_{n+3/2}.
    /// The step only ever decreases: when stiffening makes the current step exceed
    /// factor × h_crit by more than 5 %, or h_crit itself, h becomes 0.95 × factor × h_crit,
    /// never above h_crit ([`capped_step`]; the 5 % margins avoid a change for estimate noise
    /// and at every estimate, but never let h pass h_crit: with a factor above 1/1.05 the
    /// margin alone would have let a stiffening run step up to 5 % above it). A change of step breaks the exact trapezoid pairing of the ledger for that one
    /// step (the work pairs velocities of two different intervals); growing h after a softening
    /// would buy little speed for that cost, so it is not done.
    ///
    /// Between those, under strong compression (smallest Jacobian below [`JACOBIAN_COMPRESSED`])
    /// a change of the smallest Jacobian by [`JACOBIAN_RETRIGGER`] since the last estimate
    /// re-estimates at once: a violent impact stiffens a neo-Hookean body within a few steps,
    /// long before the next scheduled estimate, and the stiffest mode moves with the compression
    /// wave. Moderate strains (the pull-off's J stays above 0.9) keep the schedule alone: each
    /// estimate costs ~100 force evaluations.
    pub(super) fn next_time_step(&mut self) -> f64 {
        let every = self.model.scheme.h_crit_update_interval as u64;
        if every == 0 {
            return self.h;
        }
        let strained = self.min_jacobian < JACOBIAN_COMPRESSED
            && (self.min_jacobian - self.jacobian_at_estimate).abs() > JACOBIAN_RETRIGGER;
        if !(self.step_count.is_multiple_of(every) || strained) {
            return self.h;
        }
        let warm = std::mem::take(&mut self.ritz_vector);
        let est = self.estimate_stable_step(Some(warm));
        self.jacobian_at_estimate = self.min_jacobian;
        self.stats.h_crit_estimates += 1;
        self.h_crit = est.h_crit;
        self.stats.h_crit_min = self.stats.h_crit_min.min(est.h_crit);
        let target = self.model.scheme.time_step_factor * est.h_crit;
        if self.h > (1.05 * target).min(est.h_crit) {
            capped_step(0.95 * self.model.scheme.time_step_factor, est.h_crit)
        } else {
            self.h
        }
    }

    /// Prescribed degrees of freedom (node·3 + component), true where prescribed.
    fn prescribed_mask(&self) -> Vec<bool> {
        let mut mask = vec![false; 3 * self.u.len()];
        for b in &self.boundary.nodes {
            for c in 0..3 {
                if b.prescribed[c] != NONE {
                    mask[3 * b.node as usize + c] = true;
                }
            }
        }
        mask
    }

    /// ω_max² of M⁻¹K at the current state by Lanczos on M^{-½}KM^{-½} (PHYSICS.md §6), K·x
    /// matrix-free as the directional derivative of F_int (forward difference, relative step
    /// 1e-6 of the smallest edge) plus the interface springs W g_N(α) of glued nodes;
    /// prescribed components are removed. Lanczos Ritz values approach λ_max from below, so
    /// the estimate is θ + ‖r‖ with ‖r‖ = β_j|s_j| the Ritz residual: an eigenvalue lies within
    /// ‖r‖ of θ, which bounds λ_max once θ has converged to the top of the spectrum.
    pub fn estimate_stable_step(&mut self, warm: Option<Vec<f64>>) -> StableStep {
        self.stable_step_estimate(warm, true)
    }

    /// [`Simulation::estimate_stable_step`], with the interface springs in K or without them
    /// (`springs = false`: the bulk alone).
    pub(super) fn stable_step_estimate(
        &mut self,
        warm: Option<Vec<f64>>,
        springs: bool,
    ) -> StableStep {
        let mut op = StiffnessOperator::new(self, springs);
        let start = op.start_vector(warm);
        let n = start.len();
        let tol = self.model.scheme.h_crit_tolerance;
        let max_iter = 300.min(n);
        let mut apply = |q: &[f64], y: &mut [f64]| op.apply(q, y);
        let (alphas, _, theta, resid, s) = lanczos(&mut apply, &start, max_iter, tol, None);
        // Second pass: regenerate the same Lanczos vectors to form the Ritz vector y = Σ sⱼqⱼ.
        let mut ritz = vec![0.0; n];
        if n > 0 {
            lanczos(&mut apply, &start, alphas.len(), 0.0, Some((&s, &mut ritz)));
        }
        self.ritz_vector = ritz;
        let omega_sq = theta + resid;
        StableStep {
            omega_max_sq: omega_sq,
            ritz_value: theta,
            h_crit: 2.0 / omega_sq.sqrt(),
            iterations: alphas.len(),
        }
    }
}

/// The operator of the stable-step estimate, y = M^{-½} K M^{-½} q at the current state
/// (PHYSICS.md §6): K q matrix-free as the forward difference (F_int(U + ε x) − F_int(U))/ε,
/// x = M^{-½} q, with ε = 1e-6 of the smallest edge over max|x|, plus the interface springs
/// W g_N(α) of glued nodes; prescribed components are removed (rows and columns zero).
struct StiffnessOperator<'a> {
    sim: &'a Simulation,
    elements: ElementLoop<'a>,
    /// Prescribed degrees of freedom (node·3 + component).
    mask: Vec<bool>,
    sqrt_inv_m: Vec<f64>,
    /// F_int(U), the base of the difference.
    f0: Vec<[f64; 3]>,
    /// (node, W g_N(α)) of the glued nodes (empty for the bulk alone).
    springs: Vec<(usize, f64)>,
    eps_len: f64,
    up: Vec<[f64; 3]>,
    fp: Vec<[f64; 3]>,
    parts: Vec<ElementSums>,
}

impl<'a> StiffnessOperator<'a> {
    fn new(sim: &'a Simulation, springs: bool) -> Self {
        let n = 3 * sim.u.len();
        let elements = ElementLoop {
            model: &sim.model,
            classes: &sim.classes,
            blocks: &sim.blocks,
            team: sim.team.as_ref(),
        };
        let mut f0 = vec![[0.0; 3]; sim.u.len()];
        let mut parts = Vec::new();
        elements.assemble(&sim.u, &mut f0, false, &mut parts);
        let springs = sim
            .interface_nodes
            .iter()
            .filter(|_| springs)
            .map(|itf| {
                let law = &sim.model.interfaces[itf.interface as usize].law;
                (
                    itf.node as usize,
                    itf.area * law.spring_stiffness(itf.alpha),
                )
            })
            .collect();
        StiffnessOperator {
            sim,
            elements,
            mask: sim.prescribed_mask(),
            sqrt_inv_m: (0..n).map(|k| sim.inv_mass[k / 3].sqrt()).collect(),
            f0,
            springs,
            eps_len: 1e-6 * sim.model.mesh.min_edge(),
            up: sim.u.clone(),
            fp: vec![[0.0; 3]; sim.u.len()],
            parts,
        }
    }

    /// The Lanczos start: the previous Ritz vector `warm` (warm start) plus a deterministic
    /// pseudo-random vector so that every mode is represented.
    fn start_vector(&self, warm: Option<Vec<f64>>) -> Vec<f64> {
        let n = self.mask.len();
        let mut start: Vec<f64> = (0..n)
            .map(|k| {
                if self.mask[k] {
                    0.0
                } else {
                    splitmix(k as u64)
                }
            })
            .collect();
        if let Some(w) = warm.filter(|w| w.len() == n) {
            let nw = w.iter().map(|x| x * x).sum::<f64>().sqrt();
            let ns = start.iter().map(|x| x * x).sum::<f64>().sqrt();
            if nw > 0.0 {
                for k in 0..n {
                    start[k] = w[k] / nw + 1e-3 * start[k] / ns;
                }
            }
        }
        start
    }

    /// y = M^{-½} K M^{-½} q.
    fn apply(&mut self, q: &[f64], y: &mut [f64]) {
        let (mask, sqrt_inv_m, u) = (&self.mask, &self.sqrt_inv_m, &self.sim.u);
        let n = mask.len();
        let mut xmax = 0.0f64;
        for k in 0..n {
            if !mask[k] {
                xmax = xmax.max((q[k] * sqrt_inv_m[k]).abs());
            }
        }
        if xmax == 0.0 {
            y.fill(0.0);
            return;
        }
        let eps = self.eps_len / xmax;
        for i in 0..u.len() {
            for c in 0..3 {
                let k = 3 * i + c;
                let x = if mask[k] { 0.0 } else { q[k] * sqrt_inv_m[k] };
                self.up[i][c] = u[i][c] + eps * x;
            }
        }
        self.fp.fill([0.0; 3]);
        self.elements
            .assemble(&self.up, &mut self.fp, false, &mut self.parts);
        for i in 0..u.len() {
            for c in 0..3 {
                let k = 3 * i + c;
                y[k] = if mask[k] {
                    0.0
                } else {
                    (self.fp[i][c] - self.f0[i][c]) / eps
                };
            }
        }
        for &(i, ks) in &self.springs {
            for c in 0..3 {
                let k = 3 * i + c;
                if !mask[k] {
                    y[k] += ks * q[k] * sqrt_inv_m[k];
                }
            }
        }
        for k in 0..n {
            y[k] *= sqrt_inv_m[k];
        }
    }
}

/// A deterministic pseudo-random number in [−1, 1) (splitmix64 of the index).
fn splitmix(k: u64) -> f64 {
    let mut z = k.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

type LanczosOut = (Vec<f64>, Vec<f64>, f64, f64, Vec<f64>);

/// Lanczos tridiagonalisation of a symmetric operator from `start`, without
/// reorthogonalisation (extreme Ritz values still converge). Stops when the largest Ritz value
/// changes by less than `tol` (relative) over 5 iterations, or after `max_iter`. Returns
/// (α, β, θ_max, Ritz residual β_j|s_j|, eigenvector s of T). With `accumulate = (s, y)`,
/// runs exactly `max_iter` iterations and accumulates y = Σ sⱼ qⱼ instead.
fn lanczos(
    apply: &mut dyn FnMut(&[f64], &mut [f64]),
    start: &[f64],
    max_iter: usize,
    tol: f64,
    mut accumulate: Option<(&[f64], &mut [f64])>,
) -> LanczosOut {
    let n = start.len();
    let nrm = start.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut q: Vec<f64> = start
        .iter()
        .map(|x| x / nrm.max(f64::MIN_POSITIVE))
        .collect();
    let mut q_prev = vec![0.0; n];
    let mut w = vec![0.0; n];
    let (mut alphas, mut betas) = (Vec::new(), Vec::new());
    let mut beta_prev = 0.0;
    let mut last_theta = f64::NAN;
    let mut result = (0.0, 0.0, vec![1.0]);
    for j in 0..max_iter {
        if let Some((s, y)) = accumulate.as_mut() {
            for k in 0..n {
                y[k] += s[j] * q[k];
            }
        }
        apply(&q, &mut w);
        let a: f64 = w.iter().zip(&q).map(|(x, y)| x * y).sum();
        for k in 0..n {
            w[k] -= a * q[k] + beta_prev * q_prev[k];
        }
        let b = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        alphas.push(a);
        betas.push(b);
        let done = j + 1 == max_iter || b <= 1e-14 * a.abs();
        if accumulate.is_none() && ((j + 1) % 5 == 0 || done) {
            let m = alphas.len();
            let t = nalgebra::DMatrix::from_fn(m, m, |r, c| {
                if r == c {
                    alphas[r]
                } else if r + 1 == c {
                    betas[r]
                } else if c + 1 == r {
                    betas[c]
                } else {
                    0.0
                }
            });
            let eig = nalgebra::SymmetricEigen::new(t);
            let (imax, theta) =
                eig.eigenvalues
                    .iter()
                    .enumerate()
                    .fold(
                        (0, f64::NEG_INFINITY),
                        |acc, (i, &v)| if v > acc.1 { (i, v) } else { acc },
                    );
            let s: Vec<f64> = eig.eigenvectors.column(imax).iter().copied().collect();
            let resid = (b * s[m - 1]).abs();
            result = (theta, resid, s);
            if (theta - last_theta).abs() <= tol * theta.abs() || done {
                break;
            }
            last_theta = theta;
        }
        if b <= 1e-14 * a.abs() {
            break;
        }
        for k in 0..n {
            q_prev[k] = q[k];
            q[k] = w[k] / b;
        }
        beta_prev = b;
    }
    (alphas, betas, result.0, result.1, result.2)
}
