//! The line-search helpers: `topoccd_collision_free_stepsize` (how far along a step the mesh may
//! move without contact) and `topoccd_is_step_collision_free`, with their options
//! `topoccd_line_search_options`. Both run one `TOPOCCD_MODE_EARLIEST` query on a
//! `topoccd_ccd`, whose report then holds the earliest contact.

use std::mem::{align_of, offset_of, size_of, MaybeUninit};
use std::ptr;

use topoccd::line_search::{LineSearchError, LineSearchOptions};
use topoccd::{Frame, Mode, Report, StopReason};

use crate::ccd::{with_state, State};
use crate::options::{self, topoccd_query_options};
use crate::status::{guard, topoccd_status, Failure};
use crate::step::{self, topoccd_step};
use crate::topoccd_ccd;

/// The options of `topoccd_collision_free_stepsize` and `topoccd_is_step_collision_free`.
///
/// Initialise it with `topoccd_line_search_options_default(&options)`, then change what you
/// need. `query` points to the query's options (NULL for the defaults; their `mode` is
/// ignored: the helpers run `TOPOCCD_MODE_EARLIEST`), so a line search has a `timeout`, a
/// `max_contacts`, a `min_distance`, a `tmax` and a thread count like any query.
///
/// ```c
/// topoccd_query_options query;
/// topoccd_query_options_default(&query);
/// query.timeout = 0.5;
/// topoccd_line_search_options options;
/// topoccd_line_search_options_default(&options);
/// options.query = &query;
/// options.check_start = true;
/// ```
///
/// Versions: as `topoccd_query_options`, `size` is the size the caller was compiled with;
/// later versions only append fields.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct topoccd_line_search_options {
    /// `sizeof(topoccd_line_search_options)` as the caller compiled it; set by
    /// `topoccd_line_search_options_default`.
    pub size: usize,
    /// The query's options, read during the call; NULL for the defaults. Default NULL.
    pub query: *const topoccd_query_options,
    /// The fraction of the earliest time of impact that `topoccd_collision_free_stepsize`
    /// gives, in (0, 1]. Default 0.8, the IPC toolkit's conservative rescaling: the step stops
    /// short of the contact.
    pub conservative_rescaling: f64,
    /// Whether the exact static check runs on the t=0 positions first: triangles that already
    /// intersect there are `TOPOCCD_STATUS_START_INTERSECTS` (the message names a pair)
    /// instead of a step size. Default false: the start is assumed free of intersections (the
    /// paper's premise), and triangles that pass through each other at t=0 without a
    /// vertex-face or edge-edge contact during the step go unnoticed.
    pub check_start: bool,
    /// Padding, ignored (explicit, so that a field appended later starts after every older
    /// `size`).
    pub _padding: [u8; 7],
}

// Appending a field: as for `topoccd_query_options` (options.rs). This check names the last one.
const _: () = assert!(
    size_of::<topoccd_line_search_options>()
        == offset_of!(topoccd_line_search_options, _padding) + 7
);

/// The offset of the `bool` field, whose byte is checked before the struct is read.
const CHECK_START: usize = offset_of!(topoccd_line_search_options, check_start);

impl Default for topoccd_line_search_options {
    fn default() -> Self {
        let rust = LineSearchOptions::default();
        Self {
            size: size_of::<Self>(),
            query: ptr::null(),
            conservative_rescaling: rust.conservative_rescaling,
            check_start: rust.check_start,
            _padding: [0; 7],
        }
    }
}

fn check_size(size: usize, status: topoccd_status) -> Result<(), Failure> {
    let own = size_of::<topoccd_line_search_options>();
    if size != own || !size.is_multiple_of(align_of::<topoccd_line_search_options>()) {
        return Err(Failure::new(
            status,
            format!(
                "options->size is {size}, not the size of a topoccd_line_search_options this \
                 library reads ({own}): initialise the options with \
                 topoccd_line_search_options_default (or the library is older than the header)"
            ),
        ));
    }
    Ok(())
}

/// Fills `*options` with the defaults, for a caller whose struct has `size` bytes. Call it
/// through `topoccd_line_search_options_default(&options)`, which passes `sizeof options`.
///
/// Returns `TOPOCCD_STATUS_NULL_POINTER` for NULL and `TOPOCCD_STATUS_INVALID_ARGUMENT` for a
/// size this library does not know; then nothing is written.
///
/// # Safety
/// `options` is NULL or valid for writes of `size` bytes.
#[no_mangle]
pub unsafe extern "C" fn topoccd_line_search_options_init(
    options: *mut topoccd_line_search_options,
    size: usize,
) -> topoccd_status {
    let result = guard(|| {
        if options.is_null() {
            return Err(Failure::null("options"));
        }
        check_size(size, topoccd_status::InvalidArgument)?;
        options.write_unaligned(topoccd_line_search_options::default());
        Ok(())
    });
    result.map_or_else(|f| f.status, |()| topoccd_status::Ok)
}

/// The checked options behind `ptr` (the defaults for NULL).
struct Checked {
    rust: LineSearchOptions,
    threads: usize,
}

/// # Safety
/// `ptr` is NULL or points to an initialised `topoccd_line_search_options`, whose `query` is
/// NULL or points to initialised query options.
unsafe fn read(ptr: *const topoccd_line_search_options) -> Result<Checked, Failure> {
    let raw = if ptr.is_null() {
        topoccd_line_search_options::default()
    } else {
        let size = ptr.cast::<usize>().read_unaligned();
        check_size(size, topoccd_status::InvalidOptions)?;
        let mut out = MaybeUninit::new(topoccd_line_search_options::default());
        let bytes = out.as_mut_ptr().cast::<u8>();
        ptr::copy_nonoverlapping(ptr.cast::<u8>(), bytes, size);
        // A `bool` byte other than 0 or 1 is true, as in C.
        let b = bytes.add(CHECK_START);
        b.write(u8::from(b.read() != 0));
        out.assume_init()
    };
    let query = options::read(raw.query)?;
    let rust = LineSearchOptions {
        query: query.query,
        method: query.method,
        conservative_rescaling: raw.conservative_rescaling,
        check_start: raw.check_start,
    };
    rust.validate()
        .map_err(|e| Failure::new(topoccd_status::InvalidOptions, e.to_string()))?;
    Ok(Checked {
        rust,
        threads: query.threads,
    })
}

/// The earliest query of a line search, its report kept in `state`.
///
/// # Safety
/// As the entry points' arguments.
unsafe fn earliest(
    state: &mut State,
    step: *const topoccd_step,
    options: *const topoccd_line_search_options,
) -> Result<(Report, LineSearchOptions), Failure> {
    state.report.clear();
    if step.is_null() {
        return Err(Failure::null("step"));
    }
    let checked = read(options)?;
    let step = step::borrow(&*step)?;
    if checked.rust.check_start {
        let unbounded = topoccd::check::CheckLimits {
            max_contacts: None,
            ..Default::default()
        };
        let pairs = topoccd::check::step_intersections_within(&step, Frame::Start, &unbounded)
            .map_err(|e| {
                let status = match e {
                    topoccd::check::CheckError::OutOfMemory { .. } => topoccd_status::OutOfMemory,
                    _ => topoccd_status::Internal,
                };
                Failure::new(status, e.to_string())
            })?;
        if let Some(&first) = pairs.first() {
            let error = LineSearchError::StartIntersects {
                triangles: first,
                count: pairs.len(),
            };
            return Err(Failure::new(
                topoccd_status::StartIntersects,
                error.to_string(),
            ));
        }
    }
    let query = topoccd::QueryOptions {
        mode: Mode::Earliest,
        ..checked.rust.query
    };
    let report = state.query(&step, checked.rust.method, &query, checked.threads)?;
    state.report.fill(&report);
    // A query stopped by its deadline may not have found the earliest contact: no step size
    // is safe then. (`max_contacts` keeps the earliest time exact in this mode.)
    if let Some(t) = report
        .truncated
        .filter(|t| t.reason != StopReason::MaxContacts)
    {
        return Err(Failure::new(
            topoccd_status::Timeout,
            format!(
                "the line search's query stopped before the end ({}): no step size is known \
                 to be safe; raise the query's timeout",
                match t.reason {
                    StopReason::Deadline => "its timeout passed",
                    _ => "cancelled",
                }
            ),
        ));
    }
    Ok((report, checked.rust))
}

/// The fraction of the step that the mesh may take without contact: `*alpha` receives
/// `conservative_rescaling` times the earliest time of impact, or the query's `tmax` when no
/// features come within `min_distance` during `[0, tmax]`; 0 when features touch at the
/// start. The query runs on `ccd` in `TOPOCCD_MODE_EARLIEST`: afterwards `topoccd_ccd_report`
/// gives the earliest contact (`earliest_kind`, `earliest_index`, `earliest_toi`), which a
/// simulator uses to stop the touching vertices. `options` may be NULL for the defaults.
///
/// Returns `TOPOCCD_STATUS_OK`, or the statuses of `topoccd_ccd_query`, or
/// `TOPOCCD_STATUS_START_INTERSECTS` (with `check_start`: triangles intersect at t=0; the
/// message names the first pair), or `TOPOCCD_STATUS_TIMEOUT` (the query's `timeout` passed:
/// the report holds what was found by then). On any failure `*alpha` is 0: no step is known to
/// be safe.
///
/// ```c
/// double alpha = 0;
/// if (topoccd_collision_free_stepsize(ccd, &step, NULL, &alpha) != TOPOCCD_STATUS_OK)
///     fprintf(stderr, "%s\n", topoccd_ccd_last_error(ccd));
/// ```
///
/// # Safety
/// As `topoccd_ccd_query`; `options` is NULL or points to options initialised by
/// `topoccd_line_search_options_default`; `alpha` is NULL or valid for a write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_collision_free_stepsize(
    ccd: *mut topoccd_ccd,
    step: *const topoccd_step,
    options: *const topoccd_line_search_options,
    alpha: *mut f64,
) -> topoccd_status {
    with_state(ccd, |state| {
        if alpha.is_null() {
            return Err(Failure::null("alpha"));
        }
        alpha.write(0.0);
        let (report, rust) = earliest(state, step, options)?;
        alpha.write(match report.earliest {
            Some(contact) => rust.conservative_rescaling * contact.toi(),
            None => rust.query.narrow.tmax,
        });
        Ok(())
    })
}

/// Whether the whole step is free of contact: `*collision_free` receives true when no two
/// features come within `min_distance` during `[0, tmax]`. Otherwise `topoccd_ccd_report`
/// gives the earliest contact. Arguments, statuses and report as
/// `topoccd_collision_free_stepsize`; on any failure `*collision_free` is false.
///
/// # Safety
/// As `topoccd_collision_free_stepsize`; `collision_free` is NULL or valid for a write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_is_step_collision_free(
    ccd: *mut topoccd_ccd,
    step: *const topoccd_step,
    options: *const topoccd_line_search_options,
    collision_free: *mut bool,
) -> topoccd_status {
    with_state(ccd, |state| {
        if collision_free.is_null() {
            return Err(Failure::null("collision_free"));
        }
        collision_free.write(false);
        let (report, _) = earliest(state, step, options)?;
        collision_free.write(report.earliest.is_none());
        Ok(())
    })
}
