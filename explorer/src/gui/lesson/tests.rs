//! Tests of the lessons: parsing, errors, the shipped lessons, links.

use super::*;

const GOOD: &str = r#"+++
title = "A test"
scene = "pull_off"
summary = "one step"
+++
Intro **text**.

## First step

Read this.

```step
set = ["mesh.cells=[2,2,2]", "end_time=0.2"]
run = true
plot = "traction"
```

## Second step

```step
question = "How much?"
result = "dissipated_energy"
answer = 2000.0
tolerance = 0.1
explain = "G_c times the area."
```
"#;

fn err(text: &str) -> LessonError {
    crate::gui::at_repository_root();
    load(text, "lessons/bad.md").unwrap_err()
}

/// A lesson with two steps: the front matter, the introduction, each step's text without
/// its block, the overrides accumulated, the question.
#[test]
fn a_lesson_parses() {
    crate::gui::at_repository_root();
    let l = load(GOOD, "lessons/good.md").unwrap();
    assert_eq!((l.name.as_str(), l.title.as_str()), ("good", "A test"));
    assert_eq!(l.scene, "scenes/pull_off.toml");
    assert_eq!(l.intro, "Intro **text**.");
    assert_eq!(l.steps.len(), 2);
    assert_eq!(l.steps[0].text, "Read this.");
    assert_eq!(l.steps[0].line, 8);
    assert!(l.steps[0].run);
    assert_eq!(l.steps[0].plot, Some(PlotName::Traction));
    assert_eq!(l.sets_through(1), ["mesh.cells=[2,2,2]", "end_time=0.2"]);
    let mut later = l.clone();
    later.steps[1].set = vec!["end_time=0.3".into()];
    assert_eq!(
        later.sets_through(1),
        ["mesh.cells=[2,2,2]", "end_time=0.3"]
    );
    let q = l.steps[1].question.as_ref().unwrap();
    assert_eq!(
        (q.result, q.answer, q.tolerance),
        (RunResult::Dissipated, 2000.0, 0.1)
    );
    assert_eq!(q.line, 23);
    assert!(q.accepts(2150.0, 2000.0) && !q.accepts(2250.0, 2000.0));
}

/// Each kind of error names the file, the line, the key or value and what is admissible.
#[test]
fn errors_name_the_file_the_line_and_what_is_admissible() {
    crate::gui::at_repository_root();
    let e = err(&GOOD.replace("scene = \"pull_off\"", "scene = \"pul_off\""));
    let m = e.to_string();
    assert!(m.starts_with("lessons/bad.md: scene = \"pul_off\""), "{m}");
    assert!(m.contains("admissible are") && m.contains("peel"), "{m}");

    let e = err(&GOOD.replace("summary =", "sumary ="));
    assert_eq!(e.line, Some(4), "{e}");
    assert!(
        e.message.contains("unknown field `sumary`") && e.message.contains("`summary`"),
        "{e}"
    );

    let e = err(&GOOD.replace("run = true", "runs = true"));
    assert_eq!(e.line, Some(14), "{e}");
    assert!(
        e.message.contains("unknown field `runs`") && e.message.contains("`run`"),
        "{e}"
    );

    let e = err(&GOOD.replace("end_time=0.2", "end_time=-1"));
    let m = e.to_string();
    assert!(m.starts_with("lessons/bad.md:13: step 1"), "{m}");
    assert!(m.contains("end_time") && m.contains("-1"), "{m}");

    let e = err(&GOOD.replace("end_time=0.2", "interface.law.u_rr=0.2"));
    assert!(e.to_string().contains("u_rr"), "{e}");

    let e = err(&GOOD.replace("\"end_time=0.2\"", "\"end_time\""));
    assert_eq!(e.line, Some(13), "{e}");
    assert!(
        e.message
            .contains("set `end_time`: expected `key.path=value`"),
        "{e}"
    );

    // A step's `time` within the run, its `node` on an interface or contact face.
    let e = err(&GOOD.replace("run = true", "run = true\ntime = 0.5"));
    assert_eq!(e.line, Some(15), "{e}");
    assert!(
        e.message.contains("`time` = 0.5 s") && e.message.contains("admissible is 0 to 0.2 s"),
        "{e}"
    );
    let e = err(&GOOD.replace("run = true", "run = true\ntime = -1.0"));
    assert_eq!(e.line, Some(15), "{e}");
    assert!(e.message.contains("time = -1: must be"), "{e}");
    // 2×2×2: the glued bottom face has nodes 0 to 8, the top corner 26 is not on it.
    let e = err(&GOOD.replace("run = true", "run = true\nnode = 26"));
    assert_eq!(e.line, Some(15), "{e}");
    assert!(
        e.message
            .contains("`node` = 26: not a node of an interface or contact face")
            && e.message
                .contains("the 9 nodes of the interface and contact faces (0 to 8)"),
        "{e}"
    );
    let e = err(&GOOD.replace("run = true", "run = true\nnode = -3"));
    assert!(e.message.contains("node = -3: must be a mesh node"), "{e}");
    let l = load(
        &GOOD.replace("run = true", "run = true\ntime = 0.1\nnode = 4"),
        "lessons/good.md",
    )
    .unwrap();
    assert_eq!(
        (l.steps[0].time, l.steps[0].node),
        (Some((0.1, 15)), Some((4, 16)))
    );

    let e = err(&GOOD.replace("dissipated_energy", "dissipation"));
    assert_eq!(e.line, Some(22), "{e}");
    assert!(
        e.message.contains("unknown result `dissipation`") && e.message.contains("peak_force"),
        "{e}"
    );

    let e = err(&GOOD.replace("\"traction\"", "\"tractions\""));
    assert_eq!(e.line, Some(15), "{e}");
    assert!(
        e.message.contains("unknown plot `tractions`") && e.message.contains("law"),
        "{e}"
    );

    let e = err(&GOOD.replace("tolerance = 0.1", "tolerance = 5"));
    assert_eq!(e.line, Some(24), "{e}");
    assert!(e.message.contains("tolerance = 5"), "{e}");

    let e = err(&GOOD.replace("answer = 2000.0\n", ""));
    assert!(
        e.message
            .contains("needs all of question, result, answer and tolerance"),
        "{e}"
    );

    let e = err(&GOOD.replace("## Second step", "Second step"));
    assert!(e.message.contains("second `step` block"), "{e}");

    let e = err(&GOOD.replacen("+++\n", "", 1));
    assert_eq!(e.line, Some(1), "{e}");
    let e = err(GOOD.split("## First").next().unwrap());
    assert!(e.message.contains("no step"), "{e}");

    crate::gui::at_repository_root();
    let l = load(GOOD, "lessons/good.md").unwrap();
    let e = step_index(&l, 3).unwrap_err();
    assert!(e.contains("no step 3") && e.contains("steps 1 to 2"), "{e}");
    assert_eq!(step_index(&l, 2), Ok(1));
}

/// Every shipped lesson loads, and `lessons/` holds exactly the shipped ones.
#[test]
fn the_shipped_lessons_load_and_are_the_folder_s() {
    crate::gui::at_repository_root();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../lessons");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .filter_map(|e| {
            e.file_name()
                .to_str()?
                .strip_suffix(".md")
                .map(str::to_string)
        })
        .collect();
    files.sort();
    let mut names: Vec<String> = LESSONS.iter().map(|l| l.0.to_string()).collect();
    names.sort();
    assert_eq!(files, names);
    for (name, text) in LESSONS {
        let l = load(text, &format!("lessons/{name}.md")).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(l.name, *name);
        assert_eq!(
            std::fs::read_to_string(dir.join(format!("{name}.md"))).unwrap(),
            *text
        );
    }
}

/// Links: a scene with overrides, percent-encoded; the overrides between two documents.
#[test]
fn links_and_changed_keys() {
    let q = scene_query(
        "scenes/peel.toml",
        &["interface.law.u_r=0.004".into()],
        true,
    );
    assert_eq!(q, "?scene=peel&set=interface.law.u_r%3D0.004&run=1");
    assert_eq!(lesson_query("peel", 1), "?lesson=peel&step=2");
    let base = "end_time = 1.0\n[a]\nb = 2\n[[d]]\nx = 1\n[[d]]\nx = 2\n";
    let edited = "end_time = 2.0\n[a]\nb = 2\nc = [1, 2]\n[[d]]\nx = 1\n[[d]]\nx = 3\n";
    assert_eq!(
        changed_keys(base, edited).unwrap(),
        ["a.c=[1, 2]", "d.1.x=3", "end_time=2.0"]
    );
    let grown = format!("{base}[[d]]\nx = 4\n");
    assert_eq!(
        changed_keys(base, &grown).unwrap(),
        ["d=[{ x = 1 }, { x = 2 }, { x = 4 }]"]
    );
}
