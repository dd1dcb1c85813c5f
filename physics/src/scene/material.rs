//! `[material]`: Saint-Venant–Kirchhoff and the compressible neo-Hookean from (E, ν); the rubber
//! models (model §1.10) from their family's parameters (the table
//! [`crate::material::rubber::RUBBERS`]) and the bulk modulus K, given or through ν.

use super::check::Check;
use super::error::{num, SceneError};
use super::keys;
use super::raw::{ParamValue, RawMaterial};
use crate::material::rubber::{bulk_from_poisson, ParamError, Rubber, RubberValues, RUBBERS};
use crate::material::{Material, MaterialModel};

/// The keys of `[material]` that only the rubber models take and the scene gave, with their
/// values as shown: `bulk`, `volumetric`, then the families' parameters in the file's order.
fn rubber_keys(m: &RawMaterial) -> Vec<(&'static str, String)> {
    let shared = [
        ("bulk", m.bulk.map(num)),
        (
            "volumetric",
            m.volumetric.map(|v| format!("{v:?}").to_lowercase()),
        ),
    ];
    let params = m.params.iter().map(|(p, value)| {
        let shown = match value {
            ParamValue::Number(x) => num(*x),
            ParamValue::List(v) => format!("{v:?}"),
        };
        (p.key, Some(shown))
    });
    (shared.into_iter().chain(params))
        .filter_map(|(k, v)| Some((k, v?)))
        .collect()
}

impl RubberValues for RawMaterial {
    fn number(&self, key: &str) -> Option<f64> {
        self.params.iter().find_map(|(p, value)| match value {
            ParamValue::Number(x) if p.key == key => Some(*x),
            _ => None,
        })
    }

    fn list(&self, key: &str) -> Option<Vec<f64>> {
        self.params.iter().find_map(|(p, value)| match value {
            ParamValue::List(v) if p.key == key => Some(v.clone()),
            _ => None,
        })
    }
}

impl Check<'_> {
    /// `[material]`: SVK unless `model` says otherwise. SVK and neo-Hookean: E > 0,
    /// −1 < ν < 0.5, ρ > 0, no rubber key. A rubber: its family's parameters (each in its
    /// range, μ₀ > 0), `bulk` K > 0 or `poisson` −1 < ν < 0.5 (one of the two), no `young`,
    /// no other family's key.
    pub(super) fn material(&self, mat: &RawMaterial) -> Result<Material, SceneError> {
        let model = mat.model.unwrap_or(MaterialModel::Svk);
        let Some(spec) = model.rubber_spec() else {
            let takes = format!(
                "the `{}` model takes `young` E [Pa], `poisson` ν and `density` ρ₀",
                model.key()
            );
            if let Some((key, value)) = rubber_keys(mat).into_iter().next() {
                return Err(self.invalid(
                    format!("material.{key}"),
                    value,
                    format!(
                        "{takes}; `{key}` is a parameter of the rubber models (`model` = {})",
                        RUBBERS.iter().map(|r| r.key).collect::<Vec<_>>().join(", ")
                    ),
                ));
            }
            let young = mat
                .young
                .ok_or_else(|| self.missing("material.young", takes.clone()))?;
            self.admit(&keys::YOUNG, "material.young", young)?;
            let poisson = mat
                .poisson
                .ok_or_else(|| self.missing("material.poisson", takes.clone()))?;
            self.admit(&keys::POISSON, "material.poisson", poisson)?;
            self.admit(&keys::DENSITY, "material.density", mat.density)?;
            let m = Material::new(model, young, poisson, mat.density);
            // Each in range, E, ν and ρ₀ can still give a modulus or a wave speed that
            // overflows to inf or underflows to a subnormal (E = 1e308, ρ₀ = 1e-300).
            let c = m.wave_speed();
            if !(m.lambda.is_finite() && m.mu.is_normal() && c.is_normal()) {
                return Err(self.invalid(
                    "material.young",
                    num(young),
                    format!(
                        "with ν = {poisson} and ρ₀ = {} kg/m³ it gives λ = {:e} Pa, μ = {:e} Pa and the wave speed c_d = {c:e} m/s: each must be a finite number, μ and c_d above 1e-308",
                        mat.density, m.lambda, m.mu
                    ),
                ));
            }
            return Ok(m);
        };
        let params: Vec<&str> = spec.params.iter().map(|p| p.key).collect();
        let takes = format!(
            "the `{}` model takes {}, `bulk` K [Pa] or `poisson` ν, `volumetric` and `density`",
            spec.key,
            params
                .iter()
                .map(|k| format!("`{k}`"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        if let Some(young) = mat.young {
            return Err(self.invalid(
                "material.young",
                num(young),
                format!("{takes}: its small-strain E follows from μ₀ and K"),
            ));
        }
        let foreign = rubber_keys(mat).into_iter().find(|(k, _)| {
            let common = matches!(*k, "bulk" | "volumetric");
            !common && !params.contains(k)
        });
        if let Some((key, value)) = foreign {
            return Err(self.invalid(format!("material.{key}"), value, takes));
        }
        let param_error =
            |e: ParamError| self.invalid(format!("material.{}", e.key), e.value, e.reason);
        let MaterialModel::Rubber(family) = model else {
            unreachable!("a model with a rubber row is a rubber")
        };
        let iso = family.from_values(mat).map_err(param_error)?;
        let mu0 = iso.initial_shear_modulus();
        let bulk = match (mat.bulk, mat.poisson) {
            (Some(_), Some(nu)) => {
                return Err(self.invalid(
                    "material.poisson",
                    num(nu),
                    "give the bulk modulus once: `bulk` K [Pa] or `poisson` ν, not both",
                ))
            }
            (Some(k), None) => {
                self.admit(&super::material_keys::BULK, "material.bulk", k)?;
                k
            }
            (None, Some(nu)) => {
                self.require(
                    nu > -1.0 && nu < 0.5,
                    "material.poisson",
                    nu,
                    "a rubber's bulk modulus K = 2μ₀(1 + ν)/(3(1 − 2ν)) must be finite and positive: -1 < ν < 0.5 (0.49 to 0.4999 for a rubber; ν = 0.5, incompressible, would make K infinite and the stable step zero), or give `bulk` K > 0 [Pa] directly",
                )?;
                bulk_from_poisson(mu0, nu)
            }
            (None, None) => {
                return Err(self.missing(
                    "material.bulk",
                    format!("{takes}: the bulk modulus, as `bulk` K [Pa] or through `poisson` ν (K = 2μ₀(1 + ν)/(3(1 − 2ν)))"),
                ))
            }
        };
        self.admit(&keys::DENSITY, "material.density", mat.density)?;
        let rubber = Rubber {
            iso,
            bulk,
            volumetric: mat.volumetric.unwrap_or_default(),
        };
        Ok(Material::rubber(rubber, mat.density))
    }
}
