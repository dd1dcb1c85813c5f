//! The linear tetrahedron's internal forces (model §1.13): F constant over the element,
//! fₐ = V_e P(F_e) ∇ₓNₐ, one stress per element; for the rubbers (ψ = ψ_iso(C̄) + U(J),
//! model §1.10) the average nodal pressure of Bonet & Burton (1998) and a share of nodally
//! averaged isochoric stress (Bonet, Marriott & Hassan 2001; Puso & Solberg 2006), so that the
//! element neither locks near incompressibility nor stiffens in bending.
//!
//! Written as an energy (model §1.13, §1.14): the nodal volume ratio Jₐ = vₐ/Vₐ,
//! vₐ = Σ_{e∋a} v_e/4, v_e = J_e V_e, the element's J̄_e = ¼Σ_{a∈e} Jₐ, the nodal displacement
//! gradient Hₐ = (1/Vₐ) Σ_{e∋a} V_e H_e/4 and Fₐ = I + Hₐ, and the element's share
//! α = [`TET_ELEMENT_SHARE`] of the isochoric energy:
//!
//!   W = Σ_e V_e [α ψ_iso(F_e) + U(J̄_e)] + (1 − α) Σ_a Vₐ ψ_iso(Fₐ),
//!
//! whose gradient is, with p̄ₐ = (1/Vₐ) Σ_{e∋a} V_e U′(J̄_e)/4 and p̃_e = ¼Σ_{a∈e} p̄ₐ,
//!
//!   fₐ = Σ_e V_e [α P_iso(F_e) + (1 − α) ¼Σ_{b∈e} P_iso(F_b) + p̃_e cof F_e] ∇ₓNₐ
//!
//! (∂v_e/∂x_b = V_e cof F_e ∇ₓN_b, ∂Hₐ/∂x_b = Σ_{e∋a,b} (V_e/4Vₐ) ∇ₓN_b).
//!
//! Passes: the elements' F, J and isochoric stress (parallel on the team), the nodal
//! displacement gradients and their stresses (a scatter and a nodal loop), the nodal volumes
//! and pressures (two scatters), the forces (a scatter), in buffers kept from call to call
//! ([`TetScratch`]), so that a step allocates nothing. Plain scalar code: the tetrahedra are
//! not tuned yet.

use super::ElementSums;
use crate::element::tet4::tet_deformation_gradient;
use crate::material::{first_piola, rubber, with_law, Deformation, Material};
use crate::mesh::{Mesh, TetData};
use crate::team::Team;
pub use crate::tunables::TET_ELEMENT_SHARE;

/// One tetrahedron's state at U: H = F − I, J, cof F (under the nodal pressure), the stress
/// without the nodal pressure's part and the energy density without U(J̄).
#[derive(Debug, Clone, Copy)]
struct TetPoint {
    h: [[f64; 3]; 3],
    j: f64,
    p: [[f64; 3]; 3],
    cof: [[f64; 3]; 3],
    psi: f64,
}

/// The buffers of [`tet_forces`], reused from call to call (sized by the first): the
/// elements' points, the nodal volume ratios and pressures of the average nodal pressure, and
/// the nodal displacement gradients and isochoric stresses.
#[derive(Debug, Default, Clone)]
pub struct TetScratch {
    points: Vec<TetPoint>,
    nodal: Vec<f64>,
    pressure: Vec<f64>,
    nodal_h: Vec<[[f64; 3]; 3]>,
    nodal_p: Vec<[[f64; 3]; 3]>,
}

/// Whether the tetrahedra of `mat` take the average nodal pressure: the materials with the
/// isochoric/volumetric split (model §1.10, §1.13).
pub fn nodal_pressure(mat: &Material) -> bool {
    mat.rubber.is_some()
}

fn point(mat: &Material, g: &[[f64; 3]; 4], ue: &[[f64; 3]; 4], split: bool) -> TetPoint {
    let f = tet_deformation_gradient(g, ue);
    let h = std::array::from_fn(|i| std::array::from_fn(|j| f[i][j] - (i == j) as u8 as f64));
    let d = Deformation::<f64>::of::<false>(h);
    let (p, psi, cof) = match (&mat.rubber, split) {
        (Some(r), true) => rubber::isochoric_piola_energy::<true>(r, &d.f, d.j),
        _ => {
            let (p, psi) = with_law!(mat.model, L => first_piola::<L, f64, true, false>(mat, &d));
            (p, psi, [[0.0; 3]; 3])
        }
    };
    TetPoint {
        h,
        j: d.j,
        p,
        cof,
        psi,
    }
}

/// Adds the tetrahedra's internal forces at `u` into `f` (model §1.13) and returns their
/// strain energy Σ_e V_e ψ_e (with U(J̄_e) under the nodal pressure) and smallest J = det F_e,
/// numbered after the hexahedra ([`Mesh::element_count`]). `split`: the average nodal
/// pressure ([`nodal_pressure`]; only for a rubber). A NaN J is reported as the smallest.
/// `scratch` holds the buffers ([`TetScratch`]).
#[allow(clippy::too_many_arguments)]
pub fn tet_forces(
    mesh: &Mesh,
    data: &TetData,
    mat: &Material,
    split: bool,
    u: [&[f64]; 3],
    f: &mut [&mut [f64]; 3],
    team: Option<&Team>,
    scratch: &mut TetScratch,
) -> ElementSums {
    let at = |n: u32| [u[0][n as usize], u[1][n as usize], u[2][n as usize]];
    let run = |t: usize| point(mat, &data.grad[t], &mesh.tets[t].map(at), split);
    let TetScratch {
        points,
        nodal,
        pressure,
        nodal_h,
        nodal_p,
    } = scratch;
    match team {
        Some(team) => team.map_into(mesh.tets.len(), points, run),
        None => {
            points.clear();
            points.extend((0..mesh.tets.len()).map(run));
        }
    }
    let mut out = ElementSums {
        strain: 0.0,
        hourglass: 0.0,
        min_j: f64::INFINITY,
        min_element: 0,
        skipped: 0,
        min_stress_j: f64::INFINITY,
        min_stress_element: 0,
    };
    for (t, pt) in points.iter().enumerate() {
        if !(pt.j >= out.min_j) {
            out.min_j = pt.j;
            out.min_element = mesh.elements.len() + t;
        }
    }
    out.min_stress_j = out.min_j;
    out.min_stress_element = out.min_element;
    if let (Some(r), true) = (&mat.rubber, split) {
        out.strain += nodal_isochoric(mesh, data, r, points, nodal_h, nodal_p);
        nodal_pressure_pass(mesh, data, r, points, nodal, pressure);
    }
    for (t, conn) in mesh.tets.iter().enumerate() {
        let (pt, g, v) = (&points[t], &data.grad[t], data.volume[t]);
        out.strain += v * pt.psi;
        for (a, &n) in conn.iter().enumerate() {
            for i in 0..3 {
                f[i][n as usize] +=
                    v * (pt.p[i][0] * g[a][0] + pt.p[i][1] * g[a][1] + pt.p[i][2] * g[a][2]);
            }
        }
    }
    out
}

/// The average nodal pressure (model §1.13, (1.13a)–(1.13f)): U(J̄_e) into each point's
/// energy density and p̃_e cof F_e into its stress.
fn nodal_pressure_pass(
    mesh: &Mesh,
    data: &TetData,
    r: &rubber::Rubber,
    points: &mut [TetPoint],
    nodal: &mut Vec<f64>,
    pressure: &mut Vec<f64>,
) {
    // vₐ = Σ_{e∋a} J_e V_e/4, Jₐ = vₐ/Vₐ.
    nodal.clear();
    nodal.resize(mesh.nodes.len(), 0.0);
    for (t, conn) in mesh.tets.iter().enumerate() {
        let q = 0.25 * points[t].j * data.volume[t];
        for &a in conn {
            nodal[a as usize] += q;
        }
    }
    for (ja, va) in nodal.iter_mut().zip(&data.node_volume) {
        if *va > 0.0 {
            *ja /= va;
        }
    }
    // U(J̄_e), then p̄ₐ = (1/Vₐ) Σ_{e∋a} V_e U′(J̄_e)/4.
    pressure.clear();
    pressure.resize(mesh.nodes.len(), 0.0);
    for (t, conn) in mesh.tets.iter().enumerate() {
        let j_bar = 0.25 * conn.iter().map(|&a| nodal[a as usize]).sum::<f64>();
        let (energy, slope) = r.volumetric.energy_slope(r.bulk, j_bar);
        points[t].psi += energy;
        let q = 0.25 * data.volume[t] * slope;
        for &a in conn {
            pressure[a as usize] += q;
        }
    }
    for (p, va) in pressure.iter_mut().zip(&data.node_volume) {
        if *va > 0.0 {
            *p /= va;
        }
    }
    // P_e += p̃_e cof F_e.
    for (t, conn) in mesh.tets.iter().enumerate() {
        let p_e = 0.25 * conn.iter().map(|&a| pressure[a as usize]).sum::<f64>();
        let pt = &mut points[t];
        for i in 0..3 {
            for k in 0..3 {
                pt.p[i][k] += p_e * pt.cof[i][k];
            }
        }
    }
}

/// The nodal share of the isochoric energy (model §1.14): Hₐ = (1/Vₐ) Σ_{e∋a} V_e H_e/4,
/// P_iso(Fₐ) and ψ_iso(Fₐ) at every node of a tetrahedron, then each point's stress
/// α P_iso(F_e) + (1 − α) ¼Σ_{b∈e} P_iso(F_b) and energy density α ψ_iso(F_e); returns
/// (1 − α) Σ_a Vₐ ψ_iso(Fₐ).
fn nodal_isochoric(
    mesh: &Mesh,
    data: &TetData,
    r: &rubber::Rubber,
    points: &mut [TetPoint],
    nodal_h: &mut Vec<[[f64; 3]; 3]>,
    nodal_p: &mut Vec<[[f64; 3]; 3]>,
) -> f64 {
    let alpha = TET_ELEMENT_SHARE;
    let n = mesh.nodes.len();
    nodal_h.clear();
    nodal_h.resize(n, [[0.0; 3]; 3]);
    for (t, conn) in mesh.tets.iter().enumerate() {
        let q = 0.25 * data.volume[t];
        for &a in conn {
            add_scaled(&mut nodal_h[a as usize], q, &points[t].h);
        }
    }
    nodal_p.clear();
    nodal_p.resize(n, [[0.0; 3]; 3]);
    let mut energy = 0.0;
    for ((h, p), &va) in nodal_h
        .iter()
        .zip(nodal_p.iter_mut())
        .zip(&data.node_volume)
    {
        if va > 0.0 {
            let d = Deformation::<f64>::of::<false>(h.map(|row| row.map(|x| x / va)));
            let (pa, psi, _) = rubber::isochoric_piola_energy::<true>(r, &d.f, d.j);
            *p = pa;
            energy += (1.0 - alpha) * va * psi;
        }
    }
    for (pt, conn) in points.iter_mut().zip(&mesh.tets) {
        pt.psi *= alpha;
        pt.p = pt.p.map(|row| row.map(|x| alpha * x));
        for &a in conn {
            add_scaled(&mut pt.p, 0.25 * (1.0 - alpha), &nodal_p[a as usize]);
        }
    }
    energy
}

/// a += q b.
fn add_scaled(a: &mut [[f64; 3]; 3], q: f64, b: &[[f64; 3]; 3]) {
    for (ra, rb) in a.iter_mut().zip(b) {
        for (x, y) in ra.iter_mut().zip(rb) {
            *x += q * y;
        }
    }
}
