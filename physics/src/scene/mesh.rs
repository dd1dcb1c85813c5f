//! `[mesh]`: a box (`size`, `cells`, optional `origin`) or a Gmsh file (`file`, optional
//! `scale`), exactly one of the two.

use super::check::Check;
use super::error::{num, SceneError};
use super::raw::RawMesh;
use crate::mesh::Mesh;

/// Largest mesh a scene may ask for, in elements.
const MAX_ELEMENTS: u128 = 50_000_000;

/// The two forms, for messages.
const FORMS: &str = "a mesh is either a Gmsh file (`file`, optional `scale`) or a box \
                     (`size` and `cells`, optional `origin`)";

impl Check<'_> {
    /// The `[mesh]` section: a Gmsh file or a box.
    pub(super) fn mesh(&self, m: &RawMesh) -> Result<Mesh, SceneError> {
        match &m.file {
            Some(file) => self.gmsh_mesh(m, file),
            None => self.box_mesh(m),
        }
    }

    /// A Gmsh file read by [`crate::gmsh::read_msh`] (its path relative to the scene file's
    /// directory) with its coordinates multiplied by `scale`; no box key.
    fn gmsh_mesh(&self, m: &RawMesh, file: &str) -> Result<Mesh, SceneError> {
        let box_keys = [
            ("origin", m.origin.map(|v| format!("{v:?}"))),
            ("size", m.size.map(|v| format!("{v:?}"))),
            ("cells", m.cells.map(|v| format!("{v:?}"))),
        ];
        if let Some((k, Some(v))) = box_keys.into_iter().find(|k| k.1.is_some()) {
            return Err(self.invalid(
                format!("mesh.{k}"),
                v,
                format!("`mesh.file` is given, so `mesh.{k}` cannot be: {FORMS}"),
            ));
        }
        let scale = m.scale.unwrap_or(1.0);
        self.require(
            scale > 0.0,
            "mesh.scale",
            scale,
            "must be > 0 (metres per mesh unit)",
        )?;
        let path = self.dir.join(file);
        let mut mesh = crate::gmsh::read_msh(&path)
            .map_err(|e| self.invalid("mesh.file", format!("{file:?}"), e.to_string()))?;
        if scale != 1.0 {
            for x in &mut mesh.nodes {
                *x = x.map(|c| c * scale);
            }
        }
        Ok(mesh)
    }

    /// A box of `cells` hexahedra over `size` from `origin`, at most [`MAX_ELEMENTS`]; no
    /// `scale`.
    fn box_mesh(&self, m: &RawMesh) -> Result<Mesh, SceneError> {
        if let Some(scale) = m.scale {
            return Err(self.invalid(
                "mesh.scale",
                num(scale),
                format!("applies to a `mesh.file` only (a box's `size` is in metres): {FORMS}"),
            ));
        }
        let missing = |key: &str| {
            self.missing(
                format!("mesh.{key}"),
                format!("a box mesh needs `size` and `cells`; {FORMS}"),
            )
        };
        let size = m.size.ok_or_else(|| missing("size"))?;
        let cells = m.cells.ok_or_else(|| missing("cells"))?;
        for a in 0..3 {
            let key = format!("mesh.size[{a}]");
            self.require(size[a] > 0.0, key, size[a], "must be > 0 m")?;
            if cells[a] < 1 {
                return Err(self.invalid(
                    format!("mesh.cells[{a}]"),
                    cells[a].to_string(),
                    "must be an integer ≥ 1",
                ));
            }
        }
        let elements: u128 = cells.iter().map(|&c| c as u128).product();
        if elements > MAX_ELEMENTS {
            return Err(self.invalid(
                "mesh.cells",
                format!("{cells:?}"),
                format!("{elements} elements: at most {MAX_ELEMENTS} are admissible"),
            ));
        }
        Ok(Mesh::boxed(m.origin.unwrap_or_default(), size, cells))
    }
}
