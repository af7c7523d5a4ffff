//! `topoccd_error`: the error object of the functions that take no `topoccd_ccd` (the file
//! readers, the per-pair tests).

use std::ffi::{c_char, CString};
use std::ptr;

use crate::handle::{self, Kind};
use crate::status::{c_string, guard, topoccd_status, Failure};

/// The details of a failed call that takes no `topoccd_ccd` (reading a file, a per-pair test):
/// its status and its message. Such a function takes a last argument `topoccd_error **error`:
/// on failure, when `error` is not NULL, `*error` receives a new error object, which the caller
/// reads with `topoccd_error_message` and frees with `topoccd_error_free`; on success `*error`
/// is set to NULL. `*error` is never read, so it need not be initialised. Pass NULL for `error`
/// to get the status alone.
///
/// ```c
/// topoccd_mesh *mesh = NULL;
/// topoccd_error *error = NULL;
/// if (topoccd_mesh_read("missing.ply", &mesh, &error) != TOPOCCD_STATUS_OK) {
///     fprintf(stderr, "%s\n", topoccd_error_message(error)); /* missing.ply: cannot open: ... */
///     topoccd_error_free(&error);
/// }
/// ```
pub struct topoccd_error {
    _private: [u8; 0],
}

struct ErrorObject {
    status: topoccd_status,
    message: CString,
}

impl Kind for ErrorObject {
    const MAGIC: u64 = u64::from_be_bytes(*b"topoERR1");
    const NAME: &'static str = "topoccd_error";
}

/// Hands a call's result to C: on failure, a new error object into `*error` (when `error` is
/// not NULL); `*error` is NULL on success.
///
/// # Safety
/// `error` is NULL or valid for a write of a pointer.
pub(crate) unsafe fn deliver(
    result: Result<(), Failure>,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let (status, object) = match result {
        Ok(()) => (topoccd_status::Ok, ptr::null_mut()),
        Err(failure) => (
            failure.status,
            handle::into_raw::<_, topoccd_error>(ErrorObject {
                status: failure.status,
                message: c_string(failure.message),
            }),
        ),
    };
    if !error.is_null() {
        *error = object;
    } else if !object.is_null() {
        let mut object = object;
        handle::free::<ErrorObject, _>(&mut object);
    }
    status
}

/// The message of an error: one line of text that names what failed (the file and line, the
/// element, the option and its range). `""` for NULL; a fixed message for a pointer that is not
/// a live `topoccd_error`. Valid until the error is freed.
///
/// # Safety
/// `error` is NULL or a pointer this library returned.
#[no_mangle]
pub unsafe extern "C" fn topoccd_error_message(error: *const topoccd_error) -> *const c_char {
    if error.is_null() {
        return c"".as_ptr();
    }
    guard(|| handle::get::<ErrorObject, _>(error, "error").map(|e| e.message.as_ptr()))
        .unwrap_or(c"error is not a live topoccd_error".as_ptr())
}

/// The status of an error: `TOPOCCD_STATUS_OK` for NULL, `TOPOCCD_STATUS_INVALID_HANDLE` for a
/// pointer that is not a live `topoccd_error`.
///
/// # Safety
/// `error` is NULL or a pointer this library returned.
#[no_mangle]
pub unsafe extern "C" fn topoccd_error_status(error: *const topoccd_error) -> topoccd_status {
    if error.is_null() {
        return topoccd_status::Ok;
    }
    guard(|| handle::get::<ErrorObject, _>(error, "error").map(|e| e.status))
        .unwrap_or_else(|f| f.status)
}

/// Frees `*error` and sets `*error` to NULL. NULL, or a pointer to NULL, is allowed (nothing to
/// do).
///
/// # Safety
/// `error` is NULL or points to NULL or to a `topoccd_error` this library returned, freed only
/// once and not in use by another thread.
#[no_mangle]
pub unsafe extern "C" fn topoccd_error_free(error: *mut *mut topoccd_error) {
    let _ = guard(|| {
        handle::free::<ErrorObject, _>(error);
        Ok(())
    });
}
