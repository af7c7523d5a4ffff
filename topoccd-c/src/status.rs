//! Status codes, the failure every entry point turns into one, and the guard that keeps panics
//! inside the library.

use std::any::Any;
use std::ffi::{c_char, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// What a function of the C API returns: `TOPOCCD_STATUS_OK` (0) on success, else why it
/// failed. The message that goes with a failure is read with `topoccd_ccd_last_error` (functions
/// that take a `topoccd_ccd`) or from the `topoccd_error` the function hands back (the others).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum topoccd_status {
    /// Success.
    Ok = 0,
    /// A required pointer is NULL, or an array is NULL while its count is not 0.
    NullPointer = 1,
    /// The pointer is not a live object of the expected type: a destroyed object, or another
    /// kind of object. Detected by a tag that every object carries and that its free function
    /// clears: best effort, since reading freed memory is undefined behaviour in C (a free
    /// function that sets the caller's pointer to NULL makes the common case a
    /// `TOPOCCD_STATUS_NULL_POINTER` instead).
    InvalidHandle = 2,
    /// Another thread is using this `topoccd_ccd` right now. A `topoccd_ccd` runs one call at a
    /// time; use one per thread.
    Busy = 3,
    /// An argument is unusable: a misaligned array, a count too large for memory, a path that
    /// is not valid text on this system, an options `size` that this library does not know.
    InvalidArgument = 4,
    /// An index is out of range: a note of a mesh, a step of a sequence.
    OutOfRange = 5,
    /// A query option is out of its documented range (a tolerance of 0, `k` = 7, an unknown
    /// method or mode); the message names the option, its range and the value.
    InvalidOptions = 6,
    /// The step's input is invalid: vertex counts that differ (without parents), a triangle
    /// naming a vertex out of range or using one twice, a NaN or infinite coordinate, a bad
    /// parent row, groups of the wrong length; the message names the element.
    InvalidStep = 7,
    /// The operating system refused to open, read or list a file or folder.
    Io = 8,
    /// A file or folder holds something topoccd does not read: a malformed or truncated mesh,
    /// an unknown extension, a bad parents file, a folder that is not a frame sequence; the
    /// message names the file and the line or element.
    Format = 9,
    /// A bug inside topoccd: a panic was caught at the boundary (no panic ever crosses it).
    /// The message says where; the object stays usable.
    Internal = 10,
    /// A line search's query stopped at its `timeout` (or was cancelled) before it knew the
    /// earliest contact: no step size is known to be safe.
    Timeout = 11,
    /// A line search with `check_start` found triangles that intersect at t=0; the message
    /// names the first pair.
    StartIntersects = 12,
    /// The system refused memory that the call needed (a query whose cap was lifted on a
    /// configuration with very many pairs): the message names the buffer and the bytes asked.
    /// Nothing was kept; the object stays usable. Set `max_contacts` (its default bounds the
    /// report).
    OutOfMemory = 13,
}

/// The name of a status code (a `topoccd_status`) as text, e.g.
/// `"TOPOCCD_STATUS_INVALID_STEP"`. Never NULL: an unknown code gives
/// `"TOPOCCD_STATUS_UNKNOWN"`. The string is static.
#[no_mangle]
pub extern "C" fn topoccd_status_name(status: u32) -> *const c_char {
    // A plain integer, so that any value C passes is defined.
    let name: &CStr = match status {
        0 => c"TOPOCCD_STATUS_OK",
        1 => c"TOPOCCD_STATUS_NULL_POINTER",
        2 => c"TOPOCCD_STATUS_INVALID_HANDLE",
        3 => c"TOPOCCD_STATUS_BUSY",
        4 => c"TOPOCCD_STATUS_INVALID_ARGUMENT",
        5 => c"TOPOCCD_STATUS_OUT_OF_RANGE",
        6 => c"TOPOCCD_STATUS_INVALID_OPTIONS",
        7 => c"TOPOCCD_STATUS_INVALID_STEP",
        8 => c"TOPOCCD_STATUS_IO",
        9 => c"TOPOCCD_STATUS_FORMAT",
        10 => c"TOPOCCD_STATUS_INTERNAL",
        11 => c"TOPOCCD_STATUS_TIMEOUT",
        12 => c"TOPOCCD_STATUS_START_INTERSECTS",
        13 => c"TOPOCCD_STATUS_OUT_OF_MEMORY",
        _ => c"TOPOCCD_STATUS_UNKNOWN",
    };
    name.as_ptr()
}

const VERSION: &CStr =
    match CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
        Ok(v) => v,
        Err(_) => panic!("the package version holds a NUL byte"),
    };

/// The library's version, `"MAJOR.MINOR.PATCH"`. The string is static.
#[no_mangle]
pub extern "C" fn topoccd_version() -> *const c_char {
    VERSION.as_ptr()
}

/// A failed call: its status and its message.
#[derive(Debug)]
pub(crate) struct Failure {
    pub status: topoccd_status,
    pub message: String,
}

impl Failure {
    pub fn new(status: topoccd_status, message: impl Into<String>) -> Self {
        Self {
            status,
            message: message.into(),
        }
    }

    /// A NULL pointer where `what` was required.
    pub fn null(what: &str) -> Self {
        Self::new(topoccd_status::NullPointer, format!("{what} is NULL"))
    }

    /// A panic caught at the boundary.
    fn panic(payload: &(dyn Any + Send)) -> Self {
        let text = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic without a message".to_string());
        Self::new(
            topoccd_status::Internal,
            format!("internal error in topoccd (a bug: please report it): {text}"),
        )
    }
}

/// An error's message with the messages of its sources, `outer: inner: ...`.
pub(crate) fn chain(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(s) = source {
        let next = s.to_string();
        if !text.ends_with(&next) {
            text.push_str(": ");
            text.push_str(&next);
        }
        source = s.source();
    }
    text
}

/// Runs one entry point's work, turning a panic into [`topoccd_status::Internal`].
pub(crate) fn guard<T>(work: impl FnOnce() -> Result<T, Failure>) -> Result<T, Failure> {
    match catch_unwind(AssertUnwindSafe(work)) {
        Ok(result) => result,
        Err(payload) => Err(Failure::panic(payload.as_ref())),
    }
}

/// `text` as a C string; interior NUL bytes (never in topoccd's messages, possible in a path)
/// become `?`.
pub(crate) fn c_string(text: impl Into<String>) -> CString {
    let mut bytes = text.into().into_bytes();
    for b in &mut bytes {
        if *b == 0 {
            *b = b'?';
        }
    }
    CString::new(bytes).unwrap_or_default()
}
