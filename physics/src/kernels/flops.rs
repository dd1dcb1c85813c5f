//! Floating-point operations per element-step of each element kernel, counted from the code:
//! the kernels' own generic formulas (H = Σₐ uₐ ⊗ gₐ, F, J, the stress of
//! [`crate::material::first_piola`], the row products P·g, the hourglass modes, the corner
//! Jacobians) are run once on a number type, [`Counted`], that counts its operations: +, −, ×,
//! ÷ one each, a multiply–add two (fused or not; an FMA is 2 flops), ln apart (a library call,
//! not a flop). What the kernels write out by hand on lanes (the pairwise sum over the Gauss
//! points, the energy sums, the one-point force assembly) is counted here by the same
//! operations, written once more on [`Counted`]. Comparisons (min J) are not counted.
//!
//! Counted with the energy (the time loop asks for it at every step, for the ledger), one
//! element, either law.

use super::corners::corner_jacobians;
use super::fbar::{add_pressure_correction, halley_cube_root, scale_stress, scaled_gradient};
use crate::element::hex8::{
    box_factors, box_forces, box_gradient, centre_norms_of, modes_to_nodes, node_modes,
    parent_forces, parent_gradient,
};
use crate::material::{
    deformation_gradient, determinant, displacement_gradient, first_piola, row_dot, with_law,
    Deformation, Law, Material, MaterialModel, Real,
};
use std::cell::Cell;
use std::ops::{Add, Div, Mul, Sub};

thread_local! {
    /// Flops and logarithms counted on this thread.
    static COUNT: Cell<(u64, u64)> = const { Cell::new((0, 0)) };
}

fn tally(flops: u64, logs: u64) {
    COUNT.with(|c| {
        let (f, l) = c.get();
        c.set((f + flops, l + logs));
    });
}

/// The flops and logarithms counted while `run` runs.
fn count(run: impl FnOnce()) -> (u64, u64) {
    let before = COUNT.with(|c| c.get());
    run();
    let after = COUNT.with(|c| c.get());
    (after.0 - before.0, after.1 - before.1)
}

/// A number that counts the operations done on it (its value is carried along, unused).
#[derive(Clone, Copy, Debug)]
pub struct Counted(f64);

/// `impl $op for Counted`: one flop each.
macro_rules! counted {
    ($($trait:ident :: $method:ident),*) => {$(
        impl $trait for Counted {
            type Output = Counted;
            fn $method(self, o: Counted) -> Counted {
                tally(1, 0);
                Counted($trait::$method(self.0, o.0))
            }
        }
    )*};
}
counted!(Add::add, Sub::sub, Mul::mul, Div::div);

impl Real for Counted {
    fn splat(v: f64) -> Counted {
        Counted(v)
    }
    fn ln(self) -> Counted {
        tally(0, 1);
        Counted(self.0.ln())
    }
    fn fmadd<const FMA: bool>(self, b: Counted, c: Counted) -> Counted {
        tally(2, 0);
        Counted(self.0 * b.0 + c.0)
    }
    /// Not counted: the rubber materials' stress, the one user, is not in the flop model.
    fn per_lane<const N: usize, const M: usize>(
        x: [Counted; N],
        f: impl Fn([f64; N]) -> [f64; M],
    ) -> [Counted; M] {
        f(x.map(|c| c.0)).map(Counted)
    }
}

/// The flops of one element-step of a kernel, by part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct KernelFlops {
    /// H = Σₐ uₐ ⊗ gₐ at every point.
    pub gradient: u64,
    /// F = I + H, J = det F, the stress P and the energy density ψ at every point.
    pub stress: u64,
    /// The nodal forces fₐ (with the hourglass forces for one point) and the energy sums.
    pub forces: u64,
    /// The hourglass mode amplitudes qᵅ = Σₐ γₐᵅ uₐ and Ψ_hg (one point).
    pub hourglass: u64,
    /// The 8 corner Jacobians (one point's inversion check, when it runs).
    pub corners: u64,
    /// The corner bound J (1 − C|q|/s)³ that lets a lane group skip the corner check (one point,
    /// on every group): ‖F‖²_F and |q|² ([`centre_norms_of`]), then s, √|q|², C|q|/s, 1 − and
    /// the cube, 9 (written out on f64 in [`super::corner_bound::corner_lower_bound`]; √ one).
    pub bound: u64,
    /// Natural logarithms (neo-Hookean), not in the flops.
    pub logs: u64,
}

impl KernelFlops {
    /// Every flop of the kernel, the corner check included (the bound left out).
    pub fn total(&self) -> u64 {
        self.gradient + self.stress + self.forces + self.hourglass + self.corners
    }

    /// The flops per element-step the kernel runs when a share `checked` ∈ [0, 1] of the
    /// element-steps runs the corner check and a share `bounded` computes the corner bound:
    /// [`KernelFlops::total`] with the check and the bound on those shares only. With one point
    /// the lane groups compute the bound and run the check unless it skips it; the elements
    /// left over after the groups of a block run the check without the bound
    /// (`RunStats::corner_checks` counts the groups).
    pub fn executed(&self, checked: f64, bounded: f64) -> f64 {
        (self.total() - self.corners) as f64
            + checked * self.corners as f64
            + bounded * self.bound as f64
    }
}

fn c(v: f64) -> Counted {
    Counted(v)
}

/// F, J, P and ψ at one point (what the kernels' pointwise stress does).
fn stress_point<L: Law>(mat: &Material) -> (u64, u64) {
    count(|| {
        let h = [[c(0.01); 3]; 3];
        let d = Deformation::of::<true>(h);
        let _ = first_piola::<L, Counted, true, true>(mat, &d);
    })
}

/// At one point: the flops of H = Σₐ uₐ ⊗ gₐ (the one-point kernel's), those of F, J, P and
/// ψ, and the logarithms.
fn point(model: MaterialModel) -> (u64, u64, u64) {
    let mat = Material::example(model);
    let (gradient, _) = count(|| {
        let _ = displacement_gradient::<Counted, true>(|_, _| c(1e-3), |_, _| c(1.0));
    });
    let (stress, logs) = with_law!(model, L => stress_point::<L>(&mat));
    (gradient, stress, logs)
}

/// One element-step of the full (2×2×2) kernel ([`super::full::full_lanes`]): the parent
/// derivatives by sum factorisation and H = D·(⅛ J₀⁻¹) at the 8 points; the stress at the 8
/// points; Q = P·(⅛ w det J₀ J₀⁻ᵀ) at the 8 points, the transpose to the nodes, and the energy.
/// On an axis-aligned box (`axis_aligned`: [`crate::mesh::GaussData::axis_aligned`]) ⅛ J₀⁻¹
/// and ⅛ w det J₀ J₀⁻ᵀ are one diagonal at every point, and H and the forces go through the
/// modes of the trilinear field ([`crate::element::hex8::box_gradient`], `box_forces`), each with
/// its factors (c, cg, cg²) formed per element.
pub fn full(model: MaterialModel, axis_aligned: bool) -> KernelFlops {
    let (_, stress, logs) = point(model);
    let (gradient, _) = count(|| {
        let mut d = [[[c(0.0); 3]; 3]; 8];
        if axis_aligned {
            let k = box_factors([c(1.0); 3]);
            box_gradient(|_, _| c(1e-3), &k, &mut d);
        } else {
            parent_gradient::<Counted, true>(|_, _| c(1e-3), &mut d);
            for d_q in &d {
                for d_qi in d_q {
                    for _ in 0..3 {
                        let _ = row_dot::<_, true>(d_qi, [c(1.0); 3]);
                    }
                }
            }
        }
    });
    let (forces, _) = count(|| {
        let mut f = [[c(0.0); 3]; 8];
        if axis_aligned {
            let k = box_factors([c(1.0); 3]);
            box_forces(|_, _, _| c(1.0), &k, &mut f);
        } else {
            // Q_q,id = P_q,i · (⅛ w det J₀ ∂ξ_d/∂X) at 8 points × 3 × 3.
            let p = [c(1.0); 3];
            for _ in 0..72 {
                let _ = row_dot::<_, true>(&p, [c(1.0); 3]);
            }
            parent_forces::<Counted, true>(|_, _, _| c(1.0), &mut f);
        }
        // Ψ = Σ_q ψ_q w_q det J₀.
        let mut e = c(0.0);
        for _ in 0..8 {
            e = e + c(1.0) * c(1.0);
        }
    });
    KernelFlops {
        gradient,
        stress: 8 * stress,
        forces,
        hourglass: 0,
        corners: 0,
        bound: 0,
        logs: 8 * logs,
    }
}

/// One element-step of the F-bar kernel ([`super::fbar::fbar_lanes`], model §1.11): the full
/// kernel's ([`full`]) and, per point, F = I + H and J_q with the sums V̄ and V₀; α_q (J̄/J_q
/// and [`halley_cube_root`], the path of every element whose J̄/J_q is in [½, 2]),
/// H̄ = αH + (α − 1)I, s_q and αP̄ with
/// the sum S̄; then S̄/V̄ and, per point, s_q/J_q and P̂ = αP̄ + c cof F_q (F formed again).
/// Counted in `stress`.
pub fn fbar(model: MaterialModel, axis_aligned: bool) -> KernelFlops {
    let mut k = full(model, axis_aligned);
    let (extra, _) = count(|| {
        let h = [[c(0.01); 3]; 3];
        let mut p = [[c(1.0); 3]; 3];
        let (mut vbar, mut v0, mut sbar) = (c(0.0), c(0.0), c(0.0));
        for _ in 0..8 {
            let j = determinant::<Counted, true>(&deformation_gradient(&h));
            vbar = c(1.0).fmadd::<true>(j, vbar);
            v0 = v0 + c(1.0);
        }
        let jbar = vbar / v0;
        for _ in 0..8 {
            let alpha = halley_cube_root(jbar / c(1.0));
            let _ = scaled_gradient(&h, alpha);
            let s = scale_stress::<Counted, true>(&mut p, &deformation_gradient(&h), alpha);
            sbar = c(1.0).fmadd::<true>(s, sbar);
        }
        let p_mean = sbar / vbar;
        for _ in 0..8 {
            let cq = p_mean - c(1.0) / c(1.0);
            add_pressure_correction::<Counted, true>(&mut p, &deformation_gradient(&h), cq);
        }
    });
    k.stress += extra;
    k
}

/// One element-step of the physically stabilised one-point kernel
/// ([`super::physical::physical_lanes`], model §1.12): H and the amplitudes qᵅ, the stress at
/// the centre ([`point`]), F⁻¹, the four modes' rᵅ, r̂ᵅ, sᵅ, tᵅ, cₐᵅ and Ψ_hg, the forces
/// fₐ = V P bₐ + Σᵅ tᵅ cₐᵅ, V ψ, and the 8 corner Jacobians (checked in every group).
pub fn physical(model: MaterialModel) -> KernelFlops {
    let (_, stress, logs) = point(model);
    let (gradient, _) = count(|| {
        let _ = super::physical::gradient_and_modes::<Counted, true>(
            |_, _| c(1e-3),
            |_, _| c(1.0),
            |_, _| c(1.0),
        );
    });
    let (forces, _) = count(|| {
        let m = [[c(1.0); 3]; 3];
        let mut f = [[c(0.0); 3]; 8];
        let _ = super::physical::stabilised_forces::<Counted, true, true>(
            |_, _| c(1.0),
            |_, _| c(1.0),
            c(1.0),
            &m,
            &[[c(1.0); 3]; 4],
            c(1.0),
            &[[c(1e-3); 3]; 3],
            &[[c(1e-3); 3]; 4],
            &m,
            c(1.0),
            &mut f,
        );
        let _ = c(1.0) * c(1.0);
    });
    let (corners, _) = count(|| {
        let _ = corner_jacobians::<Counted, true>(|_, _| c(1.0), |_| c(1.0), |_, _| c(1e-3));
    });
    KernelFlops {
        gradient,
        stress,
        forces,
        hourglass: 0,
        corners,
        bound: 0,
        logs,
    }
}

/// The flops of J (1 − C|q|/s)³ from J, ‖F‖²_F and |q|²
/// ([`super::corner_bound::corner_lower_bound`], on f64): s = 2J/‖F‖²_F 2, √|q|² 1, C·√ 1,
/// ÷ s 1, 1 − 1, J r r r 3.
const BOUND_FORMULA: u64 = 9;

/// One element-step of the one-point kernel with hourglass control
/// ([`crate::element::hex8::element_forces_reduced_lanes`]) and its corner check
/// ([`super::corners`]). On an axis-aligned box (`axis_aligned`,
/// [`crate::mesh::CentreData::axis_aligned`]) the kernel goes through the modes of the trilinear
/// field ([`crate::element::hex8::element_forces_reduced_lanes_in`]'s `BOXES`): per component (T3), 3 products for
/// H and, for the forces, 7 products and the transpose of (T3).
pub fn one_point(model: MaterialModel, axis_aligned: bool) -> KernelFlops {
    let (general_gradient, stress, logs) = point(model);
    let (gradient, hourglass, forces) = if axis_aligned {
        one_point_box_parts()
    } else {
        one_point_general_parts(general_gradient)
    };
    let (corners, _) = count(|| {
        let _ = corner_jacobians::<Counted, true>(|_, _| c(1.0), |_| c(1.0), |_, _| c(1e-3));
    });
    let (norms, _) = count(|| {
        let _ = centre_norms_of(&[[c(1e-3); 3]; 3], &[[c(1e-3); 3]; 4]);
    });
    KernelFlops {
        gradient,
        stress,
        forces,
        hourglass,
        corners,
        bound: norms + BOUND_FORMULA,
        logs,
    }
}

/// The general one-point kernel's H (`gradient`, counted by [`point`]), hourglass modes and
/// energy, and forces.
fn one_point_general_parts(gradient: u64) -> (u64, u64, u64) {
    let (hourglass, _) = count(|| {
        let q = crate::material::hourglass_modes::<Counted, true>(|_, _| c(1.0), |_, _| c(1e-3));
        let _ = crate::material::hourglass_energy(c(1.0), &q);
    });
    let (forces, _) = count(|| {
        let (p, b, gamma, vol, k) = ([c(1.0); 3], [c(1.0); 3], c(1.0), c(1.0), c(1.0));
        // fₐ = V P bₐ + k Σᵅ γₐᵅ qᵅ, 8 nodes × 3 components.
        for _ in 0..24 {
            let pb = row_dot::<_, true>(&p, b);
            let mut hg = c(0.0);
            for _ in 0..4 {
                hg = gamma.fmadd::<true>(c(1.0), hg);
            }
            let _ = vol.fmadd::<true>(pb, k * hg);
        }
        // V ψ.
        let _ = vol * c(1.0);
    });
    (gradient, hourglass, forces)
}

/// The same on an axis-aligned box, through the modes of the trilinear field.
fn one_point_box_parts() -> (u64, u64, u64) {
    let (gradient, _) = count(|| {
        for _ in 0..3 {
            let m = node_modes([c(1e-3); 8]);
            // H_id = β_d m_{d}.
            for d in 0..3 {
                let _ = c(1.0) * m[1 << d];
            }
        }
    });
    let (hourglass, _) = count(|| {
        // The amplitudes qᵅ are modes of (T3): only Ψ_hg = ½ k Σᵅ |qᵅ|².
        let _ = crate::material::hourglass_energy(c(1.0), &[[c(1e-3); 3]; 4]);
    });
    let (forces, _) = count(|| {
        for _ in 0..3 {
            // m_{d} = V β_d P_id, m_{hᵅ} = k qᵅᵢ, then the nodal field.
            let mut m = [c(0.0); 8];
            for m_k in &mut m[1..] {
                *m_k = c(1.0) * c(1.0);
            }
            let _ = modes_to_nodes(m);
        }
        // V ψ.
        let _ = c(1.0) * c(1.0);
    });
    (gradient, hourglass, forces)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The counts against a count by hand (an FMA is 2 flops). Per point: H is 8 nodes × 9
    /// multiply–adds = 144 (one point); F = I + H 3; J 17 (two triple sums of 4 × and 2
    /// multiply–adds, then 1 −); SVK: 2E 6 × 7 (the entries i ≤ j: H_ij + H_ji, then 3
    /// multiply–adds), tr 2, S 1 × + 3 multiply–adds + 3 ×, ψ 2 × (1 × + 2 multiply–adds) + 1
    /// multiply–add + 2 × + 1 multiply–add, P = S + H·S 9 × 3 multiply–adds = 144.
    /// Full: gradient 36 edge differences + 9 interpolations of 4 × (1 + 1 + 2 × 2) = 24, then
    /// H = D·J 8 × 9 row products of 5; 8 points' stress; forces 72 row products of 5 for Q,
    /// the transpose 9 × (4 pair sums + 24) + 8 nodes × 3 × 2 (+ 3 for the node of signs
    /// (−, −, −), 0 − G_ξ), energy 8 × 2. One point: 1 point, hourglass modes
    /// 4 × 24 multiply–adds and Ψ_hg 4 × 6 + 2, forces 24 × (5 + 8 + 1 + 2) and V ψ 1, corners
    /// 12 edges × 3 × 2 and 8 × (triple product 17 + 1 ×), the bound ‖F‖²_F 9 × and 9 + from 0
    /// and 3 + for δᵢⱼ, |q|² 12 × and 12 +, and the formula 9.
    #[test]
    fn counts_match_a_count_by_hand() {
        let full_svk = full(MaterialModel::Svk, false);
        assert_eq!(
            full_svk,
            KernelFlops {
                gradient: 36 + 9 * 24 + 8 * 9 * 5,
                stress: 8 * 144,
                forces: 72 * 5 + 9 * (4 + 24) + 8 * 3 * 2 + 3 + 16,
                hourglass: 0,
                corners: 0,
                bound: 0,
                logs: 0,
            }
        );
        assert_eq!(full_svk.total(), 2443);
        // An axis-aligned box, through the modes: the factors (c, cg, cg²) 3 × 2 each; H per
        // component (T3) 24, per direction 4 × and 8 ±; the forces per component and direction 4
        // pair sums, 8 ± and 4 ×, then 5 sums of amplitudes and the transpose of (T3) 24.
        let box_svk = full(MaterialModel::Svk, true);
        assert_eq!(
            (box_svk.gradient, box_svk.stress, box_svk.forces),
            (6 + 3 * 24 + 9 * 12, 8 * 144, 6 + 3 * (3 * 16 + 5 + 24) + 16)
        );
        assert_eq!(box_svk.total(), 1591);
        // The box's one point: (T3) 24 sums per component and H 9 ×; Ψ_hg 4 × 6 + 2; forces
        // per component 7 × and the transpose of (T3) 24, V ψ 1; the same stress and corners.
        let box_one = one_point(MaterialModel::Svk, true);
        assert_eq!(
            box_one,
            KernelFlops {
                gradient: 3 * 24 + 9,
                stress: 144,
                forces: 3 * (7 + 24) + 1,
                hourglass: 4 * 6 + 2,
                corners: 12 * 3 * 2 + 8 * 18,
                bound: 21 + 24 + 9,
                logs: 0,
            }
        );
        assert_eq!(box_one.total(), 561);
        // Every element in a group that skips the check: 561 − 216 + 54; none skipping: 561
        // + 54; no group (the scalar kernel alone): 561.
        assert_eq!(box_one.executed(0.0, 1.0), 399.0);
        assert_eq!(box_one.executed(1.0, 1.0), 615.0);
        assert_eq!(box_one.executed(1.0, 0.0), 561.0);
        let one = one_point(MaterialModel::Svk, false);
        assert_eq!(
            one,
            KernelFlops {
                gradient: 144,
                stress: 144,
                forces: 24 * 16 + 1,
                hourglass: 4 * 24 * 2 + 4 * 6 + 2,
                corners: 12 * 3 * 2 + 8 * 18,
                bound: 21 + 24 + 9,
                logs: 0,
            }
        );
        // Neo-Hookean: one ln per point, the same H and forces.
        let nh = full(MaterialModel::NeoHookean, false);
        assert_eq!(
            (nh.gradient, nh.forces, nh.logs),
            (full_svk.gradient, full_svk.forces, 8)
        );
    }
}
