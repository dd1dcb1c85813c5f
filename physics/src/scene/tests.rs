//! The scene loader's unit tests: every section of the format, the overrides, and the messages.

use super::*;
use crate::material::MaterialModel;
use crate::model::SchemeParams;

/// Every section and key of the format, with values that differ from the defaults.
const FULL: &str = r#"
name = "pull_off"
description = "cube pulled off a mould"
end_time = 0.3
gravity = [0.0, 0.0, -9.81]
initial_velocity = [0.0, 0.0, 0.5]
initial_angular_velocity = [0.0, 0.0, 2.0]

[mesh]
origin = [1.0, 0.0, 0.0]
size = [1.0, 2.0, 3.0]
cells = [2, 3, 4]

[material]
model = "neo_hookean"
young = 5.0e6
poisson = 0.45
density = 1100.0

[scheme]
time_step_factor = 0.8
h_crit_update_interval = 0
h_crit_tolerance = 1e-4
energy_growth_limit = 2.0

[[plane]]
name = "mould"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 2.0]

[[plane]]
name = "wall"
point = [2.0, 0.0, 0.0]
normal = [-3.0, 0.0, 4.0]
velocity = [[0.0, 0.0, 0.0, 0.1], [1.0, 0.0, 0.0, 0.2]]

[[interface]]
faces = "z-"
plane = "mould"
mu_inf = 0.5
initial_damage = 2.0e-4
[interface.law]
family = "exponential"
g_n0 = 2.0e9
alpha_e = 5.0e-4
u_r = 1.0e-3

[[interface]]
faces = "x+"
plane = "mould"
[interface.law]
family = "table"
points = [[0.0, 2e9], [1e-3, 0.0]]

[[contact]]
faces = "z-"
plane = "wall"
mu = 0.3

[[displacement]]
faces = "z+"
component = "y"
table = [[0.0, 0.0], [0.3, 0.6]]

[[traction]]
faces = "x+"
vector = [0.0, 0.0, 1.0e5]
amplitude = [[0.0, 0.0], [0.1, 1.0]]

[[traction]]
faces = "y-"
vector = [1.0, 0.0, 0.0]
"#;

fn err(text: &str, overrides: &[&str]) -> String {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    parse_scene(text, "scenes/t.toml", &overrides)
        .unwrap_err()
        .to_string()
}

/// The error of `text` after `overrides` contains each of `parts`.
fn assert_error(text: &str, overrides: &[&str], parts: &[&str]) {
    let e = err(text, overrides);
    for part in parts {
        assert!(e.contains(part), "missing {part:?} in:\n{e}");
    }
}

#[test]
fn complete_scene_builds_the_model() {
    let scene = parse_scene(FULL, "scenes/full.toml", &[]).unwrap();
    let m = &scene.model;
    assert_eq!(m.name, "pull_off");
    assert_eq!(m.description, "cube pulled off a mould");
    assert_eq!(
        (m.end_time, m.gravity[2], m.initial_velocity[2]),
        (0.3, -9.81, 0.5)
    );
    assert_eq!(m.mesh.elements.len(), 24);
    assert_eq!(m.mesh.nodes[0], [1.0, 0.0, 0.0]);
    assert_eq!(m.material.model, MaterialModel::NeoHookean);
    assert_eq!(m.material.poisson, 0.45);
    assert_eq!(m.scheme.time_step_factor, 0.8);
    assert_eq!(m.scheme.h_crit_update_interval, 0);
    assert_eq!(m.scheme.h_crit_tolerance, 1e-4);
    assert_eq!(m.scheme.energy_growth_limit, 2.0);
    assert_eq!(m.moulds[0].normal, [0.0, 0.0, 1.0]);
    assert_eq!(m.moulds[1].normal, [-0.6, 0.0, 0.8]);
    let velocity = &m.moulds[1].velocity.as_ref().unwrap().points;
    assert_eq!(velocity[1], (1.0, [0.0, 0.0, 0.2]));
    let law = &m.interfaces[0].law;
    assert_eq!(law.spec().key, "exponential");
    assert_eq!(law.values().number("decay"), Ok(5.0));
    assert_eq!(m.interfaces[0].mu_inf, 0.5);
    assert_eq!(m.interfaces[0].initial_damage, 2e-4);
    assert_eq!(m.interfaces[1].initial_damage, 0.0);
    assert_eq!(
        (m.interfaces[1].faces.as_str(), m.interfaces[1].law.u_r),
        ("x+", 1e-3)
    );
    assert_eq!((m.contacts[0].plane, m.contacts[0].mu), (1, 0.3));
    assert_eq!(m.displacements[0].component, 1);
    assert_eq!(m.displacements[0].history.value(0.15), [0.3]);
    assert_eq!(m.tractions[0].amplitude.value(0.05), [0.5]);
    assert_eq!(m.tractions[1].amplitude.value(7.0), [1.0]);
    assert_eq!(scene.text, FULL);
    // The resolved text is a scene in its own right and gives the same model.
    let again = parse_scene(&scene.resolved, "scenes/full.toml", &[]).unwrap();
    assert_eq!(again.model.moulds, m.moulds);
    assert_eq!(again.model.interfaces, m.interfaces);
}

#[test]
fn defaults_and_name_from_the_file_stem() {
    let text = "end_time = 1.0\n[mesh]\nsize = [1, 1, 1]\ncells = [1, 1, 1]\n\
                [material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n";
    let m = parse_scene(text, "scenes/cube.toml", &[]).unwrap().model;
    assert_eq!(m.name, "cube");
    assert_eq!(m.material.model, MaterialModel::Svk);
    assert_eq!(m.scheme, SchemeParams::default());
    assert_eq!(
        (m.gravity, m.initial_velocity, m.initial_angular_velocity),
        ([0.0; 3], [0.0; 3], [0.0; 3])
    );
    assert!(m.moulds.is_empty() && m.interfaces.is_empty() && m.tractions.is_empty());
}

#[test]
fn override_enters_a_single_element_array_implicitly() {
    let text = "end_time = 1.0\n[mesh]\nsize = [1, 1, 1]\ncells = [1, 1, 1]\n\
                [material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n\
                [[plane]]\nname = \"floor\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\n\
                [[interface]]\nfaces = \"z-\"\nplane = \"floor\"\n[interface.law]\n\
                family = \"bilinear\"\ng_n0 = 1e9\nalpha_e = 1e-4\nu_r = 1e-3\n";
    let set = [
        "plane.normal=[1, 0, 0]",
        "interface.law.u_r=0.02",
        "name = renamed run",
    ]
    .map(String::from);
    let scene = parse_scene(text, "scenes/t.toml", &set).unwrap();
    assert_eq!(scene.model.moulds[0].normal, [1.0, 0.0, 0.0]);
    assert_eq!(scene.model.interfaces[0].law.u_r, 0.02);
    assert_eq!(scene.model.name, "renamed run");
    assert!(scene.resolved.contains("name = \"renamed run\""));
    assert!(!scene.text.contains("renamed"));
}

/// A string with runs of 300 quotes of both kinds, in the file and through `--set`, comes back
/// unchanged from the resolved text. The TOML writer (toml_write 0.1.2) counts a run of quotes
/// in a byte: past 255 the count wraps (a panic with overflow checks, which the fuzz build turns
/// off for that crate), and its longest run stays at 255, which still makes it escape them.
#[test]
fn long_runs_of_quotes_survive_the_resolved_text() {
    let quotes = format!("a{}b{}c", "\"".repeat(300), "'".repeat(300));
    let text = format!(
        "end_time = 1.0\ndescription = {}\n[mesh]\nsize = [1, 1, 1]\ncells = [1, 1, 1]\n\
         [material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n",
        toml::Value::String(quotes.clone())
    );
    let scene = parse_scene(&text, "scenes/t.toml", &[format!("name={quotes}")]).unwrap();
    assert_eq!(
        (scene.model.description.as_str(), scene.model.name.as_str()),
        (quotes.as_str(), quotes.as_str())
    );
    let again = parse_scene(&scene.resolved, "scenes/t.toml", &[]).unwrap();
    assert_eq!(
        (again.model.description.as_str(), again.model.name.as_str()),
        (quotes.as_str(), quotes.as_str())
    );
}

#[test]
fn override_with_explicit_indices() {
    let set: Vec<String> = [
        "interface.1.mu_inf=0.25",
        "mesh.cells.2=5",
        "scheme.time_step_factor=0.3",
        "plane.1.velocity.0=[0.0, 1.0, 0.0, 0.0]",
    ]
    .map(String::from)
    .to_vec();
    let m = parse_scene(FULL, "scenes/t.toml", &set).unwrap().model;
    assert_eq!(m.interfaces[1].mu_inf, 0.25);
    assert_eq!(m.interfaces[0].mu_inf, 0.5);
    assert_eq!(m.mesh.elements.len(), 2 * 3 * 5);
    assert_eq!(m.scheme.time_step_factor, 0.3);
    assert_eq!(
        m.moulds[1].velocity.as_ref().unwrap().value(0.0),
        [1.0, 0.0, 0.0]
    );
}

#[test]
fn override_creates_a_missing_table() {
    let text = FULL.replace("[scheme]\ntime_step_factor = 0.8\n", "[scheme]\n");
    let set = ["scheme.time_step_factor=1.5".to_string()];
    let m = parse_scene(&text, "scenes/t.toml", &set).unwrap().model;
    assert_eq!(m.scheme.time_step_factor, 1.5);
}

#[test]
fn ambiguous_override_says_how_to_index() {
    assert_error(
        FULL,
        &["interface.law.u_r=0.02"],
        &[
            "scenes/t.toml: --set `interface.law.u_r=0.02`",
            "`interface` has 2 elements",
            "`interface.0.law.u_r`",
        ],
    );
}

#[test]
fn malformed_overrides_are_named() {
    let cases = [
        ("end_time", "--set `end_time`: expected `key.path=value`"),
        ("=3", "--set `=3`: the key `` is empty"),
        ("mesh..size=3", "--set `mesh..size=3`: the key `mesh..size`"),
        (
            "plane.5.name=x",
            "index 5 is out of range: `plane` has 2 elements",
        ),
        ("end_time.x=1", "`end_time` is a float, not a table"),
        (
            "mesh.size.x=1",
            "`mesh.size` is an array of values: index it",
        ),
        ("mesh.size.0.x=1", "`mesh.size` holds values, not tables"),
    ];
    for (set, expected) in cases {
        let e = err(FULL, &[set]);
        assert!(e.contains(expected), "{e}");
    }
}

#[test]
fn errors_after_overrides_say_so() {
    let e = err(FULL, &["material.young=-1"]);
    assert!(
        e.starts_with("scenes/t.toml (after --set overrides): key `material.young` = -1.0:"),
        "{e}"
    );
    assert_error(
        FULL,
        &["mesh.cells=[2,2]"],
        &["(after --set overrides): key `mesh.cells`: TOML parse error at line"],
    );
}

#[test]
fn law_keys_must_match_the_family() {
    let table = "points = [[0.0, 2e9], [1e-3, 0.0]]";
    assert_error(
        &FULL.replace(table, &format!("{table}\ng_n0 = 1.0")),
        &[],
        &[
            "key `interface[1].law.g_n0` = 1.0: not a parameter of the `table` law, \
           which takes `points`",
        ],
    );
    assert_error(
        &FULL.replace("u_r = 1.0e-3\n", ""),
        &[],
        &["key `interface[0].law.u_r` is missing: the `exponential` law takes"],
    );
    let bilinear = "family = \"bilinear\"\ndecay = 3.0";
    assert_error(
        &FULL.replace("family = \"exponential\"", bilinear),
        &[],
        &["key `interface[0].law.decay` = 3.0: not a parameter of the `bilinear` law"],
    );
}

#[test]
fn a_face_set_meets_a_plane_once() {
    assert_error(
        &FULL.replace("plane = \"wall\"", "plane = \"mould\""),
        &[],
        &[
            "key `contact[0].faces` = \"z-\": face set `z-` is already attached to plane \
           `mould` by `interface[0]`",
        ],
    );
}

#[test]
fn unreadable_file_is_named() {
    let e = load_scene(Path::new("/nonexistent/dir/s.toml"), &[]).unwrap_err();
    assert!(matches!(e, SceneError::Io { .. }));
    assert!(
        e.to_string()
            .starts_with("/nonexistent/dir/s.toml: cannot read"),
        "{e}"
    );
}

/// A one-cell cube with `displacement` lines appended (a pull of its top face).
fn pulled(displacement: &str) -> String {
    format!(
        "end_time = 0.3\n[mesh]\nsize = [1, 1, 1]\ncells = [1, 1, 1]\n\
         [material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n\
         [[displacement]]\nfaces = \"z+\"\ncomponent = \"z\"\n{displacement}\n"
    )
}

#[test]
fn a_pull_speed_is_the_table_of_its_ramp_and_constant_speed() {
    let scene = parse_scene(
        &pulled("speed = 0.1\nramp = 2e-3\nramp_steps = 4"),
        "scenes/t.toml",
        &[],
    )
    .unwrap();
    let u = &scene.model.displacements[0].history;
    // Speed v k/4 on the k-th quarter of the ramp: U at the quarter ends is v t_r/4 · (1, 3,
    // 6, 10)/4, then U = U(t_r) + v (t − t_r) (linear, so exact at any t up to round-off).
    let (v, q) = (0.1, 5e-4);
    for (k, sum) in [(1, 1.0), (2, 3.0), (3, 6.0), (4, 10.0)] {
        let expected = v * q * sum / 4.0;
        assert!((u.value(k as f64 * q)[0] - expected).abs() <= 1e-15 * expected);
    }
    for t in [0.01, 0.3, 0.31] {
        let expected = v * q * 10.0 / 4.0 + v * (t - 2e-3);
        assert!(
            (u.value(t)[0] - expected).abs() <= 1e-14 * expected,
            "t = {t}"
        );
    }
    let at_once = parse_scene(&pulled("speed = -0.5"), "scenes/t.toml", &[]).unwrap();
    assert_eq!(at_once.model.displacements[0].history.value(0.2)[0], -0.1);
}

#[test]
fn a_pull_is_a_table_or_a_speed() {
    assert_error(
        &pulled("table = [[0.0, 0.0]]\nspeed = 0.1"),
        &[],
        &["displacement[0].speed", "0.1", "either `table` or `speed`"],
    );
    assert_error(
        &pulled(""),
        &[],
        &["displacement[0].table", "`speed` (m/s)"],
    );
    assert_error(
        &pulled("table = [[0.0, 0.0]]\nramp = 0.01"),
        &[],
        &["displacement[0].ramp", "0.01", "belongs to `speed`"],
    );
    assert_error(
        &pulled("speed = 0.1\nramp = -1.0"),
        &[],
        &["displacement[0].ramp", "-1", "≥ 0 s"],
    );
    assert_error(
        &pulled("speed = 0.1\nramp = 1e-3\nramp_steps = 0"),
        &[],
        &["displacement[0].ramp_steps", "≥ 1"],
    );
}

/// FULL's `[[contact]]` entry with `extra` keys after its `mu` (a `[contact.law]` table last).
fn adhesive(extra: &str) -> String {
    FULL.replace(
        "plane = \"wall\"\nmu = 0.3\n",
        &format!("plane = \"wall\"\nmu = 0.3\n{extra}"),
    )
}

const GLUE: &str = "[contact.law]\nfamily = \"bilinear\"\ng_n0 = 1e9\nalpha_e = 1e-4\nu_r = 1e-3\n";

#[test]
fn a_contact_with_a_law_is_glue_that_forms_on_contact() {
    let scene = parse_scene(&adhesive(&format!("mu_inf = 0.4\n{GLUE}")), "t.toml", &[]).unwrap();
    let m = &scene.model;
    assert!(m.contacts.is_empty());
    let itf = &m.interfaces[2];
    assert_eq!((itf.faces.as_str(), itf.plane), ("z-", 1));
    assert_eq!((itf.mu_inf, itf.forms_on_contact), (0.4, Some(0.3)));
    assert_eq!((itf.law.alpha_e, itf.law.u_r), (1e-4, 1e-3));
    assert!(m.interfaces[..2]
        .iter()
        .all(|i| i.forms_on_contact.is_none()));
}

#[test]
fn glue_keys_of_a_contact_are_checked() {
    assert_error(
        &adhesive("mu_inf = 0.4\n"),
        &[],
        &["key `contact[0].mu_inf` = 0.4: is the friction of torn glue: it needs the glue's law, a [contact.law] table"],
    );
    assert_error(
        &adhesive("[contact.delay]\ntau_c = 1e-3\na = 1.0\n"),
        &[],
        &["key `contact[0].delay`", "it needs the glue's law"],
    );
    assert_error(
        &adhesive(&format!("mu_inf = -0.1\n{GLUE}")),
        &[],
        &["key `contact[0].mu_inf` = -0.1: must be ≥ 0"],
    );
    assert_error(
        &adhesive(&GLUE.replace("u_r = 1e-3\n", "")),
        &[],
        &["key `contact[0].law.u_r` is missing: the `bilinear` law takes"],
    );
    assert_error(
        &adhesive(&GLUE.replace("alpha_e = 1e-4", "alpha_e = 2e-3")),
        &[],
        &["key `contact[0].law.u_r`"],
    );
    assert_error(
        &adhesive(&format!("{GLUE}[contact.delay]\ntau_c = -1.0\na = 1.0\n")),
        &[],
        &["key `contact[0].delay.tau_c` = -1"],
    );
}
