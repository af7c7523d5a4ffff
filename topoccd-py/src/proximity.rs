//! The proximity query from Python: `Ccd.proximity` (and `topoccd.proximity`, its one-shot
//! form in `python/topoccd/__init__.py`), with the `Proximity` result of numpy arrays.

use std::time::{Duration, Instant};

use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use topoccd::{Configuration, ProximityError, ProximityOptions, ProximityReport, StopReason};

use crate::ccd::{watched, Ccd};
use crate::errors::{input_error, options_error};
use crate::input::{indices, positions, rows};
use crate::report::{array1, array2};

/// The primitive pairs of one configuration closer than ``dhat + dmin``, as numpy arrays.
///
/// Each kind is sorted by its indices (the same for any ``threads``). Distances are not
/// squared. Types are small integers naming the closest features, in the IPC toolkit's
/// order: see ``topoccd.POINT_TRIANGLE_TYPES``, ``EDGE_EDGE_TYPES``, ``POINT_EDGE_TYPES``.
///
/// Attributes:
///     vf (numpy.ndarray): ``(N, 2)`` int64, ``(vertex, face)``.
///     vf_distance (numpy.ndarray): ``(N,)`` float64.
///     vf_type (numpy.ndarray): ``(N,)`` uint8: 0-2 a corner ``P_T0..P_T2``, 3-5 an edge
///         ``P_E0..P_E2`` (edge k from corner k to k+1), 6 the interior ``P_T``.
///     ee (numpy.ndarray): ``(M, 4)`` int64, ``(a0, a1, b0, b1)`` as the CCD report writes
///         them (``a0 < a1``, ``b0 < b1``, ``(a0, a1) < (b0, b1)``).
///     ee_distance (numpy.ndarray): ``(M,)`` float64.
///     ee_type (numpy.ndarray): ``(M,)`` uint8, ``EA0_EB0`` (0) to ``EA_EB`` (8).
///     ve (numpy.ndarray): ``(K, 3)`` int64, ``(vertex, e0, e1)``: a free point (in no
///         triangle and no edge) and a free edge (a free point near a triangle's edge is a
///         vertex-face pair).
///     ve_distance (numpy.ndarray): ``(K,)`` float64.
///     ve_type (numpy.ndarray): ``(K,)`` uint8: 0 ``P_E0``, 1 ``P_E1``, 2 ``P_E``.
///     vv (numpy.ndarray): ``(L, 2)`` int64, two free points, ``a < b``.
///     vv_distance (numpy.ndarray): ``(L,)`` float64.
///     vv_type (numpy.ndarray): ``(L,)`` uint8, always 0 (``P_P``).
///     truncated (str or None): ``"max_contacts"`` when ``max_contacts`` cut the report.
///     refitted (bool): whether the ``Ccd``'s hierarchy was refitted rather than built.
///     reused (bool): whether the ``Ccd`` evaluated the candidates it kept from a former
///         query (the positions had moved less than its margin) instead of traversing.
///     seconds (float): the query's wall time in the library.
#[pyclass(module = "topoccd", frozen)]
pub struct Proximity {
    #[pyo3(get)]
    vf: Py<PyArray2<i64>>,
    #[pyo3(get)]
    vf_distance: Py<PyArray1<f64>>,
    #[pyo3(get)]
    vf_type: Py<PyArray1<u8>>,
    #[pyo3(get)]
    ee: Py<PyArray2<i64>>,
    #[pyo3(get)]
    ee_distance: Py<PyArray1<f64>>,
    #[pyo3(get)]
    ee_type: Py<PyArray1<u8>>,
    #[pyo3(get)]
    ve: Py<PyArray2<i64>>,
    #[pyo3(get)]
    ve_distance: Py<PyArray1<f64>>,
    #[pyo3(get)]
    ve_type: Py<PyArray1<u8>>,
    #[pyo3(get)]
    vv: Py<PyArray2<i64>>,
    #[pyo3(get)]
    vv_distance: Py<PyArray1<f64>>,
    #[pyo3(get)]
    vv_type: Py<PyArray1<u8>>,
    #[pyo3(get)]
    truncated: Option<&'static str>,
    #[pyo3(get)]
    refitted: bool,
    #[pyo3(get)]
    reused: bool,
    #[pyo3(get)]
    seconds: f64,
}

#[pymethods]
impl Proximity {
    /// The number of pairs of all kinds.
    fn __len__(&self, py: Python<'_>) -> usize {
        let n = |a: &Py<PyArray1<f64>>| a.bind(py).len();
        n(&self.vf_distance) + n(&self.ee_distance) + n(&self.ve_distance) + n(&self.vv_distance)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let n = |a: &Py<PyArray1<f64>>| a.bind(py).len();
        format!(
            "<topoccd.Proximity vf={} ee={} ve={} vv={}>",
            n(&self.vf_distance),
            n(&self.ee_distance),
            n(&self.ve_distance),
            n(&self.vv_distance)
        )
    }
}

use numpy::PyUntypedArrayMethods;

impl Proximity {
    fn new(py: Python<'_>, r: &ProximityReport) -> PyResult<Self> {
        let i = |v: u32| v as i64;
        let flat_vf: Vec<i64> = r.vf.iter().flat_map(|p| [i(p.vertex), i(p.face)]).collect();
        let flat_ee: Vec<i64> = (r.ee.iter())
            .flat_map(|p| [i(p.a[0]), i(p.a[1]), i(p.b[0]), i(p.b[1])])
            .collect();
        let flat_ve: Vec<i64> = (r.ve.iter())
            .flat_map(|p| [i(p.vertex), i(p.edge[0]), i(p.edge[1])])
            .collect();
        let flat_vv: Vec<i64> = r.vv.iter().flat_map(|p| [i(p.a), i(p.b)]).collect();
        Ok(Self {
            vf: array2(py, r.vf.len(), 2, flat_vf)?,
            vf_distance: array1(py, r.vf.iter().map(|p| p.distance).collect()),
            vf_type: array1(py, r.vf.iter().map(|p| p.kind as u8).collect()),
            ee: array2(py, r.ee.len(), 4, flat_ee)?,
            ee_distance: array1(py, r.ee.iter().map(|p| p.distance).collect()),
            ee_type: array1(py, r.ee.iter().map(|p| p.kind as u8).collect()),
            ve: array2(py, r.ve.len(), 3, flat_ve)?,
            ve_distance: array1(py, r.ve.iter().map(|p| p.distance).collect()),
            ve_type: array1(py, r.ve.iter().map(|p| p.kind as u8).collect()),
            vv: array2(py, r.vv.len(), 2, flat_vv)?,
            vv_distance: array1(py, r.vv.iter().map(|p| p.distance).collect()),
            vv_type: array1(py, vec![0u8; r.vv.len()]),
            truncated: r.truncated.map(|_| "max_contacts"),
            refitted: r.stats.refitted,
            reused: r.stats.reused,
            seconds: r.stats.total_seconds,
        })
    }
}

fn library_error(e: ProximityError) -> PyErr {
    match e {
        ProximityError::Dhat(_) | ProximityError::Dmin(_) => options_error(e.to_string()),
        ProximityError::OutOfMemory { .. } => crate::errors::memory_error(e.to_string()),
        _ => input_error(e.to_string()),
    }
}

/// `Ccd.proximity`: see its docstring in `ccd.rs`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn ccd_proximity(
    slf: &Bound<'_, Ccd>,
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
) -> PyResult<Proximity> {
    let started = Instant::now();
    let threads = match threads {
        None => None,
        Some(n) if (1..=4096).contains(&n) => Some(n as usize),
        Some(n) => {
            return Err(options_error(format!(
                "threads must be None or in [1, 4096], got {n}"
            )))
        }
    };
    let max_contacts = match max_contacts {
        None => None,
        Some(n) if n >= 0 => Some(n as usize),
        Some(n) => return Err(options_error(format!("max_contacts must be >= 0, got {n}"))),
    };
    if let Some(t) = timeout {
        if !(t.is_finite() && t >= 0.0) {
            return Err(options_error(format!(
                "timeout must be finite and >= 0 seconds, got {t}"
            )));
        }
    }
    let p = positions(x, "x")?;
    let tris = rows::<3>(&indices(triangles, "triangles", Some(3))?);
    let edge_rows = match edges {
        Some(e) => rows::<2>(&indices(e, "edges", Some(2))?),
        None => Vec::new(),
    };
    let group_ids = match groups {
        Some(g) => Some(indices(g, "groups", None)?),
        None => None,
    };
    let flat = p.as_flat()?;
    let options = ProximityOptions {
        dhat,
        dmin,
        max_contacts,
        deadline: timeout.map(|t| started + Duration::from_secs_f64(t)),
        ..ProximityOptions::default()
    };
    options.validate().map_err(library_error)?;
    let config = Configuration::new(flat, &tris[..], &edge_rows).map_err(library_error)?;
    let config = match &group_ids {
        Some(g) => config.with_groups(g).map_err(library_error)?,
        None => config,
    };
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
    let token = inner.cancel_token();
    token.reset();
    let report = watched(py, pool, &token, || match pool {
        Some(pool) => pool.install(|| inner.proximity(&config, &options)),
        None => inner.proximity(&config, &options),
    })?
    .map_err(library_error)?;
    if matches!(
        report.truncated,
        Some(StopReason::Deadline | StopReason::Cancelled)
    ) {
        return Err(pyo3::exceptions::PyTimeoutError::new_err(format!(
            "the proximity query did not finish within timeout={} s (found {} pairs by then)",
            timeout.unwrap_or_default(),
            report.len()
        )));
    }
    Proximity::new(py, &report)
}
