//! `[mesh.split]`, the mesh cut in two along a plane of its faces, and `[[bond]]`, two face sets
//! of the body joined node to node by a cohesive law (model §7.8).

use super::check::Check;
use super::error::{num, SceneError};
use super::keys;
use super::raw::{RawBond, RawSplit};
use crate::mesh::Mesh;
use crate::model::Bond;

impl Check<'_> {
    /// `mesh.split`: `axis` (x, y or z, checked by serde) and `at` a plane of element faces strictly inside
    /// the mesh ([`Mesh::split`]), which adds the face sets `split-` and `split+`.
    pub(super) fn split(&self, mesh: &mut Mesh, s: &RawSplit) -> Result<(), SceneError> {
        let axis = s.axis as usize;
        if !s.at.is_finite() {
            return Err(self.invalid("mesh.split.at", num(s.at), "must be a finite number"));
        }
        mesh.split(axis, s.at)
            .map(|_| ())
            .map_err(|e| self.invalid("mesh.split.at", num(s.at), e))
    }

    /// `bond[i]`: two face sets of the mesh whose nodes pair up by position
    /// ([`Mesh::pairs`]), μ_inf ≥ 0, α₀ ≥ 0, and its law (no delay).
    pub(super) fn bond(&self, mesh: &Mesh, key: String, b: RawBond) -> Result<Bond, SceneError> {
        let faces = self.faces(mesh, format!("{key}.faces"), &b.faces)?;
        let to = self.faces(mesh, format!("{key}.to"), &b.to)?;
        self.admit(&keys::INTERFACE_MU_INF, format!("{key}.mu_inf"), b.mu_inf)?;
        self.admit(
            &keys::INITIAL_DAMAGE,
            format!("{key}.initial_damage"),
            b.initial_damage,
        )?;
        mesh.pairs(&mesh.face_sets[&faces], &mesh.face_sets[&to])
            .map_err(|e| {
                self.invalid(
                    format!("{key}.to"),
                    format!("{to:?}"),
                    format!("cannot pair the nodes of `{faces}` with those of `{to}`: {e}"),
                )
            })?;
        let law = self.delayed_law(&key, b.law, None)?;
        Ok(Bond {
            faces,
            to,
            law,
            mu_inf: b.mu_inf,
            initial_damage: b.initial_damage,
        })
    }
}
