//! A run of the explorer: where it is recorded, its start (on a thread or in the frame loop),
//! Stop, and the job's messages read into the curve, the 3-D view and the history.

use super::{App, Status, FRAME_BUDGET};
use crate::gui::job::{Job, JobMessage};
#[cfg(not(target_arch = "wasm32"))]
use crate::gui::RecordChoice;
#[cfg(not(target_arch = "wasm32"))]
use crate::record::{find_on_path, Sink, RERUN_VERSION};
use crate::scene::Scene;
#[cfg(not(target_arch = "wasm32"))]
use std::path::PathBuf;
use std::sync::mpsc::TryRecvError;

impl App {
    /// Where run `id` is recorded, per the settings (a note when the viewer is missing).
    #[cfg(not(target_arch = "wasm32"))]
    fn sink(&mut self, id: u32) -> Option<Sink> {
        let settings = &self.settings;
        let dir = PathBuf::from(&settings.output_dir);
        match settings.record {
            RecordChoice::Off => None,
            RecordChoice::File => {
                if let Err(e) = std::fs::create_dir_all(&dir) {
                    self.notes
                        .push(format!("cannot create {}: {e}", dir.display()));
                }
                let stem = settings.scene_stem();
                Some(Sink::Save(dir.join(format!("run{id:03}_{stem}.rrd"))))
            }
            RecordChoice::Viewer if find_on_path("rerun").is_some() => Some(Sink::Spawn),
            RecordChoice::Viewer => {
                let _ = std::fs::create_dir_all(&dir);
                let path = dir.join(format!("run{id:03}.rrd"));
                self.notes.push(format!(
                    "No Rerun viewer on PATH: run {id} is saved to {} instead. Install the viewer \
                     with `pip install rerun-sdk=={RERUN_VERSION}` and put its bin/ on PATH.",
                    path.display()
                ));
                Some(Sink::Save(path))
            }
        }
    }

    /// Starts a run with the current settings on a new thread.
    pub fn start(&mut self) {
        if self.job.is_some() {
            return;
        }
        if let Some(reason) = self.blocker() {
            self.status = Status::Ended(format!("not started: {reason}"));
            return;
        }
        let scene = match self.scene() {
            Ok(s) => s,
            Err(e) => {
                self.status = Status::Ended(format!("not started: {e}"));
                return;
            }
        };
        let id = self.history.iter().map(|r| r.id).max().unwrap_or(0) + 1;
        match self.launch(id, scene) {
            Ok(job) => {
                self.job = Some(job);
                self.status = Status::Running;
                self.curve.clear();
                self.view.clear();
                self.curve_run = Some(id);
                if std::mem::take(&mut self.queued_run) {
                    self.compare.insert(id);
                }
            }
            Err(e) => self.status = Status::Ended(format!("failed: cannot start a thread: {e}")),
        }
    }

    /// Starts run `id`: in the frame loop ([`App::in_page`]) or on its own thread, recorded
    /// and written as the settings ask.
    fn launch(&mut self, id: u32, scene: Scene) -> std::io::Result<Job> {
        let settings = self.settings.clone();
        #[cfg(not(target_arch = "wasm32"))]
        if !self.in_page {
            let sink = self.sink(id);
            return Job::start(id, scene, sink, settings, self.repaint.clone());
        }
        Ok(Job::in_page(id, scene, settings))
    }

    /// Asks the running job to stop after its current step.
    pub fn stop(&mut self) {
        if let Some(j) = &mut self.job {
            j.stop();
        }
    }

    /// Reads the job's messages; returns true while a run is going on.
    pub fn poll(&mut self) -> bool {
        let Some(job) = &mut self.job else {
            return false;
        };
        if job.in_frames() && job.advance(FRAME_BUDGET) {
            // The next slice of steps at the next frame, drawn at once.
            if let Some(r) = &self.repaint {
                r();
            }
        }
        loop {
            match job.try_recv() {
                Ok(JobMessage::Progress { step, point }) => {
                    job.last = Some((step, point));
                    self.curve.push(point);
                }
                Ok(JobMessage::Frame(f)) => self.view.push(*f),
                Ok(JobMessage::Done(row)) => {
                    self.curve = row.curve.clone();
                    self.status = Status::Ended(match row.status.as_str() {
                        "completed" => "finished".to_string(),
                        "cancelled" => "stopped".to_string(),
                        _ => format!("failed: {}", row.error.clone().unwrap_or_default()),
                    });
                    if let Some(pvd) = &row.paraview {
                        self.notes.push(format!(
                            "run {}: ParaView files indexed by {pvd} (open it in ParaView)",
                            row.id
                        ));
                    }
                    self.history.push(*row);
                    self.job = None;
                    self.settle = 3;
                    return self.start_queued();
                }
                Err(TryRecvError::Empty) => return true,
                Err(TryRecvError::Disconnected) => {
                    self.status =
                        Status::Ended("failed: the solver thread ended without a word".into());
                    self.job = None;
                    return false;
                }
            }
        }
    }
}
