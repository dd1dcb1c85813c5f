//! The element loop of stage 3 (PHYSICS.md §2, §4): F_int(U) = Σ_e fₑ(U) over node-disjoint
//! element blocks on the thread team, each block through the full (2×2×2) or one-point kernel
//! of [`crate::material`] built for the CPU's instruction set ([`simd`]); and the node loop of
//! stage 5 (free velocity).

mod nodes;
pub mod simd;

pub(crate) use nodes::{free_velocity_chunk, NodeSums};

use crate::material::{
    element_forces, element_forces_reduced, element_forces_reduced_lanes, hourglass_stiffness,
    LaneElements, Material,
};
use crate::mesh::{CentreData, ElementClasses, GaussData, Mesh};
use crate::model::Integration;
use crate::team::Team;
use simd::{simd_dispatch, ISA_AVX2, ISA_AVX512, ISA_PORTABLE};

/// A raw pointer to the nodal force rows, shared by the blocks of one colour (which write
/// disjoint rows).
#[derive(Clone, Copy)]
pub(crate) struct SendPtr(*mut [f64; 3]);
unsafe impl Send for SendPtr {}
unsafe impl Sync for SendPtr {}

/// Which element kernel assembles the internal forces (scene `scheme.integration`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ElementRule {
    /// 2×2×2 Gauss points ([`element_forces`]).
    Full,
    /// One point and Flanagan–Belytschko hourglass stiffness κ ([`element_forces_reduced`]).
    Reduced { kappa: f64 },
}

impl ElementRule {
    pub fn of(scheme: &crate::model::SchemeParams) -> ElementRule {
        match scheme.integration {
            Integration::Full => ElementRule::Full,
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
    /// Hourglass energy Ψ_hg(U) [J] (reduced integration; 0 unless asked for).
    pub hourglass: f64,
    /// Smallest J = det F seen, and its element.
    pub min_j: f64,
    pub min_element: usize,
}

/// Per-block results of the element loop: strain energy, hourglass energy, smallest J and its
/// element.
pub type ElementSums = (f64, f64, f64, usize);

/// Internal forces of a whole mesh: F_int(U) = Σ_e fₑ(U) (PHYSICS.md §2 and §4 stage 3).
/// `f` must be zeroed. Energies are computed only if `energy`. `blocks` come from
/// [`Mesh::element_blocks`]; `parts` is a buffer for the per-block results (reused, so the
/// step allocates nothing).
#[allow(clippy::too_many_arguments)]
pub fn assemble_internal_forces(
    mesh: &Mesh,
    classes: &ElementClasses,
    blocks: &[Vec<Vec<u32>>],
    mat: &Material,
    rule: ElementRule,
    u: &[[f64; 3]],
    f: &mut [[f64; 3]],
    energy: bool,
    team: Option<&Team>,
    parts: &mut Vec<ElementSums>,
) -> Assembly {
    assert_eq!(u.len(), f.len());
    let ptr = SendPtr(f.as_mut_ptr());
    let mut out = Assembly {
        strain: 0.0,
        hourglass: 0.0,
        min_j: f64::INFINITY,
        min_element: 0,
    };
    for colour in blocks {
        let run = |chunk: &Vec<u32>| -> (f64, f64, f64, usize) {
            // SAFETY: blocks of one colour share no node, so the nodal rows written by
            // different blocks of this colour are disjoint; inside a block the elements run
            // one after another; `f` outlives the loop.
            unsafe {
                match rule {
                    ElementRule::Full => {
                        let (e, j, el) = chunk_forces(mesh, classes, mat, u, ptr, chunk, energy);
                        (e, 0.0, j, el)
                    }
                    ElementRule::Reduced { kappa } => {
                        chunk_forces_reduced(mesh, classes, mat, kappa, u, ptr, chunk, energy)
                    }
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
        for &(e, hg, j, el) in parts.iter() {
            out.strain += e;
            out.hourglass += hg;
            // `!(j >= min_j)` keeps a NaN (it means non-finite displacements).
            if !(j >= out.min_j) {
                out.min_j = j;
                out.min_element = el;
            }
        }
    }
    out
}

simd_dispatch! {
    /// One chunk of a colour with one-point integration: groups of 8 elements go through the
    /// lane kernel ([`element_forces_reduced_lanes`]), the remainder through the scalar one
    /// ([`element_forces_reduced`]).
    fn chunk_forces_reduced / chunk_forces_reduced_avx2 / chunk_forces_reduced_avx512
        => chunk_forces_reduced_impl(
            mesh: &Mesh,
            classes: &ElementClasses,
            mat: &Material,
            kappa: f64,
            u: &[[f64; 3]],
            f: SendPtr,
            chunk: &[u32],
            energy: bool
        ) -> (f64, f64, f64, usize)
}

#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn chunk_forces_reduced_impl<const FMA: bool, const ISA: u8>(
    mesh: &Mesh,
    classes: &ElementClasses,
    mat: &Material,
    kappa: f64,
    u: &[[f64; 3]],
    f: SendPtr,
    chunk: &[u32],
    energy: bool,
) -> (f64, f64, f64, usize) {
    let (mut e_sum, mut hg_sum) = (0.0, 0.0);
    let mut min_j = f64::INFINITY;
    let mut min_e = 0usize;
    let groups = chunk.chunks_exact(8);
    let rest = groups.remainder();
    let mut lanes = LaneElements::default();
    let mut ul = [[[0.0; 8]; 3]; 8];
    let mut fl = [[[0.0; 8]; 3]; 8];
    // Class whose data sits in each lane: most meshes have few classes (a structured box has
    // one), so the lane data is rarely rewritten.
    let mut staged = [u32::MAX; 8];
    // The vector gathers index with i32 offsets.
    let gather = ISA != ISA_PORTABLE
        && u.len() <= i32::MAX as usize / 3
        && mesh.elements.len() <= i32::MAX as usize / 8;
    for group in groups {
        for (l, &e) in group.iter().enumerate() {
            let class = *classes.class_of.get_unchecked(e as usize);
            if class == staged[l] {
                continue;
            }
            staged[l] = class;
            let cd: &CentreData = classes.centre.get_unchecked(class as usize);
            lanes.set(l, cd, hourglass_stiffness(mat, cd, kappa));
        }
        #[cfg(target_arch = "x86_64")]
        let gathered = gather && {
            let elements = mesh.elements.as_ptr() as *const i32;
            let base = u.as_ptr() as *const f64;
            if ISA == ISA_AVX512 {
                simd::gather_lanes_avx512(elements, group, base, &mut ul);
            } else {
                simd::gather_lanes_avx2(elements, group, base, &mut ul);
            }
            true
        };
        #[cfg(not(target_arch = "x86_64"))]
        let gathered = {
            let _ = gather;
            false
        };
        if !gathered {
            for (l, &e) in group.iter().enumerate() {
                let conn = mesh.elements.get_unchecked(e as usize);
                for a in 0..8 {
                    let ua = u.get_unchecked(conn[a] as usize);
                    for j in 0..3 {
                        ul[a][j][l] = ua[j];
                    }
                }
            }
        }
        let [en, hg, det] = if energy {
            element_forces_reduced_lanes::<true, FMA>(mat, &lanes, &ul, &mut fl)
        } else {
            element_forces_reduced_lanes::<false, FMA>(mat, &lanes, &ul, &mut fl)
        };
        for (l, &e) in group.iter().enumerate() {
            e_sum += en[l];
            hg_sum += hg[l];
            // `!(j >= min_j)` also catches NaN.
            if !(det[l] >= min_j) {
                min_j = det[l];
                min_e = e as usize;
            }
            let conn = mesh.elements.get_unchecked(e as usize);
            for a in 0..8 {
                let row = &mut *f.0.add(conn[a] as usize);
                row[0] += fl[a][0][l];
                row[1] += fl[a][1][l];
                row[2] += fl[a][2][l];
            }
        }
    }
    let mut fe = [[0.0; 3]; 8];
    for &e in rest {
        let conn = mesh.elements.get_unchecked(e as usize);
        let cd: &CentreData = classes
            .centre
            .get_unchecked(*classes.class_of.get_unchecked(e as usize) as usize);
        let k = hourglass_stiffness(mat, cd, kappa);
        let ue: [[f64; 3]; 8] = std::array::from_fn(|a| *u.get_unchecked(conn[a] as usize));
        let (en, hg, j) = if energy {
            element_forces_reduced::<true>(mat, cd, k, &ue, &mut fe)
        } else {
            element_forces_reduced::<false>(mat, cd, k, &ue, &mut fe)
        };
        e_sum += en;
        hg_sum += hg;
        if !(j >= min_j) {
            min_j = j;
            min_e = e as usize;
        }
        for a in 0..8 {
            let row = &mut *f.0.add(conn[a] as usize);
            row[0] += fe[a][0];
            row[1] += fe[a][1];
            row[2] += fe[a][2];
        }
    }
    (e_sum, hg_sum, min_j, min_e)
}

simd_dispatch! {
    /// One chunk of a colour: gathers the 8 nodal displacements, runs the kernel, scatters
    /// forces.
    fn chunk_forces / chunk_forces_avx2 / chunk_forces_avx512
        => chunk_forces_impl(
            mesh: &Mesh,
            classes: &ElementClasses,
            mat: &Material,
            u: &[[f64; 3]],
            f: SendPtr,
            chunk: &[u32],
            energy: bool
        ) -> (f64, f64, usize)
}

#[inline(always)]
unsafe fn chunk_forces_impl<const FMA: bool, const ISA: u8>(
    mesh: &Mesh,
    classes: &ElementClasses,
    mat: &Material,
    u: &[[f64; 3]],
    f: SendPtr,
    chunk: &[u32],
    energy: bool,
) -> (f64, f64, usize) {
    let mut e_sum = 0.0;
    let mut min_j = f64::INFINITY;
    let mut min_e = 0usize;
    let mut fe = [[0.0; 3]; 8];
    for &e in chunk {
        let conn = mesh.elements.get_unchecked(e as usize);
        let gd: &GaussData = classes
            .data
            .get_unchecked(*classes.class_of.get_unchecked(e as usize) as usize);
        let ue: [[f64; 3]; 8] = std::array::from_fn(|a| *u.get_unchecked(conn[a] as usize));
        let (en, j) = if energy {
            element_forces::<true, FMA>(mat, gd, &ue, &mut fe)
        } else {
            element_forces::<false, FMA>(mat, gd, &ue, &mut fe)
        };
        e_sum += en;
        // `!(j >= min_j)` also catches NaN.
        if !(j >= min_j) {
            min_j = j;
            min_e = e as usize;
        }
        for a in 0..8 {
            let row = &mut *f.0.add(conn[a] as usize);
            row[0] += fe[a][0];
            row[1] += fe[a][1];
            row[2] += fe[a][2];
        }
    }
    (e_sum, min_j, min_e)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::MaterialModel;

    /// Runs one chunk of one colour through `run` and returns the assembled forces with the
    /// chunk's (strain, hourglass, min J, its element).
    fn assemble_chunk(
        n_nodes: usize,
        run: impl FnOnce(SendPtr) -> (f64, f64, f64, usize),
    ) -> (Vec<[f64; 3]>, (f64, f64, f64, usize)) {
        let mut f = vec![[0.0; 3]; n_nodes];
        let out = run(SendPtr(f.as_mut_ptr()));
        (f, out)
    }

    /// The one-point chunk (lane kernel fed by gathers, lane data reused across groups of one
    /// class) assembles the scalar kernel's forces and energies, element by element, on a box
    /// whose elements are partly distorted (many classes, lanes changing class between
    /// groups) under a large non-affine displacement: to round-off (1e-12) on every build
    /// this CPU runs, and the AVX2 and AVX-512 builds bit-identical (same fused arithmetic).
    #[test]
    fn reduced_chunk_matches_scalar_kernel_on_every_build() {
        let mut mesh = Mesh::boxed([0.0; 3], [1.0, 0.8, 0.6], [8, 8, 6]);
        for (i, x) in mesh.nodes.iter_mut().enumerate() {
            if i % 11 == 0 {
                let t = i as f64;
                x[0] += 0.02 * (1.7 * t).sin();
                x[1] += 0.02 * (2.3 * t).cos();
                x[2] += 0.015 * (0.9 * t).sin();
            }
        }
        let classes = mesh.element_classes().unwrap();
        assert!(classes.centre.len() > 8, "the test needs several classes");
        let u: Vec<[f64; 3]> = mesh
            .nodes
            .iter()
            .map(|x| {
                [
                    0.1 * x[1] * x[2],
                    -0.05 * x[0] * x[0],
                    0.08 * (3.0 * x[0]).sin(),
                ]
            })
            .collect();
        let kappa = 0.05;
        let n = u.len();
        for model in [MaterialModel::Svk, MaterialModel::NeoHookean] {
            let mat = Material::new(model, 5e6, 0.45, 1100.0);
            for block in mesh.element_blocks(64).into_iter().flatten() {
                let chunk: &[u32] = &block;
                assert!(chunk.len() >= 16, "the test needs whole groups of 8");
                let mut reference = vec![[0.0; 3]; n];
                let (mut e_ref, mut hg_ref) = (0.0, 0.0);
                let mut fe = [[0.0; 3]; 8];
                for &e in chunk {
                    let conn = mesh.elements[e as usize];
                    let cd = &classes.centre[classes.class_of[e as usize] as usize];
                    let ue: [[f64; 3]; 8] = std::array::from_fn(|a| u[conn[a] as usize]);
                    let k = hourglass_stiffness(&mat, cd, kappa);
                    let (en, hg, _) = element_forces_reduced::<true>(&mat, cd, k, &ue, &mut fe);
                    e_ref += en;
                    hg_ref += hg;
                    for a in 0..8 {
                        for c in 0..3 {
                            reference[conn[a] as usize][c] += fe[a][c];
                        }
                    }
                }
                let scale = reference
                    .iter()
                    .flatten()
                    .fold(0.0f64, |m, v| m.max(v.abs()));
                let args = (&mesh, &classes, &mat, kappa, &u[..], chunk);
                let mut builds = vec![(
                    "portable",
                    assemble_chunk(n, |p| unsafe {
                        chunk_forces_reduced_impl::<false, ISA_PORTABLE>(
                            args.0, args.1, args.2, args.3, args.4, p, args.5, true,
                        )
                    }),
                )];
                #[cfg(target_arch = "x86_64")]
                {
                    let fma = std::is_x86_feature_detected!("fma");
                    if fma && std::is_x86_feature_detected!("avx2") {
                        builds.push((
                            "avx2",
                            assemble_chunk(n, |p| unsafe {
                                chunk_forces_reduced_avx2(
                                    args.0, args.1, args.2, args.3, args.4, p, args.5, true,
                                )
                            }),
                        ));
                    }
                    if fma && std::is_x86_feature_detected!("avx512f") {
                        builds.push((
                            "avx512",
                            assemble_chunk(n, |p| unsafe {
                                chunk_forces_reduced_avx512(
                                    args.0, args.1, args.2, args.3, args.4, p, args.5, true,
                                )
                            }),
                        ));
                    }
                }
                for (name, (f, (en, hg, min_j, _))) in &builds {
                    for (k, (a, b)) in f.iter().zip(&reference).enumerate() {
                        for c in 0..3 {
                            assert!(
                                (a[c] - b[c]).abs() <= 1e-12 * scale,
                                "{model:?} {name}: node {k} component {c}: {} vs {}",
                                a[c],
                                b[c]
                            );
                        }
                    }
                    assert!(
                        (en - e_ref).abs() <= 1e-12 * e_ref.abs(),
                        "{model:?} {name}"
                    );
                    assert!(
                        (hg - hg_ref).abs() <= 1e-12 * hg_ref.abs(),
                        "{model:?} {name}"
                    );
                    assert!(
                        *min_j > 0.5 && *min_j < 1.5,
                        "{model:?} {name}: J = {min_j}"
                    );
                }
                if let [.., (_, avx2), (_, avx512)] = &builds[..] {
                    if builds.len() == 3 {
                        assert_eq!(avx2.0, avx512.0, "{model:?}: AVX2 and AVX-512 differ");
                        assert_eq!(avx2.1, avx512.1, "{model:?}: AVX2 and AVX-512 differ");
                    }
                }
            }
        }
    }
}
