//! numpy arrays out: the `Report` class.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::PathBuf;

use numpy::ndarray::{Array1, Array2};
use numpy::prelude::*;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use topoccd::{Certainty, Contact, Report as LibReport};

use crate::errors::input_error;

/// The result of one CCD query, as numpy arrays.
///
/// Attributes:
///     vf (numpy.ndarray): ``(N, 2)`` int64, the colliding vertex-face pairs ``(vertex, face)``,
///         sorted; ``face`` indexes the rows of ``triangles``.
///     vf_toi (numpy.ndarray): ``(N,)`` float64, each pair's time of impact in ``[0, tmax]``
///         (never later than the true first contact; at most ``tolerance`` earlier).
///     vf_certainty (numpy.ndarray): ``(N,)`` uint8: 0 resolved, 1 the iteration limit was
///         reached (the pair is reported conservatively), 2 invalid input (non-finite
///         arithmetic; reported conservatively).
///     ee (numpy.ndarray): ``(M, 4)`` int64, the colliding edge-edge pairs
///         ``(a0, a1, b0, b1)`` with ``a0 < a1``, ``b0 < b1`` and ``(a0, a1) < (b0, b1)``, sorted.
///     ee_toi (numpy.ndarray): ``(M,)`` float64.
///     ee_certainty (numpy.ndarray): ``(M,)`` uint8, as ``vf_certainty``.
///     ve, ve_toi, ve_certainty, vv, vv_toi, vv_certainty (numpy.ndarray): the same for a free
///         point against a free edge, ``(K, 3)`` ``(vertex, e0, e1)``, and for two free
///         points, ``(L, 2)`` ``(a, b)`` (with ``edges=``; see the codimensional guide page).
///     vf_barycentric, vf_point, vf_normal (numpy.ndarray or None): ``(N, 3)`` float64 with
///         ``geometry=True``: the barycentric coordinates of the contact on the face (of its
///         three vertices at the time of impact), the contact point, and the unit normal from
///         the face towards the vertex's side. ``None`` otherwise.
///     ee_params (numpy.ndarray or None): ``(M, 2)`` float64 with ``geometry=True``: the
///         contact's position along each edge, in ``[0, 1]`` from ``a0`` to ``a1`` and from
///         ``b0`` to ``b1``.
///     ee_point, ee_normal (numpy.ndarray or None): ``(M, 3)``: contact point and unit normal
///         from edge b towards edge a.
///     earliest_toi (float or None): the earliest time of impact of the step; ``None`` when
///         nothing collides. Use ``0.8 * earliest_toi`` (say) as the line-search step bound.
///     earliest (tuple or None): the pair attaining it, ``("vf", vertex, face, toi)`` or
///         ``("ee", a0, a1, b0, b1, toi)``.
///     unresolved (int): contacts whose certainty is not 0.
///     earliest_complete (bool): whether the report lists every pair within ``tolerance`` of
///         the earliest time (every contact, with ``mode="all"``): ``False`` when the query
///         was truncated, or when ``mode="earliest"`` found more such pairs than
///         ``max_contacts`` and kept the earliest of them (the earliest time is exact
///         either way).
///     truncated (dict or None): ``None`` when the query ran to its end; with
///         ``max_contacts``, once the step had more contacts: ``{"reason": "max_contacts",
///         "phase": "candidates", "tasks": K}``, the report holding the first
///         ``max_contacts`` contacts, found in the first ``K`` units of the query's fixed order
///         of work (its traversal tasks), the same for any thread count.
///     stats (dict): ``method`` (the method that ran: what ``"auto"`` chose), and work
///         counters: ``bv_tests``, ``vf_tests``, ``ee_tests``,
///         ``peak_candidates`` (the most candidate pairs buffered at once), ``vertices``,
///         ``triangles``, and ``cluster`` (a dict, ``method="cluster"`` only).
///     seconds (dict): wall time of each phase: ``build``, ``traverse``, ``narrow``,
///         ``total``, and with ``method="cluster"`` also ``clustering`` and ``merging``.
#[pyclass(module = "topoccd", frozen)]
pub struct Report {
    #[pyo3(get)]
    vf: Py<PyArray2<i64>>,
    #[pyo3(get)]
    vf_toi: Py<PyArray1<f64>>,
    #[pyo3(get)]
    vf_certainty: Py<PyArray1<u8>>,
    #[pyo3(get)]
    ee: Py<PyArray2<i64>>,
    #[pyo3(get)]
    ee_toi: Py<PyArray1<f64>>,
    #[pyo3(get)]
    ee_certainty: Py<PyArray1<u8>>,
    #[pyo3(get)]
    ve: Py<PyArray2<i64>>,
    #[pyo3(get)]
    ve_toi: Py<PyArray1<f64>>,
    #[pyo3(get)]
    ve_certainty: Py<PyArray1<u8>>,
    #[pyo3(get)]
    vv: Py<PyArray2<i64>>,
    #[pyo3(get)]
    vv_toi: Py<PyArray1<f64>>,
    #[pyo3(get)]
    vv_certainty: Py<PyArray1<u8>>,
    #[pyo3(get)]
    vf_barycentric: Option<Py<PyArray2<f64>>>,
    #[pyo3(get)]
    vf_point: Option<Py<PyArray2<f64>>>,
    #[pyo3(get)]
    vf_normal: Option<Py<PyArray2<f64>>>,
    #[pyo3(get)]
    ee_params: Option<Py<PyArray2<f64>>>,
    #[pyo3(get)]
    ee_point: Option<Py<PyArray2<f64>>>,
    #[pyo3(get)]
    ee_normal: Option<Py<PyArray2<f64>>>,
    #[pyo3(get)]
    earliest_toi: Option<f64>,
    #[pyo3(get)]
    earliest: Option<Py<PyTuple>>,
    #[pyo3(get)]
    unresolved: usize,
    #[pyo3(get)]
    earliest_complete: bool,
    #[pyo3(get)]
    truncated: Option<Py<PyDict>>,
    #[pyo3(get)]
    stats: Py<PyDict>,
    #[pyo3(get)]
    seconds: Py<PyDict>,
    /// The pairs in the library's types, for `write_pairs` (exactly the CLI's text).
    vf_rows: Vec<(u32, u32, f64)>,
    ee_rows: Vec<([u32; 2], [u32; 2], f64)>,
    ve_rows: Vec<(u32, [u32; 2], f64)>,
    vv_rows: Vec<(u32, u32, f64)>,
    /// Where the library read the positions from (a debugging aid for the no-copy check).
    #[pyo3(get, name = "_x0_address")]
    x0_address: usize,
    #[pyo3(get, name = "_x1_address")]
    x1_address: usize,
    #[pyo3(get, name = "_borrowed")]
    borrowed: (bool, bool),
}

/// The Python code of a certainty.
fn certainty_code(c: Certainty) -> u8 {
    match c {
        Certainty::Resolved => 0,
        Certainty::IterationLimit => 1,
        Certainty::InvalidInput => 2,
    }
}

pub(crate) fn array2<T: numpy::Element>(
    py: Python<'_>,
    rows: usize,
    cols: usize,
    flat: Vec<T>,
) -> PyResult<Py<PyArray2<T>>> {
    let array = Array2::from_shape_vec((rows, cols), flat)
        .map_err(|e| input_error(format!("internal shape error: {e}")))?;
    Ok(array.into_pyarray(py).unbind())
}

pub(crate) fn array1<T: numpy::Element>(py: Python<'_>, v: Vec<T>) -> Py<PyArray1<T>> {
    Array1::from_vec(v).into_pyarray(py).unbind()
}

/// What the binding knows of the step besides the library's report.
pub struct StepFacts {
    pub vertices: usize,
    pub triangles: usize,
    pub x0_address: usize,
    pub x1_address: usize,
    pub borrowed: (bool, bool),
    pub geometry: bool,
}

impl Report {
    /// Converts the library's report.
    pub fn new(py: Python<'_>, r: &LibReport, facts: &StepFacts) -> PyResult<Self> {
        let (n, m) = (r.vf.len(), r.ee.len());
        let mut vf = Vec::with_capacity(2 * n);
        let mut vf_toi = Vec::with_capacity(n);
        let mut vf_cert = Vec::with_capacity(n);
        let mut vf_rows = Vec::with_capacity(n);
        for c in &r.vf {
            vf.extend([i64::from(c.vertex), i64::from(c.face)]);
            vf_toi.push(c.toi);
            vf_cert.push(certainty_code(c.certainty));
            vf_rows.push((c.vertex, c.face, c.toi));
        }
        let mut ee = Vec::with_capacity(4 * m);
        let mut ee_toi = Vec::with_capacity(m);
        let mut ee_cert = Vec::with_capacity(m);
        let mut ee_rows = Vec::with_capacity(m);
        for c in &r.ee {
            ee.extend([c.a[0], c.a[1], c.b[0], c.b[1]].map(i64::from));
            ee_toi.push(c.toi);
            ee_cert.push(certainty_code(c.certainty));
            ee_rows.push((c.a, c.b, c.toi));
        }
        let ve: Vec<i64> = (r.ve.iter())
            .flat_map(|c| [c.vertex, c.edge[0], c.edge[1]].map(i64::from))
            .collect();
        let vv: Vec<i64> = (r.vv.iter())
            .flat_map(|c| [c.a, c.b].map(i64::from))
            .collect();
        let mut report = Report {
            ve: array2(py, r.ve.len(), 3, ve)?,
            ve_toi: array1(py, r.ve.iter().map(|c| c.toi).collect()),
            ve_certainty: array1(
                py,
                (r.ve.iter()).map(|c| certainty_code(c.certainty)).collect(),
            ),
            vv: array2(py, r.vv.len(), 2, vv)?,
            vv_toi: array1(py, r.vv.iter().map(|c| c.toi).collect()),
            vv_certainty: array1(
                py,
                (r.vv.iter()).map(|c| certainty_code(c.certainty)).collect(),
            ),
            vf: array2(py, n, 2, vf)?,
            vf_toi: array1(py, vf_toi),
            vf_certainty: array1(py, vf_cert),
            ee: array2(py, m, 4, ee)?,
            ee_toi: array1(py, ee_toi),
            ee_certainty: array1(py, ee_cert),
            vf_barycentric: None,
            vf_point: None,
            vf_normal: None,
            ee_params: None,
            ee_point: None,
            ee_normal: None,
            earliest_toi: r.earliest_toi(),
            earliest: earliest(py, r.earliest.as_ref())?,
            unresolved: r.unresolved,
            earliest_complete: r.earliest_complete,
            truncated: truncated(py, r)?,
            stats: stats(py, r, facts)?,
            seconds: seconds(py, r)?,
            vf_rows,
            ee_rows,
            ve_rows: r.ve.iter().map(|c| (c.vertex, c.edge, c.toi)).collect(),
            vv_rows: r.vv.iter().map(|c| (c.a, c.b, c.toi)).collect(),
            x0_address: facts.x0_address,
            x1_address: facts.x1_address,
            borrowed: facts.borrowed,
        };
        if facts.geometry {
            report.add_geometry(py, r)?;
        }
        Ok(report)
    }

    /// The contact geometry arrays (NaN rows where the library gave none).
    fn add_geometry(&mut self, py: Python<'_>, r: &LibReport) -> PyResult<()> {
        let nan3 = [f64::NAN; 3];
        let (n, m) = (r.vf.len(), r.ee.len());
        let (mut bary, mut point, mut normal) = (
            Vec::with_capacity(3 * n),
            Vec::with_capacity(3 * n),
            Vec::with_capacity(3 * n),
        );
        for c in &r.vf {
            match &c.geometry {
                Some(g) => {
                    bary.extend(g.barycentric);
                    point.extend(g.point);
                    normal.extend(g.normal);
                }
                None => {
                    bary.extend(nan3);
                    point.extend(nan3);
                    normal.extend(nan3);
                }
            }
        }
        self.vf_barycentric = Some(array2(py, n, 3, bary)?);
        self.vf_point = Some(array2(py, n, 3, point)?);
        self.vf_normal = Some(array2(py, n, 3, normal)?);
        let (mut params, mut point, mut normal) = (
            Vec::with_capacity(2 * m),
            Vec::with_capacity(3 * m),
            Vec::with_capacity(3 * m),
        );
        for c in &r.ee {
            match &c.geometry {
                Some(g) => {
                    params.extend([g.a_param, g.b_param]);
                    point.extend(g.point);
                    normal.extend(g.normal);
                }
                None => {
                    params.extend([f64::NAN; 2]);
                    point.extend(nan3);
                    normal.extend(nan3);
                }
            }
        }
        self.ee_params = Some(array2(py, m, 2, params)?);
        self.ee_point = Some(array2(py, m, 3, point)?);
        self.ee_normal = Some(array2(py, m, 3, normal)?);
        Ok(())
    }
}

/// `("vf", vertex, face, toi)` or `("ee", a0, a1, b0, b1, toi)`.
fn earliest(py: Python<'_>, c: Option<&Contact>) -> PyResult<Option<Py<PyTuple>>> {
    let Some(c) = c else { return Ok(None) };
    let t = match c {
        Contact::Vf(v) => ("vf", v.vertex, v.face, v.toi).into_pyobject(py)?,
        Contact::Ee(e) => ("ee", e.a[0], e.a[1], e.b[0], e.b[1], e.toi).into_pyobject(py)?,
        Contact::Ve(e) => ("ve", e.vertex, e.edge[0], e.edge[1], e.toi).into_pyobject(py)?,
        Contact::Vv(e) => ("vv", e.a, e.b, e.toi).into_pyobject(py)?,
    };
    Ok(Some(t.unbind()))
}

/// `{"reason": ..., "phase": ..., "tasks": ...}`, or `None` for a complete report.
fn truncated(py: Python<'_>, r: &LibReport) -> PyResult<Option<Py<PyDict>>> {
    let Some(t) = &r.truncated else {
        return Ok(None);
    };
    let d = PyDict::new(py);
    d.set_item("reason", t.reason.to_string())?;
    let phase = match t.phase {
        topoccd::Phase::Build => "build",
        topoccd::Phase::Candidates => "candidates",
    };
    d.set_item("phase", phase)?;
    d.set_item("tasks", t.tasks)?;
    Ok(Some(d.unbind()))
}

fn stats(py: Python<'_>, r: &LibReport, facts: &StepFacts) -> PyResult<Py<PyDict>> {
    let s = &r.stats;
    let d = PyDict::new(py);
    d.set_item("vertices", facts.vertices)?;
    d.set_item("triangles", facts.triangles)?;
    d.set_item("method", s.method.to_string())?;
    d.set_item("bv_tests", s.bv_tests)?;
    d.set_item("vf_tests", s.vf_tests)?;
    d.set_item("ee_tests", s.ee_tests)?;
    d.set_item("peak_candidates", s.peak_candidates)?;
    if let Some(c) = &s.cluster {
        let cd = PyDict::new(py);
        cd.set_item("leaf", c.leaf)?;
        cd.set_item("intermediate", c.intermediate)?;
        cd.set_item("triangles_per_leaf", c.triangles_per_leaf)?;
        cd.set_item("triangles_per_intermediate", c.triangles_per_intermediate)?;
        cd.set_item("lazy_bvhs", c.lazy_bvhs)?;
        cd.set_item("leaf_pairs", c.leaf_pairs)?;
        cd.set_item("uncertified_leaves", c.uncertified_leaves)?;
        cd.set_item("reused_leaves", c.reused_leaves)?;
        d.set_item("cluster", cd)?;
    }
    Ok(d.unbind())
}

fn seconds(py: Python<'_>, r: &LibReport) -> PyResult<Py<PyDict>> {
    let s = &r.stats.seconds;
    let d = PyDict::new(py);
    d.set_item("build", s.build)?;
    d.set_item("traverse", s.traverse)?;
    d.set_item("narrow", s.narrow)?;
    d.set_item("total", s.total)?;
    if let Some(c) = s.clustering {
        d.set_item("clustering", c)?;
    }
    if let Some(m) = s.merging {
        d.set_item("merging", m)?;
    }
    Ok(d.unbind())
}

#[pymethods]
impl Report {
    /// Writes the colliding pairs to a text file, one per line, exactly as
    /// ``topoccd step --pairs`` and ``topoccd run --pairs-dir`` do: ``vf,VERTEX,FACE,TOI`` then
    /// ``ee,A0,A1,B0,B1,TOI``, then with free edges and points ``ve,VERTEX,E0,E1,TOI`` and
    /// ``vv,A,B,TOI`` (times in the shortest decimal that reads back to the same float).
    ///
    /// Raises:
    ///     OSError: the file cannot be created or written.
    fn write_pairs(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let write = || -> std::io::Result<()> {
            let mut out = BufWriter::new(File::create(&path)?);
            for (v, f, toi) in &self.vf_rows {
                writeln!(out, "vf,{v},{f},{toi}")?;
            }
            for (a, b, toi) in &self.ee_rows {
                writeln!(out, "ee,{},{},{},{},{toi}", a[0], a[1], b[0], b[1])?;
            }
            for (v, e, toi) in &self.ve_rows {
                writeln!(out, "ve,{v},{},{},{toi}", e[0], e[1])?;
            }
            for (a, b, toi) in &self.vv_rows {
                writeln!(out, "vv,{a},{b},{toi}")?;
            }
            out.flush()
        };
        py.detach(write).map_err(|e| {
            let message = format!("{}: cannot write: {e}", path.display());
            pyo3::exceptions::PyOSError::new_err((e.raw_os_error().unwrap_or(0), message))
        })
    }

    /// Number of colliding pairs (vertex-face plus edge-edge).
    fn __len__(&self) -> usize {
        self.vf_rows.len() + self.ee_rows.len()
    }

    fn __repr__(&self) -> String {
        let earliest = self
            .earliest_toi
            .map_or("None".to_string(), |t| format!("{t}"));
        let truncated = if self.truncated.is_some() {
            ", TRUNCATED"
        } else {
            ""
        };
        format!(
            "<topoccd.Report: {} vf and {} ee contacts, earliest_toi={earliest}, unresolved={}{truncated}>",
            self.vf_rows.len(),
            self.ee_rows.len(),
            self.unresolved
        )
    }
}
