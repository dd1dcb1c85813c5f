//! Compatibility layer, to be deleted once the explorer (`src/gui.rs`) and the recorder
//! (`src/record.rs`) read the table of families ([`families`](super::family::families),
//! [`StiffnessLaw::spec`], [`StiffnessLaw::values`], [`StiffnessLaw::build`]): the closed enum
//! [`LawFamily`] they match, the field `StiffnessLaw::family`, and the constructors
//! [`StiffnessLaw::new`] and [`StiffnessLaw::from_table`]. Until then a new family also needs a
//! variant here (the compiler points at [`LawFamily::of`]).

use super::family::{Knots, ParamValues};
use super::law::{LawError, StiffnessLaw};
use super::laws::{bilinear::Bilinear, exponential::Exponential, LawKind};
use super::laws::{plateau_linear::PlateauLinear, table::Table};
use serde::{Deserialize, Serialize};

/// Which family of stiffness law (PHYSICS.md §3), as a closed enum (compatibility layer).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "family", rename_all = "snake_case", deny_unknown_fields)]
pub enum LawFamily {
    /// Paper fig. 5: plateau then linear decrease ([`PlateauLinear`]).
    PlateauLinear,
    /// Linear-softening traction ([`Bilinear`]).
    Bilinear,
    /// Exponential decrease past α_e, cut to 0 at u_r ([`Exponential`]).
    Exponential {
        /// Decay exponent k over the softening range (dimensionless, > 0).
        decay: f64,
    },
    /// User table of (α, g_N) points ([`Table`]).
    Table {
        /// (α [m], g_N [Pa/m]) pairs.
        points: Vec<[f64; 2]>,
    },
}

impl LawFamily {
    /// The closed enum's view of a law's kind.
    pub(super) fn of(kind: &LawKind) -> Self {
        match kind {
            LawKind::PlateauLinear(_) => LawFamily::PlateauLinear,
            LawKind::Bilinear(_) => LawFamily::Bilinear,
            LawKind::Exponential(e) => LawFamily::Exponential { decay: e.decay },
            LawKind::Table(t) => LawFamily::Table {
                points: t.points.clone(),
            },
        }
    }
}

impl StiffnessLaw {
    /// Builds and checks a law of `family` (compatibility layer; for `Table`, g_n0, α_e and
    /// u_r are derived from the points and the arguments are ignored).
    pub fn new(family: LawFamily, g_n0: f64, alpha_e: f64, u_r: f64) -> Result<Self, LawError> {
        let knots = Knots { g_n0, alpha_e, u_r }.values();
        match family {
            LawFamily::PlateauLinear => Self::of::<PlateauLinear>(&knots),
            LawFamily::Bilinear => Self::of::<Bilinear>(&knots),
            LawFamily::Exponential { decay } => {
                Self::of::<Exponential>(&knots.with("decay", decay))
            }
            LawFamily::Table { points } => Self::from_table(points),
        }
    }

    /// Builds and checks a `table` law (compatibility layer).
    pub fn from_table(points: Vec<[f64; 2]>) -> Result<Self, LawError> {
        Self::of::<Table>(&ParamValues::default().with("points", points))
    }
}
