//! The static layout of a recording: entity paths and names, the recording's name, the
//! blueprint (the viewer's default layout), and what is logged once before the first frame
//! (scene text, annotation context, styles, surface topology, planes, law curves, series names,
//! the legend).

use super::geometry::Geometry;
use super::{log_err, ColourField, RecordError, Statics, ARROW_FRACTION, NORMAL_FRACTION};
use crate::energy::EnergySnapshot;
use crate::interface::contact::ContactStatus;
use crate::law::InterfaceState;
use crate::model::{Model, Mould};
use crate::output::surface::mould::{body_box, mould_drawing};
use crate::output::surface::{contact_rgb, state_rgb};
use crate::output::watch::Source;
use crate::solver::Simulation;
use rerun::blueprint::components::{PanelState, PlayState};
use rerun::blueprint::{
    Blueprint, BlueprintPanel, ContainerLike, Horizontal, SelectionPanel, Spatial2DView,
    Spatial3DView, Tabs, TextDocumentView, TextLogView, TimePanel, TimeSeriesView, Vertical,
};
use rerun::{
    AnnotationContext, Arrows3D, EntityPath, LineStrips2D, Mesh3D, Points2D, Points3D,
    RecordingStream, Rgba32, SeriesLines, TextDocument, TextLog, ViewCoordinates,
};

/// A name usable as one entity path part: `z+` → `z_plus` (the series' column names too).
pub(super) use crate::output::series::name_part as path_part;

pub(super) const AXES: [&str; 3] = ["x", "y", "z"];

/// The ledger terms the recording does not draw: the internal work and the work of step
/// changes are parts of the balance the residual already shows.
const ENERGY_NOT_DRAWN: [&str; 2] = ["internal_work", "step_change_work"];

/// The ledger terms logged as the instances of `energy` [J], in the order of
/// [`EnergySnapshot::TERMS`], with each term's value in `e`: every term but
/// [`ENERGY_NOT_DRAWN`].
pub(super) fn energy_terms(e: &EnergySnapshot) -> impl Iterator<Item = (&'static str, f64)> {
    EnergySnapshot::TERMS
        .into_iter()
        .zip(e.terms())
        .filter(|(name, _)| !ENERGY_NOT_DRAWN.contains(name))
}

/// The kinetic energy of the mass that mass scaling added [J] (model §6.8), a part of the
/// kinetic energy drawn in `energy`; logged with mass scaling only.
pub(super) const ADDED_MASS_KINETIC: &str = "energy/added_mass_kinetic";

/// The energy bulk viscosity dissipated [J] (model §5.11), a term of the balance; logged with
/// bulk viscosity only.
pub(super) const BULK_VISCOUS_DISSIPATED: &str = "energy/bulk_viscous_dissipated";

/// The friction dissipated on each mould [J] (`Simulation::mould_frictions`), one instance per
/// mould in `model.moulds` order, in the energy view: logged when there are several moulds
/// (with one, it is `friction_dissipated`, already drawn).
pub(super) const MOULD_FRICTION: &str = "energy/mould_friction";

/// Does mould `p` move (a velocity or an angular-velocity history)? Its load is plotted.
pub(super) fn moving(p: &Mould) -> bool {
    p.velocity.is_some() || p.angular_velocity.is_some()
}

/// The force the body exerts on a moving mould [N] (x, y, z), in the reaction view.
pub(super) fn mould_force_path(p: &Mould) -> String {
    format!("reaction/mould_{}", path_part(&p.name))
}

/// The moment about its pivot the body exerts on a turning mould [N·m] (x, y, z).
pub(super) fn mould_moment_path(p: &Mould) -> String {
    format!("mould_moment/{}", path_part(&p.name))
}

/// Stages logged as the instances of `timing` [µs per step], in this order.
pub(super) const STAGES: [&str; 8] = [
    "positions",
    "internal_forces",
    "interface_contact",
    "free_velocity",
    "bookkeeping",
    "h_crit",
    "logging",
    "logger_thread",
];

/// The recording name: scene name and the parameters a reader compares runs by (each law as it
/// writes itself: family key and parameter values).
pub fn recording_name(sim: &Simulation) -> String {
    let m = &sim.model;
    let mut name = format!(
        "{} · {} hex8{} · {:?} E={:.3e} Pa ν={}",
        m.name,
        m.mesh.elements.len(),
        crate::output::surface::tet_count(&m.mesh),
        m.material.model,
        m.material.young,
        m.material.poisson
    );
    for itf in &m.interfaces {
        name.push_str(&format!(" · {} μ_inf={}", itf.law, itf.mu_inf));
    }
    name.push_str(&format!(" · h={}·h_crit", m.scheme.time_step_factor));
    name
}

/// The default layout: 3-D view on the left; energies and state counts on the right, with
/// reactions, α(t), the law, the time step, timings and the scene text in tabs below, and a
/// tab per watched node (`watched`: its entity path `nodes/<N>` and its title) with its
/// lengths ([u], α, g), its tractions, its codes and its log. Returns also the 3-D view's
/// blueprint path (`view/<id>`), where its eye is set ([`super::eye::send_blueprint`]).
pub fn default_blueprint(watched: &[(String, String)]) -> (Blueprint, EntityPath) {
    let view: ContainerLike = Spatial3DView::new("body and interface")
        .with_origin("/")
        .with_contents(["/body/**", "/planes/**", "/interface/**", "/contact/**"])
        .into();
    let ContainerLike::View(v) = &view else {
        unreachable!("a Spatial3DView is a view");
    };
    let path = v.blueprint_path();
    let nodes = watched.iter().map(|(p, title)| -> ContainerLike {
        Vertical::new([
            TimeSeriesView::new(format!("{title}: jump [u], damage α, gap g [m]"))
                .with_origin(format!("/{p}"))
                .with_contents([
                    format!("/{p}/jump"),
                    format!("/{p}/alpha"),
                    format!("/{p}/gap"),
                ])
                .into(),
            TimeSeriesView::new(format!("{title}: traction on the solid [Pa]"))
                .with_origin(format!("/{p}/traction"))
                .into(),
            TimeSeriesView::new(format!(
                "{title}: state (0 elastic, 1 transition, 2 ruptured, 3 unformed), contact (0 open, 1 stick, 2 slip)"
            ))
            .with_origin(format!("/{p}/status"))
            .into(),
            TextLogView::new(format!("{title}: changes"))
                .with_origin(format!("/{p}/log"))
                .into(),
        ])
        .into()
    });
    let tabs: Vec<ContainerLike> = vec![
        TimeSeriesView::new("reaction [N]")
            .with_origin("/reaction")
            .into(),
        TimeSeriesView::new("moment on turning moulds [N·m]")
            .with_origin("/mould_moment")
            .into(),
        TimeSeriesView::new("imposed displacement [m]")
            .with_origin("/imposed_displacement")
            .into(),
        TimeSeriesView::new("balance residual / largest energy")
            .with_origin("/balance")
            .into(),
        Spatial2DView::new("reaction vs displacement (mm, kN)")
            .with_origin("/plots")
            .into(),
        TimeSeriesView::new("damage α [m]")
            .with_origin("/interface/alpha")
            .into(),
        Spatial2DView::new("stiffness law")
            .with_origin("/law")
            .into(),
        TimeSeriesView::new("time step [s]")
            .with_origin("/time_step")
            .into(),
        TimeSeriesView::new("wall time per step [µs]")
            .with_origin("/timing")
            .into(),
        TextDocumentView::new("scene").with_origin("/scene").into(),
        TextDocumentView::new("run").with_origin("/run").into(),
    ];
    let tabs: Vec<ContainerLike> = tabs.into_iter().chain(nodes).collect();
    let bp = Blueprint::new(Horizontal::new([
        view,
        Vertical::new([
            TimeSeriesView::new("energy [J]")
                .with_origin("/energy")
                .into(),
            TimeSeriesView::new("interface nodes: elastic / transition / ruptured")
                .with_origin("/interface/count")
                .into(),
            Tabs::new(tabs).into(),
        ])
        .into(),
    ]))
    // Follow the run as it arrives (live), i.e. open a file at its last frame.
    .with_time_panel(
        TimePanel::new()
            .with_timeline("sim_time")
            .with_play_state(PlayState::Following)
            .with_state(PanelState::Collapsed),
    )
    .with_blueprint_panel(BlueprintPanel::new().with_state(PanelState::Collapsed))
    .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed));
    (bp, path)
}

/// Logs everything static, before the first frame.
pub(super) fn log_static(
    rec: &RecordingStream,
    st: &Statics,
    geometry: &Geometry,
    colour: ColourField,
    alpha_per_node: bool,
) -> Result<(), RecordError> {
    scene_text(rec, st)?;
    // The scenes are drawn with z up (their gravity and moulds' motions are along z): the
    // viewer's default eye then looks at the scene from above its side, z up on the screen.
    rec.log_static("/", &ViewCoordinates::RIGHT_HAND_Z_UP())
        .map_err(log_err("the view coordinates"))?;
    classes_and_styles(rec, st, geometry.scales.point_radius)?;
    // Surface topology once; positions and colours per frame.
    rec.log_static(
        "body/surface",
        &Mesh3D::update_fields().with_triangle_indices(geometry.surface.triangles.iter().copied()),
    )
    .map_err(log_err("the surface topology"))?;
    planes(rec, &st.model)?;
    law_curves(rec, &st.model)?;
    series_names(rec, st, alpha_per_node)?;
    legend(
        rec,
        colour,
        geometry.scales.arrow_scale,
        geometry.scales.extent,
    )
}

/// The scene file, the resolved parameters, and the model's advisories in the run log.
fn scene_text(rec: &RecordingStream, st: &Statics) -> Result<(), RecordError> {
    let m = &st.model;
    rec.log_static(
        "scene/file",
        &TextDocument::from_markdown(format!(
            "# {}\n\n{}\n\nFile `{}`:\n\n```toml\n{}\n```\n",
            m.name, m.description, st.file, st.text
        )),
    )
    .map_err(log_err("the scene text"))?;
    rec.log_static(
        "scene/resolved",
        &TextDocument::from_markdown(format!(
            "# Resolved parameters (after --set overrides)\n\n```toml\n{}\n```\n\n\
             h = {:.5e} s = {:.4} × h_crit (factor {}, h never above h_crit), h_crit = {:.5e} s (Lanczos, model §6); \
             {} nodes, {} hex8 elements, {} interface nodes.\n",
            st.resolved,
            st.h,
            st.h / st.h_crit,
            m.scheme.time_step_factor,
            st.h_crit,
            m.mesh.nodes.len(),
            m.mesh.elements.len(),
            st.interface_nodes.len()
        )),
    )
    .map_err(log_err("the resolved parameters"))?;
    rec.set_time_sequence("step", 0);
    rec.set_duration_secs("sim_time", 0.0);
    for text in &st.advisories {
        rec.log("run/log", &TextLog::new(text.clone()).with_level("WARN"))
            .map_err(log_err("a warning"))?;
    }
    Ok(())
}

/// Class ids for interface and contact nodes, and the styles that do not change: radii, arrow
/// colours, curve labels.
fn classes_and_styles(rec: &RecordingStream, st: &Statics, r: f32) -> Result<(), RecordError> {
    let m = &st.model;
    // Class ids for interface and contact nodes, for the whole subtree.
    // The colours the explorer's 3-D view uses too (crate::output::surface).
    let rgb = |c: [u8; 3]| Rgba32::from_rgb(c[0], c[1], c[2]);
    let (s, c) = (|x| rgb(state_rgb(x)), |x| rgb(contact_rgb(x)));
    let classes = AnnotationContext::new([
        (0, "elastic", s(InterfaceState::Elastic)),
        (1, "transition", s(InterfaceState::Transition)),
        (2, "ruptured", s(InterfaceState::Ruptured)),
        (3, "unformed", s(InterfaceState::Unformed)),
        (10, "open", c(ContactStatus::Open)),
        (11, "stick", c(ContactStatus::Stick)),
        (12, "slip", c(ContactStatus::Slip)),
    ]);
    rec.log_static("interface", &classes)
        .map_err(log_err("the annotation context"))?;
    if !st.contact_nodes.is_empty() {
        rec.log_static("contact", &classes)
            .map_err(log_err("the annotation context"))?;
    }

    // The normals' class labels (stick, slip) would be written over a small contact patch.
    let unlabelled = Arrows3D::update_fields().with_show_labels(false);
    let styles: [(&str, &dyn rerun::AsComponents); 9] = [
        ("interface/contact_normal", &unlabelled),
        ("contact/normal", &unlabelled),
        (
            "interface/nodes",
            &Points3D::update_fields().with_radii([r]),
        ),
        (
            "interface/contact_status",
            &Points3D::update_fields().with_radii([0.5 * r]),
        ),
        ("contact/nodes", &Points3D::update_fields().with_radii([r])),
        (
            "interface/cohesive_traction",
            &Arrows3D::update_fields().with_colors([Rgba32::from_rgb(245, 166, 35)]),
        ),
        (
            "interface/contact_pressure",
            &Arrows3D::update_fields().with_colors([Rgba32::from_rgb(30, 120, 220)]),
        ),
        (
            "contact/pressure",
            &Arrows3D::update_fields().with_colors([Rgba32::from_rgb(30, 120, 220)]),
        ),
        (
            "plots/reaction_vs_displacement",
            &LineStrips2D::update_fields().with_labels(
                m.displacements
                    .iter()
                    .map(|d| format!("{} {}", d.faces, AXES[d.component.min(2)])),
            ),
        ),
    ];
    for (path, style) in styles {
        let used = if path.starts_with("contact/") {
            !st.contact_nodes.is_empty()
        } else if path.starts_with("plots/") {
            !m.displacements.is_empty()
        } else if path.starts_with("interface/") {
            !st.interface_nodes.is_empty()
        } else {
            true
        };
        if used {
            rec.log_static(path, style).map_err(log_err("a style"))?;
        }
    }
    Ok(())
}

/// Moulds, each at its t = 0 placement under `planes/<name>` (static; a per-frame
/// Transform3D moves it, [`super::geometry`]): [`mould_drawing`] — a half-space as a square
/// around the body's bounding box (drawn from both sides), the other shapes as meshes.
fn planes(rec: &RecordingStream, m: &Model) -> Result<(), RecordError> {
    let grey = Rgba32::from_unmultiplied_rgba(150, 155, 165, 160);
    let body = body_box(m);
    for p in &m.moulds {
        let path = format!("planes/{}", path_part(&p.name));
        let mut mesh = mould_drawing(p, body);
        if p.shape.is_half_space() {
            let back: Vec<[u32; 3]> = mesh.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect();
            mesh.triangles.extend(back);
        }
        let f32s =
            |v: &[[f64; 3]]| -> Vec<[f32; 3]> { v.iter().map(|x| x.map(|c| c as f32)).collect() };
        let mut drawing = Mesh3D::new(f32s(&mesh.vertices))
            .with_triangle_indices(mesh.triangles)
            .with_albedo_factor(grey);
        if !p.shape.is_half_space() {
            drawing = drawing.with_vertex_normals(f32s(&mesh.normals));
        }
        rec.log_static(path, &drawing).map_err(log_err("a mould"))?;
    }
    Ok(())
}

/// Stiffness laws, normalised: x = α/u_r ∈ [0, 1] → 0..100, y = value/peak → 0..−100 (2-D views
/// point y down).
fn law_curves(rec: &RecordingStream, m: &Model) -> Result<(), RecordError> {
    for itf in &m.interfaces {
        let law = &itf.law;
        let base = format!("law/{}", path_part(&itf.faces));
        let n = 200;
        let (t_max, at) = law.peak_traction();
        let g: Vec<[f32; 2]> = (0..=n)
            .map(|k| {
                let a = law.u_r * k as f64 / n as f64;
                [
                    (100.0 * a / law.u_r) as f32,
                    (-100.0 * law.g_n(a) / law.g_n0) as f32,
                ]
            })
            .collect();
        let t: Vec<[f32; 2]> = (0..=n)
            .map(|k| {
                let d = law.u_r * k as f64 / n as f64;
                [
                    (100.0 * d / law.u_r) as f32,
                    (-100.0 * law.traction(d) / t_max) as f32,
                ]
            })
            .collect();
        rec.log_static(
            format!("{base}/g_n"),
            &LineStrips2D::new([g])
                .with_colors([Rgba32::from_rgb(30, 120, 220)])
                .with_labels([format!("g_N(α)/g_N(0), g_N(0) = {:.3e} Pa/m", law.g_n0)]),
        )
        .map_err(log_err("the law curve"))?;
        rec.log_static(
            format!("{base}/traction"),
            &LineStrips2D::new([t])
                .with_colors([Rgba32::from_rgb(208, 2, 27)])
                .with_labels([format!(
                    "T(δ)/T_max, T_max = {t_max:.3e} Pa at δ = {at:.3e} m; G_c = {:.3e} J/m²",
                    law.fracture_energy()
                )]),
        )
        .map_err(log_err("the law curve"))?;
        rec.log_static(
            format!("{base}/axes"),
            &LineStrips2D::new([
                vec![[0.0f32, 0.0], [105.0, 0.0]],
                vec![[0.0f32, 0.0], [0.0, -105.0]],
            ])
            .with_colors([Rgba32::from_rgb(120, 120, 120)])
            .with_labels(["α/u_r, δ/u_r →", "↑ normalised value"]),
        )
        .map_err(log_err("the law axes"))?;
        rec.log_static(
            format!("{base}/marks"),
            &Points2D::new([
                [(100.0 * law.alpha_e / law.u_r) as f32, 0.0],
                [100.0f32, 0.0],
            ])
            .with_radii([1.5f32])
            .with_labels([
                format!("α_e = {:.3e} m", law.alpha_e),
                format!("u_r = {:.3e} m", law.u_r),
            ]),
        )
        .map_err(log_err("the law marks"))?;
    }
    Ok(())
}

/// Scalar series: one entity per quantity, one named instance per series.
fn series_names(
    rec: &RecordingStream,
    st: &Statics,
    alpha_per_node: bool,
) -> Result<(), RecordError> {
    let mut styles: Vec<(String, SeriesLines)> = vec![
        (
            "energy".into(),
            SeriesLines::new()
                .with_names(energy_terms(&EnergySnapshot::default()).map(|(name, _)| name)),
        ),
        (
            "interface/count".into(),
            // A fourth line, unformed, only where glue forms on contact (`Logger::step`).
            if st
                .model
                .interfaces
                .iter()
                .any(|i| i.forms_on_contact.is_some())
            {
                SeriesLines::new()
                    .with_names(["elastic", "transition", "ruptured", "unformed"])
                    .with_colors(
                        [
                            InterfaceState::Elastic,
                            InterfaceState::Transition,
                            InterfaceState::Ruptured,
                            InterfaceState::Unformed,
                        ]
                        .map(|x| {
                            let c = state_rgb(x);
                            Rgba32::from_rgb(c[0], c[1], c[2])
                        }),
                    )
            } else {
                SeriesLines::new()
                    .with_names(["elastic", "transition", "ruptured"])
                    .with_colors([
                        Rgba32::from_rgb(46, 160, 67),
                        Rgba32::from_rgb(245, 166, 35),
                        Rgba32::from_rgb(208, 2, 27),
                    ])
            },
        ),
        (
            "time_step".into(),
            SeriesLines::new().with_names(["h", "h_crit"]),
        ),
        ("timing".into(), SeriesLines::new().with_names(STAGES)),
        (
            "body/colour_range".into(),
            SeriesLines::new().with_names(["min", "max"]),
        ),
    ];
    let planes = &st.model.moulds;
    if planes.len() > 1 {
        let names = planes.iter().map(|p| format!("friction on {}", p.name));
        styles.push((MOULD_FRICTION.into(), SeriesLines::new().with_names(names)));
    }
    for p in planes.iter().filter(|p| moving(p)) {
        let names = AXES.map(|a| format!("{} F_{a}", p.name));
        styles.push((mould_force_path(p), SeriesLines::new().with_names(names)));
        if p.angular_velocity.is_some() {
            let names = AXES.map(|a| format!("{} M_{a}", p.name));
            styles.push((mould_moment_path(p), SeriesLines::new().with_names(names)));
        }
    }
    for w in &st.watch.entries {
        let glued = matches!(w.source, Source::Interface(_));
        let mut traction: Vec<String> = Vec::new();
        if glued {
            traction.extend(AXES.map(|a| format!("glue −R_d {a}")));
            styles.push((
                format!("{}/jump", w.path),
                SeriesLines::new().with_names(AXES.map(|a| format!("[u]_{a}"))),
            ));
            styles.push((
                format!("{}/alpha", w.path),
                SeriesLines::new().with_names(["α"]),
            ));
        }
        traction.extend(AXES.map(|a| format!("contact R_c/h {a}")));
        styles.push((
            format!("{}/traction", w.path),
            SeriesLines::new().with_names(traction),
        ));
        styles.push((
            format!("{}/gap", w.path),
            SeriesLines::new().with_names(["g"]),
        ));
        let codes: &[&str] = if glued {
            &["state", "contact"]
        } else {
            &["contact"]
        };
        styles.push((
            format!("{}/status", w.path),
            SeriesLines::new().with_names(codes.iter().copied()),
        ));
    }
    if !st.interface_nodes.is_empty() {
        let names: Vec<String> = if alpha_per_node {
            st.interface_nodes
                .iter()
                .map(|n| format!("node {}", n.0))
                .collect()
        } else {
            vec!["min".into(), "mean".into(), "max".into()]
        };
        styles.push((
            "interface/alpha".into(),
            SeriesLines::new().with_names(names),
        ));
    }
    for (path, style) in styles {
        rec.log_static(path, &style)
            .map_err(log_err("a series style"))?;
    }
    Ok(())
}

/// What the colours and arrows mean.
fn legend(
    rec: &RecordingStream,
    colour: ColourField,
    arrow_scale: f64,
    extent: f64,
) -> Result<(), RecordError> {
    let (field, unit) = colour.label();
    rec.log_static(
        "body/legend",
        &TextDocument::from_markdown(format!(
            "Surface coloured by **{field}** [{unit}], viridis colormap (dark purple = min, \
             yellow = max) over the range seen so far in the run (see `body/colour_range`).\n\n\
             Arrows: {:.3e} m per Pa (the law's peak traction, or E without glue, draws \
             {ARROW_FRACTION} × the body extent {extent:.3e} m). Cohesive arrows show −R_d = −g_N(α)[u] \
             on the solid; contact arrows show R_c/h; at each node in contact (stick or slip), \
             an arrow of {NORMAL_FRACTION} × the body extent along the mould's outward normal, \
             coloured by the status.\n\nInterface nodes: green elastic, \
             orange transition, red ruptured, dark grey unformed (glue that forms on \
             contact, not formed yet); contact status: grey open, blue stick, \
             magenta slip.",
            arrow_scale
        )),
    )
    .map_err(log_err("the legend"))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn path_parts_are_plain() {
        assert_eq!(path_part("z+"), "z_plus");
        assert_eq!(path_part("x-"), "x_minus");
        assert_eq!(path_part("mould 2"), "mould_2");
    }
}
