//! The static intersection check: `intersecting_triangles(x, triangles, parents=None)`.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use std::time::{Duration, Instant};

use topoccd::check::{frame_intersections_within, CheckError, CheckLimits};
use topoccd::{CancelToken, StopReason};

use crate::ccd::watched;
use crate::errors::{input_error, options_error};
use crate::input::{indices, positions, rows};

/// The pairs of triangles of one configuration that intersect or touch, among the pairs that
/// share no vertex; decided exactly (the orientation predicates of the ``robust`` crate) over
/// a bounding-box tree, the GIL released.
///
/// A CCD step assumes that nothing touches at its start. Check a configuration after a cut, a
/// bad step or an import with this function.
///
/// Args:
///     x: ``(n, 3)`` positions, any real dtype.
///     triangles: ``(m, 3)`` vertex indices, any integer dtype.
///     parents: optional ``(k, 2)`` rows ``[child, parent]`` of a topology change: a vertex
///         and its parent (and two children of one parent) count as one vertex, so the two
///         sides of a fresh crack, which touch, are not reported.
///     max_contacts: the most pairs the check may report (an int ``>= 0``; default
///         ``1_000_000``, :data:`topoccd.DEFAULT_MAX_CONTACTS`), or ``None`` for no cap. With
///         more, the check stops and raises ``RuntimeError`` (a collapsed mesh intersects
///         almost everywhere).
///     timeout: ``None``, or seconds (> 0) after which the check stops and raises
///         ``TimeoutError``.
///
/// Ctrl-C (``KeyboardInterrupt``) stops a running check, as it does a query.
///
/// Returns:
///     numpy.ndarray: ``(K, 2)`` int64 rows ``[a, b]``, ``a < b``, sorted (read-only).
///
/// Raises:
///     InputError: an array of the wrong shape or dtype, a non-finite coordinate, an index out
///         of range, a bad parent row.
///     OptionsError: ``max_contacts`` or ``timeout`` out of range.
///     RuntimeError: more than ``max_contacts`` pairs intersect.
///     TimeoutError: ``timeout`` passed before the check finished.
///     KeyboardInterrupt: Ctrl-C while the check ran.
///
/// Example: the second triangle pierces the first.
///     >>> import topoccd
///     >>> x = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, -1], [0.3, 0.2, 1], [0.2, 0.3, 1]]
///     >>> topoccd.intersecting_triangles(x, [[0, 1, 2], [3, 4, 5]]).tolist()
///     [[0, 1]]
#[pyfunction]
#[pyo3(signature = (
    x, triangles, *, parents=None, max_contacts=Some(topoccd::DEFAULT_MAX_CONTACTS as i64),
    timeout=None
))]
pub fn intersecting_triangles<'py>(
    py: Python<'py>,
    x: &Bound<'py, PyAny>,
    triangles: &Bound<'py, PyAny>,
    parents: Option<&Bound<'py, PyAny>>,
    max_contacts: Option<i64>,
    timeout: Option<f64>,
) -> PyResult<Bound<'py, PyArray2<i64>>> {
    let started = Instant::now();
    let max_contacts =
        match max_contacts {
            None => None,
            Some(n) => Some(usize::try_from(n).map_err(|_| {
                options_error(format!("max_contacts must be None or >= 0, got {n}"))
            })?),
        };
    if let Some(t) = timeout {
        if !(t > 0.0 && t < 1e9) {
            return Err(options_error(format!(
                "timeout must be None or seconds in (0, 1e9), got {t}"
            )));
        }
    }
    let x = positions(x, "x")?;
    let tris = indices(triangles, "triangles", Some(3))?;
    let parent_rows = match parents {
        Some(p) => rows::<2>(&indices(p, "parents", Some(2))?),
        None => Vec::new(),
    };
    let flat = x.as_flat()?;
    let token = CancelToken::new();
    let limits = CheckLimits {
        max_contacts,
        deadline: timeout.map(|t| started + Duration::from_secs_f64(t)),
        cancel: Some(token.clone()),
    };
    let outcome = watched(py, None, &token, || {
        frame_intersections_within(flat, &tris[..], &parent_rows, &limits)
    })?;
    let pairs = outcome.map_err(|e| match e {
        CheckError::Step(e) => input_error(e.to_string()),
        CheckError::OutOfMemory { .. } => crate::errors::memory_error(e.to_string()),
        CheckError::Stopped(StopReason::Deadline) => {
            pyo3::exceptions::PyTimeoutError::new_err(format!(
                "the static check did not finish within timeout={} s (it stopped after {:.3} s): \
                 a collapsed or huge mesh can take long; max_contacts=N ends it early",
                timeout.unwrap_or_default(),
                started.elapsed().as_secs_f64()
            ))
        }
        e => pyo3::exceptions::PyRuntimeError::new_err(e.to_string()),
    })?;
    let mut out = Array2::<i64>::zeros((pairs.len(), 2));
    for (row, [a, b]) in out.rows_mut().into_iter().zip(&pairs) {
        let mut row = row;
        row[0] = i64::from(*a);
        row[1] = i64::from(*b);
    }
    let array = out.into_pyarray(py);
    array.readwrite().make_nonwriteable();
    Ok(array)
}
