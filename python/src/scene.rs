//! `decohesion.Scene`: a scene loaded by the physics crate's parser (the command line's), with
//! overrides given as a dict and turned into `--set key=value` specs.

use crate::errors::{scene_error, solver_error};
use crate::to_python;
use decohesion_run::report::state_bytes;
use decohesion_run::scene::{load_scene, parse_scene, Scene as RustScene};
use decohesion_run::solver::Simulation;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyAny, PyBool, PyDict, PyList, PyString, PyTuple};
use serde::Serialize;

/// A validated scene (see the stub `_native.pyi` for the Python documentation).
#[pyclass(module = "decohesion", frozen)]
pub struct Scene {
    pub scene: RustScene,
}

#[pymethods]
impl Scene {
    /// Reads the scene file at `path` and applies `overrides` (`{"interface.law.u_r": 0.02}`).
    #[staticmethod]
    #[pyo3(signature = (path, overrides = None))]
    fn load(path: std::path::PathBuf, overrides: Option<&Bound<'_, PyAny>>) -> PyResult<Scene> {
        let set = override_specs(overrides)?;
        let scene = load_scene(&path, &set).map_err(scene_error)?;
        Ok(Scene { scene })
    }

    /// A scene from its TOML text; `file` names it in messages, its stem is the default scene
    /// name and its folder is where a relative `mesh.file` is looked for.
    #[staticmethod]
    #[pyo3(signature = (text, file = "scene.toml", overrides = None))]
    fn from_toml(text: &str, file: &str, overrides: Option<&Bound<'_, PyAny>>) -> PyResult<Scene> {
        let set = override_specs(overrides)?;
        let scene = parse_scene(text, file, &set).map_err(scene_error)?;
        Ok(Scene { scene })
    }

    /// What `decohesion check` prints, as a dict (see the stub).
    fn check<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let sim = Simulation::new(self.scene.model.clone())
            .map_err(|e| solver_error(py, &e, &self.scene.file))?;
        to_python(py, &CheckReport::new(&self.scene, &sim))
    }

    /// The scene's name (the file's stem unless the scene sets `name`).
    #[getter]
    fn name(&self) -> &str {
        &self.scene.model.name
    }

    #[getter]
    fn description(&self) -> &str {
        &self.scene.model.description
    }

    /// The file name used in messages.
    #[getter]
    fn file(&self) -> &str {
        &self.scene.file
    }

    /// The scene text as read.
    #[getter]
    fn text(&self) -> &str {
        &self.scene.text
    }

    /// The TOML document after the overrides, what the model was built from.
    #[getter]
    fn resolved(&self) -> &str {
        &self.scene.resolved
    }

    /// End time of the run [s].
    #[getter]
    fn end_time(&self) -> f64 {
        self.scene.model.end_time
    }

    fn __repr__(&self) -> String {
        let m = &self.scene.model;
        format!(
            "Scene({:?}: {} nodes, {} hex8, end_time = {} s)",
            m.name,
            m.mesh.nodes.len(),
            m.mesh.elements.len(),
            m.end_time
        )
    }
}

/// `{"key.path": value}` (or None) as the command line's `--set key.path=value` specs, each value
/// written as TOML: bool, int, float (`nan` and `inf` too: the scene refuses them, naming the
/// key), str (a TOML string), lists and tuples as arrays, dicts as inline tables.
pub(crate) fn override_specs(overrides: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
    let Some(overrides) = overrides.filter(|o| !o.is_none()) else {
        return Ok(Vec::new());
    };
    let dict = overrides.cast::<PyDict>().map_err(|_| {
        PyTypeError::new_err(format!(
            "overrides must be a dict {{\"key.path\": value}}, got {}",
            type_name(overrides)
        ))
    })?;
    let mut specs = Vec::with_capacity(dict.len());
    for (key, value) in dict.iter() {
        let key: String = key.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "override keys are key paths such as \"interface.law.u_r\" (str), got {}",
                type_name(&key)
            ))
        })?;
        let value = toml_value(&value).map_err(|what| {
            PyTypeError::new_err(format!(
                "override `{key}`: {what} is not a scene value (bool, int, float, str, or a \
                 list or dict of them)"
            ))
        })?;
        specs.push(format!("{key}={value}"));
    }
    Ok(specs)
}

/// A Python value as a TOML value; the error is the type name of what cannot be one.
fn toml_value(v: &Bound<'_, PyAny>) -> Result<toml::Value, String> {
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.is_truthy().unwrap_or(false)));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract().map_err(|_| type_name(v))?));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = v.extract().map_err(|_| type_name(v))?;
        return items
            .iter()
            .map(toml_value)
            .collect::<Result<_, _>>()
            .map(toml::Value::Array);
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, x) in d.iter() {
            table.insert(k.extract().map_err(|_| type_name(&k))?, toml_value(&x)?);
        }
        return Ok(toml::Value::Table(table));
    }
    // Integers (numpy's too, through __index__) before floats: 3 stays an integer.
    if v.hasattr("__index__").unwrap_or(false) {
        if let Ok(i) = v.extract::<i64>() {
            return Ok(toml::Value::Integer(i));
        }
    }
    v.extract::<f64>()
        .map(toml::Value::Float)
        .map_err(|_| type_name(v))
}

/// The Python type name of `v`, for messages.
pub(crate) fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type()
        .name()
        .map_or_else(|_| "?".into(), |n| n.to_string())
}

/// What `decohesion check` derives from a scene, for `Scene.check()`.
#[derive(Serialize)]
struct CheckReport {
    file: String,
    name: String,
    description: String,
    nodes: usize,
    elements: usize,
    /// Smallest element edge L_e [m].
    smallest_edge: f64,
    material: MaterialReport,
    /// Dilatational wave speed c_d [m/s].
    wave_speed: f64,
    /// Stable step from the Lanczos estimate of ω_max (model §6.2) [s].
    h_crit: f64,
    /// The element estimate L_e/c_d [s], for comparison.
    h_crit_element: f64,
    /// h_crit of the bulk alone when the glue may set the step [s].
    h_crit_bulk: Option<f64>,
    /// h = factor × h_crit [s].
    time_step: f64,
    time_step_factor: f64,
    end_time: f64,
    expected_steps: u64,
    interfaces: Vec<InterfaceReport>,
    state_bytes_per_element: f64,
    warnings: Vec<String>,
}

#[derive(Serialize)]
struct MaterialReport {
    model: decohesion_run::material::MaterialModel,
    young: f64,
    poisson: f64,
    density: f64,
    lambda: f64,
    mu: f64,
    /// A rubber's constants (model §1.10): the family's, `bulk` K [Pa], `volumetric`.
    rubber: Option<decohesion_run::material::rubber::Rubber>,
}

#[derive(Serialize)]
struct InterfaceReport {
    faces: String,
    /// The law family's key and label.
    family: &'static str,
    label: &'static str,
    /// g_N(0) [Pa/m], α_e [m], u_r [m].
    g_n0: f64,
    alpha_e: f64,
    u_r: f64,
    mu_inf: f64,
    /// α₀ [m].
    initial_damage: f64,
    /// T_max [Pa] and the opening where it is reached [m].
    peak_traction: f64,
    peak_opening: f64,
    /// G_c [J/m²].
    fracture_energy: f64,
    /// Glued reference area [m²] and G_c × area [J].
    area: f64,
    energy_to_break: f64,
}

impl CheckReport {
    fn new(scene: &RustScene, sim: &Simulation) -> CheckReport {
        let m = &scene.model;
        let mat = &m.material;
        let le = m.mesh.min_edge();
        let interfaces = m
            .interfaces
            .iter()
            .map(|itf| {
                let quads = &m.mesh.face_sets[&itf.faces];
                let area = m.mesh.nodal_areas(quads).iter().map(|p| p.1).sum::<f64>();
                let (peak_traction, peak_opening) = itf.law.peak_traction();
                let spec = itf.law.spec();
                InterfaceReport {
                    faces: itf.faces.clone(),
                    family: spec.key,
                    label: spec.label,
                    g_n0: itf.law.g_n0,
                    alpha_e: itf.law.alpha_e,
                    u_r: itf.law.u_r,
                    mu_inf: itf.mu_inf,
                    initial_damage: itf.initial_damage,
                    peak_traction,
                    peak_opening,
                    fracture_energy: itf.law.fracture_energy(),
                    area,
                    energy_to_break: itf.law.fracture_energy() * area,
                }
            })
            .collect();
        CheckReport {
            file: scene.file.clone(),
            name: m.name.clone(),
            description: m.description.clone(),
            nodes: m.mesh.nodes.len(),
            elements: m.mesh.elements.len(),
            smallest_edge: le,
            material: MaterialReport {
                model: mat.model,
                young: mat.young,
                poisson: mat.poisson,
                density: mat.density,
                lambda: mat.lambda,
                mu: mat.mu,
                rubber: mat.rubber,
            },
            wave_speed: mat.wave_speed(),
            h_crit: sim.state.h_crit,
            h_crit_element: le / mat.wave_speed(),
            h_crit_bulk: sim.state.h_crit_bulk,
            time_step: sim.state.h,
            time_step_factor: m.scheme.time_step_factor,
            end_time: m.end_time,
            expected_steps: (m.end_time / sim.state.h).ceil() as u64,
            interfaces,
            state_bytes_per_element: state_bytes(sim) as f64 / m.mesh.elements.len() as f64,
            warnings: sim.advisories(),
        }
    }
}
