//! Every build of the node loop, the row scatter and the one-point corner check against the
//! portable or element-by-element path, bit for bit (no fused operation differs between them),
//! on the test box of the parent module; and the cache-size parser.

use super::*;

/// The free-velocity loop (stage 5) has no fused operation: every build gives the portable
/// velocities and ledger sums bit for bit, on a node count that is not a multiple of 8.
#[test]
fn free_velocity_every_build_is_bit_identical() {
    let n = 1003;
    let t = |i: usize, k: f64| (i as f64 * k).sin();
    let v0: Vec<[f64; 3]> = (0..n)
        .map(|i| [t(i, 0.7), 0.3 * t(i, 1.1), -2.0 * t(i, 0.2)])
        .collect();
    let f: Vec<[f64; 3]> = (0..n)
        .map(|i| [1e3 * t(i, 0.5), -2e3 * t(i, 1.9), 5e2 * t(i, 2.9)])
        .collect();
    let m: Vec<f64> = (0..n).map(|i| 0.1 + 0.05 * t(i, 0.13).abs()).collect();
    let im: Vec<f64> = m.iter().map(|m| 1.0 / m).collect();
    let runs: Vec<_> = free_velocity_chunk_builds()
        .into_iter()
        .map(|(name, build)| {
            let mut vp = Planes::from_rows(&v0);
            let fp = Planes::from_rows(&f);
            let g = [0.0, 0.0, -9.81];
            let sums = unsafe { build(vp.planes_mut(), fp.planes(), &m, &im, 1e-5, g) };
            (name, vp.to_rows(), sums)
        })
        .collect();
    let bits = |v: &[[f64; 3]], s: &NodeSums| {
        let mut b: Vec<u64> = v.iter().flatten().map(|x| x.to_bits()).collect();
        b.extend(
            [
                s.kinetic,
                s.kinetic_half,
                s.int_b,
                s.int_a,
                s.grav_b,
                s.grav_a,
            ]
            .map(f64::to_bits),
        );
        b
    };
    let portable = bits(&runs[0].1, &runs[0].2);
    assert!(runs[0].1 != v0, "the loop moved nothing");
    for (name, v, sums) in &runs {
        assert!(
            bits(v, sums) == portable,
            "{name} differs from the portable build"
        );
    }
}

/// The corner check skipped by the bound ([`corner_bound`]): on every block of the distorted box
/// and both fields, for thresholds `exact_below` around the field's J (0.8…1.1, and the chunk's
/// exact minimum itself) and the step's (the smallest positive f64, `CORNER_EXACT_BELOW`),
/// every build gives the same force and energy bits as with every corner checked
/// (`exact_below` = ∞); the smallest J and its element are those of the full check when that J
/// is below the threshold, else the reported J lies in [threshold, exact J]. The bound must
/// fire on some groups (else this tests nothing) and not on others, at 0.9 and at the step's
/// threshold (the inverted field's corners, J ≤ 0, are checked exactly).
#[test]
fn one_point_skipped_corner_check_changes_nothing_below_the_threshold() {
    let mesh = distorted_box();
    let classes = mesh.element_classes().unwrap();
    let n = mesh.nodes.len();
    let kappa = 0.05;
    let chunks: Vec<Vec<u32>> = mesh.element_blocks(64).into_iter().flatten().collect();
    let (mut skipped, mut groups, mut skipped_step) = (0u64, 0u64, 0u64);
    let step = CORNER_EXACT_BELOW;
    let mat = Material::new(MaterialModel::NeoHookean, 5e6, 0.45, 1100.0);
    // The two fields of the other tests (strong hourglassing: the bound stays below 0.9) and
    // `bent` at 2 % (J within 0.5 % of 1, small hourglass amplitudes: the bound skips).
    let [bent_u, inverted_u] = fields(&mesh);
    let gentle: Vec<[f64; 3]> = bent_u.1.iter().map(|r| r.map(|v| 0.02 * v)).collect();
    for (field, u) in [bent_u, inverted_u, ("gentle", gentle)] {
        for chunk in &chunks {
            for (name, build) in chunk_forces_reduced_builds() {
                let run = |t: f64| {
                    let mut f = Planes::zeros(n);
                    let r = unsafe {
                        build(
                            &mesh,
                            &classes,
                            &mat,
                            kappa,
                            Planes::from_rows(&u).planes(),
                            f.ptr(),
                            chunk,
                            true,
                            t,
                            true,
                        )
                    };
                    (f.to_rows(), r)
                };
                let (f_all, all) = run(f64::INFINITY);
                for t in [0.8, 0.9, 1.0, 1.1, all.min_j, step, f64::NEG_INFINITY] {
                    let (f, r) = run(t);
                    let what = format!("{field} {name} exact_below {t}");
                    let bits = |f: &[[f64; 3]]| -> Vec<u64> {
                        f.iter().flatten().map(|v| v.to_bits()).collect()
                    };
                    assert!(bits(&f) == bits(&f_all), "{what}: forces differ");
                    assert!(
                        r.strain.to_bits() == all.strain.to_bits()
                            && r.hourglass.to_bits() == all.hourglass.to_bits(),
                        "{what}: energies differ"
                    );
                    if all.min_j < t {
                        assert!(
                            r.min_j.to_bits() == all.min_j.to_bits()
                                && r.min_element == all.min_element,
                            "{what}: min J {} at {} instead of {} at {}",
                            r.min_j,
                            r.min_element,
                            all.min_j,
                            all.min_element
                        );
                    } else {
                        assert!(
                            r.min_j >= t && r.min_j <= all.min_j,
                            "{what}: min J {} outside [{t}, {}]",
                            r.min_j,
                            all.min_j
                        );
                    }
                    if t == 0.9 {
                        skipped += r.skipped as u64;
                        groups += chunk.len() as u64 / 8;
                    }
                    if t == step {
                        skipped_step += r.skipped as u64;
                    }
                    if t == f64::NEG_INFINITY {
                        assert_eq!(r.skipped as usize, chunk.len() / 8, "{what}");
                    }
                }
            }
        }
    }
    assert!(
        skipped > 0 && skipped < groups,
        "the bound skipped {skipped} of {groups} groups at J = 0.9"
    );
    assert!(
        skipped_step > skipped && skipped_step < groups,
        "the bound skipped {skipped_step} of {groups} groups at the step's threshold {step:e} \
         ({skipped} at 0.9)"
    );
}

/// The row scatter ([`scatter_group`] on a row along x) adds the same bits as the element by
/// element scatter ([`scatter_lane`], l = 0…7): each shared node takes (F + f_{m−1}[a₁]) +
/// f_m[a₀] in both. Checked on every group of 8 consecutive elements of a 28 × 3 × 2 box
/// (rows of 28: 6 groups in 7 are rows, the 7th straddles two rows and must not be taken for
/// one), with forces and a starting F of mixed signs and magnitudes (so that a different order
/// of the sums would change bits), and on a numbering that has the lanes' pattern but whose
/// lines overlap (node a₃ of the first element 5 after its a₀), which must not be a row. On
/// each row, the row gather ([`gather_group`], from the first element alone) stages the same
/// lanes as the element-by-element one. Every build's line adds ([`add_line`]) are checked,
/// starting from random F and from +0 (as the element loop does).
#[test]
fn the_row_scatter_adds_the_same_bits_as_the_element_by_element_scatter() {
    let mesh = Mesh::boxed([0.0; 3], [2.8, 0.3, 0.2], [28, 3, 2]);
    let n = mesh.nodes.len();
    let mut state = 0x9e3779b97f4a7c15u64;
    let mut random = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        // Magnitudes over 12 decades and both signs.
        let m = (state >> 11) as f64 / (1u64 << 53) as f64;
        (if state & 1 == 0 { 1.0 } else { -1.0 }) * 10f64.powf(12.0 * m - 6.0)
    };
    let f_start: Vec<[f64; 3]> = (0..n).map(|_| [random(), random(), random()]).collect();
    let mut rows = 0;
    let elements: Vec<u32> = (0..mesh.elements.len() as u32).collect();
    for (k, group) in elements.chunks_exact(8).enumerate() {
        let fl: [[[f64; 8]; 3]; 8] =
            std::array::from_fn(|_| std::array::from_fn(|_| std::array::from_fn(|_| random())));
        let row = unsafe { is_row(&mesh.elements, group) };
        let straddles = group[0] / 28 != group[7] / 28;
        assert_eq!(row, !straddles, "group {k}: {group:?}");
        rows += row as usize;
        // F as the element loop starts it (+0) in every other group.
        let start = if k % 2 == 0 {
            f_start.clone()
        } else {
            vec![[0.0; 3]; n]
        };
        let mut by_lane = Planes::from_rows(&start);
        for (l, &e) in group.iter().enumerate() {
            unsafe { scatter_lane(by_lane.ptr(), &mesh.elements[e as usize], &fl, l) };
        }
        // Every build's line adds (the vector ones move f₁ up a lane, with a 0 in lane 0).
        let mut builds: Vec<(&str, ScatterBuild)> =
            vec![("portable", scatter_group::<ISA_PORTABLE>)];
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx2") {
                builds.push(("avx2", scatter_group::<ISA_AVX2>));
            }
            if std::is_x86_feature_detected!("avx512f") {
                builds.push(("avx512", scatter_group::<ISA_AVX512>));
            }
        }
        for (name, scatter_build) in builds {
            let mut by_group = Planes::from_rows(&start);
            unsafe { scatter_build(by_group.ptr(), &mesh.elements, group, row, &fl) };
            let bits = |p: &Planes| p.as_slice().iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert!(
                bits(&by_group) == bits(&by_lane),
                "{name}, group {k}: the row scatter's bits differ"
            );
        }
        // The row gather (each lane vector one load from a plane, from the first element's
        // nodes alone) stages the same lanes as the element-by-element gather.
        if row {
            let u = Planes::from_rows(
                &(0..n)
                    .map(|_| [random(), random(), random()])
                    .collect::<Vec<_>>(),
            );
            let (mut by_row, mut by_conn) = ([[[0.0; 8]; 3]; 8], [[[1.0; 8]; 3]; 8]);
            unsafe {
                gather_group(&mesh, u.planes(), group, true, &mut by_row);
                gather_group(&mesh, u.planes(), group, false, &mut by_conn);
            }
            assert_eq!(
                by_row.map(|a| a.map(|j| j.map(f64::to_bits))),
                by_conn.map(|a| a.map(|j| j.map(f64::to_bits))),
                "group {k}"
            );
        }
    }
    assert_eq!(rows, 18, "21 groups, 3 of them across two rows");
    // The flags computed once per mesh give `is_row` on every group of 8 consecutive elements,
    // aligned or not, and on none that is not consecutive.
    let classes = mesh.element_classes().unwrap();
    let m = mesh.elements.len();
    for e in 0..m - 7 {
        let group: Vec<u32> = (e as u32..e as u32 + 8).collect();
        let expect = unsafe { is_row(&mesh.elements, &group) };
        assert_eq!(
            unsafe { group_is_row(&classes.row_start, &group) },
            expect,
            "from {e}"
        );
        rows -= (expect && e % 8 == 0) as usize;
        let mut shuffled = group.clone();
        shuffled.swap(3, 4);
        assert!(
            !unsafe { group_is_row(&classes.row_start, &shuffled) },
            "{shuffled:?}"
        );
    }
    assert_eq!(rows, 0, "the same 18 aligned rows");
    assert!(classes.row_start[m - 7..].iter().all(|&r| !r));
    // Lines 0–1 and 3–2 overlapping: element l's nodes are the first's + l, yet not a row.
    let first = [0u32, 1, 6, 5, 20, 21, 26, 25];
    let overlapping: Vec<[u32; 8]> = (0..8u32).map(|l| first.map(|a| a + l)).collect();
    let group: Vec<u32> = (0..8).collect();
    assert!(!unsafe { is_row(&overlapping, &group) });
    assert!(!row_starts(&overlapping)[0]);
    let apart = [0u32, 1, 11, 10, 20, 21, 31, 30];
    let lines: Vec<[u32; 8]> = (0..8u32).map(|l| apart.map(|a| a + l)).collect();
    assert!(unsafe { is_row(&lines, &group) }, "lines 10 nodes apart");
    assert_eq!(
        row_starts(&lines),
        [true, false, false, false, false, false, false, false]
    );
}

/// Cache sizes as Linux's sysfs writes them, and what is not one.
#[test]
fn cache_sizes_parse_from_sysfs_text() {
    use super::cache_size_bytes;
    assert_eq!(cache_size_bytes("32768K\n"), Some(32 << 20));
    assert_eq!(cache_size_bytes("1M"), Some(1 << 20));
    assert_eq!(cache_size_bytes("512"), Some(512));
    assert_eq!(cache_size_bytes("2G"), Some(2 << 30));
    for bad in ["", "K", "12X", "-1K", "1.5M", "99999999999999999999K"] {
        assert_eq!(cache_size_bytes(bad), None, "{bad:?}");
    }
}
