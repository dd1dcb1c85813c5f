//! An axis-aligned box (at t = 0) of full edge lengths `size` about `centre` (model §7.1): the
//! exact closest point of its boundary, with n = (x − p)/|x − p| in an edge or corner region.

use super::{unit_or, Entry, EntryError, Frame, MouldMesh, MouldShape};
use crate::interface::family::Range;
use crate::keydoc::KeyDoc;
use crate::mould::Projection;

/// An axis-aligned box, centre and half-sizes [m].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Box {
    pub centre: [f64; 3],
    pub half_size: [f64; 3],
}

impl MouldShape for Box {
    const ABOUT: &'static str =
        "an axis-aligned box (at t = 0) of full edge lengths `size` about `centre`";
    const KEYS: &'static [KeyDoc] = &[
        KeyDoc::new("centre", "[x, y, z]", "m", "centre at t = 0"),
        KeyDoc::new(
            "size",
            "[x, y, z]",
            "m",
            "full edge lengths, axis-aligned at t = 0",
        )
        .range(Range::above(0.0)),
    ];

    fn parse(e: &Entry<'_>) -> Result<(Self, Frame), EntryError> {
        let size = e.vector("size")?;
        let centre = e.vector("centre")?;
        let half_size = size.map(|c| 0.5 * c);
        Ok((Box { centre, half_size }, Frame::at(centre)))
    }

    /// p = c + [`project_box`](x − c).
    fn project(&self, _: [f64; 3], _: [f64; 3], x: [f64; 3]) -> Projection {
        let centre = self.centre;
        let q: [f64; 3] = std::array::from_fn(|c| x[c] - centre[c]);
        let (p, n) = project_box(q, self.half_size);
        Projection {
            point: std::array::from_fn(|c| centre[c] + p[c]),
            normal: n,
        }
    }

    /// 6 faces of 4 vertices (12 triangles, flat normals).
    fn drawing(&self) -> MouldMesh {
        let (centre, half_size) = (self.centre, self.half_size);
        let mut mesh = MouldMesh::default();
        // Each face: its normal axis i, sign s, and two tangent axes (j, k) with
        // e_j × e_k = s e_i, so the quad (−−, +−, ++, −+) in (j, k) winds outwards.
        for i in 0..3 {
            for s in [1.0, -1.0] {
                let (j, k) = if s > 0.0 {
                    ((i + 1) % 3, (i + 2) % 3)
                } else {
                    ((i + 2) % 3, (i + 1) % 3)
                };
                let base = mesh.vertices.len() as u32;
                for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    let mut x = centre;
                    x[i] += s * half_size[i];
                    x[j] += a * half_size[j];
                    x[k] += b * half_size[k];
                    mesh.vertices.push(x);
                    let mut n = [0.0; 3];
                    n[i] = s;
                    mesh.normals.push(n);
                }
                mesh.triangles
                    .extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
            }
        }
        mesh
    }
}

/// Closest point of the boundary of the box |qᵢ| ≤ hᵢ to q, and the outward normal there.
/// Outside: p = clamp(q), n = (q − p)/|q − p| (a face, edge or corner region). Inside or on it:
/// the nearest face (smallest hᵢ − |qᵢ|), n = ±eᵢ.
fn project_box(q: [f64; 3], h: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let p: [f64; 3] = std::array::from_fn(|c| q[c].clamp(-h[c], h[c]));
    let d: [f64; 3] = std::array::from_fn(|c| q[c] - p[c]);
    if d != [0.0; 3] {
        return (p, unit_or(d, [0.0; 3]));
    }
    let i = (0..3)
        .min_by(|&a, &b| (h[a] - q[a].abs()).total_cmp(&(h[b] - q[b].abs())))
        .unwrap_or(0);
    let s = if q[i] < 0.0 { -1.0 } else { 1.0 };
    let mut p = q;
    p[i] = s * h[i];
    let mut n = [0.0; 3];
    n[i] = s;
    (p, n)
}

#[cfg(test)]
mod tests {
    use super::super::{parse_for_test, Shape};
    use super::*;

    /// Outside, on an edge region and inside, against the values worked out by hand (gap =
    /// signed distance to the surface); a zero edge refused, naming the component.
    #[test]
    fn the_gap_is_the_signed_distance_to_the_box() {
        let bx = Shape::Box(Box {
            centre: [0.0; 3],
            half_size: [1.0, 2.0, 3.0],
        });
        let pr = bx.project([0.0; 3], [0.0; 3], [2.0, 0.5, 0.0]);
        assert_eq!((pr.point, pr.normal), ([1.0, 0.5, 0.0], [1.0, 0.0, 0.0]));
        let pr = bx.project([0.0; 3], [0.0; 3], [4.0, 6.0, 0.0]);
        assert_eq!(pr.point, [1.0, 2.0, 0.0]);
        assert!((pr.gap([4.0, 6.0, 0.0]) - 5.0).abs() < 1e-15);
        let pr = bx.project([0.0; 3], [0.0; 3], [0.0, 1.5, 0.0]);
        assert_eq!((pr.point, pr.normal), ([0.0, 2.0, 0.0], [0.0, 1.0, 0.0]));
        assert_eq!(pr.gap([0.0, 1.5, 0.0]), -0.5);
        let (parsed, _) = parse_for_test("box", "centre = [0, 0, 0]\nsize = [2, 4, 6]").unwrap();
        assert_eq!(parsed, bx);
        let e = parse_for_test("box", "centre = [0, 0, 0]\nsize = [2, 0, 6]").unwrap_err();
        assert!(matches!(e, EntryError::Invalid { key, .. } if key == "size[1]"));
    }
}
