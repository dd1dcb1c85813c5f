//! A ball of `radius` r about `centre` c (model §7.1): the closest point of its surface is
//! p = c + r n with the outward normal n = (x − c)/|x − c| (any unit vector at the centre:
//! +z), so the gap is g = |x − c| − r.

use super::{unit_or, Entry, EntryError, Frame, MouldMesh, MouldShape};
use crate::interface::family::Range;
use crate::keydoc::KeyDoc;
use crate::mould::Projection;
pub use crate::tunables::{SPHERE_MERIDIANS, SPHERE_RINGS};

/// A ball, centre and radius [m].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Sphere {
    pub centre: [f64; 3],
    pub radius: f64,
}

impl MouldShape for Sphere {
    const ABOUT: &'static str = "a ball of `radius` about `centre`";
    const KEYS: &'static [KeyDoc] = &[
        KeyDoc::new("centre", "[x, y, z]", "m", "centre at t = 0"),
        KeyDoc::new("radius", "number", "m", "radius").range(Range::above(0.0)),
    ];

    fn parse(e: &Entry<'_>) -> Result<(Self, Frame), EntryError> {
        let centre = e.vector("centre")?;
        let radius = e.number("radius")?;
        Ok((Sphere { centre, radius }, Frame::at(centre)))
    }

    /// p = c + r n, n = (x − c)/|x − c|.
    fn project(&self, _: [f64; 3], _: [f64; 3], x: [f64; 3]) -> Projection {
        let (centre, radius) = (self.centre, self.radius);
        let q: [f64; 3] = std::array::from_fn(|c| x[c] - centre[c]);
        let n = unit_or(q, [0.0, 0.0, 1.0]);
        Projection {
            point: std::array::from_fn(|c| centre[c] + radius * n[c]),
            normal: n,
        }
    }

    /// A UV sphere about z ([`SPHERE_RINGS`] × [`SPHERE_MERIDIANS`], vertices on the sphere).
    fn drawing(&self) -> MouldMesh {
        let (centre, radius) = (self.centre, self.radius);
        let mut mesh = MouldMesh::default();
        let (nr, nm) = (SPHERE_RINGS, SPHERE_MERIDIANS);
        let mut push = |n: [f64; 3]| {
            mesh.vertices
                .push(std::array::from_fn(|c| centre[c] + radius * n[c]));
            mesh.normals.push(n);
        };
        push([0.0, 0.0, 1.0]);
        for r in 1..nr {
            let theta = std::f64::consts::PI * r as f64 / nr as f64;
            for k in 0..nm {
                let phi = 2.0 * std::f64::consts::PI * k as f64 / nm as f64;
                push([
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ]);
            }
        }
        push([0.0, 0.0, -1.0]);
        let (nm32, south) = (nm as u32, (1 + (nr - 1) * nm) as u32);
        let ring = |r: u32, k: u32| 1 + r * nm32 + k % nm32;
        for k in 0..nm32 {
            mesh.triangles.push([0, ring(0, k), ring(0, k + 1)]);
            for r in 0..(nr as u32 - 2) {
                let (a, b) = (ring(r, k), ring(r, k + 1));
                let (c, d) = (ring(r + 1, k), ring(r + 1, k + 1));
                mesh.triangles.extend([[a, c, d], [a, d, b]]);
            }
            let last = nr as u32 - 2;
            mesh.triangles
                .push([south, ring(last, k + 1), ring(last, k)]);
        }
        mesh
    }
}

#[cfg(test)]
mod tests {
    use super::super::parse_for_test;
    use super::*;

    /// g = |x − c| − r outside and inside (a 3-4-5 offset: exact), and a radius ≤ 0 refused.
    #[test]
    fn the_gap_is_the_distance_to_the_sphere() {
        let (shape, frame) = parse_for_test("sphere", "centre = [1, 1, 1]\nradius = 2").unwrap();
        assert_eq!(frame.point, [1.0, 1.0, 1.0]);
        let x = [4.0, 5.0, 1.0];
        assert_eq!(shape.project(frame.point, frame.normal, x).gap(x), 3.0);
        let x = [1.0, 1.0, 0.5];
        let pr = shape.project(frame.point, frame.normal, x);
        assert_eq!((pr.normal, pr.gap(x)), ([0.0, 0.0, -1.0], -1.5));
        let e = parse_for_test("sphere", "centre = [1, 1, 1]\nradius = 0").unwrap_err();
        assert!(matches!(e, EntryError::Invalid { key, .. } if key == "radius"));
    }
}
