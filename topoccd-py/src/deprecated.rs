//! The keyword names of earlier versions, accepted for one release with a `DeprecationWarning`
//! naming the new keyword (issue 45: one vocabulary, the IPC toolkit's names).

use pyo3::exceptions::{PyDeprecationWarning, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Moves the old keywords of `deprecated` (`min_separation`, `t_max`) into `min_distance` and
/// `tmax`, with a warning each; any other keyword is a `TypeError`, as Python's own.
pub fn renamed(
    py: Python<'_>,
    function: &str,
    deprecated: Option<&Bound<'_, PyDict>>,
    min_distance: &mut f64,
    tmax: &mut f64,
) -> PyResult<()> {
    let Some(kwargs) = deprecated else {
        return Ok(());
    };
    for (key, value) in kwargs.iter() {
        let old: String = key.extract()?;
        let (new, slot) = match old.as_str() {
            "min_separation" => ("min_distance", &mut *min_distance),
            "t_max" => ("tmax", &mut *tmax),
            _ => {
                return Err(PyTypeError::new_err(format!(
                    "{function}() got an unexpected keyword argument '{old}'"
                )))
            }
        };
        *slot = value.extract()?;
        let message = std::ffi::CString::new(format!(
            "{function}(): the keyword '{old}' is deprecated, use '{new}' (the IPC toolkit's \
             name; the old one goes in the next release)"
        ))
        .unwrap_or_default();
        PyErr::warn(py, &py.get_type::<PyDeprecationWarning>(), &message, 1)?;
    }
    Ok(())
}
