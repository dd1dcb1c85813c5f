//! `[mesh]`: a box (`size`, `cells`, optional `origin`) or a Gmsh file (`file`, optional
//! `scale`), exactly one of the two; and `[[mould]]`, the rigid moulds of any shape, some of
//! them triangulated surfaces read from a file.

use super::check::Check;
use super::error::{num, SceneError};
use super::keys::{self, KeyDoc, ShapeDoc, MOULD_SHAPES};
use super::raw::{RawFaceSet, RawMesh, RawMould};
use crate::mesh::Mesh;
use crate::model::RigidPlane;
use crate::mould::surface::read_stl;
use crate::mould::{Shape, SurfaceMesh};
use std::sync::Arc;

/// Largest mesh a scene may ask for, in elements.
pub(super) const MAX_ELEMENTS: u128 = 50_000_000;

/// The two forms, for messages.
const FORMS: &str = "a mesh is either a Gmsh file (`file`, optional `scale`) or a box \
                     (`size` and `cells`, optional `origin`)";

impl Check<'_> {
    /// The `[mesh]` section: a Gmsh file or a box, and the face sets `[[mesh.face_set]]`
    /// selects from its face sets.
    pub(super) fn mesh(&self, m: &RawMesh) -> Result<Mesh, SceneError> {
        let mut mesh = match &m.file {
            Some(file) => self.gmsh_mesh(m, file),
            None => self.box_mesh(m),
        }?;
        if let Some(s) = &m.split {
            self.split(&mut mesh, s)?;
        }
        for (i, fs) in m.face_set.iter().enumerate() {
            let quads = self.face_subset(&mesh, &format!("mesh.face_set[{i}]"), fs)?;
            mesh.face_sets.insert(fs.name.clone(), quads);
        }
        Ok(mesh)
    }

    /// `mesh.face_set[i]`: the faces of the face set `of` whose centre (the mean of its four
    /// nodes) lies in the box `min` ≤ x ≤ `max` (each component, bounds included). The name
    /// must be new, `of` a face set of the mesh (or one selected before), `min` ≤ `max`, and
    /// the selection not empty.
    fn face_subset(
        &self,
        mesh: &Mesh,
        key: &str,
        fs: &RawFaceSet,
    ) -> Result<Vec<[u32; 4]>, SceneError> {
        if mesh.face_sets.contains_key(&fs.name) {
            return Err(self.invalid(
                format!("{key}.name"),
                format!("{:?}", fs.name),
                "a face set of that name exists already: choose a new name",
            ));
        }
        let of = self.faces(mesh, format!("{key}.of"), &fs.of)?;
        if let Some(c) = (0..3).find(|&c| fs.min[c] > fs.max[c]) {
            return Err(self.invalid(
                format!("{key}.min"),
                format!("{:?}", fs.min),
                format!(
                    "component {c} ({}) is above `max`'s ({}): the box needs min ≤ max",
                    num(fs.min[c]),
                    num(fs.max[c])
                ),
            ));
        }
        let centre = |q: &[u32; 4]| -> [f64; 3] {
            std::array::from_fn(|c| q.iter().map(|&n| mesh.nodes[n as usize][c]).sum::<f64>() / 4.0)
        };
        let inside = |x: [f64; 3]| (0..3).all(|c| fs.min[c] <= x[c] && x[c] <= fs.max[c]);
        let quads: Vec<[u32; 4]> = (mesh.face_sets[&of].iter())
            .filter(|q| inside(centre(q)))
            .copied()
            .collect();
        if quads.is_empty() {
            return Err(self.invalid(
                format!("{key}.max"),
                format!("{:?}", fs.max),
                format!(
                    "no face of `{of}` has its centre in the box from `min` {:?} to `max` {:?}: \
                     widen the box over the faces to select",
                    fs.min, fs.max
                ),
            ));
        }
        Ok(quads)
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
        self.admit(&keys::MESH_SCALE, "mesh.scale", scale)?;
        let path = self.dir.join(file);
        let mut mesh = crate::gmsh::read_msh_with(&path, self.read)
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
            self.admit(&keys::MESH_SIZE, format!("mesh.size[{a}]"), size[a])?;
            if !keys::MESH_CELLS.admits(cells[a] as f64) {
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

impl Check<'_> {
    /// `mould[i]`: a rigid mould of any shape ([`crate::mould`]) and its prescribed motion.
    /// Every key the shape needs must be there and no key of another shape; lengths > 0, axes
    /// and normals non-zero (normalised on load), an angular velocity that turns about some axis.
    pub(super) fn mould_of(&self, key: String, m: RawMould) -> Result<RigidPlane, SceneError> {
        let given: [(&str, Option<String>); 9] = [
            ("point", m.point.map(|v| format!("{v:?}"))),
            ("normal", m.normal.map(|v| format!("{v:?}"))),
            ("centre", m.centre.map(|v| format!("{v:?}"))),
            ("size", m.size.map(|v| format!("{v:?}"))),
            ("radius", m.radius.map(num)),
            ("axis", m.axis.map(|v| format!("{v:?}"))),
            ("length", m.length.map(num)),
            ("file", m.file.as_ref().map(|f| format!("{f:?}"))),
            ("group", m.group.as_ref().map(|g| format!("{g:?}"))),
        ];
        let shapes: Vec<&str> = MOULD_SHAPES.iter().map(|s| s.shape).collect();
        let Some(ShapeDoc { keys: taken, .. }) = MOULD_SHAPES.iter().find(|s| s.shape == m.shape)
        else {
            return Err(self.invalid(
                format!("{key}.shape"),
                format!("{:?}", m.shape),
                format!("admissible: {}", shapes.join(", ")),
            ));
        };
        for (k, v) in given.iter().chain([("scale", m.scale.map(num))].iter()) {
            if let (Some(v), false) = (v, taken.contains(k)) {
                return Err(self.invalid(
                    format!("{key}.{k}"),
                    v.clone(),
                    format!(
                        "a {} mould takes {} (and pivot, velocity, angular_velocity)",
                        m.shape,
                        taken.join(", ")
                    ),
                ));
            }
        }
        let need = |k: &str| {
            self.missing(
                format!("{key}.{k}"),
                format!("a {} mould needs {}", m.shape, taken.join(", ")),
            )
        };
        let positive = |doc: &KeyDoc, k: &str, x: Option<f64>| -> Result<f64, SceneError> {
            let x = x.ok_or_else(|| need(k))?;
            self.admit(doc, format!("{key}.{k}"), x)?;
            Ok(x)
        };
        let (mut point, mut normal) = ([0.0; 3], [0.0; 3]);
        let shape = match m.shape.as_str() {
            "half_space" => {
                point = m.point.ok_or_else(|| need("point"))?;
                normal = self.unit(
                    &format!("{key}.normal"),
                    m.normal.ok_or_else(|| need("normal"))?,
                )?;
                Shape::HalfSpace
            }
            "box" => {
                let size = m.size.ok_or_else(|| need("size"))?;
                for a in 0..3 {
                    positive(&keys::MOULD_SIZE, &format!("size[{a}]"), Some(size[a]))?;
                }
                Shape::Box {
                    centre: m.centre.ok_or_else(|| need("centre"))?,
                    half_size: size.map(|c| 0.5 * c),
                }
            }
            "sphere" => Shape::Sphere {
                centre: m.centre.ok_or_else(|| need("centre"))?,
                radius: positive(&keys::MOULD_RADIUS, "radius", m.radius)?,
            },
            "cylinder" => Shape::Cylinder {
                centre: m.centre.ok_or_else(|| need("centre"))?,
                axis: self.unit(&format!("{key}.axis"), m.axis.ok_or_else(|| need("axis"))?)?,
                radius: positive(&keys::MOULD_RADIUS, "radius", m.radius)?,
                half_length: 0.5 * positive(&keys::MOULD_LENGTH, "length", m.length)?,
            },
            _ => Shape::Surface(Arc::new(self.surface(&key, &m)?)),
        };
        let centre = m.centre.unwrap_or(point);
        let rows = |k: &str, rows: Option<Vec<[f64; 4]>>| -> Result<_, SceneError> {
            rows.map(|r| {
                self.history(
                    &format!("{key}.{k}"),
                    r.iter().map(|r| (r[0], [r[1], r[2], r[3]])).collect(),
                )
            })
            .transpose()
        };
        let angular_velocity = rows("angular_velocity", m.angular_velocity)?;
        if let Some(w) = angular_velocity
            .as_ref()
            .filter(|w| w.points.iter().all(|p| p.1 == [0.0; 3]))
        {
            return Err(self.invalid(
                format!("{key}.angular_velocity"),
                format!("{:?}", w.points.iter().map(|p| [p.0, p.1[0], p.1[1], p.1[2]]).collect::<Vec<_>>()),
                "every row is [t, 0, 0, 0]: no rotation axis; leave angular_velocity out for a mould that does not turn",
            ));
        }
        Ok(RigidPlane {
            name: m.name,
            point: if matches!(shape, Shape::HalfSpace) {
                point
            } else {
                centre
            },
            normal,
            velocity: rows("velocity", m.velocity)?,
            shape,
            angular_velocity,
            pivot: m.pivot,
        })
    }

    /// A triangulated surface from `file` (relative to the scene's directory): STL (ASCII or
    /// binary; no `group`) or a Gmsh `.msh` 2-D physical group `group`, times `scale`.
    fn surface(&self, key: &str, m: &RawMould) -> Result<SurfaceMesh, SceneError> {
        let file = m.file.as_deref().ok_or_else(|| {
            self.missing(
                format!("{key}.file"),
                "a surface mould needs `file` (an STL or a Gmsh .msh with `group`)",
            )
        })?;
        let scale = m.scale.unwrap_or(1.0);
        self.admit(&keys::MOULD_SCALE, format!("{key}.scale"), scale)?;
        let bad = |e: String| self.invalid(format!("{key}.file"), format!("{file:?}"), e);
        let bytes =
            (self.read)(&self.dir.join(file)).map_err(|e| bad(format!("cannot read it: {e}")))?;
        let msh = file.to_ascii_lowercase().ends_with(".msh");
        let (vertices, triangles, element): (_, _, Box<dyn Fn(usize) -> String>) = if msh {
            let group = m.group.as_deref().ok_or_else(|| {
                self.missing(
                    format!("{key}.group"),
                    "a .msh surface needs the name of its 2-D physical group",
                )
            })?;
            let (v, t, tags) = crate::gmsh::read_surface_group(&bytes, file, group)
                .map_err(|e| bad(e.to_string()))?;
            (v, t, Box::new(move |k| format!("element {}", tags[k])))
        } else {
            if let Some(g) = &m.group {
                return Err(self.invalid(
                    format!("{key}.group"),
                    format!("{g:?}"),
                    "an STL file has no groups (`group` is for a Gmsh .msh)",
                ));
            }
            let (v, t) = read_stl(&bytes, file).map_err(|e| bad(e.message))?;
            (v, t, Box::new(|k| format!("facet {k}")))
        };
        SurfaceMesh::new(file, m.group.clone(), scale, vertices, triangles, &*element)
            .map_err(|e| bad(e.message))
    }
}
