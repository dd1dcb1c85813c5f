//! Scene files: TOML text → validated [`Model`]. Every key, its unit, default and admissible
//! range is in the table of keys ([`keys`]), which `decohesion reference scenes` renders as
//! `docs/src/reference/scenes.md`.
//!
//! Pipeline: parse the text into a `toml::Table`, apply the `--set` overrides to it
//! (`overrides.rs`), print it back (`Scene::resolved`), deserialize that into the raw serde
//! structs (`raw.rs`: unknown keys and wrong types are refused here, with the key path and toml's
//! line and column), refuse any non-finite number, then check ranges and cross-references
//! (`check.rs`) while building the model types: the mesh (`mesh.rs`), the laws (`law.rs`, from
//! the table of law families), the material (`material.rs`, from the table of rubber families)
//! and the rest (`assemble.rs`). Every error ([`SceneError`], `error.rs`) names the file, the
//! key path, the offending value and what is admissible.

mod adhesion;
mod assemble;
mod bond;
mod check;
mod error;
pub mod keys;
mod law;
mod material;
pub mod material_keys;
mod mesh;
mod overrides;
mod raw;
#[cfg(test)]
mod tests;

pub use error::SceneError;

use crate::model::Model;
use check::Check;
use overrides::apply_override;
use raw::{from_toml, RawScene};
use std::path::Path;
use std::sync::Arc;

/// A loaded scene: the model and the texts it came from.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The validated model, shared (not copied) with the simulations built from it and the
    /// outputs that keep it (the recording, ParaView): at 10⁶ elements a copy is 58 MB.
    pub model: Arc<Model>,
    /// The scene file text as read.
    pub text: String,
    /// The TOML document after the overrides were applied, what the model was built from: one
    /// section per table, keys sorted, arrays on one line (toml's pretty printer puts every
    /// array element on its own line, which makes tables of rows unreadable).
    pub resolved: String,
    /// The file name used in messages.
    pub file: String,
}

/// Reads and loads the scene file at `path`, applying `overrides` (`key.path=value`, see
/// [`parse_scene`]).
pub fn load_scene(path: &Path, overrides: &[String]) -> Result<Scene, SceneError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
        file: file.clone(),
        source,
    })?;
    parse_scene(&text, &file, overrides)
}

/// Loads a scene from its text. `file` names it in messages, and its stem is the default scene
/// name.
///
/// Each override is `key.path=value`: the value is parsed as a TOML value (as a plain string if it
/// is not one); a numeric segment indexes an array (`plane.0.normal=[0,0,1]`); an array of one
/// table is entered without an index (`interface.law.u_r=0.02` with a single interface).
pub fn parse_scene(text: &str, file: &str, overrides: &[String]) -> Result<Scene, SceneError> {
    parse_scene_with(text, file, overrides, &|p| std::fs::read(p))
}

/// [`parse_scene`] with the files the scene names (a Gmsh mesh, a mould surface; paths relative
/// to `file`'s directory) read through `read` instead of the file system: the web page passes
/// the files built into it.
pub fn parse_scene_with(
    text: &str,
    file: &str,
    overrides: &[String],
    read: crate::gmsh::ReadFile,
) -> Result<Scene, SceneError> {
    let mut doc: toml::Table = from_toml(text, file)?;
    for spec in overrides {
        apply_override(&mut doc, spec).map_err(|reason| SceneError::Override {
            file: file.to_string(),
            spec: spec.clone(),
            reason,
        })?;
    }
    let label = if overrides.is_empty() {
        file.to_string()
    } else {
        format!("{file} (after --set overrides)")
    };
    let resolved = toml::to_string(&doc).map_err(|e| SceneError::Toml {
        file: label.clone(),
        key: None,
        message: e.to_string(),
    })?;
    // Without overrides, deserialize the file itself so that line numbers are the file's.
    let raw: RawScene = from_toml(
        if overrides.is_empty() {
            text
        } else {
            &resolved
        },
        &label,
    )?;
    let check = Check {
        file: &label,
        dir: Path::new(file).parent().unwrap_or(Path::new("")),
        read,
    };
    for (key, value) in &doc {
        check.finite(key, value)?;
    }
    let stem = Path::new(file)
        .file_stem()
        .map_or_else(|| file.to_string(), |s| s.to_string_lossy().into_owned());
    let model = check.model(raw, stem)?;
    Ok(Scene {
        model: Arc::new(model),
        text: text.to_string(),
        resolved,
        file: file.to_string(),
    })
}
