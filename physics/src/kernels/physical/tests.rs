//! The physically stabilised one-point kernel (model §1.12): its hourglass energies on a box
//! are the analytic bending, warping and twisting energies; an affine field excites no
//! hourglass force (the patch test, on distorted elements and under a large rotation); a rigid
//! rotation of a deformed element leaves its energies unchanged and rotates its forces; the
//! forces are the gradient of the energy; every build is the portable one.
//!
//! Tolerances: the box energies are quadratic forms evaluated at F = I exactly (an hourglass
//! field has H = 0 on a box), so they match their formulas to round-off, 1e-12. The affine and
//! rotated cases differ from their references by round-off in F⁻¹ and in qᵅ (a sum of ±uₐ
//! that cancels to 1e-16 of |u|): 1e-10 of the largest force. The gradient check is a central
//! difference with δ = 1e-6 of the element size: truncation O(δ²) and cancellation
//! ε Ψ/δ ≈ 1e-10 of the force scale, so 1e-6 is far above both and far below the terms
//! checked (the hourglass forces are 10⁻²–10⁻¹ of the forces here).

use super::super::fbar::tests::{assert_gradient, distorted_box};
use super::super::Planes;
use super::*;
use crate::material::MaterialModel;

/// A non-affine displacement on [`distorted_box`]'s 4×4×3 nodes: a smooth bending with a
/// varying volume ratio, plus checkerboards (−1)^(i+j) and (−1)^(i+j+k) of the node's grid
/// indices, which excite the ξη and ξηζ hourglass modes of every element.
fn bent(mesh: &Mesh) -> Vec<[f64; 3]> {
    (mesh.nodes.iter().enumerate())
        .map(|(n, x)| {
            let (i, j, k) = (n % 4, (n / 4) % 4, n / 16);
            let c2 = if (i + j) % 2 == 0 { 1.0 } else { -1.0 };
            let c3 = if (i + j + k) % 2 == 0 { 1.0 } else { -1.0 };
            [
                0.4 * x[1] * x[2] - 0.3 * x[0] * x[0] + 0.004 * c2,
                -0.5 * x[0] * x[0] + 0.2 * x[1] * x[1] - 0.003 * c3,
                0.1 * (3.0 * x[0]).sin() - 0.3 * x[2] * x[2] + 0.002 * c2,
            ]
        })
        .collect()
}

/// A rotation by `angle` about the unit axis (1, 2, 2)/3 (Rodrigues).
fn rotation(angle: f64) -> [[f64; 3]; 3] {
    let n = [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
    let (s, c) = angle.sin_cos();
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let k = [[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]];
            let delta = if i == j { 1.0 } else { 0.0 };
            c * delta + s * k[i][j] + (1.0 - c) * n[i] * n[j]
        })
    })
}

fn apply(r: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| (0..3).map(|j| r[i][j] * v[j]).sum())
}

fn materials() -> [Material; 2] {
    [
        Material::new(MaterialModel::Svk, 5e6, 0.45, 1100.0),
        Material::new(MaterialModel::NeoHookean, 5e6, 0.4999, 1100.0),
    ]
}

/// Materials whose bulk energy under [`bent`] does not dwarf the hourglass energy (at
/// ν = 0.4999 the field's volume change stores 10⁴ times more), so that the checks below
/// weigh the hourglass forces.
fn compressible() -> [Material; 2] {
    [
        Material::new(MaterialModel::Svk, 5e6, 0.3, 1100.0),
        Material::new(MaterialModel::NeoHookean, 5e6, 0.3, 1100.0),
    ]
}

/// A build of [`chunk_forces_physical`].
type Build = unsafe fn(
    &Mesh,
    &ElementClasses,
    &Material,
    [&[f64]; 3],
    PlanesPtr,
    &[u32],
    bool,
) -> ElementSums;

/// Every element of `mesh` through `build`: (forces, strain energy, hourglass energy, min J).
fn run(
    build: Build,
    mesh: &Mesh,
    mat: &Material,
    u: &[[f64; 3]],
) -> (Vec<[f64; 3]>, f64, f64, f64) {
    let classes = mesh.element_classes().unwrap();
    let chunk: Vec<u32> = (0..mesh.elements.len() as u32).collect();
    let mut f = Planes::zeros(mesh.nodes.len());
    let up = Planes::from_rows(u);
    // SAFETY: one thread; the chunk's elements and their nodes are in range of `u` and `f`.
    let s = unsafe { build(mesh, &classes, mat, up.planes(), f.ptr(), &chunk, true) };
    (f.to_rows(), s.strain, s.hourglass, s.min_j)
}

fn portable() -> Build {
    chunk_forces_physical_builds()[0].1
}

fn largest(f: &[[f64; 3]]) -> f64 {
    f.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// One box element of half-lengths ℓ = (0.05, 0.02, 0.03).
fn one_box() -> ([f64; 3], Mesh) {
    let l = [0.05, 0.02, 0.03];
    (
        l,
        Mesh::boxed([0.0; 3], [2.0 * l[0], 2.0 * l[1], 2.0 * l[2]], [1, 1, 1]),
    )
}

/// The displacement uᵢ = Q hᵅ(ξ) at the nodes of `mesh`'s one element, summed over `modes`
/// (α, i, Q). Node a of the element sits at the corner of `HEX_CORNERS` with the same index.
fn hourglass_field(mesh: &Mesh, modes: &[(usize, usize, f64)]) -> Vec<[f64; 3]> {
    let h = crate::mesh::hourglass_vectors();
    let conn = mesh.elements[0];
    let mut u = vec![[0.0; 3]; mesh.nodes.len()];
    for &(al, i, q) in modes {
        for a in 0..8 {
            u[conn[a] as usize][i] += q * h[al][a];
        }
    }
    u
}

/// On a box, one hourglass component uᵢ = Q hᵅ(ξ) at a time: Ψ_hg is
/// ½ E′ V Q²/(3ℓᵢ²) (E′ = E/(1 − ν²)) for a bending component (i in the mode's plane),
/// ½ μ V Q² (1/ℓ_m² + 1/ℓ_n²)/3 for a warping one (i normal to it), ½ E V Q²/(9ℓᵢ²) for ξηζ;
/// the strain energy is 0 (an hourglass field has F = I at the centre of a box).
#[test]
fn box_hourglass_energies_are_the_bending_warping_and_twisting_energies() {
    let (l, mesh) = one_box();
    let v = 8.0 * l[0] * l[1] * l[2];
    let q = 1e-3;
    let planes = [(0usize, 1usize), (1, 2), (2, 0)];
    for mat in materials() {
        let (e, nu, mu) = (mat.young, mat.poisson, mat.mu);
        for al in 0..4 {
            for i in 0..3 {
                let expected = if al == 3 {
                    0.5 * e * v * q * q / (9.0 * l[i] * l[i])
                } else {
                    let (m, n) = planes[al];
                    if i == m || i == n {
                        0.5 * e / (1.0 - nu * nu) * v * q * q / (3.0 * l[i] * l[i])
                    } else {
                        0.5 * mu * v * q * q * (1.0 / (l[m] * l[m]) + 1.0 / (l[n] * l[n])) / 3.0
                    }
                };
                let u = hourglass_field(&mesh, &[(al, i, q)]);
                let (_, strain, hourglass, _) = run(portable(), &mesh, &mat, &u);
                assert!(
                    (hourglass - expected).abs() <= 1e-12 * expected,
                    "{:?} mode {al} direction {i}: Ψ_hg {hourglass} vs {expected}",
                    mat.model
                );
                assert!(strain.abs() <= 1e-12 * expected, "strain energy {strain}");
            }
        }
    }
}

/// A box bent as a bar along x about y, its normal strain e = Q ζ/ℓ_x (u_x = Q ζξ) with the
/// anticlastic strain −ν e across it (u_y = −ν Q (ℓ_y/ℓ_x) ηζ): Ψ_hg is the bent bar's
/// ½ E V Q²/(3ℓ_x²), E and not E′, at ν = 0.45 and 0.4999 (a bending pair's coupling at work).
#[test]
fn a_bent_box_stores_the_bent_bars_energy() {
    let (l, mesh) = one_box();
    let v = 8.0 * l[0] * l[1] * l[2];
    let q = 1e-3;
    for mat in materials() {
        let nu = mat.poisson;
        let u = hourglass_field(&mesh, &[(2, 0, q), (1, 1, -nu * q * l[1] / l[0])]);
        let (_, _, hourglass, _) = run(portable(), &mesh, &mat, &u);
        let expected = 0.5 * mat.young * v * q * q / (3.0 * l[0] * l[0]);
        assert!(
            (hourglass - expected).abs() <= 1e-12 * expected,
            "ν = {nu}: Ψ_hg {hourglass} vs {expected}"
        );
    }
}

/// Under u = (R(I + A) − I) X (a strain, then a rotation of 60°) the hourglass forces vanish:
/// the forces are V P(F) bₐ, the hourglass energy is 0, and the interior nodes are in
/// equilibrium (the patch test), on distorted elements.
#[test]
fn an_affine_field_excites_no_hourglass_force() {
    let mesh = distorted_box();
    let classes = mesh.element_classes().unwrap();
    let a = [
        [0.08, 0.03, -0.02],
        [-0.04, -0.05, 0.06],
        [0.01, 0.07, 0.04],
    ];
    let r = rotation(std::f64::consts::FRAC_PI_3);
    let fm: [[f64; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            (0..3)
                .map(|k| r[i][k] * ((if k == j { 1.0 } else { 0.0 }) + a[k][j]))
                .sum()
        })
    });
    let u: Vec<[f64; 3]> = (mesh.nodes.iter())
        .map(|x| {
            let y = apply(&fm, *x);
            [y[0] - x[0], y[1] - x[1], y[2] - x[2]]
        })
        .collect();
    for mat in materials() {
        let (p, _) = mat.piola_energy(&nalgebra::Matrix3::from_fn(|i, j| fm[i][j]));
        let mut expected = vec![[0.0; 3]; mesh.nodes.len()];
        for (e, conn) in mesh.elements.iter().enumerate() {
            let cd = &classes.centre[classes.class_of[e] as usize];
            for a in 0..8 {
                for i in 0..3 {
                    expected[conn[a] as usize][i] +=
                        cd.volume * (0..3).map(|j| p[(i, j)] * cd.b[a][j]).sum::<f64>();
                }
            }
        }
        let scale = largest(&expected);
        for (name, build) in chunk_forces_physical_builds() {
            let (f, strain, hourglass, _) = run(build, &mesh, &mat, &u);
            for (x, y) in f.iter().flatten().zip(expected.iter().flatten()) {
                assert!((x - y).abs() <= 1e-10 * scale, "{name}: {x} vs V P b {y}");
            }
            assert!(
                hourglass.abs() <= 1e-12 * strain,
                "{name}: Ψ_hg {hourglass}"
            );
            let [nx, ny, nz] = [4usize, 4, 3];
            for k in 1..nz - 1 {
                for j in 1..ny - 1 {
                    for i in 1..nx - 1 {
                        let n = i + nx * (j + ny * k);
                        let residual = f[n].iter().fold(0.0f64, |m, v| m.max(v.abs()));
                        assert!(
                            residual <= 1e-10 * scale,
                            "{name}: node {n} force {residual}"
                        );
                    }
                }
            }
        }
    }
}

/// A rigid rotation of a deformed configuration, x → R x: the strain and hourglass energies do
/// not change and the forces rotate with it, fₐ → R fₐ (the hourglass energy is written in the
/// amplitudes pulled back by F⁻¹, which R leaves unchanged).
#[test]
fn a_rigid_rotation_leaves_the_energies_and_rotates_the_forces() {
    let mesh = distorted_box();
    let u = bent(&mesh);
    let r = rotation(1.1);
    let rotated: Vec<[f64; 3]> = (mesh.nodes.iter().zip(&u))
        .map(|(x, v)| {
            let y = apply(&r, [x[0] + v[0], x[1] + v[1], x[2] + v[2]]);
            [y[0] - x[0], y[1] - x[1], y[2] - x[2]]
        })
        .collect();
    for mat in compressible() {
        let (f, strain, hourglass, _) = run(portable(), &mesh, &mat, &u);
        let (g, strain_r, hourglass_r, _) = run(portable(), &mesh, &mat, &rotated);
        assert!(
            hourglass > 1e-3 * strain,
            "the field does not excite the hourglass modes: Ψ_hg {hourglass}, Ψ {strain}"
        );
        assert!(
            (strain_r - strain).abs() <= 1e-10 * strain,
            "{strain_r} vs {strain}"
        );
        assert!(
            (hourglass_r - hourglass).abs() <= 1e-10 * hourglass,
            "Ψ_hg {hourglass_r} vs {hourglass}"
        );
        let scale = largest(&f);
        for (fa, ga) in f.iter().zip(&g) {
            let rf = apply(&r, *fa);
            for i in 0..3 {
                assert!(
                    (rf[i] - ga[i]).abs() <= 1e-10 * scale,
                    "{:?}: R f {rf:?} vs {ga:?}",
                    mat.model
                );
            }
        }
    }
}

/// The forces are the gradient of V ψ(F) + Ψ_hg: each nodal component against the central
/// difference of the energies the kernel returns, under a field that bends the elements.
#[test]
fn forces_are_the_gradient_of_the_energy() {
    let mesh = distorted_box();
    let u = bent(&mesh);
    let delta = 1e-6 * 0.1;
    for mat in compressible() {
        let (f, strain, hourglass, j) = run(portable(), &mesh, &mat, &u);
        assert!(
            j > 0.5 && j < 0.95,
            "min J {j}: the field is not the one meant"
        );
        assert!(
            hourglass > 1e-3 * strain,
            "the field does not excite the hourglass modes: Ψ_hg {hourglass}, Ψ {strain}"
        );
        assert_gradient(&u, &f, delta, |v| {
            let (_, e, hg, _) = run(portable(), &mesh, &mat, v);
            e + hg
        });
    }
}

/// Every build gives the portable build's forces and energies to round-off (the builds differ
/// only in fused multiply–adds), and AVX2 and AVX-512 the same bits.
#[test]
fn every_build_matches_portable() {
    let mesh = distorted_box();
    let u = bent(&mesh);
    for mat in materials() {
        let builds: Vec<_> = (chunk_forces_physical_builds().into_iter())
            .map(|(name, b)| (name, run(b, &mesh, &mat, &u)))
            .collect();
        let (pf, pe, ph, pj) = &builds[0].1;
        let scale = largest(pf);
        for (name, (f, e, h, j)) in &builds {
            for (a, b) in f.iter().flatten().zip(pf.iter().flatten()) {
                assert!(
                    (a - b).abs() <= 1e-12 * scale,
                    "{name}: {a} vs portable {b}"
                );
            }
            assert!((e - pe).abs() <= 1e-12 * pe.abs(), "{name}: strain energy");
            assert!(
                (h - ph).abs() <= 1e-12 * ph.abs(),
                "{name}: hourglass energy"
            );
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
