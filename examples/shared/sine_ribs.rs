//! A finely triangulated ribbed mould surface, z = A sin(2π x / λ) over a square, for the
//! measurement of the closest-point cache (`physics/examples/mould_cache.rs`) and its test
//! (`physics/tests/mould_cache.rs`), which include this file with `#[path]`. The mould is below
//! the surface: each triangle (a, b, c) is ordered so that (b − a) × (c − a) points up (+z),
//! out of the mould, as the mould loader requires.

/// Vertices and triangles of the surface over [x0, x0 + length]² with `n` × `n` squares, each
/// split in two along its diagonal (2n² triangles).
pub fn sine_ribs(
    n: usize,
    x0: f64,
    length: f64,
    amplitude: f64,
    wavelength: f64,
) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let d = length / n as f64;
    let mut vertices = Vec::with_capacity((n + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (x0 + i as f64 * d, x0 + j as f64 * d);
            let z = amplitude * (2.0 * std::f64::consts::PI * x / wavelength).sin();
            vertices.push([x, y, z]);
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut triangles = Vec::with_capacity(2 * n * n);
    for j in 0..n {
        for i in 0..n {
            // Counter-clockwise seen from +z: the normal points up.
            let (a, b, c, e) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, e]);
        }
    }
    (vertices, triangles)
}

/// The surface as an ASCII STL (the facet normals written as the vertex order's).
pub fn to_stl(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> String {
    let mut s = String::from("solid sine_ribs\n");
    for t in triangles {
        let [a, b, c] = t.map(|v| vertices[v as usize]);
        let (u, w) = (sub(b, a), sub(c, a));
        let n = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        s += &format!(
            "facet normal {:e} {:e} {:e}\n outer loop\n",
            n[0], n[1], n[2]
        );
        for v in [a, b, c] {
            s += &format!("  vertex {:e} {:e} {:e}\n", v[0], v[1], v[2]);
        }
        s += " endloop\nendfacet\n";
    }
    s + "endsolid sine_ribs\n"
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
