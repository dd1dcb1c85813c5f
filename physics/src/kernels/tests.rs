//! Every build of every kernel against the portable build (model §1.5, §1.6, §4.5): the
//! full-integration
//! and one-point element chunks and the free-velocity node loop, on a box whose elements are
//! partly distorted (many element classes, lanes changing class between groups) under a large
//! non-affine displacement, one element of it then inverted.
//!
//! Tolerances: the builds differ only in fused multiply–adds (one rounding instead of two per
//! a·b + c), so forces and energies agree to round-off, 1e-12 of the largest nodal force or of
//! the energy (a sum of ~100 terms loses ≲ 100 ε ≈ 2e-14 relative; a wrong lane, node or
//! element is an O(1) error). Where the arithmetic is the same, the results must be the same
//! bits: the AVX2 and AVX-512 builds (both fused; they differ only in vector width, in the node
//! loads and, on AVX2, in forming the one-point H and hourglass modes 4 lanes at a time),
//! the portable chunk and its element kernel summed in chunk order, and every build of the
//! free-velocity loop (no fused operation).

mod bitwise;

use super::nodes::free_velocity_chunk_builds;
use super::*;
use crate::material::MaterialModel;
use crate::mesh::rows::is_row;
use nalgebra::Matrix3;

/// What a chunk returns: strain energy, hourglass energy, min J, its element.
type Sums = (f64, f64, f64, usize);

/// A build's name and what it assembled: the forces and the [`Sums`].
type Build<'a> = (&'a str, (Vec<[f64; 3]>, Sums));

/// The lane forces of a group of 8 elements, `fl[a][j][l]`.
type Fl = [[[f64; 8]; 3]; 8];

/// A build of [`scatter_group`].
type ScatterBuild = unsafe fn(PlanesPtr, &[[u32; 8]], &[u32], bool, &Fl);

/// The test box: 8×8×6 elements, every 11th node moved off the grid.
fn distorted_box() -> Mesh {
    let mut mesh = Mesh::boxed([0.0; 3], [1.0, 0.8, 0.6], [8, 8, 6]);
    for (i, x) in mesh.nodes.iter_mut().enumerate() {
        if i % 11 == 0 {
            let t = i as f64;
            x[0] += 0.02 * (1.7 * t).sin();
            x[1] += 0.02 * (2.3 * t).cos();
            x[2] += 0.015 * (0.9 * t).sin();
        }
    }
    mesh
}

/// A large non-affine displacement (strains of ~10 %, J in 0.8…1.2).
fn bent(mesh: &Mesh) -> Vec<[f64; 3]> {
    mesh.nodes
        .iter()
        .map(|x| {
            [
                0.1 * x[1] * x[2],
                -0.05 * x[0] * x[0],
                0.08 * (3.0 * x[0]).sin(),
            ]
        })
        .collect()
}

/// The element in the middle of the box and `bent` with its last node pushed through its first:
/// that element is inverted (its neighbours through the node may be too).
fn inverted(mesh: &Mesh, u: &[[f64; 3]]) -> (usize, u32, Vec<[f64; 3]>) {
    let e = mesh.elements.len() / 2 + 3;
    let conn = mesh.elements[e];
    let (from, to) = (mesh.nodes[conn[6] as usize], mesh.nodes[conn[0] as usize]);
    let mut u = u.to_vec();
    u[conn[6] as usize] = std::array::from_fn(|c| 1.5 * (to[c] - from[c]));
    (e, conn[6], u)
}

/// J = det(I + Σₐ uₐ ⊗ gₐ) by nalgebra, `g(a, j)` = ∂Nₐ/∂Xⱼ at the point.
fn jacobian(u: &[[f64; 3]], conn: &[u32; 8], g: impl Fn(usize, usize) -> f64) -> f64 {
    let mut f = Matrix3::identity();
    for a in 0..8 {
        for i in 0..3 {
            for j in 0..3 {
                f[(i, j)] += u[conn[a] as usize][i] * g(a, j);
            }
        }
    }
    f.determinant()
}

/// The smallest Jacobian of element `e` at its 8 corners, det(∂x/∂ξ)/det(∂X/∂ξ) from the
/// shape-function derivatives at each corner (independent of the edge form of `corners`).
fn min_corner_jacobian_iso(mesh: &Mesh, u: &[[f64; 3]], e: usize) -> f64 {
    let x = mesh.element_coords(e);
    let conn = mesh.elements[e];
    let det = |p: &dyn Fn(usize, usize) -> f64, xi: [f64; 3]| {
        let dn = crate::mesh::shape_derivatives(xi);
        Matrix3::from_fn(|r, c| (0..8).map(|a| p(a, r) * dn[a][c]).sum::<f64>()).determinant()
    };
    crate::mesh::HEX_CORNERS
        .iter()
        .map(|&xi| det(&|a, r| x[a][r] + u[conn[a] as usize][r], xi) / det(&|a, r| x[a][r], xi))
        .fold(f64::INFINITY, f64::min)
}

/// The smallest J of a chunk and its element, from `j_of(element)` (the smallest J of each),
/// asserting that no other element of the chunk is within 1e-9 of it (so the element reported
/// is not decided by round-off).
fn min_j_of(chunk: &[u32], j_of: impl Fn(usize) -> f64) -> (f64, usize) {
    let mut js: Vec<(f64, usize)> = chunk
        .iter()
        .map(|&e| (j_of(e as usize), e as usize))
        .collect();
    js.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert!(js.len() < 2 || js[1].0 - js[0].0 > 1e-9, "tie for min J");
    js[0]
}

/// Runs one chunk into a zeroed force array.
fn run_chunk(n_nodes: usize, run: impl FnOnce(PlanesPtr) -> Sums) -> (Vec<[f64; 3]>, Sums) {
    let mut f = Planes::zeros(n_nodes);
    let out = run(f.ptr());
    (f.to_rows(), out)
}

/// The scalar full-integration kernel (fused when `fma`) element by element in chunk order,
/// with the Gauss data `gauss(e)` of element e: the forces and the strain energy.
fn scalar_full_chunk<'a>(
    mesh: &Mesh,
    mat: &Material,
    gauss: impl Fn(u32) -> &'a GaussData,
    fma: bool,
    u: &[[f64; 3]],
    chunk: &[u32],
) -> (Vec<[f64; 3]>, f64) {
    let (f, (strain, ..)) = run_chunk(mesh.nodes.len(), |p| {
        let mut strain = 0.0;
        for &e in chunk {
            let conn = mesh.elements[e as usize];
            let (gd, ue) = (gauss(e), conn.map(|a| u[a as usize]));
            let mut fe = [[0.0; 3]; 8];
            strain += if fma {
                element_forces::<true, true>(mat, gd, &ue, &mut fe).0
            } else {
                element_forces::<true, false>(mat, gd, &ue, &mut fe).0
            };
            // SAFETY: one thread; `p` is the array of `run_chunk`, one row per node.
            unsafe { scatter(p, &conn, &fe) };
        }
        (strain, 0.0, 0.0, 0)
    });
    (f, strain)
}

/// The scalar one-point kernel element by element in chunk order, scattered into `p`, with the
/// one-point data `centre(e)` of element e: (strain energy, hourglass energy).
fn scalar_one_point_chunk<'a>(
    mesh: &Mesh,
    mat: &Material,
    centre: impl Fn(u32) -> &'a CentreData,
    kappa: f64,
    u: &[[f64; 3]],
    chunk: &[u32],
    p: PlanesPtr,
) -> (f64, f64) {
    let (mut strain, mut hg) = (0.0, 0.0);
    for &e in chunk {
        let conn = mesh.elements[e as usize];
        let cd = centre(e);
        let k = hourglass_stiffness(mat, cd, kappa);
        let mut fe = [[0.0; 3]; 8];
        let out = element_forces_reduced::<true>(mat, cd, k, &conn.map(|a| u[a as usize]), &mut fe);
        (strain, hg) = (strain + out.0, hg + out.1);
        // SAFETY: one thread; `p` is the caller's array, one row per node.
        unsafe { scatter(p, &conn, &fe) };
    }
    (strain, hg)
}

/// `a` and `b` agree to `tol` (or are both NaN: the forces and energy of an inverted
/// neo-Hookean element, ln J < 0's NaN, spread the same way in every build).
fn close(a: f64, b: f64, tol: f64) -> bool {
    (a.is_nan() && b.is_nan()) || (a - b).abs() <= tol
}

/// Every build of a chunk against the portable one (`builds[0]`): forces and energies to
/// round-off, min J and its element exactly as `expect_min` says (J to 1e-13: a determinant of
/// entries O(1) off by a few ulps), and AVX2 and AVX-512 bit-identical.
fn check_builds(what: &str, builds: &[Build], expect_min: (f64, usize)) {
    let (portable_f, portable) = &builds[0].1;
    let scale = portable_f
        .iter()
        .flatten()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    for (name, (f, sums)) in builds {
        for (k, (a, b)) in f.iter().zip(portable_f).enumerate() {
            for c in 0..3 {
                assert!(
                    close(a[c], b[c], 1e-12 * scale),
                    "{what} {name}: node {k} component {c}: {} vs portable {}",
                    a[c],
                    b[c]
                );
            }
        }
        assert!(
            close(sums.0, portable.0, 1e-12 * portable.0.abs()),
            "{what} {name}: strain"
        );
        assert!(
            close(sums.1, portable.1, 1e-12 * portable.1.abs()),
            "{what} {name}: hourglass"
        );
        assert!(
            (sums.2 - expect_min.0).abs() <= 1e-13 && sums.3 == expect_min.1,
            "{what} {name}: min J {} at element {}, expected {} at {}",
            sums.2,
            sums.3,
            expect_min.0,
            expect_min.1
        );
    }
    let bits = |f: &[[f64; 3]], s: &Sums| {
        let mut b: Vec<u64> = f.iter().flatten().map(|v| v.to_bits()).collect();
        b.extend([s.0.to_bits(), s.1.to_bits(), s.2.to_bits(), s.3 as u64]);
        b
    };
    let by_name = |n: &str| {
        builds
            .iter()
            .find(|b| b.0 == n)
            .map(|b| bits(&b.1 .0, &b.1 .1))
    };
    if let (Some(avx2), Some(avx512)) = (by_name("avx2"), by_name("avx512")) {
        assert!(avx2 == avx512, "{what}: the AVX2 and AVX-512 builds differ");
    }
}

/// The displacement fields of the tests: bent, then bent with one element inverted.
fn fields(mesh: &Mesh) -> [(&'static str, Vec<[f64; 3]>); 2] {
    let u = bent(mesh);
    let (_, _, inv) = inverted(mesh, &u);
    [("bent", u), ("inverted", inv)]
}

/// Full integration: on every block of the box, and on a chunk that holds the inverted element,
/// every build gives the portable forces, energies, min J and element; each build is its
/// element kernel ([`element_forces`], fused like the build) summed in chunk order, bit for
/// bit — the lane kernel of groups of 8 elements as much as the scalar remainder, and the web
/// page's lanes without fused multiply–adds (`ISA_SIMD128`) the portable build's bits; min J is
/// that of nalgebra at the Gauss points. Run on the distorted box (groups of several classes,
/// staged lane by lane) and on a regular one (groups of one class, broadcast).
#[test]
fn full_chunk_every_build_matches_portable_and_scalar_kernel() {
    for mesh in [
        distorted_box(),
        Mesh::boxed([0.0; 3], [1.0, 0.8, 0.6], [8, 8, 6]),
    ] {
        let classes = mesh.element_classes().unwrap();
        let (bad, _, _) = inverted(&mesh, &bent(&mesh));
        let mut chunks: Vec<Vec<u32>> = mesh.element_blocks(64).into_iter().flatten().collect();
        // 12 elements: one group of 8 and a remainder of 4, the inverted element in each.
        chunks.push((bad as u32 - 5..bad as u32 + 7).collect());
        chunks.push((bad as u32 - 9..bad as u32 + 3).collect());
        for model in [MaterialModel::Svk, MaterialModel::NeoHookean] {
            let mat = Material::new(model, 5e6, 0.45, 1100.0);
            for (field, u) in fields(&mesh) {
                for chunk in &chunks {
                    full_chunk_builds(&mesh, &classes, &mat, &u, chunk, field);
                }
            }
        }
    }
}

/// One chunk of [`full_chunk_every_build_matches_portable_and_scalar_kernel`].
fn full_chunk_builds(
    mesh: &Mesh,
    classes: &ElementClasses,
    mat: &Material,
    u: &[[f64; 3]],
    chunk: &[u32],
    field: &str,
) {
    let n = mesh.nodes.len();
    // Besides the builds this CPU runs, the web page's (`ISA_SIMD128`: 8 elements in lanes
    // without fused multiply–adds), compiled here for the host.
    type FullBuild = unsafe fn(
        &Mesh,
        &ElementClasses,
        &Material,
        [&[f64]; 3],
        PlanesPtr,
        &[u32],
        bool,
        bool,
    ) -> (f64, f64, usize);
    let mut all: Vec<(&str, FullBuild)> = chunk_forces_builds();
    all.push((
        "simd128",
        chunk_forces_impl::<false, { simd::ISA_SIMD128 }, true>,
    ));
    let builds: Vec<_> = all
        .into_iter()
        .map(|(name, build)| {
            let out = run_chunk(n, |p| {
                let (e, j, el) = unsafe {
                    build(
                        mesh,
                        classes,
                        mat,
                        Planes::from_rows(u).planes(),
                        p,
                        chunk,
                        true,
                        true,
                    )
                };
                (e, 0.0, j, el)
            });
            (name, out)
        })
        .collect();
    let expect_min = min_j_of(chunk, |e| {
        let gd = &classes.data[classes.class_of[e] as usize];
        (0..8)
            .map(|q| jacobian(u, &mesh.elements[e], |a, j| gd.grad[a][j][q]))
            .fold(f64::INFINITY, f64::min)
    });
    let what = format!("{:?} {field} full", mat.model);
    check_builds(&what, &builds, expect_min);
    // Each build is element_forces::<_, FMA> scattered in chunk order (`mul_add` is the
    // correctly rounded fused operation on every CPU, so the test's own build of the scalar
    // kernel gives the vector builds' bits).
    for (name, (f, sums)) in &builds {
        let gauss = |e: u32| &classes.data[classes.class_of[e as usize] as usize];
        let (reference, strain) =
            scalar_full_chunk(mesh, mat, gauss, name.starts_with("avx"), u, chunk);
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
        assert!(
            f.iter()
                .flatten()
                .zip(reference.iter().flatten())
                .all(|(a, b)| same(*a, *b))
                && same(sums.0, strain),
            "{what} {name}: the chunk ≠ its element kernel"
        );
    }
}

/// An axis-aligned box (one class, J₀ diagonal and the same at every point): every build's lane
/// and scalar kernels, which then form H and the forces through the modes of the trilinear field
/// ((T4) of `element::hex8::tensor` and its transpose, [`GaussData::axis_aligned`]), give the general
/// kernel's results (the class data with the flag cleared), scattered in chunk order: the
/// forces to 1e-13 of the largest nodal force and the strain energy to 1e-13 (round-off of sums
/// of ~10 terms in another order: measured 3e-16; a misplaced mode amplitude gives 3e-4 and
/// more, checked).
#[test]
fn axis_aligned_kernels_give_the_row_products_values() {
    let mesh = Mesh::boxed([10.0, -3.0, 0.5], [1.0, 0.8, 0.6], [8, 8, 6]);
    let classes = mesh.element_classes().unwrap();
    assert!(classes.data.len() == 1 && classes.data[0].axis_aligned);
    let mut general = classes.data[0].clone();
    general.axis_aligned = false;
    let chunk: Vec<u32> = (0..21).collect();
    let n = mesh.nodes.len();
    for model in [MaterialModel::Svk, MaterialModel::NeoHookean] {
        let mat = Material::new(model, 5e6, 0.45, 1100.0);
        let u = bent(&mesh);
        for (name, build) in chunk_forces_builds() {
            let (f, sums) = run_chunk(n, |p| {
                let (e, j, el) = unsafe {
                    build(
                        &mesh,
                        &classes,
                        &mat,
                        Planes::from_rows(&u).planes(),
                        p,
                        &chunk,
                        true,
                        true,
                    )
                };
                (e, 0.0, j, el)
            });
            let (reference, strain) =
                scalar_full_chunk(&mesh, &mat, |_| &general, name != "portable", &u, &chunk);
            let touched = reference.iter().flatten().filter(|v| **v != 0.0).count();
            assert!(touched > 100, "{model:?} {name}: {touched} force entries");
            let largest = reference
                .iter()
                .flatten()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            let worst = f
                .iter()
                .flatten()
                .zip(reference.iter().flatten())
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                worst <= 1e-13 * largest && (sums.0 - strain).abs() <= 1e-13 * strain,
                "{model:?} {name}: the axis-aligned kernel ≠ the row products ({worst:e} of {largest:e}; energy {} against {strain})",
                sums.0
            );
        }
    }
}

/// One point on an axis-aligned box (one class, `CentreData::axis_aligned`): every build's lane
/// kernel and the scalar kernel, which go through the modes of the trilinear field
/// (`element::hex8::tensor`, (T3)), give the forces and energies of the general kernel (the class
/// data with the flag cleared, bₐ and γᵅ as stored) under a large non-affine displacement, which
/// excites all four hourglass modes. They sum in another order: to 1e-12 of the largest nodal
/// force and of each energy (round-off of sums of ~10 terms; a wrong mode, sign or node is an
/// O(1) error).
#[test]
fn box_one_point_kernels_give_the_general_kernels_values() {
    let mesh = Mesh::boxed([10.0, -3.0, 0.5], [1.0, 0.8, 0.6], [8, 8, 6]);
    let classes = mesh.element_classes().unwrap();
    assert!(classes.centre.len() == 1 && classes.centre[0].axis_aligned);
    let mut general = classes.centre[0].clone();
    general.axis_aligned = false;
    let chunk: Vec<u32> = (0..21).collect();
    let n = mesh.nodes.len();
    let kappa = 0.05;
    for model in [MaterialModel::Svk, MaterialModel::NeoHookean] {
        let mat = Material::new(model, 5e6, 0.45, 1100.0);
        let u = bent(&mesh);
        let reference = run_chunk(n, |p| {
            let (strain, hg) =
                scalar_one_point_chunk(&mesh, &mat, |_| &general, kappa, &u, &chunk, p);
            (strain, hg, 0.0, 0)
        });
        let (ref_f, (ref_strain, ref_hg, ..)) = &reference;
        assert!(
            *ref_hg > 1e-6 * ref_strain,
            "{model:?}: hourglass modes not excited"
        );
        let scale = ref_f.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut runs: Vec<Build> = chunk_forces_reduced_builds()
            .into_iter()
            .map(|(name, build)| {
                let out = run_chunk(n, |p| {
                    let r = unsafe {
                        let up = Planes::from_rows(&u);
                        build(
                            &mesh,
                            &classes,
                            &mat,
                            kappa,
                            up.planes(),
                            p,
                            &chunk,
                            true,
                            0.0,
                            true,
                        )
                    };
                    (r.strain, r.hourglass, r.min_j, r.min_element)
                });
                (name, out)
            })
            .collect();
        runs.push((
            "scalar kernel",
            run_chunk(n, |p| {
                let box_data = |_| &classes.centre[0];
                let (strain, hg) =
                    scalar_one_point_chunk(&mesh, &mat, box_data, kappa, &u, &chunk, p);
                (strain, hg, 0.0, 0)
            }),
        ));
        for (name, (f, (strain, hg, ..))) in &runs {
            let worst = f
                .iter()
                .flatten()
                .zip(ref_f.iter().flatten())
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                worst <= 1e-12 * scale
                    && (strain - ref_strain).abs() <= 1e-12 * ref_strain
                    && (hg - ref_hg).abs() <= 1e-12 * ref_hg,
                "{model:?} {name}: force off by {worst:e} of {scale:e}, energies {strain} {hg} \
                 against {ref_strain} {ref_hg}"
            );
        }
    }
}

/// One point: groups of 8 elements go through the lane kernel, the rest through the scalar
/// one. On every block of the box, and on two chunks where the inverted element falls in a
/// lane group and in the remainder: every build gives the forces and energies of the scalar
/// kernel element by element and of the portable build (round-off), min J of nalgebra at the
/// centre and its element.
#[test]
fn one_point_chunk_every_build_matches_portable_and_scalar_kernel() {
    let mesh = distorted_box();
    let classes = mesh.element_classes().unwrap();
    assert!(classes.centre.len() > 8, "the test needs several classes");
    let n = mesh.nodes.len();
    let kappa = 0.05;
    let (bad, node, _) = inverted(&mesh, &bent(&mesh));
    let bad = bad as u32;
    let mut chunks: Vec<Vec<u32>> = mesh.element_blocks(64).into_iter().flatten().collect();
    // 21 elements: lanes 0..16, remainder 16..21; the inverted element at 3, then at 18.
    chunks.push((bad - 3..bad + 18).collect());
    chunks.push((bad - 18..bad + 3).collect());
    for model in [MaterialModel::Svk, MaterialModel::NeoHookean] {
        let mat = Material::new(model, 5e6, 0.45, 1100.0);
        for (field, u) in fields(&mesh) {
            for chunk in &chunks {
                // The centre's J alone (what the step control reads, Assembly::min_stress_j).
                let centre_j = |e: usize| {
                    let cd = &classes.centre[classes.class_of[e] as usize];
                    jacobian(&u, &mesh.elements[e], |a, j| cd.b[a][j])
                };
                let centre_min = chunk
                    .iter()
                    .map(|&e| centre_j(e as usize))
                    .fold(f64::INFINITY, f64::min);
                let mut builds: Vec<_> = chunk_forces_reduced_builds()
                    .into_iter()
                    .map(|(name, build)| {
                        let out = run_chunk(n, |p| {
                            let r = unsafe {
                                build(
                                    &mesh,
                                    &classes,
                                    &mat,
                                    kappa,
                                    Planes::from_rows(&u).planes(),
                                    p,
                                    chunk,
                                    true,
                                    f64::INFINITY,
                                    true,
                                )
                            };
                            assert_eq!(r.skipped, 0, "exact_below = ∞ checks every corner");
                            // Round-off of two evaluations of one determinant of |F| ~ 1.
                            let tol = 1e-12 * centre_min.abs().max(1.0);
                            assert!(
                                (r.min_stress_j - centre_min).abs() <= tol
                                    && (centre_j(r.min_stress_element) - centre_min).abs() <= tol,
                                "{name}: centre J {} (element {}) against {centre_min}",
                                r.min_stress_j,
                                r.min_stress_element
                            );
                            (r.strain, r.hourglass, r.min_j, r.min_element)
                        });
                        (name, out)
                    })
                    .collect();
                // One point: the centre's J and the corners' (by the isoparametric map).
                let expect_min = min_j_of(chunk, |e| {
                    let cd = &classes.centre[classes.class_of[e] as usize];
                    let centre = jacobian(&u, &mesh.elements[e], |a, j| cd.b[a][j]);
                    centre.min(min_corner_jacobian_iso(&mesh, &u, e))
                });
                let what = format!("{model:?} {field} one point");
                if field == "inverted" && chunk.contains(&bad) {
                    assert!(expect_min.0 < 0.0 && mesh.elements[expect_min.1].contains(&node));
                }
                check_builds(&what, &builds, expect_min);
                // The scalar kernel element by element, in chunk order, as a further "build".
                let scalar = run_chunk(n, |p| {
                    let centre = |e: u32| &classes.centre[classes.class_of[e as usize] as usize];
                    let (strain, hg) =
                        scalar_one_point_chunk(&mesh, &mat, centre, kappa, &u, chunk, p);
                    (strain, hg, expect_min.0, expect_min.1)
                });
                builds.push(("scalar kernel", scalar));
                check_builds(&what, &builds, expect_min);
            }
        }
    }
}
