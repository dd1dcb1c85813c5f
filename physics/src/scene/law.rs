//! `[interface.law]`: the family's row of the table ([`crate::law::families`]) says which keys
//! it takes and of what kind; the family then checks the values.

use super::check::Check;
use super::error::{show, SceneError};
use super::raw::{RawDelay, RawLaw};
use crate::law::{
    family_or_error, Delay, LawError, ParamKind, ParamValue, ParamValues, StiffnessLaw,
};

impl Check<'_> {
    /// `interface[i].law` and `interface[i].delay`: the law, delayed when the table is given
    /// (τ_c > 0, a > 0; refused by a family with its own rate effect, `rccm`).
    pub(super) fn delayed_law(
        &self,
        key: &str,
        raw: RawLaw,
        delay: Option<RawDelay>,
    ) -> Result<StiffnessLaw, SceneError> {
        let law = self.law(&format!("{key}.law"), raw)?;
        let delay_error = |e: LawError| {
            let at = if e.key == "delay" {
                format!("{key}.delay")
            } else {
                format!("{key}.delay.{}", e.key)
            };
            self.invalid(at, e.value, e.reason)
        };
        let delay = match delay {
            None => None,
            Some(d) => Some(Delay::new(d.tau_c, d.a).map_err(delay_error)?),
        };
        law.with_delay(delay).map_err(delay_error)
    }

    /// The RCCM law of `interface[i]`: the keys its family takes, then the family's checks.
    pub(super) fn law(&self, key: &str, raw: RawLaw) -> Result<StiffnessLaw, SceneError> {
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
            return Err(self.missing(
                format!("{key}.{}", p.key),
                format!("the `{}` law takes {}", spec.key, spec.takes()),
            ));
        }
        spec.build(&values).map_err(law_error)
    }
}
