//! The hexahedra of a mesh grouped by shape ([`ElementClasses`]): the reference data of each
//! class computed once (model §1.5), and the tetrahedra's beside them.

use super::Mesh;
use crate::element::hex8::{CentreData, GaussData};
use crate::element::{Element, Hex8};
use std::collections::HashMap;

/// Error in the reference geometry of an element (inverted or degenerate hexahedron).
#[derive(Debug, Clone, thiserror::Error)]
#[error("element {element} is degenerate or inverted in the reference configuration (det J₀ = {det_j0:e} at a Gauss point); check the node order")]
pub struct GeometryError {
    pub element: usize,
    pub det_j0: f64,
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
    /// Per element e: the elements numbered e, …, e + 7 are a row along x of a structured
    /// numbering ([`crate::kernels::row_starts`]), whose lane group the element loops gather
    /// and scatter line by line.
    pub row_start: Vec<bool>,
    /// The tetrahedra's reference data (model §1.13; empty without tetrahedra).
    pub tets: super::TetData,
}

impl Mesh {
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
                    Hex8::reference(&x).map_err(|det_j0| GeometryError { element: e, det_j0 })?;
                centre.push(CentreData::new(&x, &gd));
                data.push(gd);
            }
            class_of.push(class);
        }
        Ok(ElementClasses {
            data,
            centre,
            class_of,
            row_start: super::rows::row_starts(&self.elements),
            tets: self.tet_data()?,
        })
    }
}
