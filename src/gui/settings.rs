//! What the user sets in the explorer ([`Settings`], persisted between launches), the scenes
//! it offers, and the edited scene: the settings read from a scene file and written back into
//! its TOML, which then goes through the same parser and validation as a file.

use super::LawSettings;
use crate::scene::{parse_scene, Scene};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Where each run goes in Rerun.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum RecordChoice {
    /// Stream to the Rerun viewer (started if none listens on 127.0.0.1:9876).
    Viewer,
    /// Save each run to `out/gui/<n>_<scene>.rrd`.
    File,
    /// No recording.
    Off,
}

/// Everything the user sets, persisted between launches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Scene file.
    pub scene: String,
    pub law: LawSettings,
    /// Cells along the longest side of the box mesh; 0 when the scene reads its mesh from a
    /// Gmsh file (`mesh.file`), whose resolution the window cannot change.
    pub cells: usize,
    /// h / h_crit.
    pub factor: f64,
    /// Simulated time [s].
    pub end_time: f64,
    /// Frames per run logged to Rerun.
    pub frames: u32,
    /// "svk" or "neo_hookean".
    pub material: String,
    /// "full" (2×2×2) or "reduced" (one point + hourglass control).
    pub integration: String,
    /// κ of the hourglass control (reduced integration).
    pub hourglass: f64,
    pub record: RecordChoice,
    /// Also write ParaView files (`.vtu` per frame and a `.pvd` index, as `run --vtk`) to
    /// `<output_dir>/runNNN_<scene>_vtk/`.
    pub paraview: bool,
    /// Folder of saved recordings, ParaView files and CSV exports.
    pub output_dir: String,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            scene: "scenes/pull_off.toml".into(),
            law: LawSettings::default(),
            cells: 7,
            factor: 0.5,
            end_time: 0.33,
            frames: 200,
            material: "svk".into(),
            integration: "full".into(),
            hourglass: 0.05,
            record: RecordChoice::Viewer,
            paraview: false,
            output_dir: "out/gui".into(),
        }
    }
}

/// A scene offered by the picker.
#[derive(Debug, Clone)]
pub struct SceneEntry {
    pub path: String,
    pub description: String,
}

/// Lists `dir/*.toml` with their descriptions (unreadable files are listed with the error).
pub fn list_scenes(dir: &Path) -> Vec<SceneEntry> {
    let mut out = vec![];
    let Ok(entries) = std::fs::read_dir(dir) else {
        return out;
    };
    let mut paths: Vec<PathBuf> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    for p in paths {
        let description = match crate::scene::load_scene(&p, &[]) {
            Ok(s) => s.model.description,
            Err(e) => format!("(does not load: {e})"),
        };
        out.push(SceneEntry {
            path: p.display().to_string(),
            description,
        });
    }
    out
}

impl Settings {
    /// Takes the law and run settings of a scene (the scene file stays `self.scene`).
    pub fn take_scene(&mut self, scene: &Scene) {
        let m = &scene.model;
        if let Some(itf) = m.interfaces.first() {
            self.law.take(&itf.law, itf.mu_inf);
        }
        self.cells = scene_cells(scene).unwrap_or(0);
        self.factor = m.scheme.time_step_factor;
        self.integration = match m.scheme.integration {
            crate::model::Integration::Full => "full".into(),
            crate::model::Integration::Reduced => "reduced".into(),
        };
        self.hourglass = m.scheme.hourglass_coefficient;
        self.end_time = m.end_time;
        self.material = match m.material.model {
            crate::material::MaterialModel::Svk => "svk".into(),
            crate::material::MaterialModel::NeoHookean => "neo_hookean".into(),
        };
    }

    /// The scene file with these settings applied, as TOML text.
    pub fn scene_text(&self) -> Result<String, String> {
        let text = std::fs::read_to_string(&self.scene)
            .map_err(|e| format!("cannot read {}: {e}", self.scene))?;
        let mut doc: toml::Table = text.parse().map_err(|e| format!("{}: {e}", self.scene))?;
        let s = self;
        let law = s.law.to_toml()?;
        if let Some(toml::Value::Array(itfs)) = doc.get_mut("interface") {
            for itf in itfs.iter_mut() {
                if let toml::Value::Table(t) = itf {
                    t.insert("law".into(), toml::Value::Table(law.clone()));
                    match s.law.delay_toml() {
                        Some(d) => t.insert("delay".into(), toml::Value::Table(d)),
                        None => t.remove("delay"),
                    };
                    t.insert("mu_inf".into(), s.law.mu_inf.into());
                }
            }
        }
        if let Some(toml::Value::Table(mesh)) = doc.get_mut("mesh") {
            if let Some(toml::Value::Array(cells)) = mesh.get("cells").cloned() {
                let c: Vec<f64> = cells
                    .iter()
                    .filter_map(|v| v.as_integer())
                    .map(|v| v as f64)
                    .collect();
                let max = c.iter().cloned().fold(1.0, f64::max);
                let scaled: Vec<toml::Value> = c
                    .iter()
                    .map(|&v| {
                        let n = s.cells.max(1) as f64;
                        toml::Value::Integer(((v * n / max).round() as i64).max(1))
                    })
                    .collect();
                mesh.insert("cells".into(), toml::Value::Array(scaled));
            }
        }
        if let Some(toml::Value::Table(mat)) = doc.get_mut("material") {
            mat.insert("model".into(), s.material.clone().into());
        }
        let scheme = doc
            .entry("scheme")
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if let toml::Value::Table(t) = scheme {
            t.insert("time_step_factor".into(), s.factor.into());
            t.insert("integration".into(), s.integration.clone().into());
            t.insert("hourglass_coefficient".into(), s.hourglass.into());
        }
        doc.insert("end_time".into(), s.end_time.into());
        toml::to_string(&doc).map_err(|e| e.to_string())
    }

    /// The scene with these settings applied, validated as a file would be.
    pub fn scene(&self) -> Result<Scene, String> {
        parse_scene(&self.scene_text()?, &self.edited_name(), &[]).map_err(|e| e.to_string())
    }

    /// The name of the edited scene in messages.
    pub fn edited_name(&self) -> String {
        format!("{} (edited)", self.scene)
    }

    /// The scene file's stem, for file names ("run" when it has none).
    pub fn scene_stem(&self) -> String {
        Path::new(&self.scene)
            .file_stem()
            .map(|s| s.to_string_lossy().to_string())
            .unwrap_or_else(|| "run".into())
    }
}

/// Cells along the longest side of a scene's box mesh (`None` for a mesh file).
fn scene_cells(scene: &Scene) -> Option<usize> {
    let doc: toml::Table = scene.resolved.parse().ok()?;
    let cells = doc.get("mesh")?.get("cells")?.as_array()?;
    cells
        .iter()
        .filter_map(|v| v.as_integer())
        .max()
        .map(|v| v as usize)
}
