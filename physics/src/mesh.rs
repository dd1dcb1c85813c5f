//! Hexahedral meshes: nodes, 8-node trilinear elements, named boundary face sets, and the
//! reference-configuration quantities that the total Lagrangian formulation computes once
//! (PHYSICS.md §2): shape-function gradients ∇ₓNₐ and weights w·det J₀ at the Gauss points,
//! lumped masses, tributary areas of boundary faces.
//!
//! Node numbering of an element follows the usual convention: nodes 0–3 on the ζ = −1 face
//! counter-clockwise seen from +ζ, nodes 4–7 above them.

use std::collections::{BTreeMap, HashMap};

/// Parent coordinates (ξ, η, ζ) of the 8 nodes of the reference hexahedron.
pub const HEX_CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// A hexahedral mesh in its reference configuration. Lengths in metres.
#[derive(Debug, Clone)]
pub struct Mesh {
    /// Reference positions X of the nodes [m].
    pub nodes: Vec<[f64; 3]>,
    /// Element connectivity (8 node indices, see module docs for the order).
    pub elements: Vec<[u32; 8]>,
    /// Named boundary face sets: quadrilaterals whose node order gives an outward normal.
    pub face_sets: BTreeMap<String, Vec<[u32; 4]>>,
}

/// Slabs across the longest axis of a mesh ([`Mesh::slabs`]).
#[derive(Debug, Clone, Copy)]
pub struct Slabs {
    /// The axis (0 = x, 1 = y, 2 = z).
    pub axis: usize,
    /// Lowest coordinate along it [m].
    pub lo: f64,
    /// Slab thickness [m], at least the largest element extent along the axis.
    pub width: f64,
    pub count: usize,
}

impl Slabs {
    /// Slab of a coordinate along the axis (clamped to the slabs).
    pub fn of(&self, z: f64) -> usize {
        (((z - self.lo) / self.width).floor().max(0.0) as usize).min(self.count - 1)
    }
}

/// The 12 edges of a hex8 (local node pairs).
const HEX_EDGES: [(usize, usize); 12] = [
    (0, 1),
    (1, 2),
    (2, 3),
    (3, 0),
    (4, 5),
    (5, 6),
    (6, 7),
    (7, 4),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

/// Trilinear shape functions Nₐ(ξ) of the hexahedron.
#[inline]
pub fn shape(xi: [f64; 3]) -> [f64; 8] {
    let mut n = [0.0; 8];
    for (a, c) in HEX_CORNERS.iter().enumerate() {
        n[a] = 0.125 * (1.0 + c[0] * xi[0]) * (1.0 + c[1] * xi[1]) * (1.0 + c[2] * xi[2]);
    }
    n
}

/// Parent derivatives ∂Nₐ/∂ξⱼ of the hexahedron.
#[inline]
pub fn shape_derivatives(xi: [f64; 3]) -> [[f64; 3]; 8] {
    let mut d = [[0.0; 3]; 8];
    for (a, c) in HEX_CORNERS.iter().enumerate() {
        let f = [1.0 + c[0] * xi[0], 1.0 + c[1] * xi[1], 1.0 + c[2] * xi[2]];
        d[a] = [
            0.125 * c[0] * f[1] * f[2],
            0.125 * c[1] * f[0] * f[2],
            0.125 * c[2] * f[0] * f[1],
        ];
    }
    d
}

/// The 2×2×2 Gauss points (ξ = ±1/√3, weight 1 each), in the same order as `HEX_CORNERS`.
pub fn gauss_points() -> [[f64; 3]; 8] {
    let g = 1.0 / 3f64.sqrt();
    HEX_CORNERS.map(|c| [c[0] * g, c[1] * g, c[2] * g])
}

/// Reference-configuration data of one element shape at its 8 Gauss points, laid out with the
/// Gauss point index innermost so the per-step kernel runs over 8 lanes (SIMD-friendly).
#[derive(Debug, Clone, PartialEq)]
pub struct GaussData {
    /// ∇ₓNₐ at each Gauss point: `grad[a][j][q]` = ∂Nₐ/∂Xⱼ (ξ_q) [1/m].
    pub grad: [[[f64; 8]; 3]; 8],
    /// The same gradient times the weight w_q det J₀(ξ_q): `wgrad[a][j][q]` [m²].
    pub wgrad: [[[f64; 8]; 3]; 8],
    /// Integration weight times reference Jacobian, w_q det J₀(ξ_q) [m³].
    pub wdet: [f64; 8],
}

/// Error in the reference geometry of an element (inverted or degenerate hexahedron).
#[derive(Debug, Clone, thiserror::Error)]
#[error("element {element} is degenerate or inverted in the reference configuration (det J₀ = {det_j0:e} at a Gauss point); check the node order")]
pub struct GeometryError {
    pub element: usize,
    pub det_j0: f64,
}

impl GaussData {
    /// ∇ₓNₐ = J₀⁻ᵀ ∂Nₐ/∂ξ at the Gauss points, J₀ = ∂X/∂ξ (PHYSICS.md §2: computed once).
    pub fn new(x: &[[f64; 3]; 8]) -> Result<Self, f64> {
        let mut gd = GaussData {
            grad: [[[0.0; 8]; 3]; 8],
            wgrad: [[[0.0; 8]; 3]; 8],
            wdet: [0.0; 8],
        };
        for (q, xi) in gauss_points().iter().enumerate() {
            let dn = shape_derivatives(*xi);
            let mut j = nalgebra::Matrix3::<f64>::zeros();
            for a in 0..8 {
                for r in 0..3 {
                    for c in 0..3 {
                        j[(r, c)] += x[a][r] * dn[a][c];
                    }
                }
            }
            let det = j.determinant();
            if !(det > 0.0 && det.is_finite()) {
                return Err(det);
            }
            let jinv = j.try_inverse().ok_or(det)?;
            for a in 0..8 {
                for jdir in 0..3 {
                    // ∂N/∂X_j = Σ_c ∂N/∂ξ_c ∂ξ_c/∂X_j, ∂ξ/∂X = J⁻¹.
                    let g: f64 = (0..3).map(|c| dn[a][c] * jinv[(c, jdir)]).sum();
                    gd.grad[a][jdir][q] = g;
                    gd.wgrad[a][jdir][q] = g * det;
                }
            }
            gd.wdet[q] = det;
        }
        Ok(gd)
    }

    /// Reference volume of the element, Σ_q w_q det J₀ [m³].
    pub fn volume(&self) -> f64 {
        self.wdet.iter().sum()
    }

    /// Consistent-mass row sums per unit density, ∫ Nₐ dV (PHYSICS.md §2, lumped mass) [m³].
    pub fn lumped_volumes(&self) -> [f64; 8] {
        let mut m = [0.0; 8];
        for (q, xi) in gauss_points().iter().enumerate() {
            let n = shape(*xi);
            for a in 0..8 {
                m[a] += n[a] * self.wdet[q];
            }
        }
        m
    }
}

/// Hourglass base vectors hᵅ of the hexahedron (α = 1..4: ξη, ηζ, ζξ, ξηζ at the nodes), in the
/// node order of [`HEX_CORNERS`] (Flanagan & Belytschko 1981).
pub fn hourglass_vectors() -> [[f64; 8]; 4] {
    let mut h = [[0.0; 8]; 4];
    for (a, c) in HEX_CORNERS.iter().enumerate() {
        h[0][a] = c[0] * c[1];
        h[1][a] = c[1] * c[2];
        h[2][a] = c[2] * c[0];
        h[3][a] = c[0] * c[1] * c[2];
    }
    h
}

/// Reference data of one element shape for one-point integration with Flanagan–Belytschko
/// hourglass control (PHYSICS.md §2: "one-point integration with hourglass control").
#[derive(Debug, Clone, PartialEq)]
pub struct CentreData {
    /// Mean gradients bₐ = (1/V) ∫ ∇ₓNₐ dV (FB's uniform gradient; exact by 2×2×2 Gauss) [1/m].
    pub b: [[f64; 3]; 8],
    /// Hourglass shape vectors γₐᵅ = hₐᵅ − (Σ_c h_cᵅ X_c)·bₐ: orthogonal to every affine field,
    /// so rigid motions and homogeneous strains excite no hourglass force.
    pub gamma: [[f64; 8]; 4],
    /// Reference volume V [m³].
    pub volume: f64,
    /// Σₐ bₐ·bₐ [1/m²], for the hourglass stiffness.
    pub bb: f64,
}

impl CentreData {
    /// From the node coordinates of the element and its Gauss data.
    pub fn new(x: &[[f64; 3]; 8], gd: &GaussData) -> CentreData {
        let volume = gd.volume();
        let mut b = [[0.0; 3]; 8];
        for a in 0..8 {
            for j in 0..3 {
                b[a][j] = gd.wgrad[a][j].iter().sum::<f64>() / volume;
            }
        }
        let h = hourglass_vectors();
        let mut gamma = [[0.0; 8]; 4];
        for al in 0..4 {
            let mut hx = [0.0; 3];
            for c in 0..8 {
                for j in 0..3 {
                    hx[j] += h[al][c] * x[c][j];
                }
            }
            for a in 0..8 {
                gamma[al][a] = h[al][a] - (hx[0] * b[a][0] + hx[1] * b[a][1] + hx[2] * b[a][2]);
            }
        }
        let bb = b.iter().map(|v| dot(*v, *v)).sum();
        CentreData {
            b,
            gamma,
            volume,
            bb,
        }
    }
}

/// Element shapes deduplicated: elements that are translates of each other share their
/// Gauss data (a structured box has a single class), which keeps memory per element small and
/// the gradients hot in cache.
#[derive(Debug, Clone)]
pub struct ElementClasses {
    pub data: Vec<GaussData>,
    /// One-point data of the same classes.
    pub centre: Vec<CentreData>,
    /// Class index of each element.
    pub class_of: Vec<u32>,
}

impl Mesh {
    /// A structured box [origin, origin + size] with `cells` hexahedra per axis, and the six face
    /// sets `x-`, `x+`, `y-`, `y+`, `z-`, `z+`.
    pub fn boxed(origin: [f64; 3], size: [f64; 3], cells: [usize; 3]) -> Mesh {
        let [nx, ny, nz] = cells;
        let nid = |i: usize, j: usize, k: usize| (i + (nx + 1) * (j + (ny + 1) * k)) as u32;
        let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
        for k in 0..=nz {
            for j in 0..=ny {
                for i in 0..=nx {
                    nodes.push([
                        origin[0] + size[0] * i as f64 / nx as f64,
                        origin[1] + size[1] * j as f64 / ny as f64,
                        origin[2] + size[2] * k as f64 / nz as f64,
                    ]);
                }
            }
        }
        let mut elements = Vec::with_capacity(nx * ny * nz);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    elements.push([
                        nid(i, j, k),
                        nid(i + 1, j, k),
                        nid(i + 1, j + 1, k),
                        nid(i, j + 1, k),
                        nid(i, j, k + 1),
                        nid(i + 1, j, k + 1),
                        nid(i + 1, j + 1, k + 1),
                        nid(i, j + 1, k + 1),
                    ]);
                }
            }
        }
        let mut face_sets = BTreeMap::new();
        // Each quad is ordered counter-clockwise seen from outside (outward normal).
        let mut xm = vec![];
        let mut xp = vec![];
        for k in 0..nz {
            for j in 0..ny {
                xm.push([
                    nid(0, j, k),
                    nid(0, j, k + 1),
                    nid(0, j + 1, k + 1),
                    nid(0, j + 1, k),
                ]);
                xp.push([
                    nid(nx, j, k),
                    nid(nx, j + 1, k),
                    nid(nx, j + 1, k + 1),
                    nid(nx, j, k + 1),
                ]);
            }
        }
        let mut ym = vec![];
        let mut yp = vec![];
        for k in 0..nz {
            for i in 0..nx {
                ym.push([
                    nid(i, 0, k),
                    nid(i + 1, 0, k),
                    nid(i + 1, 0, k + 1),
                    nid(i, 0, k + 1),
                ]);
                yp.push([
                    nid(i, ny, k),
                    nid(i, ny, k + 1),
                    nid(i + 1, ny, k + 1),
                    nid(i + 1, ny, k),
                ]);
            }
        }
        let mut zm = vec![];
        let mut zp = vec![];
        for j in 0..ny {
            for i in 0..nx {
                zm.push([
                    nid(i, j, 0),
                    nid(i, j + 1, 0),
                    nid(i + 1, j + 1, 0),
                    nid(i + 1, j, 0),
                ]);
                zp.push([
                    nid(i, j, nz),
                    nid(i + 1, j, nz),
                    nid(i + 1, j + 1, nz),
                    nid(i, j + 1, nz),
                ]);
            }
        }
        for (name, set) in [
            ("x-", xm),
            ("x+", xp),
            ("y-", ym),
            ("y+", yp),
            ("z-", zm),
            ("z+", zp),
        ] {
            face_sets.insert(name.to_string(), set);
        }
        Mesh {
            nodes,
            elements,
            face_sets,
        }
    }

    /// Reference coordinates of the nodes of element `e`.
    pub fn element_coords(&self, e: usize) -> [[f64; 3]; 8] {
        self.elements[e].map(|n| self.nodes[n as usize])
    }

    /// Groups elements by shape (translation-invariant, tolerance 1e-9 of the element size) and
    /// computes the Gauss data of each class once.
    pub fn element_classes(&self) -> Result<ElementClasses, GeometryError> {
        let mut index: HashMap<[i64; 21], u32> = HashMap::new();
        let mut data = Vec::new();
        let mut centre = Vec::new();
        let mut class_of = Vec::with_capacity(self.elements.len());
        for e in 0..self.elements.len() {
            let x = self.element_coords(e);
            let size = (1..8)
                .flat_map(|a| (0..3).map(move |c| (a, c)))
                .map(|(a, c)| (x[a][c] - x[0][c]).abs())
                .fold(0.0, f64::max);
            let tol = (size * 1e-9).max(f64::MIN_POSITIVE);
            let mut key = [0i64; 21];
            for a in 1..8 {
                for c in 0..3 {
                    key[(a - 1) * 3 + c] = ((x[a][c] - x[0][c]) / tol).round() as i64;
                }
            }
            let next = data.len() as u32;
            let class = *index.entry(key).or_insert(next);
            if class == next {
                let gd =
                    GaussData::new(&x).map_err(|det_j0| GeometryError { element: e, det_j0 })?;
                centre.push(CentreData::new(&x, &gd));
                data.push(gd);
            }
            class_of.push(class);
        }
        Ok(ElementClasses {
            data,
            centre,
            class_of,
        })
    }

    /// The slabs of [`Mesh::element_blocks`]: across the longest axis, each as thick as the
    /// largest element extent along it (None for a mesh without elements).
    pub fn slabs(&self) -> Option<Slabs> {
        if self.elements.is_empty() {
            return None;
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for x in &self.nodes {
            for c in 0..3 {
                lo[c] = lo[c].min(x[c]);
                hi[c] = hi[c].max(x[c]);
            }
        }
        // Equal sides: the last (z) wins, the slowest index of a box.
        let axis = (0..3)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
            .unwrap_or(2);
        let mut thickness = 0.0f64;
        for conn in &self.elements {
            let (mut a, mut b) = (f64::INFINITY, f64::NEG_INFINITY);
            for &n in conn {
                let z = self.nodes[n as usize][axis];
                a = a.min(z);
                b = b.max(z);
            }
            thickness = thickness.max(b - a);
        }
        let span = hi[axis] - lo[axis];
        let count = if thickness > 0.0 && span.is_finite() {
            // The tolerance keeps a layer of a structured mesh whole when the node
            // coordinates make its extent an ulp larger than span/layers.
            ((span / thickness + 1e-9).floor() as usize).clamp(1, self.elements.len())
        } else {
            1
        };
        Some(Slabs {
            axis,
            lo: lo[axis],
            width: span / count as f64,
            count,
        })
    }

    /// The same mesh with node i renamed `new_index[i]` (a permutation of 0..nodes): positions,
    /// connectivity and face sets follow.
    pub fn renumbered(&self, new_index: &[u32]) -> Mesh {
        assert_eq!(new_index.len(), self.nodes.len());
        let mut nodes = vec![[0.0; 3]; self.nodes.len()];
        for (i, x) in self.nodes.iter().enumerate() {
            nodes[new_index[i] as usize] = *x;
        }
        let map = |n: &u32| new_index[*n as usize];
        Mesh {
            nodes,
            elements: self
                .elements
                .iter()
                .map(|e| e.each_ref().map(map))
                .collect(),
            face_sets: self
                .face_sets
                .iter()
                .map(|(k, q)| (k.clone(), q.iter().map(|f| f.each_ref().map(map)).collect()))
                .collect(),
        }
    }

    /// The same mesh with its nodes renumbered slab by slab across the longest axis ([`Slabs`]),
    /// keeping their order inside a slab. The nodes of an element then sit close together in
    /// memory, and each thread's share of the node loops matches its element blocks. A mesh
    /// already numbered along that axis (a box whose longest side is z, or a cube) keeps its
    /// numbering: the sort is stable and the slab index never decreases along it.
    pub fn with_nodes_in_slabs(self) -> Mesh {
        let Some(slabs) = self.slabs() else {
            return self;
        };
        let mut order: Vec<u32> = (0..self.nodes.len() as u32).collect();
        order.sort_by_key(|&i| slabs.of(self.nodes[i as usize][slabs.axis]));
        let mut new_index = vec![0u32; self.nodes.len()];
        for (new, &old) in order.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        self.renumbered(&new_index)
    }

    /// Slab blocks for the parallel element loop: colours → blocks → elements.
    ///
    /// The elements are cut into slabs across the longest axis of the mesh, each slab at least
    /// one element thick (T ≥ the largest element extent along that axis) and holding at least
    /// `min_block` elements (thin slabs are merged with the next). Two elements that share a
    /// node have centroids at most T apart, so slabs k and k + 2 never share a node: the even
    /// slabs form one colour and the odd slabs the other. The colouring is nonetheless done
    /// greedily on the slabs' node sets, so a mesh for which the argument fails (round-off at a
    /// slab boundary) still gets node-disjoint blocks, only with more colours.
    ///
    /// Inside a block the elements run in increasing index, one after another (they share
    /// nodes); blocks of one colour run in parallel. Everything here depends on the mesh alone,
    /// never on the thread count, so every node receives its element forces in the same order
    /// whatever the number of threads. Compared with a colouring of single elements (8 colours
    /// on a box, each touching every node), a colour sweeps half of the nodes once and a step
    /// needs 2 parallel sections instead of 8; the elements of a block also share most of their
    /// nodes with the previous ones, still in cache.
    pub fn element_blocks(&self, min_block: usize) -> Vec<Vec<Vec<u32>>> {
        let Some(slabs) = self.slabs() else {
            return Vec::new();
        };
        let mut layers: Vec<Vec<u32>> = vec![Vec::new(); slabs.count];
        for (e, conn) in self.elements.iter().enumerate() {
            let c = conn
                .iter()
                .fold(0.0, |s, &n| s + self.nodes[n as usize][slabs.axis])
                / 8.0;
            layers[slabs.of(c)].push(e as u32);
        }
        // Merge thin slabs forward until each block holds at least `min_block` elements.
        let mut blocks: Vec<Vec<u32>> = Vec::new();
        let mut open: Vec<u32> = Vec::new();
        for layer in layers {
            open.extend(layer);
            if open.len() >= min_block.max(1) {
                blocks.push(std::mem::take(&mut open));
            }
        }
        if !open.is_empty() {
            match blocks.last_mut() {
                Some(last) => last.extend(open),
                None => blocks.push(open),
            }
        }
        // Greedy colouring of the blocks on their node sets.
        let mut node_colours: Vec<u64> = vec![0; self.nodes.len()];
        let mut colours: Vec<Vec<Vec<u32>>> = Vec::new();
        for block in blocks {
            let used = block
                .iter()
                .flat_map(|&e| self.elements[e as usize])
                .fold(0u64, |m, n| m | node_colours[n as usize]);
            let c = ((!used).trailing_zeros() as usize).min(64);
            if c == 64 {
                // Cannot happen for slabs; keep the invariant by running such a block alone.
                colours.push(vec![block]);
                continue;
            }
            while colours.len() <= c {
                colours.push(Vec::new());
            }
            for &e in &block {
                for &n in &self.elements[e as usize] {
                    node_colours[n as usize] |= 1 << c;
                }
            }
            colours[c].push(block);
        }
        colours
    }

    /// Distinct nodes of a face set, in increasing order.
    pub fn face_set_nodes(&self, quads: &[[u32; 4]]) -> Vec<u32> {
        let mut v: Vec<u32> = quads.iter().flatten().copied().collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Tributary reference areas W_a = ∫ Nₐ dA over the quads of a face set (2×2 Gauss on each
    /// bilinear quad), as (node, W) pairs sorted by node (PHYSICS.md §4, step 4: reference W).
    pub fn nodal_areas(&self, quads: &[[u32; 4]]) -> Vec<(u32, f64)> {
        let mut acc: BTreeMap<u32, f64> = BTreeMap::new();
        let g = 1.0 / 3f64.sqrt();
        for quad in quads {
            let x = quad.map(|n| self.nodes[n as usize]);
            for (s, t) in [(-g, -g), (g, -g), (g, g), (-g, g)] {
                let n = [
                    0.25 * (1.0 - s) * (1.0 - t),
                    0.25 * (1.0 + s) * (1.0 - t),
                    0.25 * (1.0 + s) * (1.0 + t),
                    0.25 * (1.0 - s) * (1.0 + t),
                ];
                let ds = [-(1.0 - t), 1.0 - t, 1.0 + t, -(1.0 + t)].map(|v| 0.25 * v);
                let dt = [-(1.0 - s), -(1.0 + s), 1.0 + s, 1.0 - s].map(|v| 0.25 * v);
                let mut a = [0.0; 3];
                let mut b = [0.0; 3];
                for k in 0..4 {
                    for c in 0..3 {
                        a[c] += ds[k] * x[k][c];
                        b[c] += dt[k] * x[k][c];
                    }
                }
                let cr = cross(a, b);
                let da = norm(cr);
                for k in 0..4 {
                    *acc.entry(quad[k]).or_insert(0.0) += n[k] * da;
                }
            }
        }
        acc.into_iter().collect()
    }

    /// Outward unit normal of a quad in the reference configuration (from its diagonals).
    pub fn quad_normal(&self, quad: &[u32; 4]) -> [f64; 3] {
        let x = quad.map(|n| self.nodes[n as usize]);
        let d1 = sub(x[2], x[0]);
        let d2 = sub(x[3], x[1]);
        let c = cross(d1, d2);
        let l = norm(c);
        [c[0] / l, c[1] / l, c[2] / l]
    }

    /// Smallest edge length of the mesh [m] (for messages and scales).
    /// Faces of the hexahedra that belong to one element only: the boundary of the body, each
    /// quad ordered counter-clockwise seen from outside (outward normal), and the element it
    /// belongs to. Used to draw the surface; not needed by the time loop.
    pub fn boundary_faces(&self) -> Vec<([u32; 4], u32)> {
        /// Local faces of a hexahedron, outward (see the module docs for the node order).
        const FACES: [[usize; 4]; 6] = [
            [0, 3, 2, 1],
            [4, 5, 6, 7],
            [0, 1, 5, 4],
            [1, 2, 6, 5],
            [2, 3, 7, 6],
            [3, 0, 4, 7],
        ];
        let mut seen: HashMap<[u32; 4], (usize, [u32; 4], u32)> = HashMap::new();
        for (e, conn) in self.elements.iter().enumerate() {
            for f in FACES {
                let quad = f.map(|a| conn[a]);
                let mut key = quad;
                key.sort_unstable();
                seen.entry(key)
                    .and_modify(|v| v.0 += 1)
                    .or_insert((1, quad, e as u32));
            }
        }
        let mut out: Vec<([u32; 4], u32)> = seen
            .into_values()
            .filter(|v| v.0 == 1)
            .map(|v| (v.1, v.2))
            .collect();
        out.sort_unstable_by_key(|v| (v.1, v.0));
        out
    }

    /// Deformation gradient F = I + Σₐ uₐ ⊗ ∇ₓNₐ at the centre (ξ = 0) of element `e`
    /// (PHYSICS.md §2), for post-processing (von Mises stress, J) of a displacement field `u`.
    pub fn centre_deformation_gradient(&self, e: usize, u: &[[f64; 3]]) -> [[f64; 3]; 3] {
        let x = self.element_coords(e);
        let d = shape_derivatives([0.0; 3]);
        // J₀ = ∂X/∂ξ, then ∇ₓNₐ = J₀⁻ᵀ ∂Nₐ/∂ξ.
        let mut j0 = nalgebra::Matrix3::<f64>::zeros();
        for a in 0..8 {
            for i in 0..3 {
                for k in 0..3 {
                    j0[(i, k)] += x[a][i] * d[a][k];
                }
            }
        }
        let inv_t = j0
            .try_inverse()
            .unwrap_or_else(|| nalgebra::Matrix3::from_element(f64::NAN))
            .transpose();
        let mut f = [[0.0; 3]; 3];
        for (i, row) in f.iter_mut().enumerate() {
            row[i] = 1.0;
        }
        for a in 0..8 {
            let g = inv_t * nalgebra::Vector3::new(d[a][0], d[a][1], d[a][2]);
            let ua = u[self.elements[e][a] as usize];
            for i in 0..3 {
                for j in 0..3 {
                    f[i][j] += ua[i] * g[j];
                }
            }
        }
        f
    }

    /// Centre of volume X_c = ∫X dV / ∫dV of the reference mesh (the centre of mass for a
    /// uniform density), from the lumped nodal volumes: row-sum lumping keeps first moments,
    /// Σₐ Vₐ Xₐ = ∫ Σₐ Nₐ Xₐ dV = ∫ X dV.
    pub fn centre_of_volume(&self) -> Result<[f64; 3], GeometryError> {
        let classes = self.element_classes()?;
        let (mut moment, mut volume) = ([0.0; 3], 0.0);
        for (e, conn) in self.elements.iter().enumerate() {
            let lv = classes.data[classes.class_of[e] as usize].lumped_volumes();
            for a in 0..8 {
                let x = self.nodes[conn[a] as usize];
                for c in 0..3 {
                    moment[c] += lv[a] * x[c];
                }
                volume += lv[a];
            }
        }
        Ok(moment.map(|m| m / volume))
    }

    /// Largest ratio of the longest to the shortest edge over the elements (1 for cubes).
    pub fn max_aspect_ratio(&self) -> f64 {
        self.elements
            .iter()
            .map(|conn| {
                let (lo, hi) =
                    HEX_EDGES
                        .iter()
                        .fold((f64::INFINITY, 0.0f64), |(lo, hi), &(a, b)| {
                            let l = norm(sub(
                                self.nodes[conn[a] as usize],
                                self.nodes[conn[b] as usize],
                            ));
                            (lo.min(l), hi.max(l))
                        });
                hi / lo
            })
            .fold(0.0, f64::max)
    }

    pub fn min_edge(&self) -> f64 {
        let mut m = f64::INFINITY;
        for conn in &self.elements {
            for &(a, b) in &HEX_EDGES {
                m = m.min(norm(sub(
                    self.nodes[conn[a] as usize],
                    self.nodes[conn[b] as usize],
                )));
            }
        }
        m
    }
}

#[inline]
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline]
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
#[inline]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Renumbering in slabs: the identity on a box numbered along its longest side (z); on a
    /// randomly numbered box, every element and face keeps its coordinates and the slab index
    /// of the nodes never decreases with their number.
    #[test]
    fn nodes_in_slabs_keep_the_geometry_and_sort_the_numbering() {
        let m = Mesh::boxed([0.0; 3], [1.0, 2.0, 3.0], [3, 4, 5]);
        let same = m.clone().with_nodes_in_slabs();
        assert_eq!(same.nodes, m.nodes);
        assert_eq!(same.elements, m.elements);
        let n = m.nodes.len();
        let mut p: Vec<u32> = (0..n as u32).collect();
        let mut state = 12345u64;
        for i in (1..n).rev() {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
            p.swap(i, (state >> 33) as usize % (i + 1));
        }
        let shuffled = m.renumbered(&p);
        let sorted = shuffled.clone().with_nodes_in_slabs();
        let xyz = |mesh: &Mesh, conn: &[u32]| -> Vec<[f64; 3]> {
            conn.iter().map(|&k| mesh.nodes[k as usize]).collect()
        };
        for (a, b) in m.elements.iter().zip(&sorted.elements) {
            assert_eq!(xyz(&m, a), xyz(&sorted, b));
        }
        for (name, quads) in &m.face_sets {
            for (a, b) in quads.iter().zip(&sorted.face_sets[name]) {
                assert_eq!(xyz(&m, a), xyz(&sorted, b));
            }
        }
        let slabs = sorted.slabs().unwrap();
        assert_eq!((slabs.axis, slabs.count), (2, 5));
        let k: Vec<usize> = sorted.nodes.iter().map(|x| slabs.of(x[2])).collect();
        assert!(k.windows(2).all(|w| w[0] <= w[1]));
        assert!(
            shuffled
                .nodes
                .iter()
                .map(|x| slabs.of(x[2]))
                .collect::<Vec<_>>()
                != k
        );
    }

    #[test]
    fn box_counts_classes_and_blocks() {
        let m = Mesh::boxed([0.0; 3], [1.0, 2.0, 3.0], [3, 4, 5]);
        assert_eq!(m.nodes.len(), 4 * 5 * 6);
        assert_eq!(m.elements.len(), 60);
        let cls = m.element_classes().unwrap();
        assert_eq!(cls.data.len(), 1);
        let vol: f64 = cls
            .class_of
            .iter()
            .map(|&c| cls.data[c as usize].volume())
            .sum();
        assert!((vol - 6.0).abs() < 1e-12);
        // Slabs of one layer (z is the longest side): even layers, then odd layers.
        let colours = m.element_blocks(1);
        assert_eq!(colours.len(), 2);
        assert_eq!(colours[0].len() + colours[1].len(), 5);
        let mut count = vec![0; m.elements.len()];
        for colour in &colours {
            let mut owner = std::collections::HashMap::new();
            for (b, block) in colour.iter().enumerate() {
                for &e in block {
                    count[e as usize] += 1;
                    for &n in &m.elements[e as usize] {
                        let first = *owner.entry(n).or_insert(b);
                        assert_eq!(first, b, "two blocks of one colour share node {n}");
                    }
                }
            }
        }
        assert!(
            count.iter().all(|&c| c == 1),
            "every element in exactly one block"
        );
        // Blocks hold at least the minimum (merging layers): 12 elements per layer.
        let merged = m.element_blocks(20);
        assert!(merged.iter().flatten().all(|b| b.len() >= 20));
        assert_eq!(merged.iter().flatten().map(Vec::len).sum::<usize>(), 60);
    }

    /// The boundary of an n₁×n₂×n₃ box has 2(n₁n₂ + n₂n₃ + n₁n₃) quads, each pointing away
    /// from the centre of its element; F at the centre is exact for an affine field.
    #[test]
    fn boundary_faces_and_centre_gradient() {
        let mut m = Mesh::boxed([0.0; 3], [1.0, 2.0, 3.0], [3, 4, 5]);
        m.nodes[30][0] += 0.05; // a distorted interior node must not matter
        let faces = m.boundary_faces();
        assert_eq!(faces.len(), 2 * (3 * 4 + 4 * 5 + 3 * 5));
        for (q, e) in &faces {
            let c_face = q.iter().fold([0.0; 3], |acc, &n| {
                let x = m.nodes[n as usize];
                [
                    acc[0] + x[0] / 4.0,
                    acc[1] + x[1] / 4.0,
                    acc[2] + x[2] / 4.0,
                ]
            });
            let c_el = m.elements[*e as usize].iter().fold([0.0; 3], |acc, &n| {
                let x = m.nodes[n as usize];
                [
                    acc[0] + x[0] / 8.0,
                    acc[1] + x[1] / 8.0,
                    acc[2] + x[2] / 8.0,
                ]
            });
            assert!(dot(m.quad_normal(q), sub(c_face, c_el)) > 0.0);
        }
        let g = [[0.1, -0.02, 0.03], [0.05, 0.2, 0.0], [0.0, 0.01, -0.1]];
        let u: Vec<[f64; 3]> = m
            .nodes
            .iter()
            .map(|x| [dot(g[0], *x), dot(g[1], *x), dot(g[2], *x)])
            .collect();
        for e in [0, 17, 59] {
            let f = m.centre_deformation_gradient(e, &u);
            for i in 0..3 {
                for j in 0..3 {
                    let expect = g[i][j] + if i == j { 1.0 } else { 0.0 };
                    assert!(
                        (f[i][j] - expect).abs() < 1e-13,
                        "F[{i}][{j}] of element {e}"
                    );
                }
            }
        }
    }

    #[test]
    fn face_areas_and_normals() {
        let m = Mesh::boxed([0.0; 3], [1.0, 2.0, 3.0], [3, 4, 5]);
        let expect = [
            ("x-", 6.0, [-1.0, 0.0, 0.0]),
            ("y+", 3.0, [0.0, 1.0, 0.0]),
            ("z-", 2.0, [0.0, 0.0, -1.0]),
        ];
        for (name, area, normal) in expect {
            let quads = &m.face_sets[name];
            let w: f64 = m.nodal_areas(quads).iter().map(|p| p.1).sum();
            assert!((w - area).abs() < 1e-12, "{name}: {w}");
            for q in quads {
                let n = m.quad_normal(q);
                assert!(norm(sub(n, normal)) < 1e-12, "{name}: {n:?}");
            }
        }
    }

    #[test]
    fn gradients_reproduce_linear_fields() {
        // Σ_a X_a ⊗ ∇N_a = I at every Gauss point of a distorted element.
        let mut x = HEX_CORNERS.map(|c| [c[0] * 0.5 + 1.0, c[1] * 0.3, c[2] * 0.7]);
        x[6][0] += 0.1;
        x[3][2] -= 0.05;
        let gd = GaussData::new(&x).unwrap();
        for q in 0..8 {
            for i in 0..3 {
                for j in 0..3 {
                    let s: f64 = (0..8).map(|a| x[a][i] * gd.grad[a][j][q]).sum();
                    assert!((s - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12);
                }
            }
        }
    }
}
