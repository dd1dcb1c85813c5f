//! Triangulated moulds (model §7.1) against the analytic shapes they approximate (a plane, a box, a
//! sphere), to the facet error derived from the mesh itself; and the surface loader's refusals.

use decohesion_physics::mesh::{cross, dot, norm, sub};
use decohesion_physics::mould::shapes::{r#box::Box, sphere::Sphere};
use decohesion_physics::mould::surface::read_stl;
use decohesion_physics::mould::{Shape, SurfaceMesh};

fn surface(v: Vec<[f64; 3]>, t: Vec<[u32; 3]>) -> SurfaceMesh {
    SurfaceMesh::new("test", None, 1.0, v, t, &|k| format!("triangle {k}")).unwrap()
}

/// A deterministic pseudo-random number in [−1, 1).
fn rnd(k: &mut u64) -> f64 {
    *k = k
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*k >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// The 12 triangles of the box [−h, h], outward (counter-clockwise seen from outside).
fn box_mesh(h: [f64; 3]) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let v: Vec<[f64; 3]> = (0..8)
        .map(|i| {
            let s = |b: usize| if i >> b & 1 == 1 { 1.0 } else { -1.0 };
            [s(0) * h[0], s(1) * h[1], s(2) * h[2]]
        })
        .collect();
    // Faces as quads (a, b, c, d) counter-clockwise from outside; vertex i has bits (x, y, z).
    let quads = [
        [0, 2, 3, 1], // z−
        [4, 5, 7, 6], // z+
        [0, 1, 5, 4], // y−
        [2, 6, 7, 3], // y+
        [0, 4, 6, 2], // x−
        [1, 3, 7, 5], // x+
    ];
    let t = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    (v, t)
}

/// A UV sphere of radius r: `rings` latitude bands, `seg` longitudes, outward.
fn uv_sphere(r: f64, rings: usize, seg: usize) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let pi = std::f64::consts::PI;
    let mut v = vec![[0.0, 0.0, r]];
    for i in 1..rings {
        let th = pi * i as f64 / rings as f64;
        for j in 0..seg {
            let ph = 2.0 * pi * j as f64 / seg as f64;
            v.push([
                r * th.sin() * ph.cos(),
                r * th.sin() * ph.sin(),
                r * th.cos(),
            ]);
        }
    }
    v.push([0.0, 0.0, -r]);
    let south = (v.len() - 1) as u32;
    let at = |i: usize, j: usize| (1 + (i - 1) * seg + j % seg) as u32;
    let mut t = Vec::new();
    for j in 0..seg {
        t.push([0, at(1, j), at(1, j + 1)]);
        t.push([south, at(rings - 1, j + 1), at(rings - 1, j)]);
        for i in 1..rings - 1 {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    (v, t)
}

/// A large square at z = 0 in two triangles: over its inside, the gap and normal of the
/// half-space z ≥ 0, exactly (the face normal of an axis-aligned triangle is exact).
#[test]
fn triangulated_plane_is_the_half_space() {
    let l = 10.0;
    let v = vec![[-l, -l, 0.0], [l, -l, 0.0], [l, l, 0.0], [-l, l, 0.0]];
    let s = Shape::Surface(surface(v, vec![[0, 1, 2], [0, 2, 3]]).into());
    let mut k = 1;
    for _ in 0..500 {
        let x = [5.0 * rnd(&mut k), 5.0 * rnd(&mut k), 2.0 * rnd(&mut k)];
        let pr = s.project([0.0; 3], [0.0; 3], x);
        let exact = Shape::default().project([0.0; 3], [0.0, 0.0, 1.0], x);
        assert_eq!(pr.normal, [0.0, 0.0, 1.0], "{x:?}");
        assert!((pr.gap(x) - exact.gap(x)).abs() <= 1e-15, "{x:?}");
    }
}

/// A box in 12 triangles against the analytic box. In a face's region (the closest point
/// inside a face) the gap and normal are the box's, to round-off; in an edge's or a corner's
/// region the pseudo-normal n (mean of the faces' normals, the angle-weighted one at a corner)
/// is not x − p's direction, so g = n·(x − p) = |x − p| cos β with β ≤ the largest angle
/// between n and the normal cone of the feature, 45° at an edge of a box and
/// acos(1/√3) = 54.7° at a corner: g ∈ [|x − p| cos β_max, |x − p|] and > 0 outside.
#[test]
fn triangulated_box_is_the_box() {
    let h = [0.5, 1.0, 1.5];
    let (v, t) = box_mesh(h);
    let s = Shape::Surface(surface(v, t).into());
    let exact = Shape::Box(Box {
        centre: [0.0; 3],
        half_size: h,
    });
    let cos_max = (1.0f64 / 3.0).sqrt();
    let mut k = 3;
    let (mut faces, mut edges) = (0, 0);
    for _ in 0..4000 {
        let x = [2.0 * rnd(&mut k), 3.0 * rnd(&mut k), 4.0 * rnd(&mut k)];
        let (a, b) = (
            s.project([0.0; 3], [0.0; 3], x),
            exact.project([0.0; 3], [0.0; 3], x),
        );
        let (ga, gb) = (a.gap(x), b.gap(x));
        let outside = (0..3).filter(|&c| x[c].abs() > h[c]).count();
        if outside <= 1 {
            faces += 1;
            assert!((ga - gb).abs() <= 1e-14, "{x:?}: {ga} vs {gb}");
            assert!(norm(sub(a.normal, b.normal)) <= 1e-15, "{x:?}");
        } else {
            edges += 1;
            assert!(ga > 0.0 && ga <= gb * (1.0 + 1e-14), "{x:?}: {ga} vs {gb}");
            assert!(ga >= gb * cos_max * (1.0 - 1e-14), "{x:?}: {ga} vs {gb}");
        }
    }
    assert!(faces > 500 && edges > 500, "{faces} {edges}");
}

/// A UV sphere of radius R against the ball: the facets lie between the spheres of radius
/// R − s and R, s = max over the facets of R − (distance of the centre to the facet's plane)
/// (the chord error R(1 − cos θ_c), θ_c the angular radius of the facet), so the distance
/// from an outside x to the mesh is in [g, g + s] (g = |x| − R, the ball's gap); the
/// pseudo-normal makes an angle β ≤ β_max with x − p, β_max = the largest angle between the
/// normals of two facets that share a vertex: g_mesh ∈ [g cos β_max, g + s]. Inside the
/// sphere by more than s, g_mesh < 0. The normal is within θ_c + β_max of the radial direction.
#[test]
fn triangulated_sphere_is_the_ball_to_the_chord_error() {
    let r = 0.3;
    let (v, t) = uv_sphere(r, 24, 48);
    let normal = |tr: &[u32; 3]| {
        let [a, b, c] = tr.map(|i| v[i as usize]);
        let n = cross(sub(b, a), sub(c, a));
        n.map(|x| x / norm(n))
    };
    let (mut s, mut theta_c, mut beta) = (0.0f64, 0.0f64, 0.0f64);
    for tr in &t {
        let n = normal(tr);
        s = s.max(r - dot(n, v[tr[0] as usize]));
        for &i in tr {
            theta_c = theta_c.max((dot(n, v[i as usize]) / r).min(1.0).acos());
        }
        for tr2 in t.iter().filter(|o| o.iter().any(|i| tr.contains(i))) {
            beta = beta.max(dot(n, normal(tr2)).min(1.0).acos());
        }
    }
    let surf = Shape::Surface(surface(v.clone(), t.clone()).into());
    let ball = Shape::Sphere(Sphere {
        centre: [0.0; 3],
        radius: r,
    });
    let mut k = 11;
    for _ in 0..3000 {
        let d = [rnd(&mut k), rnd(&mut k), rnd(&mut k)];
        let dist = r * (1.02 + 0.5 * (1.0 + rnd(&mut k)));
        let x = d.map(|c| c * dist / norm(d));
        let (a, b) = (
            surf.project([0.0; 3], [0.0; 3], x),
            ball.project([0.0; 3], [0.0; 3], x),
        );
        let (ga, gb) = (a.gap(x), b.gap(x));
        assert!(
            ga <= gb + s + 1e-15 && ga >= gb * beta.cos() - 1e-15,
            "{x:?}: {ga} vs {gb}, s = {s}"
        );
        assert!(
            dot(a.normal, b.normal) >= (theta_c + beta).cos() - 1e-15,
            "{x:?}"
        );
        let inside = x.map(|c| c * (r - 2.0 * s) / dist);
        assert!(surf.project([0.0; 3], [0.0; 3], inside).gap(inside) < 0.0);
    }
    // The chord error of this mesh, as derived: R(1 − cos θ_c) is s.
    assert!(
        (s - r * (1.0 - theta_c.cos())).abs() < 1e-3 * s,
        "{s} {theta_c}"
    );
}

/// STL: a binary file and an ASCII file of the same box read back to the same surface; a flipped
/// facet, a facet whose written normal opposes its vertex order, a degenerate facet and a file
/// that is not an STL are refused with the file, the element and the reason.
#[test]
fn stl_in_and_bad_surfaces_out() {
    let (v, t) = box_mesh([1.0, 1.0, 1.0]);
    let facets: Vec<[[f64; 3]; 3]> = t.iter().map(|tr| tr.map(|i| v[i as usize])).collect();
    let normal_of = |f: &[[f64; 3]; 3]| cross(sub(f[1], f[0]), sub(f[2], f[0]));
    let mut bin = vec![0u8; 80];
    bin.extend((facets.len() as u32).to_le_bytes());
    let mut ascii = String::from("solid box\n");
    for f in &facets {
        let n = normal_of(f);
        for x in std::iter::once(n).chain(f.iter().copied()) {
            for c in x {
                bin.extend((c as f32).to_le_bytes());
            }
        }
        bin.extend([0, 0]);
        ascii += &format!("facet normal {} {} {}\n outer loop\n", n[0], n[1], n[2]);
        for x in f {
            ascii += &format!("  vertex {} {} {}\n", x[0], x[1], x[2]);
        }
        ascii += " endloop\nendfacet\n";
    }
    ascii += "endsolid box\n";
    let (vb, tb) = read_stl(&bin, "box.stl").unwrap();
    let (va, ta) = read_stl(ascii.as_bytes(), "box.stl").unwrap();
    assert_eq!((&vb, &tb), (&va, &ta));
    assert_eq!(tb.len(), 12);
    let s = SurfaceMesh::new("box.stl", None, 2.0, vb, tb, &|k| format!("facet {k}")).unwrap();
    // Scaled by 2: the box of half-size 2; merged vertices: 8.
    assert_eq!(s.mesh.vertices().len(), 8);
    let x = [3.0, 0.0, 0.0];
    assert!((s.project(x).gap(x) - 1.0).abs() < 1e-15);
    // A facet flipped in the file.
    let mut flipped = facets.clone();
    flipped[5].swap(1, 2);
    let vf: Vec<[f64; 3]> = flipped.iter().flatten().copied().collect();
    let tf = (0..12u32).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
    let e = SurfaceMesh::new("box.stl", None, 1.0, vf, tf, &|k| format!("facet {k}")).unwrap_err();
    assert!(e.to_string().starts_with("box.stl: "), "{e}");
    assert!(
        e.message.contains("facet 5") && e.message.contains("inconsistent"),
        "{e}"
    );
    // A written normal against the vertex order.
    let bad = ascii.replacen("facet normal 0 0 -", "facet normal 0 0 ", 1);
    let e = read_stl(bad.as_bytes(), "n.stl").unwrap_err();
    assert!(
        e.message.contains("facet 0") && e.message.contains("opposes"),
        "{e}"
    );
    // Degenerate.
    let e = SurfaceMesh::new(
        "d",
        None,
        1.0,
        vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
        vec![[0, 1, 2]],
        &|k| format!("facet {k}"),
    )
    .unwrap_err();
    assert!(e.message.contains("facet 0 is degenerate"), "{e}");
    // Not an STL.
    let e = read_stl(
        b"hello, this is text and not a mesh at all, not even close to 84 bytes long!!",
        "x.stl",
    )
    .unwrap_err();
    assert!(e.message.contains("not an STL"), "{e}");
}
