//! numpy arrays in: positions borrowed without a copy when they are float64 and C-contiguous,
//! converted once otherwise; integer arrays (triangles, parents, groups) checked and converted
//! to `u32`. Every problem is an [`InputError`](crate::errors::InputError) naming the array and
//! the element.

use numpy::prelude::*;
use numpy::{PyArray2, PyReadonlyArray2, PyUntypedArray};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::input_error;

/// An `(n, 3)` float64 array ready to be read as a flat `&[f64]`.
pub struct Positions<'py> {
    array: PyReadonlyArray2<'py, f64>,
    /// Whether the caller's own array is used (no copy was made).
    pub borrowed: bool,
}

impl Positions<'_> {
    /// The coordinates, `x0 y0 z0 x1 y1 z1 ...`.
    pub fn as_flat(&self) -> PyResult<&[f64]> {
        self.array
            .as_slice()
            .map_err(|e| input_error(format!("positions are not contiguous: {e}")))
    }

    /// Number of rows (vertices).
    pub fn rows(&self) -> usize {
        self.array.shape()[0]
    }
}

/// `numpy.asarray(obj)`, with a failure reported as an `InputError` naming `name`.
fn as_ndarray<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<Bound<'py, PyUntypedArray>> {
    let py = obj.py();
    let numpy = py.import("numpy")?;
    let array = numpy
        .call_method1("asarray", (obj,))
        .map_err(|e| input_error(format!("{name}: cannot be read as a numpy array: {e}")))?;
    array
        .cast_into::<PyUntypedArray>()
        .map_err(|_| input_error(format!("{name}: cannot be read as a numpy array")))
}

/// The shape of an array as Python writes it: `(4, 2)`, `(5,)`.
fn shape_text(shape: &[usize]) -> String {
    match shape {
        [one] => format!("({one},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// The dtype's kind character (`f`, `i`, `u`, `b`, `c`, `O`, ...) and its name.
fn dtype_of(array: &Bound<'_, PyUntypedArray>) -> PyResult<(String, String)> {
    let dtype = array.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    let name: String = dtype.str()?.extract()?;
    Ok((kind, name))
}

/// `numpy.ascontiguousarray(array, dtype=dtype)`.
fn contiguous<'py>(
    array: &Bound<'py, PyUntypedArray>,
    dtype: &str,
    name: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let py = array.py();
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", dtype)?;
    py.import("numpy")?
        .call_method("ascontiguousarray", (array,), Some(&kwargs))
        .map_err(|e| input_error(format!("{name}: cannot be converted to {dtype}: {e}")))
}

/// Reads positions: an `(n, 3)` array of any real dtype, in any memory order (or an empty
/// array of shape `(0,)`, as an empty list reads, for no vertices). A float64 C-contiguous
/// array is borrowed as it is; anything else is converted once.
pub fn positions<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<Positions<'py>> {
    let check_shape = |shape: &[usize]| {
        if (shape.len() == 2 && shape[1] == 3) || shape == [0] {
            Ok(())
        } else {
            Err(input_error(format!(
                "{name} must have shape (n, 3), got {}",
                shape_text(shape)
            )))
        }
    };
    let borrow_error = |e| input_error(format!("{name}: cannot be read: {e}"));
    if let Ok(array) = obj.cast::<PyArray2<f64>>() {
        if array.is_c_contiguous() {
            check_shape(array.shape())?;
            return Ok(Positions {
                array: array.try_readonly().map_err(borrow_error)?,
                borrowed: true,
            });
        }
    }
    let array = as_ndarray(obj, name)?;
    check_shape(array.shape())?;
    let (kind, dtype) = dtype_of(&array)?;
    if !matches!(kind.as_str(), "f" | "i" | "u") && array.len() > 0 {
        return Err(input_error(format!(
            "{name} must hold real numbers, got dtype {dtype}"
        )));
    }
    let converted = contiguous(&array, "float64", name)?;
    let converted = if array.shape() == [0] {
        converted.call_method1("reshape", ((0, 3),))?
    } else {
        converted
    };
    let converted = converted
        .cast_into::<PyArray2<f64>>()
        .map_err(|_| input_error(format!("{name}: conversion to float64 failed")))?;
    Ok(Positions {
        array: converted.try_readonly().map_err(borrow_error)?,
        borrowed: false,
    })
}

/// Converts checked integers to `u32`, naming the first bad element as `name[row, col]` (or
/// `name[row]` for a 1-d array).
fn to_u32<T: Copy + Into<i128>>(
    values: &[T],
    cols: Option<usize>,
    name: &str,
) -> PyResult<Vec<u32>> {
    let mut out = Vec::with_capacity(values.len());
    for (i, &v) in values.iter().enumerate() {
        let v: i128 = v.into();
        match u32::try_from(v) {
            Ok(x) => out.push(x),
            Err(_) => {
                let at = match cols {
                    Some(c) => format!("{name}[{}, {}]", i / c, i % c),
                    None => format!("{name}[{i}]"),
                };
                let why = if v < 0 {
                    "is negative".to_string()
                } else {
                    format!("exceeds the largest index {}", u32::MAX)
                };
                return Err(input_error(format!("{at} = {v} {why}")));
            }
        }
    }
    Ok(out)
}

/// Reads an integer array of shape `(rows, cols)` (or `(rows,)` when `cols` is `None`) as flat
/// `u32` values. Any integer dtype is accepted; an empty array of any dtype too (an empty list
/// is float64 to numpy).
pub fn indices(obj: &Bound<'_, PyAny>, name: &str, cols: Option<usize>) -> PyResult<Vec<u32>> {
    let array = as_ndarray(obj, name)?;
    let shape = array.shape();
    let shape_ok = match cols {
        Some(c) => (shape.len() == 2 && shape[1] == c) || (shape.len() == 1 && shape[0] == 0),
        None => shape.len() == 1,
    };
    if !shape_ok {
        let want = match cols {
            Some(c) => format!("(m, {c})"),
            None => "(n,)".to_string(),
        };
        return Err(input_error(format!(
            "{name} must have shape {want}, got {}",
            shape_text(shape)
        )));
    }
    if array.len() == 0 {
        return Ok(Vec::new());
    }
    let (kind, dtype) = dtype_of(&array)?;
    match kind.as_str() {
        "u" => with_flat_ints::<u64, _>(&array, "uint64", name, |f| to_u32(f, cols, name)),
        "i" => with_flat_ints::<i64, _>(&array, "int64", name, |f| to_u32(f, cols, name)),
        _ => Err(input_error(format!(
            "{name} must hold integers (vertex indices), got dtype {dtype}"
        ))),
    }
}

/// Calls `read` on the values of an integer array converted once to `T` (numpy dtype
/// `dtype`), flat, in C order.
fn with_flat_ints<T: numpy::Element + Copy, R>(
    array: &Bound<'_, PyUntypedArray>,
    dtype: &str,
    name: &str,
    read: impl FnOnce(&[T]) -> PyResult<R>,
) -> PyResult<R> {
    let converted = contiguous(array, dtype, name)?;
    let a = converted
        .cast_into::<numpy::PyArrayDyn<T>>()
        .map_err(|_| input_error(format!("{name}: conversion to {dtype} failed")))?;
    let a = a
        .try_readonly()
        .map_err(|e| input_error(format!("{name}: cannot be read: {e}")))?;
    let flat = a
        .as_slice()
        .map_err(|e| input_error(format!("{name}: {e}")))?;
    read(flat)
}

/// Groups `[a, b, c, a, b, c, ...]` into `[[a, b, c], ...]`.
pub fn rows<const N: usize>(flat: &[u32]) -> Vec<[u32; N]> {
    flat.chunks_exact(N)
        .map(|c| {
            let mut row = [0u32; N];
            row.copy_from_slice(c);
            row
        })
        .collect()
}
