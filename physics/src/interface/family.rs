//! What one interface-law family declares, and the table of families (model §2.6).
//!
//! A family is one file of `interface/laws/` holding a type that implements [`Family`]: its key
//! in scene files, its label, its parameters ([`Param`]: symbol, unit, admissible range,
//! default), g_N(α) on the softening branch, G_c in closed form and its own admissibility
//! checks. `physics/build.rs` lists the files, so [`families`] — the table that the scene loader,
//! the explorer and the recorder read — needs no editing when a family is added.

use super::damage::Loading;
use super::law::{LawError, StiffnessLaw};
use super::laws::{LawKind, FAMILIES};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;

/// An interval of admissible values; an infinite end is open.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    pub min: f64,
    /// `min` itself is excluded.
    pub min_open: bool,
    pub max: f64,
    /// `max` itself is excluded.
    pub max_open: bool,
}

impl Range {
    /// (min, ∞).
    pub const fn above(min: f64) -> Self {
        Range {
            min,
            min_open: true,
            max: f64::INFINITY,
            max_open: true,
        }
    }

    /// [min, ∞).
    pub const fn at_least(min: f64) -> Self {
        Range {
            min_open: false,
            ..Range::above(min)
        }
    }

    /// From `min` to `max`, each end excluded when its flag says so: `between(0.0, true, 1.0,
    /// false)` is (0, 1].
    pub const fn between(min: f64, min_open: bool, max: f64, max_open: bool) -> Self {
        Range {
            min,
            min_open,
            max,
            max_open,
        }
    }

    /// `x` is finite and inside.
    pub fn contains(&self, x: f64) -> bool {
        let above = if self.min_open {
            x > self.min
        } else {
            x >= self.min
        };
        let below = if self.max_open {
            x < self.max
        } else {
            x <= self.max
        };
        x.is_finite() && above && below
    }
}

/// As the messages write it: `> 0`, `≥ 0`, `< 1`, `in (0, 1]`.
impl fmt::Display for Range {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        let (lo, hi) = (self.min, self.max);
        match (lo.is_finite(), hi.is_finite()) {
            (true, false) => write!(f, "{} {lo}", if self.min_open { ">" } else { "≥" }),
            (false, true) => write!(f, "{} {hi}", if self.max_open { "<" } else { "≤" }),
            _ => {
                let open = if self.min_open { "(" } else { "[" };
                let close = if self.max_open { ")" } else { "]" };
                write!(f, "in {open}{lo}, {hi}{close}")
            }
        }
    }
}

/// A number parameter: what is admissible, and what the explorer's editor starts from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NumberParam {
    /// Admissible values, checked when the law is built.
    pub range: Range,
    /// The editor's initial value, and the value of an optional parameter a scene leaves out.
    pub default: f64,
    /// The span the editor's slider offers (a user may type any admissible value).
    pub typical: [f64; 2],
    /// Whether the slider is logarithmic.
    pub logarithmic: bool,
}

/// What kind of value a parameter takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParamKind {
    Number(NumberParam),
    /// Rows (α [m], g_N [Pa/m]), checked by the family; `default` is the editor's initial table.
    Points {
        default: &'static [[f64; 2]],
    },
}

/// One parameter of a law family, as scene files and the explorer see it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Param {
    /// Key in a scene's `[interface.law]` table (`g_n0`).
    pub key: &'static str,
    /// Symbol in messages and labels (`g_N(0)`).
    pub symbol: &'static str,
    /// SI unit (`Pa/m`, `m`, `–`).
    pub unit: &'static str,
    /// What it is, in a few words.
    pub meaning: &'static str,
    /// Why the family narrows the range, appended to its message (empty if it does not); for
    /// rows, what the family requires of them (the scene reference shows it).
    pub note: &'static str,
    /// A scene may leave it out; the default then applies.
    pub optional: bool,
    pub kind: ParamKind,
}

impl Param {
    /// A number parameter that scenes must give, admissible in `range`; the editor starts from
    /// `default` on a linear slider over [default/10, 10·default] unless [`Param::editor`] says
    /// otherwise.
    pub const fn number(
        key: &'static str,
        symbol: &'static str,
        unit: &'static str,
        range: Range,
        default: f64,
    ) -> Self {
        Param {
            key,
            symbol,
            unit,
            meaning: "",
            note: "",
            optional: false,
            kind: ParamKind::Number(NumberParam {
                range,
                default,
                typical: [default / 10.0, default * 10.0],
                logarithmic: false,
            }),
        }
    }

    /// With what it is, in a few words.
    pub const fn meaning(self, meaning: &'static str) -> Self {
        Param { meaning, ..self }
    }

    /// A parameter that scenes may leave out: the default then applies.
    pub const fn optional(self) -> Self {
        Param {
            optional: true,
            ..self
        }
    }

    /// With the span of the editor's slider, and whether it is logarithmic.
    pub const fn editor(self, typical: [f64; 2], logarithmic: bool) -> Self {
        let kind = match self.kind {
            ParamKind::Number(n) => ParamKind::Number(NumberParam {
                typical,
                logarithmic,
                ..n
            }),
            points => points,
        };
        Param { kind, ..self }
    }

    /// The same parameter with another admissible range, and the reason (a family that narrows
    /// a shared parameter, e.g. the bilinear law's α_e > 0).
    pub const fn narrowed(self, range: Range, note: &'static str) -> Self {
        let kind = match self.kind {
            ParamKind::Number(n) => ParamKind::Number(NumberParam { range, ..n }),
            points => points,
        };
        Param { kind, note, ..self }
    }

    /// The default value (the editor's initial value).
    pub fn default_value(&self) -> ParamValue {
        match self.kind {
            ParamKind::Number(n) => ParamValue::Number(n.default),
            ParamKind::Points { default } => ParamValue::Points(default.to_vec()),
        }
    }

    /// The value to build with: `given` checked against the kind and the range, or the default
    /// of an optional parameter. `family` and `takes` name the law in messages.
    fn admit(
        &self,
        given: Option<&ParamValue>,
        family: &str,
        takes: &str,
    ) -> Result<ParamValue, LawError> {
        let value = match given {
            None if self.optional => return Ok(self.default_value()),
            None => {
                return Err(LawError::new(
                    self.key,
                    "(missing)",
                    format!("the `{family}` law takes {takes}"),
                ))
            }
            Some(value) => value,
        };
        match (self.kind, value) {
            (ParamKind::Number(n), ParamValue::Number(x)) if !n.range.contains(*x) => {
                let note = if self.note.is_empty() {
                    String::new()
                } else {
                    format!("; {}", self.note)
                };
                Err(LawError::new(
                    self.key,
                    x,
                    format!(
                        "{} must be finite and {} ({}){note}",
                        self.symbol, n.range, self.unit
                    ),
                ))
            }
            (ParamKind::Number(_), ParamValue::Number(_))
            | (ParamKind::Points { .. }, ParamValue::Points(_)) => Ok(value.clone()),
            (ParamKind::Number(_), _) => Err(LawError::new(
                self.key,
                value,
                format!("must be a number ({})", self.unit),
            )),
            (ParamKind::Points { .. }, _) => Err(LawError::new(
                self.key,
                value,
                "must be rows [α, g_N] (m, Pa/m)",
            )),
        }
    }
}

/// g_N(0), shared by the parametric families.
pub const G_N0: Param = Param::number("g_n0", "g_N(0)", "Pa/m", Range::above(0.0), 5e8)
    .meaning("undamaged stiffness")
    .editor([1e5, 1e12], true);

/// α_e, shared by the parametric families.
pub const ALPHA_E: Param = Param::number("alpha_e", "α_e", "m", Range::at_least(0.0), 2e-3)
    .meaning("end of the elastic range")
    .editor([0.0, 0.05], true);

/// u_r, shared by the parametric families; u_r > α_e is checked by [`Knots::from_values`].
pub const U_R: Param = Param::number("u_r", "u_r", "m", Range::above(0.0), 4e-3)
    .meaning("rupture opening (> α_e)")
    .editor([1e-6, 0.1], true);

/// r_T, shared by the g_N(α) families: g_T(α) = r_T g_N(α) loads the tangential jump, and the
/// damage measure weighs it, f = (⟨[u]_N⟩₊² + r_T|[u]_T|²)^½ (`damage.rs`), so that G_c is the work
/// of separation in every mode. Optional, 1 by default (paper eq. 16's one stiffness; model §2.2).
pub const R_T: Param = Param::number("r_t", "r_T", "–", Range::above(0.0), 1.0)
    .meaning("tangential/normal stiffness ratio g_T/g_N")
    .editor([0.05, 20.0], true)
    .optional();

/// The value of one parameter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ParamValue {
    Number(f64),
    /// (α [m], g_N [Pa/m]) rows.
    Points(Vec<[f64; 2]>),
}

impl From<f64> for ParamValue {
    fn from(x: f64) -> Self {
        ParamValue::Number(x)
    }
}

impl From<Vec<[f64; 2]>> for ParamValue {
    fn from(points: Vec<[f64; 2]>) -> Self {
        ParamValue::Points(points)
    }
}

/// As messages show it: `0.0005`, `[[0.0, 1.0], [1.0, 0.0]]`.
impl fmt::Display for ParamValue {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            ParamValue::Number(x) => write!(f, "{x}"),
            ParamValue::Points(points) => write!(f, "{points:?}"),
        }
    }
}

/// A law's parameter values by key: a scene's `[interface.law]` table without `family`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(transparent)]
pub struct ParamValues(pub BTreeMap<String, ParamValue>);

impl ParamValues {
    /// These values with `key` set to `value`.
    pub fn with(mut self, key: &str, value: impl Into<ParamValue>) -> Self {
        self.0.insert(key.to_string(), value.into());
        self
    }

    pub fn get(&self, key: &str) -> Option<&ParamValue> {
        self.0.get(key)
    }

    /// The number at `key`, or why there is none.
    pub fn number(&self, key: &str) -> Result<f64, LawError> {
        match self.get(key) {
            Some(ParamValue::Number(x)) => Ok(*x),
            Some(other) => Err(LawError::new(key, other, "must be a number")),
            None => Err(LawError::new(key, "(missing)", "a number is required")),
        }
    }

    /// The rows at `key`, or why there are none.
    pub fn points(&self, key: &str) -> Result<&[[f64; 2]], LawError> {
        match self.get(key) {
            Some(ParamValue::Points(points)) => Ok(points),
            Some(other) => Err(LawError::new(key, other, "must be rows [α, g_N]")),
            None => Err(LawError::new(
                key,
                "(missing)",
                "rows [α, g_N] are required",
            )),
        }
    }
}

/// The three numbers of every law: g_N(0) [Pa/m], α_e [m], u_r [m], with u_r > α_e.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Knots {
    pub g_n0: f64,
    pub alpha_e: f64,
    pub u_r: f64,
}

impl Knots {
    /// Reads `g_n0`, `alpha_e`, `u_r` (ranges already checked) and checks u_r > α_e.
    pub fn from_values(values: &ParamValues) -> Result<Self, LawError> {
        let (g_n0, alpha_e, u_r) = (
            values.number(G_N0.key)?,
            values.number(ALPHA_E.key)?,
            values.number(U_R.key)?,
        );
        if !(u_r.is_finite() && u_r > alpha_e) {
            return Err(LawError::new(
                U_R.key,
                u_r,
                format!(
                    "u_r must be finite and > α_e = {alpha_e} m (rupture after the elastic range)"
                ),
            ));
        }
        Ok(Knots { g_n0, alpha_e, u_r })
    }

    /// The values [`Knots::from_values`] reads.
    pub fn values(&self) -> ParamValues {
        ParamValues::default()
            .with(G_N0.key, self.g_n0)
            .with(ALPHA_E.key, self.alpha_e)
            .with(U_R.key, self.u_r)
    }
}

/// What a law family declares. Implemented by the type of one file of `interface/laws/`, named
/// after the file (`plateau_linear.rs` → `PlateauLinear`); the family's own data (the
/// exponential decay, the table's points) are its fields.
pub trait Family: Sized + Into<LawKind> {
    /// Key in scene files (`family = "plateau_linear"`); equal to the file name.
    const KEY: &'static str;
    /// Name shown to users (`plateau–linear (paper fig. 5)`).
    const LABEL: &'static str;
    /// What g_N(α) is, in a sentence, for the scene reference (`decohesion reference scenes`).
    const DESCRIPTION: &'static str = "";
    /// Parameters, in the order an editor shows them.
    const PARAMS: &'static [Param];

    /// The family's own checks (model §2.5: g_N non-increasing, g_N(0) > 0, u_r > α_e,
    /// g_N(u_r) = 0, and whatever else the family needs), then its data and knots. `values`
    /// holds every parameter of [`Family::PARAMS`], of the right kind and in its range.
    fn build(values: &ParamValues) -> Result<(Self, Knots), LawError>;

    /// The parameter values that build this law again; by default its knots (g_n0, alpha_e,
    /// u_r), which is all a family without data of its own takes.
    fn values(&self, law: &StiffnessLaw) -> ParamValues {
        law.knots().values()
    }

    /// g_N(α) [Pa/m] on the softening branch, α_e < α < u_r.
    fn softening(&self, law: &StiffnessLaw, alpha: f64) -> f64;

    /// G_c = ∫₀^∞ g_N(δ) δ dδ [J/m²] in closed form (= ∫₀^{u_r} for a law cut at u_r): the
    /// work of separation under monotonic opening, in any mode (`damage.rs`).
    fn fracture_energy(&self, law: &StiffnessLaw) -> f64;

    /// Openings where T(δ) = g_N(δ)δ may peak that a uniform sampling could miss (kinks, an
    /// interior maximum); [`StiffnessLaw::peak_traction`] also samples [0, u_r].
    fn peak_candidates(&self, _law: &StiffnessLaw, _consider: &mut dyn FnMut(f64)) {}

    /// The normal jump is loaded on opening only (R_N = g_N⟨[u]_N⟩₊, `rccm`); the g_N(α)
    /// families load both signs (model §2.2).
    const OPENING_ONLY: bool = false;

    /// The tangential ratio r = g_T/g_N of a family that does not take [`R_T`] (`rccm`:
    /// C_T/C_N); a family that takes `r_t` gets its value.
    fn tangential_ratio(&self) -> f64 {
        1.0
    }

    /// Stage 8 (model §4.8) for the family: α at the end of an interval `h` from α, α_s and
    /// the damage measure f of the next configuration. By default eq. 12, delayed when the
    /// law has a delay ([`StiffnessLaw::rate_independent_or_delayed`]).
    fn next_damage(&self, law: &StiffnessLaw, s: DamageStep, alpha_s: &mut f64) -> f64 {
        law.rate_independent_or_delayed(s, alpha_s)
    }

    /// The opening whose running maximum α is, for a damage measure f whose shear part is
    /// `shear` = r|[u]_T|²: f itself for the families whose damage depends on f only (eq. 12);
    /// `bk` maps f and the mode mixity to the mode-I opening of the same damage (model §2.11).
    /// What [`StiffnessLaw::initial_damage`] takes the maximum of.
    fn damage_opening(&self, _law: &StiffnessLaw, f: f64, _shear: f64) -> f64 {
        f
    }

    /// Whether the family takes `[interface.delay]`; `Some(reason)` when it does not.
    fn refuses_delay(&self) -> Option<&'static str> {
        None
    }
}

/// The data of one stage-8 update at a node (model §4.8): α now, the damage measure f of
/// the next configuration, the interval h [s] over which it is reached, and the shear part
/// r|[u]_T|² of f² (the mode mixity B = r|[u]_T|²/f² of `bk`, model §2.11; the other families
/// do not read it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DamageStep {
    pub alpha: f64,
    pub f: f64,
    pub h: f64,
    pub shear: f64,
}

/// One row of the table of families: what [`Family`] declares, without its type.
#[derive(Debug)]
pub struct FamilySpec {
    pub key: &'static str,
    pub label: &'static str,
    /// [`Family::DESCRIPTION`].
    pub description: &'static str,
    pub params: &'static [Param],
    build: fn(&ParamValues) -> Result<StiffnessLaw, LawError>,
}

impl FamilySpec {
    /// The row of family `F`.
    pub const fn of<F: Family>() -> Self {
        FamilySpec {
            key: F::KEY,
            label: F::LABEL,
            description: F::DESCRIPTION,
            params: F::PARAMS,
            build: build::<F>,
        }
    }

    /// The parameter of that key, if the family takes it.
    pub fn param(&self, key: &str) -> Option<&'static Param> {
        self.params.iter().find(|p| p.key == key)
    }

    /// Its parameter keys as messages list them: `` `g_n0`, `alpha_e`, `u_r` ``.
    pub fn takes(&self) -> String {
        takes(self.params)
    }

    /// Every parameter at its default: the explorer's starting law, admissible for every family.
    pub fn defaults(&self) -> ParamValues {
        ParamValues(
            self.params
                .iter()
                .map(|p| (p.key.to_string(), p.default_value()))
                .collect(),
        )
    }

    /// Builds and checks the law: no key outside [`FamilySpec::params`], each value of its kind
    /// and in its range (an optional one left out takes its default), then the family's own
    /// checks. The error names the key, the value and what is admissible.
    pub fn build(&self, values: &ParamValues) -> Result<StiffnessLaw, LawError> {
        (self.build)(values)
    }
}

/// The table of law families, in the order of their keys.
pub fn families() -> &'static [FamilySpec] {
    FAMILIES
}

/// The family of that key (`plateau_linear`), if there is one.
pub fn family(key: &str) -> Option<&'static FamilySpec> {
    FAMILIES.iter().find(|f| f.key == key)
}

/// The family of that key, or an error (key `family`) that lists the admissible keys.
pub fn family_or_error(key: &str) -> Result<&'static FamilySpec, LawError> {
    family(key).ok_or_else(|| {
        let keys: Vec<String> = FAMILIES.iter().map(|f| format!("`{}`", f.key)).collect();
        LawError::new(
            "family",
            format!("{key:?}"),
            format!(
                "no law family of that name; admissible: {}",
                keys.join(", ")
            ),
        )
    })
}

fn takes(params: &[Param]) -> String {
    let keys: Vec<String> = params.iter().map(|p| format!("`{}`", p.key)).collect();
    keys.join(", ")
}

/// [`FamilySpec::build`] of family `F`.
fn build<F: Family>(given: &ParamValues) -> Result<StiffnessLaw, LawError> {
    let takes = takes(F::PARAMS);
    if let Some((key, value)) = given
        .0
        .iter()
        .find(|(k, _)| !F::PARAMS.iter().any(|p| p.key == k.as_str()))
    {
        return Err(LawError::new(
            key,
            value,
            format!(
                "not a parameter of the `{}` law, which takes {takes}",
                F::KEY
            ),
        ));
    }
    let mut values = ParamValues::default();
    for p in F::PARAMS {
        let value = p.admit(given.get(p.key), F::KEY, &takes)?;
        values.0.insert(p.key.to_string(), value);
    }
    let (own, knots) = F::build(&values)?;
    let r_t = match values.get(R_T.key) {
        Some(ParamValue::Number(r)) => *r,
        _ => own.tangential_ratio(),
    };
    let loading = Loading {
        ratio: r_t,
        opening_only: F::OPENING_ONLY,
        nonnegative_dissipation: false,
    };
    Ok(StiffnessLaw::from_parts(own.into(), knots, loading))
}

#[cfg(test)]
mod tests;
