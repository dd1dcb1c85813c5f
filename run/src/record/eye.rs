//! The 3-D view's default eye: placed from the scene at t = 0 so that
//! the body and the moulds near it open whole on screen, and written into the blueprint as the
//! view's `EyeControls3D` property.
//!
//! Rerun 0.36's Rust `Spatial3DView` builder has no eye setter (Python's has `eye_controls=`),
//! but a view's properties are plain blueprint entities: the Python SDK logs the archetype
//! under `view/<view id>/EyeControls3D`, and so does [`send_blueprint`] here, into the same
//! blueprint store, before the blueprint is activated.

use super::APPLICATION_ID;
use crate::model::Model;
use crate::output::surface::mould::{body_box, mould_drawing};
use rerun::blueprint::components::Eye3DKind;
use rerun::blueprint::{Blueprint, BlueprintActivation};
use rerun::external::re_sdk_types::blueprint::archetypes::EyeControls3D;
use rerun::log::LogMsg;
use rerun::{EntityPath, RecordingStream, RecordingStreamBuilder, RecordingStreamResult};

pub use crate::tunables::EYE_ASPECT_MIN;
pub use crate::tunables::EYE_ELEVATION_DEG;
pub use crate::tunables::EYE_FOV_Y_DEG;
pub use crate::tunables::EYE_MARGIN;
pub use crate::tunables::EYE_NEAR_FRACTION;

/// The default eye of the 3-D view, z up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eye {
    /// The orbit centre: the centre of the body's bounding box at t = 0 [m].
    pub target: [f64; 3],
    /// Where the eye is [m].
    pub position: [f64; 3],
    /// The world's up direction on screen.
    pub up: [f64; 3],
}

/// The box that is framed: the body's bounding box at t = 0, grown to the moulds' drawings
/// (a half-space as its square around the body, [`mould_drawing`]) clipped to within
/// [`EYE_NEAR_FRACTION`] × the body's largest extent of the body's box.
pub fn framed_box(m: &Model) -> ([f64; 3], [f64; 3]) {
    let body = body_box(m);
    let (lo, hi) = body;
    let extent = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
    let reach = EYE_NEAR_FRACTION * extent;
    let (mut flo, mut fhi) = body;
    for p in &m.moulds {
        for x in mould_drawing(p, body).vertices {
            for i in 0..3 {
                let c = x[i].clamp(lo[i] - reach, hi[i] + reach);
                flo[i] = flo[i].min(c);
                fhi[i] = fhi[i].max(c);
            }
        }
    }
    (flo, fhi)
}

/// The eye for scene `m`: looking at the centre c of the body's bounding box from the +x −y
/// side at [`EYE_ELEVATION_DEG`], d = M r / sin θ away, where r is the largest distance from c
/// to a corner of the [`framed_box`] (the radius of a sphere about c holding it), θ the
/// smaller half field of view, min(fov_y/2, atan(a tan(fov_y/2))) with a = [`EYE_ASPECT_MIN`],
/// and M = [`EYE_MARGIN`]: a sphere of radius r seen from distance d subtends the half angle
/// asin(r/d) ≤ θ, so the whole framed box is in the view's frustum.
pub fn scene_eye(m: &Model) -> Eye {
    let (lo, hi) = body_box(m);
    let target: [f64; 3] = std::array::from_fn(|i| 0.5 * (lo[i] + hi[i]));
    let (flo, fhi) = framed_box(m);
    let r = (0..8)
        .map(|corner| {
            (0..3)
                .map(|i| {
                    let x = if corner >> i & 1 == 0 { flo[i] } else { fhi[i] };
                    (x - target[i]).powi(2)
                })
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max);
    let half_y = 0.5 * EYE_FOV_Y_DEG.to_radians();
    let theta = half_y.min((EYE_ASPECT_MIN * half_y.tan()).atan());
    // An empty body (no nodes) or a point still gets a finite eye.
    let d = EYE_MARGIN * r.max(f64::MIN_POSITIVE.sqrt()) / theta.sin();
    let e = EYE_ELEVATION_DEG.to_radians();
    let h = e.cos() * std::f64::consts::FRAC_1_SQRT_2;
    let dir = [h, -h, e.sin()];
    Eye {
        target,
        position: std::array::from_fn(|i| target[i] + d * dir[i]),
        up: [0.0, 0.0, 1.0],
    }
}

/// The blueprint property that sets `eye` on a 3-D view (orbital, as the viewer's default).
pub fn eye_controls(eye: &Eye) -> EyeControls3D {
    let f = |x: [f64; 3]| x.map(|c| c as f32);
    EyeControls3D::new()
        .with_kind(Eye3DKind::Orbital)
        .with_position(f(eye.position))
        .with_look_target(f(eye.target))
        .with_eye_up(f(eye.up))
}

/// Sends `bp` to `rec`, made active and default, with `eye` logged as the `EyeControls3D`
/// property of the view at `view` (its blueprint path, `view/<id>`) in the same blueprint
/// store, before the activation command (the viewer activates a blueprint once it has it
/// whole). The SDK builds a blueprint's messages on a memory stream of its own
/// (`Blueprint::send`); here that stream is ours, the property is logged on it, and its rows
/// are moved into the blueprint's store.
pub fn send_blueprint(
    rec: &RecordingStream,
    bp: &Blueprint,
    eye: Option<(EntityPath, &Eye)>,
) -> RecordingStreamResult<()> {
    let (tmp, storage) = RecordingStreamBuilder::new(APPLICATION_ID)
        .blueprint()
        .memory()?;
    let activation = BlueprintActivation {
        make_active: true,
        make_default: true,
    };
    bp.send(&tmp, activation)?;
    if let Some((view, eye)) = eye {
        tmp.set_time_sequence("blueprint", 0);
        tmp.log(format!("{view}/EyeControls3D"), &eye_controls(eye))?;
    }
    let own = tmp.store_info().map(|info| info.store_id.clone());
    let (mut infos, mut rows, mut command) = (vec![], vec![], None);
    for msg in storage.take() {
        match msg {
            LogMsg::BlueprintActivationCommand(c) => command = Some(c),
            LogMsg::SetStoreInfo(_) if Some(msg.store_id()) == own.as_ref() => {}
            LogMsg::SetStoreInfo(_) => infos.push(msg),
            LogMsg::ArrowMsg(..) => rows.push(msg),
        }
    }
    // `Blueprint::send` always ends with the command; without it nothing was built to send.
    let Some(command) = command else {
        return Ok(());
    };
    infos.append(&mut rows);
    for msg in &mut infos {
        if msg.store_id() != &command.blueprint_id {
            msg.set_store_id(command.blueprint_id.clone());
        }
    }
    rec.send_blueprint(infos, command);
    Ok(())
}
