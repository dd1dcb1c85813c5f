//! Bulk viscosity (model §4.12): a viscous mean stress q in each element, linear in the
//! volumetric strain rate (b₁, the ringing of the highest modes) and quadratic in compression
//! (b₂, shock fronts), added to the internal forces at stage 3 and booked by the ledger as a
//! dissipation (model §5.11).

use super::mass_scaling::{class_lengths, tet_lengths};
use super::Simulation;
use crate::kernels::Planes;
use crate::model::BulkViscosity;

/// What the bulk viscosity keeps between stages and steps.
#[derive(Debug, Default, Clone, serde::Serialize, serde::Deserialize)]
pub(super) struct BulkViscosityState {
    /// Per hexahedron class, then per tetrahedron: its length L_e = c_d h_e [m] (h_e its
    /// element bound at rest, so a bar of length L has L_e = L), density ρ_e [kg/m³] and wave
    /// speed c_d,e [m/s] (mass scaling included).
    class: Vec<[f64; 3]>,
    /// The viscous nodal forces f_bv at tₙ₊₁ [N] (a part of F_int).
    pub force: Planes,
    /// Σ_e q J V ε̇ with V_{n+½} [W]: the power of the viscous stress at the velocity that
    /// computed it, −Σ V_{n+½}·f_bv.
    pub power: f64,
    /// (λ + 2μ)/K ≥ 1: the damping ratio of an element's breathing mode, its highest, over
    /// b₁ − b₂² (L_e/c_d) min(0, ε̇) (model §4.12).
    mode_ratio: f64,
    /// ξ = (b₁ − b₂² (L_e/c_d) min(0, ε̇)) (λ + 2μ)/K of the most damped element at tₙ₊₁ [-].
    pub xi_max: f64,
    /// h̄ of the step's impulses (stage 5) [s].
    pub h_bar: f64,
}

/// The central-difference stable step of a mode of damping ratio ξ, over the undamped one:
/// h_crit(ξ) = (2/ω)(√(1 + ξ²) − ξ) (model §6.6).
pub(super) fn damped_step_factor(xi: f64) -> f64 {
    (1.0 + xi * xi).sqrt() - xi
}

impl Simulation {
    /// At set-up: the per-class constants ([`BulkViscosityState::class`]); nothing without
    /// bulk viscosity.
    pub(super) fn bulk_viscosity_setup(&mut self) {
        if self.model.scheme.bulk_viscosity.is_none() {
            return;
        }
        let mat = self.model.material;
        let lengths = class_lengths(&self.model, &self.work.classes);
        let m = mat.p_wave_modulus();
        let constants = |l: f64, factor: Option<&f64>| {
            let rho = mat.density * factor.copied().unwrap_or(1.0);
            [l, rho, (m / rho).sqrt()]
        };
        let class = (lengths.iter().enumerate())
            .map(|(c, &l)| constants(l, self.setup.class_density.get(c)))
            .chain(
                (tet_lengths(&self.model, &self.work.classes)
                    .iter()
                    .enumerate())
                .map(|(t, &l)| constants(l, self.setup.tet_density.get(t))),
            )
            .collect();
        self.state.bulk_viscosity = Some(BulkViscosityState {
            class,
            mode_ratio: mode_ratio(&mat),
            force: Planes::zeros(self.state.u.len()),
            ..Default::default()
        });
    }

    /// Stage 3 with bulk viscosity (model §4.12), after the elastic forces: in each element,
    /// at its centre, F = I + Σ uₐ ⊗ bₐ at Uₙ₊₁, Ḟ = Σ vₐ ⊗ bₐ with V_{n+½}, the volumetric
    /// strain rate ε̇ = tr(Ḟ F⁻¹) = J̇/J, the viscous mean stress
    ///
    ///   q = ρ_e L_e ε̇ (b₁ c_d − b₂² L_e min(0, ε̇))      (tension positive; q ε̇ ≥ 0)
    ///
    /// and its nodal forces fₐ = q J V F⁻ᵀ bₐ, added to F_int; their power Σₐ fₐ·vₐ = q J V ε̇
    /// is the rate of dissipation.
    pub(super) fn bulk_viscosity_forces(&mut self) {
        let Some(bv) = self.model.scheme.bulk_viscosity else {
            return;
        };
        let Some(state) = self.state.bulk_viscosity.as_mut() else {
            return;
        };
        let BulkViscosity { linear, quadratic } = bv;
        let b2 = quadratic * quadratic;
        let constants = |[l, rho, speed]: [f64; 3]| [l, rho, speed, linear, b2];
        state.force.fill_zero();
        let (mut power, mut xi_max) = (0.0, linear);
        let (u, v) = (&self.state.u, &self.state.v);
        let classes = &self.work.classes;
        for (e, conn) in self.model.mesh.elements.iter().enumerate() {
            let c = classes.class_of[e] as usize;
            let cd = &classes.centre[c];
            let (p, xi) = viscous_forces(
                &mut state.force,
                conn,
                &cd.b,
                cd.volume,
                (u, v),
                constants(state.class[c]),
            );
            power += p;
            xi_max = f64::max(xi_max, xi);
        }
        let n_classes = classes.data.len();
        let tets = &classes.tets;
        for (t, conn) in self.model.mesh.tets.iter().enumerate() {
            let (p, xi) = viscous_forces(
                &mut state.force,
                conn,
                &tets.grad[t],
                tets.volume[t],
                (u, v),
                constants(state.class[n_classes + t]),
            );
            power += p;
            xi_max = f64::max(xi_max, xi);
        }
        let [fx, fy, fz] = self.state.f_int.planes_mut();
        let [gx, gy, gz] = state.force.planes();
        for (fi, gi) in [(fx, gx), (fy, gy), (fz, gz)] {
            for (a, b) in fi.iter_mut().zip(gi) {
                *a += b;
            }
        }
        (state.power, state.xi_max) = (power, xi_max * state.mode_ratio);
    }

    /// The ledger's halves of the viscous impulses P = −h̄ f_bv (model §5.11): the backward
    /// half ½V_{n+½}·P = −½h̄ × [`BulkViscosityState::power`] and the forward half ½V_{n+3/2}·P
    /// with the final velocities; (0, 0) without bulk viscosity.
    pub(super) fn bulk_viscosity_halves(&self) -> (f64, f64) {
        let Some(state) = self.state.bulk_viscosity.as_ref() else {
            return (0.0, 0.0);
        };
        let (v, f) = (self.state.v.planes(), state.force.planes());
        let vf: f64 = (0..3)
            .map(|c| v[c].iter().zip(f[c]).map(|(a, b)| a * b).sum::<f64>())
            .sum();
        (-0.5 * state.h_bar * state.power, -0.5 * state.h_bar * vf)
    }
}

/// The viscous stress of one element (model §4.12) added to `force`, at its centre for a
/// hexahedron (constant over a tetrahedron, model §1.13): with `grad` the N shape-function
/// gradients bₐ there, F = I + Σₐ uₐ ⊗ bₐ, Ḟ = Σₐ vₐ ⊗ bₐ, ε̇ = tr(Ḟ F⁻¹) = J̇/J,
///
///   q = ρ_e L_e ε̇ (b₁ c_d − b₂² L_e min(0, ε̇)),   fₐ = q J V F⁻ᵀ bₐ = q V cof(F) bₐ,
///
/// `c` = [L_e, ρ_e, c_d, b₁, b₂²]. Returns the power Σₐ fₐ·vₐ = q J V ε̇ ≥ 0 and the damping
/// ratio b₁ − b₂² (L_e/c_d) min(0, ε̇) before the mode factor (λ + 2μ)/K.
fn viscous_forces<const N: usize>(
    force: &mut Planes,
    conn: &[u32; N],
    grad: &[[f64; 3]; N],
    volume: f64,
    (u, v): (&Planes, &Planes),
    c: [f64; 5],
) -> (f64, f64) {
    let [l, rho, speed, linear, b2] = c;
    let mut f = [[0.0; 3]; 3];
    let mut fdot = [[0.0; 3]; 3];
    for (i, fi) in f.iter_mut().enumerate() {
        fi[i] = 1.0;
    }
    for a in 0..N {
        let (ua, va) = (u.get(conn[a] as usize), v.get(conn[a] as usize));
        for i in 0..3 {
            for j in 0..3 {
                f[i][j] += ua[i] * grad[a][j];
                fdot[i][j] += va[i] * grad[a][j];
            }
        }
    }
    let cof = cofactor(&f);
    let j = (0..3).map(|k| f[0][k] * cof[0][k]).sum::<f64>();
    // F⁻¹ = cof(F)ᵀ/J, so tr(Ḟ F⁻¹) = Σ Ḟ_ik cof_ik / J.
    let rate = (0..3)
        .map(|i| (0..3).map(|k| fdot[i][k] * cof[i][k]).sum::<f64>())
        .sum::<f64>()
        / j;
    let compression = rate.min(0.0);
    let q = rho * l * rate * (linear * speed - b2 * l * compression);
    let s = q * volume;
    for a in 0..N {
        let n = conn[a] as usize;
        let mut fa = force.get(n);
        for i in 0..3 {
            fa[i] += s * (0..3).map(|k| cof[i][k] * grad[a][k]).sum::<f64>();
        }
        force.set(n, fa);
    }
    (s * j * rate, linear - b2 * l / speed * compression)
}

/// (λ + 2μ)/K, K = λ + ⅔μ: the damping ratio of the breathing mode of a cube element (its
/// highest mode, the top of the element bound) over b₁ (model §4.12); 1 when incompressible,
/// 3 at ν = 0.
pub(super) fn mode_ratio(mat: &crate::material::Material) -> f64 {
    mat.p_wave_modulus() / (mat.lambda + 2.0 / 3.0 * mat.mu)
}

/// The cofactor matrix of a 3×3 matrix: cof(F) = J F⁻ᵀ.
fn cofactor(f: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let m = |i: usize, j: usize| f[i % 3][j % 3];
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            m(i + 1, j + 1) * m(i + 2, j + 2) - m(i + 1, j + 2) * m(i + 2, j + 1)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// cof(F) = J F⁻ᵀ on a general matrix, and the damped-step factor's limits.
    #[test]
    fn cofactor_is_j_times_the_inverse_transpose() {
        let f = [[1.1, 0.2, -0.1], [0.05, 0.9, 0.3], [0.0, -0.2, 1.3]];
        let cof = cofactor(&f);
        let j: f64 = (0..3).map(|k| f[0][k] * cof[0][k]).sum();
        // F cof(F)ᵀ = J I.
        for i in 0..3 {
            for k in 0..3 {
                let x: f64 = (0..3).map(|m| f[i][m] * cof[k][m]).sum();
                let want = if i == k { j } else { 0.0 };
                assert!((x - want).abs() <= 1e-15, "({i},{k}): {x} against {want}");
            }
        }
        assert_eq!(damped_step_factor(0.0), 1.0);
        assert!((damped_step_factor(0.06) - 0.941_798).abs() < 1e-6);
        assert!(damped_step_factor(10.0) < 0.05);
    }
}
