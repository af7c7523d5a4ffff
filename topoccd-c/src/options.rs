//! `topoccd_query_options`: the options of a query (and of the per-pair tests), filled with the
//! defaults by the library, sized so that fields can be appended without breaking callers built
//! against an older header.

use std::mem::{offset_of, size_of, MaybeUninit};
use std::ptr;

use topoccd::{ClusterGrowth, DopKind, Method, Mode, NarrowOptions, QueryOptions};

use crate::status::{guard, topoccd_status, Failure};

/// The broad phase of a query: every method reports the same pairs (see the Rust `Method`).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum topoccd_method {
    /// `TOPOCCD_METHOD_BVH` below 100,000 triangles, `TOPOCCD_METHOD_CLUSTER` above; the default.
    /// The report's `stats.method` says which ran.
    Auto = 0,
    /// A k-DOP bounding volume hierarchy built for the step.
    Bvh = 1,
    /// The paper's certified clusters, a hierarchy over them and lazy hierarchies over their
    /// triangles: fastest on large deforming meshes.
    Cluster = 2,
    /// The sweep-and-prune oracle.
    Brute = 3,
}

/// What a query reports.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum topoccd_mode {
    /// Every colliding pair with its time of impact; the default.
    All = 0,
    /// Only the earliest time of impact and the pairs within the tolerance of it: what a line
    /// search needs, and faster.
    Earliest = 1,
}

/// How `TOPOCCD_METHOD_CLUSTER` grows its leaf clusters (both are sound).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum topoccd_growth {
    /// The disk certificate alone: bigger clusters; the default.
    Certificate = 0,
    /// The paper's criterion on top of the certificate.
    Paper = 1,
}

/// The options of `topoccd_ccd_query` and of the per-pair tests (which read `tolerance`,
/// `max_iterations`, `min_distance` and `tmax` only).
///
/// Initialise it with `topoccd_query_options_default(&options)`, then change what you need.
/// Every function that takes it checks it first (an uninitialised or out-of-range value is
/// `TOPOCCD_STATUS_INVALID_OPTIONS`, with a message naming the option and its range); a NULL
/// options pointer means the defaults.
///
/// ```c
/// topoccd_query_options options;
/// topoccd_query_options_default(&options);
/// options.mode = TOPOCCD_MODE_EARLIEST;
/// options.geometry = true;
/// ```
///
/// Versions: `size` is the size of the struct the caller was compiled with, which
/// `topoccd_query_options_default` (an inline function of the header) passes to
/// `topoccd_query_options_init`. Later versions only append fields; a newer library reading an
/// older, smaller struct gives the fields the caller does not know their defaults.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct topoccd_query_options {
    /// `sizeof(topoccd_query_options)` as the caller compiled it; set by
    /// `topoccd_query_options_default`.
    pub size: usize,
    /// A `topoccd_method`. Default `TOPOCCD_METHOD_AUTO`.
    pub method: u32,
    /// A `topoccd_mode`. Default `TOPOCCD_MODE_ALL`.
    pub mode: u32,
    /// Resolution of the elementary tests, absolute, in time units, in (0, 1). Reported times
    /// are never later than the first contact and at most this much earlier unless the
    /// features come close first. Default 1e-6.
    pub tolerance: f64,
    /// Most parameter boxes an elementary test examines before it gives up conservatively
    /// (the contact is then `TOPOCCD_CERTAINTY_ITERATION_LIMIT`), at least 1. Default 1,000,000.
    pub max_iterations: u32,
    /// `k` of the k-DOP bounding volumes: 6, 14, 18 or 26. Default 18.
    pub k: u32,
    /// Distance, in coordinate units, at or below which features count as touching; finite,
    /// >= 0. Default 0.
    pub min_distance: f64,
    /// End of the time interval searched, in (0, 1]; later contacts are not reported.
    /// Default 1.
    pub tmax: f64,
    /// A `topoccd_growth`. Default `TOPOCCD_GROWTH_CERTIFICATE`.
    pub growth: u32,
    /// Threads of the query: 0 for one per core (a pool shared by the process), else a count
    /// in [1, 4096] (a pool kept by the `topoccd_ccd`). Results are identical for any count.
    /// Default 0.
    pub threads: u32,
    /// Whether contacts carry their geometry (barycentric coordinates, point, normal and
    /// distance at the time of impact). Default false.
    pub geometry: bool,
    /// Whether the two sides of a fresh crack are kept apart: with parents, a new vertex and
    /// its parent count as one vertex, so pairs joined that way are not tested. Default true.
    pub crack_filter: bool,
    /// Padding, ignored: it keeps the struct free of implicit padding, so that a field
    /// appended later starts after the `size` of every older caller.
    pub _padding: [u8; 6],
    /// Most contacts the report keeps; 0 for no cap. A query that has more stops, and its
    /// report's `truncated` says so; the contacts kept are the first of a fixed order, the same
    /// for any thread count. In `TOPOCCD_MODE_EARLIEST` the earliest time stays exact. Default
    /// 1,000,000 (the Rust and Python default), so that memory stays bounded.
    pub max_contacts: u64,
    /// Seconds a query may run; 0 for no limit. A query past it stops within a millisecond of
    /// work per thread; its report holds the earliest contact found by then and `truncated` is
    /// `TOPOCCD_STOP_REASON_DEADLINE`. Finite, >= 0. Default 0.
    pub timeout: f64,
}

/// The size of the first version of the struct (it ends with `_padding`): the smallest `size`
/// accepted.
const FIRST_SIZE: usize = offset_of!(topoccd_query_options, _padding) + 6;

/// The `bool` fields, whose bytes are checked before the struct is read as Rust values.
const BOOL_FIELDS: [usize; 2] = [
    offset_of!(topoccd_query_options, geometry),
    offset_of!(topoccd_query_options, crack_filter),
];

// Appending a field (the only change allowed: callers built against an older header pass a
// smaller struct): add it after the last field, give it its default in `Default` below, list
// it in `BOOL_FIELDS` if it is a `bool`, and end the struct with explicit padding, never
// implicit (a field appended later must start at or after every older `size`, or an older
// caller's padding would be read as its value). This check names the last field: move it to
// the new one (`size_of == offset_of!(.., new_field) + size of its type`).
const _: () =
    assert!(size_of::<topoccd_query_options>() == offset_of!(topoccd_query_options, timeout) + 8);

impl Default for topoccd_query_options {
    fn default() -> Self {
        let query = QueryOptions::default();
        Self {
            size: size_of::<Self>(),
            method: method_code(Method::default()),
            mode: topoccd_mode::All as u32,
            tolerance: query.narrow.tolerance,
            max_iterations: query.narrow.max_iterations,
            k: query.kdop.k() as u32,
            min_distance: query.narrow.min_distance,
            tmax: query.narrow.tmax,
            growth: match query.growth {
                ClusterGrowth::Paper => topoccd_growth::Paper as u32,
                ClusterGrowth::Certificate => topoccd_growth::Certificate as u32,
            },
            threads: 0,
            geometry: query.geometry,
            crack_filter: query.crack_filter,
            _padding: [0; 6],
            max_contacts: query.max_contacts.map_or(0, |n| n as u64),
            timeout: 0.0,
        }
    }
}

/// The C code of a Rust method.
pub(crate) fn method_code(method: Method) -> u32 {
    (match method {
        Method::Bvh => topoccd_method::Bvh,
        Method::Cluster => topoccd_method::Cluster,
        Method::Brute => topoccd_method::Brute,
        _ => topoccd_method::Auto,
    }) as u32
}

/// Fills `*options` with the defaults, for a caller whose struct has `size` bytes. Call it
/// through `topoccd_query_options_default(&options)`, which passes `sizeof options`; callers
/// without the header's inline functions (other languages' bindings) call it directly.
///
/// Returns `TOPOCCD_STATUS_NULL_POINTER` for NULL and `TOPOCCD_STATUS_INVALID_ARGUMENT` for a
/// size this library does not know (smaller than the first version's, larger than its own, or
/// not a multiple of the struct's alignment); then nothing is written.
///
/// # Safety
/// `options` is NULL or valid for writes of `size` bytes.
#[no_mangle]
pub unsafe extern "C" fn topoccd_query_options_init(
    options: *mut topoccd_query_options,
    size: usize,
) -> topoccd_status {
    let result = guard(|| {
        if options.is_null() {
            return Err(Failure::null("options"));
        }
        check_size(size)?;
        let defaults = topoccd_query_options {
            size,
            ..topoccd_query_options::default()
        };
        // `size` bytes only: an older caller's struct is smaller than this library's.
        ptr::copy_nonoverlapping(
            ptr::addr_of!(defaults).cast::<u8>(),
            options.cast::<u8>(),
            size,
        );
        Ok(())
    });
    result.map_or_else(|f| f.status, |()| topoccd_status::Ok)
}

fn check_size(size: usize) -> Result<(), Failure> {
    let own = size_of::<topoccd_query_options>();
    let align = std::mem::align_of::<topoccd_query_options>();
    if size < FIRST_SIZE || size > own || !size.is_multiple_of(align) {
        return Err(Failure::new(
            topoccd_status::InvalidArgument,
            format!(
                "options->size is {size}, not the size of a topoccd_query_options this library \
                 reads ({FIRST_SIZE} to {own}): initialise the options with \
                 topoccd_query_options_default (or the library is older than the header)"
            ),
        ));
    }
    Ok(())
}

/// The options behind `ptr` (the defaults for NULL), read as far as the caller's `size` says,
/// and checked.
///
/// # Safety
/// `ptr` is NULL or points to an initialised `topoccd_query_options` of its `size` bytes.
pub(crate) unsafe fn read(ptr: *const topoccd_query_options) -> Result<Options, Failure> {
    let raw = if ptr.is_null() {
        topoccd_query_options::default()
    } else {
        let size = ptr.cast::<usize>().read_unaligned();
        check_size(size).map_err(|f| Failure::new(topoccd_status::InvalidOptions, f.message))?;
        let mut out = MaybeUninit::new(topoccd_query_options::default());
        let bytes = out.as_mut_ptr().cast::<u8>();
        ptr::copy_nonoverlapping(ptr.cast::<u8>(), bytes, size);
        // A `bool` byte other than 0 or 1 is true, as in C.
        for offset in BOOL_FIELDS {
            let b = bytes.add(offset);
            b.write(u8::from(b.read() != 0));
        }
        out.assume_init()
    };
    Options::from_raw(&raw)
}

/// Checked options, as the Rust library takes them.
pub(crate) struct Options {
    pub method: Method,
    pub query: QueryOptions,
    /// `0` for the shared pool.
    pub threads: usize,
}

fn invalid(message: String) -> Failure {
    Failure::new(topoccd_status::InvalidOptions, message)
}

impl Options {
    fn from_raw(o: &topoccd_query_options) -> Result<Self, Failure> {
        let method = match o.method {
            0 => Method::Auto,
            1 => Method::Bvh,
            2 => Method::Cluster,
            3 => Method::Brute,
            m => {
                return Err(invalid(format!(
                    "method {m} is not a topoccd_method (TOPOCCD_METHOD_AUTO, _BVH, _CLUSTER or \
                     _BRUTE: 0 to 3)"
                )))
            }
        };
        let mode = match o.mode {
            0 => Mode::All,
            1 => Mode::Earliest,
            m => {
                return Err(invalid(format!(
                    "mode {m} is not a topoccd_mode (TOPOCCD_MODE_ALL or TOPOCCD_MODE_EARLIEST: 0 \
                     or 1)"
                )))
            }
        };
        let growth = match o.growth {
            0 => ClusterGrowth::Certificate,
            1 => ClusterGrowth::Paper,
            g => {
                return Err(invalid(format!(
                    "growth {g} is not a topoccd_growth (TOPOCCD_GROWTH_CERTIFICATE or \
                     TOPOCCD_GROWTH_PAPER: 0 or 1)"
                )))
            }
        };
        let kdop = DopKind::from_k(o.k as usize)
            .ok_or_else(|| invalid(format!("k must be 6, 14, 18 or 26, got {}", o.k)))?;
        if !(o.timeout >= 0.0 && o.timeout.is_finite()) {
            return Err(invalid(format!(
                "timeout must be finite and >= 0 (0: no limit), got {}",
                o.timeout
            )));
        }
        if o.threads > 4096 {
            return Err(invalid(format!(
                "threads must be 0 (one per core) or in [1, 4096], got {}",
                o.threads
            )));
        }
        let query = QueryOptions {
            narrow: NarrowOptions {
                tolerance: o.tolerance,
                max_iterations: o.max_iterations,
                min_distance: o.min_distance,
                tmax: o.tmax,
            },
            kdop,
            mode,
            growth,
            geometry: o.geometry,
            crack_filter: o.crack_filter,
            max_contacts: (o.max_contacts > 0)
                .then(|| o.max_contacts.min(usize::MAX as u64) as usize),
            // The clock starts when the options are read, at the start of the query.
            deadline: (o.timeout > 0.0)
                .then(|| std::time::Instant::now() + std::time::Duration::from_secs_f64(o.timeout)),
        };
        query.validate().map_err(|e| invalid(e.to_string()))?;
        Ok(Self {
            method,
            query,
            threads: o.threads as usize,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_version_is_64_bytes_on_64_bit_targets() {
        // The size C callers built against the first header pass (x86_64, aarch64).
        if size_of::<usize>() == 8 {
            assert_eq!(FIRST_SIZE, 64);
        }
    }

    #[test]
    fn defaults_are_the_libraries() {
        let o = unsafe { read(std::ptr::null()) }.unwrap();
        assert_eq!(o.query, QueryOptions::default());
        assert_eq!(o.method, Method::default());
        assert_eq!(o.threads, 0);
    }

    #[test]
    fn sizes_outside_the_known_versions_are_refused() {
        for size in [
            0,
            8,
            FIRST_SIZE - 8,
            FIRST_SIZE + 1,
            size_of::<topoccd_query_options>() + 8,
        ] {
            let o = topoccd_query_options {
                size,
                ..Default::default()
            };
            let err = unsafe { read(&o) }.err().unwrap();
            assert_eq!(err.status, topoccd_status::InvalidOptions, "{size}");
            assert!(
                err.message.contains("topoccd_query_options_default"),
                "{}",
                err.message
            );
        }
    }

    #[test]
    fn bool_bytes_other_than_one_are_true() {
        // What a C caller may store through a `uint8_t *`: not 0 or 1, in a buffer of C's.
        let mut buffer = [0u64; 8];
        let defaults = topoccd_query_options::default();
        unsafe {
            let bytes = buffer.as_mut_ptr().cast::<u8>();
            ptr::copy_nonoverlapping(ptr::addr_of!(defaults).cast::<u8>(), bytes, FIRST_SIZE);
            bytes.add(BOOL_FIELDS[0]).write(2);
            let read = read(buffer.as_ptr().cast()).unwrap();
            assert!(read.query.geometry);
        }
    }
}
