//! The model from the raw scene: each section checked and turned into the model's types, in the
//! order of the format (end time, mesh, material, scheme, planes, interfaces, contacts, loads);
//! the first error found is returned.

use super::adhesion::ContactEntry;
use super::check::Check;
use super::error::{num, SceneError};
use super::keys;
use super::raw::{
    RawBulkViscosity, RawDisplacement, RawInterface, RawMassScaling, RawPlane, RawScene, RawScheme,
    RawTraction,
};
use crate::mesh::{dot, Mesh};
use crate::model::{
    BulkViscosity, Interface, MassScaling, Model, Mould, PiecewiseLinear, PrescribedDisplacement,
    SchemeParams, StartOffset, Traction,
};
use crate::mould::mould_closest_point;

/// The (face set, plane) pairs attached so far, with the key that attached each: a face set
/// meets a plane through one `[[interface]]` or one `[[contact]]`.
pub(super) struct Attachments<'p> {
    pub planes: &'p [Mould],
    pub pairs: Vec<(String, usize, String)>,
}

impl Check<'_> {
    pub(super) fn model(&self, raw: RawScene, default_name: String) -> Result<Model, SceneError> {
        self.admit(&keys::END_TIME, "end_time", raw.end_time)?;
        let mesh = self.mesh(&raw.mesh)?;
        let material = self.material(&raw.material)?;
        let mut scheme = self.scheme(&raw.scheme)?;
        scheme.mass_scaling = match &raw.mass_scaling {
            None => None,
            Some(ms) => Some(self.mass_scaling(ms)?),
        };
        scheme.bulk_viscosity = match &raw.bulk_viscosity {
            None => None,
            Some(bv) => Some(self.bulk_viscosity(bv)?),
        };
        let mut planes = each(raw.plane, "plane", |key, p| self.plane_of(key, p))?;
        let n_planes = planes.len();
        planes.extend(each(raw.mould, "mould", |key, m| self.mould_of(key, m))?);
        let key_of = |i: usize| match i.checked_sub(n_planes) {
            None => format!("plane[{i}]"),
            Some(j) => format!("mould[{j}]"),
        };
        for (i, p) in planes.iter().enumerate() {
            if let Some(j) = planes[..i].iter().position(|q| q.name == p.name) {
                return Err(self.invalid(
                    format!("{}.name", key_of(i)),
                    format!("{:?}", p.name),
                    format!(
                        "plane and mould names must be unique (`{}` has it already)",
                        key_of(j)
                    ),
                ));
            }
        }
        let mut attached = Attachments {
            planes: &planes,
            pairs: vec![],
        };
        let interfaces = each(raw.interface, "interface", |key, it| {
            self.interface(&mesh, &mut attached, key, it)
        })?;
        let (mut interfaces, mut contacts) = (interfaces, vec![]);
        for entry in each(raw.contact, "contact", |key, c| {
            self.contact(&mesh, &mut attached, key, c)
        })? {
            match entry {
                ContactEntry::Plain(c) => contacts.push(c),
                ContactEntry::Adhesive(itf) => interfaces.push(itf),
            }
        }
        let bonds = each(raw.bond, "bond", |key, b| self.bond(&mesh, key, b))?;
        let displacements = each(raw.displacement, "displacement", |key, d| {
            self.displacement(&mesh, key, d, raw.end_time)
        })?;
        let tractions = each(raw.traction, "traction", |key, t| {
            self.traction(&mesh, key, t)
        })?;
        let model = Model {
            name: raw.name.unwrap_or(default_name),
            description: raw.description,
            mesh,
            material,
            gravity: raw.gravity,
            initial_velocity: raw.initial_velocity,
            initial_angular_velocity: raw.initial_angular_velocity,
            moulds: planes,
            interfaces,
            contacts,
            bonds,
            displacements,
            tractions,
            scheme,
            end_time: raw.end_time,
        };
        for k in 0..model.interfaces.len() {
            self.glued_start(&model, k)?;
        }
        Ok(model)
    }

    /// Refuses glued nodes of interface `k` that start inside their mould by more than the
    /// tolerance ([`StartOffset`]): their glue would start compressed, pushing them out with a
    /// force the scene does not say, and the contact would see them as having gone through.
    fn glued_start(&self, model: &Model, k: usize) -> Result<(), SceneError> {
        let Some(o) = StartOffset::of(model, k).filter(|o| o.deep_nodes > 0) else {
            return Ok(());
        };
        Err(self.invalid(
            format!("interface[{k}].faces"),
            format!("{:?}", o.faces),
            format!(
                "{} glued nodes start inside mould `{}` by up to {:.4e} m, beyond the tolerance {:.4e} m (1e-3 of the law's α_e): move the face set or the mould so that the glued face lies on the mould",
                o.deep_nodes, o.mould, o.deepest, o.tolerance
            ),
        ))
    }

    /// Refuses a glued face set that faces the same way as its mould: every face's outward
    /// normal must point into the mould, against the mould's normal there (which points into
    /// the solid). A face whose outward normal has a positive component along the mould normal
    /// at its centre (beyond 1e-6, the round-off of unit vectors) looks away from the mould: its
    /// nodes could only be pulled off the mould by moving into the body, and the glue could
    /// never tear.
    pub(super) fn glued_faces_face_mould(
        &self,
        mesh: &Mesh,
        plane: &Mould,
        key: &str,
        faces: &str,
    ) -> Result<(), SceneError> {
        let quads = &mesh.face_sets[faces];
        let flipped = |q: &[u32; 4]| {
            let centre: [f64; 3] = std::array::from_fn(|c| {
                q.iter().map(|&n| mesh.nodes[n as usize][c]).sum::<f64>() / 4.0
            });
            let (_, n_mould) = mould_closest_point(plane, centre);
            let n_face = mesh.quad_normal(q);
            (dot(n_face, n_mould) > 1e-6).then_some((n_face, n_mould))
        };
        let bad: Vec<_> = quads.iter().filter_map(flipped).collect();
        let Some(&(n_face, n_mould)) = bad.first() else {
            return Ok(());
        };
        // (+ 0.0 prints −0 as 0.)
        let v = |x: [f64; 3]| format!("[{:.4}, {:.4}, {:.4}]", x[0] + 0.0, x[1] + 0.0, x[2] + 0.0);
        Err(self.invalid(
            format!("{key}.faces"),
            format!("{faces:?}"),
            format!(
                "{} of its {} faces look away from mould `{}`: outward normal {} (first such face) against the mould normal {}, which points into the solid; a glued face's outward normal must point into the mould (opposite to the mould normal), else the glue can never tear. Glue the opposite face set, or flip the mould's normal",
                bad.len(),
                quads.len(),
                plane.name,
                v(n_face),
                v(n_mould)
            ),
        ))
    }

    /// `[scheme]`: the defaults of [`SchemeParams`] for what is left out, then the ranges.
    fn scheme(&self, s: &RawScheme) -> Result<SchemeParams, SceneError> {
        let d = SchemeParams::default();
        let scheme = SchemeParams {
            time_step_factor: s.time_step_factor.unwrap_or(d.time_step_factor),
            h_crit_update_interval: s.h_crit_update_interval.unwrap_or(d.h_crit_update_interval),
            h_crit_tolerance: s.h_crit_tolerance.unwrap_or(d.h_crit_tolerance),
            energy_growth_limit: s.energy_growth_limit.unwrap_or(d.energy_growth_limit),
            integration: s.integration.unwrap_or(d.integration),
            hourglass_coefficient: s.hourglass_coefficient.unwrap_or(d.hourglass_coefficient),
            // From `[mass_scaling]`, by the caller.
            mass_scaling: None,
            bulk_viscosity: None,
        };
        let checked = [
            (&keys::TIME_STEP_FACTOR, scheme.time_step_factor),
            (&keys::H_CRIT_TOLERANCE, scheme.h_crit_tolerance),
            (&keys::ENERGY_GROWTH_LIMIT, scheme.energy_growth_limit),
            (&keys::HOURGLASS_COEFFICIENT, scheme.hourglass_coefficient),
        ];
        for (doc, value) in checked {
            self.admit(doc, format!("scheme.{}", doc.key), value)?;
        }
        Ok(scheme)
    }

    /// `[mass_scaling]`: h_t > 0, the kinetic share in (0, 1] (default 0.05).
    fn mass_scaling(&self, ms: &RawMassScaling) -> Result<MassScaling, SceneError> {
        let (target, share) = (
            &keys::MASS_SCALING_TARGET_STEP,
            &keys::MASS_SCALING_KINETIC_SHARE,
        );
        self.admit(target, "mass_scaling.target_step", ms.target_step)?;
        let kinetic_share = (ms.kinetic_share).unwrap_or(MassScaling::DEFAULT_KINETIC_SHARE);
        self.admit(share, "mass_scaling.kinetic_share", kinetic_share)?;
        Ok(MassScaling {
            target_step: ms.target_step,
            kinetic_share,
        })
    }

    /// `[bulk_viscosity]`: b₁ in [0, 1), b₂ in [0, 5), Abaqus/Explicit's defaults when left out.
    fn bulk_viscosity(&self, bv: &RawBulkViscosity) -> Result<BulkViscosity, SceneError> {
        let linear = bv.linear.unwrap_or(BulkViscosity::DEFAULT_LINEAR);
        let quadratic = bv.quadratic.unwrap_or(BulkViscosity::DEFAULT_QUADRATIC);
        self.admit(
            &keys::BULK_VISCOSITY_LINEAR,
            "bulk_viscosity.linear",
            linear,
        )?;
        let key = "bulk_viscosity.quadratic";
        self.admit(&keys::BULK_VISCOSITY_QUADRATIC, key, quadratic)?;
        Ok(BulkViscosity { linear, quadratic })
    }

    /// `plane[i]`: sugar for a half-space mould (`mould/shapes/half_space.rs`): the entry is
    /// rewritten as the `[[mould]]` entry `shape = "half_space"` with the same `name`, `point`,
    /// `normal` and `velocity`, and read by the one mould path ([`Check::mould_of`]), so its
    /// messages name `plane[i]` and its normal is normalised by the same arithmetic.
    fn plane_of(&self, key: String, p: RawPlane) -> Result<Mould, SceneError> {
        let floats = |v: &[f64]| toml::Value::Array(v.iter().map(|&x| x.into()).collect());
        let mut t = toml::Table::new();
        t.insert("name".into(), p.name.into());
        t.insert("shape".into(), "half_space".into());
        t.insert("point".into(), floats(&p.point));
        t.insert("normal".into(), floats(&p.normal));
        if let Some(rows) = p.velocity {
            let rows = rows.iter().map(|r| floats(r)).collect();
            t.insert("velocity".into(), toml::Value::Array(rows));
        }
        self.mould_of(key, t)
    }

    /// `interface[i]`: its face set and plane, μ_inf ≥ 0, α₀ ≥ 0, its law.
    fn interface(
        &self,
        mesh: &Mesh,
        attached: &mut Attachments,
        key: String,
        it: RawInterface,
    ) -> Result<Interface, SceneError> {
        let (faces, plane) = self.on_plane(mesh, attached, &key, &it.faces, &it.plane)?;
        self.admit(&keys::INTERFACE_MU_INF, format!("{key}.mu_inf"), it.mu_inf)?;
        self.admit(
            &keys::INITIAL_DAMAGE,
            format!("{key}.initial_damage"),
            it.initial_damage,
        )?;
        let law = self.delayed_law(&key, it.law, it.delay)?;
        self.glued_faces_face_mould(mesh, &attached.planes[plane], &key, &faces)?;
        self.attach(attached, &faces, plane, key)?;
        Ok(Interface {
            faces,
            plane,
            law,
            mu_inf: it.mu_inf,
            initial_damage: it.initial_damage,
            forms_on_contact: None,
        })
    }

    /// The face set and the plane index that `key` names (`key.faces`, `key.plane`).
    pub(super) fn on_plane(
        &self,
        mesh: &Mesh,
        attached: &Attachments,
        key: &str,
        faces: &str,
        plane: &str,
    ) -> Result<(String, usize), SceneError> {
        Ok((
            self.faces(mesh, format!("{key}.faces"), faces)?,
            self.plane(attached.planes, format!("{key}.plane"), plane)?,
        ))
    }

    /// Records that `key` attaches `faces` to `plane`, unless another key did already.
    pub(super) fn attach(
        &self,
        attached: &mut Attachments,
        faces: &str,
        plane: usize,
        key: String,
    ) -> Result<(), SceneError> {
        let first = (attached.pairs.iter()).find(|(f, p, _)| f == faces && *p == plane);
        if let Some((_, _, first)) = first {
            return Err(self.invalid(
                format!("{key}.faces"),
                format!("{faces:?}"),
                format!(
                    "face set `{faces}` is already attached to plane `{}` by `{first}`; \
                     a face set meets a plane through one [[interface]] or one [[contact]] \
                     (an interface already gives contact with friction mu_inf once ruptured)",
                    attached.planes[plane].name
                ),
            ));
        }
        attached.pairs.push((faces.to_string(), plane, key));
        Ok(())
    }

    /// `displacement[i]`: its face set and its history U(t), from `table` or from `speed`.
    fn displacement(
        &self,
        mesh: &Mesh,
        key: String,
        d: RawDisplacement,
        end_time: f64,
    ) -> Result<PrescribedDisplacement, SceneError> {
        let faces = self.faces(mesh, format!("{key}.faces"), &d.faces)?;
        let rows = match (&d.table, d.speed) {
            (Some(table), None) => {
                let extras = [
                    ("ramp", d.ramp.map(num)),
                    ("ramp_steps", d.ramp_steps.map(|n| n.to_string())),
                ];
                if let Some((name, Some(value))) = extras.into_iter().find(|e| e.1.is_some()) {
                    return Err(self.invalid(
                        format!("{key}.{name}"),
                        value,
                        "belongs to `speed`, not to `table` (a table gives U(t) itself)",
                    ));
                }
                table.iter().map(|r| (r[0], [r[1]])).collect()
            }
            (None, Some(v)) => self.speed_rows(&key, v, &d, end_time)?,
            (Some(_), Some(v)) => {
                return Err(self.invalid(
                    format!("{key}.speed"),
                    num(v),
                    "give either `table` or `speed`, not both",
                ))
            }
            (None, None) => {
                return Err(self.invalid(
                    format!("{key}.table"),
                    "missing".into(),
                    "needs `table` = [[t (s), U (m)], …] or `speed` (m/s)",
                ))
            }
        };
        Ok(PrescribedDisplacement {
            faces,
            component: d.component as usize,
            history: self.history(&format!("{key}.table"), rows)?,
        })
    }

    /// `displacement[i].speed` v [m/s] as the piecewise-linear U(t) it stands for: the speed
    /// is reached over `ramp` t_r [s] in n = `ramp_steps` equal increments (v k/n on the k-th
    /// interval of length t_r/n: a ramp in steps sends n stress waves of ρc_d v/n instead of
    /// one of ρc_d v), then U = U(t_r) + v (t − t_r), the last row placed at 2 max(T, t_r) so that
    /// a last step ending past T = `end_time` still sees the constant speed.
    fn speed_rows(
        &self,
        key: &str,
        v: f64,
        d: &RawDisplacement,
        end_time: f64,
    ) -> Result<Vec<(f64, [f64; 1])>, SceneError> {
        self.require(
            v.is_finite(),
            format!("{key}.speed"),
            v,
            "must be finite (m/s)",
        )?;
        let ramp = d.ramp.unwrap_or(0.0);
        self.admit(&keys::RAMP, format!("{key}.ramp"), ramp)?;
        let n = d.ramp_steps.unwrap_or(4);
        if !keys::RAMP_STEPS.admits(f64::from(n)) {
            return Err(self.invalid(
                format!("{key}.ramp_steps"),
                n.to_string(),
                keys::RAMP_STEPS.must(),
            ));
        }
        let mut rows = vec![(0.0, [0.0])];
        if ramp > 0.0 {
            let dt = ramp / n as f64;
            for k in 1..=n {
                let u = rows[rows.len() - 1].1[0] + v * (k as f64 / n as f64) * dt;
                rows.push((k as f64 * dt, [u]));
            }
        }
        let (t_r, u_r) = (rows[rows.len() - 1].0, rows[rows.len() - 1].1[0]);
        let t_last = 2.0 * end_time.max(ramp);
        rows.push((t_last, [u_r + v * (t_last - t_r)]));
        Ok(rows)
    }

    /// `traction[i]`: its face set, vector and amplitude history (constant 1 if none).
    fn traction(&self, mesh: &Mesh, key: String, t: RawTraction) -> Result<Traction, SceneError> {
        let faces = self.faces(mesh, format!("{key}.faces"), &t.faces)?;
        let amplitude = match t.amplitude {
            None => PiecewiseLinear::constant([1.0]),
            Some(rows) => self.history(
                &format!("{key}.amplitude"),
                rows.iter().map(|r| (r[0], [r[1]])).collect(),
            )?,
        };
        Ok(Traction {
            faces,
            vector: t.vector,
            amplitude,
        })
    }
}

/// `f(key, item)` for each item of the array of tables `name`, with its key `name[i]`.
fn each<T, U>(
    items: Vec<T>,
    name: &str,
    mut f: impl FnMut(String, T) -> Result<U, SceneError>,
) -> Result<Vec<U>, SceneError> {
    (items.into_iter().enumerate())
        .map(|(i, item)| f(format!("{name}[{i}]"), item))
        .collect()
}
