//! The contact potentials for `topoccd.ipc` (`python/topoccd/ipc.py`): the collision set
//! built from `Ccd.proximity`'s pairs, the barrier potential and friction, numpy in and out,
//! the GIL released around the work. Everything is computed by the library
//! (`topoccd::ipc`); this module converts arrays and names.
//!
//! - `collisions`: the library's set with the mesh's edge ids.
//! - `friction`: tangential collisions and the friction potential.

mod collisions;
mod friction;

use numpy::{PyArray1, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use topoccd::ipc::{
    Barrier, BarrierPotential, CollisionOptions, CollisionSetType, PsdProjection, SparseMatrix,
};
use topoccd::{Configuration, ProximityOptions, ProximityReport};

use crate::ccd::Ccd;
use crate::errors::{input_error, options_error};
use crate::report::{array1, array2};

use self::collisions::{Collisions, MeshView};

pub(crate) fn flat<'a>(a: &'a PyReadonlyArray2<'_, f64>, name: &str) -> PyResult<&'a [f64]> {
    a.as_slice()
        .map_err(|e| input_error(format!("{name}: not contiguous: {e}")))
}

fn rows<const N: usize>(
    a: &PyReadonlyArray2<'_, i32>,
    name: &str,
    n: usize,
) -> PyResult<Vec<[u32; N]>> {
    let s = a
        .as_slice()
        .map_err(|e| input_error(format!("{name}: not contiguous: {e}")))?;
    let mut out = Vec::with_capacity(s.len() / N.max(1));
    for (r, c) in s.chunks_exact(N).enumerate() {
        let mut row = [0u32; N];
        for k in 0..N {
            if c[k] < 0 || c[k] as usize >= n {
                return Err(input_error(format!(
                    "{name}[{r}, {k}] = {} is not a vertex index in [0, {n})",
                    c[k]
                )));
            }
            row[k] = c[k] as u32;
        }
        out.push(row);
    }
    Ok(out)
}

/// A Hessian's CSR arrays `(data, indices, indptr)` as numpy arrays.
pub(crate) type CsrArrays = (Py<PyArray1<f64>>, Py<PyArray1<i32>>, Py<PyArray1<i32>>);

/// The library's sparse matrix as numpy CSR arrays (int32 indices, as scipy's).
pub(crate) fn csr_arrays(py: Python<'_>, m: &SparseMatrix) -> CsrArrays {
    let (indptr, indices, data) = m.csr();
    (
        array1(py, data.to_vec()),
        array1(py, indices.iter().map(|&i| i as i32).collect()),
        array1(py, indptr.iter().map(|&i| i as i32).collect()),
    )
}

/// A collision set (the native half of `topoccd.ipc.NormalCollisions`).
#[pyclass(module = "topoccd", name = "IpcCollisions")]
pub struct IpcCollisions {
    /// The library's set (`topoccd::ipc`): the potentials evaluate it.
    pub(crate) core: topoccd::ipc::NormalCollisions,
    /// The same collisions with the mesh's edge ids, for the ids, weights and friction.
    pub(crate) set: Collisions,
    /// The proximity pairs of the last build and the mesh's edges, for the candidates.
    report: ProximityReport,
    edges: Vec<[u32; 2]>,
    /// The library's edges of the last build and their mesh ids: reused while the edges
    /// stay the same.
    edge_cache: (Vec<[u32; 2]>, Vec<u32>),
}

#[pymethods]
impl IpcCollisions {
    #[new]
    fn new() -> Self {
        Self {
            core: topoccd::ipc::NormalCollisions::default(),
            set: Collisions::default(),
            report: ProximityReport::default(),
            edges: Vec::new(),
            edge_cache: Default::default(),
        }
    }

    /// Builds the set at `x` from the pairs of one proximity query of `ccd`.
    #[allow(clippy::too_many_arguments)]
    fn build(
        &mut self,
        py: Python<'_>,
        ccd: &Bound<'_, Ccd>,
        rest: PyReadonlyArray2<'_, f64>,
        x: PyReadonlyArray2<'_, f64>,
        edges: PyReadonlyArray2<'_, i32>,
        free_edges: PyReadonlyArray2<'_, i32>,
        faces: PyReadonlyArray2<'_, i32>,
        _vertex_areas: PyReadonlyArray1<'_, f64>,
        _edge_areas: PyReadonlyArray1<'_, f64>,
        dhat: f64,
        dmin: f64,
        use_area_weighting: bool,
        improved_max_approx: bool,
    ) -> PyResult<()> {
        if !(dhat.is_finite() && dhat > 0.0) {
            return Err(options_error(format!(
                "dhat must be finite and > 0, got {dhat}"
            )));
        }
        if !(dmin.is_finite() && dmin >= 0.0) {
            return Err(options_error(format!(
                "dmin must be finite and >= 0, got {dmin}"
            )));
        }
        let (rest, x) = (flat(&rest, "rest_positions")?, flat(&x, "vertices")?);
        let n = x.len() / 3;
        let edges = rows::<2>(&edges, "edges", n)?;
        let free = rows::<2>(&free_edges, "edges", n)?;
        let faces = rows::<3>(&faces, "faces", n)?;
        let options = ProximityOptions {
            // A hair wider than dhat + dmin: the exact test below decides.
            dhat: (dhat + dmin) * (1.0 + 1e-9),
            dmin: 0.0,
            max_contacts: None,
            ..ProximityOptions::default()
        };
        let config =
            Configuration::new(x, &faces[..], &free).map_err(|e| input_error(e.to_string()))?;
        let mut this = ccd.try_borrow_mut().map_err(|_| {
            pyo3::exceptions::PyRuntimeError::new_err(
                "this Ccd is running a query in another thread",
            )
        })?;
        let inner = &mut this.inner;
        let rest3 = rest.as_chunks::<3>().0;
        let copts = CollisionOptions {
            dhat,
            dmin,
            use_area_weighting,
            collision_set_type: if improved_max_approx {
                CollisionSetType::ImprovedMaxApprox
            } else {
                CollisionSetType::Ipc
            },
            ..Default::default()
        };
        let cache = std::mem::take(&mut self.edge_cache);
        let same_edges = self.edges == edges;
        let (core, set, report) = py
            .detach(
                || -> Result<(topoccd::ipc::NormalCollisions, Collisions, ProximityReport), String> {
                    let report: ProximityReport =
                        inner.proximity(&config, &options).map_err(|e| e.to_string())?;
                    let core = topoccd::ipc::NormalCollisions::from_proximity(
                        &config, &report, rest3, &copts,
                    )
                    .map_err(|e| e.to_string())?;
                    let map = if same_edges && cache.0 == core.edges {
                        cache.1
                    } else {
                        collisions::edge_map(&edges, &core.edges)
                    };
                    let set = collisions::from_core(&core, map, n).map_err(|e| {
                        format!(
                            "edges lacks the edge ({}, {}) of a pair: pass every edge of the faces and the free edges",
                            e.0[0], e.0[1]
                        )
                    })?;
                    Ok((core, set, report))
                },
            )
            .map_err(input_error)?;
        self.edge_cache = (core.edges.clone(), set.edge_map.clone());
        self.core = core;
        self.set = set;
        self.report = report;
        if !same_edges {
            self.edges = edges;
        }
        Ok(())
    }

    /// The collisions of one kind (`"vv"`, `"ev"`, `"ee"`, `"fv"`): `(n, 2)` ids.
    fn ids(&self, py: Python<'_>, kind: &str) -> PyResult<Py<numpy::PyArray2<i64>>> {
        let k = kind_code(kind)?;
        let (start, count) = (
            self.set.counts[..k].iter().sum::<usize>(),
            self.set.counts[k],
        );
        let flat: Vec<i64> = (self.set.items[start..start + count].iter())
            .flat_map(|c| [c.ids[0] as i64, c.ids[1] as i64])
            .collect();
        array2(py, count, 2, flat)
    }

    /// The raw pairs of the last build of one kind, as candidates.
    fn candidates(&self, py: Python<'_>, kind: &str) -> PyResult<Py<numpy::PyArray2<i64>>> {
        let mesh = MeshView { edges: &self.edges };
        let all = collisions::candidate_ids(&mesh, &self.report);
        let c = &all[kind_code(kind)?];
        array2(
            py,
            c.len(),
            2,
            c.iter().flat_map(|p| [p[0] as i64, p[1] as i64]).collect(),
        )
    }

    /// The weights, in the set's order.
    #[getter]
    fn weights(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        array1(py, self.set.items.iter().map(|c| c.weight).collect())
    }

    /// The edge-edge collisions' mollifier thresholds.
    #[getter]
    fn eps_x(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        array1(
            py,
            self.set
                .items
                .iter()
                .filter(|c| c.kind == 2)
                .map(|c| c.eps_x)
                .collect(),
        )
    }

    #[getter]
    fn dmin(&self) -> f64 {
        self.set.dmin
    }

    #[getter]
    fn counts(&self) -> (usize, usize, usize, usize) {
        let c = self.set.counts;
        (c[0], c[1], c[2], c[3])
    }

    fn __len__(&self) -> usize {
        self.set.items.len()
    }

    /// The smallest squared distance over the set at `x`.
    fn minimum_distance(&self, py: Python<'_>, x: PyReadonlyArray2<'_, f64>) -> PyResult<f64> {
        let x = flat(&x, "vertices")?;
        self.check(x)?;
        let (core, x3) = (&self.core, x.as_chunks::<3>().0);
        Ok(py.detach(|| core.compute_minimum_distance(x3)))
    }
}

impl IpcCollisions {
    pub(crate) fn check(&self, x: &[f64]) -> PyResult<()> {
        if x.len() / 3 < self.set.num_vertices {
            return Err(input_error(format!(
                "X has {} vertices, the collisions were built on {}",
                x.len() / 3,
                self.set.num_vertices
            )));
        }
        Ok(())
    }
}

pub(crate) fn kind_code(kind: &str) -> PyResult<usize> {
    match kind {
        "vv" => Ok(0),
        "ev" => Ok(1),
        "ee" => Ok(2),
        "fv" => Ok(3),
        _ => Err(input_error(format!(
            "kind must be vv, ev, ee or fv, got {kind:?}"
        ))),
    }
}

pub(crate) fn psd_of(code: u8) -> PyResult<PsdProjection> {
    match code {
        0 => Ok(PsdProjection::None),
        1 => Ok(PsdProjection::Clamp),
        2 => Ok(PsdProjection::Abs),
        _ => Err(options_error(format!(
            "project_hessian_to_psd must be 0, 1 or 2, got {code}"
        ))),
    }
}

fn positive(name: &str, v: f64) -> PyResult<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(options_error(format!(
            "{name} must be finite and > 0, got {v}"
        )))
    }
}

/// The barrier potential (the native half of `topoccd.ipc.BarrierPotential`): the library's
/// `BarrierPotential` with the clamped log barrier.
#[pyclass(module = "topoccd", name = "IpcBarrierPotential")]
pub struct IpcBarrierPotential {
    pub(crate) core: BarrierPotential,
}

#[pymethods]
impl IpcBarrierPotential {
    #[new]
    fn new(dhat: f64, stiffness: f64, use_physical_barrier: bool) -> PyResult<Self> {
        let mut core =
            BarrierPotential::new(positive("dhat", dhat)?, positive("stiffness", stiffness)?);
        core.use_physical_barrier = use_physical_barrier;
        Ok(Self { core })
    }

    #[getter]
    fn get_dhat(&self) -> f64 {
        self.core.dhat
    }

    #[setter]
    fn set_dhat(&mut self, v: f64) -> PyResult<()> {
        self.core.dhat = positive("dhat", v)?;
        Ok(())
    }

    #[getter]
    fn get_stiffness(&self) -> f64 {
        self.core.stiffness
    }

    #[setter]
    fn set_stiffness(&mut self, v: f64) -> PyResult<()> {
        self.core.stiffness = positive("stiffness", v)?;
        Ok(())
    }

    #[getter]
    fn use_physical_barrier(&self) -> bool {
        self.core.use_physical_barrier
    }

    fn energy(
        &self,
        py: Python<'_>,
        c: PyRef<'_, IpcCollisions>,
        x: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<f64> {
        let x = flat(&x, "X")?;
        c.check(x)?;
        let (set, b, x3) = (&c.core, self.core, x.as_chunks::<3>().0);
        Ok(py.detach(|| b.energy(set, x3)))
    }

    fn gradient(
        &self,
        py: Python<'_>,
        c: PyRef<'_, IpcCollisions>,
        x: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<Py<PyArray1<f64>>> {
        let x = flat(&x, "X")?;
        c.check(x)?;
        let (set, b, x3) = (&c.core, self.core, x.as_chunks::<3>().0);
        let g = py.detach(|| b.gradient(set, x3));
        Ok(array1(py, g))
    }

    /// The Hessian's CSR arrays `(data, indices, indptr)`.
    fn hessian(
        &self,
        py: Python<'_>,
        c: PyRef<'_, IpcCollisions>,
        x: PyReadonlyArray2<'_, f64>,
        psd: u8,
    ) -> PyResult<CsrArrays> {
        let x = flat(&x, "X")?;
        c.check(x)?;
        let psd = psd_of(psd)?;
        let (set, b, x3) = (&c.core, self.core, x.as_chunks::<3>().0);
        let h = py.detach(|| b.hessian(set, x3, psd));
        Ok(csr_arrays(py, &h))
    }

    /// The normal force magnitude of a unit-weight collision at the squared distance `d2`
    /// (ipctk's `force_magnitude`): `-2 sqrt(d2) B'(d2)`.
    fn force_magnitude(&self, d2: f64, dmin: f64) -> f64 {
        -2.0 * d2.sqrt() * self.core.first_derivative(d2, dmin)
    }
}

/// `b(d, dhat)` of the clamped log barrier (`which` 0), its derivatives (1, 2), or its units
/// (3, ipctk's `units(dhat)`).
#[pyfunction]
pub fn ipc_barrier(kind: &str, which: u8, d: f64, dhat: f64) -> PyResult<f64> {
    if kind != "clamped_log" {
        return Err(options_error(format!("unknown barrier {kind:?}")));
    }
    let b = Barrier::ClampedLog;
    Ok(match which {
        0 => b.value(d, dhat),
        1 => b.first_derivative(d, dhat),
        2 => b.second_derivative(d, dhat),
        _ => b.units(dhat),
    })
}

/// ipctk's `initial_barrier_stiffness`: `(kappa, max_kappa)`.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn ipc_initial_barrier_stiffness(
    bbox_diagonal: f64,
    dhat: f64,
    average_mass: f64,
    grad_energy: PyReadonlyArray1<'_, f64>,
    grad_barrier: PyReadonlyArray1<'_, f64>,
    min_barrier_stiffness_scale: f64,
    dmin: f64,
) -> PyResult<(f64, f64)> {
    if !(bbox_diagonal > 0.0
        && average_mass > 0.0
        && min_barrier_stiffness_scale > 0.0
        && dhat > 0.0)
    {
        return Err(options_error(
            "bbox_diagonal, dhat, average_mass and min_barrier_stiffness_scale must be > 0",
        ));
    }
    let (ge, gb) = (grad_energy.as_slice()?, grad_barrier.as_slice()?);
    if ge.len() != gb.len() {
        return Err(input_error(format!(
            "grad_energy ({}) and grad_barrier ({}) differ in size",
            ge.len(),
            gb.len()
        )));
    }
    let k = topoccd::ipc::initial_barrier_stiffness(
        bbox_diagonal,
        Barrier::ClampedLog,
        dhat,
        average_mass,
        ge,
        gb,
        min_barrier_stiffness_scale,
        dmin,
    );
    Ok((k.stiffness, k.max_stiffness))
}

/// ipctk's `update_barrier_stiffness`.
#[pyfunction]
pub fn ipc_update_barrier_stiffness(
    prev_min_distance: f64,
    min_distance: f64,
    max_barrier_stiffness: f64,
    barrier_stiffness: f64,
    bbox_diagonal: f64,
    dhat_epsilon_scale: f64,
    dmin: f64,
) -> f64 {
    topoccd::ipc::update_barrier_stiffness(
        prev_min_distance,
        min_distance,
        max_barrier_stiffness,
        barrier_stiffness,
        bbox_diagonal,
        dhat_epsilon_scale,
        dmin,
    )
}

pub use friction::IpcTangentialCollisions;

/// Registers the classes and functions.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<IpcCollisions>()?;
    m.add_class::<IpcBarrierPotential>()?;
    m.add_class::<IpcTangentialCollisions>()?;
    m.add_function(wrap_pyfunction!(ipc_barrier, m)?)?;
    m.add_function(wrap_pyfunction!(ipc_initial_barrier_stiffness, m)?)?;
    m.add_function(wrap_pyfunction!(ipc_update_barrier_stiffness, m)?)?;
    Ok(())
}
