//! Why a scene could not be loaded ([`SceneError`]) and how messages show values.

/// Why a scene could not be loaded. `file` is the file name, followed by
/// `(after --set overrides)` when overrides were applied (line numbers then refer to
/// [`Scene::resolved`](super::Scene::resolved), not to the file).
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{file}: cannot read the scene file: {source}")]
    Io {
        file: String,
        source: std::io::Error,
    },
    /// A `--set` override is malformed or does not fit the document.
    #[error("{file}: --set `{spec}`: {reason}")]
    Override {
        file: String,
        spec: String,
        reason: String,
    },
    /// TOML syntax error, unknown key, missing key or wrong type; `message` is toml's, with the
    /// line and column.
    #[error("{file}: {}{message}", key_prefix(.key))]
    Toml {
        file: String,
        /// Key path (`interface[0].law.u_r`), `None` when the error is not inside a key.
        key: Option<String>,
        message: String,
    },
    /// A key whose value is not admissible.
    #[error("{file}: key `{key}` = {value}: {reason}")]
    Invalid {
        file: String,
        key: String,
        value: String,
        /// What is admissible.
        reason: String,
    },
    /// A key that the rest of the scene requires but which is absent.
    #[error("{file}: key `{key}` is missing: {reason}")]
    Missing {
        file: String,
        key: String,
        reason: String,
    },
}

fn key_prefix(key: &Option<String>) -> String {
    key.as_ref()
        .map(|k| format!("key `{k}`: "))
        .unwrap_or_default()
}

pub(super) use crate::keydoc::{num, show};
