//! The corner Jacobians of one-point integration. The one-point rule evaluates F only at the
//! element centre, where the hourglass modes have no gradient: an element can turn inside out
//! at a corner (hourglassing) with J(0) > 0 and the run would go on with inverted corners. So
//! the one-point kernels also take, per element, the smallest Jacobian of the trilinear map
//! at its 8 corners, J_a = det[e_ξ, e_η, e_ζ](x) / det[E_ξ, E_η, E_ζ](X) with e the current
//! and E the reference edges meeting at corner a ([`crate::mesh::CORNER_EDGES`]; the signs of
//! ∂x/∂ξ = −½[s_ξe_ξ, s_η e_η, s_ζ e_ζ] cancel in the ratio). e_k = E_k + (u_b − u_a) needs only
//! the displacements the kernel has gathered and per-shape constants: 12 edges and 8 triple
//! products per element, on the same 8 lanes as the kernel.

use super::corner_bound::corner_lower_bound;
use crate::element::hex8::OnePointScratch;
use crate::material::{F64x8, Real};
use crate::mesh::{CentreData, CORNER_EDGES, ORIENTED_EDGES};

/// det[c₀, c₁, c₂] = c₀·(c₁ × c₂).
#[inline(always)]
fn det3<T: Real, const FMA: bool>(c0: [T; 3], c1: [T; 3], c2: [T; 3]) -> T {
    let x = c1[1].fmadd::<FMA>(c2[2], T::splat(0.0) - c1[2] * c2[1]);
    let y = c1[2].fmadd::<FMA>(c2[0], T::splat(0.0) - c1[0] * c2[2]);
    let z = c1[0].fmadd::<FMA>(c2[1], T::splat(0.0) - c1[1] * c2[0]);
    c0[0].fmadd::<FMA>(x, c0[1].fmadd::<FMA>(y, c0[2] * z))
}

/// J at the 8 corners, J_a = det[e](x)/det[E](X), from the reference edges `edge(k, j)`, the
/// reciprocal reference determinants `inv_det(a)` and the nodal displacements `u(a, j)`.
/// Written out edge by edge and corner by corner with constant indices, so that the tables
/// fold into the code: a loop over them kept a zero-initialised 2.3 kB array of edges (a
/// `memset` call per lane group) and bounds checks on the table entries. (No
/// `std::array::from_fn` either: its closures were not inlined into the kernels'
/// `target_feature` builds, which ran much slower; docs: performance log.)
#[inline(always)]
pub(super) fn corner_jacobians<T: Real, const FMA: bool>(
    edge: impl Fn(usize, usize) -> T,
    inv_det: impl Fn(usize) -> T,
    u: impl Fn(usize, usize) -> T,
) -> [T; 8] {
    let e = [
        edge_now(0, &edge, &u),
        edge_now(1, &edge, &u),
        edge_now(2, &edge, &u),
        edge_now(3, &edge, &u),
        edge_now(4, &edge, &u),
        edge_now(5, &edge, &u),
        edge_now(6, &edge, &u),
        edge_now(7, &edge, &u),
        edge_now(8, &edge, &u),
        edge_now(9, &edge, &u),
        edge_now(10, &edge, &u),
        edge_now(11, &edge, &u),
    ];
    [
        corner_jacobian::<T, FMA>(0, &e, &inv_det),
        corner_jacobian::<T, FMA>(1, &e, &inv_det),
        corner_jacobian::<T, FMA>(2, &e, &inv_det),
        corner_jacobian::<T, FMA>(3, &e, &inv_det),
        corner_jacobian::<T, FMA>(4, &e, &inv_det),
        corner_jacobian::<T, FMA>(5, &e, &inv_det),
        corner_jacobian::<T, FMA>(6, &e, &inv_det),
        corner_jacobian::<T, FMA>(7, &e, &inv_det),
    ]
}

/// Edge k of [`ORIENTED_EDGES`] now, e_k = E_k + (u_b − u_a).
#[inline(always)]
fn edge_now<T: Real>(
    k: usize,
    edge: &impl Fn(usize, usize) -> T,
    u: &impl Fn(usize, usize) -> T,
) -> [T; 3] {
    let (a, b) = ORIENTED_EDGES[k];
    [
        edge(k, 0) + (u(b, 0) - u(a, 0)),
        edge(k, 1) + (u(b, 1) - u(a, 1)),
        edge(k, 2) + (u(b, 2) - u(a, 2)),
    ]
}

/// J at corner a from the current edges `e`: det[e_i, e_j, e_k] / det[E_i, E_j, E_k].
#[inline(always)]
fn corner_jacobian<T: Real, const FMA: bool>(
    a: usize,
    e: &[[T; 3]; 12],
    inv_det: &impl Fn(usize) -> T,
) -> T {
    let [i, j, k] = CORNER_EDGES[a];
    det3::<T, FMA>(e[i], e[j], e[k]) * inv_det(a)
}

/// The corner Jacobians of one element (`cd` its shape, `u` its nodal displacements).
pub fn element_corner_jacobians(cd: &CentreData, u: &[[f64; 3]; 8]) -> [f64; 8] {
    corner_jacobians::<f64, false>(
        |k, j| cd.edges[k][j],
        |a| cd.corner_inv_det[a],
        |a, j| u[a][j],
    )
}

/// The smallest corner Jacobian of one element (a NaN corner, one not checked, is passed over).
#[inline(always)]
pub fn min_corner_jacobian(cd: &CentreData, u: &[[f64; 3]; 8]) -> f64 {
    let j = element_corner_jacobians(cd, u);
    j.iter()
        .fold(f64::INFINITY, |m, &x| if x < m { x } else { m })
}

/// The corner data of 8 elements, one per lane, staged as [`crate::element::hex8::LaneElements`]
/// (aligned to a cache line as it is).
#[derive(Debug, Clone, Copy)]
#[repr(align(64))]
pub struct LaneCorners {
    edges: [[[f64; 8]; 3]; 12],
    inv_det: [[f64; 8]; 8],
    /// C of the corner bound ([`CentreData::corner_bound`]).
    bound: [f64; 8],
}

impl Default for LaneCorners {
    fn default() -> Self {
        LaneCorners {
            edges: [[[0.0; 8]; 3]; 12],
            inv_det: [[0.0; 8]; 8],
            bound: [f64::INFINITY; 8],
        }
    }
}

impl LaneCorners {
    /// Puts the element shape `cd` into lane `l`.
    #[inline(always)]
    pub fn set(&mut self, l: usize, cd: &CentreData) {
        for k in 0..12 {
            for j in 0..3 {
                self.edges[k][j][l] = cd.edges[k][j];
            }
        }
        for a in 0..8 {
            self.inv_det[a][l] = cd.corner_inv_det[a];
        }
        self.bound[l] = cd.corner_bound;
    }

    /// Per lane, the lower bound J (1 − C|q|/s)³, s = 2J/‖F‖²_F, of every corner Jacobian
    /// (model §1.9; [`super::corner_bound::corner_lower_bound`], derived there): `det` the
    /// centre's J = det F that the one-point kernel returned, `work` its F − I = H and
    /// hourglass amplitudes qᵅ. −∞ where the bound does not apply. `ISA`: whole vectors in
    /// the AVX builds ([`super::simd::corner_bound_avx512`], the same bits as lane by lane).
    #[inline(always)]
    pub fn lower_bound<const ISA: u8>(&self, det: &[f64; 8], work: &OnePointScratch) -> [f64; 8] {
        let (f_norm2, q_norm2) = work.centre_norms();
        #[cfg(target_arch = "x86_64")]
        {
            use super::simd::{corner_bound_avx2, corner_bound_avx512, ISA_AVX2, ISA_AVX512};
            // SAFETY: the AVX builds run only on CPUs that have the features (`simd_dispatch!`).
            if ISA == ISA_AVX512 {
                return unsafe { corner_bound_avx512(&self.bound, det, &f_norm2, &q_norm2) };
            }
            if ISA == ISA_AVX2 {
                return unsafe { corner_bound_avx2(&self.bound, det, &f_norm2, &q_norm2) };
            }
        }
        let mut b = [0.0; 8];
        for l in 0..8 {
            b[l] = corner_lower_bound(self.bound[l], det[l], f_norm2[l], q_norm2[l]);
        }
        b
    }

    /// The smallest corner Jacobian of each lane's element, `u[a][j][lane]` the displacements.
    #[inline(always)]
    pub fn min_jacobian<const FMA: bool>(&self, u: &[[[f64; 8]; 3]; 8]) -> [f64; 8] {
        let j = corner_jacobians::<F64x8, FMA>(
            |k, c| F64x8(self.edges[k][c]),
            |a| F64x8(self.inv_det[a]),
            |a, c| F64x8(u[a][c]),
        );
        // A select, not a conditional store: LLVM kept the store's branches (8 lanes × 8
        // corners of compares and jumps, which an unrelated change brought back into a one-point
        // step's profile; docs: performance log) where a select becomes one compare-and-blend
        // (minpd's rule) per corner.
        let mut m = [f64::INFINITY; 8];
        for ja in j {
            for l in 0..8 {
                m[l] = if ja.0[l] < m[l] { ja.0[l] } else { m[l] };
            }
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{GaussData, HEX_CORNERS};

    /// The edge tables against the corner coordinates: each edge raises one coordinate from
    /// −1 to +1, and each corner's three edges are along ξ, η, ζ and contain it.
    #[test]
    fn edge_tables_follow_the_corners() {
        for (k, &(a, b)) in ORIENTED_EDGES.iter().enumerate() {
            let d = k / 4;
            for c in 0..3 {
                let expect = if c == d { 2.0 } else { 0.0 };
                assert_eq!(HEX_CORNERS[b][c] - HEX_CORNERS[a][c], expect, "edge {k}");
            }
        }
        for (a, edges) in CORNER_EDGES.iter().enumerate() {
            for (d, &k) in edges.iter().enumerate() {
                assert_eq!(k / 4, d);
                assert!(ORIENTED_EDGES[k].0 == a || ORIENTED_EDGES[k].1 == a);
            }
        }
    }

    /// The corner J against det(∂x/∂ξ)/det(∂X/∂ξ) from the shape-function derivatives at the
    /// corner (an independent route), on a distorted element with a large displacement, in
    /// f64 and on the 8 lanes (with and without FMA); an affine field gives det F at every
    /// corner; one corner pushed through the opposite face reads J < 0 there only.
    #[test]
    fn corner_jacobians_match_the_isoparametric_map() {
        let mut x = HEX_CORNERS.map(|c| [c[0] * 0.3, c[1] * 0.2, c[2] * 0.25]);
        x[6][0] += 0.05;
        x[1][2] -= 0.03;
        let gd = GaussData::new(&x).unwrap();
        let cd = CentreData::new(&x, &gd);
        let u: [[f64; 3]; 8] = std::array::from_fn(|a| {
            let t = a as f64;
            [
                0.03 * t.sin(),
                0.02 * (1.3 * t).cos(),
                -0.04 * (0.7 * t).sin(),
            ]
        });
        let jac = |p: &[[f64; 3]; 8], xi: [f64; 3]| {
            let dn = crate::mesh::shape_derivatives(xi);
            nalgebra::Matrix3::from_fn(|r, c| (0..8).map(|a| p[a][r] * dn[a][c]).sum::<f64>())
                .determinant()
        };
        let xc: [[f64; 3]; 8] = std::array::from_fn(|a| std::array::from_fn(|j| x[a][j] + u[a][j]));
        let j = element_corner_jacobians(&cd, &u);
        let mut lanes = LaneCorners::default();
        let mut ul = [[[0.0; 8]; 3]; 8];
        for l in 0..8 {
            lanes.set(l, &cd);
            for a in 0..8 {
                for c in 0..3 {
                    ul[a][c][l] = u[a][c];
                }
            }
        }
        for (a, xi) in HEX_CORNERS.iter().enumerate() {
            let expect = jac(&xc, *xi) / jac(&x, *xi);
            assert!(
                (j[a] - expect).abs() <= 1e-13,
                "corner {a}: {} vs {expect}",
                j[a]
            );
        }
        let m = j.iter().copied().fold(f64::INFINITY, f64::min);
        for lane_min in [
            lanes.min_jacobian::<false>(&ul),
            lanes.min_jacobian::<true>(&ul),
        ] {
            assert!(lane_min.iter().all(|&v| (v - m).abs() <= 1e-13));
        }
        // Affine: u = G X, J = det(I + G) at every corner.
        let g = [[0.1, 0.02, -0.03], [0.01, -0.2, 0.05], [0.0, 0.04, 0.15]];
        let ua: [[f64; 3]; 8] = std::array::from_fn(|a| {
            std::array::from_fn(|r| (0..3).map(|c| g[r][c] * x[a][c]).sum())
        });
        let f = nalgebra::Matrix3::from_fn(|r, c| g[r][c] + if r == c { 1.0 } else { 0.0 });
        for v in element_corner_jacobians(&cd, &ua) {
            assert!((v - f.determinant()).abs() <= 1e-13);
        }
        // Node 6 pushed past the centre towards node 0: corner 6 inverts, the centre does not.
        let mut ui = [[0.0; 3]; 8];
        ui[6] = [-0.45, -0.3, -0.375];
        let ji = element_corner_jacobians(&cd, &ui);
        assert!(ji[6] < 0.0 && ji[0] > 0.0, "{ji:?}");
        assert!(
            jac(
                &std::array::from_fn(|a| std::array::from_fn(|c| x[a][c] + ui[a][c])),
                [0.0; 3]
            ) > 0.0
        );
    }
}
