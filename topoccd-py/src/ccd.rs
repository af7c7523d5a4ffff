//! The `Ccd` class: one query per simulation step, buffers kept across steps, the GIL released
//! while the library works.

use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant};

use pyo3::prelude::*;
use topoccd::io::{input_warnings, InputWarning};
use topoccd::{Ccd as LibCcd, Report as LibReport, Step, StepError, StopReason};

use crate::errors::{input_error, memory_error, options_error, warn_input};
use crate::input::{indices, positions, rows};
use crate::options::Keywords;
use crate::report::{Report, StepFacts};

/// A reusable continuous-collision-detection query.
///
/// Keep one ``Ccd`` for the whole simulation and call :meth:`query` once per step: its buffers
/// (swept volumes, hierarchy nodes, candidate lists) and its thread pool are reused. One
/// ``Ccd`` runs one query at a time (a second thread calling ``query`` on the same object while
/// a query runs gets ``RuntimeError``); use one ``Ccd`` per thread.
///
/// Example: a triangle falls through a fixed one; its lowest vertex touches at t=0.5.
///     >>> import numpy as np, topoccd
///     >>> fixed = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
///     >>> falling = np.array([[0.2, 0.2, 1], [0.3, 0.2, 1.5], [0.2, 0.3, 1.5]])
///     >>> x0 = np.vstack([fixed, falling]); x1 = np.vstack([fixed, falling - [0, 0, 2]])
///     >>> tris = np.array([[0, 1, 2], [3, 4, 5]])
///     >>> ccd = topoccd.Ccd()
///     >>> r = ccd.query(x0, x1, tris)
///     >>> r.vf.tolist(), r.vf_toi.round(4).tolist(), r.earliest[:3]
///     ([[3, 0], [4, 0], [5, 0]], [0.5, 0.75, 0.75], ('vf', 3, 0))
#[pyclass(module = "topoccd")]
pub struct Ccd {
    pub(crate) inner: LibCcd,
    /// The thread pool of the last `threads=N` query, kept for the next.
    pub(crate) pool: Option<(usize, rayon::ThreadPool)>,
}

impl Ccd {
    /// Builds the thread pool for `threads`, unless the one kept has that many threads.
    pub(crate) fn ensure_pool(&mut self, threads: usize) -> PyResult<()> {
        if self.pool.as_ref().map(|(n, _)| *n) != Some(threads) {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| {
                    pyo3::exceptions::PyRuntimeError::new_err(format!(
                        "cannot start {threads} threads: {e}"
                    ))
                })?;
            self.pool = Some((threads, pool));
        }
        Ok(())
    }
}

/// The step's arrays, once converted.
struct Arrays<'a> {
    x0: &'a [f64],
    x1: &'a [f64],
    triangles: &'a [u32],
    parents: Option<&'a [[u32; 2]]>,
    groups: Option<&'a [u32]>,
    edges: Option<&'a [[u32; 2]]>,
}

/// Builds the step: the input checked, and its warnings found (the GIL released).
fn build<'a>(a: &Arrays<'a>) -> Result<(Step<'a>, Vec<InputWarning>), Failure> {
    let step = match a.parents {
        Some(parents) => Step::with_parents(a.x0, a.x1, a.triangles, parents),
        None => Step::new(a.x0, a.x1, a.triangles),
    }
    .map_err(Failure::Step)?;
    let step = match a.groups {
        Some(g) => step.with_groups(g).map_err(Failure::Step)?,
        None => step,
    };
    let step = match a.edges {
        Some(e) => step.with_edges(e).map_err(Failure::Step)?,
        None => step,
    };
    // The input as given: the positions at t=0 of the vertices that exist then (the new
    // vertices of a topology change start on their parents by design).
    let (old, _) = a.x0.as_chunks::<3>();
    let warnings = input_warnings(old, step.triangles());
    Ok((step, warnings))
}

/// Queries the step (without the GIL).
fn run(
    ccd: &mut LibCcd,
    pool: Option<&rayon::ThreadPool>,
    step: &Step<'_>,
    method: topoccd::Method,
    options: &topoccd::QueryOptions,
) -> Result<(LibReport, usize, usize), Failure> {
    let x0_address = step.x0().as_ptr() as usize;
    let x1_address = step.x1().as_ptr() as usize;
    let mut go = || ccd.query(step, method, options);
    let report = match pool {
        Some(pool) => pool.install(go),
        None => go(),
    }
    .map_err(|e| match e {
        topoccd::OptionsError::OutOfMemory { .. } => Failure::Memory(e.to_string()),
        _ => Failure::Options(e.to_string()),
    })?;
    Ok((report, x0_address, x1_address))
}

/// How often the calling thread looks for a pending signal (Ctrl-C) while a query runs.
const SIGNAL_POLL: Duration = Duration::from_millis(20);

/// Runs `query` as a job of the thread pool (`pool`, else rayon's global pool) while this
/// thread, the caller's (the main thread, where Python runs signal handlers), waits without the
/// GIL and checks for signals every [`SIGNAL_POLL`]: a `KeyboardInterrupt` (or any exception a
/// handler raises) cancels the query through `token`, which stops within about a millisecond
/// of work per thread; the exception is returned once the query has stopped. (A job of the
/// pool, not a thread of its own: nothing is started per query.)
pub(crate) fn watched<T: Send>(
    py: Python<'_>,
    pool: Option<&rayon::ThreadPool>,
    token: &topoccd::CancelToken,
    query: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let signal = (Mutex::new(false), Condvar::new());
    let slot = Mutex::new(None);
    let mut interrupted = None;
    let state = (&signal, &slot, token);
    // (A panic of the job resumes here, once the scope is over.)
    match pool {
        Some(pool) => pool.in_place_scope(|s| watch(py, s, state, query, &mut interrupted)),
        None => rayon::in_place_scope(|s| watch(py, s, state, query, &mut interrupted)),
    }
    if let Some(e) = interrupted {
        return Err(e);
    }
    let out = slot.into_inner().unwrap_or_else(|e| e.into_inner());
    out.ok_or_else(|| pyo3::exceptions::PyRuntimeError::new_err("the query did not run"))
}

/// Set by the job of [`watched`] when it is done (also when it panics: the guard's drop).
struct Done<'a>(&'a (Mutex<bool>, Condvar));

impl Drop for Done<'_> {
    fn drop(&mut self) {
        let (flag, wake) = self.0;
        *flag.lock().unwrap_or_else(|e| e.into_inner()) = true;
        wake.notify_all();
    }
}

/// The body of [`watched`]'s scope: spawns the job, then waits and watches.
#[allow(clippy::type_complexity)]
fn watch<'scope, T: Send + 'scope>(
    py: Python<'_>,
    scope: &rayon::Scope<'scope>,
    (signal, slot, token): (
        &'scope (Mutex<bool>, Condvar),
        &'scope Mutex<Option<T>>,
        &topoccd::CancelToken,
    ),
    query: impl FnOnce() -> T + Send + 'scope,
    interrupted: &mut Option<PyErr>,
) {
    scope.spawn(move |_| {
        let _done = Done(signal);
        let out = query();
        *slot.lock().unwrap_or_else(|e| e.into_inner()) = Some(out);
    });
    loop {
        let over = py.detach(|| {
            let (flag, wake) = signal;
            let guard = flag.lock().unwrap_or_else(|e| e.into_inner());
            let (guard, _) = wake
                .wait_timeout_while(guard, SIGNAL_POLL, |done| !*done)
                .unwrap_or_else(|e| e.into_inner());
            *guard
        });
        if over {
            break;
        }
        if interrupted.is_none() {
            if let Err(e) = py.check_signals() {
                token.cancel();
                *interrupted = Some(e);
            }
        }
    }
}

/// Why a query failed, carried out of the GIL-free section.
enum Failure {
    Step(StepError),
    Options(String),
    /// An allocation the system refused (a `MemoryError`).
    Memory(String),
}

impl Failure {
    fn into_py(self) -> PyErr {
        match self {
            Failure::Step(StepError::LengthMismatch { start, end }) => input_error(format!(
                "x0 has {start} rows but x1 has {end}: a step needs the same vertices at \
                     t=0 and t=1 (for a topology change that appends vertices, give their \
                     parents: parents=[[child, parent], ...], or an empty (0, 2) array for new \
                     vertices that do not move)"
            )),
            Failure::Step(e @ StepError::OutOfMemory { .. }) => memory_error(e.to_string()),
            Failure::Step(e) => input_error(e.to_string()),
            Failure::Options(m) => options_error(m),
            Failure::Memory(m) => memory_error(m),
        }
    }
}

#[pymethods]
impl Ccd {
    /// A new query object; nothing is allocated until the first query.
    #[new]
    fn new() -> Self {
        Ccd {
            inner: LibCcd::new(),
            pool: None,
        }
    }

    /// Every contact of one step (or only the earliest), between positions ``x0`` at t=0 and
    /// ``x1`` at t=1 moving linearly.
    ///
    /// Args:
    ///     x0: ``(n0, 3)`` positions at t=0, any real dtype, any memory order. A float64
    ///         C-contiguous array is read in place (no copy); anything else is converted once.
    ///     x1: ``(n, 3)`` positions at t=1; ``n == n0`` unless ``parents`` is given.
    ///     triangles: ``(m, 3)`` vertex indices (any integer dtype), the step's faces.
    ///     parents: optional ``(k, 2)`` integer rows ``[child, parent]`` for a topology change
    ///         (a cut or fracture duplicating vertices): ``n0 <= n``, a new vertex (index
    ///         ``>= n0``) starts at its parent's ``x0`` position (without a parent, it does not
    ///         move). A child and its parent count as one vertex for ``crack_filter``.
    ///     edges: optional ``(E, 2)`` integer edges for codimensional geometry (rods, hair,
    ///         yarn, particles): those in no triangle are free edges, and, once ``edges`` is
    ///         given (even empty), vertices in no triangle and no edge are free points. The
    ///         report's ``ve`` (point, edge) and ``vv`` (point, point) hold their extra pairs.
    ///     groups: optional ``(n,)`` integer group id per vertex. Two features are tested only
    ///         if some vertex of one and some vertex of the other are in different groups (the
    ///         ``can_collide`` rule of ipctk): give each rigid or non-self-colliding object one id.
    ///     method: ``"auto"`` (the default: ``"bvh"`` below 100,000 triangles, ``"cluster"``
    ///         above; ``stats["method"]`` says which ran), ``"bvh"`` (a k-DOP hierarchy built
    ///         per step), ``"cluster"`` (the paper's certified clusters: measured 1.1 to 2
    ///         times faster than ``"bvh"`` where clusters hold hundreds of triangles, as on
    ///         thin shells, smooth bodies and their fragments, and 0.75 to 0.9 times as fast on
    ///         crumpled cloth) or ``"brute"`` (the sweep-and-prune oracle). All report the
    ///         same pairs, but for a near miss within ``tolerance`` (or a pair given up on)
    ///         inside a certified cluster, which ``"cluster"`` proves apart and leaves out.
    ///     mode: ``"all"`` (every colliding pair) or ``"earliest"`` (only the pair or pairs
    ///         within ``tolerance`` of the earliest time: faster, for a line search). Earliest
    ///         reports contacts of ``"all"``, unchanged, but may leave out a near miss within
    ///         ``tolerance`` (or a pair given up on) that its shorter search proves apart
    ///         (with coordinates of 1e300 beside coordinates of 1, the rounding of the large
    ///         ones counts as within: such a pair may touch only later).
    ///     tolerance: time resolution of the elementary tests, in (0, 1). Reported times are
    ///         never later than the true first contact and at most this much earlier, unless
    ///         the features come that close (relative to their displacement, plus rounding)
    ///         before they touch.
    ///     min_distance: distance (coordinate units, >= 0) at or below which features count
    ///         as touching.
    ///     tmax: only contacts at times in ``[0, tmax]``, ``tmax`` in (0, 1].
    ///     max_iterations: per elementary test, >= 1; a pair still undecided then is reported
    ///         with certainty code 1.
    ///     k: bounding volumes are k-DOPs, k in {6, 14, 18, 26}.
    ///     growth: ``method="cluster"`` only: ``"certificate"`` or ``"paper"``; ``None`` for the
    ///         library's default.
    ///     threads: ``None`` for one thread per core, or a count (a pool kept by this object).
    ///     geometry: also compute the contact points, normals and barycentric coordinates.
    ///     crack_filter: skip pairs of features that share a vertex or a vertex's crack twin
    ///         (``parents``); on by default.
    ///     max_contacts: the most contacts the report keeps (an int ``>= 0``; default
    ///         ``1_000_000``, :data:`topoccd.DEFAULT_MAX_CONTACTS`, as in Rust), or ``None``
    ///         for no limit (memory then grows with the contacts). Once the step is known to
    ///         have more, the query stops and
    ///         ``report.truncated`` says so; the report then holds the first ``max_contacts``
    ///         contacts of the query's fixed order of work, the same for any ``threads``. With
    ///         ``mode="earliest"`` the earliest time stays exact (the query truncates only
    ///         once it knows that time is 0) and the pairs are the first ``max_contacts``
    ///         within ``tolerance`` of it; before that it keeps the ``max_contacts`` earliest
    ///         pairs, and ``report.earliest_complete`` says whether every pair within
    ///         ``tolerance`` of the earliest time is listed. Memory stays within a few times ``max_contacts``
    ///         contacts: a collapsed mesh (positions cast to integers) can have hundreds of
    ///         millions at t=0.
    ///     timeout: ``None``, or seconds (> 0) after which the query stops and raises
    ///         ``TimeoutError`` (within about a millisecond of work per thread).
    ///
    /// The old keywords ``min_separation`` and ``t_max`` still work for one release, with a
    /// ``DeprecationWarning`` naming the new one.
    ///
    /// Ctrl-C (``KeyboardInterrupt``) stops a running query, typically within a tenth of a
    /// second: the query runs as a job of the thread pool while the calling thread waits
    /// without the GIL and checks for signals every 20 ms.
    ///
    /// Before the query runs, input that is valid but likely a mistake is warned about
    /// (:class:`InputWarning`, with ``warnings.warn``): vertices of ``x0`` that sit exactly on
    /// one another, triangles of zero area, and every coordinate a whole number on such a
    /// degenerate mesh (positions cast to integers); each warning names how many, the first
    /// few and the likely cause, as the command line's do.
    ///
    /// Returns:
    ///     Report: numpy arrays of the pairs and their times; see :class:`Report`.
    ///
    /// Raises:
    ///     InputError: an array of the wrong shape or dtype, a non-finite coordinate, an
    ///         index out of range, ``x0`` shorter than ``x1`` without ``parents``, a bad
    ///         parent row (a child that is not new, a parent that is not old, a child twice)
    ///         or groups array (the message names the element).
    ///     OptionsError: an option out of range.
    ///     TimeoutError: ``timeout`` passed before the query finished.
    ///     KeyboardInterrupt: Ctrl-C while the query ran.
    #[pyo3(signature = (
        x0, x1, triangles, *, parents=None, groups=None, edges=None, method="auto", mode="all",
        tolerance=1e-6, min_distance=0.0, tmax=1.0, max_iterations=1_000_000, k=18,
        growth=None, threads=None, geometry=false, crack_filter=true,
        max_contacts=Some(topoccd::DEFAULT_MAX_CONTACTS as i64), timeout=None, **deprecated
    ))]
    #[allow(clippy::too_many_arguments)]
    fn query(
        slf: &Bound<'_, Self>,
        py: Python<'_>,
        x0: &Bound<'_, PyAny>,
        x1: &Bound<'_, PyAny>,
        triangles: &Bound<'_, PyAny>,
        parents: Option<&Bound<'_, PyAny>>,
        groups: Option<&Bound<'_, PyAny>>,
        edges: Option<&Bound<'_, PyAny>>,
        method: &str,
        mode: &str,
        tolerance: f64,
        min_distance: f64,
        tmax: f64,
        max_iterations: i64,
        k: i64,
        growth: Option<&str>,
        threads: Option<i64>,
        geometry: bool,
        crack_filter: bool,
        max_contacts: Option<i64>,
        timeout: Option<f64>,
        deprecated: Option<&Bound<'_, pyo3::types::PyDict>>,
    ) -> PyResult<Report> {
        let started = Instant::now();
        let (mut min_distance, mut tmax) = (min_distance, tmax);
        crate::deprecated::renamed(py, "query", deprecated, &mut min_distance, &mut tmax)?;
        let keywords = Keywords {
            method,
            mode,
            tolerance,
            min_distance,
            tmax,
            max_iterations,
            k,
            growth,
            geometry,
            crack_filter,
            max_contacts,
            timeout,
        };
        let (method, mut options) = keywords.resolve()?;
        let threads = match threads {
            None => None,
            Some(n) if (1..=4096).contains(&n) => Some(n as usize),
            Some(n) => {
                return Err(options_error(format!(
                    "threads must be None or in [1, 4096], got {n}"
                )))
            }
        };
        let p0 = positions(x0, "x0")?;
        let p1 = positions(x1, "x1")?;
        let tris = indices(triangles, "triangles", Some(3))?;
        let parent_rows = match parents {
            Some(p) => Some(rows::<2>(&indices(p, "parents", Some(2))?)),
            None => None,
        };
        let group_ids = match groups {
            Some(g) => Some(indices(g, "groups", None)?),
            None => None,
        };
        let edge_rows = match edges {
            Some(e) => Some(rows::<2>(&indices(e, "edges", Some(2))?)),
            None => None,
        };
        let arrays = Arrays {
            edges: edge_rows.as_deref(),
            x0: p0.as_flat()?,
            x1: p1.as_flat()?,
            triangles: &tris,
            parents: parent_rows.as_deref(),
            groups: group_ids.as_deref(),
        };
        let borrowed = (p0.borrowed, p1.borrowed);
        let mut this = slf.try_borrow_mut().map_err(|_| {
            pyo3::exceptions::PyRuntimeError::new_err(
                "this Ccd is running a query in another thread; use one Ccd per thread",
            )
        })?;
        if let Some(n) = threads {
            this.ensure_pool(n)?;
        }
        let Ccd { inner, pool } = &mut *this;
        let pool = match threads {
            Some(_) => pool.as_ref().map(|(_, p)| p),
            None => None,
        };
        let (step, warnings) = py.detach(|| build(&arrays)).map_err(Failure::into_py)?;
        for w in &warnings {
            warn_input(py, &w.to_string())?;
        }
        let token = inner.cancel_token();
        token.reset();
        // The deadline counts from the call, input conversion included.
        options.deadline = timeout.map(|t| started + Duration::from_secs_f64(t));
        let outcome = watched(py, pool, &token, || {
            run(inner, pool, &step, method, &options)
        })?;
        let (report, x0_address, x1_address) = outcome.map_err(Failure::into_py)?;
        if let Some(t) = report
            .truncated
            .filter(|t| t.reason != StopReason::MaxContacts)
        {
            let seconds = timeout.unwrap_or_default();
            return Err(pyo3::exceptions::PyTimeoutError::new_err(format!(
                "the query did not finish within timeout={seconds} s: it stopped after {:.3} s \
                 ({}), having found {} contacts; a collapsed or huge step (see the warnings) \
                 can take long: max_contacts=N ends it early with the first N contacts",
                started.elapsed().as_secs_f64(),
                match t.reason {
                    StopReason::Deadline => "deadline",
                    _ => "cancelled",
                },
                report.contact_count(),
            )));
        }
        let facts = StepFacts {
            vertices: p1.rows(),
            triangles: tris.len() / 3,
            x0_address,
            x1_address,
            borrowed,
            geometry: options.geometry,
        };
        Report::new(py, &report, &facts)
    }

    /// Every primitive pair of one configuration closer than ``dhat + dmin``: vertex-face,
    /// edge-edge (triangles' edges and free ``edges``), free point-free edge and free point-free
    /// point, with distances and closest-feature types. Keeps the hierarchy in this ``Ccd``:
    /// call it every solver iteration with the same triangles and edges, and it is refitted,
    /// not rebuilt.
    ///
    /// Args:
    ///     x: ``(n, 3)`` float positions.
    ///     triangles: ``(m, 3)`` integer triangles (``(0, 3)`` for none).
    ///     dhat: the distance threshold, > 0.
    ///     edges: ``(k, 2)`` free edges (rods, hair); edges of the triangles may be given too,
    ///         they count once. Vertices in no triangle and no edge are free points.
    ///     dmin: the minimum distance offset, >= 0: pairs closer than ``dhat + dmin``.
    ///     groups: one id per vertex; features whose vertices share one group are not paired.
    ///     max_contacts: keep at most this many pairs (``truncated`` says so); one million by
    ///         default, as every other query; ``None`` lifts the cap. A query under the cap
    ///         keeps its pairs for the next call's reuse.
    ///     timeout: seconds; ``TimeoutError`` after it.
    ///     threads: ``None`` for one thread per core, or a count.
    ///
    /// Returns:
    ///     Proximity: numpy arrays per kind (see :class:`Proximity`).
    ///
    /// A pair can repeat. Every primitive pair is reported by its closest features, so a
    /// vertex near an edge or a corner of the mesh comes back once for each face around that
    /// edge or corner (``vf`` rows with types ``P_E*`` or ``P_T0..2``), and two edges near at
    /// a shared corner likewise. The collision set of the potentials (``topoccd.ipc``, the
    /// library's ``topoccd::ipc::NormalCollisions``) merges repeats into one collision with
    /// their count as its multiplicity, as the IPC toolkit does.
    ///
    /// Example: a vertex 0.5e-3 above a triangle.
    ///     >>> import topoccd
    ///     >>> x = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, 0.5e-3]]
    ///     >>> p = topoccd.Ccd().proximity(x, [[0, 1, 2]], 1e-3)
    ///     >>> p.vf.tolist(), p.vf_distance.round(6).tolist(), p.vf_type.tolist()
    ///     ([[3, 0]], [0.0005], [6])
    #[pyo3(signature = (
        x, triangles, dhat, *, edges=None, dmin=0.0, groups=None,
        max_contacts=Some(topoccd::DEFAULT_MAX_CONTACTS as i64), timeout=None, threads=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn proximity(
        slf: &Bound<'_, Self>,
        py: Python<'_>,
        x: &Bound<'_, PyAny>,
        triangles: &Bound<'_, PyAny>,
        dhat: f64,
        edges: Option<&Bound<'_, PyAny>>,
        dmin: f64,
        groups: Option<&Bound<'_, PyAny>>,
        max_contacts: Option<i64>,
        timeout: Option<f64>,
        threads: Option<i64>,
    ) -> PyResult<crate::proximity::Proximity> {
        crate::proximity::ccd_proximity(
            slf,
            py,
            x,
            triangles,
            dhat,
            edges,
            dmin,
            groups,
            max_contacts,
            timeout,
            threads,
        )
    }

    fn __repr__(&self) -> String {
        match &self.pool {
            Some((n, _)) => format!("<topoccd.Ccd with a pool of {n} threads>"),
            None => "<topoccd.Ccd>".to_string(),
        }
    }
}
