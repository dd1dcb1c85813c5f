//! A triangulated surface read from `file` (STL, or a Gmsh `.msh` 2-D physical group `group`),
//! times `scale` (model §7.1): its closest point by parry's BVH, with the angle-weighted
//! pseudo-normal of the feature hit ([`SurfaceMesh`], `mould/surface.rs`).

use super::{normalise, Entry, EntryError, Frame, MouldMesh, MouldShape};
use crate::interface::family::Range;
use crate::keydoc::KeyDoc;
use crate::mesh::{cross, sub};
use crate::mould::surface::read_stl;
use crate::mould::{Projection, SurfaceMesh};
use std::sync::Arc;

/// A checked triangulated surface, shared by the clones of the model.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(transparent)]
pub struct Surface(pub Arc<SurfaceMesh>);

impl std::ops::Deref for Surface {
    type Target = SurfaceMesh;
    fn deref(&self) -> &SurfaceMesh {
        &self.0
    }
}

impl From<Arc<SurfaceMesh>> for Surface {
    fn from(s: Arc<SurfaceMesh>) -> Self {
        Surface(s)
    }
}

impl From<SurfaceMesh> for Surface {
    fn from(s: SurfaceMesh) -> Self {
        Surface(Arc::new(s))
    }
}

impl MouldShape for Surface {
    const ABOUT: &'static str = "a triangulated surface read from `file` (STL, or a Gmsh `.msh` \
                                 2-D physical group `group`), times `scale`";
    const KEYS: &'static [KeyDoc] = &[
        KeyDoc::new(
            "file",
            "string",
            "",
            "the triangles: an STL (ASCII or binary) or a Gmsh `.msh`, relative to the scene \
             file's directory",
        )
        .admissible(
            "triangles counter-clockwise seen from the solid (out of the mould), consistent, \
             not degenerate",
        ),
        KeyDoc::new(
            "group",
            "string",
            "",
            "the 2-D physical group (triangles or quadrangles) of a `.msh` file",
        )
        .default_text("required for a `.msh` file; refused for an STL")
        .admissible("a 2-D physical group of the file"),
        KeyDoc::new("scale", "number", "–", "metres per file unit")
            .default_number(1.0)
            .range(Range::above(0.0)),
    ];

    /// STL (ASCII or binary; no `group`) or a Gmsh `.msh` 2-D physical group `group`, times
    /// `scale`, checked by [`SurfaceMesh::new`]. Its frame is the origin.
    fn parse(e: &Entry<'_>) -> Result<(Self, Frame), EntryError> {
        let file = e.string_opt("file")?.ok_or_else(|| {
            e.missing_because(
                "file",
                "a surface mould needs `file` (an STL or a Gmsh .msh with `group`)",
            )
        })?;
        let scale = e.number_opt("scale")?.unwrap_or(1.0);
        let group = e.string_opt("group")?;
        let bad = |m: String| e.invalid("file", format!("{file:?}"), m);
        let bytes = (e.read)(file).map_err(|err| bad(format!("cannot read it: {err}")))?;
        let msh = file.to_ascii_lowercase().ends_with(".msh");
        let (vertices, triangles, element): (_, _, std::boxed::Box<dyn Fn(usize) -> String>) =
            if msh {
                let group = group.ok_or_else(|| {
                    e.missing_because(
                        "group",
                        "a .msh surface needs the name of its 2-D physical group",
                    )
                })?;
                let (v, t, tags) = crate::gmsh::read_surface_group(&bytes, file, group)
                    .map_err(|err| bad(err.to_string()))?;
                (
                    v,
                    t,
                    std::boxed::Box::new(move |k| format!("element {}", tags[k])),
                )
            } else {
                if let Some(g) = group {
                    return Err(e.invalid(
                        "group",
                        format!("{g:?}"),
                        "an STL file has no groups (`group` is for a Gmsh .msh)",
                    ));
                }
                let (v, t) = read_stl(&bytes, file).map_err(|err| bad(err.message))?;
                (v, t, std::boxed::Box::new(|k| format!("facet {k}")))
            };
        let group = group.map(str::to_string);
        let s = SurfaceMesh::new(file, group, scale, vertices, triangles, &*element)
            .map_err(|err| bad(err.message))?;
        Ok((s.into(), Frame::at([0.0; 3])))
    }

    /// [`SurfaceMesh::project`].
    fn project(&self, _: [f64; 3], _: [f64; 3], x: [f64; 3]) -> Projection {
        self.0.project(x)
    }

    /// Its own triangles with parry's angle-weighted vertex pseudo-normals.
    fn drawing(&self) -> MouldMesh {
        let mut mesh = MouldMesh::default();
        let tri = &self.mesh;
        mesh.vertices = tri.vertices().iter().map(|p| [p.x, p.y, p.z]).collect();
        mesh.triangles = tri.indices().to_vec();
        mesh.normals = match tri.pseudo_normals() {
            Some(pn) => pn
                .vertices_pseudo_normal
                .iter()
                .map(|n| normalise([n.x, n.y, n.z]))
                .collect(),
            // Without pseudo-normals (not built oriented): the area-weighted face normals.
            None => {
                let mut acc = vec![[0.0; 3]; mesh.vertices.len()];
                for t in &mesh.triangles {
                    let [a, b, c] = t.map(|v| mesh.vertices[v as usize]);
                    let n = cross(sub(b, a), sub(c, a));
                    for &v in t {
                        for i in 0..3 {
                            acc[v as usize][i] += n[i];
                        }
                    }
                }
                acc.into_iter().map(normalise).collect()
            }
        };
        mesh
    }
}

#[cfg(test)]
mod tests {
    use super::super::{parse_for_test, Shape};
    use super::*;

    /// A unit square of two triangles facing +z: a point above it projects straight down
    /// (gap = its height, normal +z), and the drawing is its two triangles wound along +z.
    /// Without a `file` the message says what a surface needs.
    #[test]
    fn a_surface_projects_on_its_triangles() {
        let v = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let s = SurfaceMesh::new("square", None, 1.0, v, vec![[0, 1, 2], [0, 2, 3]], &|k| {
            format!("triangle {k}")
        })
        .unwrap();
        let shape = Shape::Surface(s.into());
        let x = [0.25, 0.5, 0.5];
        let pr = shape.project([0.0; 3], [0.0; 3], x);
        assert_eq!((pr.normal, pr.gap(x)), ([0.0, 0.0, 1.0], 0.5));
        let m = shape.drawing();
        assert_eq!((m.vertices.len(), m.triangles.len()), (4, 2));
        assert!(m.normals.iter().all(|n| *n == [0.0, 0.0, 1.0]));
        let e = parse_for_test("surface", "scale = 2").unwrap_err();
        assert!(matches!(e, EntryError::Missing { key, .. } if key == "file"));
    }
}
