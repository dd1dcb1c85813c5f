//! The mould shapes, one file each (model §7.1).
//!
//! `physics/build.rs` lists the files of this folder and writes the `mod` lines and one
//! `shapes!` line per file; the macro below turns that list into [`Shape`] (one variant per
//! shape, holding its data: a projection is one `match` away, no indirection) and [`SHAPES`]
//! (the table the scene loader and the scene reference read). A shape's file `<key>.rs` holds
//! everything about it: a type `<Key>` (CamelCase) implementing [`MouldShape`] — its data, the
//! keys of `[[mould]]` it takes with their documentation, their parse and validation, its
//! closest point and outward normal, its drawing — and its unit test. The file name is the
//! value of `shape` in the scene. To add a shape, add its file: nothing else is edited.
//!
//! A registry generated from the folder rather than a trait object: the step projects every
//! node on every mould each step, so the shapes stay an enum (static dispatch, inlined, the
//! same code as the hand-written `match` it replaces), and the law families already work this
//! way, so the two seams read alike.

use super::Projection;
use crate::keydoc::{show, KeyDoc};
use crate::mesh::norm;

/// What a shape's file implements (module docs). The scene key is the file's name.
pub trait MouldShape: Sized + Into<Shape> {
    /// What the mould is, a phrase for the scene reference (`a ball of \`radius\` about
    /// \`centre\``).
    const ABOUT: &'static str;
    /// The keys of `[[mould]]` this shape takes besides the common ones (`name`, `shape`,
    /// `pivot`, `velocity`, `angular_velocity`), documented; any other key is refused.
    const KEYS: &'static [KeyDoc];

    /// The shape from its keys, validated (lengths > 0, axes non-zero, normalised), and the
    /// mould's frame at t = 0 ([`Frame`]).
    fn parse(e: &Entry<'_>) -> Result<(Self, Frame), EntryError>;

    /// Closest point p of the shape's surface to x and the outward unit normal n there, in the
    /// mould's frame at t = 0 (model §7.1); `point`, `normal` are the mould's ([`Frame`]).
    fn project(&self, point: [f64; 3], normal: [f64; 3], x: [f64; 3]) -> Projection;

    /// The shape's surface as triangles at t = 0 ([`MouldMesh`]); empty if it has no finite
    /// drawing of its own (a half-space: the outputs draw a square around the body).
    fn drawing(&self) -> MouldMesh;
}

/// The mould's `point` and `normal` ([`super::Mould`]): a half-space's plane; for another
/// shape its reference point (the default pivot) and a zero normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub point: [f64; 3],
    pub normal: [f64; 3],
}

impl Frame {
    /// A shape about `centre`: the frame's point, no normal.
    pub fn at(centre: [f64; 3]) -> Self {
        Frame {
            point: centre,
            normal: [0.0; 3],
        }
    }
}

/// A mould's surface as triangles, in its frame at t = 0, wound so that (b − a) × (c − a)
/// points out of the mould (into the solid), with a unit normal per vertex.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MouldMesh {
    pub vertices: Vec<[f64; 3]>,
    pub normals: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

/// Why a shape's keys were refused; `key` is relative to the `[[mould]]` entry (`radius`,
/// `size[1]`), the scene loader adds the entry's path and the file.
#[derive(Debug, Clone, PartialEq)]
pub enum EntryError {
    /// A key whose value is not admissible: the value as written, what is admissible.
    Invalid {
        key: String,
        value: String,
        reason: String,
    },
    /// A key the shape needs.
    Missing { key: String, reason: String },
}

/// The keys of one `[[mould]]` entry that are its shape's, as the scene wrote them (the common
/// keys taken out), and what a shape's parse needs to read them.
pub struct Entry<'a> {
    /// The shape's key (`sphere`).
    pub shape: &'static str,
    /// The keys the shape takes ([`MouldShape::KEYS`]).
    pub keys: &'static [KeyDoc],
    /// The shape's keys as written.
    pub table: &'a toml::Table,
    /// Reads a file the scene names, relative to the scene file's directory.
    pub read: &'a dyn Fn(&str) -> std::io::Result<Vec<u8>>,
}

impl Entry<'_> {
    /// The value of `key`, if given.
    pub fn get(&self, key: &str) -> Option<&toml::Value> {
        self.table.get(key)
    }

    /// `key` = `value` is not admissible.
    pub fn invalid(&self, key: &str, value: String, reason: impl Into<String>) -> EntryError {
        EntryError::Invalid {
            key: key.to_string(),
            value,
            reason: reason.into(),
        }
    }

    /// `key` is missing, for `reason`.
    pub fn missing_because(&self, key: &str, reason: impl Into<String>) -> EntryError {
        EntryError::Missing {
            key: key.to_string(),
            reason: reason.into(),
        }
    }

    /// `key` is missing: the shape needs all its keys.
    pub fn missing(&self, key: &str) -> EntryError {
        let keys: Vec<&str> = self.keys.iter().map(|k| k.key).collect();
        self.missing_because(
            key,
            format!("a {} mould needs {}", self.shape, keys.join(", ")),
        )
    }

    /// The documentation of `key` (a key of [`MouldShape::KEYS`]).
    fn doc(&self, key: &str) -> &'static KeyDoc {
        (self.keys.iter().find(|k| k.key == key))
            .unwrap_or_else(|| panic!("`{key}` is not a key of the {} shape", self.shape))
    }

    /// A TOML number (an integer is accepted as a real).
    fn as_number(&self, key: &str, v: &toml::Value) -> Result<f64, EntryError> {
        match v {
            toml::Value::Float(x) => Ok(*x),
            toml::Value::Integer(i) => Ok(*i as f64),
            other => Err(self.invalid(key, show(other), "must be a number")),
        }
    }

    /// The number `key`, if given, admitted by its range ([`KeyDoc::admits`]).
    pub fn number_opt(&self, key: &str) -> Result<Option<f64>, EntryError> {
        let Some(v) = self.get(key) else {
            return Ok(None);
        };
        let x = self.as_number(key, v)?;
        let doc = self.doc(key);
        if !doc.admits(x) {
            return Err(self.invalid(key, show(v), doc.must()));
        }
        Ok(Some(x))
    }

    /// The number `key` (required), admitted by its range.
    pub fn number(&self, key: &str) -> Result<f64, EntryError> {
        self.number_opt(key)?.ok_or_else(|| self.missing(key))
    }

    /// The 3-vector `key` (required): 3 numbers, each admitted by the key's range if it has one
    /// (`key[i]` in the message).
    pub fn vector(&self, key: &str) -> Result<[f64; 3], EntryError> {
        let v = self.get(key).ok_or_else(|| self.missing(key))?;
        let items = match v {
            toml::Value::Array(items) if items.len() == 3 => items,
            toml::Value::Array(items) => {
                return Err(self.invalid(
                    key,
                    show(v),
                    format!(
                        "invalid length {}, expected an array of length 3 ([x, y, z])",
                        items.len()
                    ),
                ))
            }
            other => {
                return Err(self.invalid(key, show(other), "must be an array [x, y, z]"));
            }
        };
        let doc = self.doc(key);
        let mut out = [0.0; 3];
        for (c, item) in items.iter().enumerate() {
            let at = format!("{key}[{c}]");
            out[c] = self.as_number(&at, item)?;
            if doc.range.is_some() && !doc.admits(out[c]) {
                return Err(self.invalid(&at, show(item), doc.must()));
            }
        }
        Ok(out)
    }

    /// The unit vector along the 3-vector `key` (required; a normal or an axis), which must
    /// not be zero: v/|v|, scaled by its largest component first so that neither tiny nor huge
    /// vectors under- or overflow.
    pub fn unit(&self, key: &str) -> Result<[f64; 3], EntryError> {
        let v = self.vector(key)?;
        let scale = v.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        if scale == 0.0 {
            return Err(self.invalid(
                key,
                format!("{v:?}"),
                "must be a non-zero vector (it is normalised on load)",
            ));
        }
        let n = v.map(|c| c / scale);
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        Ok(n.map(|c| c / len))
    }

    /// The string `key`, if given.
    pub fn string_opt(&self, key: &str) -> Result<Option<&str>, EntryError> {
        match self.get(key) {
            None => Ok(None),
            Some(toml::Value::String(s)) => Ok(Some(s)),
            Some(other) => Err(self.invalid(key, show(other), "must be a string")),
        }
    }
}

/// One row of [`SHAPES`]: a shape's key, documentation and parse.
#[derive(Clone, Copy)]
pub struct ShapeSpec {
    /// The value of `shape` (the file's name).
    pub key: &'static str,
    pub about: &'static str,
    pub keys: &'static [KeyDoc],
    /// [`MouldShape::parse`], as a [`Shape`].
    pub parse: fn(&Entry<'_>) -> Result<(Shape, Frame), EntryError>,
}

impl ShapeSpec {
    const fn of<S: MouldShape>(key: &'static str) -> Self {
        ShapeSpec {
            key,
            about: S::ABOUT,
            keys: S::KEYS,
            parse: |e| S::parse(e).map(|(s, f)| (s.into(), f)),
        }
    }
}

/// Builds [`Shape`], its dispatch and [`SHAPES`] from `index Type => module "key"` lines.
macro_rules! shapes {
    ($($index:literal $shape:ident => $module:ident $key:literal,)*) => {
        /// The shape of a mould in its frame at t = 0, one variant per file of this folder. The
        /// mould is the solid region: the body lies outside it (on the side its outward normal
        /// points to).
        #[derive(Debug, Clone, PartialEq, serde::Serialize)]
        #[serde(rename_all = "snake_case", tag = "shape")]
        pub enum Shape {
            $($shape($module::$shape),)*
        }

        $(impl From<$module::$shape> for Shape {
            fn from(shape: $module::$shape) -> Self {
                Shape::$shape(shape)
            }
        })*

        /// Every shape's row, in the order of the file names.
        pub static SHAPES: &[ShapeSpec] = &[$(ShapeSpec::of::<$module::$shape>($key),)*];

        /// The values of `shape`, in the order of [`SHAPES`].
        pub const SHAPE_KEYS: &[&str] = &[$($key,)*];

        impl Shape {
            /// The shape's row of [`SHAPES`].
            pub fn spec(&self) -> &'static ShapeSpec {
                match self {
                    $(Shape::$shape(_) => &SHAPES[$index],)*
                }
            }

            /// [`MouldShape::project`] of the shape.
            #[inline]
            pub fn project(&self, point: [f64; 3], normal: [f64; 3], x: [f64; 3]) -> Projection {
                match self {
                    $(Shape::$shape(s) => s.project(point, normal, x),)*
                }
            }

            /// [`MouldShape::drawing`] of the shape.
            pub fn drawing(&self) -> MouldMesh {
                match self {
                    $(Shape::$shape(s) => s.drawing(),)*
                }
            }
        }
    };
}

include!(concat!(env!("OUT_DIR"), "/mould_shapes.rs"));

const _: () = assert!(
    crate::interface::laws::same_str(GENERATED_IN, env!("CARGO_MANIFEST_DIR")),
    "mould_shapes.rs was generated for another clone sharing this target directory: \
     `touch physics/build.rs` reruns the build script"
);

/// The half-space: the shape of a `[[plane]]` and of a `Mould` left to its default.
impl Default for Shape {
    fn default() -> Self {
        Shape::HalfSpace(half_space::HalfSpace)
    }
}

impl Shape {
    /// The half-space of a `[[plane]]` ([`half_space`]), whose gaps and velocities are the
    /// plane's (model §7.2).
    pub fn is_half_space(&self) -> bool {
        matches!(self, Shape::HalfSpace(_))
    }
}

/// The unit vector along d, or `fallback` when d is 0.
pub fn unit_or(d: [f64; 3], fallback: [f64; 3]) -> [f64; 3] {
    let l = norm(d);
    if l > 0.0 {
        d.map(|c| c / l)
    } else {
        fallback
    }
}

/// a/|a| (a ≠ 0).
pub fn normalise(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    [a[0] / n, a[1] / n, a[2] / n]
}

/// Parses the keys of one shape for a unit test: `toml` the shape's keys, no file to read.
#[cfg(test)]
pub fn parse_for_test(shape: &str, toml: &str) -> Result<(Shape, Frame), EntryError> {
    let spec = SHAPES.iter().find(|s| s.key == shape).expect("a shape");
    let table: toml::Table = toml.parse().expect("valid TOML");
    let read = |_: &str| -> std::io::Result<Vec<u8>> {
        Err(std::io::Error::other("no file in a unit test"))
    };
    (spec.parse)(&Entry {
        shape: spec.key,
        keys: spec.keys,
        table: &table,
        read: &read,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every shape declares what it is and documents each of its keys once, with a unit for a
    /// number; the keys of `[[mould]]` every shape takes are none of a shape's own.
    #[test]
    fn every_shape_documents_its_keys() {
        for s in SHAPES {
            assert!(!s.about.is_empty(), "{}", s.key);
            for (i, k) in s.keys.iter().enumerate() {
                assert!(
                    !k.description.is_empty() && !k.kind.is_empty(),
                    "{}.{}",
                    s.key,
                    k.key
                );
                assert!(
                    s.keys[..i].iter().all(|o| o.key != k.key),
                    "{}.{} twice",
                    s.key,
                    k.key
                );
                assert!(
                    !["name", "shape", "pivot", "velocity", "angular_velocity"].contains(&k.key),
                    "{}.{} is a common key",
                    s.key,
                    k.key
                );
                if k.kind == "number" {
                    assert!(
                        !k.unit.is_empty(),
                        "{}.{}: a number needs a unit",
                        s.key,
                        k.key
                    );
                }
            }
        }
    }
}
