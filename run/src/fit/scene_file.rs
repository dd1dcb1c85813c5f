//! The scene file with the fitted values: the original text, comments and layout kept
//! (toml_edit), each fitted key set (or added where it took its default) with a comment giving
//! its σ, and the caller's `--set` overrides applied as well, so that the file alone gives the
//! fitted run.

use anyhow::{anyhow, bail, Result};
use toml_edit::{DocumentMut, Item, Value};

/// Sets `key` (the `--set` path) to `value` in `doc`, with a trailing comment `note`.
pub fn set(doc: &mut DocumentMut, key: &str, value: Value, note: Option<&str>) -> Result<()> {
    let segs: Vec<&str> = key.split('.').map(str::trim).collect();
    let mut item: &mut Item = doc.as_item_mut();
    let mut i = 0;
    while i < segs.len() {
        let seg = segs[i];
        i += 1;
        let last = i == segs.len();
        // Step into `seg` of the current table (a table, an inline table).
        let next: &mut Item = match item {
            Item::Table(t) => {
                if last {
                    put(t, seg, value, note);
                    return Ok(());
                }
                t.entry(seg)
                    .or_insert_with(|| Item::Table(toml_edit::Table::new()))
            }
            Item::Value(Value::InlineTable(t)) => {
                if last {
                    let mut v = value;
                    decorate(&mut v, note);
                    t.insert(seg, v);
                    return Ok(());
                }
                let v = t
                    .get_mut(seg)
                    .ok_or_else(|| anyhow!("`{}` is missing", segs[..i].join(".")))?;
                return set_in_value(v, &segs[i..], value, note, key);
            }
            _ => bail!("`{}` is not a table", segs[..i - 1].join(".")),
        };
        item = match next {
            Item::ArrayOfTables(a) => {
                let index = match segs.get(i).and_then(|s| s.parse::<usize>().ok()) {
                    Some(n) => {
                        i += 1;
                        n
                    }
                    None if a.len() == 1 => 0,
                    None => bail!("`{key}`: say which element of `{seg}`"),
                };
                let len = a.len();
                let t = a
                    .get_mut(index)
                    .ok_or_else(|| anyhow!("`{key}`: `{seg}` has {len} elements"))?;
                if i == segs.len() {
                    bail!("`{key}` names a table, not a value");
                }
                // Continue inside the element (a table).
                let seg = segs[i];
                i += 1;
                if i == segs.len() {
                    put(t, seg, value, note);
                    return Ok(());
                }
                t.entry(seg)
                    .or_insert_with(|| Item::Table(toml_edit::Table::new()))
            }
            other => other,
        };
    }
    bail!("`{key}`: empty key")
}

/// Sets `segs` inside an inline value (an inline table).
fn set_in_value(
    v: &mut Value,
    segs: &[&str],
    value: Value,
    note: Option<&str>,
    key: &str,
) -> Result<()> {
    let Value::InlineTable(t) = v else {
        bail!("`{key}`: not a table");
    };
    if segs.len() == 1 {
        let mut value = value;
        decorate(&mut value, note);
        t.insert(segs[0], value);
        return Ok(());
    }
    let inner = t
        .get_mut(segs[0])
        .ok_or_else(|| anyhow!("`{key}`: `{}` is missing", segs[0]))?;
    set_in_value(inner, &segs[1..], value, note, key)
}

/// Sets `seg` of the table `t` to `value`: in place when the key is there, so that the comment
/// lines above it (its key's decor) and the spacing after `=` stay.
fn put(t: &mut toml_edit::Table, seg: &str, mut value: Value, note: Option<&str>) {
    decorate(&mut value, note);
    match t.get_mut(seg) {
        Some(Item::Value(old)) => {
            if let Some(prefix) = old.decor().prefix().cloned() {
                value.decor_mut().set_prefix(prefix);
            }
            *old = value;
        }
        _ => {
            t.insert(seg, Item::Value(value));
        }
    }
}

fn decorate(v: &mut Value, note: Option<&str>) {
    if let Some(n) = note {
        v.decor_mut().set_suffix(format!("  # {n}"));
    }
}

/// The text of the scene `text` with each (key, value, note) set; the header comment says where
/// the values came from.
pub fn fitted_scene(
    text: &str,
    header: &str,
    values: &[(String, Value, Option<String>)],
) -> Result<String> {
    let mut doc: DocumentMut = text.parse()?;
    for (key, value, note) in values {
        set(&mut doc, key, value.clone(), note.as_deref())?;
    }
    let mut out = String::new();
    for line in header.lines() {
        out.push_str("# ");
        out.push_str(line);
        out.push('\n');
    }
    out.push_str(&doc.to_string());
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_keys_keeping_comments() {
        let text = "name = 'x' # the name\n[[interface]]\nfaces = 'z-'\n[interface.law]\n# the law\nu_r = 4e-3 # m\n";
        let out = fitted_scene(
            text,
            "fitted",
            &[
                (
                    "interface.law.u_r".into(),
                    Value::from(5e-3),
                    Some("σ = 1e-4".into()),
                ),
                ("interface.law.alpha_e".into(), Value::from(2e-3), None),
                ("end_time".into(), Value::from(0.5), None),
            ],
        )
        .unwrap();
        assert!(out.starts_with("# fitted\n"));
        assert!(out.contains("# the law"), "{out}");
        assert!(out.contains("u_r = 0.005  # σ = 1e-4"), "{out}");
        let doc: toml::Table = toml::from_str(&out).unwrap();
        let law = &doc["interface"][0]["law"];
        assert_eq!(law["alpha_e"].as_float(), Some(2e-3));
        assert_eq!(doc["end_time"].as_float(), Some(0.5));
    }
}
