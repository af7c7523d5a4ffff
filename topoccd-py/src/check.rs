//! The static intersection check: `intersecting_triangles(x, triangles, parents=None)`.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use topoccd::check::frame_intersections;

use crate::errors::input_error;
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
///
/// Returns:
///     numpy.ndarray: ``(K, 2)`` int64 rows ``[a, b]``, ``a < b``, sorted (read-only).
///
/// Raises:
///     InputError: an array of the wrong shape or dtype, a non-finite coordinate, an index out
///         of range, a bad parent row.
///
/// Example: the second triangle pierces the first.
///     >>> import topoccd
///     >>> x = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, -1], [0.3, 0.2, 1], [0.2, 0.3, 1]]
///     >>> topoccd.intersecting_triangles(x, [[0, 1, 2], [3, 4, 5]]).tolist()
///     [[0, 1]]
#[pyfunction]
#[pyo3(signature = (x, triangles, *, parents=None))]
pub fn intersecting_triangles<'py>(
    py: Python<'py>,
    x: &Bound<'py, PyAny>,
    triangles: &Bound<'py, PyAny>,
    parents: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray2<i64>>> {
    let x = positions(x, "x")?;
    let tris = indices(triangles, "triangles", Some(3))?;
    let parent_rows = match parents {
        Some(p) => rows::<2>(&indices(p, "parents", Some(2))?),
        None => Vec::new(),
    };
    let flat = x.as_flat()?;
    let pairs = py
        .detach(|| frame_intersections(flat, &tris[..], &parent_rows))
        .map_err(|e| input_error(e.to_string()))?;
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
