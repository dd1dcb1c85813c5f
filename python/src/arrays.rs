//! numpy arrays out, without the `numpy` crate: the values are copied into a new `bytearray`
//! and `numpy.frombuffer` views it with the dtype and shape. The array owns that memory (it is
//! writable, and nothing the solver holds is shared), and numpy is needed at run time only.
//!
//! The `numpy` crate would do the same copy; it is left out because it asks for the `default`
//! features of num-complex and num-integer, which the Rerun SDK's arrow crates use without
//! them: building this module would then recompile arrow and the Rerun crates above it instead
//! of reusing the command line's build.

use pyo3::prelude::*;
use pyo3::types::{PyAny, PyByteArray};

/// A value of a numpy dtype, written in native byte order.
pub trait Element: Copy {
    /// The numpy dtype (native byte order).
    const DTYPE: &'static str;
    /// Appends the value's bytes.
    fn put(self, out: &mut Vec<u8>);
}

impl Element for f64 {
    const DTYPE: &'static str = "float64";
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_ne_bytes());
    }
}

impl Element for i64 {
    const DTYPE: &'static str = "int64";
    fn put(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_ne_bytes());
    }
}

impl Element for i8 {
    const DTYPE: &'static str = "int8";
    fn put(self, out: &mut Vec<u8>) {
        out.push(self as u8);
    }
}

/// A new numpy array of `shape` holding `values` in row-major order.
pub fn array<'py, T: Element>(
    py: Python<'py>,
    values: impl IntoIterator<Item = T>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let count: usize = shape.iter().product();
    let mut bytes = Vec::with_capacity(count * std::mem::size_of::<T>());
    for v in values {
        v.put(&mut bytes);
    }
    debug_assert_eq!(bytes.len(), count * std::mem::size_of::<T>());
    let buffer = PyByteArray::new(py, &bytes);
    py.import("numpy")?
        .call_method1("frombuffer", (buffer, T::DTYPE))?
        .call_method1("reshape", (shape.to_vec(),))
}

/// An (n, 3) float64 array of 3-vectors.
pub fn vectors<'py>(
    py: Python<'py>,
    rows: impl ExactSizeIterator<Item = [f64; 3]>,
) -> PyResult<Bound<'py, PyAny>> {
    let n = rows.len();
    array(py, rows.flatten(), &[n, 3])
}

/// An (n,) array.
pub fn column<'py, T: Element>(
    py: Python<'py>,
    values: impl ExactSizeIterator<Item = T>,
) -> PyResult<Bound<'py, PyAny>> {
    let n = values.len();
    array(py, values, &[n])
}
