//! The F-bar kernel (model §1.11): the full element under a homogeneous deformation (so the
//! patch test, on distorted elements too), the forces the exact gradient of its energy, and
//! every build the portable one.
//!
//! Tolerances: under a homogeneous deformation J_q = J̄ at every point, α = 1 in exact
//! arithmetic and the correction's bracket is a difference of equal numbers, so F-bar and the
//! full kernel differ by round-off only: a few ulps of α and of the stress, 1e-12 of the
//! largest nodal force (an error of the formulation is O(1)). The gradient check is a central
//! difference with step δ = 1e-6 of the element size: its truncation error is O(δ²) ≈ 1e-12
//! and its cancellation ε Ψ/δ ≈ 1e-10 of the force scale, so 1e-6 of the largest force is far
//! above both and far below the correction term (which moves the forces by a share of the
//! volumetric stress, O(10⁻¹) here).

use super::super::{chunk_forces, Planes};
use super::*;
use crate::material::MaterialModel;

/// A 3×3×2 box with every 5th node moved off the grid (several element classes, none a box).
pub(in crate::kernels) fn distorted_box() -> Mesh {
    let mut mesh = Mesh::boxed([0.0; 3], [0.3, 0.3, 0.2], [3, 3, 2]);
    for (i, x) in mesh.nodes.iter_mut().enumerate() {
        if i % 5 == 0 {
            let t = i as f64;
            x[0] += 0.012 * (1.7 * t).sin();
            x[1] += 0.011 * (2.3 * t).cos();
            x[2] += 0.009 * (0.9 * t).sin();
        }
    }
    mesh
}

/// A non-affine displacement whose volume ratio varies across each element (J in ~0.75…1.1).
fn bent(mesh: &Mesh) -> Vec<[f64; 3]> {
    (mesh.nodes.iter())
        .map(|x| {
            [
                0.4 * x[1] * x[2] - 0.3 * x[0] * x[0],
                -0.5 * x[0] * x[0] + 0.2 * x[1] * x[1],
                0.1 * (3.0 * x[0]).sin() - 0.3 * x[2] * x[2],
            ]
        })
        .collect()
}

/// u = A X: F = I + A at every point of every element.
fn affine(mesh: &Mesh) -> Vec<[f64; 3]> {
    let a = [
        [0.08, 0.03, -0.02],
        [-0.04, -0.05, 0.06],
        [0.01, 0.07, 0.04],
    ];
    (mesh.nodes.iter())
        .map(|x| std::array::from_fn(|i| (0..3).map(|j| a[i][j] * x[j]).sum()))
        .collect()
}

fn materials() -> [Material; 2] {
    [
        Material::new(MaterialModel::Svk, 5e6, 0.45, 1100.0),
        Material::new(MaterialModel::NeoHookean, 5e6, 0.49, 1100.0),
    ]
}

/// A build of [`chunk_forces_fbar`].
type FbarBuild = unsafe fn(
    &Mesh,
    &ElementClasses,
    &Material,
    [&[f64]; 3],
    PlanesPtr,
    &[u32],
    bool,
) -> (f64, f64, usize);

/// One chunk through the F-bar build `build`: (forces, strain energy, min J).
fn fbar_chunk(
    build: FbarBuild,
    mesh: &Mesh,
    mat: &Material,
    u: &[[f64; 3]],
    chunk: &[u32],
) -> (Vec<[f64; 3]>, f64, f64) {
    let classes = mesh.element_classes().unwrap();
    let mut f = Planes::zeros(mesh.nodes.len());
    let up = Planes::from_rows(u);
    // SAFETY: one thread; the chunk's elements and their nodes are in range of `u` and `f`.
    let (e, j, _) = unsafe { build(mesh, &classes, mat, up.planes(), f.ptr(), chunk, true) };
    (f.to_rows(), e, j)
}

fn largest(f: &[[f64; 3]]) -> f64 {
    f.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// Under u = A X the F-bar element is the full one: forces and energy of every build equal the
/// full kernel's to round-off, on distorted elements, over a chunk of 8 + 10 elements (a lane
/// group and a shorter one); and the interior nodes are in equilibrium (the patch test).
#[test]
fn homogeneous_deformation_is_the_full_element_and_passes_the_patch_test() {
    let mesh = distorted_box();
    let classes = mesh.element_classes().unwrap();
    let u = affine(&mesh);
    let chunk: Vec<u32> = (0..mesh.elements.len() as u32).collect();
    assert_eq!(chunk.len(), 18);
    for mat in materials() {
        let mut full_f = Planes::zeros(mesh.nodes.len());
        let up = Planes::from_rows(&u);
        // SAFETY: as in `fbar_chunk`.
        let (full_e, ..) = unsafe {
            chunk_forces(
                &mesh,
                &classes,
                &mat,
                up.planes(),
                full_f.ptr(),
                &chunk,
                true,
                false,
            )
        };
        let full_f = full_f.to_rows();
        let scale = largest(&full_f);
        assert!(scale > 0.0);
        for (name, build) in chunk_forces_fbar_builds() {
            let (f, e, _) = fbar_chunk(build, &mesh, &mat, &u, &chunk);
            for (a, b) in f.iter().flatten().zip(full_f.iter().flatten()) {
                assert!(
                    (a - b).abs() <= 1e-12 * scale,
                    "{:?} {name}: F-bar {a} vs full {b}",
                    mat.model
                );
            }
            assert!(
                (e - full_e).abs() <= 1e-12 * full_e,
                "{name}: energy {e} vs {full_e}"
            );
            // Interior nodes (not on the box's faces): zero net force.
            let [nx, ny, nz] = [4usize, 4, 3];
            for k in 1..nz - 1 {
                for j in 1..ny - 1 {
                    for i in 1..nx - 1 {
                        let n = i + nx * (j + ny * k);
                        let r = f[n].iter().fold(0.0f64, |m, v| m.max(v.abs()));
                        assert!(r <= 1e-12 * scale, "{name}: interior node {n} force {r}");
                    }
                }
            }
        }
    }
}

/// The forces are the gradient of Ψ = Σ_q w_q ψ(F̄_q): each nodal component against the central
/// difference of the energy the same kernel returns, under a displacement whose volume ratio
/// varies inside the elements (so the correction of eq. (1.11c) is at work).
#[test]
fn forces_are_the_gradient_of_the_energy() {
    let mesh = distorted_box();
    let u = bent(&mesh);
    let chunk: Vec<u32> = (0..mesh.elements.len() as u32).collect();
    let build = chunk_forces_fbar_builds()[0].1;
    let delta = 1e-6 * 0.1;
    for mat in materials() {
        let (f, _, j) = fbar_chunk(build, &mesh, &mat, &u, &chunk);
        assert!(
            j > 0.5 && j < 0.95,
            "min J {j}: the field is not the one meant"
        );
        assert_gradient(&u, &f, delta, |v| {
            fbar_chunk(build, &mesh, &mat, v, &chunk).1
        });
    }
}

/// Each nodal component of the forces `f` at `u` within 1e-6 of the largest force of the
/// central difference (energy(u + δeᵢ) − energy(u − δeᵢ))/2δ (the tolerance is argued in the
/// module doc of each kernel's tests).
pub(in crate::kernels) fn assert_gradient(
    u: &[[f64; 3]],
    f: &[[f64; 3]],
    delta: f64,
    energy: impl Fn(&[[f64; 3]]) -> f64,
) {
    let scale = largest(f);
    for n in 0..u.len() {
        for c in 0..3 {
            let at = |s: f64| {
                let mut v = u.to_vec();
                v[n][c] += s;
                energy(&v)
            };
            let fd = (at(delta) - at(-delta)) / (2.0 * delta);
            assert!(
                (fd - f[n][c]).abs() <= 1e-6 * scale,
                "node {n} component {c}: force {} vs ∂Ψ/∂u {fd}",
                f[n][c]
            );
        }
    }
}

/// Every build gives the portable build's forces and energy to round-off (the builds differ
/// only in fused multiply–adds), and AVX2 and AVX-512 the same bits.
#[test]
fn every_build_matches_portable() {
    let mesh = distorted_box();
    let u = bent(&mesh);
    let chunk: Vec<u32> = (0..mesh.elements.len() as u32).rev().collect();
    for mat in materials() {
        let builds: Vec<_> = (chunk_forces_fbar_builds().into_iter())
            .map(|(name, b)| (name, fbar_chunk(b, &mesh, &mat, &u, &chunk)))
            .collect();
        let (pf, pe, pj) = &builds[0].1;
        let scale = largest(pf);
        for (name, (f, e, j)) in &builds {
            for (a, b) in f.iter().flatten().zip(pf.iter().flatten()) {
                assert!(
                    (a - b).abs() <= 1e-12 * scale,
                    "{name}: {a} vs portable {b}"
                );
            }
            assert!((e - pe).abs() <= 1e-12 * pe.abs(), "{name}: energy");
            assert!((j - pj).abs() <= 1e-13, "{name}: min J");
        }
        let bits = |n: &str| {
            (builds.iter().find(|b| b.0 == n)).map(|b| {
                b.1 .0
                    .iter()
                    .flatten()
                    .map(|v| v.to_bits())
                    .collect::<Vec<_>>()
            })
        };
        if let (Some(a), Some(b)) = (bits("avx2"), bits("avx512")) {
            assert!(a == b, "the AVX2 and AVX-512 builds differ");
        }
    }
}

/// The vector cube root against the library's over its interval [½, 2]: within 2 ulps (three
/// Halley steps from the Taylor start converge to rounding; a wrong step is off by 10⁻⁵ or more).
#[test]
fn halley_cube_root_is_the_cube_root() {
    for k in 0..=3000 {
        let r = 0.5 + 1.5 * k as f64 / 3000.0;
        let (y, exact) = (halley_cube_root(r), r.cbrt());
        assert!(
            (y - exact).abs() <= 2.0 * f64::EPSILON * exact,
            "∛{r}: {y} vs {exact}"
        );
    }
}
