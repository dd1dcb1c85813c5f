//! The raw serde structs: the file as written. Optional keys are `Option` or
//! `#[serde(default)]`; unknown keys and wrong types are refused while deserializing, with the key
//! path and toml's line and column. The module is private to the scene loader: its items are
//! `pub` for the sibling modules only.

use super::error::SceneError;
use crate::material::rubber::{RubberParam, Volumetric};
use crate::material::MaterialModel;
use crate::model::Integration;
use serde::de::DeserializeOwned;
use serde::Deserialize;

/// Deserializes TOML text, keeping the key path and toml's line/column in errors.
pub fn from_toml<T: DeserializeOwned>(text: &str, file: &str) -> Result<T, SceneError> {
    serde_path_to_error::deserialize(toml::Deserializer::new(text)).map_err(|e| {
        let key = e.path().to_string();
        SceneError::Toml {
            file: file.to_string(),
            key: (key != ".").then_some(key),
            message: e.into_inner().to_string().trim_end().to_string(),
        }
    })
}

/// Arrays of a fixed length for `deserialize_with`: toml's deserializer fills a `[T; N]` from the
/// first N elements and drops the rest without a word, so an array is read whole and its length
/// checked.
mod exact {
    use serde::de::{Deserialize, Deserializer, Error};

    fn fixed<T, E: Error, const N: usize>(v: Vec<T>, what: &str) -> Result<[T; N], E> {
        let n = v.len();
        v.try_into()
            .map_err(|_| E::invalid_length(n, &format!("{what} of length {N}").as_str()))
    }

    /// `[T; N]`.
    pub fn array<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
        d: D,
    ) -> Result<[T; N], D::Error> {
        fixed(Vec::deserialize(d)?, "an array")
    }

    /// `Option<[T; N]>` (with `#[serde(default)]`: absent is None).
    pub fn option<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
        d: D,
    ) -> Result<Option<[T; N]>, D::Error> {
        array(d).map(Some)
    }

    /// `Option<Vec<[T; N]>>`: rows of N numbers; the message names the row.
    pub fn option_rows<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
        d: D,
    ) -> Result<Option<Vec<[T; N]>>, D::Error> {
        let rows: Vec<Vec<T>> = Vec::deserialize(d)?;
        (rows.into_iter().enumerate())
            .map(|(k, r)| fixed(r, &format!("row [{k}]: a row")))
            .collect::<Result<_, _>>()
            .map(Some)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawScene {
    pub name: Option<String>,
    #[serde(default)]
    pub description: String,
    pub end_time: f64,
    #[serde(default, deserialize_with = "exact::array")]
    pub gravity: [f64; 3],
    #[serde(default, deserialize_with = "exact::array")]
    pub initial_velocity: [f64; 3],
    #[serde(default, deserialize_with = "exact::array")]
    pub initial_angular_velocity: [f64; 3],
    pub mesh: RawMesh,
    pub material: RawMaterial,
    #[serde(default)]
    pub scheme: RawScheme,
    pub mass_scaling: Option<RawMassScaling>,
    pub bulk_viscosity: Option<RawBulkViscosity>,
    #[serde(default)]
    pub plane: Vec<RawPlane>,
    /// `[[mould]]`: each entry as written; its common keys are a [`RawMould`], the others its
    /// shape's.
    #[serde(default)]
    pub mould: Vec<toml::Table>,
    #[serde(default)]
    pub interface: Vec<RawInterface>,
    #[serde(default)]
    pub contact: Vec<RawContact>,
    #[serde(default)]
    pub bond: Vec<RawBond>,
    #[serde(default)]
    pub displacement: Vec<RawDisplacement>,
    #[serde(default)]
    pub traction: Vec<RawTraction>,
}

/// Either a box (`size`, `cells`, optional `origin`) or a Gmsh file (`file`, optional `scale`);
/// `Check::mesh` (`mesh.rs`) enforces that exactly one form is given.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawMesh {
    #[serde(default, deserialize_with = "exact::option")]
    pub origin: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "exact::option")]
    pub size: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "exact::option")]
    pub cells: Option<[usize; 3]>,
    pub file: Option<String>,
    pub scale: Option<f64>,
    /// `[[mesh.face_set]]`: named parts of face sets, selected by a box.
    #[serde(default)]
    pub face_set: Vec<RawFaceSet>,
    /// `[mesh.split]`: the mesh cut in two along a plane of its faces.
    pub split: Option<RawSplit>,
}

/// `[mesh.split]`: the plane X_axis = `at` along which the mesh is cut
/// ([`crate::mesh::Mesh::split`]).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSplit {
    pub axis: Axis,
    pub at: f64,
}

/// `[[mesh.face_set]]`: the faces of the face set `of` whose centre lies in the box
/// [`min`, `max`] (bounds included), as a new face set `name`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawFaceSet {
    pub name: String,
    pub of: String,
    #[serde(deserialize_with = "exact::array")]
    pub min: [f64; 3],
    #[serde(deserialize_with = "exact::array")]
    pub max: [f64; 3],
}

/// `[material]`: the model, E and ν (SVK and the compressible neo-Hookean), ρ₀, a rubber's bulk
/// modulus and volumetric form, and the rubber families' parameters, whose keys (and whether each
/// is a number or a list) are the families' rows ([`crate::material::rubber::RUBBERS`]): a family
/// with keys of its own adds nothing here. Deserialized by hand ([`material`]) for that reason,
/// with serde's errors (an unknown key lists the admissible ones, with the line).
pub struct RawMaterial {
    pub model: Option<MaterialModel>,
    pub young: Option<f64>,
    pub poisson: Option<f64>,
    pub density: f64,
    pub bulk: Option<f64>,
    pub volumetric: Option<Volumetric>,
    /// The rubber families' parameters the scene gave, in the file's order.
    pub params: Vec<(&'static RubberParam, ParamValue)>,
}

/// A rubber family's parameter as given: a number, or a list ([`RubberParam::list`]).
pub enum ParamValue {
    Number(f64),
    List(Vec<f64>),
}

mod material {
    use super::{ParamValue, RawMaterial};
    use crate::material::rubber::{rubber_param, rubber_param_keys, RubberParam};
    use serde::de::{Deserializer, Error, MapAccess, Visitor};
    use serde::Deserialize;
    use std::fmt;

    /// The keys every model shares.
    const FIELDS: &[&str] = &["model", "young", "poisson", "density", "bulk", "volumetric"];

    /// [`FIELDS`], then every family's parameter keys: what an unknown key is told.
    fn every_key() -> &'static [&'static str] {
        static KEYS: std::sync::OnceLock<Vec<&'static str>> = std::sync::OnceLock::new();
        KEYS.get_or_init(|| FIELDS.iter().copied().chain(rubber_param_keys()).collect())
    }

    /// A key of `[material]`: one of [`FIELDS`] (its index) or a family's parameter.
    enum Field {
        Shared(usize),
        Param(&'static RubberParam),
    }

    impl<'de> Deserialize<'de> for Field {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Field, D::Error> {
            struct Key;
            impl Visitor<'_> for Key {
                type Value = Field;
                fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                    f.write_str("a key of [material]")
                }
                fn visit_str<E: Error>(self, v: &str) -> Result<Field, E> {
                    if let Some(i) = FIELDS.iter().position(|&k| k == v) {
                        return Ok(Field::Shared(i));
                    }
                    rubber_param(v)
                        .map(Field::Param)
                        .ok_or_else(|| E::unknown_field(v, every_key()))
                }
            }
            d.deserialize_identifier(Key)
        }
    }

    impl<'de> Deserialize<'de> for RawMaterial {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<RawMaterial, D::Error> {
            struct Table;
            impl<'de> Visitor<'de> for Table {
                type Value = RawMaterial;
                fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                    f.write_str("the table [material]")
                }
                fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<RawMaterial, A::Error> {
                    let mut m = RawMaterial {
                        model: None,
                        young: None,
                        poisson: None,
                        density: f64::NAN,
                        bulk: None,
                        volumetric: None,
                        params: vec![],
                    };
                    let mut density = None;
                    while let Some(field) = map.next_key::<Field>()? {
                        match field {
                            Field::Shared(0) => m.model = Some(map.next_value()?),
                            Field::Shared(1) => m.young = Some(map.next_value()?),
                            Field::Shared(2) => m.poisson = Some(map.next_value()?),
                            Field::Shared(3) => density = Some(map.next_value()?),
                            Field::Shared(4) => m.bulk = Some(map.next_value()?),
                            Field::Shared(_) => m.volumetric = Some(map.next_value()?),
                            Field::Param(p) => {
                                let value = if p.list {
                                    ParamValue::List(map.next_value()?)
                                } else {
                                    ParamValue::Number(map.next_value()?)
                                };
                                m.params.push((p, value));
                            }
                        }
                    }
                    m.density = density.ok_or_else(|| A::Error::missing_field("density"))?;
                    Ok(m)
                }
            }
            d.deserialize_struct("RawMaterial", FIELDS, Table)
        }
    }
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct RawScheme {
    pub time_step_factor: Option<f64>,
    pub h_crit_update_interval: Option<usize>,
    pub h_crit_tolerance: Option<f64>,
    pub energy_growth_limit: Option<f64>,
    pub integration: Option<Integration>,
    pub hourglass_coefficient: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawMassScaling {
    pub target_step: f64,
    pub kinetic_share: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawBulkViscosity {
    pub linear: Option<f64>,
    pub quadratic: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawPlane {
    pub name: String,
    #[serde(deserialize_with = "exact::array")]
    pub point: [f64; 3],
    #[serde(deserialize_with = "exact::array")]
    pub normal: [f64; 3],
    #[serde(default, deserialize_with = "exact::option_rows")]
    pub velocity: Option<Vec<[f64; 4]>>,
}

/// `[[mould]]`: the keys every shape takes. The entry is read as a table (`RawScene::mould`):
/// these keys are taken out of it and read here, the others are the shape's
/// ([`crate::mould::shapes`]), which `scene/mesh.rs` hands to the shape's parse.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawMould {
    pub name: String,
    pub shape: String,
    #[serde(default, deserialize_with = "exact::option")]
    pub pivot: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "exact::option_rows")]
    pub velocity: Option<Vec<[f64; 4]>>,
    #[serde(default, deserialize_with = "exact::option_rows")]
    pub angular_velocity: Option<Vec<[f64; 4]>>,
}

impl RawMould {
    /// The keys of [`RawMould`].
    pub const KEYS: &'static [&'static str] =
        &["name", "shape", "pivot", "velocity", "angular_velocity"];
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawInterface {
    pub faces: String,
    /// The plane or mould, by name (`mould` is the same key).
    #[serde(alias = "mould")]
    pub plane: String,
    #[serde(default)]
    pub mu_inf: f64,
    #[serde(default)]
    pub initial_damage: f64,
    pub law: RawLaw,
    pub delay: Option<RawDelay>,
}

/// `[[bond]]`: the nodes of face set `faces` joined to the nodes of `to` at the same place by
/// a cohesive law (model §7.8).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawBond {
    pub faces: String,
    pub to: String,
    #[serde(default)]
    pub mu_inf: f64,
    #[serde(default)]
    pub initial_damage: f64,
    pub law: RawLaw,
}

/// `[interface.delay]`: delayed damage on the interface's law (absent: rate-independent).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawDelay {
    pub tau_c: f64,
    pub a: f64,
}

/// `[interface.law]`: the family's key and its parameters, which the family's row of the table
/// ([`crate::law::families`]) checks.
#[derive(Deserialize)]
pub struct RawLaw {
    pub family: String,
    #[serde(flatten)]
    pub params: toml::Table,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawContact {
    pub faces: String,
    /// The plane or mould, by name (`mould` is the same key).
    #[serde(alias = "mould")]
    pub plane: String,
    #[serde(default)]
    pub mu: f64,
    /// `[contact.law]`: glue that forms on contact (`adhesion.rs`), with its `mu_inf` and
    /// optional `[contact.delay]`; absent: contact only.
    pub law: Option<RawLaw>,
    pub mu_inf: Option<f64>,
    pub delay: Option<RawDelay>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawDisplacement {
    pub faces: String,
    pub component: Axis,
    /// U(t) as rows [t (s), U (m)]; or, instead, `speed`.
    #[serde(default, deserialize_with = "exact::option_rows")]
    pub table: Option<Vec<[f64; 2]>>,
    /// A constant pull speed (m/s) instead of a table: U = v t after the ramp.
    pub speed: Option<f64>,
    /// With `speed`: the time (s) over which the speed is reached (default 0: at once).
    pub ramp: Option<f64>,
    /// With `speed`: the number of equal speed increments of the ramp (default 4).
    pub ramp_steps: Option<u32>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    X,
    Y,
    Z,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawTraction {
    pub faces: String,
    #[serde(deserialize_with = "exact::array")]
    pub vector: [f64; 3],
    #[serde(default, deserialize_with = "exact::option_rows")]
    pub amplitude: Option<Vec<[f64; 2]>>,
}
