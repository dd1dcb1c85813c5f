//! The interface law as the explorer edits it: its family and parameters ([`LawSettings`]),
//! checked by the library's own constructors, and written into the edited scene as TOML.

use crate::law::{LawFamily, StiffnessLaw};
use serde::{Deserialize, Serialize};

/// The law families offered by the editor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Family {
    PlateauLinear,
    Bilinear,
    Exponential,
    Table,
}

impl Family {
    pub(super) const ALL: [Family; 4] = [
        Family::PlateauLinear,
        Family::Bilinear,
        Family::Exponential,
        Family::Table,
    ];
    pub(super) fn key(self) -> &'static str {
        match self {
            Family::PlateauLinear => "plateau_linear",
            Family::Bilinear => "bilinear",
            Family::Exponential => "exponential",
            Family::Table => "table",
        }
    }
    pub(super) fn label(self) -> &'static str {
        match self {
            Family::PlateauLinear => "plateau–linear (paper fig. 5)",
            Family::Bilinear => "bilinear (linear-softening traction)",
            Family::Exponential => "exponential",
            Family::Table => "table of points",
        }
    }
}

/// The interface law as edited (applied to every interface of the scene).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct LawSettings {
    pub family: Family,
    /// g_N(0) [Pa/m].
    pub g_n0: f64,
    /// α_e [m].
    pub alpha_e: f64,
    /// u_r [m].
    pub u_r: f64,
    /// Exponent k of the exponential family.
    pub decay: f64,
    /// (α [m], g_N [Pa/m]) rows of the table family.
    pub points: Vec<[f64; 2]>,
    /// μ_inf, friction of the fully ruptured interface.
    pub mu_inf: f64,
}

impl Default for LawSettings {
    fn default() -> Self {
        LawSettings {
            family: Family::PlateauLinear,
            g_n0: 5e8,
            alpha_e: 2e-3,
            u_r: 4e-3,
            decay: 5.0,
            points: vec![[0.0, 5e8], [2e-3, 5e8], [4e-3, 0.0]],
            mu_inf: 0.5,
        }
    }
}

impl LawSettings {
    /// The law, or why it is inadmissible (the library's own checks).
    pub fn law(&self) -> Result<StiffnessLaw, String> {
        let r = match self.family {
            Family::PlateauLinear => {
                StiffnessLaw::new(LawFamily::PlateauLinear, self.g_n0, self.alpha_e, self.u_r)
            }
            Family::Bilinear => {
                StiffnessLaw::new(LawFamily::Bilinear, self.g_n0, self.alpha_e, self.u_r)
            }
            Family::Exponential => StiffnessLaw::new(
                LawFamily::Exponential { decay: self.decay },
                self.g_n0,
                self.alpha_e,
                self.u_r,
            ),
            Family::Table => StiffnessLaw::from_table(self.points.clone()),
        };
        let law = r.map_err(|e| format!("{}: {}", e.key, e.reason))?;
        if !(self.mu_inf.is_finite() && self.mu_inf >= 0.0) {
            return Err(format!("μ_inf = {}: must be finite and ≥ 0", self.mu_inf));
        }
        Ok(law)
    }

    pub(super) fn to_toml(&self) -> toml::Table {
        let mut t = toml::Table::new();
        t.insert("family".into(), self.family.key().into());
        if self.family == Family::Table {
            let rows = self
                .points
                .iter()
                .map(|p| toml::Value::Array(vec![p[0].into(), p[1].into()]))
                .collect();
            t.insert("points".into(), toml::Value::Array(rows));
        } else {
            t.insert("g_n0".into(), self.g_n0.into());
            t.insert("alpha_e".into(), self.alpha_e.into());
            t.insert("u_r".into(), self.u_r.into());
            if self.family == Family::Exponential {
                t.insert("decay".into(), self.decay.into());
            }
        }
        t
    }
}
