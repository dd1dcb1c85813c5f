//! Lanczos tridiagonalisation for the stable-step estimate (model §6.2): the largest Ritz
//! value θ of a symmetric operator, its residual ‖r‖ and Ritz vector.
//!
//! The vector work of an iteration runs on the step's thread team in two fused passes over
//! chunks of [`DOF_GRAIN`] degrees of freedom, and its sums are summed per chunk, then over the
//! chunks in order: the same bits for any number of threads. Run serially, the vector work of
//! an iteration (six passes: the basis copy, qᵀw, the update, ‖w‖, the scaling) took as long
//! as the operator's internal-force assembly itself (docs: performance log).

use super::state::StableStep;
use crate::team::{SharedSlice, Team};
pub(crate) use crate::tunables::DOF_GRAIN;

/// `f(a, b)` over the consecutive ranges a..b of [`DOF_GRAIN`] of n degrees of freedom, on
/// `team` (participant t on its contiguous share, as in the step's node loops) or on the
/// calling thread; the results into `out` in order.
pub(super) fn dof_chunks<R: Send>(
    team: Option<&Team>,
    n: usize,
    out: &mut Vec<R>,
    f: impl Fn(usize, usize) -> R + Sync,
) {
    let chunk = |i: usize| f(i * DOF_GRAIN, ((i + 1) * DOF_GRAIN).min(n));
    match team {
        Some(team) => team.map_into(n.div_ceil(DOF_GRAIN), out, chunk),
        None => {
            out.clear();
            out.extend((0..n.div_ceil(DOF_GRAIN)).map(chunk));
        }
    }
}

/// Σ of `f(a, b)` over the chunks of [`dof_chunks`], summed in chunk order (`parts` is the
/// buffer of the per-chunk values).
pub(super) fn dof_sum(
    team: Option<&Team>,
    n: usize,
    parts: &mut Vec<f64>,
    f: impl Fn(usize, usize) -> f64 + Sync,
) -> f64 {
    dof_chunks(team, n, parts, f);
    parts.iter().sum()
}

/// When a Lanczos run stops: after `max_iter` iterations, or at a check (every `check_every`
/// iterations) where the largest Ritz value changed by at most `tol` (relative) since the last
/// check, or where the Ritz residual is at most `residual` × θ (0: not used).
pub(super) struct LanczosStop {
    pub max_iter: usize,
    pub tol: f64,
    pub residual: f64,
    pub check_every: usize,
}

/// A Lanczos run's result: the tridiagonal's diagonal α, the largest Ritz value θ, its residual
/// β_j|s_j| and the eigenvector s of T; `converged` when it stopped on its test (or on an
/// invariant subspace, or with the whole space spanned), not on `max_iter`.
pub(super) struct LanczosOut {
    pub alphas: Vec<f64>,
    pub theta: f64,
    pub resid: f64,
    pub s: Vec<f64>,
    pub converged: bool,
}

impl LanczosOut {
    /// ω_max² ≈ θ + ‖r‖ and h_crit = 2/ω_max.
    pub fn stable_step(&self) -> StableStep {
        let omega_sq = self.theta + self.resid;
        StableStep {
            omega_max_sq: omega_sq,
            ritz_value: self.theta,
            h_crit: 2.0 / omega_sq.sqrt(),
            iterations: self.alphas.len(),
            converged: self.converged,
        }
    }
}

/// The operator of a Lanczos run: y = A q, returning qᵀy (summed as [`dof_sum`] does, so that
/// the operator can form it in its own last pass over y).
pub(super) type Operator<'a> = dyn FnMut(&[f64], &mut [f64]) -> f64 + 'a;

/// The vectors of a Lanczos run, kept between runs so that an estimate allocates no mesh-sized vector once
/// the first has sized them: the current and previous Lanczos vectors, the work vector, and the
/// basis q₀, q₁, … (flat, `n` values each) while it fits in `basis_limit` vectors.
#[derive(Debug, Default, Clone)]
pub(super) struct LanczosWork {
    q: Vec<f64>,
    q_prev: Vec<f64>,
    w: Vec<f64>,
    basis: Vec<f64>,
    /// Per-chunk sums of the passes.
    parts: Vec<f64>,
    units: Vec<()>,
    /// Largest number of basis vectors kept (0: none).
    pub basis_limit: usize,
}

impl LanczosWork {
    /// The Ritz vector y = Σ sⱼqⱼ of `out` into `ritz` (resized): from the kept basis when the
    /// run fitted in it, otherwise by running the same Lanczos iterations again from `start`
    /// (the same arithmetic in the same order: the same y to the bit either way).
    pub fn ritz_vector(
        &mut self,
        apply: &mut Operator,
        start: &[f64],
        out: &LanczosOut,
        team: Option<&Team>,
        ritz: &mut Vec<f64>,
    ) {
        let n = start.len();
        ritz.clear();
        ritz.resize(n, 0.0);
        let m = out.alphas.len();
        if n == 0 {
            return;
        }
        if self.basis.len() >= m * n {
            let (basis, y) = (&self.basis[..m * n], SharedSlice::new(ritz));
            // SAFETY: range a..b of `ritz` is touched by this item only.
            dof_chunks(team, n, &mut self.units, |a, b| unsafe {
                let y = y.range(a, b);
                for (sj, q) in out.s.iter().zip(basis.chunks_exact(n)) {
                    for (yk, qk) in y.iter_mut().zip(&q[a..b]) {
                        *yk += sj * qk;
                    }
                }
            });
            return;
        }
        let stop = LanczosStop {
            max_iter: m,
            tol: 0.0,
            residual: 0.0,
            check_every: usize::MAX,
        };
        let limit = std::mem::replace(&mut self.basis_limit, 0);
        lanczos(apply, start, &stop, Some((&out.s, ritz)), team, self);
        self.basis_limit = limit;
    }
}

/// Lanczos tridiagonalisation of a symmetric operator from `start`, without
/// reorthogonalisation (extreme Ritz values still converge), until `stop`
/// ([`LanczosStop`]). With `accumulate = (s, y)`, runs exactly `max_iter` iterations and
/// accumulates y = Σ sⱼ qⱼ instead of checking; keeps the first `work.basis_limit` vectors qⱼ
/// in `work` ([`LanczosWork::ritz_vector`]). The vector passes run on `team` (or the calling
/// thread), the same bits either way.
///
/// Iteration j: αⱼ = qⱼᵀAqⱼ (from the operator), w = Aqⱼ − αⱼqⱼ − βⱼ₋₁qⱼ₋₁ and βⱼ = ‖w‖ in one
/// pass, qⱼ₊₁ = w/βⱼ (and its copy into the basis) in a second.
pub(super) fn lanczos(
    apply: &mut Operator,
    start: &[f64],
    stop: &LanczosStop,
    mut accumulate: Option<(&[f64], &mut [f64])>,
    team: Option<&Team>,
    work: &mut LanczosWork,
) -> LanczosOut {
    let max_iter = stop.max_iter;
    let n = start.len();
    let LanczosWork {
        q,
        q_prev,
        w,
        basis,
        parts,
        units,
        basis_limit,
    } = work;
    let basis_limit = *basis_limit;
    let nrm = dof_sum(team, n, parts, |a, b| {
        start[a..b].iter().map(|x| x * x).sum()
    })
    .sqrt();
    let scale = nrm.max(f64::MIN_POSITIVE);
    for v in [&mut *q, &mut *q_prev, &mut *w] {
        v.resize(n, 0.0);
    }
    basis.clear();
    // q₀ = start/‖start‖, q₋₁ = 0, and q₀ into the basis.
    next_vector(
        team,
        units,
        start,
        scale,
        q,
        q_prev,
        basis,
        basis_limit > 0,
        true,
    );
    let (mut alphas, mut betas) = (Vec::new(), Vec::new());
    let mut beta_prev = 0.0;
    let mut last_theta = f64::NAN;
    let mut result = (0.0, 0.0, vec![1.0]);
    // The run is converged unless it checks and stops on max_iter short of the whole space.
    let mut converged = true;
    for j in 0..max_iter {
        if let Some((s, y)) = accumulate.as_mut() {
            let (y, q, sj) = (SharedSlice::new(y), &q[..], s[j]);
            // SAFETY: range a..b of `y` is touched by this item only.
            dof_chunks(team, n, units, |a, b| unsafe {
                for (yk, qk) in y.range(a, b).iter_mut().zip(&q[a..b]) {
                    *yk += sj * qk;
                }
            });
        }
        let a = apply(q, w);
        let b = {
            let (ws, q, qp) = (SharedSlice::new(w), &q[..], &q_prev[..]);
            // SAFETY: range a..b of `w` is touched by this item only.
            dof_sum(team, n, parts, |lo, hi| unsafe {
                let mut sum = 0.0;
                for (k, wk) in ws.range(lo, hi).iter_mut().enumerate() {
                    *wk -= a * q[lo + k] + beta_prev * qp[lo + k];
                    sum += *wk * *wk;
                }
                sum
            })
            .sqrt()
        };
        alphas.push(a);
        betas.push(b);
        let done = j + 1 == max_iter || b <= 1e-14 * a.abs();
        if accumulate.is_none() && ((j + 1) % stop.check_every == 0 || done) {
            let (theta, resid, s) = top_ritz_pair(&alphas, &betas);
            let met = (theta - last_theta).abs() <= stop.tol * theta.abs()
                || (stop.residual > 0.0 && resid <= stop.residual * theta.abs());
            result = (theta, resid, s);
            if met || done {
                // Stopped on max_iter short of the whole space and of an invariant subspace.
                converged = met || j + 1 >= n || b <= 1e-14 * a.abs();
                break;
            }
            last_theta = theta;
        }
        if b <= 1e-14 * a.abs() {
            break;
        }
        // q_{j+1} = w/β, q_j becomes the previous vector (a swap, no copy).
        std::mem::swap(q_prev, q);
        let keep = j + 1 < basis_limit;
        next_vector(team, units, w, b, q, q_prev, basis, keep, false);
        beta_prev = b;
    }
    LanczosOut {
        alphas,
        theta: result.0,
        resid: result.1,
        s: result.2,
        converged,
    }
}

/// q = v/scale in one pass over the chunks, also appending q to `basis` when `keep` (the
/// basis grows by exactly one vector: the doubling of `extend` left up to twice the basis
/// allocated, 53 MB for 32 vectors of a 40³ mesh; once sized, no allocation) and zeroing
/// `q_prev` when `zero_prev`.
#[allow(clippy::too_many_arguments)]
fn next_vector(
    team: Option<&Team>,
    units: &mut Vec<()>,
    v: &[f64],
    scale: f64,
    q: &mut [f64],
    q_prev: &mut [f64],
    basis: &mut Vec<f64>,
    keep: bool,
    zero_prev: bool,
) {
    let n = v.len();
    let len = basis.len();
    if keep {
        basis.reserve_exact(n);
    }
    let (qs, ps) = (SharedSlice::new(q), SharedSlice::new(q_prev));
    let slot = SharedSlice::new(&mut basis.spare_capacity_mut()[..if keep { n } else { 0 }]);
    // SAFETY: range a..b of `q`, `q_prev` and the basis slot is touched by this item only.
    dof_chunks(team, n, units, |a, b| unsafe {
        let q = qs.range(a, b);
        for (qk, vk) in q.iter_mut().zip(&v[a..b]) {
            *qk = vk / scale;
        }
        if keep {
            for (bk, qk) in slot.range(a, b).iter_mut().zip(q.iter()) {
                bk.write(*qk);
            }
        }
        if zero_prev {
            ps.range(a, b).fill(0.0);
        }
    });
    if keep {
        // SAFETY: the pass above initialised the n values after `len`.
        unsafe { basis.set_len(len + n) };
    }
}

/// The largest eigenvalue θ of the Lanczos tridiagonal T (diagonal `alphas`, off-diagonal
/// `betas`), its residual β_m|s_m| and its eigenvector s.
fn top_ritz_pair(alphas: &[f64], betas: &[f64]) -> (f64, f64, Vec<f64>) {
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
    let resid = (betas[m - 1] * s[m - 1]).abs();
    (theta, resid, s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kept basis and the regenerating second pass give the same Ritz vector to the bit
    /// (what leaves every golden file unchanged), and it is the top eigenvector: on the 1-D
    /// Laplacian tridiag(−1, 2, −1) of order n, λ_max = 2 − 2 cos(nπ/(n+1)) exactly.
    #[test]
    fn the_kept_basis_gives_the_regenerated_ritz_vector_to_the_bit() {
        let n = 40;
        let mut apply = |q: &[f64], y: &mut [f64]| {
            for k in 0..n {
                let left = if k > 0 { q[k - 1] } else { 0.0 };
                let right = if k + 1 < n { q[k + 1] } else { 0.0 };
                y[k] = 2.0 * q[k] - left - right;
            }
            q.iter().zip(y.iter()).map(|(a, b)| a * b).sum()
        };
        let start: Vec<f64> = (0..n).map(|k| ((k * 7919) % 101) as f64 - 50.0).collect();
        let stop = LanczosStop {
            max_iter: n,
            tol: 1e-13,
            residual: 0.0,
            check_every: 5,
        };
        let ritz = |limit: usize, apply: &mut Operator| {
            let mut work = LanczosWork {
                basis_limit: limit,
                ..Default::default()
            };
            let out = lanczos(apply, &start, &stop, None, None, &mut work);
            let mut y = Vec::new();
            work.ritz_vector(apply, &start, &out, None, &mut y);
            (out, y)
        };
        let (out, kept) = ritz(n, &mut apply);
        for limit in [0, 3] {
            let (_, regenerated) = ritz(limit, &mut apply);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&kept), bits(&regenerated), "basis limit {limit}");
        }
        let lambda = 2.0 - 2.0 * (n as f64 * std::f64::consts::PI / (n as f64 + 1.0)).cos();
        assert!(
            (out.theta - lambda).abs() <= 1e-10 * lambda,
            "θ {} vs {lambda}",
            out.theta
        );
        let mut ay = vec![0.0; n];
        apply(&kept, &mut ay);
        let norm = kept.iter().map(|x| x * x).sum::<f64>().sqrt();
        let res = (0..n)
            .map(|k| (ay[k] - out.theta * kept[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(
            res <= 1e-6 * lambda * norm,
            "‖Ay − θy‖ = {res:.3e}, ‖y‖ = {norm}"
        );
        assert!(out.converged);
    }

    /// `converged` says why a run stopped: on the 1-D Laplacian of order 400 (λ_max clustered,
    /// gaps O(1/n²)), 10 iterations do not meet a 1e-12 test, so the run stops on max_iter
    /// unconverged; 40 iterations of the order-40 operator span its whole space (converged
    /// whatever the test); a loose test met before max_iter is converged.
    #[test]
    fn a_run_stopped_by_its_cap_is_not_converged() {
        let laplacian = |n: usize| {
            move |q: &[f64], y: &mut [f64]| {
                for k in 0..n {
                    let left = if k > 0 { q[k - 1] } else { 0.0 };
                    let right = if k + 1 < n { q[k + 1] } else { 0.0 };
                    y[k] = 2.0 * q[k] - left - right;
                }
                q.iter().zip(y.iter()).map(|(a, b)| a * b).sum()
            }
        };
        let run = |n: usize, max_iter: usize, tol: f64| {
            let start: Vec<f64> = (0..n).map(|k| ((k * 7919) % 101) as f64 - 50.0).collect();
            let stop = LanczosStop {
                max_iter,
                tol,
                residual: 0.0,
                check_every: 5,
            };
            let mut apply = laplacian(n);
            let out = lanczos(
                &mut apply,
                &start,
                &stop,
                None,
                None,
                &mut LanczosWork::default(),
            );
            (out.converged, out.alphas.len())
        };
        assert_eq!(run(400, 10, 1e-12), (false, 10));
        assert_eq!(run(40, 40, 1e-300), (true, 40));
        let (converged, iterations) = run(400, 300, 1e-2);
        assert!(converged && iterations < 300, "{iterations}");
    }
}
