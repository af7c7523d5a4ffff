//! `topoccd_sparse`: a square sparse matrix (a potential's Hessian) in compressed sparse rows,
//! read in place with `topoccd_sparse_csr`.

use topoccd::ipc::SparseMatrix;

use crate::error::{deliver, topoccd_error};
use crate::handle::{self, Kind};
use crate::status::{guard, topoccd_status, Failure};

/// A square sparse matrix, `size x size`, symmetric for a Hessian (so its CSR arrays read as
/// CSC too), made by `topoccd_barrier_hessian` or `topoccd_friction_hessian`, freed by
/// `topoccd_sparse_free`.
pub struct topoccd_sparse {
    _private: [u8; 0],
}

struct SparseObject(SparseMatrix);

impl Kind for SparseObject {
    const MAGIC: u64 = u64::from_be_bytes(*b"topoSPM1");
    const NAME: &'static str = "topoccd_sparse";
}

/// The arrays of a `topoccd_sparse` in compressed sparse rows, borrowed: valid until
/// `topoccd_sparse_free`. Row `i`'s nonzeros are `data[k]` at column `indices[k]` for `k` in
/// `[indptr[i], indptr[i + 1])`, columns increasing (Eigen's `Map<SparseMatrix<double,
/// RowMajor, ...>>`, SciPy's `csr_matrix`, MKL's and SuiteSparse's CSR read them).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct topoccd_csr {
    /// Rows and columns.
    pub size: usize,
    /// Number of stored entries (`indptr[size]`).
    pub nnz: usize,
    /// `size + 1` row offsets.
    pub indptr: *const usize,
    /// `nnz` column indices.
    pub indices: *const usize,
    /// `nnz` values.
    pub data: *const f64,
}

pub(crate) fn into_raw(m: SparseMatrix) -> *mut topoccd_sparse {
    handle::into_raw(SparseObject(m))
}

/// `out` as a slice of `len` doubles, which must be `expected`.
///
/// # Safety
/// `out` is NULL or valid for `len` writes.
pub(crate) unsafe fn output<'a>(
    out: *mut f64,
    len: usize,
    expected: usize,
    what: &str,
) -> Result<&'a mut [f64], Failure> {
    if len != expected {
        return Err(Failure::new(
            topoccd_status::InvalidArgument,
            format!("{what}_len is {len}, but 3 vertex_count = {expected} entries are written"),
        ));
    }
    if len == 0 {
        return Ok(&mut []);
    }
    if out.is_null() {
        return Err(Failure::null(what));
    }
    if !(out as usize).is_multiple_of(std::mem::align_of::<f64>()) {
        return Err(Failure::new(
            topoccd_status::InvalidArgument,
            format!("{what} is not aligned for doubles"),
        ));
    }
    Ok(std::slice::from_raw_parts_mut(out, len))
}

/// The CSR arrays of `matrix` into `*csr`.
///
/// ```c
/// topoccd_csr h;
/// topoccd_sparse_csr(hessian, &h, NULL);
/// for (size_t i = 0; i < h.size; i++)
///     for (size_t k = h.indptr[i]; k < h.indptr[i + 1]; k++)
///         y[i] += h.data[k] * x[h.indices[k]];
/// ```
///
/// # Safety
/// `matrix` is NULL or a `topoccd_sparse` this library returned; `csr` and `error` are NULL
/// or valid for a write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_sparse_csr(
    matrix: *const topoccd_sparse,
    csr: *mut topoccd_csr,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        let m = &handle::get::<SparseObject, _>(matrix, "matrix")?.0;
        if csr.is_null() {
            return Err(Failure::null("csr"));
        }
        let (indptr, indices, data) = m.csr();
        *csr = topoccd_csr {
            size: m.size(),
            nnz: m.nnz(),
            indptr: indptr.as_ptr(),
            indices: indices.as_ptr(),
            data: data.as_ptr(),
        };
        Ok(())
    });
    deliver(result, error)
}

/// Frees `*matrix` and sets it to NULL. NULL, or a pointer to NULL, is allowed.
///
/// # Safety
/// `matrix` is NULL or points to NULL or to a `topoccd_sparse` this library returned, not in
/// use by another thread.
#[no_mangle]
pub unsafe extern "C" fn topoccd_sparse_free(matrix: *mut *mut topoccd_sparse) {
    let _ = guard(|| {
        handle::free::<SparseObject, _>(matrix);
        Ok(())
    });
}
