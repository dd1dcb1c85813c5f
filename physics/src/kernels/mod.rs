//! The element loop of stage 3 (model §1.5, §1.6, §4.3): F_int(U) = Σ_e fₑ(U) over node-disjoint
//! element blocks on the thread team, each block through the full (2×2×2) or one-point kernel
//! of [`crate::material`] built for the CPU's instruction set ([`simd`]); and the node loop of
//! stage 5 (free velocity).

pub mod corner_bound;
pub mod corners;
mod fbar;
pub mod flops;
mod full;
mod gather;
mod groups;
mod nodes;
mod physical;
pub mod simd;
pub mod tet;

use gather::*;
pub use gather::{last_level_cache_bytes, prefetch_pays};
use groups::{full_group, reduced_group, scalar_element};

pub(crate) use crate::mesh::planes::PlanesPtr;
pub use crate::mesh::planes::{NodalField, Planes};
pub use crate::mesh::rows::row_starts;
pub(crate) use nodes::{free_velocity_chunk, internal_and_gravity_impulses, NodeSums};

// The web page calls the scalar full kernel per law (`groups::scalar_element`).
#[cfg_attr(target_arch = "wasm32", allow(unused_imports))]
use crate::element::hex8::element_forces;
use crate::element::hex8::{
    element_forces_reduced, element_forces_reduced_lanes_in, hourglass_stiffness, LaneElements,
    OnePointScratch,
};
use crate::material::{with_law, F64x8, Material};
use crate::mesh::{CentreData, ElementClasses, GaussData, Mesh};
use crate::model::Integration;
use crate::team::Team;
// The AVX builds exist on x86_64 only (wasm32 runs the portable one).
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_imports))]
use simd::{simd_dispatch, ISA_AVX2, ISA_AVX512, ISA_PORTABLE};

/// Which element kernel assembles the internal forces (scene `scheme.integration`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ElementRule {
    /// 2×2×2 Gauss points ([`element_forces`]).
    Full,
    /// One point and Flanagan–Belytschko hourglass stiffness κ ([`element_forces_reduced`]).
    Reduced { kappa: f64 },
    /// 2×2×2 Gauss points with F̄ = (J̄/J)^{1/3} F ([`fbar`], model §1.11).
    FBar,
    /// One point and physical hourglass stabilisation ([`physical`], model §1.12).
    ReducedPhysical,
}

impl ElementRule {
    pub fn of(scheme: &crate::model::SchemeParams) -> ElementRule {
        match scheme.integration {
            Integration::Full => ElementRule::Full,
            Integration::Fbar => ElementRule::FBar,
            Integration::ReducedPhysical => ElementRule::ReducedPhysical,
            Integration::Reduced => ElementRule::Reduced {
                kappa: scheme.hourglass_coefficient,
            },
        }
    }
}

/// What an assembly returns besides the forces.
#[derive(Debug, Clone, Copy)]
pub struct Assembly {
    /// Strain energy Ψ(U) [J] (0 unless asked for).
    pub strain: f64,
    /// Hourglass energy Ψ_hg(U) [J] (the one-point rules, §1.6 and §1.12; 0 unless asked for).
    pub hourglass: f64,
    /// Smallest J = det F seen, and its element: at the Gauss points (full integration), at
    /// the centre and the 8 corners (one point, [`corners`]). With one point it is exact when
    /// below the `exact_below` of [`assemble_internal_forces`]; above, it may be a lower bound
    /// of the exact one that is itself ≥ `exact_below` ([`corner_bound`]).
    pub min_j: f64,
    pub min_element: usize,
    /// Smallest J where the stress is evaluated, and its element: the Gauss points (full
    /// integration, = `min_j`), the centre (one point). It sets the material's tangent, so the
    /// step control reads it as the compression indicator; one point's hourglass stiffness is
    /// constant, and a corner's J (hourglassing) changes no stiffness. Always exact.
    pub min_stress_j: f64,
    pub min_stress_element: usize,
    /// One point: lane groups of 8 elements, and those whose exact corner check the bound
    /// skipped.
    pub corner_groups: u64,
    pub corner_skipped: u64,
}

/// What a chunk of the element loop returns besides its forces: the strain and hourglass
/// energies, the smallest J reported and its element, how many lane groups skipped the exact
/// corner check ([`corner_bound`]; one point), and the smallest J where the stress is
/// evaluated and its element ([`Assembly::min_stress_j`]).
#[derive(Debug, Clone, Copy)]
pub struct ElementSums {
    pub strain: f64,
    pub hourglass: f64,
    pub min_j: f64,
    pub min_element: usize,
    pub skipped: u32,
    pub min_stress_j: f64,
    pub min_stress_element: usize,
}

impl ElementSums {
    /// The sums of a chunk whose stress is evaluated at the Gauss points (full integration,
    /// F-bar) from its (strain energy, min J, its element): no hourglass energy, no corner
    /// check, and the stress's J the reported one.
    fn at_gauss_points((strain, min_j, element): (f64, f64, usize)) -> ElementSums {
        ElementSums {
            strain,
            hourglass: 0.0,
            min_j,
            min_element: element,
            skipped: 0,
            min_stress_j: min_j,
            min_stress_element: element,
        }
    }
}

/// The buffers of [`assemble_internal_forces`], kept from call to call so that an assembly
/// allocates nothing once the first has sized them: the per-block results of the hexahedra's
/// loop and the tetrahedra's buffers ([`tet::TetScratch`]).
#[derive(Debug, Default, Clone)]
pub struct AssemblyScratch {
    pub parts: Vec<ElementSums>,
    pub tets: tet::TetScratch,
}

/// Internal forces of a whole mesh: F_int(U) = Σ_e fₑ(U) (model §1.5 and §4.3), the
/// hexahedra by `rule`, then the tetrahedra ([`tet`], model §1.13).
/// `f` must be zeroed. Energies are computed only if `energy`. `blocks` come from
/// [`Mesh::element_blocks`]; `scratch` holds the per-block results and the tetrahedra's
/// buffers ([`AssemblyScratch`]; reused, so the step allocates nothing).
///
/// The smallest J ([`Assembly::min_j`]): with one point, a group of 8 elements skips the exact
/// corner check when the bound J_a ≥ J (1 − C|q|/s)³ ([`corner_bound`]) of each of its
/// elements is ≥ `exact_below`, and reports the bounds. So the smallest J and its element are
/// exactly those of the full check whenever that J is below `exact_below` (the element that
/// has it has a bound below it, so its group was checked, and every skipped element reports
/// a value ≥ `exact_below`); otherwise the reported J lies in [`exact_below`, exact J].
/// `prefetch`: ask the cache for each lane group's nodes one group ahead ([`prefetch_pays`]).
/// `f64::INFINITY` checks every corner; `f64::NEG_INFINITY` none (J unused). The forces and
/// energies do not depend on it.
#[allow(clippy::too_many_arguments)]
pub fn assemble_internal_forces(
    mesh: &Mesh,
    classes: &ElementClasses,
    blocks: &[Vec<Vec<u32>>],
    mat: &Material,
    rule: ElementRule,
    u: &Planes,
    f: &mut Planes,
    energy: bool,
    team: Option<&Team>,
    scratch: &mut AssemblyScratch,
    exact_below: f64,
    prefetch: bool,
) -> Assembly {
    let AssemblyScratch { parts, tets } = scratch;
    assert_eq!(u.len(), f.len());
    let ptr = f.ptr();
    let u = u.planes();
    let mut out = Assembly {
        strain: 0.0,
        hourglass: 0.0,
        min_j: f64::INFINITY,
        min_element: 0,
        min_stress_j: f64::INFINITY,
        min_stress_element: 0,
        corner_groups: 0,
        corner_skipped: 0,
    };
    for colour in blocks {
        let run = |chunk: &Vec<u32>| -> ElementSums {
            // SAFETY: blocks of one colour share no node, so the nodes written by
            // different blocks of this colour are disjoint; inside a block the elements run
            // one after another; `f` outlives the loop.
            unsafe {
                match rule {
                    ElementRule::Full => ElementSums::at_gauss_points(chunk_forces(
                        mesh, classes, mat, u, ptr, chunk, energy, prefetch,
                    )),
                    ElementRule::FBar => ElementSums::at_gauss_points(fbar::chunk_forces_fbar(
                        mesh, classes, mat, u, ptr, chunk, energy,
                    )),
                    ElementRule::ReducedPhysical => {
                        physical::chunk_forces_physical(mesh, classes, mat, u, ptr, chunk, energy)
                    }
                    ElementRule::Reduced { kappa } => chunk_forces_reduced(
                        mesh,
                        classes,
                        mat,
                        kappa,
                        u,
                        ptr,
                        chunk,
                        energy,
                        exact_below,
                        prefetch,
                    ),
                }
            }
        };
        match team {
            Some(team) => team.map_into(colour.len(), parts, |i| run(&colour[i])),
            None => {
                parts.clear();
                parts.extend(colour.iter().map(run));
            }
        }
        if let ElementRule::Reduced { .. } = rule {
            out.corner_groups += colour.iter().map(|c| c.len() as u64 / 8).sum::<u64>();
        }
        for p in parts.iter() {
            out.corner_skipped += p.skipped as u64;
            out.strain += p.strain;
            out.hourglass += p.hourglass;
            // `!(j >= min_j)` keeps a NaN (it means non-finite displacements).
            if !(p.min_j >= out.min_j) {
                out.min_j = p.min_j;
                out.min_element = p.min_element;
            }
            if !(p.min_stress_j >= out.min_stress_j) {
                out.min_stress_j = p.min_stress_j;
                out.min_stress_element = p.min_stress_element;
            }
        }
    }
    if !mesh.tets.is_empty() {
        let split = tet::nodal_pressure(mat);
        let p = tet::tet_forces(
            mesh,
            &classes.tets,
            mat,
            split,
            u,
            &mut f.planes_mut(),
            team,
            tets,
        );
        out.strain += p.strain;
        if !(p.min_j >= out.min_j) {
            out.min_j = p.min_j;
            out.min_element = p.min_element;
        }
        if !(p.min_stress_j >= out.min_stress_j) {
            out.min_stress_j = p.min_stress_j;
            out.min_stress_element = p.min_stress_element;
        }
    }
    out
}

/// The `exact_below` of [`assemble_internal_forces`] that the solver's step passes: below this
/// J the element loop reports the corners' smallest J exactly; above it, with one point and
/// after t₀, the lane groups whose bound proves every corner positive report their bounds.
/// The smallest positive normal f64: the inversion check (J ≤ 0) is the only reader in the
/// step, and a skipped group then reports positive bounds (never a bound that underflowed to
/// 0, which that check would take for an inverted corner). At 0.9, the step control's
/// compression threshold used before, the bound let no lane group skip the check once a
/// torn-off body rang in its hourglass modes (corner J below 0.9); here nearly every group
/// skips it (model §1.9; docs: performance log).
pub const CORNER_EXACT_BELOW: f64 = f64::MIN_POSITIVE;

simd_dispatch! {
    /// One chunk of a colour with one-point integration: groups of 8 elements go through the
    /// lane kernel ([`element_forces_reduced_lanes_in`]; H and the hourglass modes 4 lanes at a
    /// time on AVX2; a group of 8 axis-aligned boxes through the modes of
    /// the trilinear field, its `BOXES`), the remainder through the scalar one
    /// ([`element_forces_reduced`], which takes the modes on a box too).
    fn chunk_forces_reduced / chunk_forces_reduced_avx2 / chunk_forces_reduced_avx512
        / chunk_forces_reduced_builds
        => chunk_forces_reduced_impl(
            mesh: &Mesh,
            classes: &ElementClasses,
            mat: &Material,
            kappa: f64,
            u: [&[f64]; 3],
            f: PlanesPtr,
            chunk: &[u32],
            energy: bool,
            exact_below: f64,
            prefetch: bool
        ) -> ElementSums, const by prefetch
}

/// `PREFETCH`: the loop asks for the next group's nodes ([`prefetch_group`]); it is the
/// `prefetch` argument, made a constant by the dispatch, so the loop is compiled once with the
/// hints and once without. With the flag tested inside the loop, LLVM laid it out so that the
/// hints stalled behind the load of the next group's connectivity and the kernel lost the gain
/// (docs: performance log).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn chunk_forces_reduced_impl<const FMA: bool, const ISA: u8, const PREFETCH: bool>(
    mesh: &Mesh,
    classes: &ElementClasses,
    mat: &Material,
    kappa: f64,
    u: [&[f64]; 3],
    f: PlanesPtr,
    chunk: &[u32],
    energy: bool,
    exact_below: f64,
    prefetch: bool,
) -> ElementSums {
    // The dispatch made the argument this constant.
    debug_assert_eq!(prefetch, PREFETCH);
    let (mut e_sum, mut hg_sum) = (0.0, 0.0);
    let mut skipped = 0u32;
    let mut min_j = f64::INFINITY;
    let mut min_e = 0usize;
    let (mut min_jc, mut min_ec) = (f64::INFINITY, 0usize);
    let groups = chunk.chunks_exact(8);
    let rest = groups.remainder();
    let mut lanes = LaneElements::default();
    let mut corner_lanes = corners::LaneCorners::default();
    let mut ul = NodeLanes::zeros();
    let mut fl = NodeLanes::zeros();
    // Class whose data sits in each lane: most meshes have few classes (a structured box has
    // one), so the lane data is rarely rewritten.
    let mut staged = [u32::MAX; 8];
    // Bit l: lane l holds an axis-aligned box (`CentreData::axis_aligned`).
    let mut boxes = 0u8;
    let work = &mut OnePointScratch::default();
    for (k, group) in groups.enumerate() {
        if let (true, Some(next)) = (PREFETCH, chunk.get(8 * k + 8..8 * k + 16)) {
            prefetch_group(mesh, u, f, next);
        }
        for (l, &e) in group.iter().enumerate() {
            let class = *classes.class_of.get_unchecked(e as usize);
            if class == staged[l] {
                continue;
            }
            staged[l] = class;
            let cd: &CentreData = classes.centre.get_unchecked(class as usize);
            lanes.set(l, cd, hourglass_stiffness(mat, cd, kappa));
            corner_lanes.set(l, cd);
            boxes = (boxes & !(1 << l)) | ((cd.axis_aligned as u8) << l);
        }
        let row = group_is_row(&classes.row_start, group);
        gather_group(mesh, u, group, row, &mut ul.0);
        let [en, hg, det] = match (ISA == ISA_AVX2, boxes == u8::MAX) {
            (true, true) => {
                reduced_group::<FMA, true, true>(mat, &lanes, &ul.0, &mut fl.0, work, energy)
            }
            (false, true) => {
                reduced_group::<FMA, false, true>(mat, &lanes, &ul.0, &mut fl.0, work, energy)
            }
            (true, false) => {
                reduced_group::<FMA, true, false>(mat, &lanes, &ul.0, &mut fl.0, work, energy)
            }
            (false, false) => {
                reduced_group::<FMA, false, false>(mat, &lanes, &ul.0, &mut fl.0, work, energy)
            }
        };
        // The corners' J too (hourglassing turns corners, not the centre); a NaN centre stays.
        // Skipped where every lane's bound J (1 − C|q|/s)³ ≤ J_a is ≥ `exact_below`: then each
        // lane reports its bound, which is ≥ `exact_below` and ≤ its exact J.
        let bound = corner_lanes.lower_bound::<ISA>(&det, work);
        let j = if exact_below == f64::NEG_INFINITY || all_at_least(&bound, exact_below) {
            skipped += 1;
            bound
        } else {
            let mut j = corner_lanes.min_jacobian::<FMA>(&ul.0);
            for l in 0..8 {
                if !(j[l] < det[l]) {
                    j[l] = det[l];
                }
            }
            j
        };
        for l in 0..8 {
            e_sum += en[l];
            hg_sum += hg[l];
        }
        // Lane by lane only where some lane lowers a minimum (or is NaN): the same result.
        if !all_at_least(&j, min_j) {
            for (l, &e) in group.iter().enumerate() {
                keep_min_j(j[l], e, &mut min_j, &mut min_e);
            }
        }
        if !all_at_least(&det, min_jc) {
            for (l, &e) in group.iter().enumerate() {
                keep_min_j(det[l], e, &mut min_jc, &mut min_ec);
            }
        }
        scatter_group::<ISA>(f, &mesh.elements, group, row, &fl.0);
    }
    let mut fe = [[0.0; 3]; 8];
    for &e in rest {
        let conn = mesh.elements.get_unchecked(e as usize);
        let cd: &CentreData = classes
            .centre
            .get_unchecked(*classes.class_of.get_unchecked(e as usize) as usize);
        let k = hourglass_stiffness(mat, cd, kappa);
        let ue: [[f64; 3]; 8] = std::array::from_fn(|a| node_of(u, conn[a]));
        let (en, hg, j) = if energy {
            element_forces_reduced::<true>(mat, cd, k, &ue, &mut fe)
        } else {
            element_forces_reduced::<false>(mat, cd, k, &ue, &mut fe)
        };
        e_sum += en;
        hg_sum += hg;
        let jc = corners::min_corner_jacobian(cd, &ue);
        keep_min_j(if jc < j { jc } else { j }, e, &mut min_j, &mut min_e);
        keep_min_j(j, e, &mut min_jc, &mut min_ec);
        scatter(f, conn, &fe);
    }
    ElementSums {
        strain: e_sum,
        hourglass: hg_sum,
        min_j,
        min_element: min_e,
        skipped,
        min_stress_j: min_jc,
        min_stress_element: min_ec,
    }
}

/// Whether every lane of `v` is ≥ `t` (false for a NaN lane).
#[inline(always)]
fn all_at_least(v: &[f64; 8], t: f64) -> bool {
    let mut all = true;
    for &x in v {
        all &= x >= t;
    }
    all
}

simd_dispatch! {
    /// One chunk of a colour with full integration: groups of 8 elements go through the lane
    /// kernel ([`full::full_lanes`], one element per lane; the class data broadcast when the 8
    /// share a class, else staged per lane), the remainder — and every element in the
    /// portable build (not in its WebAssembly SIMD build, `ISA_SIMD128`), and the groups that
    /// mix axis-aligned boxes with other shapes — through the scalar one ([`element_forces`],
    /// the Gauss points in lanes). Both give each element the same bits; the forces are
    /// scattered element after element in chunk order.
    fn chunk_forces / chunk_forces_avx2 / chunk_forces_avx512 / chunk_forces_builds
        => chunk_forces_impl(
            mesh: &Mesh,
            classes: &ElementClasses,
            mat: &Material,
            u: [&[f64]; 3],
            f: PlanesPtr,
            chunk: &[u32],
            energy: bool,
            prefetch: bool
        ) -> (f64, f64, usize), const by prefetch
}

/// `PREFETCH` as in [`chunk_forces_reduced_impl`].
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn chunk_forces_impl<const FMA: bool, const ISA: u8, const PREFETCH: bool>(
    mesh: &Mesh,
    classes: &ElementClasses,
    mat: &Material,
    u: [&[f64]; 3],
    f: PlanesPtr,
    chunk: &[u32],
    energy: bool,
    prefetch: bool,
) -> (f64, f64, usize) {
    // The dispatch made the argument this constant.
    debug_assert_eq!(prefetch, PREFETCH);
    let mut e_sum = 0.0;
    let mut min_j = f64::INFINITY;
    let mut min_e = 0usize;
    // The portable build (no vector unit assumed) runs every element through the scalar
    // kernel, whose lanes are the Gauss points: faster there than 8 elements in lanes (docs:
    // performance log). Its WebAssembly SIMD build (the page) takes the lanes, as AVX does.
    let lanes_end = if ISA == ISA_PORTABLE {
        0
    } else {
        chunk.len() / 8 * 8
    };
    let (grouped, rest) = chunk.split_at(lanes_end);
    let mut ul = NodeLanes::zeros();
    let mut fl = [[F64x8([0.0; 8]); 3]; 8];
    // Lanes of several classes: each lane's data, rewritten when its class changes.
    let mut lanes = full::LaneGauss::default();
    let mut staged = [u32::MAX; 8];
    let mut work = full::FullScratch::default();
    for (k, group) in grouped.chunks_exact(8).enumerate() {
        if let (true, Some(next)) = (PREFETCH, grouped.get(8 * k + 8..8 * k + 16)) {
            prefetch_group(mesh, u, f, next);
        }
        let row = group_is_row(&classes.row_start, group);
        gather_group(mesh, u, group, row, &mut ul.0);
        let class = *classes.class_of.get_unchecked(group[0] as usize);
        let one_class = group
            .iter()
            .all(|&e| *classes.class_of.get_unchecked(e as usize) == class);
        let (en, det) = if one_class {
            let gd = classes.data.get_unchecked(class as usize);
            let g = full::OneClass(gd);
            if gd.axis_aligned {
                full_group::<FMA, true, _>(mat, &g, &ul.0, &mut fl, &mut work, energy)
            } else {
                full_group::<FMA, false, _>(mat, &g, &ul.0, &mut fl, &mut work, energy)
            }
        } else {
            let mut boxes = 0;
            for (l, &e) in group.iter().enumerate() {
                let c = *classes.class_of.get_unchecked(e as usize);
                if c != staged[l] {
                    staged[l] = c;
                    lanes.set(l, classes.data.get_unchecked(c as usize));
                }
                boxes += classes.data.get_unchecked(c as usize).axis_aligned as usize;
            }
            match boxes {
                0 => full_group::<FMA, false, _>(mat, &lanes, &ul.0, &mut fl, &mut work, energy),
                8 => full_group::<FMA, true, _>(mat, &lanes, &ul.0, &mut fl, &mut work, energy),
                _ => {
                    // Boxes and other shapes in one group: the lane kernel takes the box path
                    // (through the modes) or the general one for all 8 lanes, the scalar kernel
                    // per element, so each element goes through the scalar kernel here.
                    for &e in group {
                        let (en, j) = scalar_element::<FMA>(mesh, classes, mat, u, f, e, energy);
                        e_sum += en;
                        keep_min_j(j, e, &mut min_j, &mut min_e);
                    }
                    continue;
                }
            }
        };
        // SAFETY: `[[F64x8; 3]; 8]` is `[[[f64; 8]; 3]; 8]` more aligned (F64x8 is
        // `repr(C)` over `[f64; 8]`).
        let fv = &*(&fl as *const [[F64x8; 3]; 8] as *const [[[f64; 8]; 3]; 8]);
        for (l, &e) in group.iter().enumerate() {
            e_sum += en.0[l];
            keep_min_j(det.0[l], e, &mut min_j, &mut min_e);
        }
        scatter_group::<ISA>(f, &mesh.elements, group, row, fv);
    }
    for &e in rest {
        let (en, j) = scalar_element::<FMA>(mesh, classes, mat, u, f, e, energy);
        e_sum += en;
        keep_min_j(j, e, &mut min_j, &mut min_e);
    }
    (e_sum, min_j, min_e)
}

#[cfg(test)]
mod tests;
