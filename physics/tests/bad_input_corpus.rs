//! The bad-input corpus (`tests/data/bad_input/`, table `cases.toml`) through the library: every
//! scene, Gmsh and STL case must be refused with an error that names the file and contains the
//! case's expected text (the key or line, the value, what is admissible), and none may panic.
//! A failure lists every case that panicked, was accepted or gave a message without the expected
//! text. The command-line cases run through the binary in the root crate's tests.

use crate::corpus::{self, panic_text, Case, Corpus};
use decohesion_physics::gmsh::parse_msh;
use decohesion_physics::mould::surface::{read_stl, SurfaceMesh};
use decohesion_physics::scene::{load_scene, parse_scene, Scene};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// What went wrong with one case, or None when it was refused as the table says.
fn judge(case: &Case, corpus: &Corpus) -> Option<String> {
    // A scene file is read by the loader (a file that is not UTF-8 is one of the cases).
    let scene_file = case.file.as_ref().filter(|_| case.kind == "scene");
    let (text, file) = match scene_file {
        Some(f) => (String::new(), corpus::dir().join(f)),
        None => case.scene(corpus),
    };
    let label = file.display().to_string();
    let loaded = catch_unwind(AssertUnwindSafe(|| match scene_file {
        Some(_) => load_scene(&file, &case.set),
        None => parse_scene(&text, &label, &case.set),
    }));
    let message = match loaded {
        Err(payload) => return Some(format!("PANICKED: {}", panic_text(&*payload))),
        Ok(Ok(_)) => return Some("ACCEPTED (no error)".into()),
        Ok(Err(e)) => e.to_string(),
    };
    if std::env::var_os("BAD_INPUT_SHOW").is_some() {
        eprintln!("== {}\n{message}", case.name());
    }
    let mut missing = case.missing(&message);
    if !message.contains(&label) {
        missing.push("the scene file's name");
    }
    // A mesh or STL error names that file too.
    let inner = case.file.as_deref().filter(|_| case.kind != "scene");
    if inner.is_some_and(|f| !message.contains(f)) {
        missing.push("the mesh or STL file's name");
    }
    (!missing.is_empty()).then(|| format!("message lacks {missing:?}:\n      {message}"))
}

/// The file parsers on their own (no scene around them) must not panic either.
fn parser_panics(case: &Case) -> Option<String> {
    let file = case.file.as_deref()?;
    let bytes = std::fs::read(corpus::dir().join(file)).unwrap();
    let run = || match case.kind.as_str() {
        "msh" => {
            let _ = parse_msh(&bytes, file);
        }
        "stl" => {
            if let Ok((v, t)) = read_stl(&bytes, file) {
                let _ = SurfaceMesh::new(file, None, 1.0, v, t, &|k| format!("facet {k}"));
            }
        }
        _ => {}
    };
    (catch_unwind(AssertUnwindSafe(run)).err())
        .map(|p| format!("PANICKED (parser): {}", panic_text(&*p)))
}

#[test]
fn every_bad_input_is_refused_with_a_message_that_says_why() {
    let corpus = corpus::corpus();
    let cases: Vec<&Case> = (corpus.case.iter()).filter(|c| c.kind != "cli").collect();
    let mut failures = Vec::new();
    for case in &cases {
        for problem in [judge(case, &corpus), parser_panics(case)]
            .into_iter()
            .flatten()
        {
            failures.push(format!("  {} ({}): {problem}", case.name(), case.kind));
        }
    }
    let panics = failures.iter().filter(|f| f.contains("PANICKED")).count();
    assert!(
        failures.is_empty(),
        "{} of {} cases failed, {panics} of them by panicking:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

/// The corpus's kinds and size: at least 200 cases in all.
#[test]
fn the_corpus_covers_every_kind() {
    let corpus = corpus::corpus();
    let count = |kind: &str| corpus.case.iter().filter(|c| c.kind == kind).count();
    for kind in ["scene", "msh", "stl", "cli"] {
        assert!(count(kind) >= 20, "only {} `{kind}` cases", count(kind));
    }
    assert!(corpus.case.len() >= 200, "{} cases", corpus.case.len());
    // Every file of the folder's case directories is a case.
    for sub in ["scene", "msh", "stl"] {
        for entry in std::fs::read_dir(corpus::dir().join(sub)).unwrap() {
            let name = format!("{sub}/{}", entry.unwrap().file_name().to_string_lossy());
            assert!(
                corpus.case.iter().any(|c| c.file.as_deref() == Some(&name)),
                "{name} is in the folder but not in cases.toml"
            );
        }
    }
}

/// The valid inputs the cases break load: the scene, the one-hexahedron mesh in the mesh
/// template, the closed box (ASCII and binary) in the STL template.
#[test]
fn the_valid_inputs_load() {
    let corpus = corpus::corpus();
    let dir = corpus::dir();
    let load = |text: String, name: &str| -> Scene {
        let file = dir.join(name).display().to_string();
        parse_scene(&text, &file, &[]).unwrap_or_else(|e| panic!("{e}"))
    };
    load(
        std::fs::read_to_string(dir.join("valid/glued_cube.toml")).unwrap(),
        "valid.toml",
    );
    let scene = load(
        corpus.template.msh.replace("{file}", "valid/one_hex.msh"),
        "msh_scene.toml",
    );
    assert_eq!(scene.model.mesh.elements.len(), 1);
    for stl in ["valid/box.stl", "valid/box_binary.stl"] {
        load(corpus.template.stl.replace("{file}", stl), "stl_scene.toml");
    }
}

proptest::proptest! {
    /// No byte string makes the Gmsh or the STL reader panic: the corpus's valid mesh and
    /// surfaces (ASCII and binary) with a stretch of bytes replaced by arbitrary ones.
    #[test]
    fn mutated_meshes_and_surfaces_never_panic(
        which in 0usize..3,
        at in 0usize..4096,
        cut in 0usize..64,
        insert in proptest::collection::vec(proptest::num::u8::ANY, 0..16),
    ) {
        let files = ["valid/one_hex.msh", "valid/box.stl", "valid/box_binary.stl"];
        let bytes = std::fs::read(corpus::dir().join(files[which])).unwrap();
        let at = at % (bytes.len() + 1);
        let end = (at + cut).min(bytes.len());
        let mut b = bytes[..at].to_vec();
        b.extend(&insert);
        b.extend(&bytes[end..]);
        let _ = parse_msh(&b, "fuzz.msh");
        if let Ok((v, t)) = read_stl(&b, "fuzz.stl") {
            let _ = SurfaceMesh::new("fuzz.stl", None, 1.0, v, t, &|k| format!("facet {k}"));
        }
    }
}
