//! Running the `decohesion` binary from tests: scratch folders, the command, its JSON summary.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output};

pub const BIN: &str = env!("CARGO_BIN_EXE_decohesion");

/// An empty folder `decohesion-<prefix>-<pid>-<name>` under the system's temporary directory.
pub fn scratch(prefix: &str, name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("decohesion-{prefix}-{}-{name}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs the binary with `args` and returns what it printed and its status.
pub fn decohesion(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .output()
        .expect("the decohesion binary runs")
}

/// Runs the binary with `args`, which must succeed (else the test fails with its stderr).
pub fn decohesion_ok(args: &[&str]) -> Output {
    let out = decohesion(args);
    assert!(
        out.status.success(),
        "decohesion {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The `--summary` JSON file at `path`.
pub fn summary(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Sends SIGINT (Ctrl-C) to a running `decohesion` and waits for it: the run must end as not a
/// success, its summary at `summary_path` saying `cancelled`. Returns that summary.
pub fn interrupt_cancelled(child: Child, summary_path: &Path) -> serde_json::Value {
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let out = child.wait_with_output().unwrap();
    assert!(!out.status.success(), "a cancelled run is not a success");
    let s = summary(summary_path);
    assert_eq!(
        s["status"],
        "cancelled",
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    s
}
