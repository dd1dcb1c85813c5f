//! Lanczos tridiagonalisation for the stable-step estimate (PHYSICS.md §6): the largest Ritz
//! value θ of a symmetric operator, its residual ‖r‖ and Ritz vector.

use super::state::StableStep;

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
/// β_j|s_j| and the eigenvector s of T.
pub(super) struct LanczosOut {
    pub alphas: Vec<f64>,
    pub theta: f64,
    pub resid: f64,
    pub s: Vec<f64>,
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
        }
    }
}

/// The vectors of a Lanczos run, kept between runs so that an estimate allocates no mesh-sized vector once
/// the first has sized them: the current and previous Lanczos vectors, the work vector, and the
/// basis q₀, q₁, … (flat, `n` values each) while it fits in `basis_limit` vectors.
#[derive(Debug, Default, Clone)]
pub(super) struct LanczosWork {
    q: Vec<f64>,
    q_prev: Vec<f64>,
    w: Vec<f64>,
    basis: Vec<f64>,
    /// Largest number of basis vectors kept (0: none).
    pub basis_limit: usize,
}

impl LanczosWork {
    /// The Ritz vector y = Σ sⱼqⱼ of `out` into `ritz` (resized, zeroed): from the kept basis
    /// when the run fitted in it, otherwise by running the same Lanczos iterations again from
    /// `start` (the same arithmetic in the same order: the same y to the bit either way).
    pub fn ritz_vector(
        &mut self,
        apply: &mut dyn FnMut(&[f64], &mut [f64]),
        start: &[f64],
        out: &LanczosOut,
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
            for (sj, q) in out.s.iter().zip(self.basis.chunks_exact(n)) {
                for k in 0..n {
                    ritz[k] += sj * q[k];
                }
            }
            return;
        }
        let stop = LanczosStop {
            max_iter: m,
            tol: 0.0,
            residual: 0.0,
            check_every: usize::MAX,
        };
        let limit = std::mem::replace(&mut self.basis_limit, 0);
        lanczos(apply, start, &stop, Some((&out.s, ritz)), self);
        self.basis_limit = limit;
    }
}

/// Lanczos tridiagonalisation of a symmetric operator from `start`, without
/// reorthogonalisation (extreme Ritz values still converge), until `stop`
/// ([`LanczosStop`]). With `accumulate = (s, y)`, runs exactly `max_iter` iterations and
/// accumulates y = Σ sⱼ qⱼ instead of checking; keeps the first `work.basis_limit` vectors qⱼ
/// in `work` ([`LanczosWork::ritz_vector`]).
pub(super) fn lanczos(
    apply: &mut dyn FnMut(&[f64], &mut [f64]),
    start: &[f64],
    stop: &LanczosStop,
    mut accumulate: Option<(&[f64], &mut [f64])>,
    work: &mut LanczosWork,
) -> LanczosOut {
    let max_iter = stop.max_iter;
    let n = start.len();
    let nrm = start.iter().map(|x| x * x).sum::<f64>().sqrt();
    let LanczosWork {
        q,
        q_prev,
        w,
        basis,
        basis_limit,
    } = work;
    q.clear();
    q.extend(start.iter().map(|x| x / nrm.max(f64::MIN_POSITIVE)));
    q_prev.clear();
    q_prev.resize(n, 0.0);
    w.clear();
    w.resize(n, 0.0);
    basis.clear();
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
        if j < *basis_limit {
            // Grown by exactly one vector (the doubling of `extend` left up to twice the
            // basis allocated: 53 MB for 32 vectors of a 40³ mesh); once sized, no allocation.
            basis.reserve_exact(n);
            basis.extend_from_slice(q);
        }
        apply(q, w);
        let a: f64 = w.iter().zip(q.iter()).map(|(x, y)| x * y).sum();
        for k in 0..n {
            w[k] -= a * q[k] + beta_prev * q_prev[k];
        }
        let b = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        alphas.push(a);
        betas.push(b);
        let done = j + 1 == max_iter || b <= 1e-14 * a.abs();
        if accumulate.is_none() && ((j + 1) % stop.check_every == 0 || done) {
            let (theta, resid, s) = top_ritz_pair(&alphas, &betas);
            let converged = (theta - last_theta).abs() <= stop.tol * theta.abs()
                || (stop.residual > 0.0 && resid <= stop.residual * theta.abs());
            result = (theta, resid, s);
            if converged || done {
                break;
            }
            last_theta = theta;
        }
        if b <= 1e-14 * a.abs() {
            break;
        }
        // q_{j+1} = w/β, q_j becomes the previous vector (a swap, no copy).
        std::mem::swap(q_prev, q);
        for k in 0..n {
            q[k] = w[k] / b;
        }
        beta_prev = b;
    }
    LanczosOut {
        alphas,
        theta: result.0,
        resid: result.1,
        s: result.2,
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
        };
        let start: Vec<f64> = (0..n).map(|k| ((k * 7919) % 101) as f64 - 50.0).collect();
        let stop = LanczosStop {
            max_iter: n,
            tol: 1e-13,
            residual: 0.0,
            check_every: 5,
        };
        let ritz = |limit: usize, apply: &mut dyn FnMut(&[f64], &mut [f64])| {
            let mut work = LanczosWork {
                basis_limit: limit,
                ..Default::default()
            };
            let out = lanczos(apply, &start, &stop, None, &mut work);
            let mut y = Vec::new();
            work.ritz_vector(apply, &start, &out, &mut y);
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
    }
}
