//! The half-space n·(x − p) ≤ 0 of the mould's `point` p and `normal` n: the shape of a
//! `[[plane]]` (model §2.1, §7.1). Its closest point is the orthogonal projection,
//! p' = x − g n with g = n·(x − p), and its normal n everywhere.

use super::{Entry, EntryError, Frame, MouldMesh, MouldShape};
use crate::keydoc::KeyDoc;
use crate::mesh::dot;
use crate::mould::Projection;

/// The half-space; its plane is the mould's `point` and `normal` ([`Frame`]), which the plane
/// path of the step reads directly.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct HalfSpace;

impl MouldShape for HalfSpace {
    const ABOUT: &'static str = "the half-space on the mould's side of the plane through `point` \
                                 with normal `normal` (into the solid); a `[[plane]]` is this \
                                 shape";
    const KEYS: &'static [KeyDoc] = &[
        KeyDoc::new("point", "[x, y, z]", "m", "a point of the plane at t = 0")
            .admissible("3 finite numbers"),
        KeyDoc::new(
            "normal",
            "[x, y, z]",
            "–",
            "normal of the plane, into the solid; normalised on load",
        )
        .admissible("not all zero"),
    ];

    fn parse(e: &Entry<'_>) -> Result<(Self, Frame), EntryError> {
        let point = e.vector("point")?;
        let normal = e.unit("normal")?;
        Ok((HalfSpace, Frame { point, normal }))
    }

    /// p' = x − g n, g = n·(x − p); the normal n.
    fn project(&self, point: [f64; 3], normal: [f64; 3], x: [f64; 3]) -> Projection {
        let g = dot(normal, std::array::from_fn(|c| x[c] - point[c]));
        Projection {
            point: std::array::from_fn(|c| x[c] - g * normal[c]),
            normal,
        }
    }

    /// None of its own: the outputs draw the square of its plane that covers the body.
    fn drawing(&self) -> MouldMesh {
        MouldMesh::default()
    }
}

#[cfg(test)]
mod tests {
    use super::super::{parse_for_test, Shape};
    use super::*;

    /// The normal is normalised on load; the gap is the signed distance to the plane,
    /// g = n·(x − p) exactly (a 3-4-5 normal: every product exact in binary but the /5).
    #[test]
    fn the_half_space_is_its_plane() {
        let (shape, frame) =
            parse_for_test("half_space", "point = [0, 0, 1]\nnormal = [0, 3, 4]").unwrap();
        assert_eq!(shape, Shape::HalfSpace(HalfSpace));
        assert_eq!(frame.normal, [0.0, 0.6, 0.8]);
        let x = [2.0, 5.0, 1.0];
        let pr = shape.project(frame.point, frame.normal, x);
        assert!((pr.gap(x) - 3.0).abs() < 1e-15, "{}", pr.gap(x));
        assert!((pr.gap(pr.point)).abs() < 1e-15);
        let e = parse_for_test("half_space", "point = [0, 0, 1]\nnormal = [0, 0, 0]");
        assert!(matches!(e, Err(EntryError::Invalid { key, .. }) if key == "normal"));
    }
}
