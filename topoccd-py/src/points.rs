//! numpy arrays of points in, for the per-pair tests, the line search and the static check:
//! any real dtype, converted once to C-contiguous float64 (borrowed when it already is). Every
//! problem is an [`InputError`](crate::errors::InputError) naming the argument.

use numpy::prelude::*;
use numpy::{PyArrayDyn, PyReadonlyArrayDyn, PyUntypedArray};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::input_error;

/// A float64 array, C-contiguous, with its shape.
pub struct Points<'py> {
    array: PyReadonlyArrayDyn<'py, f64>,
}

impl Points<'_> {
    /// The values in C order.
    pub fn flat(&self) -> PyResult<&[f64]> {
        self.array
            .as_slice()
            .map_err(|e| input_error(format!("points are not contiguous: {e}")))
    }

    /// The shape.
    pub fn shape(&self) -> &[usize] {
        self.array.shape()
    }
}

/// The shape of an array as Python writes it: `(4, 2)`, `(5,)`.
pub fn shape_text(shape: &[usize]) -> String {
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

/// Reads `obj` as a float64 array whose shape `check` accepts (it returns the expected shape's
/// text otherwise, for the message); a float64 C-contiguous array is read in place.
pub fn points<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    expected: &str,
    check: impl Fn(&[usize]) -> bool,
) -> PyResult<Points<'py>> {
    let shape_error = |shape: &[usize]| {
        input_error(format!(
            "{name} must have shape {expected}, got {}",
            shape_text(shape)
        ))
    };
    let borrow_error = |e| input_error(format!("{name}: cannot be read: {e}"));
    if let Ok(array) = obj.cast::<PyArrayDyn<f64>>() {
        if array.is_c_contiguous() {
            if !check(array.shape()) {
                return Err(shape_error(array.shape()));
            }
            return Ok(Points {
                array: array.try_readonly().map_err(borrow_error)?,
            });
        }
    }
    let py = obj.py();
    let numpy = py.import("numpy")?;
    let array = numpy
        .call_method1("asarray", (obj,))
        .map_err(|e| input_error(format!("{name}: cannot be read as a numpy array: {e}")))?
        .cast_into::<PyUntypedArray>()
        .map_err(|_| input_error(format!("{name}: cannot be read as a numpy array")))?;
    if !check(array.shape()) {
        return Err(shape_error(array.shape()));
    }
    let dtype = array.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "f" | "i" | "u") && array.len() > 0 {
        let dtype: String = dtype.str()?.extract()?;
        return Err(input_error(format!(
            "{name} must hold real numbers, got dtype {dtype}"
        )));
    }
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", "float64")?;
    let converted = numpy
        .call_method("ascontiguousarray", (array,), Some(&kwargs))
        .map_err(|e| input_error(format!("{name}: cannot be converted to float64: {e}")))?
        .cast_into::<PyArrayDyn<f64>>()
        .map_err(|_| input_error(format!("{name}: conversion to float64 failed")))?;
    Ok(Points {
        array: converted.try_readonly().map_err(borrow_error)?,
    })
}
