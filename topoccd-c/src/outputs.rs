//! The outputs of the potentials' C calls, shared by the barrier (`ipc.rs`) and friction
//! (`friction.rs`): an energy, a dense gradient and a sparse Hessian, each checked (its
//! pointer, its length, the projection) after the inputs and before the potential runs.

use topoccd::ipc::{PsdProjection, SparseMatrix};

use crate::ipc;
use crate::sparse::{self, topoccd_sparse};
use crate::status::Failure;

/// Sets `*out` to NULL first, so that a failed call leaves no dangling handle.
///
/// # Safety
/// `out` is NULL or valid for a write of a pointer.
pub(crate) unsafe fn clear<T>(out: *mut *mut T) {
    if !out.is_null() {
        *out = std::ptr::null_mut();
    }
}

/// Writes `energy()` into `*out`.
///
/// # Safety
/// `out` is NULL or valid for a write.
pub(crate) unsafe fn energy(
    out: *mut f64,
    energy: impl FnOnce() -> Result<f64, Failure>,
) -> Result<(), Failure> {
    if out.is_null() {
        return Err(Failure::null("energy"));
    }
    *out = energy()?;
    Ok(())
}

/// Writes `gradient()` into `out`, `len` doubles, which must be `3 vertex_count`.
///
/// # Safety
/// `out` is NULL or valid for `len` writes.
pub(crate) unsafe fn gradient(
    out: *mut f64,
    len: usize,
    vertex_count: usize,
    gradient: impl FnOnce() -> Result<Vec<f64>, Failure>,
) -> Result<(), Failure> {
    let out = sparse::output(out, len, 3 * vertex_count, "gradient")?;
    out.copy_from_slice(&gradient()?);
    Ok(())
}

/// Checks `projection` (a `topoccd_psd_projection`) and hands `hessian(projection)` to
/// `*out` as a new `topoccd_sparse`.
///
/// # Safety
/// `out` is NULL or valid for a write of a pointer.
pub(crate) unsafe fn hessian(
    out: *mut *mut topoccd_sparse,
    projection: u32,
    hessian: impl FnOnce(PsdProjection) -> Result<SparseMatrix, Failure>,
) -> Result<(), Failure> {
    let method = ipc::projection(projection)?;
    if out.is_null() {
        return Err(Failure::null("hessian"));
    }
    *out = sparse::into_raw(hessian(method)?);
    Ok(())
}
