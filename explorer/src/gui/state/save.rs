//! What the explorer saves: the history and the curves as CSV, a run's summary as JSON, into
//! the output folder (native) or as a download (the page).

use super::App;
#[cfg(not(target_arch = "wasm32"))]
use std::path::Path;

impl App {
    /// Writes the history as CSV.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn export_csv(&mut self, path: &Path) -> Result<(), String> {
        crate::gui::history::export_csv(&self.history, path)
    }

    /// Saves `bytes` as the file `name`: into the output folder on native, as a download in the
    /// page; notes where it went or why not.
    pub fn save_file(&mut self, name: &str, bytes: &[u8]) {
        #[cfg(not(target_arch = "wasm32"))]
        let saved = {
            let path = Path::new(&self.settings.output_dir).join(name);
            std::fs::create_dir_all(&self.settings.output_dir)
                .and_then(|()| std::fs::write(&path, bytes))
                .map(|()| format!("{name} written to {}", path.display()))
                .map_err(|e| format!("{}: {e}", path.display()))
        };
        #[cfg(target_arch = "wasm32")]
        let saved =
            crate::gui::browser::download(name, bytes).map(|()| format!("{name} downloaded"));
        match saved {
            Ok(note) => self.notes.push(note),
            Err(e) => self.notes.push(format!("cannot save {name}: {e}")),
        }
    }

    /// Saves the history as CSV (`history.csv`, [`crate::gui::history::csv`]).
    pub fn save_history_csv(&mut self) {
        let text = crate::gui::history::csv(&self.history);
        self.save_file("history.csv", text.as_bytes());
    }

    /// Saves the curves of the runs as CSV (`curves.csv`, [`crate::gui::history::curves_csv`]): the
    /// force–displacement curve and the node counts over time of every run in the history.
    pub fn save_curves_csv(&mut self) {
        let text = crate::gui::history::curves_csv(&self.history);
        self.save_file("curves.csv", text.as_bytes());
    }

    /// Saves the summary of history row `i` as JSON (`runNNN_<scene>_summary.json`, what
    /// `decohesion run --summary` writes), if the run is of this session.
    pub fn save_summary(&mut self, i: usize) {
        let Some(row) = self.history.get(i) else {
            return;
        };
        let name = format!(
            "run{:03}_{}_summary.json",
            row.id,
            row.settings.scene_stem()
        );
        match row.summary_json.clone() {
            Some(json) => self.save_file(&name, json.as_bytes()),
            None => self.notes.push(format!(
                "run {}: its summary is kept for the runs of this session only",
                row.id
            )),
        }
    }
}
