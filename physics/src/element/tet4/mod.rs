//! The linear 4-node tetrahedron (model §1.13): its topology (faces, edges) and the reference
//! quantities of one element — the constant shape-function gradients ∇ₓNₐ and det D = 6V.
//!
//! Node numbering: Gmsh's, with a positive volume V = det[X₁ − X₀, X₂ − X₀, X₃ − X₀]/6.

/// Local faces of a tetrahedron, each outward (counter-clockwise seen from outside): the faces
/// opposite nodes 3, 2, 0 and 1.
pub const TET_FACES: [[usize; 3]; 4] = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];

/// The 6 edges of a tetrahedron (local node pairs).
pub const TET_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];

/// det[X₁ − X₀, X₂ − X₀, X₃ − X₀] = 6V of a tetrahedron, and its inverse matrix D⁻¹ of
/// D = [X₁ − X₀ | X₂ − X₀ | X₃ − X₀] (columns), from which ∇ₓNₐ are the rows of D⁻¹
/// (a = 1, 2, 3) and ∇ₓN₀ = −Σ of them: X = X₀ + D ξ, N₀ = 1 − ξ₁ − ξ₂ − ξ₃, Nₖ = ξₖ, so
/// ∇ₓNₐ = D⁻ᵀ ∂Nₐ/∂ξ.
pub fn tet_gradients(x: &[[f64; 3]; 4]) -> (f64, [[f64; 3]; 4]) {
    let d = nalgebra::Matrix3::from_fn(|i, k| x[k + 1][i] - x[0][i]);
    let det = d.determinant();
    let inv = d
        .try_inverse()
        .unwrap_or_else(|| nalgebra::Matrix3::from_element(f64::NAN));
    let mut g = [[0.0; 3]; 4];
    for k in 0..3 {
        for j in 0..3 {
            g[k + 1][j] = inv[(k, j)];
            g[0][j] -= inv[(k, j)];
        }
    }
    (det, g)
}

/// F = I + Σₐ uₐ ⊗ ∇ₓNₐ of a tetrahedron (model §1.13), constant over it.
#[inline]
pub fn tet_deformation_gradient(g: &[[f64; 3]; 4], ue: &[[f64; 3]; 4]) -> [[f64; 3]; 3] {
    let mut f = [[0.0; 3]; 3];
    for (i, row) in f.iter_mut().enumerate() {
        row[i] = 1.0;
        for (j, fij) in row.iter_mut().enumerate() {
            for a in 0..4 {
                *fij += ue[a][i] * g[a][j];
            }
        }
    }
    f
}

/// The linear 4-node tetrahedron, Gmsh's node order with a positive volume.
pub struct Tet4;

/// The reference data of one tetrahedron: ∇ₓNₐ (constant over it) [1/m] and its volume [m³].
#[derive(Debug, Clone, Copy)]
pub struct TetReference {
    pub grad: [[f64; 3]; 4],
    pub volume: f64,
}

impl super::Element for Tet4 {
    const NAME: &'static str = "4-node tetrahedron";
    const NODES: usize = 4;
    const GMSH_TYPE: i32 = 4;
    const VTK_TYPE: u8 = 10;
    const FACES: &'static [&'static [usize]] =
        &[&TET_FACES[0], &TET_FACES[1], &TET_FACES[2], &TET_FACES[3]];
    const EDGES: &'static [(usize, usize)] = &TET_EDGES;
    type Reference = TetReference;

    /// [`tet_gradients`]: det D = 6V must be positive.
    fn reference(x: &[[f64; 3]]) -> Result<TetReference, f64> {
        let (det, grad) = tet_gradients(&std::array::from_fn(|a| x[a]));
        if !(det > 0.0) {
            return Err(det);
        }
        Ok(TetReference {
            grad,
            volume: det / 6.0,
        })
    }

    /// Vₐ = V/4 (model §1.13).
    fn lumped_volumes(r: &TetReference, out: &mut [f64]) {
        out.fill(0.25 * r.volume);
    }
}
