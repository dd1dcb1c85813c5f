//! A finely triangulated ribbed mould surface, z = A sin(2π x / λ) over a square, and the scene
//! of a sheet lying on such a mould ([`Sheet`]), for the measurement of the closest-point cache
//! (`physics/examples/mould_cache.rs`), its test (`physics/tests/mould_cache.rs`) and the
//! allocation test (`physics/tests/allocation.rs`), which include this file with `#[path]`. The
//! mould is below the surface: each triangle (a, b, c) is ordered so that (b − a) × (c − a)
//! points up (+z), out of the mould, as the mould loader requires.

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

/// A neo-Hookean sheet (E = 5 MPa, ν = 0.45, ρ = 1100 kg/m³: the rubber of the pull-off and
/// demould scenes) meshed as a box of `cells` hex8 from `origin` over `size` [m], whose z− face
/// touches (μ = 0.3) the triangulated mould `file` (beside the scene), moved by the mould
/// `velocity` history (a TOML array of [t, vx, vy, vz] rows) if given, under gravity if
/// `gravity`: the scene text of the cache's measurement, its test and the allocation test.
pub struct Sheet<'a> {
    pub name: &'a str,
    pub file: &'a str,
    pub velocity: Option<&'a str>,
    pub gravity: bool,
    pub origin: [f64; 3],
    pub size: [f64; 3],
    pub cells: [usize; 3],
}

impl Sheet<'_> {
    /// The scene file's text.
    pub fn toml(&self) -> String {
        let v = |x: [f64; 3]| format!("[{:?}, {:?}, {:?}]", x[0], x[1], x[2]);
        let mut s = format!("name = {:?}\nend_time = 1.0\n", self.name);
        if self.gravity {
            s += "gravity = [0.0, 0.0, -9.81]\n";
        }
        s += "[material]\nmodel = \"neo_hookean\"\nyoung = 5.0e6\npoisson = 0.45\ndensity = 1100.0\n";
        s += &format!(
            "[[mould]]\nname = \"mould\"\nshape = \"surface\"\nfile = {:?}\n",
            self.file
        );
        if let Some(vel) = self.velocity {
            s += &format!("velocity = {vel}\n");
        }
        let c = self.cells;
        s += &format!(
            "[mesh]\norigin = {}\nsize = {}\ncells = [{}, {}, {}]\n",
            v(self.origin),
            v(self.size),
            c[0],
            c[1],
            c[2]
        );
        s += "[[contact]]\nfaces = \"z-\"\nmould = \"mould\"\nmu = 0.3\n";
        s
    }
}
