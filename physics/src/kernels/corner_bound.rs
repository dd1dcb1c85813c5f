//! A cheap lower bound on the corner Jacobians of the one-point rule ([`super::corners`]) from
//! what the one-point kernel has at the centre: J = det F, ‖F‖ and the hourglass amplitudes
//! qᵅ = Σₐ γₐᵅ uₐ.
//!
//! **Derivation.** Every nodal field of a non-degenerate hexahedron splits uniquely as
//! uₐ = c + H̃ Xₐ + Σᵝ dᵝ hₐᵝ (a constant, an affine part, the four hourglass base vectors
//! hᵝ of [`crate::mesh::hourglass_vectors`]). The mean gradients satisfy Σₐ bₐ = 0 and
//! Σₐ Xₐ ⊗ bₐ = I (Σₐ Nₐ = 1 and Σₐ Xₐ Nₐ = X pointwise, so also on average), hence the
//! kernel's H = Σₐ uₐ ⊗ bₐ = H̃ + Σᵝ dᵝ ⊗ mᵝ with mᵝ = Σₐ hₐᵝ bₐ; and γᵅ is orthogonal to the
//! constant and affine fields, so qᵅ = Σᵝ Gᵅᵝ dᵝ with Gᵅᵝ = γᵅ·hᵝ, d = G⁻¹q.
//! At corner a with reference edges B = [E_ξ, E_η, E_ζ] (columns) the current edges are
//! Eₖ + u_r − u_p = (I + H̃)Eₖ + Σᵝ dᵝ (h_rᵝ − h_pᵝ), so with the row Sₐᵝ of these hourglass
//! differences, A = (I + H̃)B + Σᵝ dᵝ ⊗ Sₐᵝ and
//!
//!   A B⁻¹ = F + Δₐ,   Δₐ = Σᵝ dᵝ ⊗ wₐᵝ,   wₐᵝ = Sₐᵝ B⁻¹ − mᵝ,   F = I + H,
//!
//! and J_a = det A / det B = det(F + Δₐ). A rank-one term has ‖d ⊗ w‖₂ = |d||w|, so
//! ‖Δₐ‖₂ ≤ Σᵝ |dᵝ||wₐᵝ| ≤ Σᵅ |qᵅ| Σᵝ |wₐᵝ||(G⁻¹)ᵝᵅ| ≤ C |q| (Cauchy–Schwarz over α), with
//! C = maxₐ (Σᵅ (Σᵝ |wₐᵝ||(G⁻¹)ᵝᵅ|)²)^½ a constant of the element's shape
//! ([`corner_bound_constant`]) and |q|² = Σᵅ |qᵅ|².
//! The singular values of F + Δ differ from F's by at most δ = ‖Δ‖₂ (Weyl); if J > 0 and
//! δ < σ_min(F), F + tΔ stays regular for t ∈ [0, 1], so det(F + Δ) keeps the sign of J and
//! det(F + Δ) ≥ Πᵢ(σᵢ − δ) ≥ J (1 − δ/σ_min)³. Finally σ_min = J/(σ₁σ₂) ≥ 2J/‖F‖²_F
//! (σ₁σ₂ ≤ (σ₁² + σ₂²)/2 ≤ ‖F‖²_F/2), so with s = 2J/‖F‖²_F:
//!
//!   J_a ≥ J (1 − C|q|/s)³  for every corner a, when J > 0 and C|q| < s
//!
//! ([`corner_lower_bound`]; −∞ otherwise). Corners whose reference edges are not right-handed
//! (NaN in `corner_inv_det`, not checked by the exact route either) are left out of C.

pub use crate::mesh::corner_bound_constant;

/// The lower bound J (1 − C|q|/s)³, s = 2J/‖F‖²_F, on every corner Jacobian (module docs):
/// `c` from [`corner_bound_constant`], `j` = det F and `f_norm2` = ‖F‖²_F at the centre,
/// `q_norm2` = Σᵅ |qᵅ|². −∞ when the bound does not apply (J ≤ 0, C|q| ≥ s, a NaN).
#[inline(always)]
pub fn corner_lower_bound(c: f64, j: f64, f_norm2: f64, q_norm2: f64) -> f64 {
    let s = 2.0 * j / f_norm2;
    let r = 1.0 - c * q_norm2.sqrt() / s;
    if j > 0.0 && r > 0.0 {
        j * r * r * r
    } else {
        f64::NEG_INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::corners::element_corner_jacobians;
    use crate::mesh::{hourglass_vectors, CentreData, GaussData, HEX_CORNERS};
    use nalgebra::Matrix3;
    use proptest::prelude::*;

    /// J = det F, ‖F‖²_F and Σᵅ|qᵅ|² of an element, computed here independently of the
    /// kernels (F = I + Σₐ uₐ ⊗ bₐ, qᵅ = Σₐ γₐᵅ uₐ).
    fn centre(cd: &CentreData, u: &[[f64; 3]; 8]) -> (f64, f64, f64) {
        let f = Matrix3::from_fn(|i, j| {
            (0..8).map(|a| u[a][i] * cd.b[a][j]).sum::<f64>() + if i == j { 1.0 } else { 0.0 }
        });
        let qq: f64 = (0..4)
            .map(|al| {
                (0..3)
                    .map(|i| {
                        (0..8)
                            .map(|a| cd.gamma[al][a] * u[a][i])
                            .sum::<f64>()
                            .powi(2)
                    })
                    .sum::<f64>()
            })
            .sum();
        (f.determinant(), f.norm_squared(), qq)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        /// The bound is below every checked corner J on random elements: distorted shapes
        /// (each node moved up to 30 % of the edge, an aspect ratio up to 4), a random affine
        /// stretch and rotation, and random hourglass modes up to 40 % of the edge; the exact
        /// corner J from [`element_corner_jacobians`]. The bound is exact arithmetic; the
        /// margin 1e-12 covers the rounding of both routes (J of order 1).
        #[test]
        fn bound_is_below_every_corner_jacobian(
            shape in prop::array::uniform8(prop::array::uniform3(-0.3f64..0.3)),
            aspect in prop::array::uniform3(0.25f64..1.0),
            g in prop::array::uniform3(prop::array::uniform3(-0.4f64..0.4)),
            modes in prop::array::uniform4(prop::array::uniform3(-0.4f64..0.4)),
            hg_scale in prop::sample::select(vec![0.0, 1e-4, 1e-2, 0.1, 1.0]),
        ) {
            let x: [[f64; 3]; 8] = std::array::from_fn(|a| {
                std::array::from_fn(|j| (HEX_CORNERS[a][j] + shape[a][j]) * aspect[j])
            });
            let Ok(gd) = GaussData::new(&x) else { return Ok(()) };
            let cd = CentreData::new(&x, &gd);
            let h = hourglass_vectors();
            let u: [[f64; 3]; 8] = std::array::from_fn(|a| {
                std::array::from_fn(|i| {
                    let affine: f64 = (0..3).map(|j| g[i][j] * x[a][j]).sum();
                    let hg: f64 = (0..4).map(|be| modes[be][i] * h[be][a]).sum();
                    affine + hg_scale * hg * aspect[i]
                })
            });
            let c = corner_bound_constant(&cd);
            let (j, f2, qq) = centre(&cd, &u);
            let bound = corner_lower_bound(c, j, f2, qq);
            for (a, ja) in element_corner_jacobians(&cd, &u).into_iter().enumerate() {
                if ja.is_nan() {
                    continue;
                }
                prop_assert!(bound <= ja + 1e-12, "corner {a}: bound {bound} > J {ja} (J {j})");
            }
        }
    }

    /// Sharpness where it is used: with no hourglass mode the bound is J itself (every corner
    /// of an affine field has J = det F); in the ξη mode u_x = t s_ξ s_η of a cube, whose
    /// corners have J_a = 1 ∓ 2t/L exactly (L the edge; `physics/tests/corner_jacobian.rs`),
    /// the bound stays below and within a factor 15 of the exact deficit 2t/L.
    #[test]
    fn bound_is_det_f_without_hourglassing_and_close_with_it() {
        let x = HEX_CORNERS.map(|c| [c[0] * 0.3, c[1] * 0.2, c[2] * 0.25]);
        let gd = GaussData::new(&x).unwrap();
        let cd = CentreData::new(&x, &gd);
        let c = corner_bound_constant(&cd);
        assert!(c.is_finite() && c > 0.0);
        let f = Matrix3::new(1.1, 0.02, 0.0, 0.0, 0.95, 0.03, 0.01, 0.0, 1.0);
        let j = f.determinant();
        assert_eq!(corner_lower_bound(c, j, f.norm_squared(), 0.0), j);
        let cube = HEX_CORNERS.map(|c| c.map(|v| 0.5 * v));
        let cd = CentreData::new(&cube, &GaussData::new(&cube).unwrap());
        let c = corner_bound_constant(&cd);
        for t in [1e-4, 1e-3, 1e-2] {
            let u: [[f64; 3]; 8] =
                std::array::from_fn(|a| [t * HEX_CORNERS[a][0] * HEX_CORNERS[a][1], 0.0, 0.0]);
            let (j, f2, qq) = centre(&cd, &u);
            let exact = element_corner_jacobians(&cd, &u)
                .into_iter()
                .fold(f64::INFINITY, f64::min);
            assert!((exact - (1.0 - 2.0 * t)).abs() < 1e-14);
            let bound = corner_lower_bound(c, j, f2, qq);
            assert!(
                bound <= exact && 1.0 - bound <= 15.0 * (1.0 - exact),
                "{t}: {bound}"
            );
        }
    }

    /// The whole-vector bound of the AVX builds is the per-lane bound bit for bit, on lanes
    /// that take every branch: J ≤ 0, 1 − C|q|/s ≤ 0, C = ∞, q = 0, NaN.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn vector_bound_is_the_lane_bound_bit_for_bit() {
        use crate::kernels::simd::{corner_bound_avx2, corner_bound_avx512};
        let c = [0.7, 1.3, f64::INFINITY, 0.2, 2.0, 0.01, 0.5, f64::NAN];
        let j = [1.02, 0.93, 1.0, -0.1, 0.999, 1.7, 0.0, 1.0];
        let f2 = [3.1, 2.8, 3.0, 3.3, 3.0, 5.9, 3.0, 3.0];
        let q2 = [1e-4, 2.5, 1e-6, 1e-4, 0.0, 0.3, 1e-4, 1e-4];
        let lane: Vec<u64> = (0..8)
            .map(|l| corner_lower_bound(c[l], j[l], f2[l], q2[l]).to_bits())
            .collect();
        assert!(lane.iter().filter(|&&b| f64::from_bits(b) > 0.0).count() >= 3);
        assert!(
            lane.iter()
                .filter(|&&b| f64::from_bits(b) == f64::NEG_INFINITY)
                .count()
                >= 3
        );
        let bits = |b: [f64; 8]| b.map(f64::to_bits).to_vec();
        if std::is_x86_feature_detected!("avx2") {
            assert_eq!(bits(unsafe { corner_bound_avx2(&c, &j, &f2, &q2) }), lane);
        }
        if std::is_x86_feature_detected!("avx512f") {
            assert_eq!(bits(unsafe { corner_bound_avx512(&c, &j, &f2, &q2) }), lane);
        }
    }
}
