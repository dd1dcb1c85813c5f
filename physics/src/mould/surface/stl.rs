//! STL files, ASCII or binary, read into triangles ([`read_stl`]).

use super::SurfaceError;
use crate::mesh::{cross, dot, sub};

/// The triangles of an STL file (binary when it is not ASCII `solid … facet`), checked with the
/// file's facet normals: a written normal (non-zero) that opposes the vertex order's normal is
/// refused. Returns (vertices, triangles), three vertices per triangle.
pub fn read_stl(bytes: &[u8], file: &str) -> Result<Triangles, SurfaceError> {
    let err = |message: String| SurfaceError {
        file: file.to_string(),
        message,
    };
    let text = std::str::from_utf8(bytes).ok();
    let ascii = text.filter(|t| t.trim_start().starts_with("solid") && t.contains("facet"));
    let facets: Vec<([f64; 3], [[f64; 3]; 3])> = match ascii {
        Some(t) => read_ascii_stl(t).map_err(err)?,
        None => read_binary_stl(bytes).map_err(err)?,
    };
    if facets.is_empty() {
        return Err(err("not an STL file with triangles (no facet found)".into()));
    }
    let mut vertices = Vec::with_capacity(3 * facets.len());
    for (k, (n, v)) in facets.iter().enumerate() {
        if !n.iter().all(|c| c.is_finite()) {
            return Err(err(format!(
                "facet {k}: its written normal {n:?} is not a finite vector (write the outward unit normal, or 0 0 0)"
            )));
        }
        let computed = cross(sub(v[1], v[0]), sub(v[2], v[0]));
        if dot(*n, computed) < 0.0 {
            return Err(err(format!(
                "facet {k}: its written normal {n:?} opposes the normal of its vertex order (counter-clockwise seen from outside): inconsistent orientation"
            )));
        }
        vertices.extend_from_slice(v);
    }
    let triangles = (0..facets.len() as u32)
        .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
        .collect();
    Ok((vertices, triangles))
}

type Facet = ([f64; 3], [[f64; 3]; 3]);

/// Vertices and triangles (indices into the vertices).
pub type Triangles = (Vec<[f64; 3]>, Vec<[u32; 3]>);

fn read_ascii_stl(text: &str) -> Result<Vec<Facet>, String> {
    let mut out = Vec::new();
    let mut words = text.split_whitespace().enumerate().peekable();
    // The line of the i-th word, for messages.
    let line_of = |i: usize| {
        let mut n = 0;
        let at = text
            .char_indices()
            .filter(|&(k, c)| {
                !c.is_whitespace() && (k == 0 || text[..k].ends_with(char::is_whitespace))
            })
            .map(|(k, _)| k)
            .find(|_| {
                n += 1;
                n > i
            })
            .unwrap_or(text.len());
        1 + text[..at].matches('\n').count()
    };
    let triple = |words: &mut std::iter::Peekable<_>,
                  what: &str,
                  facet: usize|
     -> Result<[f64; 3], String> {
        let mut v = [0.0; 3];
        for c in &mut v {
            let (i, w): (usize, &str) = words
                .next()
                .ok_or_else(|| format!("ASCII STL ends inside the {what} of facet {facet}"))?;
            *c = w.parse().map_err(|_| {
                format!(
                    "ASCII STL line {}: expected a number in the {what} of facet {facet}, found {w:?}",
                    line_of(i)
                )
            })?;
        }
        Ok(v)
    };
    while let Some((_, w)) = words.next() {
        if w != "facet" {
            continue;
        }
        match words.next() {
            Some((_, "normal")) => {}
            _ => {
                return Err(format!(
                    "ASCII STL facet {}: expected `facet normal`",
                    out.len()
                ))
            }
        }
        let n = triple(&mut words, "facet normal", out.len())?;
        let mut v = [[0.0; 3]; 3];
        let mut k = 0;
        while k < 3 {
            match words.next() {
                Some((_, "vertex")) => {
                    v[k] = triple(&mut words, "vertex", out.len())?;
                    k += 1;
                }
                Some((_, "endfacet")) | None => {
                    return Err(format!(
                        "ASCII STL facet {}: fewer than 3 vertices",
                        out.len()
                    ))
                }
                _ => {}
            }
        }
        out.push((n, v));
    }
    Ok(out)
}

fn read_binary_stl(bytes: &[u8]) -> Result<Vec<Facet>, String> {
    if bytes.len() < 84 {
        return Err(format!(
            "not an STL file: {} bytes, neither ASCII (`solid … facet …`) nor a binary STL (80-byte header and a triangle count)",
            bytes.len()
        ));
    }
    let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    let expected = 84 + 50 * count;
    if bytes.len() != expected {
        return Err(format!(
            "not an STL file: a binary STL with {count} triangles has {expected} bytes, this file has {}",
            bytes.len()
        ));
    }
    let f =
        |o: usize| f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]) as f64;
    let v3 = |o: usize| [f(o), f(o + 4), f(o + 8)];
    Ok((0..count)
        .map(|k| {
            let o = 84 + 50 * k;
            (v3(o), [v3(o + 12), v3(o + 24), v3(o + 36)])
        })
        .collect())
}
