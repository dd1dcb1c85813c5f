//! The interface law as the explorer edits it ([`LawSettings`]): the key of a family of the
//! table ([`families`]) and the values of its parameters, built and checked by
//! [`StiffnessLaw::build`], written into the edited scene as TOML. Nothing here names a family
//! but the one the window starts with: the editor ([`super::law_editor`]) draws the parameters
//! the family declares, so a family added to `physics/src/interface/laws/` appears here as it is.

use crate::law::{
    families, family, Delay, FamilySpec, Knots, Param, ParamValue, ParamValues, StiffnessLaw,
};
use serde::{Deserialize, Serialize};

/// The family the window starts with: the paper's (fig. 5).
pub const DEFAULT_FAMILY: &str = "plateau_linear";

/// The interface law as edited (applied to every interface of the scene).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(from = "Stored")]
pub struct LawSettings {
    /// Key of the family in the table (`plateau_linear`), as in a scene's `[interface.law]`.
    #[serde(rename = "family_key")]
    pub family: String,
    /// Edited parameter values by key, kept when the family changes: families that share a
    /// parameter (g_N(0), α_e, u_r) share its value. A parameter with no value here, or one of
    /// another kind, takes the family's default.
    pub values: ParamValues,
    /// μ_inf, friction of the fully ruptured interface.
    pub mu_inf: f64,
    /// `[interface.delay]`, and the opening rate of the editor's T(δ) at a rate.
    pub delay: DelaySettings,
}

impl Default for LawSettings {
    fn default() -> Self {
        LawSettings {
            family: default_family().key.to_string(),
            values: ParamValues::default(),
            mu_inf: 0.5,
            delay: DelaySettings::default(),
        }
    }
}

/// Delayed damage as edited: on or off, τ_c [s] and a [–] (checked by [`Delay::new`]), and the
/// opening rate [m/s] at which the editor draws T(δ).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct DelaySettings {
    pub on: bool,
    pub tau_c: f64,
    pub a: f64,
    pub plot_rate: f64,
}

/// Off; when switched on, the `rate_effect` scene's τ_c = 10 ms and a = 2, drawn at 0.1 m/s.
impl Default for DelaySettings {
    fn default() -> Self {
        DelaySettings {
            on: false,
            tau_c: 1e-2,
            a: 2.0,
            plot_rate: 0.1,
        }
    }
}

/// [`DEFAULT_FAMILY`], or the first of the table if it is gone.
fn default_family() -> &'static FamilySpec {
    family(DEFAULT_FAMILY).unwrap_or(&families()[0])
}

impl LawSettings {
    /// The edited family's row of the table (`None` for a key that names no family).
    pub fn spec(&self) -> Option<&'static FamilySpec> {
        family(&self.family)
    }

    /// The value of `param`: the edited one if it is of the parameter's kind, else its default.
    pub fn value(&self, param: &Param) -> ParamValue {
        match self.values.get(param.key) {
            Some(v) if same_kind(v, param) => v.clone(),
            _ => param.default_value(),
        }
    }

    /// The edited value of `param`, set to its default first if there is none of its kind.
    pub fn value_mut(&mut self, param: &Param) -> &mut ParamValue {
        let value = self.value(param);
        let slot = (self.values.0)
            .entry(param.key.to_string())
            .or_insert_with(|| value.clone());
        if !same_kind(slot, param) {
            *slot = value;
        }
        slot
    }

    /// What the law is built from: every parameter of the family, edited or at its default.
    pub fn params(&self) -> ParamValues {
        let params = self.spec().map_or(&[][..], |spec| spec.params);
        ParamValues(
            params
                .iter()
                .map(|p| (p.key.to_string(), self.value(p)))
                .collect(),
        )
    }

    /// The law, or why it is inadmissible: the library's error (key = value: what is
    /// admissible).
    pub fn law(&self) -> Result<StiffnessLaw, String> {
        let law = StiffnessLaw::build(&self.family, &self.params()).map_err(|e| e.to_string())?;
        if !(self.mu_inf.is_finite() && self.mu_inf >= 0.0) {
            return Err(format!("μ_inf = {}: must be finite and ≥ 0", self.mu_inf));
        }
        let delay = match self.delay.on {
            true => {
                Some(Delay::new(self.delay.tau_c, self.delay.a).map_err(|e| format!("delay.{e}"))?)
            }
            false => None,
        };
        law.with_delay(delay).map_err(|e| e.to_string())
    }

    /// The `[interface.delay]` table of the edited scene, `None` when the delay is off.
    pub(super) fn delay_toml(&self) -> Option<toml::Table> {
        let d = self.delay;
        d.on.then(|| {
            toml::Table::from_iter([("tau_c".into(), d.tau_c.into()), ("a".into(), d.a.into())])
        })
    }

    /// g_N(0), α_e, u_r of the law (`None` if it is inadmissible), for the history.
    pub fn knots(&self) -> Option<Knots> {
        self.law().ok().map(|l| l.knots())
    }

    /// Takes a scene's law: its family and the values that build it again.
    pub fn take(&mut self, law: &StiffnessLaw, mu_inf: f64) {
        self.family = law.spec().key.to_string();
        self.values.0.extend(law.values().0);
        self.mu_inf = mu_inf;
        self.delay.on = law.delay().is_some();
        if let Some(d) = law.delay() {
            (self.delay.tau_c, self.delay.a) = (d.tau_c, d.a);
        }
    }

    /// The `[interface.law]` table of the edited scene: `family` and [`LawSettings::params`].
    pub(super) fn to_toml(&self) -> Result<toml::Table, String> {
        let mut t = toml::Table::new();
        t.insert("family".into(), self.family.clone().into());
        for (key, value) in self.params().0 {
            let value = toml::Value::try_from(&value).map_err(|e| format!("{key}: {e}"))?;
            t.insert(key, value);
        }
        Ok(t)
    }
}

fn same_kind(value: &ParamValue, param: &Param) -> bool {
    use crate::law::ParamKind;
    matches!(
        (value, param.kind),
        (ParamValue::Number(_), ParamKind::Number(_))
            | (ParamValue::Points(_), ParamKind::Points { .. })
    )
}

/// [`LawSettings`] as saved, by this version or an earlier one. Before the table of families
/// the settings held the family as an enum variant (`family: PlateauLinear`) and one field per
/// parameter (`g_n0`, `alpha_e`, `u_r`, `decay`, `points`, which are the parameters' keys):
/// they are read into the values. A family that no longer exists falls back to the default.
#[derive(Deserialize, Default)]
#[serde(default)]
struct Stored {
    family_key: Given<String>,
    values: ParamValues,
    mu_inf: Given<f64>,
    family: Given<LegacyFamily>,
    g_n0: Given<f64>,
    alpha_e: Given<f64>,
    u_r: Given<f64>,
    decay: Given<f64>,
    points: Given<Vec<[f64; 2]>>,
    delay: DelaySettings,
}

impl From<Stored> for LawSettings {
    fn from(s: Stored) -> Self {
        let mut law = LawSettings::default();
        let key = s.family_key.0.or(s.family.0.map(|f| f.0));
        if let Some(spec) = key.as_deref().and_then(family) {
            law.family = spec.key.to_string();
        }
        let legacy = [
            ("g_n0", s.g_n0),
            ("alpha_e", s.alpha_e),
            ("u_r", s.u_r),
            ("decay", s.decay),
        ];
        for (key, x) in legacy {
            if let Given(Some(x)) = x {
                law.values.0.insert(key.into(), ParamValue::Number(x));
            }
        }
        if let Given(Some(points)) = s.points {
            law.values
                .0
                .insert("points".into(), ParamValue::Points(points));
        }
        law.values.0.extend(s.values.0);
        law.mu_inf = s.mu_inf.0.unwrap_or(law.mu_inf);
        law.delay = s.delay;
        law
    }
}

/// A field the saved settings may lack, written as its bare value when present (RON would
/// want `Some(…)` for an `Option`).
struct Given<T>(Option<T>);

impl<T> Default for Given<T> {
    fn default() -> Self {
        Given(None)
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Given<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        T::deserialize(d).map(|v| Given(Some(v)))
    }
}

/// The family of earlier settings, an enum variant (`PlateauLinear`), as its key
/// (`plateau_linear`).
struct LegacyFamily(String);

impl<'de> Deserialize<'de> for LegacyFamily {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Name;
        impl serde::de::Visitor<'_> for Name {
            type Value = LegacyFamily;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a law family's variant name")
            }
            fn visit_str<E>(self, name: &str) -> Result<LegacyFamily, E> {
                let mut key = String::new();
                for (i, c) in name.chars().enumerate() {
                    if c.is_ascii_uppercase() && i > 0 {
                        key.push('_');
                    }
                    key.push(c.to_ascii_lowercase());
                }
                Ok(LegacyFamily(key))
            }
        }
        // A variant is an identifier in RON (eframe's storage) and a string in JSON.
        d.deserialize_identifier(Name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The explorer's settings on the pull-off scene.
    fn pull_off_settings() -> crate::gui::Settings {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        crate::gui::Settings {
            scene: root.join("../scenes/pull_off.toml").display().to_string(),
            ..Default::default()
        }
    }

    /// Every family of the table, at the editor's starting values, gives an admissible law that
    /// reaches the scene loader unchanged through the edited scene (the pull-off scene with
    /// that law), and comes back into the editor as the same settings.
    #[test]
    fn every_family_goes_through_the_edited_scene_and_back() {
        let mut settings = pull_off_settings();
        for spec in families() {
            settings.law = LawSettings {
                family: spec.key.into(),
                ..LawSettings::default()
            };
            let built = (settings.law.law()).unwrap_or_else(|e| panic!("{}: {e}", spec.key));
            assert_eq!(built, spec.build(&spec.defaults()).unwrap());
            let scene = settings.scene().unwrap();
            let loaded = &scene.model.interfaces[0].law;
            assert_eq!(loaded, &built, "{}", spec.key);
            let mut back = LawSettings::default();
            back.take(loaded, 0.5);
            assert_eq!(back.law().unwrap(), built);
            assert_eq!(back.params(), settings.law.params());
        }
    }

    /// A delay switched on reaches the scene as `[interface.delay]` and comes back; a bad τ_c
    /// is refused naming `delay.tau_c`; `rccm` refuses any delay with the reason.
    #[test]
    fn the_delay_goes_through_the_edited_scene_and_back() {
        let mut settings = pull_off_settings();
        settings.law.delay.on = true;
        let scene = settings.scene().unwrap();
        let loaded = &scene.model.interfaces[0].law;
        let d = loaded.delay().expect("delayed");
        assert_eq!((d.tau_c, d.a), (1e-2, 2.0));
        let mut back = LawSettings::default();
        back.take(loaded, 0.5);
        assert_eq!(back.delay, settings.law.delay);
        settings.law.delay.tau_c = 0.0;
        let e = settings.law.law().unwrap_err();
        assert!(
            e.starts_with("delay.tau_c = 0: τ_c must be finite and > 0 (s)"),
            "{e}"
        );
        settings.law.delay.tau_c = 1e-3;
        settings.law.family = "rccm".into();
        assert!(settings.law.law().unwrap_err().contains("viscosity b"));
        settings.law.delay.on = false;
        assert!(settings.scene().unwrap().model.interfaces[0]
            .law
            .delay()
            .is_none());
    }

    /// Values shared by two families survive a change of family; a value of the wrong kind
    /// falls back to the default; an unknown family is refused with the admissible keys.
    #[test]
    fn values_follow_the_family() {
        let mut law = LawSettings::default();
        let spec = law.spec().unwrap();
        let first = &spec.params[0];
        let shared = families()
            .iter()
            .find(|f| f.key != spec.key && f.param(first.key).is_some());
        *law.value_mut(first) = ParamValue::Number(1.25);
        if let Some(other) = shared {
            law.family = other.key.into();
            assert_eq!(law.params().get(first.key), Some(&ParamValue::Number(1.25)));
        }
        law.values
            .0
            .insert(first.key.into(), ParamValue::Points(vec![]));
        assert_eq!(law.value(first), first.default_value());
        law.family = "trilinear".into();
        let e = law.law().unwrap_err();
        assert!(e.starts_with("family = \"trilinear\""), "{e}");
        assert!(e.contains(&format!("`{}`", spec.key)), "{e}");
    }

    /// Settings saved before the table of families (the family as an enum variant, one field
    /// per parameter) load with their family and values, in JSON and in eframe's RON; settings
    /// of this version round-trip.
    #[test]
    fn earlier_settings_still_load() {
        let ron = "(family:Exponential,g_n0:1e9,alpha_e:0.001,u_r:0.003,decay:3.0,\
                   points:[(0.0,1e9),(0.003,0.0)],mu_inf:0.25)";
        let json = r#"{"family": "Exponential", "g_n0": 1e9, "alpha_e": 0.001, "u_r": 0.003,
                       "decay": 3.0, "points": [[0.0, 1e9], [0.003, 0.0]], "mu_inf": 0.25}"#;
        let from_ron = ron_storage(ron);
        let from_json: LawSettings = serde_json::from_str(json).unwrap();
        assert_eq!(from_ron, from_json);
        assert_eq!(from_json.family, "exponential");
        assert_eq!(from_json.mu_inf, 0.25);
        let law = from_json.law().unwrap();
        assert_eq!((law.g_n0, law.alpha_e, law.u_r), (1e9, 1e-3, 3e-3));
        assert_eq!(law.values().number("decay").unwrap(), 3.0);
        // A family that is gone: the default family, the values kept.
        let gone: LawSettings = serde_json::from_str(r#"{"family": "Trilinear"}"#).unwrap();
        assert_eq!(gone.family, DEFAULT_FAMILY);
        let saved = serde_json::to_string(&from_json).unwrap();
        assert_eq!(
            serde_json::from_str::<LawSettings>(&saved).unwrap(),
            from_json
        );
    }

    /// eframe's storage of one value, in RON.
    struct Saved(String);

    impl eframe::Storage for Saved {
        fn get_string(&self, _key: &str) -> Option<String> {
            Some(self.0.clone())
        }
        fn set_string(&mut self, _key: &str, value: String) {
            self.0 = value;
        }
        fn remove_string(&mut self, _key: &str) {}
        fn flush(&mut self) {}
    }

    /// `law` read back through eframe's storage, as a launch reads the saved settings.
    fn ron_storage(law: &str) -> LawSettings {
        eframe::get_value(&Saved(law.into()), "law").expect("the saved law loads")
    }

    /// Points and numbers of this version's settings go through RON and back.
    #[test]
    fn settings_round_trip_through_eframe_storage() {
        let mut law = LawSettings {
            family: "table".into(),
            ..LawSettings::default()
        };
        law.values
            .0
            .insert("points".into(), vec![[0.0, 2e8], [1e-3, 0.0]].into());
        law.values.0.insert("g_n0".into(), 3e8.into());
        let mut storage = Saved(String::new());
        eframe::set_value(&mut storage, "law", &law);
        assert_eq!(ron_storage(&storage.0), law);
    }
}
