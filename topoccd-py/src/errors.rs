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
    PyPermissionError, PyValueError,
};
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
    "A keyword option out of its range (tolerance, t_max, k, method, mode, threads...)."
);
create_exception!(
    topoccd,
    FormatError,
    PyOSError,
    "A mesh or sequence file that could be opened but not understood (truncated, malformed, \
     a face that is not a triangle, a frame missing from a sequence...). The message names the \
     file and the line or element."
);

/// An [`InputError`] with this message.
pub fn input_error(message: impl Into<String>) -> PyErr {
    InputError::new_err(message.into())
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
/// system refused, [`FormatError`] when the content is wrong.
pub fn io_error(err: &IoError) -> PyErr {
    match err {
        IoError::Io { path, source, .. } => {
            os_error(source, chain(err), path.display().to_string())
        }
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
