//! The checks shared by every section: the file label for errors, ranges, finite numbers, names
//! that must exist (face sets, planes) and piecewise-linear histories.

use super::error::{num, SceneError};
use super::keys::KeyDoc;
use crate::mesh::{dot, sub, Mesh};
use crate::model::{Mould, PiecewiseLinear};
use crate::mould::mould_closest_point;
use std::path::Path;

/// Validation of the raw scene; knows the file label for its errors and the directory that
/// relative paths in the scene (`mesh.file`) are resolved against.
pub(super) struct Check<'a> {
    pub file: &'a str,
    pub dir: &'a Path,
    /// Reads the files the scene names (meshes, mould surfaces) relative to `dir`.
    pub read: crate::gmsh::ReadFile<'a>,
}

impl Check<'_> {
    /// A key whose value is not admissible.
    pub fn invalid(
        &self,
        key: impl Into<String>,
        value: String,
        reason: impl Into<String>,
    ) -> SceneError {
        SceneError::Invalid {
            file: self.file.to_string(),
            key: key.into(),
            value,
            reason: reason.into(),
        }
    }

    /// A key that the rest of the scene requires but which is absent.
    pub fn missing(&self, key: impl Into<String>, reason: impl Into<String>) -> SceneError {
        SceneError::Missing {
            file: self.file.to_string(),
            key: key.into(),
            reason: reason.into(),
        }
    }

    /// `Ok` if `ok`, else an [`SceneError::Invalid`] for the number `value` at `key`.
    pub fn require(
        &self,
        ok: bool,
        key: impl Into<String>,
        value: f64,
        reason: &str,
    ) -> Result<(), SceneError> {
        if ok {
            Ok(())
        } else {
            Err(self.invalid(key, num(value), reason))
        }
    }

    /// `Ok` if the number `value` at `key` is admissible for the key `doc` of the table of keys
    /// ([`KeyDoc::admits`]), else an [`SceneError::Invalid`] that says what is
    /// ([`KeyDoc::must`]).
    pub fn admit(
        &self,
        doc: &KeyDoc,
        key: impl Into<String>,
        value: f64,
    ) -> Result<(), SceneError> {
        if doc.admits(value) {
            Ok(())
        } else {
            Err(self.invalid(key, num(value), doc.must()))
        }
    }

    /// Refuses inf and nan anywhere in the document.
    pub fn finite(&self, key: &str, value: &toml::Value) -> Result<(), SceneError> {
        match value {
            toml::Value::Float(x) if !x.is_finite() => {
                Err(self.invalid(key, num(*x), "must be a finite number"))
            }
            toml::Value::Array(items) => items
                .iter()
                .enumerate()
                .try_for_each(|(i, v)| self.finite(&format!("{key}[{i}]"), v)),
            toml::Value::Table(t) => t
                .iter()
                .try_for_each(|(k, v)| self.finite(&format!("{key}.{k}"), v)),
            _ => Ok(()),
        }
    }

    /// A face set name that exists in the mesh.
    pub fn faces(&self, mesh: &Mesh, key: String, name: &str) -> Result<String, SceneError> {
        if mesh.face_sets.contains_key(name) {
            return Ok(name.to_string());
        }
        let names: Vec<String> = mesh.face_sets.keys().map(|n| format!("`{n}`")).collect();
        Err(self.invalid(
            key,
            format!("{name:?}"),
            format!("no face set of that name; admissible: {}", names.join(", ")),
        ))
    }

    /// The index of the plane named `name`.
    pub fn plane(&self, planes: &[Mould], key: String, name: &str) -> Result<usize, SceneError> {
        if let Some(i) = planes.iter().position(|p| p.name == name) {
            return Ok(i);
        }
        let reason = if planes.is_empty() {
            "no plane or mould of that name: the scene defines no [[plane]] and no [[mould]]"
                .to_string()
        } else {
            let names: Vec<String> = planes.iter().map(|p| format!("`{}`", p.name)).collect();
            format!(
                "no plane or mould of that name; admissible: {}",
                names.join(", ")
            )
        };
        Err(self.invalid(key, format!("{name:?}"), reason))
    }

    /// Refuses the contact face set `faces` of entry `key` (`contact[k]`, plain or adhesive) on
    /// mould `plane` if some of its nodes start inside its
    /// mould beyond the tolerance: gap g₀ = n·(X − p) < −δ at the closest mould point p
    /// ([`mould_closest_point`]), δ = [`contact_start_tolerance`]. Contact acts on velocities
    /// (model §3.1, §3.8): it stops a node from going deeper but never pushes it out, so a
    /// node that starts inside stays inside for the whole run, its contact force taking the
    /// interpenetration as the rest state. The message names the face set, the mould, how many
    /// nodes and how deep.
    pub fn contact_start(
        &self,
        mesh: &Mesh,
        plane: &Mould,
        key: &str,
        faces: &str,
    ) -> Result<(), SceneError> {
        let Some(quads) = mesh.face_sets.get(faces) else {
            return Ok(());
        };
        let tol = contact_start_tolerance(mesh, plane);
        let (mut count, mut deepest) = (0usize, 0.0f64);
        for node in mesh.face_set_nodes(quads) {
            let x = mesh.nodes[node as usize];
            let (p, n) = mould_closest_point(plane, x);
            let depth = -dot(n, sub(x, p));
            if depth > tol {
                count += 1;
                deepest = deepest.max(depth);
            }
        }
        if count == 0 {
            return Ok(());
        }
        Err(self.invalid(
            format!("{key}.faces"),
            format!("{faces:?}"),
            format!(
                "{count} of its nodes start inside mould `{}` by up to {deepest:.4e} m, beyond the tolerance {tol:.4e} m (1e-6 of the body's size): contact acts on velocities and would never push them out; move the face set or the mould so that the face lies on or off the mould",
                plane.name
            ),
        ))
    }

    /// A piecewise-linear history from rows (t, value): ≥ 1 row, t ≥ 0 strictly increasing.
    pub fn history<const N: usize>(
        &self,
        key: &str,
        rows: Vec<(f64, [f64; N])>,
    ) -> Result<PiecewiseLinear<N>, SceneError> {
        if rows.is_empty() {
            return Err(self.invalid(key, "[]".into(), "needs at least one row [t, …]"));
        }
        for (i, row) in rows.iter().enumerate() {
            let t_key = format!("{key}[{i}][0]");
            self.require(row.0 >= 0.0, &t_key, row.0, "times must be ≥ 0 s")?;
            if i > 0 && row.0 <= rows[i - 1].0 {
                return Err(self.invalid(
                    t_key,
                    num(row.0),
                    format!(
                        "times must be strictly increasing (the previous row has t = {} s)",
                        num(rows[i - 1].0)
                    ),
                ));
            }
        }
        Ok(PiecewiseLinear { points: rows })
    }
}

/// Largest depth inside its mould at which a contact node is taken as "on the mould" at
/// t = 0: 1e-6 of the body's size (the largest edge of the mesh's bounding box; a mesh written
/// with six significant digits puts its nodes there), and never below the round-off of
/// positions, 16ε·(largest |coordinate|, the mould's point included).
pub fn contact_start_tolerance(mesh: &Mesh, plane: &Mould) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for x in &mesh.nodes {
        for c in 0..3 {
            (lo[c], hi[c]) = (lo[c].min(x[c]), hi[c].max(x[c]));
        }
    }
    let size = (0..3).fold(0.0f64, |a, c| a.max(hi[c] - lo[c]));
    let scale = (lo.iter().chain(&hi).chain(&plane.point)).fold(0.0f64, |a, x| a.max(x.abs()));
    (1e-6 * size).max(16.0 * f64::EPSILON * scale)
}
