//! The table against the loader: the keys against the serde structs' fields, the choices
//! against the enums, the defaults against what a scene that leaves the keys out gets.

use super::super::raw::{
    Axis, RawBond, RawBulkViscosity, RawContact, RawDelay, RawDisplacement, RawFaceSet,
    RawInterface, RawLaw, RawMassScaling, RawMaterial, RawMesh, RawMould, RawPlane, RawScene,
    RawScheme, RawSplit, RawTraction,
};
use super::*;
use crate::law::Delay;
use crate::material::MaterialModel;
use crate::model::{Integration, SchemeParams};
use crate::scene::parse_scene;
use serde::de::{self, DeserializeOwned, Visitor};
use std::fmt;

/// The error that ends an introspection.
#[derive(Debug)]
struct Stop;

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("introspection")
    }
}

impl std::error::Error for Stop {}

impl de::Error for Stop {
    fn custom<T: fmt::Display>(_: T) -> Self {
        Stop
    }
}

/// A deserializer that only records the names a derived `Deserialize` asks for: a struct's
/// fields (with their aliases) or an enum's variants (as renamed).
struct Names<'a>(&'a mut Option<&'static [&'static str]>);

impl<'de> de::Deserializer<'de> for Names<'_> {
    type Error = Stop;

    fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Stop> {
        Err(Stop)
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        fields: &'static [&'static str],
        _: V,
    ) -> Result<V::Value, Stop> {
        *self.0 = Some(fields);
        Err(Stop)
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _: &'static str,
        variants: &'static [&'static str],
        _: V,
    ) -> Result<V::Value, Stop> {
        *self.0 = Some(variants);
        Err(Stop)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map identifier
        ignored_any
    }
}

/// The field names (aliases included) or variant names that `T` deserializes; `None` for
/// a type that asks for neither (a struct with a flattened field asks for a map).
fn names<T: DeserializeOwned>() -> Option<Vec<&'static str>> {
    let mut seen = None;
    let _ = T::deserialize(Names(&mut seen));
    seen.map(|names| {
        let mut names = names.to_vec();
        names.sort_unstable();
        names
    })
}

/// The keys of a section, aliases included, sorted.
fn documented(path: &str) -> Vec<&'static str> {
    let section = section(path).unwrap_or_else(|| panic!("no section `{path}`"));
    let mut keys: Vec<&str> = (section.keys.iter())
        .flat_map(|k| std::iter::once(k.key).chain(k.alias))
        .collect();
    keys.sort_unstable();
    keys
}

/// Every key the loader accepts has its row, and every row is a key the loader accepts: a
/// field added to a struct of `raw.rs` without its row here fails.
#[test]
fn every_section_documents_exactly_the_keys_the_loader_accepts() {
    let structs: Vec<(&str, Option<Vec<&str>>)> = vec![
        ("", names::<RawScene>()),
        ("mesh", names::<RawMesh>()),
        ("mesh.face_set", names::<RawFaceSet>()),
        ("mesh.split", names::<RawSplit>()),
        ("material", names::<RawMaterial>()),
        ("scheme", names::<RawScheme>()),
        ("mass_scaling", names::<RawMassScaling>()),
        ("bulk_viscosity", names::<RawBulkViscosity>()),
        ("plane", names::<RawPlane>()),
        ("mould", names::<RawMould>()),
        ("interface", names::<RawInterface>()),
        ("interface.delay", names::<RawDelay>()),
        ("contact", names::<RawContact>()),
        ("bond", names::<RawBond>()),
        ("displacement", names::<RawDisplacement>()),
        ("traction", names::<RawTraction>()),
    ];
    for (path, fields) in &structs {
        let fields = fields
            .as_ref()
            .unwrap_or_else(|| panic!("the struct of `{path}` lists no fields"));
        assert_eq!(
            &documented(path),
            fields,
            "section `{path}`: the table of keys (physics/src/scene/keys.rs) and the serde \
             struct (raw.rs) differ"
        );
    }
    // `[interface.law]` flattens the family's parameters (documented by the families):
    // serde asks for a map; its one fixed key is `family`.
    assert_eq!(names::<RawLaw>(), None);
    assert_eq!(documented("interface.law"), ["family"]);
    let law: RawLaw = super::super::raw::from_toml("family = \"rccm\"", "t.toml").unwrap();
    assert_eq!((law.family.as_str(), law.params.len()), ("rccm", 0));
    // No section without its struct.
    for s in SECTIONS {
        assert!(
            s.path == "interface.law" || structs.iter().any(|(p, _)| *p == s.path),
            "section `{}` has no serde struct in this test",
            s.path
        );
    }
    // A key of kind table names a section of that path.
    for s in SECTIONS {
        for k in s.keys.iter().filter(|k| k.kind.contains("table")) {
            let path = if s.path.is_empty() {
                k.key.to_string()
            } else {
                format!("{}.{}", s.path, k.key)
            };
            let shared = matches!(path.as_str(), "contact.law" | "contact.delay" | "bond.law");
            assert!(
                shared || section(&path).is_some(),
                "`{path}` is a table without a section"
            );
        }
    }
}

/// `[material]` reads a family's parameter by its key alone (`raw.rs`), as a number or a list
/// by the first family that declares it: a key two families share must be of one kind and unit,
/// and no family's key may be one of the keys every model shares.
#[test]
fn a_rubber_key_means_one_kind_in_every_family() {
    use crate::material::rubber::{rubber_param, RUBBERS};
    for spec in RUBBERS {
        for p in spec.params {
            let first = rubber_param(p.key).unwrap();
            assert_eq!(
                (first.list, first.unit),
                (p.list, p.unit),
                "`{}` of `{}`: another family reads it as another kind or unit",
                p.key,
                spec.key
            );
            assert!(
                documented("material").iter().all(|&k| k != p.key),
                "`{}` of `{}` is a key every model shares",
                p.key,
                spec.key
            );
        }
    }
}

#[test]
fn choices_are_the_variants_of_the_enums() {
    let key = |path: &str, key: &str| section(path).unwrap().key(key).unwrap().choices;
    let sorted = |c: &[&'static str]| {
        let mut c = c.to_vec();
        c.sort_unstable();
        Some(c)
    };
    assert_eq!(sorted(key("material", "model")), names::<MaterialModel>());
    assert_eq!(
        sorted(key("material", "volumetric")),
        names::<crate::material::rubber::Volumetric>()
    );
    assert_eq!(sorted(key("scheme", "integration")), names::<Integration>());
    assert_eq!(sorted(key("displacement", "component")), names::<Axis>());
    assert_eq!(sorted(key("mesh.split", "axis")), names::<Axis>());
    let shapes: Vec<&str> = (crate::mould::shapes::SHAPES.iter())
        .map(|s| s.key)
        .collect();
    assert_eq!(key("mould", "shape"), shapes);
}

/// The keys of `[[mould]]` the section documents are those every shape takes; no shape
/// declares one of them again (each shape's own keys are documented by its file).
#[test]
fn mould_shapes_take_documented_keys() {
    let common = documented("mould");
    for shape in crate::mould::shapes::SHAPES {
        for k in shape.keys {
            assert!(
                !common.contains(&k.key),
                "{}.{} is a common key",
                shape.key,
                k.key
            );
        }
    }
}

/// What a scene that leaves the optional keys out gets is what the table says.
#[test]
fn defaults_are_what_the_loader_takes() {
    let text = r#"
            end_time = 1.0
            [mesh]
            size = [1.0, 1.0, 1.0]
            cells = [1, 1, 1]
            [material]
            young = 1e6
            poisson = 0.3
            density = 1000.0
            [[plane]]
            name = "p"
            point = [0.0, 0.0, 0.0]
            normal = [0.0, 0.0, 1.0]
            [[interface]]
            faces = "z-"
            plane = "p"
            [interface.law]
            family = "plateau_linear"
            g_n0 = 1e9
            alpha_e = 1e-4
            u_r = 1e-3
            [[contact]]
            faces = "x-"
            plane = "p"
        "#;
    let model = parse_scene(text, "t.toml", &[]).unwrap().model;
    let number = |path: &str, key: &str| match section(path).unwrap().key(key).unwrap().default {
        DefaultDoc::Number(x) => x,
        other => panic!("`{path}.{key}` has no number default: {other:?}"),
    };
    let d = SchemeParams::default();
    assert_eq!(model.scheme, d);
    let scheme = [
        ("time_step_factor", d.time_step_factor),
        ("h_crit_update_interval", d.h_crit_update_interval as f64),
        ("h_crit_tolerance", d.h_crit_tolerance),
        ("energy_growth_limit", d.energy_growth_limit),
        ("hourglass_coefficient", d.hourglass_coefficient),
    ];
    for (key, value) in scheme {
        assert_eq!(number("scheme", key), value, "scheme.{key}");
    }
    assert_eq!(
        section("scheme")
            .unwrap()
            .key("integration")
            .unwrap()
            .default,
        DefaultDoc::Text("\"full\"")
    );
    assert_eq!(d.integration, Integration::Full);
    assert_eq!(
        section("material").unwrap().key("model").unwrap().default,
        DefaultDoc::Text("\"svk\"")
    );
    assert_eq!(model.material.model, MaterialModel::Svk);
    let itf = &model.interfaces[0];
    assert_eq!(number("interface", "mu_inf"), itf.mu_inf);
    assert_eq!(number("interface", "initial_damage"), itf.initial_damage);
    assert_eq!(number("contact", "mu"), model.contacts[0].mu);
    assert_eq!((model.name.as_str(), model.gravity), ("t", [0.0; 3]));
    assert_eq!(model.initial_velocity, [0.0; 3]);
    assert_eq!(model.initial_angular_velocity, [0.0; 3]);
}

/// `Delay::new` checks `[interface.delay]`; its ranges are the table's.
#[test]
fn delay_ranges_are_the_tables() {
    for x in [-1.0, 0.0, 1e-12, 1.0, f64::INFINITY, f64::NAN] {
        assert_eq!(Delay::new(x, 1.0).is_ok(), TAU_C.admits(x), "tau_c = {x}");
        assert_eq!(Delay::new(1.0, x).is_ok(), DELAY_A.admits(x), "a = {x}");
    }
}

/// Every row says what it is; a number default is admissible; keys are unique.
#[test]
fn every_row_is_complete_and_consistent() {
    for s in SECTIONS {
        assert!(!s.about.is_empty() && !s.presence.is_empty(), "{}", s.path);
        for (i, k) in s.keys.iter().enumerate() {
            let at = format!("{}.{}", s.path, k.key);
            assert!(!k.kind.is_empty() && !k.description.is_empty(), "{at}");
            assert!(
                s.keys[..i]
                    .iter()
                    .all(|o| o.key != k.key && Some(o.key) != k.alias),
                "{at} twice"
            );
            if k.range.is_some() || k.kind == "number" {
                assert!(
                    !k.unit.is_empty(),
                    "{at}: a number needs a unit (– if none)"
                );
            }
            if let Some(r) = k.range {
                assert!(r.min <= r.max, "{at}: empty range");
            }
            match k.default {
                DefaultDoc::Number(x) => assert!(k.admits(x), "{at}: default {x} refused"),
                DefaultDoc::Text(t) => assert!(!t.is_empty(), "{at}"),
                DefaultDoc::Required => {}
            }
            if !k.choices.is_empty() {
                assert_eq!(k.kind, "string", "{at}");
            }
        }
    }
    assert_eq!(
        MESH_CELLS.admissible,
        "integers; their product at most 50 000 000 elements"
    );
    assert_eq!(super::super::mesh::MAX_ELEMENTS, 50_000_000);
}

#[test]
fn messages_say_the_range_and_the_unit() {
    assert_eq!(END_TIME.must(), "must be > 0 s");
    assert_eq!(
        POISSON.must(),
        "must satisfy -1 < ν < 0.5 (0.5 is incompressible; above 0.49 use scheme.integration = \"fbar\" or \"reduced_physical\")"
    );
    assert_eq!(H_CRIT_TOLERANCE.must(), "must be in (0, 0.01]");
    assert_eq!(INTERFACE_MU_INF.must(), "must be ≥ 0");
}
