//! The explorer's lesson actions: opening a lesson, a step or overrides, running a step, and
//! the link to what it shows.

use super::{
    changed_keys, find, lesson_query, scene_query, step_index, Lesson, LessonState, Opening,
};

impl crate::gui::App {
    /// Opens what `o` asks for; the error says why not (also noted for the window).
    pub fn open(&mut self, o: &Opening) -> Result<(), String> {
        let r = match &o.lesson {
            Some(name) => find(name).and_then(|l| {
                let k = step_index(&l, o.step.max(1))?;
                self.open_lesson(l, k);
                Ok(())
            }),
            None if !o.set.is_empty() => self.apply_set(&self.settings.scene.clone(), &o.set),
            None => Ok(()),
        };
        if let Err(e) = &r {
            self.notes.push(e.clone());
        }
        #[cfg(not(target_arch = "wasm32"))]
        if let Some(path) = &o.data {
            self.load_measured(path);
        }
        if let Err(e) = self.set_display(&o.hide, o.projector, o.embed) {
            self.notes.push(e.clone());
            return Err(e);
        }
        r
    }

    /// The settings of `scene` with the overrides `set`.
    pub fn apply_set(&mut self, scene: &str, set: &[String]) -> Result<(), String> {
        let s = crate::gui::settings::open_scene_with(scene, set)?;
        self.settings.scene = scene.to_string();
        self.settings.set = set.to_vec();
        self.settings.take_scene(&s);
        self.validation = None;
        Ok(())
    }

    /// Opens `lesson` at step `k` (0-based).
    pub fn open_lesson(&mut self, lesson: Lesson, k: usize) {
        self.lesson = Some(LessonState::new(lesson, 0));
        self.go_to_step(k);
    }

    /// Closes the lesson; the settings stay, the 3-D view no longer holds a step's time or node.
    pub fn close_lesson(&mut self) {
        self.lesson = None;
        self.view.set_hold(Default::default());
    }

    /// Opens step `k` of the lesson: the scene with the overrides of the steps up to it; its run
    /// starts if it has one and no question (a question's run starts with the prediction).
    pub fn go_to_step(&mut self, k: usize) {
        let Some(state) = &mut self.lesson else {
            return;
        };
        state.step = k.min(state.lesson.steps.len() - 1);
        state.prediction.clear();
        state.predicted = None;
        state.run = None;
        let (scene, set) = (
            state.lesson.scene.clone(),
            state.lesson.sets_through(state.step),
        );
        let step = state.current();
        let auto = step.run && step.question.is_none();
        let hold = crate::gui::view3d::Hold {
            time: step.time.map(|t| t.0),
            node: step.node.map(|n| n.0),
        };
        if let Err(e) = self.apply_set(&scene, &set) {
            self.notes.push(e);
            return;
        }
        self.view.set_hold(hold);
        if auto {
            self.run_step();
        }
    }

    /// Starts the open step's run, with the prediction field's value if it reads as a number.
    pub fn run_step(&mut self) {
        self.start();
        let id = self.job.as_ref().and(self.curve_run);
        if let Some(state) = &mut self.lesson {
            state.predicted = state
                .prediction
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|p| p.is_finite());
            state.run = id;
        }
    }

    /// The settings as the scene file gives them (no overrides, no edits).
    fn file_settings(&self) -> Result<crate::gui::Settings, String> {
        let mut base = self.settings.clone();
        base.set.clear();
        base.take_scene(&crate::gui::settings::open_scene(&base.scene)?);
        Ok(base)
    }

    /// Every key the settings change in the scene file, as overrides (`key.path=value`).
    pub fn changed_keys(&self) -> Result<Vec<String>, String> {
        changed_keys(
            &self.file_settings()?.scene_text()?,
            &self.settings.scene_text()?,
        )
    }

    /// The query of a link to what the explorer shows: the lesson's step while its settings are
    /// the step's, else the scene and every changed key.
    pub fn link_query(&self) -> Result<String, String> {
        if let Some(state) = &self.lesson {
            let mut step = self.settings.clone();
            step.set = state.lesson.sets_through(state.step);
            if let Ok(s) = crate::gui::settings::open_scene_with(&state.lesson.scene, &step.set) {
                step.take_scene(&s);
                if step.scene_text() == self.settings.scene_text() {
                    let q = lesson_query(&state.lesson.name, state.step);
                    return Ok(q + &self.display.query());
                }
            }
        }
        let q = scene_query(&self.settings.scene, &self.changed_keys()?, false);
        Ok(q + &self.display.query())
    }
}
