//! Eigenvalues and eigenvectors of a symmetric 3×3 matrix, for the principal stretches of the
//! Ogden material (model §1.10).

use crate::tunables::EIGEN_MAX_SWEEPS;

/// Eigenvalues dₐ and orthonormal eigenvectors (the columns of V, `v[i][a]` component i of
/// eigenvector a) of the symmetric 3×3 matrix `a`, A = V diag(d) Vᵀ, by cyclic Jacobi
/// rotations: each rotation in the plane (p, q), with θ = (a_qq − a_pp)/(2a_pq),
/// t = sgn θ/(|θ| + √(θ² + 1)), c = 1/√(t² + 1), s = tc, zeroes a_pq (A ← RᵀAR, V ← VR).
/// Robust for repeated eigenvalues (any orthonormal basis of an eigenspace is returned: the
/// identity for a multiple of I), accurate to round-off relative to the largest |dₐ|.
/// Stops when the off-diagonal entries are below round-off of the diagonal, or after
/// [`EIGEN_MAX_SWEEPS`].
pub fn symmetric_eigen(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..EIGEN_MAX_SWEEPS {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let diag = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if !(off > 1e-18 * diag) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            let apq = a[p][q];
            if apq == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * apq);
            let t = if theta.abs() > 1e150 {
                0.5 / theta
            } else {
                theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt())
            };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A ← RᵀAR with R the identity but R_pp = R_qq = c, R_pq = s, R_qp = −s.
            for row in a.iter_mut() {
                let (kp, kq) = (row[p], row[q]);
                row[p] = c * kp - s * kq;
                row[q] = s * kp + c * kq;
            }
            for k in 0..3 {
                let (pk, qk) = (a[p][k], a[q][k]);
                a[p][k] = c * pk - s * qk;
                a[q][k] = s * pk + c * qk;
            }
            a[p][q] = 0.0;
            a[q][p] = 0.0;
            for row in v.iter_mut() {
                let (kp, kq) = (row[p], row[q]);
                row[p] = c * kp - s * kq;
                row[q] = s * kp + c * kq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// V diag(d) Vᵀ gives A back and VᵀV = I, to round-off, for distinct, double and triple
    /// eigenvalues.
    #[test]
    fn reconstructs_the_matrix() {
        let cases = [
            [[2.0, 0.3, -0.1], [0.3, 1.5, 0.2], [-0.1, 0.2, 0.7]],
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            [[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 3.0]],
            [
                [1.0 + 1e-9, 1e-12, 0.0],
                [1e-12, 1.0, 3e-13],
                [0.0, 3e-13, 1.0],
            ],
            [[50.0, 7.0, 0.0], [7.0, 1.0, 0.0], [0.0, 0.0, 0.02]],
        ];
        for a in cases {
            let (d, v) = symmetric_eigen(a);
            let scale = d.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for i in 0..3 {
                for j in 0..3 {
                    let r: f64 = (0..3).map(|k| v[i][k] * d[k] * v[j][k]).sum();
                    assert!((r - a[i][j]).abs() < 1e-14 * scale, "{a:?}");
                    let o: f64 = (0..3).map(|k| v[k][i] * v[k][j]).sum();
                    let id = if i == j { 1.0 } else { 0.0 };
                    assert!((o - id).abs() < 1e-14);
                }
            }
        }
    }
}
