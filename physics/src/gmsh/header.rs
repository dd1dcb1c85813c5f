//! The parts of a `.msh` file read before (or beside) mshio: whether it is binary, the
//! `$MeshFormat` data size mshio would panic on, the `$PhysicalNames` section, and mshio's parse
//! errors as messages with the line (ASCII) or byte (binary) they are at.

use super::MshError;
use std::collections::BTreeMap;

/// True when the header says binary (`$MeshFormat` / `4.1 1 8`).
pub(super) fn is_binary(bytes: &[u8]) -> bool {
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(256)]);
    text.lines()
        .skip_while(|l| l.trim() != "$MeshFormat")
        .nth(1)
        .and_then(|l| l.split_whitespace().nth(1).map(|t| t == "1"))
        .unwrap_or(false)
}

/// The data size of the `$MeshFormat` line (`4.1 file-type data-size`), the bytes of an unsigned
/// integer in a binary file, refused unless 1, 2, 4, 8 or 16 (Gmsh writes sizeof(size_t) = 8):
/// mshio 0.4.2 panics on any other value in a binary file, and on digits that overflow an
/// integer in either kind, instead of returning an error.
pub(super) fn check_data_size(bytes: &[u8], file: &str, binary: bool) -> Result<(), MshError> {
    const TAG: &[u8] = b"$MeshFormat";
    let head = &bytes[..bytes.len().min(4096)];
    let Some(start) = head.windows(TAG.len()).position(|w| w == TAG) else {
        return Ok(());
    };
    // mshio separates the three numbers by single spaces, tabs or line ends; tokens split on any
    // run of them (a run mshio rejects is its own syntax error either way).
    let is_space = |b: &u8| matches!(b, b' ' | b'\t' | b'\r' | b'\n');
    let mut at = start + TAG.len();
    let token = |at: &mut usize| {
        while *at < head.len() && is_space(&head[*at]) {
            *at += 1;
        }
        let from = *at;
        while *at < head.len() && !is_space(&head[*at]) {
            *at += 1;
        }
        from
    };
    let (_version, _file_type, size_at) = (token(&mut at), token(&mut at), token(&mut at));
    // mshio reads the leading digits of the data size (what follows them is its syntax error).
    let digits: String = head[size_at..at]
        .iter()
        .take_while(|b| b.is_ascii_digit())
        .map(|&b| b as char)
        .collect();
    if digits.is_empty() {
        return Ok(());
    }
    match digits.parse::<u64>() {
        Ok(1 | 2 | 4 | 8 | 16) => Ok(()),
        _ => Err(MshError::Syntax {
            file: file.to_string(),
            at: location(bytes, size_at, binary),
            message: format!(
                "data size {} in $MeshFormat: admissible 1, 2, 4, 8 or 16 (the bytes of an unsigned integer; Gmsh writes 8)",
                if digits.len() > 24 { format!("{}…", &digits[..24]) } else { digits }
            ),
        }),
    }
}

/// "line N" (1-based) of byte `offset`, or "byte N" in a binary file.
pub(super) fn location(bytes: &[u8], offset: usize, binary: bool) -> String {
    let offset = offset.min(bytes.len());
    if binary {
        format!("byte {offset}")
    } else {
        let line = 1 + bytes[..offset].iter().filter(|&&b| b == b'\n').count();
        format!("line {line}")
    }
}

/// The `$PhysicalNames` section (always ASCII, before the binary sections): (dim, tag) → name.
/// It is searched before the first `$Entities` or `$Nodes` so that binary data is never read as
/// text.
pub(super) fn physical_names(
    bytes: &[u8],
    file: &str,
    binary: bool,
) -> Result<BTreeMap<(i32, i32), String>, MshError> {
    let find = |pat: &[u8], from: usize| {
        bytes[from..]
            .windows(pat.len())
            .position(|w| w == pat)
            .map(|p| p + from)
    };
    let stop = [&b"\n$Entities"[..], b"\n$Nodes"]
        .iter()
        .filter_map(|p| find(p, 0))
        .min()
        .unwrap_or(bytes.len());
    let mut names = BTreeMap::new();
    let Some(start) = find(b"$PhysicalNames", 0).filter(|&s| s < stop) else {
        return Ok(names);
    };
    let first_line = 1 + bytes[..start].iter().filter(|&&b| b == b'\n').count();
    let end = find(b"$EndPhysicalNames", start).ok_or_else(|| MshError::Syntax {
        file: file.to_string(),
        at: location(bytes, start, binary),
        message: "$PhysicalNames has no $EndPhysicalNames".into(),
    })?;
    let text = String::from_utf8_lossy(&bytes[start..end]);
    let mut lines = text.lines().enumerate().skip(1);
    let bad = |i: usize, what: &str| MshError::Syntax {
        file: file.to_string(),
        at: format!("line {}", first_line + i),
        message: format!("in $PhysicalNames: {what}"),
    };
    let (i, count) = lines
        .next()
        .ok_or_else(|| bad(1, "the number of names is missing"))?;
    let count: usize = count
        .trim()
        .parse()
        .map_err(|_| bad(i, &format!("expected the number of names, found {count:?}")))?;
    for _ in 0..count {
        let (i, line) = lines
            .next()
            .ok_or_else(|| bad(count + 1, &format!("expected {count} names")))?;
        let expected = "expected `dimension tag \"name\"`";
        let mut parts = line.trim().splitn(3, char::is_whitespace);
        let dim = parts.next().and_then(|s| s.parse::<i32>().ok());
        let tag = parts.next().and_then(|s| s.parse::<i32>().ok());
        let name = parts
            .next()
            .map(str::trim)
            .and_then(|s| s.strip_prefix('"'))
            .and_then(|s| s.strip_suffix('"'));
        match (dim, tag, name) {
            (Some(d), Some(t), Some(n)) => {
                names.insert((d, t), n.to_string());
            }
            _ => return Err(bad(i, &format!("{expected}, found {line:?}"))),
        }
    }
    Ok(names)
}

/// mshio's parse error as a [`MshError::Syntax`]: the innermost error kind, the sections it was
/// in from the outermost inwards, and the line (ASCII) or byte offset (binary).
pub(super) fn syntax_error(
    e: &mshio::MshParserError<&[u8]>,
    bytes: &[u8],
    file: &str,
    binary: bool,
) -> MshError {
    let trace = e.filtered_backtrace();
    let offset = trace
        .first()
        .map_or(0, |(rest, _)| bytes.len().saturating_sub(rest.len()));
    let what = trace
        .iter()
        .find(|(_, k)| k.context().is_none())
        .map_or_else(|| "unexpected content".to_string(), |(_, k)| k.to_string());
    let mut within: Vec<&str> = trace
        .iter()
        .rev()
        .filter_map(|(_, k)| k.context())
        .collect();
    within.dedup();
    let within = if within.is_empty() {
        String::new()
    } else {
        format!(" (in {})", within.join(" › "))
    };
    MshError::Syntax {
        file: file.to_string(),
        at: location(bytes, offset, binary),
        message: format!("{}{within}", what.trim_end_matches('.')),
    }
}
