//! `[mesh]`: a box (`size`, `cells`, optional `origin`) or a Gmsh file (`file`, optional
//! `scale`), exactly one of the two; and `[[mould]]`, the rigid moulds of any shape: the keys
//! every shape takes, and the shape's own handed to its file (`mould/shapes/`).

use super::check::Check;
use super::error::{num, show, SceneError};
use super::keys;
use super::raw::{RawFaceSet, RawMesh, RawMould};
use crate::mesh::Mesh;
use crate::mould::shapes::{Entry, EntryError, SHAPES, SHAPE_KEYS};
use crate::mould::Mould;
pub(crate) use crate::tunables::MAX_ELEMENTS;

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
    /// `mould[i]`: a rigid mould of any shape ([`crate::mould::shapes`]) and its prescribed
    /// motion. The keys every shape takes are read here ([`RawMould`]); the others must be keys
    /// of the shape (its [`MouldShape::KEYS`](crate::mould::shapes::MouldShape::KEYS)), which its
    /// own parse reads and checks (lengths > 0, axes and normals non-zero, normalised on load).
    /// An angular velocity must turn about some axis.
    pub(super) fn mould_of(&self, key: String, mut m: toml::Table) -> Result<Mould, SceneError> {
        let common: toml::Table = (RawMould::KEYS.iter())
            .filter_map(|k| Some((k.to_string(), m.remove(*k)?)))
            .collect();
        let raw: RawMould =
            serde_path_to_error::deserialize(toml::Value::Table(common)).map_err(|e| {
                let path = e.path().to_string();
                SceneError::Toml {
                    file: self.file.to_string(),
                    key: Some(if path == "." {
                        key.clone()
                    } else {
                        format!("{key}.{path}")
                    }),
                    message: e.into_inner().to_string().trim_end().to_string(),
                }
            })?;
        let Some(spec) = SHAPES.iter().find(|s| s.key == raw.shape) else {
            return Err(self.invalid(
                format!("{key}.shape"),
                format!("{:?}", raw.shape),
                format!("admissible: {}", SHAPE_KEYS.join(", ")),
            ));
        };
        if let Some((k, v)) = m
            .iter()
            .find(|(k, _)| spec.keys.iter().all(|d| d.key != *k))
        {
            let taken: Vec<&str> = spec.keys.iter().map(|d| d.key).collect();
            return Err(self.invalid(
                format!("{key}.{k}"),
                show(v),
                format!(
                    "a {} mould takes {} (and pivot, velocity, angular_velocity)",
                    spec.key,
                    taken.join(", ")
                ),
            ));
        }
        let read = |file: &str| (self.read)(&self.dir.join(file));
        let entry = Entry {
            shape: spec.key,
            keys: spec.keys,
            table: &m,
            read: &read,
        };
        let (shape, frame) = (spec.parse)(&entry).map_err(|e| match e {
            EntryError::Invalid {
                key: k,
                value,
                reason,
            } => self.invalid(format!("{key}.{k}"), value, reason),
            EntryError::Missing { key: k, reason } => self.missing(format!("{key}.{k}"), reason),
        })?;
        let rows = |k: &str, rows: Option<Vec<[f64; 4]>>| -> Result<_, SceneError> {
            rows.map(|r| {
                self.history(
                    &format!("{key}.{k}"),
                    r.iter().map(|r| (r[0], [r[1], r[2], r[3]])).collect(),
                )
            })
            .transpose()
        };
        let angular_velocity = rows("angular_velocity", raw.angular_velocity)?;
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
        Ok(Mould {
            name: raw.name,
            point: frame.point,
            normal: frame.normal,
            velocity: rows("velocity", raw.velocity)?,
            shape,
            angular_velocity,
            pivot: raw.pivot,
        })
    }
}
