//! Scene files: TOML text → validated [`Model`]. Every key, its unit, default and admissible
//! range is documented in `scenes/README.md`.
//!
//! Pipeline: parse the text into a `toml::Table`, apply the `--set` overrides to it, print it back
//! (`Scene::resolved`), deserialize that into raw serde structs (unknown keys and wrong types are
//! refused here, with the key path and toml's line and column), refuse any non-finite number, then
//! check ranges and cross-references while building the model types. Every error names the file,
//! the key path, the offending value and what is admissible.

use crate::law::{family_or_error, LawError, ParamKind, ParamValue, ParamValues, StiffnessLaw};
use crate::material::{Material, MaterialModel};
use crate::mesh::Mesh;
use crate::model::{
    ContactFaces, Integration, Interface, Model, PiecewiseLinear, PrescribedDisplacement,
    RigidPlane, SchemeParams, Traction,
};
use serde::de::DeserializeOwned;
use serde::Deserialize;
use std::path::Path;

/// Largest mesh a scene may ask for, in elements.
const MAX_ELEMENTS: u128 = 50_000_000;

/// A loaded scene: the model and the texts it came from.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The validated model.
    pub model: Model,
    /// The scene file text as read.
    pub text: String,
    /// The TOML document after the overrides were applied, what the model was built from: one
    /// section per table, keys sorted, arrays on one line (toml's pretty printer puts every
    /// array element on its own line, which makes tables of rows unreadable).
    pub resolved: String,
    /// The file name used in messages.
    pub file: String,
}

/// Why a scene could not be loaded. `file` is the file name, followed by
/// `(after --set overrides)` when overrides were applied (line numbers then refer to
/// [`Scene::resolved`], not to the file).
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
    };
    for (key, value) in &doc {
        check.finite(key, value)?;
    }
    let stem = Path::new(file)
        .file_stem()
        .map_or_else(|| file.to_string(), |s| s.to_string_lossy().into_owned());
    let model = check.model(raw, stem)?;
    Ok(Scene {
        model,
        text: text.to_string(),
        resolved,
        file: file.to_string(),
    })
}

/// Deserializes TOML text, keeping the key path and toml's line/column in errors.
fn from_toml<T: DeserializeOwned>(text: &str, file: &str) -> Result<T, SceneError> {
    serde_path_to_error::deserialize(toml::Deserializer::new(text)).map_err(|e| {
        let key = e.path().to_string();
        SceneError::Toml {
            file: file.to_string(),
            key: (key != ".").then_some(key),
            message: e.into_inner().to_string().trim_end().to_string(),
        }
    })
}

/// Applies one `key.path=value` override to the document; the error is the reason.
fn apply_override(doc: &mut toml::Table, spec: &str) -> Result<(), String> {
    let (key, text) = spec
        .split_once('=')
        .ok_or("expected `key.path=value` (no `=` found)")?;
    let segs: Vec<&str> = key.trim().split('.').map(str::trim).collect();
    if segs.iter().any(|s| s.is_empty()) {
        return Err(format!(
            "the key `{}` is empty or has an empty segment; expected `key.path=value`",
            key.trim()
        ));
    }
    let text = text.trim();
    let value = toml::Value::deserialize(toml::de::ValueDeserializer::new(text))
        .unwrap_or_else(|_| toml::Value::String(text.to_string()));
    let mut node = doc;
    let mut i = 0;
    loop {
        let (seg, last) = (segs[i], i + 1 == segs.len());
        if last {
            node.insert(seg.to_string(), value);
            return Ok(());
        }
        let next = node
            .entry(seg)
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        i += 1;
        node = match next {
            toml::Value::Table(t) => t,
            toml::Value::Array(items) => {
                let path = segs[..i].join(".");
                let rest = segs[i..].join(".");
                let index = match segs[i].parse::<usize>() {
                    Ok(n) => {
                        i += 1;
                        n
                    }
                    Err(_) if !items.iter().all(toml::Value::is_table) => {
                        return Err(format!(
                            "`{path}` is an array of values: index it with a number, \
                             e.g. `{path}.0`"
                        ))
                    }
                    Err(_) if items.len() == 1 => 0,
                    Err(_) if items.is_empty() => return Err(format!("`{path}` is empty")),
                    Err(_) => {
                        return Err(format!(
                            "`{path}` has {} elements: say which one, e.g. `{path}.0.{rest}`",
                            items.len()
                        ))
                    }
                };
                let len = items.len();
                let Some(item) = items.get_mut(index) else {
                    return Err(format!(
                        "index {index} is out of range: `{path}` has {len} elements"
                    ));
                };
                if i == segs.len() {
                    *item = value;
                    return Ok(());
                }
                match item {
                    toml::Value::Table(t) => t,
                    _ => {
                        return Err(format!(
                            "`{path}` holds values, not tables: `{path}.{index}` has no keys"
                        ))
                    }
                }
            }
            other => {
                return Err(format!(
                    "`{}` is a {}, not a table: it has no key `{}`",
                    segs[..i].join("."),
                    other.type_str(),
                    segs[i]
                ))
            }
        };
    }
}

// Raw serde structs: the file as written. Optional keys are `Option` or `#[serde(default)]`.

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    name: Option<String>,
    #[serde(default)]
    description: String,
    end_time: f64,
    #[serde(default)]
    gravity: [f64; 3],
    #[serde(default)]
    initial_velocity: [f64; 3],
    #[serde(default)]
    initial_angular_velocity: [f64; 3],
    mesh: RawMesh,
    material: RawMaterial,
    #[serde(default)]
    scheme: RawScheme,
    #[serde(default)]
    plane: Vec<RawPlane>,
    #[serde(default)]
    interface: Vec<RawInterface>,
    #[serde(default)]
    contact: Vec<RawContact>,
    #[serde(default)]
    displacement: Vec<RawDisplacement>,
    #[serde(default)]
    traction: Vec<RawTraction>,
}

/// Either a box (`size`, `cells`, optional `origin`) or a Gmsh file (`file`, optional `scale`);
/// [`Check::mesh`] enforces that exactly one form is given.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMesh {
    origin: Option<[f64; 3]>,
    size: Option<[f64; 3]>,
    cells: Option<[usize; 3]>,
    file: Option<String>,
    scale: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMaterial {
    model: Option<MaterialModel>,
    young: f64,
    poisson: f64,
    density: f64,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawScheme {
    time_step_factor: Option<f64>,
    h_crit_update_interval: Option<usize>,
    h_crit_tolerance: Option<f64>,
    energy_growth_limit: Option<f64>,
    integration: Option<Integration>,
    hourglass_coefficient: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPlane {
    name: String,
    point: [f64; 3],
    normal: [f64; 3],
    velocity: Option<Vec<[f64; 4]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawInterface {
    faces: String,
    plane: String,
    #[serde(default)]
    mu_inf: f64,
    #[serde(default)]
    initial_damage: f64,
    law: RawLaw,
}

/// `[interface.law]`: the family's key and its parameters, which the family's row of the table
/// ([`crate::law::families`]) checks.
#[derive(Deserialize)]
struct RawLaw {
    family: String,
    #[serde(flatten)]
    params: toml::Table,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawContact {
    faces: String,
    plane: String,
    #[serde(default)]
    mu: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawDisplacement {
    faces: String,
    component: Axis,
    table: Vec<[f64; 2]>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum Axis {
    X,
    Y,
    Z,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTraction {
    faces: String,
    vector: [f64; 3],
    amplitude: Option<Vec<[f64; 2]>>,
}

/// A number as the messages show it (shortest form that reads back to the same value).
fn num(x: f64) -> String {
    format!("{x:?}")
}

/// A TOML value as the messages show it: numbers (integers too) as [`num`], arrays element by
/// element, anything else as TOML writes it.
fn show(value: &toml::Value) -> String {
    match value {
        toml::Value::Float(x) => num(*x),
        toml::Value::Integer(i) => num(*i as f64),
        toml::Value::Array(items) => {
            let items: Vec<String> = items.iter().map(show).collect();
            format!("[{}]", items.join(", "))
        }
        other => other.to_string(),
    }
}

/// Validation of the raw scene; knows the file label for its errors and the directory that
/// relative paths in the scene (`mesh.file`) are resolved against.
struct Check<'a> {
    file: &'a str,
    dir: &'a Path,
}

impl Check<'_> {
    fn invalid(
        &self,
        key: impl Into<String>,
        value: String,
        reason: impl Into<String>,
    ) -> SceneError {
        SceneError::Invalid {
            file: self.file.to_string(),
            key: key.into(),
            value,
            reason: reason.into(),
        }
    }

    /// `Ok` if `ok`, else an [`SceneError::Invalid`] for the number `value` at `key`.
    fn require(
        &self,
        ok: bool,
        key: impl Into<String>,
        value: f64,
        reason: &str,
    ) -> Result<(), SceneError> {
        if ok {
            Ok(())
        } else {
            Err(self.invalid(key, num(value), reason))
        }
    }

    /// Refuses inf and nan anywhere in the document.
    fn finite(&self, key: &str, value: &toml::Value) -> Result<(), SceneError> {
        match value {
            toml::Value::Float(x) if !x.is_finite() => {
                Err(self.invalid(key, num(*x), "must be a finite number"))
            }
            toml::Value::Array(items) => items
                .iter()
                .enumerate()
                .try_for_each(|(i, v)| self.finite(&format!("{key}[{i}]"), v)),
            toml::Value::Table(t) => t
                .iter()
                .try_for_each(|(k, v)| self.finite(&format!("{key}.{k}"), v)),
            _ => Ok(()),
        }
    }

    /// A face set name that exists in the mesh.
    fn faces(&self, mesh: &Mesh, key: String, name: &str) -> Result<String, SceneError> {
        if mesh.face_sets.contains_key(name) {
            return Ok(name.to_string());
        }
        let names: Vec<String> = mesh.face_sets.keys().map(|n| format!("`{n}`")).collect();
        Err(self.invalid(
            key,
            format!("{name:?}"),
            format!("no face set of that name; admissible: {}", names.join(", ")),
        ))
    }

    /// The index of the plane named `name`.
    fn plane(&self, planes: &[RigidPlane], key: String, name: &str) -> Result<usize, SceneError> {
        if let Some(i) = planes.iter().position(|p| p.name == name) {
            return Ok(i);
        }
        let reason = if planes.is_empty() {
            "no plane of that name: the scene defines no [[plane]]".to_string()
        } else {
            let names: Vec<String> = planes.iter().map(|p| format!("`{}`", p.name)).collect();
            format!("no plane of that name; admissible: {}", names.join(", "))
        };
        Err(self.invalid(key, format!("{name:?}"), reason))
    }

    /// A piecewise-linear history from rows (t, value): ≥ 1 row, t ≥ 0 strictly increasing.
    fn history<const N: usize>(
        &self,
        key: &str,
        rows: Vec<(f64, [f64; N])>,
    ) -> Result<PiecewiseLinear<N>, SceneError> {
        if rows.is_empty() {
            return Err(self.invalid(key, "[]".into(), "needs at least one row [t, …]"));
        }
        for (i, row) in rows.iter().enumerate() {
            let t_key = format!("{key}[{i}][0]");
            self.require(row.0 >= 0.0, &t_key, row.0, "times must be ≥ 0 s")?;
            if i > 0 && row.0 <= rows[i - 1].0 {
                return Err(self.invalid(
                    t_key,
                    num(row.0),
                    format!(
                        "times must be strictly increasing (the previous row has t = {} s)",
                        num(rows[i - 1].0)
                    ),
                ));
            }
        }
        Ok(PiecewiseLinear { points: rows })
    }

    /// The RCCM law of `interface[i]`: the keys its family takes, then the family's checks.
    fn law(&self, key: &str, raw: RawLaw) -> Result<StiffnessLaw, SceneError> {
        let law_error = |e: LawError| self.invalid(format!("{key}.{}", e.key), e.value, e.reason);
        let spec = family_or_error(&raw.family).map_err(law_error)?;
        let mut values = ParamValues::default();
        for (k, value) in raw.params {
            let Some(param) = spec.param(&k) else {
                return Err(self.invalid(
                    format!("{key}.{k}"),
                    show(&value),
                    format!(
                        "not a parameter of the `{}` law, which takes {}",
                        spec.key,
                        spec.takes()
                    ),
                ));
            };
            let shown = show(&value);
            let typed = match param.kind {
                ParamKind::Number(_) => value.try_into().map(ParamValue::Number),
                ParamKind::Points { .. } => value.try_into().map(ParamValue::Points),
            };
            let typed = typed.map_err(|e| {
                let expected = match param.kind {
                    ParamKind::Number(_) => format!("a number ({})", param.unit),
                    ParamKind::Points { .. } => "rows [α, g_N] of two numbers".to_string(),
                };
                self.invalid(
                    format!("{key}.{k}"),
                    shown,
                    format!("must be {expected}: {e}"),
                )
            })?;
            values.0.insert(k, typed);
        }
        if let Some(p) = (spec.params.iter()).find(|p| !p.optional && values.get(p.key).is_none()) {
            return Err(SceneError::Missing {
                file: self.file.to_string(),
                key: format!("{key}.{}", p.key),
                reason: format!("the `{}` law takes {}", spec.key, spec.takes()),
            });
        }
        spec.build(&values).map_err(law_error)
    }

    /// The `[mesh]` section: a box, or a Gmsh file read by [`crate::gmsh::read_msh`] (its path
    /// relative to the scene file's directory) with its coordinates multiplied by `scale`.
    fn mesh(&self, m: &RawMesh) -> Result<Mesh, SceneError> {
        const FORMS: &str = "a mesh is either a Gmsh file (`file`, optional `scale`) or a box \
                             (`size` and `cells`, optional `origin`)";
        if let Some(file) = &m.file {
            let box_keys = [
                ("origin", m.origin.map(|v| format!("{v:?}"))),
                ("size", m.size.map(|v| format!("{v:?}"))),
                ("cells", m.cells.map(|v| format!("{v:?}"))),
            ];
            if let Some((k, Some(v))) = box_keys.into_iter().find(|k| k.1.is_some()) {
                return Err(self.invalid(
                    format!("mesh.{k}"),
                    v,
                    format!("`mesh.file` is given, so `mesh.{k}` cannot be: {FORMS}"),
                ));
            }
            let scale = m.scale.unwrap_or(1.0);
            self.require(
                scale > 0.0,
                "mesh.scale",
                scale,
                "must be > 0 (metres per mesh unit)",
            )?;
            let path = self.dir.join(file);
            let mut mesh = crate::gmsh::read_msh(&path)
                .map_err(|e| self.invalid("mesh.file", format!("{file:?}"), e.to_string()))?;
            if scale != 1.0 {
                for x in &mut mesh.nodes {
                    *x = x.map(|c| c * scale);
                }
            }
            return Ok(mesh);
        }
        if let Some(scale) = m.scale {
            return Err(self.invalid(
                "mesh.scale",
                num(scale),
                format!("applies to a `mesh.file` only (a box's `size` is in metres): {FORMS}"),
            ));
        }
        let missing = |key: &str| SceneError::Missing {
            file: self.file.to_string(),
            key: format!("mesh.{key}"),
            reason: format!("a box mesh needs `size` and `cells`; {FORMS}"),
        };
        let size = m.size.ok_or_else(|| missing("size"))?;
        let cells = m.cells.ok_or_else(|| missing("cells"))?;
        for a in 0..3 {
            let key = format!("mesh.size[{a}]");
            self.require(size[a] > 0.0, key, size[a], "must be > 0 m")?;
            if cells[a] < 1 {
                return Err(self.invalid(
                    format!("mesh.cells[{a}]"),
                    cells[a].to_string(),
                    "must be an integer ≥ 1",
                ));
            }
        }
        let elements: u128 = cells.iter().map(|&c| c as u128).product();
        if elements > MAX_ELEMENTS {
            return Err(self.invalid(
                "mesh.cells",
                format!("{cells:?}"),
                format!("{elements} elements: at most {MAX_ELEMENTS} are admissible"),
            ));
        }
        Ok(Mesh::boxed(m.origin.unwrap_or_default(), size, cells))
    }

    fn model(&self, raw: RawScene, default_name: String) -> Result<Model, SceneError> {
        self.require(
            raw.end_time > 0.0,
            "end_time",
            raw.end_time,
            "must be > 0 s",
        )?;

        let mesh = self.mesh(&raw.mesh)?;

        let mat = &raw.material;
        self.require(
            mat.young > 0.0,
            "material.young",
            mat.young,
            "must be > 0 Pa",
        )?;
        self.require(
            mat.poisson > -1.0 && mat.poisson < 0.5,
            "material.poisson",
            mat.poisson,
            "must satisfy -1 < ν < 0.5 (0.5 is incompressible; use 0.49 at most)",
        )?;
        self.require(
            mat.density > 0.0,
            "material.density",
            mat.density,
            "must be > 0 kg/m³",
        )?;
        let material = Material::new(
            mat.model.unwrap_or(MaterialModel::Svk),
            mat.young,
            mat.poisson,
            mat.density,
        );

        let d = SchemeParams::default();
        let s = &raw.scheme;
        let scheme = SchemeParams {
            time_step_factor: s.time_step_factor.unwrap_or(d.time_step_factor),
            h_crit_update_interval: s.h_crit_update_interval.unwrap_or(d.h_crit_update_interval),
            h_crit_tolerance: s.h_crit_tolerance.unwrap_or(d.h_crit_tolerance),
            energy_growth_limit: s.energy_growth_limit.unwrap_or(d.energy_growth_limit),
            integration: s.integration.unwrap_or(d.integration),
            hourglass_coefficient: s.hourglass_coefficient.unwrap_or(d.hourglass_coefficient),
        };
        let f = scheme.time_step_factor;
        self.require(
            f > 0.0 && f < 2.0,
            "scheme.time_step_factor",
            f,
            "must be in (0, 2) (above 1 the scheme is unstable)",
        )?;
        let tol = scheme.h_crit_tolerance;
        self.require(
            tol > 0.0 && tol <= 1e-2,
            "scheme.h_crit_tolerance",
            tol,
            "must be in (0, 0.01]",
        )?;
        let g = scheme.energy_growth_limit;
        self.require(g > 1.0, "scheme.energy_growth_limit", g, "must be > 1")?;
        let k = scheme.hourglass_coefficient;
        self.require(
            (0.0..=1.0).contains(&k),
            "scheme.hourglass_coefficient",
            k,
            "must be in [0, 1] (typical 0.03–0.1)",
        )?;

        let mut planes: Vec<RigidPlane> = Vec::with_capacity(raw.plane.len());
        for (i, p) in raw.plane.into_iter().enumerate() {
            let key = format!("plane[{i}]");
            if let Some(j) = planes.iter().position(|q| q.name == p.name) {
                return Err(self.invalid(
                    format!("{key}.name"),
                    format!("{:?}", p.name),
                    format!("plane names must be unique (`plane[{j}]` has it already)"),
                ));
            }
            // Scale before squaring so that neither tiny nor huge normals under/overflow.
            let scale = p.normal.iter().fold(0.0f64, |m, c| m.max(c.abs()));
            if scale == 0.0 {
                return Err(self.invalid(
                    format!("{key}.normal"),
                    format!("{:?}", p.normal),
                    "must be a non-zero vector (it is normalised on load)",
                ));
            }
            let n = p.normal.map(|c| c / scale);
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let velocity = match p.velocity {
                None => None,
                Some(rows) => Some(self.history(
                    &format!("{key}.velocity"),
                    rows.iter().map(|r| (r[0], [r[1], r[2], r[3]])).collect(),
                )?),
            };
            planes.push(RigidPlane {
                name: p.name,
                point: p.point,
                normal: n.map(|c| c / len),
                velocity,
            });
        }

        // (face set, plane) pairs already attached, with the key that attached them: a face set
        // meets a plane through one interface or one contact.
        let mut attached: Vec<(String, usize, String)> = vec![];
        let mut attach = |faces: &str, plane: usize, key: String| {
            if let Some((_, _, first)) = attached.iter().find(|(f, p, _)| f == faces && *p == plane)
            {
                return Err(self.invalid(
                    format!("{key}.faces"),
                    format!("{faces:?}"),
                    format!(
                        "face set `{faces}` is already attached to plane `{}` by `{first}`; \
                         a face set meets a plane through one [[interface]] or one [[contact]] \
                         (an interface already gives contact with friction mu_inf once ruptured)",
                        planes[plane].name
                    ),
                ));
            }
            attached.push((faces.to_string(), plane, key));
            Ok(())
        };

        let mut interfaces = Vec::with_capacity(raw.interface.len());
        for (i, it) in raw.interface.into_iter().enumerate() {
            let key = format!("interface[{i}]");
            let faces = self.faces(&mesh, format!("{key}.faces"), &it.faces)?;
            let plane = self.plane(&planes, format!("{key}.plane"), &it.plane)?;
            self.require(
                it.mu_inf >= 0.0,
                format!("{key}.mu_inf"),
                it.mu_inf,
                "must be ≥ 0",
            )?;
            self.require(
                it.initial_damage >= 0.0,
                format!("{key}.initial_damage"),
                it.initial_damage,
                "must be ≥ 0 m (the damage α₀ at t = 0; ≥ u_r means ruptured from the start)",
            )?;
            let law = self.law(&format!("{key}.law"), it.law)?;
            attach(&faces, plane, key)?;
            interfaces.push(Interface {
                faces,
                plane,
                law,
                mu_inf: it.mu_inf,
                initial_damage: it.initial_damage,
            });
        }

        let mut contacts = Vec::with_capacity(raw.contact.len());
        for (i, c) in raw.contact.into_iter().enumerate() {
            let key = format!("contact[{i}]");
            let faces = self.faces(&mesh, format!("{key}.faces"), &c.faces)?;
            let plane = self.plane(&planes, format!("{key}.plane"), &c.plane)?;
            self.require(c.mu >= 0.0, format!("{key}.mu"), c.mu, "must be ≥ 0")?;
            attach(&faces, plane, key)?;
            contacts.push(ContactFaces {
                faces,
                plane,
                mu: c.mu,
            });
        }

        let mut displacements = Vec::with_capacity(raw.displacement.len());
        for (i, d) in raw.displacement.into_iter().enumerate() {
            let key = format!("displacement[{i}]");
            displacements.push(PrescribedDisplacement {
                faces: self.faces(&mesh, format!("{key}.faces"), &d.faces)?,
                component: d.component as usize,
                history: self.history(
                    &format!("{key}.table"),
                    d.table.iter().map(|r| (r[0], [r[1]])).collect(),
                )?,
            });
        }

        let mut tractions = Vec::with_capacity(raw.traction.len());
        for (i, t) in raw.traction.into_iter().enumerate() {
            let key = format!("traction[{i}]");
            let faces = self.faces(&mesh, format!("{key}.faces"), &t.faces)?;
            let amplitude = match t.amplitude {
                None => PiecewiseLinear::constant([1.0]),
                Some(rows) => self.history(
                    &format!("{key}.amplitude"),
                    rows.iter().map(|r| (r[0], [r[1]])).collect(),
                )?,
            };
            tractions.push(Traction {
                faces,
                vector: t.vector,
                amplitude,
            });
        }

        Ok(Model {
            name: raw.name.unwrap_or(default_name),
            description: raw.description,
            mesh,
            material,
            gravity: raw.gravity,
            initial_velocity: raw.initial_velocity,
            initial_angular_velocity: raw.initial_angular_velocity,
            planes,
            interfaces,
            contacts,
            displacements,
            tractions,
            scheme,
            end_time: raw.end_time,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert_eq!(m.planes[0].normal, [0.0, 0.0, 1.0]);
        assert_eq!(m.planes[1].normal, [-0.6, 0.0, 0.8]);
        let velocity = &m.planes[1].velocity.as_ref().unwrap().points;
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
        assert_eq!(again.model.planes, m.planes);
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
        assert!(m.planes.is_empty() && m.interfaces.is_empty() && m.tractions.is_empty());
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
        assert_eq!(scene.model.planes[0].normal, [1.0, 0.0, 0.0]);
        assert_eq!(scene.model.interfaces[0].law.u_r, 0.02);
        assert_eq!(scene.model.name, "renamed run");
        assert!(scene.resolved.contains("name = \"renamed run\""));
        assert!(!scene.text.contains("renamed"));
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
            m.planes[1].velocity.as_ref().unwrap().value(0.0),
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
        let e = err(FULL, &["interface.law.u_r=0.02"]);
        assert!(
            e.contains("scenes/t.toml: --set `interface.law.u_r=0.02`"),
            "{e}"
        );
        assert!(e.contains("`interface` has 2 elements"), "{e}");
        assert!(e.contains("`interface.0.law.u_r`"), "{e}");
    }

    #[test]
    fn malformed_overrides_are_named() {
        let e = err(FULL, &["end_time"]);
        assert!(
            e.contains("--set `end_time`: expected `key.path=value`"),
            "{e}"
        );
        let e = err(FULL, &["=3"]);
        assert!(e.contains("--set `=3`: the key `` is empty"), "{e}");
        let e = err(FULL, &["mesh..size=3"]);
        assert!(
            e.contains("--set `mesh..size=3`: the key `mesh..size`"),
            "{e}"
        );
        let e = err(FULL, &["plane.5.name=x"]);
        assert!(
            e.contains("index 5 is out of range: `plane` has 2 elements"),
            "{e}"
        );
        let e = err(FULL, &["end_time.x=1"]);
        assert!(e.contains("`end_time` is a float, not a table"), "{e}");
        let e = err(FULL, &["mesh.size.x=1"]);
        assert!(
            e.contains("`mesh.size` is an array of values: index it"),
            "{e}"
        );
        let e = err(FULL, &["mesh.size.0.x=1"]);
        assert!(e.contains("`mesh.size` holds values, not tables"), "{e}");
    }

    #[test]
    fn errors_after_overrides_say_so() {
        let e = err(FULL, &["material.young=-1"]);
        assert!(
            e.starts_with("scenes/t.toml (after --set overrides): key `material.young` = -1.0:"),
            "{e}"
        );
        let e = err(FULL, &["mesh.cells=[2,2]"]);
        assert!(
            e.contains("(after --set overrides): key `mesh.cells`: TOML parse error at line"),
            "{e}"
        );
    }

    #[test]
    fn law_keys_must_match_the_family() {
        let e = err(
            &FULL.replace(
                "points = [[0.0, 2e9], [1e-3, 0.0]]",
                "points = [[0.0, 2e9], [1e-3, 0.0]]\ng_n0 = 1.0",
            ),
            &[],
        );
        assert!(e.contains("key `interface[1].law.g_n0` = 1.0: not a parameter of the `table` law, which takes `points`"), "{e}");
        let e = err(&FULL.replace("u_r = 1.0e-3\n", ""), &[]);
        assert!(
            e.contains("key `interface[0].law.u_r` is missing: the `exponential` law takes"),
            "{e}"
        );
        let e = err(
            &FULL.replace(
                "family = \"exponential\"",
                "family = \"bilinear\"\ndecay = 3.0",
            ),
            &[],
        );
        assert!(
            e.contains("key `interface[0].law.decay` = 3.0: not a parameter of the `bilinear` law"),
            "{e}"
        );
    }

    #[test]
    fn a_face_set_meets_a_plane_once() {
        let e = err(&FULL.replace("plane = \"wall\"", "plane = \"mould\""), &[]);
        assert!(e.contains("key `contact[0].faces` = \"z-\": face set `z-` is already attached to plane `mould` by `interface[0]`"), "{e}");
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
}
