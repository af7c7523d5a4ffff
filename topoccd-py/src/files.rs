//! Readers: one mesh file, and frame sequences, as numpy arrays.

use std::path::PathBuf;

use numpy::ndarray::Array2;
use numpy::prelude::*;
use numpy::PyArray2;
use pyo3::exceptions::PyIndexError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use topoccd::io::sequence::Sequence as LibSequence;

use crate::errors::{input_error, io_error, sequence_error};

/// `(rows, N)` array from rows of `N` values.
fn table<'py, T: Copy + numpy::Element, U: Copy, const N: usize>(
    py: Python<'py>,
    rows: &[[U; N]],
    f: impl Fn(U) -> T,
) -> PyResult<Bound<'py, PyArray2<T>>> {
    let flat: Vec<T> = rows.iter().flat_map(|r| r.map(&f)).collect();
    let array = Array2::from_shape_vec((rows.len(), N), flat)
        .map_err(|e| input_error(format!("internal shape error: {e}")))?;
    Ok(array.into_pyarray(py))
}

/// Reads a triangle mesh file, ``.ply``, ``.obj`` or ``.stl`` (what the library reads), chosen
/// by the extension.
///
/// Returns:
///     tuple: ``(positions, triangles)``: ``(n, 3)`` float64 and ``(m, 3)`` int64 arrays.
///
/// Raises:
///     FileNotFoundError, PermissionError, OSError: the file cannot be read.
///     FormatError: the file is malformed (the message names the line or element).
#[pyfunction]
pub fn read_mesh<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyTuple>> {
    let mesh = py
        .detach(|| topoccd::io::read_mesh(&path))
        .map_err(|e| io_error(&e))?;
    let positions = table(py, &mesh.positions, |x: f64| x)?;
    let triangles = table(py, &mesh.triangles, i64::from)?;
    (positions, triangles).into_pyobject(py)
}

/// What a mesh file holds besides its triangles, by the rule every reader and command uses
/// (the CLI's ``step``, ``run``, ``proximity`` and ``check`` read the same): its free edges
/// (edges in no triangle) and its free points (vertices in no triangle and no edge).
///
/// Args:
///     path: a ``.ply``, ``.obj`` or ``.stl`` file.
///     loose_vertices: ``"points"`` (the default, the IPC toolkit's rule: loose vertices are
///         particles, whether or not the file has edges) or ``"ignore"`` (leftovers).
///
/// Returns:
///     tuple: ``(free_edges, free_points)``: ``(k, 2)`` and ``(p,)`` int64 arrays, sorted; pass
///     the file's edges as ``edges=`` to a query (an empty ``(0, 2)`` array turns the free
///     points on when the file has no edges).
///
/// Raises:
///     ValueError: ``loose_vertices`` is neither name.
///     OSError, FormatError: the file cannot be read.
#[pyfunction]
#[pyo3(signature = (path, *, loose_vertices="points"))]
pub fn read_primitives<'py>(
    py: Python<'py>,
    path: PathBuf,
    loose_vertices: &str,
) -> PyResult<Bound<'py, PyTuple>> {
    let loose: topoccd::io::LooseVertices =
        loose_vertices
            .parse()
            .map_err(|e: topoccd::io::UnknownLooseVertices| {
                pyo3::exceptions::PyValueError::new_err(e.to_string())
            })?;
    let mesh = py
        .detach(|| topoccd::io::read_mesh(&path))
        .map_err(|e| io_error(&e))?;
    let p = topoccd::io::FilePrimitives::of_mesh(&mesh, loose);
    let edges = table(py, &p.free_edges, i64::from)?;
    let points: Vec<i64> = p.free_points.iter().map(|&v| i64::from(v)).collect();
    let points = numpy::PyArray1::from_vec(py, points);
    (edges, points).into_pyobject(py)
}

/// A frame sequence on disk: a folder of frames ``0000.ply``, ``0001.ply``, ... (or ``.obj``),
/// with optional ``NNNN.parents`` files for topology changes. Step ``k`` goes from frame ``k``
/// to frame ``k + 1`` and uses the triangles of frame ``k + 1``.
///
/// ``len(seq)`` is the number of steps; ``seq[k]`` reads the two frames of step ``k`` and
/// returns ``(x0, x1, triangles, parents)`` ready for :meth:`Ccd.query`: ``x0`` is frame
/// ``k``'s positions (fewer rows than ``x1`` when the step appends vertices), ``parents`` the
/// ``(k, 2)`` int64 ``[child, parent]`` rows of frame ``k + 1``'s parents file (empty without
/// one): ``query(x0, x1, triangles, parents=parents)`` is the step ``topoccd run`` queries.
/// Iterating yields the steps in order. Only the folder listing is read when the sequence is opened.
#[pyclass(module = "topoccd", frozen)]
pub struct Sequence {
    inner: LibSequence,
}

#[pymethods]
impl Sequence {
    /// Number of steps (frames less one).
    fn __len__(&self) -> usize {
        self.inner.steps()
    }

    /// Step ``k`` as ``(x0, x1, triangles, parents)``; negative ``k`` counts from the end.
    ///
    /// Raises:
    ///     IndexError: no such step.
    ///     OSError, FormatError: a frame or parents file cannot be read.
    fn __getitem__<'py>(&self, py: Python<'py>, k: isize) -> PyResult<Bound<'py, PyTuple>> {
        let steps = self.inner.steps() as isize;
        let index = if k < 0 { k + steps } else { k };
        if index < 0 || index >= steps {
            return Err(PyIndexError::new_err(format!(
                "step {k} is out of range: the sequence has {steps} steps"
            )));
        }
        let frames = py
            .detach(|| self.inner.load(index as usize))
            .map_err(|e| sequence_error(&e))?;
        let x0 = table(py, &frames.x0, |x: f64| x)?;
        let x1 = table(py, &frames.x1, |x: f64| x)?;
        let triangles = table(py, &frames.triangles, i64::from)?;
        let parents = table(py, &frames.parents, i64::from)?;
        (x0, x1, triangles, parents).into_pyobject(py)
    }

    /// Iterates over the steps in order, reading each step's two frames when it is reached.
    fn __iter__(slf: Bound<'_, Self>) -> SequenceIter {
        SequenceIter {
            sequence: slf.unbind(),
            next: 0,
        }
    }

    /// The frame files, in order (``len(seq) + 1`` paths).
    #[getter]
    fn frames(&self) -> Vec<String> {
        self.inner
            .frames
            .iter()
            .map(|p| p.display().to_string())
            .collect()
    }

    /// The folder.
    #[getter]
    fn folder(&self) -> String {
        self.inner.dir.display().to_string()
    }

    fn __repr__(&self) -> String {
        format!(
            "<topoccd.Sequence {}: {} steps>",
            self.inner.dir.display(),
            self.inner.steps()
        )
    }
}

/// Opens a frame sequence folder (see :class:`Sequence`): lists and checks the frame numbering.
///
/// Raises:
///     FileNotFoundError, OSError: the folder cannot be listed.
///     FormatError: fewer than two frames, or a gap in the numbering.
#[pyfunction]
pub fn read_sequence(py: Python<'_>, folder: PathBuf) -> PyResult<Sequence> {
    let inner = py
        .detach(|| LibSequence::open(&folder))
        .map_err(|e| sequence_error(&e))?;
    Ok(Sequence { inner })
}

/// Iterator over the steps of a :class:`Sequence`.
#[pyclass(module = "topoccd")]
pub struct SequenceIter {
    sequence: Py<Sequence>,
    next: usize,
}

#[pymethods]
impl SequenceIter {
    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__<'py>(&mut self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyTuple>>> {
        let sequence = self.sequence.bind(py).get();
        if self.next >= sequence.inner.steps() {
            return Ok(None);
        }
        let k = self.next;
        self.next += 1;
        sequence.__getitem__(py, k as isize).map(Some)
    }
}
