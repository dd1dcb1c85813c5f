//! The logger thread of a recording: opens the stream, logs the static layout, then turns
//! each [`Snapshot`] into one buffered row of every entity (geometry, [`super::geometry`]; the
//! scalar series, here) and closes the stream with the run's outcome.

use super::eye::scene_eye;
use super::geometry::Geometry;
use super::layout::{
    energy_terms, log_static, mould_force_path, mould_moment_path, moving, path_part,
    ADDED_MASS_KINETIC, AXES, BULK_VISCOUS_DISSIPATED, MOULD_FRICTION,
};
use super::stream::Stream;
use super::{ColourField, Msg, RecordError, Sink, Statics, ALPHA_PER_NODE_MAX};
use crate::output::watch::{Reading, Source};
use crate::output::Snapshot;
use crate::solver::StageTimes;
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

/// What the logger thread reports when it ends.
pub(super) struct LoggerEnd {
    /// Busy time of the thread [s].
    pub(super) busy: Duration,
}

/// The body of the logger thread: opens the sink (an error ends the thread; the solver sees
/// it at its next frame), logs everything static, then the frames until the finish message.
pub(super) fn run(
    rx: Receiver<Msg>,
    sink: Sink,
    name: String,
    id: Option<String>,
    st: Statics,
    colour: ColourField,
) -> Result<LoggerEnd, RecordError> {
    let started = Instant::now();
    let watched: Vec<(String, String)> = (st.watch.entries.iter())
        .map(|w| {
            let entry = w.path.trim_start_matches("nodes/").replacen('/', " on ", 1);
            (w.path.clone(), format!("node {entry}"))
        })
        .collect();
    let stream = Stream::open(&sink, name, id.as_deref(), &scene_eye(&st.model), &watched)?;
    let mut logger = Logger::new(stream, st, colour)?;
    let mut busy = started.elapsed();
    while let Ok(msg) = rx.recv() {
        let t = Instant::now();
        match msg {
            Msg::Frame(s) => logger.frame(&s, busy)?,
            Msg::Finish {
                snapshot,
                status,
                text,
                level,
            } => {
                if let Some(s) = snapshot {
                    logger.frame(&s, busy)?;
                }
                logger.finish(status, &text, level)?;
                busy += t.elapsed();
                break;
            }
        }
        busy += t.elapsed();
    }
    Ok(LoggerEnd { busy })
}

/// The logger thread's side: owns the stream and turns snapshots into entities.
struct Logger {
    stream: Stream,
    st: Statics,
    geometry: Geometry,
    /// One α(t) series per interface node ([`ALPHA_PER_NODE_MAX`]), else min / mean / max.
    alpha_per_node: bool,
    /// (U [mm], −F [kN]) of each prescribed displacement so far, re-sent at every flush.
    reaction_curves: Vec<Vec<[f32; 2]>>,
    /// Step, stage times, solver-thread output time and logger busy time at the last frame.
    last: Option<(u64, StageTimes, f64, Duration)>,
    /// Each watched entry's (state, contact status) names at the last frame, to log changes.
    watched: Vec<Option<(&'static str, &'static str)>>,
}

impl Logger {
    fn new(stream: Stream, st: Statics, colour: ColourField) -> Result<Logger, RecordError> {
        let geometry = Geometry::new(&st.model, colour);
        let alpha_per_node = st.interface_nodes.len() <= ALPHA_PER_NODE_MAX;
        log_static(stream.rec(), &st, &geometry, colour, alpha_per_node)?;
        Ok(Logger {
            stream,
            reaction_curves: vec![Vec::new(); st.model.displacements.len()],
            st,
            geometry,
            alpha_per_node,
            last: None,
            watched: Vec::new(),
        })
    }

    /// Buffers one snapshot as a frame at its step and time and sends the buffer when due
    /// ([`Stream::flush_if_due`]). `busy` is the logger thread's time so far, for the timing
    /// series.
    fn frame(&mut self, s: &Snapshot, busy: Duration) -> Result<(), RecordError> {
        self.stream.columns.begin(s.step, s.time);
        let colour_range = self.geometry.frame(&mut self.stream.columns, &self.st, s);
        // Reaction against imposed displacement (mm, kN; y up drawn as −y), sent at flushes.
        let m = &self.st.model;
        for (k, d) in m.displacements.iter().enumerate() {
            let u = d.history.value(s.time)[0];
            let f = s.reactions.get(k).copied().unwrap_or(0.0);
            self.reaction_curves[k].push([(1e3 * u) as f32, (-1e-3 * f) as f32]);
        }
        self.series(s, busy, colour_range);
        self.watched_nodes(s)?;
        self.stream.flush_if_due(&self.reaction_curves)
    }

    /// One row of every scalar series.
    fn series(&mut self, s: &Snapshot, busy: Duration, colour_range: (f64, f64)) {
        let m = &self.st.model;
        let cols = &mut self.stream.columns;
        // One row of every scalar series.
        let e = &s.energies;
        let energies: Vec<f64> = energy_terms(e).map(|(_, v)| v).collect();
        cols.scalars("energy", &energies);
        cols.scalars("balance/relative_residual", &[e.relative_residual]);
        if m.scheme.mass_scaling.is_some() {
            cols.scalars(ADDED_MASS_KINETIC, &[e.added_mass_kinetic]);
        }
        if m.scheme.bulk_viscosity.is_some() {
            cols.scalars(BULK_VISCOUS_DISSIPATED, &[e.bulk_viscous_dissipated]);
        }
        if m.moulds.len() > 1 {
            cols.scalars(MOULD_FRICTION, &s.mould_friction);
        }
        for (p, (f, mm)) in m.moulds.iter().zip(&s.mould_loads) {
            if moving(p) {
                cols.scalars(&mould_force_path(p), f);
            }
            if p.angular_velocity.is_some() {
                cols.scalars(&mould_moment_path(p), mm);
            }
        }
        for (k, d) in m.displacements.iter().enumerate() {
            let name = format!("{}_{}", path_part(&d.faces), AXES[d.component.min(2)]);
            cols.scalars(
                &format!("reaction/{name}"),
                &[s.reactions.get(k).copied().unwrap_or(0.0)],
            );
            cols.scalars(
                &format!("imposed_displacement/{name}"),
                &[d.history.value(s.time)[0]],
            );
        }
        let c = s.counts;
        let counts = [c.elastic, c.transition, c.ruptured, c.unformed].map(|n| n as f64);
        // `unformed` only where glue forms on contact (the series' names, `layout`).
        let forming = (m.interfaces.iter()).any(|i| i.forms_on_contact.is_some());
        cols.scalars("interface/count", &counts[..if forming { 4 } else { 3 }]);
        if !s.interface.is_empty() {
            if self.alpha_per_node {
                let alpha: Vec<f64> = s.interface.iter().map(|n| n.alpha).collect();
                cols.scalars("interface/alpha", &alpha);
            } else {
                let (mut mn, mut mx, mut sum) = (f64::INFINITY, f64::NEG_INFINITY, 0.0);
                for n in &s.interface {
                    mn = mn.min(n.alpha);
                    mx = mx.max(n.alpha);
                    sum += n.alpha;
                }
                cols.scalars("interface/alpha", &[mn, sum / s.interface.len() as f64, mx]);
            }
        }
        cols.scalars("time_step", &[s.h, s.h_crit]);
        // Wall time per step of each stage since the previous frame [µs].
        let (step0, stages0, solver0, busy0) =
            self.last
                .take()
                .unwrap_or((0, StageTimes::default(), 0.0, Duration::ZERO));
        let steps = (s.step.saturating_sub(step0)).max(1) as f64;
        let per_step = |now: f64, before: f64| 1e6 * (now - before) / steps;
        let st = &s.stages;
        cols.scalars(
            "timing",
            &[
                per_step(st.positions, stages0.positions),
                per_step(st.internal_forces, stages0.internal_forces),
                per_step(st.interface_contact, stages0.interface_contact),
                per_step(st.free_velocity, stages0.free_velocity),
                per_step(st.bookkeeping, stages0.bookkeeping),
                per_step(st.h_crit, stages0.h_crit),
                per_step(s.output_seconds, solver0),
                per_step(busy.as_secs_f64(), busy0.as_secs_f64()),
            ],
        );
        self.last = Some((s.step, s.stages.clone(), s.output_seconds, busy));
        let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
        cols.scalars(
            "body/colour_range",
            &[finite(colour_range.0), finite(colour_range.1)],
        );
    }

    /// One row of each watched entry's series (`nodes/<N>/…`), and its state and contact
    /// status by name in `nodes/<N>/log` at the first frame and whenever they change.
    fn watched_nodes(&mut self, s: &Snapshot) -> Result<(), RecordError> {
        let cols = &mut self.stream.columns;
        self.watched.resize(s.watched.len(), None);
        let mut changes = Vec::new();
        for ((w, r), last) in (self.st.watch.entries.iter())
            .zip(&s.watched)
            .zip(&mut self.watched)
        {
            let p = &w.path;
            let glued = matches!(w.source, Source::Interface(_));
            if glued {
                cols.scalars(&format!("{p}/jump"), &r.jump);
                cols.scalars(&format!("{p}/alpha"), &[r.alpha]);
                let mut t = r.glue.to_vec();
                t.extend(r.contact);
                cols.scalars(&format!("{p}/traction"), &t);
                cols.scalars(&format!("{p}/status"), &[r.state_code(), r.status_code()]);
            } else {
                cols.scalars(&format!("{p}/traction"), &r.contact);
                cols.scalars(&format!("{p}/status"), &[r.status_code()]);
            }
            cols.scalars(&format!("{p}/gap"), &[r.gap]);
            let now = (r.state_name(), r.status_name());
            if *last != Some(now) {
                *last = Some(now);
                changes.push((format!("{p}/log"), change_text(w.node, r)));
            }
        }
        if changes.is_empty() {
            return Ok(());
        }
        let rec = self.stream.rec();
        rec.set_time_sequence("step", s.step as i64);
        rec.set_duration_secs("sim_time", s.time);
        for (path, text) in changes {
            rec.log(path, &rerun::TextLog::new(text).with_level("INFO"))
                .map_err(super::log_err("a watched node's log"))?;
        }
        Ok(())
    }

    fn finish(self, status: &str, text: &str, level: &str) -> Result<(), RecordError> {
        self.stream
            .close(&self.reaction_curves, status, text, level)
    }
}

/// A watched entry's state and contact status by name, with α and g.
fn change_text(node: u32, r: &Reading) -> String {
    match r.state {
        Some(_) => format!(
            "node {node}: {}, contact {} (α = {:.4e} m, g = {:.4e} m)",
            r.state_name(),
            r.status_name(),
            r.alpha,
            r.gap
        ),
        None => format!(
            "node {node}: contact {} (g = {:.4e} m)",
            r.status_name(),
            r.gap
        ),
    }
}
