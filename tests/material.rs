//! The materials and the element kernels against model §1.3–§1.6 written out by hand
//! (`by_hand`), at ν = 0.45 so that λ (9 μ here) weighs: the Lamé constants, the P-wave modulus
//! and speed, the pointwise stress, and each element kernel (full 2×2×2, one point, one point on
//! 8 elements in lanes) on distorted elements under homogeneous deformations, where the
//! nodal forces are exactly those of the constant stress: Σₐ fₐ ⊗ Xₐ = V P (the virtual work
//! of every homogeneous δu = G X) and Σₐ fₐ = 0, the strain energy is ψ V and J = det F.

use crate::by_hand::{deformations, lame, piola_energy, stress_scale};
use decohesion::element::hex8::{
    element_forces, element_forces_reduced, element_forces_reduced_lanes, hourglass_stiffness,
    LaneElements,
};
use decohesion::material::{Material, MaterialModel};
use decohesion::mesh::{CentreData, GaussData, HEX_CORNERS};
use nalgebra::{Matrix3, Vector3};

const YOUNG: f64 = 5e6;
const NU: f64 = 0.45;
const RHO: f64 = 1100.0;
const MODELS: [MaterialModel; 2] = [MaterialModel::Svk, MaterialModel::NeoHookean];

/// At E = 5 MPa, ν = 0.45, ρ = 1100 kg/m³, by hand: λ = 5·0.45/(1.45·0.1) = 450/29 MPa,
/// μ = 5/2.9 = 50/29 MPa, M = λ + 2μ = E(1−ν)/((1+ν)(1−2ν)) = 550/29 MPa,
/// c = √(M/ρ) = √(10⁶/58) m/s. Each is a few roundings away: 1e-14 relative.
#[test]
fn lame_constants_p_wave_modulus_and_wave_speed() {
    let mat = Material::new(MaterialModel::Svk, YOUNG, NU, RHO);
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-14 * b.abs();
    assert!(near(mat.lambda, 450e6 / 29.0), "λ = {}", mat.lambda);
    assert!(near(mat.mu, 50e6 / 29.0), "μ = {}", mat.mu);
    assert!(near(mat.p_wave_modulus(), 550e6 / 29.0));
    assert!(near(mat.wave_speed(), (1e6f64 / 58.0).sqrt()));
    // M = E(1−ν)/((1+ν)(1−2ν)) and the same λ, μ over the admissible range of ν.
    for nu in [-0.5, 0.0, 0.3, 0.49, 0.499] {
        let mat = Material::new(MaterialModel::NeoHookean, YOUNG, nu, RHO);
        let m = YOUNG * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
        assert!(near(mat.p_wave_modulus(), m), "ν = {nu}");
        assert!(near(mat.wave_speed(), (m / RHO).sqrt()), "ν = {nu}");
        let (lambda, mu) = lame(YOUNG, nu);
        assert!(
            (mat.lambda - lambda).abs() <= 1e-14 * m && near(mat.mu, mu),
            "ν = {nu}"
        );
    }
}

/// The pointwise P and ψ, and σ = J⁻¹ P Fᵀ = J⁻¹ F S Fᵀ, against the formulas by hand.
#[test]
fn pointwise_stress_and_energy_match_the_formulas() {
    for model in MODELS {
        let mat = Material::new(model, YOUNG, NU, RHO);
        for (name, f) in deformations() {
            let (p, psi) = mat.piola_energy(&f);
            let (p_hand, psi_hand) = piola_energy(model, YOUNG, NU, &f);
            let scale = stress_scale(YOUNG, NU, &f);
            assert!(
                (p - p_hand).abs().max() <= 1e-12 * scale,
                "{model:?} {name}: P = {p} by hand {p_hand}"
            );
            assert!(
                (psi - psi_hand).abs() <= 1e-12 * scale,
                "{model:?} {name}: ψ"
            );
            let j = f.determinant();
            let sigma_hand = p_hand * f.transpose() / j;
            assert!(
                (mat.cauchy_stress(&f) - sigma_hand).abs().max() <= 1e-12 * scale,
                "{model:?} {name}: σ"
            );
        }
    }
}

/// Objectivity of the pointwise law: P(RF) = R P(F), ψ(RF) = ψ(F).
#[test]
fn pointwise_stress_is_objective() {
    let r = *nalgebra::Rotation3::from_axis_angle(
        &nalgebra::Unit::new_normalize(Vector3::new(1.0, 2.0, -0.5)),
        1.7,
    )
    .matrix();
    for model in MODELS {
        let mat = Material::new(model, YOUNG, NU, RHO);
        for (name, f) in deformations() {
            let (p1, psi1) = mat.piola_energy(&f);
            let (p2, psi2) = mat.piola_energy(&(r * f));
            let scale = stress_scale(YOUNG, NU, &f);
            assert!(
                (r * p1 - p2).abs().max() <= 1e-12 * scale,
                "{model:?} {name}"
            );
            assert!((psi1 - psi2).abs() <= 1e-12 * scale, "{model:?} {name}");
        }
    }
}

/// A distorted hexahedron (0.4 × 0.25 × 0.3 m, one corner moved by `k`-dependent amounts), so
/// that the Gauss points see different gradients and no two test elements are alike.
fn distorted_element(k: usize) -> [[f64; 3]; 8] {
    let mut x = HEX_CORNERS.map(|c| [0.2 * c[0] + 1.0, 0.125 * c[1] - 0.3, 0.15 * c[2] + 0.5]);
    let t = k as f64 + 1.0;
    x[(k + 5) % 8][k % 3] += 0.04 * t.sin();
    x[(k + 2) % 8][(k + 1) % 3] -= 0.03 * (1.7 * t).cos();
    x
}

/// U = (F − I) X at the nodes.
fn homogeneous(x: &[[f64; 3]; 8], f: &Matrix3<f64>) -> [[f64; 3]; 8] {
    x.map(|xa| {
        let u = (f - Matrix3::identity()) * Vector3::from(xa);
        [u[0], u[1], u[2]]
    })
}

/// Checks the forces `f`, strain energy and J of one element of nodes `x` and volume `vol`
/// under the homogeneous F against the formulas by hand: V⁻¹ Σₐ fₐ ⊗ Xₐ = P and Σₐ fₐ = 0 to
/// 1e-12 of [`stress_scale`] (the sums over 8 nodes of coordinates ≤ 1.2 m add ≲ 10 ε), energy
/// ψ V to 1e-12 of the scale times V, J = det F to 1e-13 |F|³.
#[allow(clippy::too_many_arguments)]
fn check_element(
    what: &str,
    model: MaterialModel,
    f_def: &Matrix3<f64>,
    x: &[[f64; 3]; 8],
    vol: f64,
    f: &[[f64; 3]; 8],
    strain: f64,
    j: f64,
) {
    let (p_hand, psi_hand) = piola_energy(model, YOUNG, NU, f_def);
    let scale = stress_scale(YOUNG, NU, f_def);
    let mut p = Matrix3::zeros();
    let mut sum = Vector3::zeros();
    for a in 0..8 {
        p += Vector3::from(f[a]) * Vector3::from(x[a]).transpose() / vol;
        sum += Vector3::from(f[a]);
    }
    assert!(
        (p - p_hand).abs().max() <= 1e-12 * scale,
        "{what}: V⁻¹ Σ f ⊗ X = {p}, P by hand {p_hand}"
    );
    assert!(
        sum.abs().max() <= 1e-12 * scale * vol,
        "{what}: Σ f = {sum}"
    );
    assert!(
        (strain - psi_hand * vol).abs() <= 1e-12 * scale * vol,
        "{what}: energy {strain} vs ψ V = {}",
        psi_hand * vol
    );
    let j_scale = f_def.abs().max().powi(3);
    assert!(
        (j - f_def.determinant()).abs() <= 1e-13 * j_scale,
        "{what}: J = {j}"
    );
}

/// Full 2×2×2 integration, with and without fused multiply–adds, and one point with hourglass
/// control: a homogeneous field excites no hourglass mode (γ ⟂ affine fields), so the one-point
/// forces are V P bₐ and the hourglass energy is round-off.
#[test]
fn element_kernels_match_the_formulas() {
    for model in MODELS {
        let mat = Material::new(model, YOUNG, NU, RHO);
        for (k, (name, f_def)) in deformations().into_iter().enumerate() {
            let x = distorted_element(k);
            let gd = GaussData::new(&x).unwrap();
            let u = homogeneous(&x, &f_def);
            let mut f = [[0.0; 3]; 8];
            for fma in [false, true] {
                let (strain, j) = if fma {
                    element_forces::<true, true>(&mat, &gd, &u, &mut f)
                } else {
                    element_forces::<true, false>(&mat, &gd, &u, &mut f)
                };
                let what = format!("{model:?} {name} full, FMA {fma}");
                check_element(&what, model, &f_def, &x, gd.volume(), &f, strain, j);
            }
            let cd = CentreData::new(&x, &gd);
            let k_hg = hourglass_stiffness(&mat, &cd, 0.1);
            let (strain, hg, j) = element_forces_reduced::<true>(&mat, &cd, k_hg, &u, &mut f);
            let what = format!("{model:?} {name} one point");
            check_element(&what, model, &f_def, &x, cd.volume, &f, strain, j);
            // q = Σ γ u of an affine u: |q| ~ ε |u|, Ψ_hg = ½ k |q|² ~ k ε² |u|².
            assert!(hg.abs() <= 1e-20 * k_hg, "{what}: Ψ_hg = {hg}");
        }
    }
}

/// One point on 8 elements at once, one per lane, each with its own shape and deformation
/// (the lanes must not mix), with and without fused multiply–adds.
#[test]
fn one_point_lane_kernel_matches_the_formulas() {
    let defs = deformations();
    let lanes: Vec<([[f64; 3]; 8], Matrix3<f64>)> = (0..8)
        .map(|l| {
            let f = defs[l % defs.len()].1 * (1.0 + 0.01 * l as f64);
            (distorted_element(l + 3), f)
        })
        .collect();
    let cds: Vec<CentreData> = lanes
        .iter()
        .map(|(x, _)| CentreData::new(x, &GaussData::new(x).unwrap()))
        .collect();
    for model in MODELS {
        let mat = Material::new(model, YOUNG, NU, RHO);
        let mut el = LaneElements::default();
        let mut u = [[[0.0; 8]; 3]; 8];
        for (l, ((x, f_def), cd)) in lanes.iter().zip(&cds).enumerate() {
            let ul = homogeneous(x, f_def);
            for a in 0..8 {
                for j in 0..3 {
                    u[a][j][l] = ul[a][j];
                }
            }
            el.set(l, cd, hourglass_stiffness(&mat, cd, 0.1));
        }
        for fma in [false, true] {
            let mut f = [[[0.0; 8]; 3]; 8];
            let [strain, hg, j] = if fma {
                element_forces_reduced_lanes::<true, true>(&mat, &el, &u, &mut f)
            } else {
                element_forces_reduced_lanes::<true, false>(&mat, &el, &u, &mut f)
            };
            for (l, (x, f_def)) in lanes.iter().enumerate() {
                let fl: [[f64; 3]; 8] =
                    std::array::from_fn(|a| std::array::from_fn(|i| f[a][i][l]));
                let what = format!("{model:?} lane {l}, FMA {fma}");
                check_element(&what, model, f_def, x, el.vol[l], &fl, strain[l], j[l]);
                assert!(
                    hg[l].abs() <= 1e-20 * el.k_hg[l],
                    "{what}: Ψ_hg = {}",
                    hg[l]
                );
            }
        }
    }
}
