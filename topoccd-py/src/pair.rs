//! The per-pair tests in the IPC toolkit's shape: `point_triangle_ccd`, `edge_edge_ccd`,
//! `point_edge_ccd` and `point_point_ccd`, on one pair (eight, six or four points) or on a batch
//! of pairs (two `(N, 4, 3)`, `(N, 3, 3)` or `(N, 2, 3)` arrays), the GIL released.
//! A batch runs in chunks on a thread pool (`threads=`: pools kept per size), and between two
//! chunks looks at the clock (`timeout=`) and at pending signals (Ctrl-C).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyTimeoutError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use rayon::prelude::*;
use topoccd::pair::{
    edge_edge, vertex_edge, vertex_face, vertex_vertex, EdgeEdge, Outcome, VertexEdge, VertexFace,
    VertexVertex,
};
use topoccd::{Certainty, NarrowOptions};

use crate::errors::options_error;
use crate::points::points;

/// The kinds of pair, with the names of their points (as the IPC toolkit names them).
#[derive(Clone, Copy)]
enum Kind {
    PointTriangle,
    EdgeEdge,
    PointEdge,
    PointPoint,
}

impl Kind {
    fn function(self) -> &'static str {
        match self {
            Kind::PointTriangle => "point_triangle_ccd",
            Kind::EdgeEdge => "edge_edge_ccd",
            Kind::PointEdge => "point_edge_ccd",
            Kind::PointPoint => "point_point_ccd",
        }
    }

    fn names(self) -> &'static [&'static str] {
        match self {
            Kind::PointTriangle => &[
                "p_t0", "t0_t0", "t1_t0", "t2_t0", "p_t1", "t0_t1", "t1_t1", "t2_t1",
            ],
            Kind::EdgeEdge => &[
                "ea0_t0", "ea1_t0", "eb0_t0", "eb1_t0", "ea0_t1", "ea1_t1", "eb0_t1", "eb1_t1",
            ],
            Kind::PointEdge => &["p_t0", "e0_t0", "e1_t0", "p_t1", "e0_t1", "e1_t1"],
            Kind::PointPoint => &["p0_t0", "p1_t0", "p0_t1", "p1_t1"],
        }
    }

    /// Points of one pair at one time.
    fn half(self) -> usize {
        self.names().len() / 2
    }

    /// One test on the points, in the order of [`Kind::names`].
    fn test(self, p: &[[f64; 3]], options: &NarrowOptions) -> Outcome {
        let outcome = match self {
            Kind::PointTriangle => vertex_face(
                &VertexFace::from_points(p.try_into().unwrap_or_default()),
                options,
            ),
            Kind::EdgeEdge => edge_edge(
                &EdgeEdge::from_points(p.try_into().unwrap_or_default()),
                options,
            ),
            Kind::PointEdge => vertex_edge(
                &VertexEdge::from_points(p.try_into().unwrap_or_default()),
                options,
            ),
            Kind::PointPoint => vertex_vertex(
                &VertexVertex::from_points(p.try_into().unwrap_or_default()),
                options,
            ),
        };
        // The options were validated once, before the first test.
        outcome.unwrap_or(Outcome::Separated)
    }
}

/// The certainty code of an outcome: 0 for a resolved contact or a separated pair (a proof),
/// 1 for the iteration limit, 2 for invalid input.
fn code(outcome: &Outcome) -> u8 {
    match outcome {
        Outcome::Separated => 0,
        Outcome::Contact { certainty, .. } => match certainty {
            Certainty::Resolved => 0,
            Certainty::IterationLimit => 1,
            Certainty::InvalidInput => 2,
        },
    }
}

/// The keyword options as the library's, validated.
fn options(
    min_distance: f64,
    tmax: f64,
    tolerance: f64,
    max_iterations: i64,
) -> PyResult<NarrowOptions> {
    let max_iterations = u32::try_from(max_iterations).map_err(|_| {
        options_error(format!(
            "max_iterations must be in [1, {}], got {max_iterations}",
            u32::MAX
        ))
    })?;
    let options = NarrowOptions {
        tolerance,
        max_iterations,
        min_distance,
        tmax,
    };
    // The library's messages name its fields, which are the keywords' names.
    options
        .validate()
        .map_err(|e| options_error(e.to_string()))?;
    Ok(options)
}

/// The thread pools of `threads=N` batches, one per size, kept for the process (building one
/// costs about a thread start per thread; a simulator calls the batch every step).
fn pool(threads: usize) -> PyResult<Arc<rayon::ThreadPool>> {
    static POOLS: OnceLock<Mutex<HashMap<usize, Arc<rayon::ThreadPool>>>> = OnceLock::new();
    let mut pools = POOLS
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    if let Some(p) = pools.get(&threads) {
        return Ok(p.clone());
    }
    let built = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start {threads} threads: {e}")))?;
    let built = Arc::new(built);
    pools.insert(threads, built.clone());
    Ok(built)
}

/// The batch keywords that are not the narrow phase's: `threads` and `timeout`, checked.
struct Batch {
    threads: Option<usize>,
    timeout: Option<f64>,
}

impl Batch {
    fn new(threads: Option<i64>, timeout: Option<f64>) -> PyResult<Self> {
        let threads = match threads {
            None => None,
            Some(n) if (1..=4096).contains(&n) => Some(n as usize),
            Some(n) => {
                return Err(options_error(format!(
                    "threads must be None or in [1, 4096], got {n}"
                )))
            }
        };
        if let Some(t) = timeout {
            if !(t > 0.0 && t < 1e9) {
                return Err(options_error(format!(
                    "timeout must be None or seconds in (0, 1e9), got {t}"
                )));
            }
        }
        Ok(Self { threads, timeout })
    }
}

/// How long one chunk of a batch should take: the clock and the signals are looked at between
/// chunks, so a timeout or a Ctrl-C is met within about this (plus the slowest pair).
const CHUNK_TIME: Duration = Duration::from_millis(20);

/// The tests of a batch, `a` and `b` holding `3 * kind.half()` coordinates per pair, in order; in chunks sized
/// to take about [`CHUNK_TIME`] each, with the signals and the deadline checked between them.
fn batch(
    py: Python<'_>,
    kind: Kind,
    (a, b): (&[f64], &[f64]),
    options: &NarrowOptions,
    limits: &Batch,
    started: Instant,
) -> PyResult<Vec<Outcome>> {
    let pool = limits.threads.map(pool).transpose()?;
    let deadline = limits.timeout.map(|t| started + Duration::from_secs_f64(t));
    let half = kind.half();
    let n = a.len() / (3 * half);
    let mut outcomes = Vec::with_capacity(n);
    let mut chunk = 256usize;
    while outcomes.len() < n {
        let (lo, hi) = (outcomes.len(), (outcomes.len() + chunk).min(n));
        let w = 3 * half;
        let (ca, cb) = (&a[w * lo..w * hi], &b[w * lo..w * hi]);
        let clock = Instant::now();
        let work = || -> Vec<Outcome> {
            ca.par_chunks_exact(w)
                .zip(cb.par_chunks_exact(w))
                .with_min_len(64)
                .map(|(a, b)| {
                    let mut p = [[0.0; 3]; 8];
                    for k in 0..half {
                        p[k].copy_from_slice(&a[3 * k..3 * k + 3]);
                        p[k + half].copy_from_slice(&b[3 * k..3 * k + 3]);
                    }
                    kind.test(&p[..2 * half], options)
                })
                .collect()
        };
        let done = py.detach(|| match &pool {
            Some(p) => p.install(work),
            None => work(),
        });
        outcomes.extend(done);
        // The next chunk sized from this one's pace (at most 4 times as many pairs).
        let took = clock.elapsed().as_secs_f64().max(1e-6);
        let pace = (hi - lo) as f64 / took;
        chunk = ((pace * CHUNK_TIME.as_secs_f64()) as usize).clamp(64, 4 * chunk.max(64));
        py.check_signals()?;
        if outcomes.len() < n && deadline.is_some_and(|d| Instant::now() >= d) {
            return Err(PyTimeoutError::new_err(format!(
                "{}() did not finish within timeout={} s: it stopped after {:.3} s, having \
                 tested {} of {n} pairs",
                kind.function(),
                limits.timeout.unwrap_or_default(),
                started.elapsed().as_secs_f64(),
                outcomes.len()
            )));
        }
    }
    Ok(outcomes)
}

/// Runs one kind of test on the arguments: its points, or two `(N, k, 3)` arrays.
fn run<'py>(
    py: Python<'py>,
    kind: Kind,
    args: &Bound<'py, PyTuple>,
    options: NarrowOptions,
    certainty: bool,
    limits: Batch,
) -> PyResult<Bound<'py, PyTuple>> {
    let started = Instant::now();
    let half = kind.half();
    match args.len() {
        n if n == 2 * half => {
            let mut p = [[0.0; 3]; 8];
            for (k, name) in kind.names().iter().enumerate() {
                let a = points(&args.get_item(k)?, name, "(3,)", |s| s == [3])?;
                p[k].copy_from_slice(a.flat()?);
            }
            let outcome = py.detach(|| kind.test(&p[..2 * half], &options));
            let toi = outcome.toi().unwrap_or(f64::INFINITY);
            if certainty {
                (outcome.is_contact(), toi, code(&outcome)).into_pyobject(py)
            } else {
                (outcome.is_contact(), toi).into_pyobject(py)
            }
        }
        2 => {
            let shape = format!("(N, {half}, 3)");
            let shape = shape.as_str();
            let is_batch = |s: &[usize]| s.len() == 3 && s[1] == half && s[2] == 3;
            let x_t0 = points(&args.get_item(0)?, "x_t0", shape, is_batch)?;
            let x_t1 = points(&args.get_item(1)?, "x_t1", shape, is_batch)?;
            if x_t0.shape()[0] != x_t1.shape()[0] {
                return Err(crate::errors::input_error(format!(
                    "x_t0 and x_t1 must have the same shape, got ({}, {half}, 3) and ({}, \
                     {half}, 3)",
                    x_t0.shape()[0],
                    x_t1.shape()[0]
                )));
            }
            let (a, b) = (x_t0.flat()?, x_t1.flat()?);
            let outcomes = batch(py, kind, (a, b), &options, &limits, started)?;
            let hit: Vec<bool> = outcomes.iter().map(Outcome::is_contact).collect();
            let toi: Vec<f64> = outcomes
                .iter()
                .map(|o| o.toi().unwrap_or(f64::INFINITY))
                .collect();
            let hit = PyArray1::from_vec(py, hit);
            let toi = PyArray1::from_vec(py, toi);
            hit.readwrite().make_nonwriteable();
            toi.readwrite().make_nonwriteable();
            if certainty {
                let codes = PyArray1::from_vec(py, outcomes.iter().map(code).collect());
                codes.readwrite().make_nonwriteable();
                (hit, toi, codes).into_pyobject(py)
            } else {
                (hit, toi).into_pyobject(py)
            }
        }
        n => Err(PyTypeError::new_err(format!(
            "{}() takes {} points ({}) or two (N, {half}, 3) arrays (x_t0, x_t1), got {n} \
             positional arguments",
            kind.function(),
            ["four", "six", "eight"][half - 2],
            kind.names().join(", ")
        ))),
    }
}

/// Continuous collision test of a point against a triangle, each corner moving linearly from
/// its ``_t0`` to its ``_t1`` position, over ``[0, tmax]``; in the IPC toolkit's shape.
///
/// One pair: ``point_triangle_ccd(p_t0, t0_t0, t1_t0, t2_t0, p_t1, t0_t1, t1_t1, t2_t1)``,
/// eight points of shape ``(3,)``, gives ``(hit, toi)``: ``hit`` a bool, ``toi`` the time of
/// impact (``inf`` when there is no hit).
///
/// A batch: ``point_triangle_ccd(x_t0, x_t1)``, two ``(N, 4, 3)`` arrays holding each pair's
/// four points (the point, then the triangle's corners) at t=0 and at t=1, gives ``(hit,
/// toi)`` as arrays of N (bool and float64, read-only). The pairs are tested without the GIL,
/// on every core (rayon's global pool, whose size ``RAYON_NUM_THREADS`` sets when the process
/// starts) or on ``threads`` threads; the result does not depend on the thread count. A batch
/// runs in chunks of about 20 ms: between two, ``timeout`` is checked and Ctrl-C
/// (``KeyboardInterrupt``) is seen.
///
/// The test is conservative: when the point touches the triangle (in exact arithmetic) at some
/// time in ``[0, tmax]``, ``hit`` is true and ``toi`` is never later than the first contact,
/// and at most ``tolerance`` earlier unless the features come close before they touch.
///
/// Args:
///     min_distance: distance (coordinate units, >= 0) at or below which the point and the
///         triangle count as touching. Default 0.
///     tmax: end of the interval searched, in (0, 1]. Default 1.
///     tolerance: time resolution, in (0, 1). Default 1e-6.
///     max_iterations: most boxes examined per pair, >= 1; a pair still undecided then is a
///         hit at the earliest time not ruled out (certainty code 1). Default 1,000,000.
///     certainty: also return the certainty code (an int, or a uint8 array): 0 resolved (or
///         no hit), 1 iteration limit, 2 invalid input (a non-finite coordinate: a hit at 0).
///     threads: a batch only: ``None`` (every core, or ``RAYON_NUM_THREADS``), or a count in
///         [1, 4096] (a pool of that size, kept for the process). Ignored for one pair.
///     timeout: a batch only: ``None``, or seconds (> 0) after which the batch stops and
///         raises ``TimeoutError`` (met within about 0.1 s). Ignored for one pair.
///
/// Raises:
///     InputError: a point of the wrong shape or dtype.
///     OptionsError: an option out of range.
///     TimeoutError: a batch still running after ``timeout``.
///     KeyboardInterrupt: Ctrl-C during a batch.
///     TypeError: neither eight points nor two arrays.
///
/// Example: a point falls through a triangle; it touches at t=0.5.
///     >>> import topoccd
///     >>> tri = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
///     >>> hit, toi = topoccd.point_triangle_ccd([0.2, 0.2, 1], *tri, [0.2, 0.2, -1], *tri)
///     >>> hit, round(toi, 4)
///     (True, 0.5)
#[pyfunction]
#[pyo3(signature = (
    *points, min_distance=0.0, tmax=1.0, tolerance=1e-6, max_iterations=1_000_000,
    certainty=false, threads=None, timeout=None
))]
#[allow(clippy::too_many_arguments)]
pub fn point_triangle_ccd<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyTuple>,
    min_distance: f64,
    tmax: f64,
    tolerance: f64,
    max_iterations: i64,
    certainty: bool,
    threads: Option<i64>,
    timeout: Option<f64>,
) -> PyResult<Bound<'py, PyTuple>> {
    let options = options(min_distance, tmax, tolerance, max_iterations)?;
    let limits = Batch::new(threads, timeout)?;
    run(py, Kind::PointTriangle, points, options, certainty, limits)
}

/// Continuous collision test of two edges, each end moving linearly from its ``_t0`` to its
/// ``_t1`` position, over ``[0, tmax]``; in the IPC toolkit's shape.
///
/// One pair: ``edge_edge_ccd(ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1,
/// eb1_t1)`` gives ``(hit, toi)``. A batch: ``edge_edge_ccd(x_t0, x_t1)``, two ``(N, 4, 3)``
/// arrays (edge a's ends, then edge b's), gives arrays of N. Keywords, result and errors as
/// :func:`point_triangle_ccd`.
///
/// Example: two edges cross at t=0.5, in a batch of one.
///     >>> import numpy as np, topoccd
///     >>> x_t0 = np.array([[[-1, 0, 0], [1, 0, 0], [0, -1, 1], [0, 1, 1]]], dtype=float)
///     >>> x_t1 = x_t0.copy(); x_t1[:, 2:, 2] = -1
///     >>> hit, toi = topoccd.edge_edge_ccd(x_t0, x_t1)
///     >>> hit.tolist(), toi.round(4).tolist()
///     ([True], [0.5])
#[pyfunction]
#[pyo3(signature = (
    *points, min_distance=0.0, tmax=1.0, tolerance=1e-6, max_iterations=1_000_000,
    certainty=false, threads=None, timeout=None
))]
#[allow(clippy::too_many_arguments)]
pub fn edge_edge_ccd<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyTuple>,
    min_distance: f64,
    tmax: f64,
    tolerance: f64,
    max_iterations: i64,
    certainty: bool,
    threads: Option<i64>,
    timeout: Option<f64>,
) -> PyResult<Bound<'py, PyTuple>> {
    let options = options(min_distance, tmax, tolerance, max_iterations)?;
    let limits = Batch::new(threads, timeout)?;
    run(py, Kind::EdgeEdge, points, options, certainty, limits)
}

/// Continuous collision test of a point against an edge (its interior and ends), each moving
/// linearly from its ``_t0`` to its ``_t1`` position, over ``[0, tmax]``; in the IPC toolkit's
/// shape, for free points and edges (particles, rods, hair).
///
/// One pair: ``point_edge_ccd(p_t0, e0_t0, e1_t0, p_t1, e0_t1, e1_t1)`` gives ``(hit, toi)``.
/// A batch: ``point_edge_ccd(x_t0, x_t1)``, two ``(N, 3, 3)`` arrays (the point, then the
/// edge's ends), gives arrays of N. It is the edge-edge test with the point as an edge of
/// length zero, with its guarantees. Keywords (``threads`` and ``timeout`` included), result and errors as
/// :func:`point_triangle_ccd`.
///
/// Example: a point falls across an edge at t=0.5.
///     >>> import topoccd
///     >>> e = [[-1, 0, 0], [1, 0, 0]]
///     >>> hit, toi = topoccd.point_edge_ccd([0.3, 0, 1], *e, [0.3, 0, -1], *e)
///     >>> hit, round(toi, 4)
///     (True, 0.5)
#[pyfunction]
#[pyo3(signature = (
    *points, min_distance=0.0, tmax=1.0, tolerance=1e-6, max_iterations=1_000_000,
    certainty=false, threads=None, timeout=None
))]
#[allow(clippy::too_many_arguments)]
pub fn point_edge_ccd<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyTuple>,
    min_distance: f64,
    tmax: f64,
    tolerance: f64,
    max_iterations: i64,
    certainty: bool,
    threads: Option<i64>,
    timeout: Option<f64>,
) -> PyResult<Bound<'py, PyTuple>> {
    let options = options(min_distance, tmax, tolerance, max_iterations)?;
    let limits = Batch::new(threads, timeout)?;
    run(py, Kind::PointEdge, points, options, certainty, limits)
}

/// Continuous collision test of two points, each moving linearly from its ``_t0`` to its
/// ``_t1`` position, over ``[0, tmax]``; in the IPC toolkit's shape, for free points
/// (particles). They touch only within ``min_distance``, or where their paths cross.
///
/// One pair: ``point_point_ccd(p0_t0, p1_t0, p0_t1, p1_t1)`` gives ``(hit, toi)``. A batch:
/// ``point_point_ccd(x_t0, x_t1)``, two ``(N, 2, 3)`` arrays. Keywords, result and errors as
/// :func:`point_triangle_ccd`.
///
/// Example: two particles meet head on at t=0.25.
///     >>> import topoccd
///     >>> hit, toi = topoccd.point_point_ccd([-1, 0, 0], [1, 0, 0], [3, 0, 0], [-3, 0, 0])
///     >>> hit, round(toi, 4)
///     (True, 0.25)
#[pyfunction]
#[pyo3(signature = (
    *points, min_distance=0.0, tmax=1.0, tolerance=1e-6, max_iterations=1_000_000,
    certainty=false, threads=None, timeout=None
))]
#[allow(clippy::too_many_arguments)]
pub fn point_point_ccd<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyTuple>,
    min_distance: f64,
    tmax: f64,
    tolerance: f64,
    max_iterations: i64,
    certainty: bool,
    threads: Option<i64>,
    timeout: Option<f64>,
) -> PyResult<Bound<'py, PyTuple>> {
    let options = options(min_distance, tmax, tolerance, max_iterations)?;
    let limits = Batch::new(threads, timeout)?;
    run(py, Kind::PointPoint, points, options, certainty, limits)
}
