//! What the explorer shares with the command line, on both targets (the web page has no
//! command line): the `--vary key=v1,v2,…` parser of `sweep` (the explorer's *compare values
//! of*) and the colours of series.

use anyhow::{bail, Result};
use serde::Serialize;

/// One `--vary key=v1,v2,…`: a scene key and its values, as `--set` would take them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Vary {
    pub key: String,
    pub values: Vec<String>,
}

/// Splits `text` on the commas outside brackets and quotes (so `mesh.cells=[2,2,2],[3,3,3]`
/// is two values).
fn split_values(text: &str) -> Vec<String> {
    let (mut out, mut cur, mut depth, mut quote) = (vec![], String::new(), 0i32, None);
    for ch in text.chars() {
        match (ch, quote) {
            ('"' | '\'', None) => quote = Some(ch),
            (c, Some(q)) if c == q => quote = None,
            ('[' | '{', None) => depth += 1,
            (']' | '}', None) => depth -= 1,
            (',', None) if depth == 0 => {
                out.push(std::mem::take(&mut cur));
                continue;
            }
            _ => {}
        }
        cur.push(ch);
    }
    out.push(cur);
    out.into_iter().map(|v| v.trim().to_string()).collect()
}

impl Vary {
    /// Parses `key=v1,v2,…`; the error names the key and what is wrong.
    pub fn parse(spec: &str) -> Result<Vary> {
        let Some((key, list)) = spec.split_once('=') else {
            bail!("--vary `{spec}`: expected `key.path=v1,v2,…` (no `=` found)");
        };
        let key = key.trim().to_string();
        if key.is_empty() {
            bail!("--vary `{spec}`: the key is empty; expected `key.path=v1,v2,…`");
        }
        if list.trim().is_empty() {
            bail!("--vary {key}: the list of values is empty; expected `{key}=v1,v2,…`");
        }
        let values = split_values(list);
        if let Some(i) = values.iter().position(String::is_empty) {
            bail!(
                "--vary {key}: value {} of `{}` is empty; expected `{key}=v1,v2,…`",
                i + 1,
                list.trim()
            );
        }
        Ok(Vary { key, values })
    }
}

/// Colours of series, in order (the first eight of Tableau 10): the sweep's series (one per
/// combination of the other keys) and the explorer's compared runs.
pub const PALETTE: [[u8; 3]; 8] = [
    [31, 119, 180],
    [214, 39, 40],
    [44, 160, 44],
    [148, 103, 189],
    [255, 127, 14],
    [23, 190, 207],
    [140, 86, 75],
    [227, 119, 194],
];
