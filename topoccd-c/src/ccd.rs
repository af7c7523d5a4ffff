//! `topoccd_ccd`: the reusable query, its report and its last error message.

use std::ffi::{c_char, CString};
use std::ptr;
use std::sync::{Mutex, MutexGuard, TryLockError};

use topoccd::Ccd;

use crate::handle::{self, Kind};
use crate::options::{self, topoccd_query_options};
use crate::report::{topoccd_report, ReportBuffers};
use crate::status::{c_string, guard, topoccd_status, Failure};
use crate::step::{self, topoccd_step};

/// A reusable continuous-collision-detection query. Keep one per simulation and query it every
/// step: its buffers (hierarchy, candidate pairs, the report's arrays) are reused, and the
/// topology may change freely from one step to the next. It holds the report of its last query
/// and the message of its last failure.
///
/// One `topoccd_ccd` runs one call at a time: a call while another thread uses it returns
/// `TOPOCCD_STATUS_BUSY`. Different `topoccd_ccd`s share nothing and run in parallel.
///
/// ```c
/// topoccd_ccd *ccd = topoccd_ccd_new();
/// /* every step: */
/// if (topoccd_ccd_query(ccd, &step, &options) != TOPOCCD_STATUS_OK)
///     fprintf(stderr, "%s\n", topoccd_ccd_last_error(ccd));
/// topoccd_ccd_free(&ccd); /* ccd is NULL now */
/// ```
pub struct topoccd_ccd {
    _private: [u8; 0],
}

struct CcdObject(Mutex<State>);

impl Kind for CcdObject {
    const MAGIC: u64 = u64::from_be_bytes(*b"topoCCD1");
    const NAME: &'static str = "topoccd_ccd";
}

#[derive(Default)]
pub(crate) struct State {
    pub(crate) ccd: Ccd,
    /// The pool of the last query that asked for a thread count, kept for the next.
    pool: Option<(usize, rayon::ThreadPool)>,
    pub(crate) report: ReportBuffers,
    /// The message of the last call that failed, `""` after a call that succeeded.
    error: CString,
    /// The arrays of the last proximity report (`topoccd_proximity`).
    pub(crate) proximity: crate::proximity::ProximityBuffers,
}

/// Runs `work` on the `Ccd` of `state`, on its kept pool of `threads` threads (built when the
/// count changes), or on the process's pool for 0.
pub(crate) fn run_on<T: Send>(
    state: &mut State,
    threads: usize,
    work: impl FnOnce(&mut Ccd) -> T + Send,
) -> Result<T, Failure> {
    let State { ccd, pool, .. } = state;
    if threads == 0 {
        return Ok(work(ccd));
    }
    if pool.as_ref().map(|(n, _)| *n) != Some(threads) {
        let built = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| {
                Failure::new(
                    topoccd_status::InvalidOptions,
                    format!("cannot start {threads} threads: {e}"),
                )
            })?;
        *pool = Some((threads, built));
    }
    match pool {
        Some((_, p)) => Ok(p.install(|| work(ccd))),
        None => Ok(work(ccd)),
    }
}

/// The state of a `topoccd_ccd`, locked for one call.
///
/// # Safety
/// `ccd` is NULL or a pointer this library returned (or points to at least 8 readable bytes).
unsafe fn lock<'a>(ccd: *const topoccd_ccd) -> Result<MutexGuard<'a, State>, Failure> {
    let object = handle::get::<CcdObject, _>(ccd, "ccd")?;
    match object.0.try_lock() {
        Ok(state) => Ok(state),
        Err(TryLockError::WouldBlock) => Err(Failure::new(
            topoccd_status::Busy,
            "the topoccd_ccd is in use by another thread (use one topoccd_ccd per thread)",
        )),
        // Never left poisoned (panics are caught while the lock is held), but if it were, its
        // state is made fresh.
        Err(TryLockError::Poisoned(poisoned)) => {
            let mut state = poisoned.into_inner();
            *state = State::default();
            object.0.clear_poison();
            Ok(state)
        }
    }
}

/// Runs one call on the state of `ccd`, keeping its message.
///
/// # Safety
/// As [`lock`].
pub(crate) unsafe fn with_state(
    ccd: *const topoccd_ccd,
    work: impl FnOnce(&mut State) -> Result<(), Failure>,
) -> topoccd_status {
    let result = guard(|| {
        let mut state = lock(ccd)?;
        // The lock is held while the work runs; a panic in it is caught here, so the lock is
        // never poisoned, and the state, which the panic may have left half-done, is reset.
        let result = guard(|| work(&mut state));
        if matches!(&result, Err(f) if f.status == topoccd_status::Internal) {
            state.ccd = Ccd::new();
            state.report.clear();
        }
        state.error = match &result {
            Ok(()) => CString::default(),
            Err(f) => c_string(f.message.clone()),
        };
        result
    });
    match result {
        Ok(()) => topoccd_status::Ok,
        Err(f) => f.status,
    }
}

impl State {
    /// Runs one query on `step`, in the pool of `threads` (0: the shared pool), kept for the
    /// next query that asks for as many.
    pub(crate) fn query(
        &mut self,
        step: &topoccd::Step<'_>,
        method: topoccd::Method,
        query: &topoccd::QueryOptions,
        threads: usize,
    ) -> Result<topoccd::Report, Failure> {
        let State { ccd, pool, .. } = self;
        let mut run = || ccd.query(step, method, query);
        let result = if threads == 0 {
            run()
        } else {
            if pool.as_ref().map(|(n, _)| *n) != Some(threads) {
                let built = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .map_err(|e| {
                        Failure::new(
                            topoccd_status::InvalidOptions,
                            format!("cannot start {threads} threads: {e}"),
                        )
                    })?;
                *pool = Some((threads, built));
            }
            match pool {
                Some((_, p)) => p.install(run),
                None => run(),
            }
        };
        result.map_err(|e| {
            let status = match e {
                topoccd::OptionsError::OutOfMemory { .. } => topoccd_status::OutOfMemory,
                _ => topoccd_status::InvalidOptions,
            };
            Failure::new(status, e.to_string())
        })
    }
}

/// A new query with empty buffers; NULL only if the library failed inside (never in practice).
/// Free it with `topoccd_ccd_free`.
#[no_mangle]
pub extern "C" fn topoccd_ccd_new() -> *mut topoccd_ccd {
    guard(|| {
        Ok(handle::into_raw::<_, topoccd_ccd>(CcdObject(Mutex::new(
            State::default(),
        ))))
    })
    .unwrap_or(ptr::null_mut())
}

/// Frees `*ccd`, with its report, and sets `*ccd` to NULL, so that a later call through the
/// same variable is refused with `TOPOCCD_STATUS_NULL_POINTER`. NULL, or a pointer to NULL, is
/// allowed (nothing to do). A copy of the pointer made before is dangling: a call through it is
/// undefined behaviour, which the object's tag (cleared here) turns into
/// `TOPOCCD_STATUS_INVALID_HANDLE` as long as the allocator has not reused the memory (best
/// effort).
///
/// # Safety
/// `ccd` is NULL or points to NULL or to a `topoccd_ccd` this library returned, which no other
/// thread is using.
#[no_mangle]
pub unsafe extern "C" fn topoccd_ccd_free(ccd: *mut *mut topoccd_ccd) {
    let _ = guard(|| {
        handle::free::<CcdObject, _>(ccd);
        Ok(())
    });
}

/// Runs continuous collision detection over one step and keeps its report in `ccd`
/// (`topoccd_ccd_report`). `options` may be NULL for the defaults.
///
/// Every vertex-face pair and every pair of edges that share no vertex and pass the step's
/// pair filter (parents, groups), and come within `min_distance` during `[0, tmax]`, is
/// reported with a conservative time of impact (never later than the first contact) and its
/// certainty (`TOPOCCD_MODE_ALL`); only the earliest pair(s) with `TOPOCCD_MODE_EARLIEST`. The
/// result does not depend on the method, the thread count or earlier queries.
///
/// Returns `TOPOCCD_STATUS_OK`, or: `TOPOCCD_STATUS_NULL_POINTER` (`ccd` or `step` NULL, or an
/// array NULL with a count that is not 0), `TOPOCCD_STATUS_INVALID_HANDLE`,
/// `TOPOCCD_STATUS_BUSY`, `TOPOCCD_STATUS_INVALID_ARGUMENT` (a misaligned array, an impossible
/// count), `TOPOCCD_STATUS_INVALID_OPTIONS`, `TOPOCCD_STATUS_INVALID_STEP` (the message names the
/// element: `triangle 4 names vertex 99, but there are only 10 vertices`). After a failure the
/// report is empty.
///
/// ```c
/// /* A triangle (3 4 5) falls through a fixed one (0 1 2): vertex 3 hits it at t=0.5. */
/// const double x0[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 1, 0.3, 0.2, 1.5, 0.2, 0.3, 1.5};
/// const double x1[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, -1, 0.3, 0.2, -0.5, 0.2, 0.3, -0.5};
/// const uint32_t triangles[] = {0, 1, 2, 3, 4, 5};
/// topoccd_step step = {0};
/// step.x0 = x0; step.x0_count = 6;
/// step.x1 = x1; step.x1_count = 6;
/// step.triangles = triangles; step.triangle_count = 2;
/// topoccd_ccd_query(ccd, &step, NULL);
/// ```
///
/// # Safety
/// `ccd` is NULL or a `topoccd_ccd` this library returned; `step` is NULL or points to a
/// `topoccd_step` whose arrays are NULL or valid for reads of their counts' rows; `options` is
/// NULL or points to options initialised by `topoccd_query_options_default`.
#[no_mangle]
pub unsafe extern "C" fn topoccd_ccd_query(
    ccd: *mut topoccd_ccd,
    step: *const topoccd_step,
    options: *const topoccd_query_options,
) -> topoccd_status {
    with_state(ccd, |state| {
        state.report.clear();
        if step.is_null() {
            return Err(Failure::null("step"));
        }
        let options = options::read(options)?;
        let step = step::borrow(&*step)?;
        let found = state.query(&step, options.method, &options.query, options.threads)?;
        state.report.fill(&found);
        Ok(())
    })
}

/// The report of the last query of `ccd`, read in place: `*report` receives a pointer to it,
/// valid until the next query on `ccd` or `topoccd_ccd_free`. Before the first query, and after
/// a query that failed, the report is empty.
///
/// ```c
/// const topoccd_report *r = NULL;
/// topoccd_ccd_report(ccd, &r);
/// for (size_t i = 0; i < r->vf_count; i++)
///     printf("vertex %u hits face %u at t=%g\n", r->vf[i].vertex, r->vf[i].face, r->vf[i].toi);
/// ```
///
/// # Safety
/// `ccd` is NULL or a `topoccd_ccd` this library returned; `report` is NULL or valid for a
/// write of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_ccd_report(
    ccd: *const topoccd_ccd,
    report: *mut *const topoccd_report,
) -> topoccd_status {
    with_state(ccd, |state| {
        if report.is_null() {
            return Err(Failure::null("report"));
        }
        *report = state.report.view();
        Ok(())
    })
}

/// The message of the last call on `ccd` that failed, naming what was wrong (the element, the
/// option and its range); `""` when the last call succeeded. Never NULL: for a NULL `ccd`, one
/// that is not a live `topoccd_ccd`, or one that another thread is using, a fixed message says
/// so. Valid until the next call on `ccd`.
///
/// # Safety
/// `ccd` is NULL or a `topoccd_ccd` this library returned.
#[no_mangle]
pub unsafe extern "C" fn topoccd_ccd_last_error(ccd: *const topoccd_ccd) -> *const c_char {
    guard(|| lock(ccd).map(|state| state.error.as_ptr())).unwrap_or_else(|f| match f.status {
        topoccd_status::NullPointer => c"ccd is NULL".as_ptr(),
        topoccd_status::Busy => {
            c"the topoccd_ccd is in use by another thread (use one topoccd_ccd per thread)".as_ptr()
        }
        _ => {
            c"ccd is not a live topoccd_ccd: it was freed already, or it is another kind of object"
                .as_ptr()
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CStr;

    /// A panic inside a call (none is known: this one is made on purpose) is caught at the
    /// boundary: the status is `Internal`, the message says what panicked, and the object is
    /// reset and stays usable.
    #[test]
    fn a_panic_is_a_status_and_the_object_stays_usable() {
        let mut ccd = topoccd_ccd_new();
        let status = unsafe { with_state(ccd, |_| panic!("made on purpose")) };
        assert_eq!(status, topoccd_status::Internal);
        let message = unsafe { CStr::from_ptr(topoccd_ccd_last_error(ccd)) };
        let message = message.to_str().unwrap();
        assert!(message.contains("internal error in topoccd"), "{message}");
        assert!(message.contains("made on purpose"), "{message}");

        let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let t = [[0u32, 1, 2]];
        let step = topoccd_step {
            x0: x.as_ptr().cast(),
            x0_count: 3,
            x1: x.as_ptr().cast(),
            x1_count: 3,
            triangles: t.as_ptr().cast(),
            triangle_count: 1,
            parents: ptr::null(),
            parent_count: 0,
            groups: ptr::null(),
            group_count: 0,
            edges: ptr::null(),
            edge_count: 0,
        };
        let status = unsafe { topoccd_ccd_query(ccd, &step, ptr::null()) };
        assert_eq!(status, topoccd_status::Ok);
        unsafe { topoccd_ccd_free(&mut ccd) };
        assert!(ccd.is_null());
    }

    /// The same for a function that reports through a `topoccd_error`.
    #[test]
    fn a_panic_in_a_reader_is_an_error_object() {
        let mut error: *mut crate::topoccd_error = ptr::null_mut();
        let result = guard(|| -> Result<(), Failure> { panic!("in a reader") });
        let status = unsafe { crate::error::deliver(result, &mut error) };
        assert_eq!(status, topoccd_status::Internal);
        let message = unsafe { CStr::from_ptr(crate::topoccd_error_message(error)) };
        assert!(message.to_str().unwrap().contains("in a reader"));
        unsafe { crate::topoccd_error_free(&mut error) };
        assert!(error.is_null());
    }
}
