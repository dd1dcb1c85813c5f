//! The bad-input corpus (`tests/data/bad_input/`, table `cases.toml`) through the binary: each
//! command-line case must exit with its status (1: an input refused, 2: a malformed command
//! line) and print its expected text on stderr; every file case (a scene, a Gmsh mesh or an STL
//! surface) must make `decohesion check` exit 1 with the case's expected text. Nothing may print
//! "panicked". A failure lists every case that went wrong. The library runs the same scene, mesh
//! and STL cases in-process (`physics/tests/bad_input_corpus.rs`).

use crate::common::cli::{scratch, BIN};
use crate::corpus::{self, Case};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A refused input ends at once; a case still running after this long was accepted (a run, a
/// sweep, a benchmark started) and is killed.
const RUNAWAY: Duration = Duration::from_secs(300);

/// The exit status and stderr of the binary with `args`, or None when it had to be killed.
fn run(args: &[String]) -> Option<(Option<i32>, String)> {
    let mut child = Command::new(BIN)
        .args(args)
        .arg("--quiet")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the decohesion binary runs");
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > RUNAWAY {
            child.kill().ok();
            child.wait().ok();
            return None;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    Some((
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    ))
}

/// What went wrong with one case, or None.
fn judge(case: &Case, args: &[String], status: i32) -> Option<String> {
    let Some((code, stderr)) = run(args) else {
        return Some(format!("still running after {RUNAWAY:?}: accepted"));
    };
    let mut problems = Vec::new();
    if stderr.contains("panicked") {
        problems.push("PANICKED".to_string());
    }
    if code != Some(status) {
        problems.push(format!("exit status {code:?}, not {status}"));
    }
    let missing = case.missing(&stderr);
    if !missing.is_empty() {
        problems.push(format!("stderr lacks {missing:?}"));
    }
    (!problems.is_empty()).then(|| format!("{}:\n      {}", problems.join("; "), stderr.trim()))
}

#[test]
fn every_bad_command_line_is_refused_with_a_message_that_says_why() {
    let corpus = corpus::corpus();
    let dir = corpus::dir().display().to_string();
    let scratch = scratch("bad-input", "check");
    let mut failures = Vec::new();
    let mut count = 0;
    for case in &corpus.case {
        let (args, status) = match (case.kind.as_str(), &case.file) {
            ("cli", _) => {
                let args = (case.args.iter())
                    .map(|a| a.replace("{dir}", &dir))
                    .collect();
                (args, case.status.expect("a cli case has a status"))
            }
            // `check` on the scene file itself, or on the template around the mesh or STL file
            // (written to a scratch folder, naming the file by its absolute path).
            ("scene", Some(f)) => (vec!["check".into(), format!("{dir}/{f}")], 1),
            ("msh" | "stl", Some(f)) => {
                let template = if case.kind == "msh" {
                    &corpus.template.msh
                } else {
                    &corpus.template.stl
                };
                let scene = scratch.join(format!("{count}.toml"));
                std::fs::write(&scene, template.replace("{file}", &format!("{dir}/{f}"))).unwrap();
                (vec!["check".into(), scene.display().to_string()], 1)
            }
            _ => continue,
        };
        let mut args: Vec<String> = args;
        args.extend(
            case.set
                .iter()
                .flat_map(|s| ["--set".to_string(), s.clone()]),
        );
        count += 1;
        if let Some(problem) = judge(case, &args, status) {
            failures.push(format!("  {} ({}): {problem}", case.name(), case.kind));
        }
    }
    let panics = failures.iter().filter(|f| f.contains("PANICKED")).count();
    assert!(
        failures.is_empty(),
        "{} of {count} cases failed, {panics} of them by panicking:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// A mould of an open surface is accepted, and `check` warns with its number of open edges.
#[test]
fn check_warns_of_an_open_surface() {
    let corpus = corpus::corpus();
    let dir = corpus::dir().display().to_string();
    let scene = scratch("bad-input", "open").join("open.toml");
    let text = (corpus.template.stl).replace("{file}", &format!("{dir}/valid/box_open.stl"));
    std::fs::write(&scene, text).unwrap();
    let out = crate::common::cli::decohesion_ok(&["check", scene.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("warning                      mould `wall`: the surface of")
            && stdout.contains("valid/box_open.stl is open (4 edges belong to one triangle only)"),
        "{stdout}"
    );
}
