//! The static layout of a recording: entity paths and names, the recording's name, the
//! blueprint (the viewer's default layout), and what is logged once before the first frame
//! (scene text, annotation context, styles, surface topology, planes, law curves, series names,
//! the legend).

use super::geometry::Geometry;
use super::{log_err, ColourField, RecordError, Statics, ARROW_FRACTION};
use crate::law::InterfaceState;
use crate::mesh::{cross, dot, norm, sub};
use crate::model::{Model, Shape};
use crate::output::surface::{contact_rgb, state_rgb};
use crate::solver::{ContactStatus, Simulation};
use rerun::blueprint::components::{PanelState, PlayState};
use rerun::blueprint::{
    Blueprint, BlueprintPanel, Horizontal, SelectionPanel, Spatial2DView, Spatial3DView, Tabs,
    TextDocumentView, TimePanel, TimeSeriesView, Vertical,
};
use rerun::{
    AnnotationContext, Arrows3D, LineStrips2D, Mesh3D, Points2D, Points3D, RecordingStream, Rgba32,
    SeriesLines, TextDocument, TextLog,
};

/// A name usable as one entity path part: `z+` → `z_plus`.
pub(super) fn path_part(s: &str) -> String {
    let mut out = String::new();
    for ch in s.chars() {
        match ch {
            '+' => out.push_str("_plus"),
            '-' => out.push_str("_minus"),
            c if c.is_ascii_alphanumeric() || c == '_' => out.push(c),
            _ => out.push('_'),
        }
    }
    out
}

pub(super) const AXES: [&str; 3] = ["x", "y", "z"];

/// The ledger terms logged as the instances of `energy` [J], in this order.
pub(super) const ENERGY_TERMS: [&str; 13] = [
    "kinetic",
    "strain",
    "hourglass",
    "interface_stored",
    "damage_dissipated",
    "contact_normal_dissipated",
    "friction_dissipated",
    "external_work",
    "gravity_work",
    "traction_work",
    "reaction_work",
    "plane_work",
    "residual",
];

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
        "{} · {} hex8 · {:?} E={:.3e} Pa ν={}",
        m.name,
        m.mesh.elements.len(),
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
/// reactions, α(t), the law, the time step, timings and the scene text in tabs below.
pub fn default_blueprint() -> Blueprint {
    Blueprint::new(Horizontal::new([
        Spatial3DView::new("body and interface")
            .with_origin("/")
            .with_contents(["/body/**", "/planes/**", "/interface/**", "/contact/**"])
            .into(),
        Vertical::new([
            TimeSeriesView::new("energy [J]")
                .with_origin("/energy")
                .into(),
            TimeSeriesView::new("interface nodes: elastic / transition / ruptured")
                .with_origin("/interface/count")
                .into(),
            Tabs::new([
                TimeSeriesView::new("reaction [N]")
                    .with_origin("/reaction")
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
            ])
            .into(),
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
    .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
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
    classes_and_styles(rec, st, geometry.scales.point_radius)?;
    // Surface topology once; positions and colours per frame.
    rec.log_static(
        "body/surface",
        &Mesh3D::update_fields().with_triangle_indices(geometry.surface.triangles.iter().copied()),
    )
    .map_err(log_err("the surface topology"))?;
    planes(
        rec,
        &st.model,
        geometry.scales.extent,
        geometry.scales.centre,
    )?;
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
             h = {:.5e} s = {:.4} × h_crit (factor {}, h never above h_crit), h_crit = {:.5e} s (Lanczos, PHYSICS.md §6); \
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

    let styles: [(&str, &dyn rerun::AsComponents); 7] = [
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
/// Transform3D moves it, [`super::geometry`]): a half-space as a square of 1.6 × the body
/// extent centred under the body's centre, the other shapes as meshes ([`mould_mesh`]).
fn planes(
    rec: &RecordingStream,
    m: &Model,
    extent: f64,
    centre: [f64; 3],
) -> Result<(), RecordError> {
    let grey = Rgba32::from_unmultiplied_rgba(150, 155, 165, 160);
    for p in &m.planes {
        let path = format!("planes/{}", path_part(&p.name));
        if p.shape != Shape::HalfSpace {
            let mesh = mould_mesh(&p.shape);
            let f32s = |v: &[[f64; 3]]| -> Vec<[f32; 3]> {
                v.iter().map(|x| x.map(|c| c as f32)).collect()
            };
            rec.log_static(
                path,
                &Mesh3D::new(f32s(&mesh.vertices))
                    .with_vertex_normals(f32s(&mesh.normals))
                    .with_triangle_indices(mesh.triangles)
                    .with_albedo_factor(grey),
            )
            .map_err(log_err("a mould"))?;
            continue;
        }
        let n = p.normal;
        let a = if n[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let t1 = normalise(cross(n, a));
        let t2 = cross(n, t1);
        let d = dot(sub(centre, p.point), n);
        let c = [0, 1, 2].map(|i| centre[i] - d * n[i]);
        let s = 0.8 * extent;
        let corner =
            |a: f64, b: f64| [0, 1, 2].map(|i| (c[i] + s * (a * t1[i] + b * t2[i])) as f32);
        let verts = [
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ];
        rec.log_static(
            path,
            &Mesh3D::new(verts)
                .with_triangle_indices([[0, 1, 2], [0, 2, 3], [0, 2, 1], [0, 3, 2]])
                .with_albedo_factor(grey),
        )
        .map_err(log_err("a plane"))?;
    }
    Ok(())
}

/// A mould's surface as triangles, in its frame at t = 0, wound so that (b − a) × (c − a)
/// points out of the mould (into the solid), with a unit normal per vertex.
pub(super) struct MouldMesh {
    pub(super) vertices: Vec<[f64; 3]>,
    pub(super) normals: Vec<[f64; 3]>,
    pub(super) triangles: Vec<[u32; 3]>,
}

/// Rings (pole to pole) and meridians of a sphere's drawing: 2 + 15 × 32 = 482 vertices,
/// 960 triangles; each pole is a vertex, so the point of a sphere pressed along its axis is
/// exact.
pub(super) const SPHERE_RINGS: usize = 16;
pub(super) const SPHERE_MERIDIANS: usize = 32;
/// Segments around a cylinder's drawing.
pub(super) const CYLINDER_SEGMENTS: usize = 48;

/// The drawing of a mould shape other than the half-space (empty for a half-space): a box as
/// 6 faces of 4 vertices (12 triangles, flat normals); a sphere as a UV sphere about z
/// ([`SPHERE_RINGS`] × [`SPHERE_MERIDIANS`], vertices on the sphere); a capped cylinder as its
/// side ([`CYLINDER_SEGMENTS`] quads, radial normals) and two fans for the caps (axial
/// normals); a triangulated surface as its own triangles with parry's angle-weighted vertex
/// pseudo-normals.
pub(super) fn mould_mesh(shape: &Shape) -> MouldMesh {
    let mut mesh = MouldMesh {
        vertices: vec![],
        normals: vec![],
        triangles: vec![],
    };
    match shape {
        Shape::HalfSpace => {}
        Shape::Box { centre, half_size } => {
            // Each face: its normal axis i, sign s, and two tangent axes (j, k) with
            // e_j × e_k = s e_i, so the quad (−−, +−, ++, −+) in (j, k) winds outwards.
            for i in 0..3 {
                for s in [1.0, -1.0] {
                    let (j, k) = if s > 0.0 {
                        ((i + 1) % 3, (i + 2) % 3)
                    } else {
                        ((i + 2) % 3, (i + 1) % 3)
                    };
                    let base = mesh.vertices.len() as u32;
                    for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                        let mut x = *centre;
                        x[i] += s * half_size[i];
                        x[j] += a * half_size[j];
                        x[k] += b * half_size[k];
                        mesh.vertices.push(x);
                        let mut n = [0.0; 3];
                        n[i] = s;
                        mesh.normals.push(n);
                    }
                    mesh.triangles
                        .extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
                }
            }
        }
        Shape::Sphere { centre, radius } => {
            let (nr, nm) = (SPHERE_RINGS, SPHERE_MERIDIANS);
            let mut push = |n: [f64; 3]| {
                mesh.vertices
                    .push(std::array::from_fn(|c| centre[c] + radius * n[c]));
                mesh.normals.push(n);
            };
            push([0.0, 0.0, 1.0]);
            for r in 1..nr {
                let theta = std::f64::consts::PI * r as f64 / nr as f64;
                for k in 0..nm {
                    let phi = 2.0 * std::f64::consts::PI * k as f64 / nm as f64;
                    push([
                        theta.sin() * phi.cos(),
                        theta.sin() * phi.sin(),
                        theta.cos(),
                    ]);
                }
            }
            push([0.0, 0.0, -1.0]);
            let (nm32, south) = (nm as u32, (1 + (nr - 1) * nm) as u32);
            let ring = |r: u32, k: u32| 1 + r * nm32 + k % nm32;
            for k in 0..nm32 {
                mesh.triangles.push([0, ring(0, k), ring(0, k + 1)]);
                for r in 0..(nr as u32 - 2) {
                    let (a, b) = (ring(r, k), ring(r, k + 1));
                    let (c, d) = (ring(r + 1, k), ring(r + 1, k + 1));
                    mesh.triangles.extend([[a, c, d], [a, d, b]]);
                }
                let last = nr as u32 - 2;
                mesh.triangles
                    .push([south, ring(last, k + 1), ring(last, k)]);
            }
        }
        Shape::Cylinder {
            centre,
            axis,
            radius,
            half_length,
        } => {
            let a = normalise(*axis);
            let e1 = normalise(cross(
                a,
                if a[0].abs() < 0.9 {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 1.0, 0.0]
                },
            ));
            let e2 = cross(a, e1);
            let ns = CYLINDER_SEGMENTS as u32;
            let radial = |k: u32| -> [f64; 3] {
                let phi = 2.0 * std::f64::consts::PI * k as f64 / ns as f64;
                std::array::from_fn(|c| phi.cos() * e1[c] + phi.sin() * e2[c])
            };
            let at = |z: f64, r: f64, n: [f64; 3]| -> [f64; 3] {
                std::array::from_fn(|c| centre[c] + z * a[c] + r * n[c])
            };
            let l = *half_length;
            // Side: vertices 2k (bottom, z = −l) and 2k + 1 (top).
            for k in 0..ns {
                let n = radial(k);
                mesh.vertices
                    .extend([at(-l, *radius, n), at(l, *radius, n)]);
                mesh.normals.extend([n, n]);
            }
            for k in 0..ns {
                let (b0, t0) = (2 * k, 2 * k + 1);
                let (b1, t1) = (2 * ((k + 1) % ns), 2 * ((k + 1) % ns) + 1);
                mesh.triangles.extend([[b0, b1, t1], [b0, t1, t0]]);
            }
            // Caps: a centre and a ring each, normal ±a.
            for s in [1.0, -1.0] {
                let n = a.map(|c| s * c);
                let base = mesh.vertices.len() as u32;
                mesh.vertices.push(at(s * l, 0.0, n));
                mesh.normals.push(n);
                for k in 0..ns {
                    mesh.vertices.push(at(s * l, *radius, radial(k)));
                    mesh.normals.push(n);
                }
                for k in 0..ns {
                    let (p, q) = (base + 1 + k, base + 1 + (k + 1) % ns);
                    mesh.triangles
                        .push(if s > 0.0 { [base, p, q] } else { [base, q, p] });
                }
            }
        }
        Shape::Surface(s) => {
            let tri = &s.mesh;
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
        }
    }
    mesh
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
        ("energy".into(), SeriesLines::new().with_names(ENERGY_TERMS)),
        (
            "interface/count".into(),
            SeriesLines::new()
                .with_names(["elastic", "transition", "ruptured"])
                .with_colors([
                    Rgba32::from_rgb(46, 160, 67),
                    Rgba32::from_rgb(245, 166, 35),
                    Rgba32::from_rgb(208, 2, 27),
                ]),
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
             on the solid; contact arrows show R_c/h.\n\nInterface nodes: green elastic, \
             orange transition, red ruptured; contact status: grey open, blue stick, \
             magenta slip.",
            arrow_scale
        )),
    )
    .map_err(log_err("the legend"))?;
    Ok(())
}

fn normalise(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    [a[0] / n, a[1] / n, a[2] / n]
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

    /// Every drawn triangle winds outwards (its (b − a) × (c − a) along the vertex normals),
    /// normals are unit, a sphere's vertices are on it, and the counts are the documented ones.
    #[test]
    fn mould_meshes_are_closed_outward_and_on_the_shape() {
        let shapes = [
            Shape::Box {
                centre: [1.0, 2.0, 3.0],
                half_size: [0.5, 1.0, 2.0],
            },
            Shape::Sphere {
                centre: [0.0, 0.0, 0.18],
                radius: 0.1,
            },
            Shape::Cylinder {
                centre: [0.0, 1.0, 0.0],
                axis: [0.6, 0.0, 0.8],
                radius: 0.3,
                half_length: 1.0,
            },
        ];
        let counts = [(24, 12), (482, 960), (194, 192)];
        for (shape, (nv, nt)) in shapes.iter().zip(counts) {
            let m = mould_mesh(shape);
            assert_eq!((m.vertices.len(), m.triangles.len()), (nv, nt), "{shape:?}");
            assert_eq!(m.normals.len(), nv);
            assert!(m.normals.iter().all(|n| (norm(*n) - 1.0).abs() < 1e-12));
            for t in &m.triangles {
                let [a, b, c] = t.map(|v| m.vertices[v as usize]);
                let f = cross(sub(b, a), sub(c, a));
                let n = t.iter().fold([0.0; 3], |s, &v| {
                    let n = m.normals[v as usize];
                    [s[0] + n[0], s[1] + n[1], s[2] + n[2]]
                });
                assert!(dot(f, n) > 0.0, "{shape:?}: {t:?} winds inwards");
            }
        }
        let m = mould_mesh(&shapes[1]);
        for x in &m.vertices {
            assert!((norm(sub(*x, [0.0, 0.0, 0.18])) - 0.1).abs() < 1e-15);
        }
        assert!(mould_mesh(&Shape::HalfSpace).vertices.is_empty());
    }
}
