//! The reference pages generated from the code (`decohesion reference scenes|cli`) are the
//! committed ones under `docs/src/reference/`, so that they cannot drift from the code; and the
//! scene page says what the loader does with the law families and moulds as the code has them.

use std::path::{Path, PathBuf};
use std::process::Command;

/// `decohesion reference PAGE` on standard output.
fn generate(page: &str) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_decohesion"))
        .args(["reference", page])
        .output()
        .expect("the decohesion command runs");
    assert!(
        out.status.success(),
        "decohesion reference {page} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("the page is UTF-8")
}

fn committed_path(page: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("docs/src/reference/{page}.md"))
}

/// Fails, saying how to regenerate it, when the committed page differs from the generated one.
fn assert_current(page: &str) {
    let path = committed_path(page);
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    let fresh = generate(page);
    if committed == fresh {
        return;
    }
    let (old, new): (Vec<&str>, Vec<&str>) = (committed.lines().collect(), fresh.lines().collect());
    let line = (old.iter().zip(&new))
        .position(|(a, b)| a != b)
        .unwrap_or(old.len().min(new.len()));
    let at = |lines: &[&str]| {
        lines
            .get(line)
            .copied()
            .unwrap_or("(end of file)")
            .to_string()
    };
    panic!(
        "docs/src/reference/{page}.md is stale: run `decohesion reference {page} --out \
         docs/src/reference/{page}.md` (or scripts/gen_reference.sh)\n\
         first difference at line {}:\n  committed: {}\n  generated: {}",
        line + 1,
        at(&old),
        at(&new)
    );
}

#[test]
fn scenes_md_is_current() {
    assert_current("scenes");
}

#[test]
fn cli_md_is_current() {
    assert_current("cli");
}

/// The lines of the section whose heading contains `title`, up to the next heading of its
/// level or above.
fn section(page: &str, title: &str) -> String {
    let level = |line: &str| line.chars().take_while(|c| *c == '#').count();
    let mut lines = page
        .lines()
        .skip_while(|l| !(l.starts_with('#') && l.contains(title)));
    let heading = lines
        .next()
        .unwrap_or_else(|| panic!("no heading {title:?} in the page"));
    let rest = lines.take_while(|l| !(l.starts_with('#') && level(l) <= level(heading)));
    std::iter::once(heading)
        .chain(rest)
        .collect::<Vec<_>>()
        .join("\n")
}

/// `rccm` takes C_N, C_T, w, b (not g_n0, alpha_e, u_r); `[[interface]].plane`
/// names a plane or a mould (not only a plane); every family has its section.
#[test]
fn the_scene_page_says_what_the_loader_does() {
    let page = generate("scenes");
    let rccm = section(&page, "Family `rccm`");
    for key in ["`c_n`", "`c_t`", "`w`", "`b`"] {
        assert!(rccm.contains(key), "{key} missing in:\n{rccm}");
    }
    for key in ["`g_n0`", "`alpha_e`", "`u_r`", "`r_t`"] {
        assert!(!rccm.contains(key), "{key} listed for rccm:\n{rccm}");
    }
    assert!(rccm.contains("`[interface.delay]`: refused"), "{rccm}");
    let interface = section(&page, "`[[interface]]` (zero or more)");
    let plane_row = interface
        .lines()
        .find(|l| l.starts_with("| `plane`"))
        .expect("the plane row");
    assert!(
        plane_row.contains("(or `mould`)") && plane_row.contains("`[[mould]]`"),
        "{plane_row}"
    );
    for family in [
        "plateau_linear",
        "bilinear",
        "bk",
        "exponential",
        "rccm",
        "table",
    ] {
        assert!(page.contains(&format!("Family `{family}`")), "{family}");
    }
    for shape in ["half_space", "box", "sphere", "cylinder", "surface"] {
        assert!(page.contains(&format!("| `{shape}` |")), "{shape}");
    }
}

/// Every subcommand has its section, and every argument of `check` its help text.
#[test]
fn the_cli_page_documents_every_subcommand() {
    let page = generate("cli");
    for sub in [
        "run",
        "check",
        "gui",
        "sweep",
        "tradeoff",
        "bench",
        "reference",
    ] {
        assert!(
            page.contains(&format!("## `decohesion {sub}`")),
            "no section for {sub}"
        );
    }
    let check = section(&page, "`decohesion check`");
    for arg in ["`<SCENE>`", "`--set <KEY=VALUE>`"] {
        let row = check
            .lines()
            .find(|l| l.starts_with(&format!("| {arg}")))
            .unwrap_or_else(|| panic!("no row {arg} in:\n{check}"));
        let help = row
            .trim_end_matches(" |")
            .rsplit(" | ")
            .next()
            .unwrap_or("");
        assert!(!help.trim().is_empty(), "{arg} has no help: {row}");
    }
}

/// `--out` writes the page, the same text as standard output, creating the folder.
#[test]
fn out_writes_the_page_to_a_file() {
    let dir = std::env::temp_dir().join(format!("decohesion-reference-{}", std::process::id()));
    let file = dir.join("sub/scenes.md");
    let status = Command::new(env!("CARGO_BIN_EXE_decohesion"))
        .args(["reference", "scenes", "--out"])
        .arg(&file)
        .status()
        .expect("the decohesion command runs");
    assert!(status.success());
    let written = std::fs::read_to_string(&file).expect("the page was written");
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(written, generate("scenes"));
}
