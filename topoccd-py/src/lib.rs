//! The extension module `topoccd._topoccd` of the Python package `topoccd` (see
//! `python/topoccd/`): numpy arrays in, numpy arrays out, the GIL released while the library
//! works, library errors as Python exceptions (never a panic on user input).
//!
//! - `ccd`: the `Ccd` class and its `query`.
//! - `input`: numpy arrays to the library's input (borrowed when float64 and C-contiguous).
//! - `options`: keyword options to the library's options.
//! - `report`: the library's report to numpy arrays.
//! - `files`: mesh and sequence readers.
//! - `check`: the static intersection check (`intersecting_triangles`).
//! - `pair`: the per-pair tests (`point_triangle_ccd`, `edge_edge_ccd`, `point_edge_ccd`,
//!   `point_point_ccd`).
//! - `points`: numpy arrays of points in.
//! - `proximity`: `Ccd.proximity` and its `Proximity` result.
//! - `errors`: the exceptions.
//! - `deprecated`: the keyword names of earlier versions.
//! - `ipc`: the contact potentials of `topoccd.ipc`.

mod ccd;
mod check;
mod deprecated;
mod errors;
mod files;
mod input;
mod ipc;
mod options;
mod pair;
mod points;
mod proximity;
mod report;

use pyo3::prelude::*;

/// Continuous collision detection for deforming, topology-changing triangle meshes (the Rust
/// extension; import ``topoccd``, not this module).
#[pymodule]
fn _topoccd(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<ccd::Ccd>()?;
    m.add_class::<report::Report>()?;
    m.add_class::<proximity::Proximity>()?;
    m.add_class::<files::Sequence>()?;
    m.add_function(wrap_pyfunction!(files::read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(files::read_primitives, m)?)?;
    m.add_function(wrap_pyfunction!(files::read_sequence, m)?)?;
    m.add_function(wrap_pyfunction!(pair::point_triangle_ccd, m)?)?;
    m.add_function(wrap_pyfunction!(pair::edge_edge_ccd, m)?)?;
    m.add_function(wrap_pyfunction!(pair::point_edge_ccd, m)?)?;
    m.add_function(wrap_pyfunction!(pair::point_point_ccd, m)?)?;
    m.add_function(wrap_pyfunction!(check::intersecting_triangles, m)?)?;
    ipc::register(m)?;
    m.add("InputError", py.get_type::<errors::InputError>())?;
    m.add("OptionsError", py.get_type::<errors::OptionsError>())?;
    m.add("FormatError", py.get_type::<errors::FormatError>())?;
    m.add("InputWarning", py.get_type::<errors::InputWarning>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("DEFAULT_MAX_CONTACTS", topoccd::DEFAULT_MAX_CONTACTS)?;
    Ok(())
}
