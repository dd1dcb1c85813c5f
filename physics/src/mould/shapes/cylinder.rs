//! A capped cylinder of `radius` and `length` along `axis` about `centre` (model §7.1): the
//! exact closest point of its side, caps or rims, with n = (x − p)/|x − p| beyond a rim.

use super::{unit_or, Entry, EntryError, Frame, MouldMesh, MouldShape};
use crate::interface::family::Range;
use crate::keydoc::KeyDoc;
use crate::mesh::{cross, dot, norm};
use crate::mould::Projection;
pub use crate::tunables::CYLINDER_SEGMENTS;

/// A capped cylinder: centre of its axis, unit axis, radius and half-length [m].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Cylinder {
    pub centre: [f64; 3],
    pub axis: [f64; 3],
    pub radius: f64,
    pub half_length: f64,
}

impl MouldShape for Cylinder {
    const ABOUT: &'static str =
        "a capped cylinder of `radius` and `length` along `axis` about `centre`";
    const KEYS: &'static [KeyDoc] = &[
        KeyDoc::new("centre", "[x, y, z]", "m", "centre of the axis at t = 0"),
        KeyDoc::new("axis", "[x, y, z]", "–", "axis; normalised on load")
            .admissible("not all zero"),
        KeyDoc::new("radius", "number", "m", "radius").range(Range::above(0.0)),
        KeyDoc::new("length", "number", "m", "length (capped)").range(Range::above(0.0)),
    ];

    fn parse(e: &Entry<'_>) -> Result<(Self, Frame), EntryError> {
        let centre = e.vector("centre")?;
        let shape = Cylinder {
            centre,
            axis: e.unit("axis")?,
            radius: e.number("radius")?,
            half_length: 0.5 * e.number("length")?,
        };
        Ok((shape, Frame::at(centre)))
    }

    /// With z = a·q and ρ = q − z a (q = x − c), beyond the rim (|z| > l, |ρ| > r) the rim
    /// point and n = (x − p)/|x − p|; beyond a cap only, the cap (n = ±a); beyond the side
    /// only, the side (n = ρ/|ρ|); inside, the nearer of the cap and the side.
    fn project(&self, _: [f64; 3], _: [f64; 3], x: [f64; 3]) -> Projection {
        let (centre, a, r, l) = (self.centre, self.axis, self.radius, self.half_length);
        let q: [f64; 3] = std::array::from_fn(|c| x[c] - centre[c]);
        let z = dot(q, a);
        let rho: [f64; 3] = std::array::from_fn(|c| q[c] - z * a[c]);
        // A radial direction even on the axis: any unit vector ⊥ a.
        let any_perp = {
            let t = if a[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            };
            let s = dot(t, a);
            unit_or(std::array::from_fn(|c| t[c] - s * a[c]), [0.0; 3])
        };
        let er = unit_or(rho, any_perp);
        let rr = norm(rho);
        let s = if z < 0.0 { -1.0 } else { 1.0 };
        let (dz, dr) = (z.abs() - l, rr - r);
        let at = |zz: f64, radial: f64| -> [f64; 3] {
            std::array::from_fn(|c| centre[c] + zz * a[c] + radial * er[c])
        };
        let (point, normal) = if dz > 0.0 && dr > 0.0 {
            let p = at(s * l, r);
            (p, unit_or(std::array::from_fn(|c| x[c] - p[c]), er))
        } else if dz > 0.0 || (dr <= 0.0 && dz >= dr) {
            (at(s * l, rr), a.map(|c| s * c))
        } else {
            (at(z, r), er)
        };
        Projection { point, normal }
    }

    /// Its side ([`CYLINDER_SEGMENTS`] quads, radial normals) and two fans for the caps (axial
    /// normals).
    fn drawing(&self) -> MouldMesh {
        let (centre, radius) = (self.centre, self.radius);
        let mut mesh = MouldMesh::default();
        let a = super::normalise(self.axis);
        let e1 = super::normalise(cross(
            a,
            if a[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            },
        ));
        let e2 = cross(a, e1);
        let ns = CYLINDER_SEGMENTS as u32;
        let radial = |k: u32| -> [f64; 3] {
            let phi = 2.0 * std::f64::consts::PI * k as f64 / ns as f64;
            std::array::from_fn(|c| phi.cos() * e1[c] + phi.sin() * e2[c])
        };
        let at = |z: f64, r: f64, n: [f64; 3]| -> [f64; 3] {
            std::array::from_fn(|c| centre[c] + z * a[c] + r * n[c])
        };
        let l = self.half_length;
        // Side: vertices 2k (bottom, z = −l) and 2k + 1 (top).
        for k in 0..ns {
            let n = radial(k);
            mesh.vertices.extend([at(-l, radius, n), at(l, radius, n)]);
            mesh.normals.extend([n, n]);
        }
        for k in 0..ns {
            let (b0, t0) = (2 * k, 2 * k + 1);
            let (b1, t1) = (2 * ((k + 1) % ns), 2 * ((k + 1) % ns) + 1);
            mesh.triangles.extend([[b0, b1, t1], [b0, t1, t0]]);
        }
        // Caps: a centre and a ring each, normal ±a.
        for s in [1.0, -1.0] {
            let n = a.map(|c| s * c);
            let base = mesh.vertices.len() as u32;
            mesh.vertices.push(at(s * l, 0.0, n));
            mesh.normals.push(n);
            for k in 0..ns {
                mesh.vertices.push(at(s * l, radius, radial(k)));
                mesh.normals.push(n);
            }
            for k in 0..ns {
                let (p, q) = (base + 1 + k, base + 1 + (k + 1) % ns);
                mesh.triangles
                    .push(if s > 0.0 { [base, p, q] } else { [base, q, p] });
            }
        }
        mesh
    }
}

#[cfg(test)]
mod tests {
    use super::super::parse_for_test;
    use super::*;

    /// Beside the side, beyond a cap, beyond a rim and inside, against the values worked out
    /// by hand (gap = signed distance to the surface); a zero axis refused.
    #[test]
    fn the_gap_is_the_signed_distance_to_the_cylinder() {
        let (cy, f) = parse_for_test(
            "cylinder",
            "centre = [0, 0, 0]\naxis = [0, 0, 2]\nradius = 1\nlength = 4",
        )
        .unwrap();
        let gap = |x: [f64; 3]| cy.project(f.point, f.normal, x).gap(x);
        assert_eq!(gap([3.0, 0.0, 0.5]), 2.0);
        let x = [0.0, 0.5, -2.5];
        let pr = cy.project(f.point, f.normal, x);
        assert_eq!((pr.normal, pr.gap(x)), ([0.0, 0.0, -1.0], 0.5));
        assert!((gap([4.0, 0.0, 6.0]) - 5.0).abs() < 1e-15);
        assert!((gap([0.0, 0.9, 0.0]) + 0.1).abs() < 1e-15);
        let e = parse_for_test(
            "cylinder",
            "centre = [0, 0, 0]\naxis = [0, 0, 0]\nradius = 1\nlength = 4",
        )
        .unwrap_err();
        assert!(matches!(e, EntryError::Invalid { key, .. } if key == "axis"));
    }
}
