//! Runs compared over one setting: the keys the explorer can vary, `key=v1,v2,…` parsed and
//! checked, the queue of variants, and the history rows ticked for comparison.

use super::App;
use crate::gui::history::legend_labels;
use crate::gui::{HistoryRow, Settings};

/// Settings the explorer can vary over queued runs ([`App::queue_variants`]) besides the
/// number parameters of the law (`interface.law.NAME`, alias `NAME`): the key path as
/// `sweep --vary` and `--set` take it, and its short name. `mesh.cells` is the number of cells
/// along the longest side of a box mesh (the other sides scaled in proportion), as
/// `tradeoff --cells` takes it.
pub const VARIANT_KEYS: [(&str, &str); 4] = [
    ("interface.mu_inf", "mu_inf"),
    ("mesh.cells", "cells"),
    ("scheme.time_step_factor", "factor"),
    ("end_time", "end_time"),
];

/// The prefix of the law's parameters in a key path.
const LAW_PREFIX: &str = "interface.law.";

/// The number parameters of a law family (none for an unknown family).
fn number_params(spec: Option<&'static crate::law::FamilySpec>) -> Vec<&'static str> {
    spec.map_or(&[][..], |f| f.params)
        .iter()
        .filter(|p| matches!(p.kind, crate::law::ParamKind::Number(_)))
        .map(|p| p.key)
        .collect()
}

/// The short name of the compared key `key` (a key path or its short name): a number parameter
/// of the law (`params`, of the family `family`, or of any family when it is not known yet) or
/// one of [`VARIANT_KEYS`]. The error lists what is admissible.
pub fn variant_key(key: &str, family: Option<&str>, params: &[&str]) -> Result<String, String> {
    let param = key.strip_prefix(LAW_PREFIX).unwrap_or(key);
    if params.contains(&param) {
        return Ok(param.to_string());
    }
    if let Some((_, short)) = VARIANT_KEYS.iter().find(|(p, s)| key == *p || key == *s) {
        return Ok(short.to_string());
    }
    let law = match family {
        Some(f) => format!("of the `{f}` law"),
        None => "of the scene's law".to_string(),
    };
    let paths: Vec<&str> = VARIANT_KEYS.iter().map(|k| k.0).collect();
    let shorts: Vec<&str> = VARIANT_KEYS.iter().map(|k| k.1).collect();
    Err(format!(
        "`{key}` cannot be compared: admissible are {LAW_PREFIX}NAME for a number parameter \
         {law} (NAME: {}), {} (short names: NAME, {})",
        params.join(", "),
        paths.join(", "),
        shorts.join(", ")
    ))
}

/// Parses `key=v1,v2,…` of *compare values of* and `gui --compare`: the short name of the key
/// ([`variant_key`]) and the values, which must be numbers. The error names the key and the
/// value (without the flag, which the caller adds).
fn parse_compare(
    spec: &str,
    family: Option<&str>,
    params: &[&str],
) -> Result<(String, Vec<f64>), String> {
    let vary = crate::vary::Vary::parse(spec).map_err(|e| e.to_string().replace("--vary ", ""))?;
    let key = variant_key(&vary.key, family, params)?;
    let values = vary
        .values
        .iter()
        .map(|v| match v.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(format!("{} = `{v}`: not a number", vary.key)),
        })
        .collect::<Result<Vec<f64>, String>>()?;
    Ok((key, values))
}

/// Checks `gui --compare key=v1,v2,…` before the window opens: the syntax, the key (against
/// the law of `scene`, or of any family when no scene is given: the window then checks it
/// against the law it opens with) and that the values are numbers. The window checks each
/// value against the scene when it queues the runs.
pub fn check_compare(spec: &str, scene: Option<&str>) -> Result<(), String> {
    match scene {
        Some(path) => {
            let mut settings = Settings::default();
            settings.take_scene(&crate::gui::settings::open_scene(path)?);
            let params = number_params(settings.law.spec());
            parse_compare(spec, Some(&settings.law.family), &params)?;
        }
        None => {
            let mut params: Vec<&str> = crate::law::families()
                .iter()
                .flat_map(|f| number_params(Some(f)))
                .collect();
            params.sort_unstable();
            params.dedup();
            parse_compare(spec, None, &params)?;
        }
    }
    Ok(())
}

impl App {
    /// Ticks or unticks history run `id` for comparison.
    pub fn toggle_compare(&mut self, id: u32) {
        if !self.compare.remove(&id) {
            self.compare.insert(id);
        }
    }

    /// The history rows ticked for comparison (in run order) with their legend labels: `run N`
    /// and the parameters that differ between them.
    pub fn compared(&self) -> Vec<(&HistoryRow, String)> {
        let rows: Vec<&HistoryRow> = self
            .history
            .iter()
            .filter(|r| self.compare.contains(&r.id))
            .collect();
        let labels = legend_labels(&rows);
        rows.into_iter().zip(labels).collect()
    }

    /// Queues one run per value of `key` (a number parameter of the edited law or one of
    /// [`VARIANT_KEYS`], as a key path or its short name: [`variant_key`]), the other settings
    /// as they are now; the runs start one after the other and are ticked for comparison.
    /// Nothing is queued if a value is refused.
    pub fn queue_variants(&mut self, key: &str, values: &[f64]) -> Result<(), String> {
        let params = number_params(self.settings.law.spec());
        let short = variant_key(key, Some(&self.settings.law.family), &params)?;
        let mut variants = vec![];
        for &v in values {
            let mut s = self.settings.clone();
            match short.as_str() {
                "mu_inf" => s.law.mu_inf = v,
                "cells" if v >= 1.0 && v.fract() == 0.0 && s.cells > 0 => s.cells = v as usize,
                "factor" => s.factor = v,
                "end_time" => s.end_time = v,
                "cells" => {
                    return Err(format!(
                        "{key} = {v}: must be a whole number ≥ 1 (cells along the longest side), \
                         on a scene with a box mesh"
                    ))
                }
                param => {
                    s.law.values.0.insert(param.to_string(), v.into());
                }
            }
            s.law.law().map_err(|e| format!("{key} = {v}: {e}"))?;
            s.scene().map_err(|e| format!("{key} = {v}: {e}"))?;
            variants.push(s);
        }
        self.queue.extend(variants);
        if self.job.is_none() {
            self.start_queued();
        }
        Ok(())
    }

    /// [`App::queue_variants`] from `key=v1,v2,…` (as `decohesion sweep --vary` takes it, the
    /// key a path or its short name); the error names the key and the value.
    pub fn queue_spec(&mut self, spec: &str) -> Result<(), String> {
        if spec.trim().is_empty() {
            return Err("write key=v1,v2,… first, e.g. interface.law.u_r=0.003,0.004,0.006".into());
        }
        let params = number_params(self.settings.law.spec());
        let (_, values) = parse_compare(spec, Some(&self.settings.law.family), &params)?;
        let key = spec.split_once('=').map_or(spec, |(k, _)| k).trim();
        self.queue_variants(key, &values)
    }

    /// Starts the next queued run, if any; true if one started.
    pub(super) fn start_queued(&mut self) -> bool {
        while let Some(s) = self.queue.pop_front() {
            self.settings = s;
            self.validation = None;
            self.queued_run = true;
            self.start();
            self.queued_run = false;
            if self.job.is_some() {
                return true;
            }
        }
        false
    }
}
