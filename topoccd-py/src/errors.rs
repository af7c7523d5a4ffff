//! The Python exceptions, and how the library's errors become them.
//!
//! - [`InputError`] (a `ValueError`): arrays that do not describe a valid step (shape, dtype,
//!   NaN, an index out of range, a bad parent row). The message names the element.
//! - [`OptionsError`] (a `ValueError`): a keyword option out of its range.
//! - [`FormatError`] (an `OSError`): a file that could be opened but not understood; the message
//!   names the file and the line or element. Files that cannot be opened raise the matching
//!   built-in `OSError` subclass (`FileNotFoundError`, `PermissionError`, ...).

use std::io::ErrorKind;

use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyIsADirectoryError, PyNotADirectoryError, PyOSError,
    PyPermissionError, PyUserWarning, PyValueError,
};
use pyo3::prelude::*;
use pyo3::PyErr;
use topoccd::io::sequence::SequenceError;
use topoccd::io::IoError;

create_exception!(
    topoccd,
    InputError,
    PyValueError,
    "Invalid input arrays: wrong shape or dtype, a non-finite coordinate, a vertex index out of \
     range, a bad parent row or group array. The message names the offending element."
);
create_exception!(
    topoccd,
    OptionsError,
    PyValueError,
    "A keyword option out of its range (tolerance, tmax, k, method, mode, threads...)."
);
create_exception!(
    topoccd,
    FormatError,
    PyOSError,
    "A mesh or sequence file that could be opened but not understood (truncated, malformed, \
     a face that is not a triangle, a frame missing from a sequence...). The message names the \
     file and the line or element."
);

create_exception!(
    topoccd,
    InputWarning,
    PyUserWarning,
    "Input that is valid but likely a mistake, warned about before a query runs: vertices that \
     sit exactly on one another, triangles of zero area, positions cast to integers. The \
     message names how many, the first few and the likely cause. Filter it with the warnings \
     module (warnings.simplefilter('ignore', topoccd.InputWarning))."
);

/// Warns with an [`InputWarning`] (through Python's `warnings`, so filters apply); the warning
/// points at the caller's line.
pub fn warn_input(py: Python<'_>, message: &str) -> PyResult<()> {
    let category = py.get_type::<InputWarning>();
    let message = std::ffi::CString::new(message.replace('\0', " "))
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    PyErr::warn(py, &category, &message, 1)
}

/// An [`InputError`] with this message.
pub fn input_error(message: impl Into<String>) -> PyErr {
    InputError::new_err(message.into())
}

/// A `MemoryError` with this message: an allocation the system refused (the library gave up
/// and freed what it held).
pub fn memory_error(message: impl Into<String>) -> PyErr {
    pyo3::exceptions::PyMemoryError::new_err(message.into())
}

/// An [`OptionsError`] with this message.
pub fn options_error(message: impl Into<String>) -> PyErr {
    OptionsError::new_err(message.into())
}

/// The built-in `OSError` subclass for an operating-system error, carrying `errno`, the message
/// and the file name as Python's own file functions do.
fn os_error(source: &std::io::Error, message: String, path: String) -> PyErr {
    let args = (source.raw_os_error().unwrap_or(0), message, path);
    match source.kind() {
        ErrorKind::NotFound => PyFileNotFoundError::new_err(args),
        ErrorKind::PermissionDenied => PyPermissionError::new_err(args),
        ErrorKind::AlreadyExists => PyFileExistsError::new_err(args),
        ErrorKind::IsADirectory => PyIsADirectoryError::new_err(args),
        ErrorKind::NotADirectory => PyNotADirectoryError::new_err(args),
        _ => PyOSError::new_err(args),
    }
}

/// The message of an error and of its sources, as `message: cause: cause`.
fn chain(err: &dyn std::error::Error) -> String {
    let mut text = err.to_string();
    let mut source = err.source();
    while let Some(s) = source {
        let more = s.to_string();
        if !text.ends_with(&more) {
            text.push_str(": ");
            text.push_str(&more);
        }
        source = s.source();
    }
    text
}

/// A reading or writing error as a Python exception: `OSError` (subclass) when the operating
/// system refused, `MemoryError` when the file's content did not fit in memory, [`FormatError`]
/// when the content is wrong.
pub fn io_error(err: &IoError) -> PyErr {
    match err {
        IoError::Io { path, source, .. } => {
            os_error(source, chain(err), path.display().to_string())
        }
        IoError::Folder { path } => {
            let args = (21, chain(err), path.display().to_string());
            PyIsADirectoryError::new_err(args)
        }
        IoError::OutOfMemory { .. } => memory_error(chain(err)),
        _ => FormatError::new_err(chain(err)),
    }
}

/// A sequence error as a Python exception (see [`io_error`]).
pub fn sequence_error(err: &SequenceError) -> PyErr {
    match err {
        SequenceError::Folder { path, source } => {
            os_error(source, chain(err), path.display().to_string())
        }
        SequenceError::Frame(io) => io_error(io),
        _ => FormatError::new_err(chain(err)),
    }
}
