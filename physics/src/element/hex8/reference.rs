//! The 8-node trilinear hexahedron in the reference configuration (model §1.5): shape
//! functions, the 2×2×2 Gauss points, and what the total Lagrangian formulation computes once
//! per element shape — gradients ∇ₓNₐ (the stable-step bound's), ⅛J₀⁻¹ (the full kernel's) and
//! weights w·det J₀ at the Gauss points ([`GaussData`]),
//! the one-point data with hourglass vectors ([`CentreData`]), lumped volumes, and the constant
//! of the corner-Jacobian bound ([`corner_bound_constant`]).

use crate::vec3::{cross, dot, sub};
use nalgebra::{Matrix3, Matrix4, RowVector3};

/// Parent coordinates (ξ, η, ζ) of the 8 nodes of the reference hexahedron.
pub const HEX_CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Trilinear shape functions Nₐ(ξ) of the hexahedron.
#[inline]
pub fn shape(xi: [f64; 3]) -> [f64; 8] {
    let mut n = [0.0; 8];
    for (a, c) in HEX_CORNERS.iter().enumerate() {
        n[a] = 0.125 * (1.0 + c[0] * xi[0]) * (1.0 + c[1] * xi[1]) * (1.0 + c[2] * xi[2]);
    }
    n
}

/// Parent derivatives ∂Nₐ/∂ξⱼ of the hexahedron.
#[inline]
pub fn shape_derivatives(xi: [f64; 3]) -> [[f64; 3]; 8] {
    let mut d = [[0.0; 3]; 8];
    for (a, c) in HEX_CORNERS.iter().enumerate() {
        let f = [1.0 + c[0] * xi[0], 1.0 + c[1] * xi[1], 1.0 + c[2] * xi[2]];
        d[a] = [
            0.125 * c[0] * f[1] * f[2],
            0.125 * c[1] * f[0] * f[2],
            0.125 * c[2] * f[0] * f[1],
        ];
    }
    d
}

/// The 2×2×2 Gauss points (ξ = ±1/√3, weight 1 each), in the same order as `HEX_CORNERS`.
pub fn gauss_points() -> [[f64; 3]; 8] {
    let g = 1.0 / 3f64.sqrt();
    HEX_CORNERS.map(|c| [c[0] * g, c[1] * g, c[2] * g])
}

/// Reference-configuration data of one element shape at its 8 Gauss points, laid out with the
/// Gauss point index innermost so the per-step kernel runs over 8 lanes (SIMD-friendly).
#[derive(Debug, Clone, PartialEq)]
pub struct GaussData {
    /// ∇ₓNₐ at each Gauss point: `grad[a][j][q]` = ∂Nₐ/∂Xⱼ (ξ_q) [1/m].
    pub grad: [[[f64; 8]; 3]; 8],
    /// The same gradient times the weight w_q det J₀(ξ_q): `wgrad[a][j][q]` [m²].
    pub wgrad: [[[f64; 8]; 3]; 8],
    /// Integration weight times reference Jacobian, w_q det J₀(ξ_q) [m³].
    pub wdet: [f64; 8],
    /// ⅛ ∂ξ_d/∂Xⱼ at each Gauss point, `jinv[d][j][q]` [1/m]: what the sum-factorised kernels
    /// turn the parent derivatives 8 ∂u/∂ξ into H with (`element::hex8::tensor`, (T1)).
    pub jinv: [[[f64; 8]; 3]; 3],
    /// The same times w_q det J₀(ξ_q), `wjinv[d][j][q]` [m²] (`element::hex8::tensor`, (T2)).
    pub wjinv: [[[f64; 8]; 3]; 3],
    /// J₀ is diagonal at every Gauss point (an axis-aligned box), and then the same at every
    /// point (the mean of the eight computed, which differ by rounding): ∂ξ_d/∂Xⱼ = 0 for d ≠ j,
    /// so the full kernels form H and the forces through the modes of the trilinear field with
    /// the factors ⅛ ∂ξ_d/∂X_d and ⅛ w det J₀ ∂ξ_d/∂X_d (`element::hex8::tensor`, (T4)).
    pub axis_aligned: bool,
}

/// `sum`, a computed sum of 8 terms whose absolute values add up to `magnitude`, or 0 when it is
/// within the rounding error of such a sum, |fl(Σₐ tₐ) − Σₐ tₐ| ≤ γ₈ Σₐ |tₐ| (γ₈ = 8u/(1 − 8u)
/// < 8ε, u = ε/2): a sum that is zero in exact arithmetic (an off-diagonal entry of a box's J₀,
/// Σ_c h_cᵅ X_c of a parallelepiped) then comes out as zero, not as its cancellation error.
fn zero_within_rounding(sum: f64, magnitude: f64) -> f64 {
    if sum.abs() <= 8.0 * f64::EPSILON * magnitude {
        0.0
    } else {
        sum
    }
}

impl GaussData {
    /// ∇ₓNₐ = J₀⁻ᵀ ∂Nₐ/∂ξ at the Gauss points, J₀ = ∂X/∂ξ (model §1.5: computed once).
    pub fn new(x: &[[f64; 3]; 8]) -> Result<Self, f64> {
        let mut gd = GaussData {
            grad: [[[0.0; 8]; 3]; 8],
            wgrad: [[[0.0; 8]; 3]; 8],
            wdet: [0.0; 8],
            jinv: [[[0.0; 8]; 3]; 3],
            wjinv: [[[0.0; 8]; 3]; 3],
            axis_aligned: true,
        };
        let points = gauss_points();
        let mut jacobians = [nalgebra::Matrix3::<f64>::zeros(); 8];
        for (j, xi) in jacobians.iter_mut().zip(&points) {
            let dn = shape_derivatives(*xi);
            let mut magnitude = nalgebra::Matrix3::<f64>::zeros();
            for a in 0..8 {
                for r in 0..3 {
                    for c in 0..3 {
                        j[(r, c)] += x[a][r] * dn[a][c];
                        magnitude[(r, c)] += (x[a][r] * dn[a][c]).abs();
                    }
                }
            }
            // The off-diagonal entries of an axis-aligned box come out as ±1e-16 |X| of
            // cancellation otherwise (some of them in a unit cube; docs: performance log), which
            // would hide that J₀ is diagonal.
            for r in 0..3 {
                for c in 0..3 {
                    j[(r, c)] = zero_within_rounding(j[(r, c)], magnitude[(r, c)]);
                    if r != c && j[(r, c)] != 0.0 {
                        gd.axis_aligned = false;
                    }
                }
            }
        }
        // J₀ diagonal at the 8 points makes X affine in each ξ_d alone (a trilinear X whose
        // ∂X_r/∂ξ_c, c ≠ r, vanish at the 8 points has no such terms): an axis-aligned box, whose
        // J₀ is one constant diagonal matrix in exact arithmetic. The 8 computed ones differ from
        // it by rounding; each point takes their mean, so that the kernels may apply ⅛ J₀⁻¹ and
        // ⅛ w det J₀ J₀⁻ᵀ to sums over points (`element::hex8::tensor`, (T4)).
        if gd.axis_aligned {
            let mean = nalgebra::Matrix3::from_diagonal(
                &(jacobians
                    .iter()
                    .map(|j| j.diagonal())
                    .sum::<nalgebra::Vector3<f64>>()
                    / 8.0),
            );
            jacobians = [mean; 8];
        }
        for (q, (j, xi)) in jacobians.iter().zip(&points).enumerate() {
            let dn = shape_derivatives(*xi);
            let det = j.determinant();
            if !(det > 0.0 && det.is_finite()) {
                return Err(det);
            }
            let jinv = j.try_inverse().ok_or(det)?;
            for a in 0..8 {
                for jdir in 0..3 {
                    // ∂N/∂X_j = Σ_c ∂N/∂ξ_c ∂ξ_c/∂X_j, ∂ξ/∂X = J⁻¹.
                    let g: f64 = (0..3).map(|c| dn[a][c] * jinv[(c, jdir)]).sum();
                    gd.grad[a][jdir][q] = g;
                    gd.wgrad[a][jdir][q] = g * det;
                }
            }
            gd.wdet[q] = det;
            for d in 0..3 {
                for jdir in 0..3 {
                    // ⅛ is a power of two: exact.
                    gd.jinv[d][jdir][q] = 0.125 * jinv[(d, jdir)];
                    gd.wjinv[d][jdir][q] = 0.125 * (jinv[(d, jdir)] * det);
                }
            }
        }
        Ok(gd)
    }

    /// Reference volume of the element, Σ_q w_q det J₀ [m³].
    pub fn volume(&self) -> f64 {
        self.wdet.iter().sum()
    }

    /// Consistent-mass row sums per unit density, ∫ Nₐ dV (model §1.7, lumped mass) [m³].
    pub fn lumped_volumes(&self) -> [f64; 8] {
        let mut m = [0.0; 8];
        for (q, xi) in gauss_points().iter().enumerate() {
            let n = shape(*xi);
            for a in 0..8 {
                m[a] += n[a] * self.wdet[q];
            }
        }
        m
    }
}

/// Local faces of a hexahedron, each outward (counter-clockwise seen from outside; the node
/// order of [`HEX_CORNERS`]).
pub const FACES: [[usize; 4]; 6] = [
    [0, 3, 2, 1],
    [4, 5, 6, 7],
    [0, 1, 5, 4],
    [1, 2, 6, 5],
    [2, 3, 7, 6],
    [3, 0, 4, 7],
];

/// The 12 edges of a hex8 (local node pairs).
pub const EDGES: [(usize, usize); 12] = [
    (0, 1),
    (1, 2),
    (2, 3),
    (3, 0),
    (4, 5),
    (5, 6),
    (6, 7),
    (7, 4),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

/// Hourglass base vectors hᵅ of the hexahedron (α = 1..4: ξη, ηζ, ζξ, ξηζ at the nodes), in the
/// node order of [`HEX_CORNERS`] (Flanagan & Belytschko 1981).
pub fn hourglass_vectors() -> [[f64; 8]; 4] {
    let mut h = [[0.0; 8]; 4];
    for (a, c) in HEX_CORNERS.iter().enumerate() {
        h[0][a] = c[0] * c[1];
        h[1][a] = c[1] * c[2];
        h[2][a] = c[2] * c[0];
        h[3][a] = c[0] * c[1] * c[2];
    }
    h
}

/// Reference data of one element shape for one-point integration with Flanagan–Belytschko
/// hourglass control (model §1.6).
#[derive(Debug, Clone, PartialEq)]
pub struct CentreData {
    /// Mean gradients bₐ = (1/V) ∫ ∇ₓNₐ dV (FB's uniform gradient; exact by 2×2×2 Gauss) [1/m].
    pub b: [[f64; 3]; 8],
    /// Hourglass shape vectors γₐᵅ = hₐᵅ − (Σ_c h_cᵅ X_c)·bₐ: orthogonal to every affine field,
    /// so rigid motions and homogeneous strains excite no hourglass force.
    pub gamma: [[f64; 8]; 4],
    /// Reference volume V [m³].
    pub volume: f64,
    /// Σₐ bₐ·bₐ [1/m²], for the hourglass stiffness.
    pub bb: f64,
    /// An axis-aligned box ([`GaussData::axis_aligned`]): then bₐ = sₐ ⊙ β (sₐ the node's signs,
    /// [`HEX_CORNERS`]) and γᵅ = hᵅ hold exactly, and the one-point kernels take the modal
    /// path (`element::hex8::tensor`, (T3)).
    pub axis_aligned: bool,
    /// β_d = |b_{a,d}| on an axis-aligned box, 1/(8 ∂X_d/∂ξ_d) [1/m] (the mean of the eight
    /// |b_{a,d}|); 0 on other shapes.
    pub beta: [f64; 3],
    /// The 12 edges X_b − X_a of [`ORIENTED_EDGES`] [m], and 1/det[E_ξ, E_η, E_ζ] of each corner's
    /// three edges ([`CORNER_EDGES`]) [1/m³]: the corner Jacobians of the one-point rule's
    /// check, J_a = det[e_ξ, e_η, e_ζ](x)/det[E_ξ, E_η, E_ζ](X) (`kernels::corners`).
    pub edges: [[f64; 3]; 12],
    pub corner_inv_det: [f64; 8],
    /// C of the corner bound J_a ≥ J (1 − C|q|/s)³ (model §1.9,
    /// [`crate::kernels::corner_bound::corner_bound_constant`]): with it the one-point kernel
    /// skips the exact corner check where it cannot change what the check reports.
    pub corner_bound: f64,
    /// J₀⁻¹ = (∂X/∂ξ)⁻¹ at the centre, J₀ = ⅛ Σₐ Xₐ ⊗ ĉₐ (ĉₐ the node's corner of
    /// [`HEX_CORNERS`]) [1/m]: reference to parent coordinates, for the physical hourglass
    /// stabilisation (model §1.12).
    pub jinv0: [[f64; 3]; 3],
    /// ℓ_d = |∂X/∂ξ_d| at the centre, the half-lengths of the element along its parent axes
    /// [m] (model §1.12).
    pub half_lengths: [f64; 3],
}

/// The edges of the hexahedron as (a, b), b being a with one natural coordinate raised from −1
/// to +1 ([`HEX_CORNERS`]): four along ξ, four along η, four along ζ.
pub const ORIENTED_EDGES: [(usize, usize); 12] = [
    (0, 1),
    (3, 2),
    (4, 5),
    (7, 6),
    (0, 3),
    (1, 2),
    (4, 7),
    (5, 6),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

/// The edges of [`ORIENTED_EDGES`] that meet at each corner, along ξ, η, ζ. At corner a the
/// isoparametric Jacobian is ∂x/∂ξ = −½[s_ξ e_ξ, s_η e_η, s_ζ e_ζ] (s the corner's signs), so
/// det F there is det[e_ξ, e_η, e_ζ](x) / det[e_ξ, e_η, e_ζ](X): the signs cancel.
pub const CORNER_EDGES: [[usize; 3]; 8] = [
    [0, 4, 8],
    [0, 5, 9],
    [1, 5, 10],
    [1, 4, 11],
    [2, 6, 8],
    [2, 7, 9],
    [3, 7, 10],
    [3, 6, 11],
];

impl CentreData {
    /// From the node coordinates of the element and its Gauss data.
    pub fn new(x: &[[f64; 3]; 8], gd: &GaussData) -> CentreData {
        let volume = gd.volume();
        let mut b = [[0.0; 3]; 8];
        for a in 0..8 {
            for j in 0..3 {
                b[a][j] = gd.wgrad[a][j].iter().sum::<f64>() / volume;
            }
        }
        // On an axis-aligned box bₐ = sₐ ⊙ β in exact arithmetic; the eight sums above agree
        // with it to rounding, and the box takes β_d, the mean of the eight |b_{a,d}|.
        let mut axis_aligned = gd.axis_aligned;
        let mut beta = [0.0; 3];
        if axis_aligned {
            for (d, beta_d) in beta.iter_mut().enumerate() {
                *beta_d = (0..8).map(|a| HEX_CORNERS[a][d] * b[a][d]).sum::<f64>() / 8.0;
            }
            for (a, b_a) in b.iter_mut().enumerate() {
                *b_a = std::array::from_fn(|d| HEX_CORNERS[a][d] * beta[d]);
            }
        }
        let h = hourglass_vectors();
        let mut gamma = [[0.0; 8]; 4];
        for al in 0..4 {
            let mut hx = [0.0; 3];
            let mut magnitude = [0.0f64; 3];
            for c in 0..8 {
                for j in 0..3 {
                    hx[j] += h[al][c] * x[c][j];
                    magnitude[j] += x[c][j].abs();
                }
            }
            // Σ_c h_cᵅ X_c is zero for every affine X (hᵅ is orthogonal to the affine fields):
            // on a box γᵅ = hᵅ exactly, not hᵅ ± 1e-17.
            for j in 0..3 {
                hx[j] = zero_within_rounding(hx[j], magnitude[j]);
                axis_aligned &= hx[j] == 0.0;
            }
            for a in 0..8 {
                gamma[al][a] = h[al][a] - (hx[0] * b[a][0] + hx[1] * b[a][1] + hx[2] * b[a][2]);
            }
        }
        let bb = b.iter().map(|v| dot(*v, *v)).sum();
        let edges = ORIENTED_EDGES.map(|(a, b)| sub(x[b], x[a]));
        // A corner whose reference edges are not right-handed (a degenerate corner of a
        // hexahedron valid at its Gauss points) gets NaN: its corner J is NaN, which the
        // minimum over the corners passes over (that corner is not checked).
        let corner_inv_det = CORNER_EDGES.map(|[i, j, k]| {
            let d = dot(edges[i], cross(edges[j], edges[k]));
            if d > 0.0 {
                1.0 / d
            } else {
                f64::NAN
            }
        });
        let mut cd = CentreData {
            b,
            gamma,
            volume,
            bb,
            axis_aligned,
            beta: if axis_aligned { beta } else { [0.0; 3] },
            edges,
            corner_inv_det,
            corner_bound: f64::INFINITY,
            jinv0: [[0.0; 3]; 3],
            half_lengths: [0.0; 3],
        };
        cd.corner_bound = corner_bound_constant(&cd);
        let j0 =
            Matrix3::from_fn(|i, d| (0..8).map(|a| x[a][i] * HEX_CORNERS[a][d]).sum::<f64>() / 8.0);
        cd.half_lengths = std::array::from_fn(|d| j0.column(d).norm());
        // A valid element has det J₀ > 0 at its centre (the mean of its Gauss points' det J₀).
        if let Some(inv) = j0.try_inverse() {
            cd.jinv0 = std::array::from_fn(|d| std::array::from_fn(|i| inv[(d, i)]));
        }
        cd
    }
}

/// C of the corner-Jacobian bound ([`crate::kernels::corner_bound`], whose module docs derive
/// it): ‖A B⁻¹ − F‖₂ ≤ C |q| at every checked corner of an element
/// of shape `cd` [dimensionless per metre of hourglass amplitude: 1/m · m = 1 for q in m].
/// `f64::INFINITY` when G is singular (no bound).
pub fn corner_bound_constant(cd: &CentreData) -> f64 {
    let h = hourglass_vectors();
    let g = Matrix4::from_fn(|al, be| (0..8).map(|a| cd.gamma[al][a] * h[be][a]).sum::<f64>());
    let Some(g_inv) = g.try_inverse() else {
        return f64::INFINITY;
    };
    let m: [RowVector3<f64>; 4] = std::array::from_fn(|be| {
        (0..8).fold(RowVector3::zeros(), |s, a| {
            s + h[be][a] * RowVector3::from(cd.b[a])
        })
    });
    let mut c = 0.0f64;
    for (a, edges) in CORNER_EDGES.iter().enumerate() {
        if cd.corner_inv_det[a].is_nan() {
            continue;
        }
        let b = Matrix3::from_fn(|r, k| cd.edges[edges[k]][r]);
        let Some(b_inv) = b.try_inverse() else {
            return f64::INFINITY;
        };
        let w: [f64; 4] = std::array::from_fn(|be| {
            let s = RowVector3::from_fn(|_, k| {
                let (p, r) = ORIENTED_EDGES[edges[k]];
                h[be][r] - h[be][p]
            });
            (s * b_inv - m[be]).norm()
        });
        let ca: f64 = (0..4)
            .map(|al| {
                let x: f64 = (0..4).map(|be| w[be] * g_inv[(be, al)].abs()).sum();
                x * x
            })
            .sum();
        c = c.max(ca.sqrt());
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradients_reproduce_linear_fields() {
        // Σ_a X_a ⊗ ∇N_a = I at every Gauss point of a distorted element.
        let mut x = HEX_CORNERS.map(|c| [c[0] * 0.5 + 1.0, c[1] * 0.3, c[2] * 0.7]);
        x[6][0] += 0.1;
        x[3][2] -= 0.05;
        let gd = GaussData::new(&x).unwrap();
        for q in 0..8 {
            for i in 0..3 {
                for j in 0..3 {
                    let s: f64 = (0..8).map(|a| x[a][i] * gd.grad[a][j][q]).sum();
                    assert!((s - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12);
                }
            }
        }
    }

    /// An axis-aligned box far from the origin, with cell sizes that are not powers of two:
    /// J₀ comes out exactly diagonal (its off-diagonal sums cancel only to round-off before
    /// the snap), ⅛ ∂ξ_d/∂X_d = ¼/Δ_d to round-off. A box rotated by 30°, or one node moved by
    /// 1e-6 of the cell (a shear of ~1e-8 in J₀'s entries, against the snap's threshold
    /// 8ε Σ|tₐ| ≈ 2e-12 at |X| = 1000), is not axis-aligned.
    #[test]
    fn axis_aligned_boxes_have_diagonal_jacobians_and_others_not() {
        let (lo, d) = ([1000.3, -7.1, 3.3], [0.3 / 7.0, 0.11, 0.7 / 3.0]);
        let boxed = |i: usize, j: usize, k: usize| -> [[f64; 3]; 8] {
            HEX_CORNERS.map(|c| {
                let n = [i, j, k];
                let mut x = [0.0; 3];
                for r in 0..3 {
                    let at = n[r] as f64 + 0.5 * (c[r] + 1.0);
                    x[r] = lo[r] + at * d[r];
                }
                x
            })
        };
        let mut checked = 0;
        for (i, j, k) in [(0, 0, 0), (3, 5, 2), (17, 1, 9)] {
            let gd = GaussData::new(&boxed(i, j, k)).unwrap();
            assert!(gd.axis_aligned, "cell ({i}, {j}, {k})");
            // One point: bₐ = sₐ ⊙ β with β_d = 1/(4 L_d), within rounding of the Gauss sums
            // it replaces, and γᵅ = hᵅ exactly. (Rounding here: X ~ 1000 against cells of
            // 0.04–0.2 leaves J₀ ≈ 1e-12 relative, as for ⅛J₀⁻¹ above.)
            let cd = CentreData::new(&boxed(i, j, k), &gd);
            assert!(cd.axis_aligned, "cell ({i}, {j}, {k})");
            assert_eq!(cd.gamma, hourglass_vectors());
            for a in 0..8 {
                for r in 0..3 {
                    let beta = 0.25 / d[r];
                    assert!((cd.beta[r] - beta).abs() <= 1e-9 * beta);
                    assert_eq!(cd.b[a][r], HEX_CORNERS[a][r] * cd.beta[r]);
                    let summed = gd.wgrad[a][r].iter().sum::<f64>() / gd.volume();
                    assert!((summed - cd.b[a][r]).abs() <= 1e-9 * beta);
                }
            }
            for q in 0..8 {
                for r in 0..3 {
                    for c in 0..3 {
                        if r == c {
                            let expect = 0.25 / d[r];
                            assert!((gd.jinv[r][c][q] - expect).abs() <= 1e-9 * expect);
                        } else {
                            assert_eq!(gd.jinv[r][c][q], 0.0);
                            assert_eq!(gd.wjinv[r][c][q], 0.0);
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert_eq!(checked, 3 * 8 * 6);
        let mut sheared = boxed(3, 5, 2);
        sheared[6][0] += 1e-6 * d[0];
        let (s, c) = (0.5f64, 0.75f64.sqrt());
        let rotated = boxed(1, 1, 1).map(|x| [c * x[0] - s * x[1], s * x[0] + c * x[1], x[2]]);
        for (what, x) in [("sheared", sheared), ("rotated", rotated)] {
            let gd = GaussData::new(&x).unwrap();
            assert!(!gd.axis_aligned, "{what}");
            let cd = CentreData::new(&x, &gd);
            assert!(!cd.axis_aligned && cd.beta == [0.0; 3], "{what}");
            // γᵅ = hᵅ exactly on any parallelepiped (X affine in ξ), not on the sheared cell.
            assert_eq!(cd.gamma == hourglass_vectors(), what == "rotated", "{what}");
        }
    }
}
