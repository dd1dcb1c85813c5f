//! `[mesh]`: a box (`size`, `cells`, optional `origin`) or a Gmsh file (`file`, optional
//! `scale`), exactly one of the two; and `[[mould]]`, the rigid moulds of any shape, some of
//! them triangulated surfaces read from a file.

use super::check::Check;
use super::error::{num, SceneError};
use super::raw::{RawMesh, RawMould};
use crate::mesh::Mesh;
use crate::model::RigidPlane;
use crate::mould::surface::read_stl;
use crate::mould::{Shape, SurfaceMesh};
use std::sync::Arc;

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

/// The keys of `[[mould]]` each shape takes (besides `name`, `shape`, `pivot`, `velocity`,
/// `angular_velocity`).
const SHAPE_KEYS: [(&str, &[&str]); 5] = [
    ("half_space", &["point", "normal"]),
    ("box", &["centre", "size"]),
    ("sphere", &["centre", "radius"]),
    ("cylinder", &["centre", "axis", "radius", "length"]),
    ("surface", &["file", "group", "scale"]),
];

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
        let shapes: Vec<&str> = SHAPE_KEYS.iter().map(|s| s.0).collect();
        let Some((_, keys)) = SHAPE_KEYS.iter().find(|s| s.0 == m.shape) else {
            return Err(self.invalid(
                format!("{key}.shape"),
                format!("{:?}", m.shape),
                format!("admissible: {}", shapes.join(", ")),
            ));
        };
        for (k, v) in given.iter().chain([("scale", m.scale.map(num))].iter()) {
            if let (Some(v), false) = (v, keys.contains(k)) {
                return Err(self.invalid(
                    format!("{key}.{k}"),
                    v.clone(),
                    format!(
                        "a {} mould takes {} (and pivot, velocity, angular_velocity)",
                        m.shape,
                        keys.join(", ")
                    ),
                ));
            }
        }
        let need = |k: &str| {
            self.missing(
                format!("{key}.{k}"),
                format!("a {} mould needs {}", m.shape, keys.join(", ")),
            )
        };
        let positive = |k: &str, x: Option<f64>| -> Result<f64, SceneError> {
            let x = x.ok_or_else(|| need(k))?;
            self.require(x > 0.0, format!("{key}.{k}"), x, "must be > 0 m")?;
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
                    positive(&format!("size[{a}]"), Some(size[a]))?;
                }
                Shape::Box {
                    centre: m.centre.ok_or_else(|| need("centre"))?,
                    half_size: size.map(|c| 0.5 * c),
                }
            }
            "sphere" => Shape::Sphere {
                centre: m.centre.ok_or_else(|| need("centre"))?,
                radius: positive("radius", m.radius)?,
            },
            "cylinder" => Shape::Cylinder {
                centre: m.centre.ok_or_else(|| need("centre"))?,
                axis: self.unit(&format!("{key}.axis"), m.axis.ok_or_else(|| need("axis"))?)?,
                radius: positive("radius", m.radius)?,
                half_length: 0.5 * positive("length", m.length)?,
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
        self.require(
            scale > 0.0,
            format!("{key}.scale"),
            scale,
            "must be > 0 (metres per file unit)",
        )?;
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
