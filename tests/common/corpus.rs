//! The bad-input corpus, `tests/data/bad_input/`: a folder of malformed inputs and the table
//! `cases.toml` that says, for each, what its error must contain. Read by the physics tests
//! (`physics/tests/bad_input_corpus.rs`: every scene, mesh and STL case through the library) and
//! by the root tests (`tests/bad_input_cli.rs`: the command-line cases and every file case through
//! the binary). Included by both crates' test binaries.
#![allow(dead_code)]

use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The table: the scene templates and the cases.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Corpus {
    /// The scene text around a mesh or STL case, `{file}` standing for the case's file.
    pub template: Templates,
    pub case: Vec<Case>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Templates {
    pub msh: String,
    pub stl: String,
}

/// One malformed input and what its error must contain.
#[derive(Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct Case {
    /// `scene`, `msh`, `stl` or `cli`.
    pub kind: String,
    /// The input, a file of the folder (scene, msh, stl).
    pub file: Option<String>,
    /// Or, for a scene, `[from, to]`: `valid/glued_cube.toml` with `from` replaced by `to`.
    pub edit: Option<[String; 2]>,
    /// The name in reports; by default the file.
    pub name: Option<String>,
    /// `--set` overrides (scene cases).
    #[serde(default)]
    pub set: Vec<String>,
    /// The command line's arguments (cli cases), `{dir}` standing for the folder.
    #[serde(default)]
    pub args: Vec<String>,
    /// The exit status of a cli case (1: an input the program refuses; 2: a malformed command
    /// line).
    pub status: Option<i32>,
    /// Substrings the error message must contain.
    pub expect: Vec<String>,
}

/// The folder of the corpus.
pub fn dir() -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = if here.join("tests/data/bad_input").is_dir() {
        here.to_path_buf()
    } else {
        here.join("..")
    };
    root.join("tests/data/bad_input")
}

/// The table, read and checked: unique names, one input per case.
pub fn corpus() -> Corpus {
    let path = dir().join("cases.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let corpus: Corpus =
        toml::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut names = std::collections::BTreeSet::new();
    for c in &corpus.case {
        let name = c.name();
        assert!(
            names.insert(name.clone()),
            "cases.toml: case `{name}` twice"
        );
        let inputs =
            c.file.is_some() as usize + c.edit.is_some() as usize + !c.args.is_empty() as usize;
        assert_eq!(
            inputs, 1,
            "cases.toml: case `{name}` needs one of file, edit, args"
        );
        assert!(
            !c.expect.is_empty(),
            "cases.toml: case `{name}` expects nothing"
        );
    }
    corpus
}

impl Case {
    pub fn name(&self) -> String {
        self.name
            .clone()
            .or_else(|| self.file.clone())
            .unwrap_or_else(|| "(unnamed)".into())
    }

    /// The scene text of a scene, msh or stl case and the scene file name to give it: for a file
    /// case the file itself, for an edit the edited valid scene, for a mesh or surface the
    /// template around the file; always in the corpus folder, so that relative paths resolve
    /// there.
    pub fn scene(&self, corpus: &Corpus) -> (String, PathBuf) {
        let dir = dir();
        let valid = || std::fs::read_to_string(dir.join("valid/glued_cube.toml")).unwrap();
        match (self.kind.as_str(), &self.file, &self.edit) {
            ("scene", Some(f), _) => (std::fs::read_to_string(dir.join(f)).unwrap(), dir.join(f)),
            ("scene", None, Some([from, to])) => {
                let text = valid();
                assert!(
                    text.contains(from.as_str()),
                    "{}: {from:?} is not in the valid scene",
                    self.name()
                );
                (
                    text.replacen(from.as_str(), to, 1),
                    dir.join(format!("{}.toml", self.name())),
                )
            }
            ("msh", Some(f), _) => (
                corpus.template.msh.replace("{file}", f),
                dir.join("msh_scene.toml"),
            ),
            ("stl", Some(f), _) => (
                corpus.template.stl.replace("{file}", f),
                dir.join("stl_scene.toml"),
            ),
            (kind, ..) => panic!("{}: no scene for a `{kind}` case", self.name()),
        }
    }

    /// The substrings of `expect` that `message` lacks.
    pub fn missing<'a>(&'a self, message: &str) -> Vec<&'a str> {
        (self.expect.iter())
            .filter(|e| !message.contains(e.as_str()))
            .map(String::as_str)
            .collect()
    }
}

/// The text of a panic's payload.
pub fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "(no message)".into())
}
