//! The `--set key.path=value` overrides, applied to the parsed TOML document before it is
//! deserialized (so they are validated like the file).

use serde::Deserialize;

/// Applies one `key.path=value` override to the document; the error is the reason.
pub(super) fn apply_override(doc: &mut toml::Table, spec: &str) -> Result<(), String> {
    let (key, text) = spec
        .split_once('=')
        .ok_or("expected `key.path=value` (no `=` found)")?;
    let segs: Vec<&str> = key.trim().split('.').map(str::trim).collect();
    if segs.iter().any(|s| s.is_empty()) {
        return Err(format!(
            "the key `{}` is empty or has an empty segment; expected `key.path=value`",
            key.trim()
        ));
    }
    let text = text.trim();
    let value = toml::Value::deserialize(toml::de::ValueDeserializer::new(text))
        .unwrap_or_else(|_| toml::Value::String(text.to_string()));
    let mut node = doc;
    let mut i = 0;
    loop {
        let (seg, last) = (segs[i], i + 1 == segs.len());
        if last {
            node.insert(seg.to_string(), value);
            return Ok(());
        }
        let next = node
            .entry(seg)
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        i += 1;
        node = match next {
            toml::Value::Table(t) => t,
            toml::Value::Array(items) => {
                let path = segs[..i].join(".");
                let rest = segs[i..].join(".");
                let index = match segs[i].parse::<usize>() {
                    Ok(n) => {
                        i += 1;
                        n
                    }
                    Err(_) if !items.iter().all(toml::Value::is_table) => {
                        return Err(format!(
                            "`{path}` is an array of values: index it with a number, \
                             e.g. `{path}.0`"
                        ))
                    }
                    Err(_) if items.len() == 1 => 0,
                    Err(_) if items.is_empty() => return Err(format!("`{path}` is empty")),
                    Err(_) => {
                        return Err(format!(
                            "`{path}` has {} elements: say which one, e.g. `{path}.0.{rest}`",
                            items.len()
                        ))
                    }
                };
                let len = items.len();
                let Some(item) = items.get_mut(index) else {
                    return Err(format!(
                        "index {index} is out of range: `{path}` has {len} elements"
                    ));
                };
                if i == segs.len() {
                    *item = value;
                    return Ok(());
                }
                match item {
                    toml::Value::Table(t) => t,
                    _ => {
                        return Err(format!(
                            "`{path}` holds values, not tables: `{path}.{index}` has no keys"
                        ))
                    }
                }
            }
            other => {
                return Err(format!(
                    "`{}` is a {}, not a table: it has no key `{}`",
                    segs[..i].join("."),
                    other.type_str(),
                    segs[i]
                ))
            }
        };
    }
}
