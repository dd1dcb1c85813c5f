//! `[[contact]]` entries: contact with Coulomb friction μ, or, with a `[contact.law]` table,
//! glue that forms on contact (model §8; [`crate::model::Interface::forms_on_contact`]):
//! the same law families as `[interface.law]`, with `mu_inf` (μ(α) = μ_inf(1 − g_N(α)/g_N(0))
//! once glued, paper eq. 21) and an optional `[contact.delay]`, as an `[[interface]]` takes.

use super::assemble::Attachments;
use super::check::Check;
use super::error::SceneError;
use super::keys;
use super::raw::RawContact;
use crate::mesh::Mesh;
use crate::model::{ContactFaces, Interface};

/// What a `[[contact]]` entry becomes in the model.
pub(super) enum ContactEntry {
    /// Contact only ([`crate::model::Model::contacts`]).
    Plain(ContactFaces),
    /// Glue that forms on contact: an interface whose nodes are not glued at t = 0
    /// ([`crate::model::Model::interfaces`], `forms_on_contact = Some(μ)`).
    Adhesive(Interface),
}

impl Check<'_> {
    /// `contact[i]`: its face set and plane, μ ≥ 0, no node starting inside the mould; with
    /// `[contact.law]` also μ_inf ≥ 0, the law (and delay) as for `[[interface]]`, and faces
    /// that look into the mould (the glue must be able to tear). `mu_inf` or `[contact.delay]`
    /// without a law are refused: they describe glue that the entry does not have.
    pub(super) fn contact(
        &self,
        mesh: &Mesh,
        attached: &mut Attachments,
        key: String,
        c: RawContact,
    ) -> Result<ContactEntry, SceneError> {
        let (faces, plane) = self.on_plane(mesh, attached, &key, &c.faces, &c.plane)?;
        self.admit(&keys::CONTACT_MU, format!("{key}.mu"), c.mu)?;
        self.contact_start(mesh, &attached.planes[plane], &key, &faces)?;
        let Some(law) = c.law else {
            if let Some(mu_inf) = c.mu_inf {
                return Err(self.invalid(
                    format!("{key}.mu_inf"),
                    format!("{mu_inf}"),
                    "is the friction of torn glue: it needs the glue's law, a [contact.law] table (without one the entry is contact with friction `mu` only)",
                ));
            }
            if c.delay.is_some() {
                return Err(self.invalid(
                    format!("{key}.delay"),
                    "a table".into(),
                    "delays the glue's damage: it needs the glue's law, a [contact.law] table",
                ));
            }
            self.attach(attached, &faces, plane, key)?;
            return Ok(ContactEntry::Plain(ContactFaces {
                faces,
                plane,
                mu: c.mu,
            }));
        };
        let mu_inf = c.mu_inf.unwrap_or(0.0);
        self.admit(&keys::CONTACT_MU_INF, format!("{key}.mu_inf"), mu_inf)?;
        let law = self.delayed_law(&key, law, c.delay)?;
        self.glued_faces_face_mould(mesh, &attached.planes[plane], &key, &faces)?;
        self.attach(attached, &faces, plane, key)?;
        Ok(ContactEntry::Adhesive(Interface {
            faces,
            plane,
            law,
            mu_inf,
            initial_damage: 0.0,
            forms_on_contact: Some(c.mu),
        }))
    }
}
