//! The checks of a triangulated surface before it is used ([`check_surface`]): finite
//! coordinates, vertices welded within [`WELD_TOLERANCE`], no degenerate triangle, no edge of
//! more than two triangles, one orientation throughout, no fold ([`FOLD_TOLERANCE`]); and the
//! count of its open edges.

use crate::mesh::{cross, dot, norm, sub};
pub use crate::tunables::{FOLD_TOLERANCE, WELD_TOLERANCE};
use std::collections::HashMap;

/// What the checks found on an admissible surface.
#[derive(Debug, Clone)]
pub struct Topology {
    /// Per vertex, the index of the vertex it is welded to (the first vertex of the file within
    /// the weld tolerance of it; itself when there is none). Unused vertices keep their own.
    pub id: Vec<u32>,
    /// The edges that belong to one triangle only: the rim of an open surface (0 when closed).
    pub open_edges: usize,
}

/// Checks the triangles (indices into `vertices`) and welds the vertices; refuses, naming the
/// triangles by `element(k)`: a non-finite coordinate, a degenerate triangle (area ≤ 1e-12 × its
/// longest edge², or two of its vertices welded into one), an edge of more than two triangles
/// (not a surface), two triangles that run through their shared edge the same way (inconsistent
/// orientation) and two that fold onto each other.
pub fn check_surface(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    element: &dyn Fn(usize) -> String,
) -> Result<Topology, String> {
    for (k, t) in triangles.iter().enumerate() {
        for (j, &v) in t.iter().enumerate() {
            let Some(x) = vertices.get(v as usize) else {
                return Err(format!(
                    "{} refers to a vertex that does not exist",
                    element(k)
                ));
            };
            if !x.iter().all(|c| c.is_finite()) {
                return Err(format!(
                    "{} has a non-finite coordinate at its vertex {j}: {x:?} (every coordinate, times the mould's `scale`, must be a finite number)",
                    element(k)
                ));
            }
        }
    }
    let id = weld(vertices, triangles)?;
    let at = |v: u32| vertices[id[v as usize] as usize];
    // Directed edge (a, b) → the triangle that runs through it; undirected edge → its triangles.
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    let mut uses: HashMap<(u32, u32), (usize, Option<usize>)> = HashMap::new();
    for (k, t) in triangles.iter().enumerate() {
        let [a, b, c] = t.map(at);
        let area2 = norm(cross(sub(b, a), sub(c, a)));
        let longest = [
            dot(sub(b, a), sub(b, a)),
            dot(sub(c, b), sub(c, b)),
            dot(sub(a, c), sub(a, c)),
        ]
        .into_iter()
        .fold(0.0f64, f64::max);
        let v = t.map(|v| id[v as usize]);
        if v[0] == v[1] || v[1] == v[2] || v[0] == v[2] || !(area2 > 1e-12 * longest) {
            return Err(format!(
                "{} is degenerate (zero area, or two of its vertices within the weld tolerance of each other, {WELD_TOLERANCE:e} of the surface's size): its orientation is undefined",
                element(k)
            ));
        }
        for e in 0..3 {
            let (p, q) = (v[e], v[(e + 1) % 3]);
            if let Some(j) = directed.insert((p, q), k) {
                return Err(format!(
                    "{} and {} run through their shared edge the same way: the surface's orientation is inconsistent (one of them is flipped; the normal (b − a) × (c − a) must point out of the mould)",
                    element(j),
                    element(k)
                ));
            }
            let entry = uses.entry((p.min(q), p.max(q))).or_insert((k, None));
            if entry.0 != k {
                if entry.1.is_some() {
                    return Err(format!(
                        "{} shares an edge with two other triangles: not a surface (an edge belongs to at most two triangles)",
                        element(k)
                    ));
                }
                entry.1 = Some(k);
            }
        }
    }
    let unit_normal = |k: usize| {
        let [a, b, c] = triangles[k].map(at);
        let n = cross(sub(b, a), sub(c, a));
        let l = norm(n);
        n.map(|x| x / l)
    };
    // The folds, in the order of the triangles (the message names the first pair).
    let mut folds: Vec<(usize, usize, f64)> = (uses.values())
        .filter_map(|&(k, other)| {
            let j = other?;
            let cos = dot(unit_normal(k), unit_normal(j));
            (cos <= -1.0 + FOLD_TOLERANCE).then_some((k, j, cos))
        })
        .collect();
    folds.sort_by_key(|&(k, j, _)| (k, j));
    if let Some(&(k, j, cos)) = folds.first() {
        return Err(format!(
            "{} and {} share an edge and face opposite ways (n₁·n₂ = {cos:.6}): the surface folds back onto itself there, where the normal of the closest point (the sum of the two) is zero and the gap undefined; a mould's surface must not fold back (n₁·n₂ > −1 + {FOLD_TOLERANCE:e}){}",
            element(k),
            element(j),
            if folds.len() > 1 {
                format!("; {} folded edges in all", folds.len())
            } else {
                String::new()
            }
        ));
    }
    let open_edges = uses.values().filter(|u| u.1.is_none()).count();
    Ok(Topology { id, open_edges })
}

/// Per vertex, the first vertex of the file within [`WELD_TOLERANCE`] × the diagonal of the
/// used vertices' bounding box (itself when none). A grid of cells of the tolerance's size
/// holds the vertices kept so far; a vertex looks in its cell and the 26 around it.
fn weld(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> Result<Vec<u32>, String> {
    let mut used = vec![false; vertices.len()];
    for &v in triangles.iter().flatten() {
        used[v as usize] = true;
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for (x, _) in vertices.iter().zip(&used).filter(|(_, &u)| u) {
        for c in 0..3 {
            lo[c] = lo[c].min(x[c]);
            hi[c] = hi[c].max(x[c]);
        }
    }
    let extent = [0, 1, 2].map(|c| hi[c] - lo[c]);
    // The diagonal without overflow in the squares.
    let big = extent.into_iter().fold(0.0f64, f64::max);
    let diagonal = if big > 0.0 {
        big * norm(extent.map(|e| e / big))
    } else {
        0.0
    };
    if !diagonal.is_finite() {
        return Err(format!(
            "the surface's extent {extent:?} is not a finite length: its coordinates, times the mould's `scale`, must stay well within ±1e308"
        ));
    }
    let tol = WELD_TOLERANCE * diagonal;
    let mut id: Vec<u32> = (0..vertices.len() as u32).collect();
    if !(tol > 0.0) {
        // Every used vertex at one point: each triangle is degenerate, as the caller says.
        return Ok(id);
    }
    let cell = |x: &[f64; 3]| [0, 1, 2].map(|c| ((x[c] - lo[c]) / tol).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    for (i, x) in vertices.iter().enumerate() {
        if !used[i] {
            continue;
        }
        let home = cell(x);
        let mut found: Option<u32> = None;
        for d in 0..27 {
            let key = [d % 3 - 1, d / 3 % 3 - 1, d / 9 - 1].map(|o| o as i64);
            let key = [0, 1, 2].map(|c| home[c].saturating_add(key[c]));
            for &r in grid.get(&key).into_iter().flatten() {
                let y = &vertices[r as usize];
                if norm(sub(*x, *y)) <= tol && found.is_none_or(|f| r < f) {
                    found = Some(r);
                }
            }
        }
        match found {
            Some(r) => id[i] = r,
            None => grid.entry(home).or_default().push(i as u32),
        }
    }
    Ok(id)
}
