//! The documentation of one key of a scene file as data ([`KeyDoc`]): its type, unit, default,
//! admissible values and meaning. The scene's tables of keys (`scene/keys.rs`) and the mould
//! shapes (`mould/shapes/`, each of which declares the keys it takes) are made of these; the
//! loader checks numbers against their ranges and `decohesion reference scenes` renders them.

use crate::interface::family::Range;

/// What the loader takes when a scene leaves a key out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DefaultDoc {
    /// The scene must give the key.
    Required,
    /// This number.
    Number(f64),
    /// What the loader does, in words (`the file's stem`, `[0, 0, 0]`, `required for a box`).
    Text(&'static str),
}

/// One key of a section of a scene file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeyDoc {
    /// The key in its section (`end_time`).
    pub key: &'static str,
    /// Another name the loader accepts for it (`mould` for `plane`), if any.
    pub alias: Option<&'static str>,
    /// The TOML type (`number`, `integer`, `string`, `[x, y, z]`, `rows [t, U]`, `table`).
    pub kind: &'static str,
    /// SI unit; `–` for a dimensionless number, empty for a key that is not a quantity.
    pub unit: &'static str,
    /// The quantity's symbol (`ν`), if a range between two numbers reads better as an
    /// inequality (`-1 < ν < 0.5`); empty otherwise.
    pub symbol: &'static str,
    pub default: DefaultDoc,
    /// Admissible values of the number (each component of an array): the loader refuses any
    /// other (`Check::admit`). `None`: any finite number, or not a number.
    pub range: Option<Range>,
    /// The admissible strings of a key that names one of a few choices (`svk`, `neo_hookean`).
    pub choices: &'static [&'static str],
    /// Further conditions, in words (appended to the range in messages and in the reference).
    pub admissible: &'static str,
    /// What the key is.
    pub description: &'static str,
}

impl KeyDoc {
    /// A required key of that type, unit and meaning, any value of the type admissible.
    pub const fn new(
        key: &'static str,
        kind: &'static str,
        unit: &'static str,
        description: &'static str,
    ) -> Self {
        KeyDoc {
            key,
            alias: None,
            kind,
            unit,
            symbol: "",
            default: DefaultDoc::Required,
            range: None,
            choices: &[],
            admissible: "",
            description,
        }
    }

    /// With another accepted name.
    pub const fn alias(self, alias: &'static str) -> Self {
        KeyDoc {
            alias: Some(alias),
            ..self
        }
    }

    /// With the quantity's symbol, for its range as an inequality.
    pub const fn symbol(self, symbol: &'static str) -> Self {
        KeyDoc { symbol, ..self }
    }

    /// Optional: `x` when left out.
    pub const fn default_number(self, x: f64) -> Self {
        KeyDoc {
            default: DefaultDoc::Number(x),
            ..self
        }
    }

    /// Optional, or required in some cases only: what happens when it is left out, in words.
    pub const fn default_text(self, text: &'static str) -> Self {
        KeyDoc {
            default: DefaultDoc::Text(text),
            ..self
        }
    }

    /// Each number in `range`.
    pub const fn range(self, range: Range) -> Self {
        KeyDoc {
            range: Some(range),
            ..self
        }
    }

    /// One of these strings.
    pub const fn choices(self, choices: &'static [&'static str]) -> Self {
        KeyDoc { choices, ..self }
    }

    /// With further conditions, in words.
    pub const fn admissible(self, admissible: &'static str) -> Self {
        KeyDoc { admissible, ..self }
    }

    /// `x` is admissible: finite and in [`KeyDoc::range`] if there is one.
    pub fn admits(&self, x: f64) -> bool {
        self.range.map_or(x.is_finite(), |r| r.contains(x))
    }

    /// The range as the reference and the messages write it: `> 0`, `in (0, 0.01]`, or with a
    /// symbol and two finite ends `-1 < ν < 0.5`.
    pub fn range_text(&self) -> Option<String> {
        let r = self.range?;
        if self.symbol.is_empty() || !(r.min.is_finite() && r.max.is_finite()) {
            return Some(r.to_string());
        }
        let sign = |open: bool| if open { "<" } else { "≤" };
        Some(format!(
            "{} {} {} {} {}",
            r.min,
            sign(r.min_open),
            self.symbol,
            sign(r.max_open),
            r.max
        ))
    }

    /// What a message says of a number outside the range: `must be > 0 s`, `must satisfy -1 < ν
    /// < 0.5 (0.5 is incompressible; above 0.49 use scheme.integration = "fbar" or
    /// "reduced_physical")`.
    pub fn must(&self) -> String {
        let mut text = match (self.range_text(), self.symbol.is_empty()) {
            (Some(r), false) if r.contains(self.symbol) => format!("must satisfy {r}"),
            (Some(r), _) => format!("must be {r}"),
            (None, _) => "must be finite".to_string(),
        };
        if !matches!(self.unit, "" | "–") {
            text.push(' ');
            text.push_str(self.unit);
        }
        if !self.admissible.is_empty() {
            text.push_str(&format!(" ({})", self.admissible));
        }
        text
    }
}

/// A number as the messages show it (shortest form that reads back to the same value).
pub fn num(x: f64) -> String {
    format!("{x:?}")
}

/// A TOML value as the messages show it: numbers (integers too) as [`num`], arrays element by
/// element, anything else as TOML writes it.
pub fn show(value: &toml::Value) -> String {
    match value {
        toml::Value::Float(x) => num(*x),
        toml::Value::Integer(i) => num(*i as f64),
        toml::Value::Array(items) => {
            let items: Vec<String> = items.iter().map(show).collect();
            format!("[{}]", items.join(", "))
        }
        other => other.to_string(),
    }
}
