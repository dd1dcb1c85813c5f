//! Links: URL queries that open a scene or a lesson's step, and the overrides (TOML keys)
//! that turn one scene document into another.

/// `text` as it may stand in a URL's query (RFC 3986: letters, digits and `-._~` as they are,
/// every other byte percent-encoded).
pub fn url_encode(text: &str) -> String {
    let mut out = String::new();
    for b in text.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~".contains(&b) {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

/// The query of a link that opens `scene` (`scenes/NAME.toml`: `NAME`) with the overrides
/// `set` (and starts the run with `run`).
pub fn scene_query(scene: &str, set: &[String], run: bool) -> String {
    let name = scene
        .strip_prefix("scenes/")
        .and_then(|s| s.strip_suffix(".toml"))
        .unwrap_or(scene);
    let mut q = format!("?scene={}", url_encode(name));
    for s in set {
        q.push_str("&set=");
        q.push_str(&url_encode(s));
    }
    if run {
        q.push_str("&run=1");
    }
    q
}

/// The query of a link to step `k` (0-based) of lesson `name`.
pub fn lesson_query(name: &str, k: usize) -> String {
    format!("?lesson={}&step={}", url_encode(name), k + 1)
}

/// The overrides that turn the document `base` into `edited` (both TOML texts): one
/// `key.path=value` per value that differs, arrays of tables of the same length entered by
/// index, any other array (and a table or array of another length) given whole. Keys that
/// `edited` lacks are not listed (an override cannot remove a key).
pub fn changed_keys(base: &str, edited: &str) -> Result<Vec<String>, String> {
    let base: toml::Table = base.parse().map_err(|e| format!("{e}"))?;
    let edited: toml::Table = edited.parse().map_err(|e| format!("{e}"))?;
    let mut out = vec![];
    diff_tables(&base, &edited, "", &mut out);
    out.sort();
    Ok(out)
}

fn diff_tables(base: &toml::Table, edited: &toml::Table, prefix: &str, out: &mut Vec<String>) {
    for (key, value) in edited {
        let path = format!("{prefix}{key}");
        diff_values(base.get(key), value, &path, out);
    }
}

fn diff_values(
    base: Option<&toml::Value>,
    edited: &toml::Value,
    path: &str,
    out: &mut Vec<String>,
) {
    use toml::Value;
    match (base, edited) {
        (Some(b), e) if b == e => {}
        (Some(Value::Table(b)), Value::Table(e)) => diff_tables(b, e, &format!("{path}."), out),
        (Some(Value::Array(b)), Value::Array(e))
            if b.len() == e.len() && b.iter().chain(e).all(Value::is_table) =>
        {
            for (i, (bi, ei)) in b.iter().zip(e).enumerate() {
                diff_values(Some(bi), ei, &format!("{path}.{i}"), out);
            }
        }
        (_, e) => out.push(format!("{path}={}", inline(e))),
    }
}

/// A TOML value on one line (tables inline).
fn inline(v: &toml::Value) -> String {
    match v {
        toml::Value::Table(t) => {
            let items: Vec<String> = t
                .iter()
                .map(|(k, v)| format!("{k} = {}", inline(v)))
                .collect();
            format!("{{ {} }}", items.join(", "))
        }
        toml::Value::Array(a) => {
            let items: Vec<String> = a.iter().map(inline).collect();
            format!("[{}]", items.join(", "))
        }
        other => other.to_string(),
    }
}
