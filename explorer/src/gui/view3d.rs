//! The explorer's 3-D view of the current run: the deformed surface x = X + U coloured by a
//! field (|U|, von Mises, J; viridis over the range the run's frames reach so far), the
//! interface nodes as points coloured by the state of their law (elastic / transition /
//! ruptured) or by contact status (open / stick / slip), in the recording's colours
//! ([`crate::output::surface`]), the contact-only nodes coloured by contact status, and the
//! moulds see-through, every shape (a half-space as a square around the body), placed by
//! each frame's pose. Orbit by
//! dragging, zoom by scrolling, reset by double-click; a time slider over the run's frames
//! ([`super::frames`]) that follows the newest frame while the run computes, unless the user
//! picks one, and plays them. A click selects the interface or contact node drawn nearest to
//! it on the screen (within [`PICK_RADIUS`] points; elsewhere, none): a ring marks it, and the
//! explorer plots its jump, tractions, α, gap and status over the run's frames
//! ([`View3d::inspected`], `plots.rs`).
//!
//! Drawn by a paint callback of egui's glow renderer ([`gl`]): GLSL ES 3.00 / GLSL 1.40, so
//! the same code draws on WebGL2. Under the wgpu renderer the view says so instead.

mod gl;

use super::frames::{Field, Frame};
use crate::output::surface::{contact_rgb, state_rgb, viridis};
use crate::output::watch::Reading;
use eframe::egui_glow;
use gl::{GlView, Scene, Uniforms, Vertex};
use nalgebra::{Matrix4, Point3, Vector3};
use std::collections::VecDeque;
use std::sync::{Arc, Mutex};

use crate::tunables::FRAME_TIMES;

pub use crate::tunables::PICK_RADIUS;

use crate::tunables::FOV_Y;

/// The node inspected: one boundary entry of the run's frames over time.
#[derive(Debug, Clone)]
pub struct Inspected {
    /// The mesh node (0-based).
    pub node: u32,
    /// What the entry is ("glued on `z-` to mould").
    pub label: String,
    /// (tₙ [s], step n, the entry's state) of every frame.
    pub series: Vec<(f64, u64, Reading)>,
    /// The index in `series` of the frame shown (the slider's).
    pub shown: usize,
}

/// What the vertex buffer shows; a change rebuilds it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Key {
    frame: usize,
    field: Field,
    contact: bool,
    range: (f32, f32),
}

/// The state of the 3-D view (no GL until the first paint).
pub struct View3d {
    frames: Vec<Frame>,
    /// Per field, the smallest and largest finite value over the frames.
    ranges: [(f32, f32); 3],
    /// Largest distance of a surface vertex from the reference centre over the frames [m]:
    /// the camera keeps that sphere in sight.
    radius: f32,
    /// The frame shown; `None` follows the newest.
    pub shown: Option<usize>,
    pub field: Field,
    /// Points coloured by contact status rather than by the state of the law.
    pub contact: bool,
    /// Steps through the frames, one per repaint, and starts over at the end.
    pub playing: bool,
    /// Turns the camera a little every repaint (to measure the frame rate).
    pub spinning: bool,
    yaw: f32,
    pitch: f32,
    zoom: f32,
    /// The window draws with glow (set by the application every frame).
    pub glow: bool,
    gl: Arc<Mutex<Option<Result<GlView, String>>>>,
    scene: Option<(Key, Arc<Scene>)>,
    version: u64,
    frame_times: VecDeque<f32>,
    /// Where the picture was drawn last, in points.
    pub rect: Option<egui::Rect>,
    /// The 3-D view's panel as the window laid it out last, in points (set by the application).
    pub panel: Option<egui::Rect>,
    /// "save PNG" was pressed: the application saves the picture.
    pub png_requested: bool,
    /// "save GIF" was pressed: the application captures the frames as an animation.
    pub gif_requested: bool,
    /// The boundary entry picked (index into a frame's `readings`, its `points` then
    /// `contact_points`).
    pub selected: Option<usize>,
    /// What a lesson step asks the view to show ([`View3d::set_hold`]).
    hold: Hold,
    /// The part of `hold` not shown yet: taken as the frames arrive, once each per run.
    pending: Hold,
}

/// What a lesson step asks the 3-D view to show: the frame at a time (the view stops following
/// the newest frame there, the run goes on) and a node inspected.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Hold {
    /// Simulated time [s].
    pub time: Option<f64>,
    /// A mesh node (0-based) of an interface or contact face.
    pub node: Option<u32>,
}

impl Default for View3d {
    fn default() -> Self {
        View3d {
            frames: vec![],
            ranges: [(f32::INFINITY, f32::NEG_INFINITY); 3],
            radius: 0.0,
            shown: None,
            field: Field::default(),
            contact: false,
            playing: false,
            spinning: false,
            yaw: -0.9,
            pitch: 0.35,
            zoom: 1.0,
            glow: false,
            gl: Arc::default(),
            scene: None,
            version: 0,
            frame_times: VecDeque::new(),
            rect: None,
            panel: None,
            png_requested: false,
            gif_requested: false,
            selected: None,
            hold: Hold::default(),
            pending: Hold::default(),
        }
    }
}

impl View3d {
    /// Forgets the frames (a new run starts).
    pub fn clear(&mut self) {
        self.frames.clear();
        self.ranges = [(f32::INFINITY, f32::NEG_INFINITY); 3];
        self.radius = 0.0;
        self.shown = None;
        self.playing = false;
        self.selected = None;
        self.pending = self.hold;
    }

    /// Shows what `hold` asks, now for the frames there are and then for each run's as its
    /// frames arrive: the frame nearest `hold.time` once a frame has reached it, the entry of
    /// `hold.node` once the run's first frame is in. A default `Hold` asks nothing.
    pub fn set_hold(&mut self, hold: Hold) {
        self.hold = hold;
        self.pending = hold;
        self.take_hold();
    }

    /// Applies the pending part of the hold that the frames so far allow.
    fn take_hold(&mut self) {
        if let (Some(t), Some(last)) = (self.pending.time, self.frames.last()) {
            if last.time >= t {
                let after = self.frames.partition_point(|f| f.time < t);
                let nearest = match after.checked_sub(1) {
                    Some(b) if t - self.frames[b].time < self.frames[after].time - t => b,
                    _ => after,
                };
                self.shown = Some(nearest);
                self.playing = false;
                self.pending.time = None;
            }
        }
        if let (Some(node), Some(first)) = (self.pending.node, self.frames.first()) {
            let k = first
                .topology
                .boundary_nodes
                .iter()
                .position(|&b| b == node);
            self.selected = k.or(self.selected);
            self.pending.node = None;
        }
    }

    /// Takes a frame of the current run.
    pub fn push(&mut self, f: Frame) {
        for (r, field) in self.ranges.iter_mut().zip(&f.fields) {
            for &v in field.iter().filter(|v| v.is_finite()) {
                *r = (r.0.min(v), r.1.max(v));
            }
        }
        let c = f.topology.centre;
        for x in &f.positions {
            let d2: f32 = (0..3).map(|i| (x[i] - c[i]).powi(2)).sum();
            self.radius = self.radius.max(d2.sqrt());
        }
        self.frames.push(f);
        self.take_hold();
    }

    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// Index of the frame drawn.
    pub fn index(&self) -> Option<usize> {
        let last = self.frames.len().checked_sub(1)?;
        Some(self.shown.map_or(last, |i| i.min(last)))
    }

    /// Vertex buffer uploads so far (one per change of what is shown).
    pub fn uploads(&self) -> u64 {
        self.gl
            .lock()
            .ok()
            .and_then(|g| g.as_ref().and_then(|v| v.as_ref().ok().map(|v| v.uploads)))
            .unwrap_or(0)
    }

    /// Mean frame rate over the last [`FRAME_TIMES`] repaints [1/s].
    pub fn frame_rate(&self) -> f32 {
        let n = self.frame_times.len() as f32;
        n / self.frame_times.iter().sum::<f32>().max(1e-6)
    }

    fn reset_camera(&mut self) {
        let d = View3d::default();
        (self.yaw, self.pitch, self.zoom) = (d.yaw, d.pitch, d.zoom);
    }

    /// The controls, the time slider and the picture.
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        let dt = ui.input(|i| i.unstable_dt);
        if self.frame_times.len() == FRAME_TIMES {
            self.frame_times.pop_front();
        }
        self.frame_times.push_back(dt);
        ui.heading("3-D view");
        self.controls_ui(ui);
        self.slider_ui(ui);
        let size = ui.available_size().max(egui::vec2(200.0, 200.0));
        let (rect, response) = ui.allocate_exact_size(size, egui::Sense::click_and_drag());
        self.rect = Some(rect);
        self.camera_input(ui, &response);
        if response.clicked() && !response.double_clicked() {
            if let Some(pos) = response.interact_pointer_pos() {
                self.pick(rect, pos);
            }
        }
        ui.painter()
            .rect_filled(rect, 0.0, egui::Color32::from_gray(24));
        if self.playing || self.spinning {
            if let Some(i) = self.index() {
                if self.playing {
                    self.shown = Some((i + 1) % self.frames.len());
                }
            }
            if self.spinning {
                self.yaw += 0.02;
            }
            ui.ctx().request_repaint();
        }
        let text = |ui: &egui::Ui, s: &str| {
            ui.painter().text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                s,
                egui::FontId::proportional(14.0),
                egui::Color32::LIGHT_GRAY,
            );
        };
        if !self.glow {
            text(
                ui,
                "the 3-D view draws with the glow renderer (OpenGL / WebGL2) only",
            );
        } else if let Some(i) = self.index() {
            self.paint(ui, rect, i);
            self.legend_ui(ui, rect);
            self.marker_ui(ui, rect, i);
        } else {
            text(ui, "run a scene to see the body here");
        }
    }

    /// The rows wrap at the panel's width: unwrapped, they are wider than the embeddable
    /// view's panel, which egui then moves right by the excess, under the plots (the 3-D view a
    /// strip at the frame's right edge).
    fn controls_ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.label("colour");
            for f in Field::ALL {
                ui.radio_value(&mut self.field, f, f.label().0);
            }
        });
        ui.horizontal_wrapped(|ui| {
            ui.label("interface nodes");
            ui.radio_value(&mut self.contact, false, "state");
            ui.radio_value(&mut self.contact, true, "contact");
            if ui
                .button("reset view")
                .on_hover_text("drag: orbit, scroll: zoom, double-click: reset")
                .clicked()
            {
                self.reset_camera();
            }
            if ui
                .button("save PNG")
                .on_hover_text("the picture at this frame, as a PNG file (a download in the page)")
                .clicked()
            {
                self.png_requested = true;
            }
            if ui
                .button("save GIF")
                .on_hover_text("the run's frames as an animation (at most 60, 10 per second)")
                .clicked()
            {
                self.gif_requested = true;
            }
        });
    }

    fn slider_ui(&mut self, ui: &mut egui::Ui) {
        let n = self.frames.len();
        ui.horizontal_wrapped(|ui| {
            let play = if self.playing { "pause" } else { "play" };
            if ui.add_enabled(n > 1, egui::Button::new(play)).clicked() {
                self.playing = !self.playing;
            }
            let mut following = self.shown.is_none();
            if ui
                .checkbox(&mut following, "newest")
                .on_hover_text("follow the newest frame while the run computes")
                .changed()
            {
                self.shown = (!following).then(|| self.index().unwrap_or(0));
            }
            let mut i = self.index().unwrap_or(0);
            let slider = egui::Slider::new(&mut i, 0..=n.saturating_sub(1)).text("frame");
            if ui.add_enabled(n > 0, slider).changed() {
                self.shown = Some(i);
                self.playing = false;
            }
        });
        match self.index().map(|i| &self.frames[i]) {
            Some(f) => {
                let mut s = format!("t = {:.4e} s, step {}; {n} frames", f.time, f.step);
                if self.playing || self.spinning {
                    s += &format!("; {:.0} pictures/s", self.frame_rate());
                }
                ui.label(s)
            }
            None => ui.label("no frames"),
        };
    }

    fn camera_input(&mut self, ui: &egui::Ui, r: &egui::Response) {
        if r.dragged() {
            let d = r.drag_delta();
            self.yaw -= 0.01 * d.x;
            self.pitch = (self.pitch + 0.01 * d.y).clamp(-1.5, 1.5);
        }
        if r.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            self.zoom = (self.zoom * (scroll * 0.002).exp()).clamp(0.1, 20.0);
        }
        if r.double_clicked() {
            self.reset_camera();
        }
    }

    /// The vertex buffer of frame `i`, rebuilt only when what it shows changed.
    fn scene(&mut self, i: usize) -> Arc<Scene> {
        let key = Key {
            frame: i,
            field: self.field,
            contact: self.contact,
            range: self.ranges[self.field as usize],
        };
        if let Some((k, s)) = &self.scene {
            if *k == key {
                return s.clone();
            }
        }
        self.version += 1;
        let s = Arc::new(build_scene(&self.frames[i], &key, self.version));
        self.scene = Some((key, s.clone()));
        s
    }

    /// The camera of frame `i` drawn in `rect`: (projection × view, view), in coordinates
    /// relative to the reference centre. The sphere of all frames fits the narrower side of
    /// the picture; the eye orbits at (yaw, pitch), z up.
    fn camera(&self, rect: egui::Rect, i: usize) -> (Matrix4<f32>, Matrix4<f32>) {
        let aspect = rect.width() / rect.height().max(1.0);
        let half = (FOV_Y / 2.0).tan() * aspect.min(1.0);
        let radius = self.radius.max(0.5 * self.frames[i].topology.extent);
        let dist = 1.1 * radius * (1.0 + half * half).sqrt() / half / self.zoom;
        let (cy, sy, cp, sp) = (
            self.yaw.cos(),
            self.yaw.sin(),
            self.pitch.cos(),
            self.pitch.sin(),
        );
        let eye = Point3::new(dist * cp * cy, dist * cp * sy, dist * sp);
        let view = Matrix4::look_at_rh(&eye, &Point3::origin(), &Vector3::z());
        let proj = Matrix4::new_perspective(aspect, FOV_Y, 0.02 * dist, 10.0 * dist);
        (proj * view, view)
    }

    /// Where the point `x` [m] of frame `i` is drawn in `rect`, and its depth (normalised
    /// device z, smaller nearer): the clip coordinates c = P V (x − centre, 1), screen
    /// (left + (1 + c_x/c_w) w/2, top + (1 − c_y/c_w) h/2). `None` behind the eye.
    pub fn project(&self, rect: egui::Rect, i: usize, x: [f32; 3]) -> Option<(egui::Pos2, f32)> {
        let (mvp, _) = self.camera(rect, i);
        let c = self.frames[i].topology.centre;
        let p = mvp * nalgebra::Vector4::new(x[0] - c[0], x[1] - c[1], x[2] - c[2], 1.0);
        if p.w <= 0.0 {
            return None;
        }
        let (nx, ny, nz) = (p.x / p.w, p.y / p.w, p.z / p.w);
        let pos = egui::pos2(
            rect.left() + 0.5 * (1.0 + nx) * rect.width(),
            rect.top() + 0.5 * (1.0 - ny) * rect.height(),
        );
        Some((pos, nz))
    }

    /// Selects the interface or contact node of the frame shown drawn nearest to `pos` in
    /// `rect` (the nearer to the eye of two at the same distance), if it is within
    /// [`PICK_RADIUS`]; else none.
    pub fn pick(&mut self, rect: egui::Rect, pos: egui::Pos2) {
        let Some(i) = self.index() else { return };
        let f = &self.frames[i];
        let mut best: Option<(f32, f32, usize)> = None;
        for (k, &x) in f.points.iter().chain(&f.contact_points).enumerate() {
            let Some((p, depth)) = self.project(rect, i, x) else {
                continue;
            };
            let d = p.distance(pos);
            if d <= PICK_RADIUS && best.is_none_or(|(bd, bz, _)| (d, depth) < (bd, bz)) {
                best = Some((d, depth, k));
            }
        }
        self.selected = best.map(|b| b.2);
    }

    /// The selected node over the frames so far, with the frame shown.
    pub fn inspected(&self) -> Option<Inspected> {
        let k = self.selected?;
        let first = self.frames.first()?;
        let t = &first.topology;
        Some(Inspected {
            node: *t.boundary_nodes.get(k)?,
            label: t.boundary_labels.get(k)?.clone(),
            series: (self.frames.iter())
                .filter_map(|f| Some((f.time, f.step, *f.readings.get(k)?)))
                .collect(),
            shown: self.index()?,
        })
    }

    /// A ring around the selected node and its number, over the picture.
    fn marker_ui(&self, ui: &egui::Ui, rect: egui::Rect, i: usize) {
        let Some(k) = self.selected else { return };
        let f = &self.frames[i];
        let Some(&x) = f.points.iter().chain(&f.contact_points).nth(k) else {
            return;
        };
        let Some((p, _)) = self.project(rect, i, x) else {
            return;
        };
        let painter = ui.painter_at(rect);
        let ink = egui::Color32::from_rgb(255, 230, 0);
        painter.circle_stroke(p, 7.0, egui::Stroke::new(2.0, ink));
        painter.text(
            p + egui::vec2(10.0, -10.0),
            egui::Align2::LEFT_BOTTOM,
            format!("node {}", f.topology.boundary_nodes[k]),
            egui::FontId::proportional(13.0),
            ink,
        );
    }

    fn paint(&mut self, ui: &egui::Ui, rect: egui::Rect, i: usize) {
        let scene = self.scene(i);
        let (mvp, view) = self.camera(rect, i);
        let ppp = ui.ctx().pixels_per_point();
        let uniforms = Uniforms {
            mvp: to_array(&mvp),
            view: to_array(&view),
            point_size: (4.0 * ppp).max(2.0),
        };
        let gl_view = self.gl.clone();
        let callback = egui_glow::CallbackFn::new(move |info, painter| {
            let Ok(mut slot) = gl_view.lock() else { return };
            let v = slot.get_or_insert_with(|| GlView::new(painter.gl()));
            if let Ok(v) = v {
                v.paint(painter.gl(), &info, &scene, &uniforms);
            }
        });
        ui.painter().add(egui::PaintCallback {
            rect,
            callback: Arc::new(callback),
        });
        if let Ok(Some(Err(e))) = self.gl.lock().as_deref() {
            ui.painter().text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                e,
                egui::FontId::proportional(13.0),
                egui::Color32::from_rgb(220, 50, 50),
            );
        }
    }

    /// The colour bar of the field and the point colours, at the bottom of the picture.
    fn legend_ui(&self, ui: &egui::Ui, rect: egui::Rect) {
        let p = ui.painter_at(rect);
        let (lo, hi) = self.ranges[self.field as usize];
        let (name, unit) = self.field.label();
        let bar = egui::Rect::from_min_size(
            rect.left_bottom() + egui::vec2(10.0, -34.0),
            egui::vec2(160.0, 10.0),
        );
        const STEPS: usize = 32;
        for k in 0..STEPS {
            let [r, g, b] = viridis(k as f64 / (STEPS - 1) as f64);
            let w = bar.width() / STEPS as f32;
            let cell = egui::Rect::from_min_size(
                bar.min + egui::vec2(k as f32 * w, 0.0),
                egui::vec2(w + 0.5, bar.height()),
            );
            p.rect_filled(cell, 0.0, egui::Color32::from_rgb(r, g, b));
        }
        let font = egui::FontId::proportional(12.0);
        let grey = egui::Color32::LIGHT_GRAY;
        p.text(
            bar.left_bottom() + egui::vec2(0.0, 3.0),
            egui::Align2::LEFT_TOP,
            format!("{name} [{unit}]: {lo:.3e} … {hi:.3e}"),
            font.clone(),
            grey,
        );
        let legend: Vec<(&str, [u8; 3])> = if self.contact {
            use crate::interface::contact::ContactStatus as C;
            [("open", C::Open), ("stick", C::Stick), ("slip", C::Slip)]
                .map(|(s, c)| (s, contact_rgb(c)))
                .to_vec()
        } else {
            use crate::law::InterfaceState as S;
            let states = [
                ("elastic", S::Elastic),
                ("transition", S::Transition),
                ("ruptured", S::Ruptured),
                ("unformed", S::Unformed),
            ];
            states.map(|(s, c)| (s, state_rgb(c))).to_vec()
        };
        let mut at = rect.left_top() + egui::vec2(10.0, 8.0);
        for (label, [r, g, b]) in legend {
            p.circle_filled(
                at + egui::vec2(4.0, 7.0),
                4.0,
                egui::Color32::from_rgb(r, g, b),
            );
            p.text(
                at + egui::vec2(12.0, 0.0),
                egui::Align2::LEFT_TOP,
                label,
                font.clone(),
                grey,
            );
            at.y += 16.0;
        }
    }
}

fn to_array(m: &Matrix4<f32>) -> [f32; 16] {
    let mut a = [0.0; 16];
    a.copy_from_slice(m.as_slice());
    a
}

/// The vertices of a frame: surface (coloured by the field), interface and contact-only
/// points, the moulds' triangles placed by the frame's poses.
fn build_scene(f: &Frame, key: &Key, version: u64) -> Scene {
    let t = &f.topology;
    let c = t.centre;
    let rel = |x: [f32; 3], d: [f32; 3]| [0, 1, 2].map(|i| x[i] + d[i] - c[i]);
    let (lo, hi) = key.range;
    let span = if hi > lo { hi - lo } else { 1.0 };
    let rgba = |[r, g, b]: [u8; 3], a: u8| [r, g, b, a];
    let values = f.field(key.field);
    let mut vertices: Vec<Vertex> = f
        .positions
        .iter()
        .zip(values)
        .map(|(&x, &v)| Vertex {
            pos: rel(x, [0.0; 3]),
            rgba: rgba(viridis(((v - lo) / span) as f64), 255),
        })
        .collect();
    let colour = |s, k| {
        if key.contact {
            contact_rgb(k)
        } else {
            state_rgb(s)
        }
    };
    vertices.extend(f.points.iter().zip(&f.states).map(|(&x, &(s, k))| Vertex {
        pos: rel(x, [0.0; 3]),
        rgba: rgba(colour(s, k), 255),
    }));
    // Contact-only nodes have no law: coloured by their contact status always.
    vertices.extend(
        f.contact_points
            .iter()
            .zip(&f.contact_states)
            .map(|(&x, &k)| Vertex {
                pos: rel(x, [0.0; 3]),
                rgba: rgba(contact_rgb(k), 255),
            }),
    );
    for (mould, pose) in t.moulds.iter().zip(&f.mould_poses) {
        vertices.extend(mould.placed(pose).map(|x| Vertex {
            pos: rel(x, [0.0; 3]),
            rgba: [150, 155, 165, 70],
        }));
    }
    Scene {
        version,
        topology: t.clone(),
        vertices,
        surface: f.positions.len(),
        points: f.points.len() + f.contact_points.len(),
    }
}
