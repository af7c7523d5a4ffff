//! Friction for `topoccd.ipc`: the library's tangential collisions and friction potential
//! (`topoccd::ipc::friction`), built from the library's normal collision set, with the
//! mesh's own edge ids for ipctk's names. Static and kinetic coefficients, global or per
//! vertex (ipctk's default blend).

use numpy::{IntoPyArray, PyArray1, PyArray3, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use topoccd::ipc::friction::{
    FrictionCoefficients, FrictionError, FrictionPotential, StencilKind, TangentialCollision,
    TangentialCollisions,
};

use super::{csr_arrays, flat, psd_of, CsrArrays, IpcBarrierPotential, IpcCollisions};
use crate::errors::{input_error, options_error};
use crate::report::{array1, array2};

/// A friction error as the Python exception it is: bad coefficients or `eps_v` are options,
/// the rest input.
fn friction_error(e: FrictionError) -> PyErr {
    match e {
        FrictionError::BadCoefficient { .. } | FrictionError::BadEpsV { .. } => {
            options_error(e.to_string())
        }
        _ => input_error(e.to_string()),
    }
}

/// Tangential collisions (the native half of `topoccd.ipc.TangentialCollisions`).
#[pyclass(module = "topoccd", name = "IpcTangentialCollisions")]
pub struct IpcTangentialCollisions {
    core: TangentialCollisions,
    /// Each collision's two ids as ipctk names them (edge ids into the mesh's `edges`), in
    /// the set's order.
    ids: Vec<[u32; 2]>,
    num_vertices: usize,
}

#[pymethods]
impl IpcTangentialCollisions {
    /// Builds the tangential collisions of `collisions` at the lagged positions `x`, with
    /// the normal forces of `potential` and the coefficients `mu_s`, `mu_k`: one value each
    /// (global) or one per vertex.
    #[new]
    fn new(
        py: Python<'_>,
        collisions: PyRef<'_, IpcCollisions>,
        potential: PyRef<'_, IpcBarrierPotential>,
        x: PyReadonlyArray2<'_, f64>,
        mu_s: PyReadonlyArray1<'_, f64>,
        mu_k: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Self> {
        let x = flat(&x, "vertices")?;
        collisions.check(x)?;
        let (mu_s, mu_k) = (mu_s.as_slice()?, mu_k.as_slice()?);
        let n = x.len() / 3;
        let mu = match (mu_s.len(), mu_k.len()) {
            (1, 1) => FrictionCoefficients::Global {
                mu_s: mu_s[0],
                mu_k: mu_k[0],
            },
            (a, b) if a == n && b == n => FrictionCoefficients::PerVertex { mu_s, mu_k },
            (a, b) => {
                return Err(input_error(format!(
                "mu_s and mu_k must be scalars or have one entry per vertex ({n}), got {a} and {b}"
            )))
            }
        };
        let (normal, barrier, x3) = (&collisions.core, potential.core, x.as_chunks::<3>().0);
        let core = py
            .detach(|| TangentialCollisions::build(x3, normal, &barrier, mu))
            .map_err(friction_error)?;
        let map = &collisions.set.edge_map;
        let edge = |e: usize| map.get(e).copied().unwrap_or(u32::MAX);
        let ids = (core.iter())
            .map(|c| {
                let [p, q] = c.primitives;
                match c.kind {
                    StencilKind::VertexVertex => [p as u32, q as u32],
                    StencilKind::EdgeVertex => [edge(p), q as u32],
                    StencilKind::EdgeEdge => [edge(p), edge(q)],
                    StencilKind::FaceVertex => [p as u32, q as u32],
                }
            })
            .collect();
        Ok(Self {
            core,
            ids,
            num_vertices: n,
        })
    }

    fn __len__(&self) -> usize {
        self.core.len()
    }

    /// The collisions of one kind (`"vv"`, `"ev"`, `"ee"`, `"fv"`): `(n, 2)` ids.
    fn ids(&self, py: Python<'_>, kind: &str) -> PyResult<Py<numpy::PyArray2<i64>>> {
        let k = super::kind_code(kind)?;
        let counts = self.counts();
        let start: usize = counts[..k].iter().sum();
        let sel = &self.ids[start..start + counts[k]];
        array2(
            py,
            sel.len(),
            2,
            sel.iter()
                .flat_map(|c| [c[0] as i64, c[1] as i64])
                .collect(),
        )
    }

    #[getter]
    fn normal_force_magnitude(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.each(py, |c| c.normal_force_magnitude)
    }
    #[getter]
    fn mu_s(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.each(py, |c| c.mu_s)
    }
    #[getter]
    fn mu_k(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.each(py, |c| c.mu_k)
    }
    #[getter]
    fn weights(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.each(py, |c| c.weight)
    }
    /// `(n, 2)`: each collision's closest-point coordinates, padded with zeros.
    #[getter]
    fn closest_points(&self, py: Python<'_>) -> PyResult<Py<numpy::PyArray2<f64>>> {
        let flat = self.core.iter().flat_map(|c| c.closest_point).collect();
        array2(py, self.core.len(), 2, flat)
    }
    /// `(n, 3, 2)`: each collision's tangent basis, its columns the two tangents.
    #[getter]
    fn tangent_bases(&self, py: Python<'_>) -> PyResult<Py<PyArray3<f64>>> {
        let flat: Vec<f64> = (self.core.iter())
            .flat_map(|c| {
                let [t0, t1] = c.tangent_basis;
                (0..3).flat_map(move |r| [t0[r], t1[r]])
            })
            .collect();
        let a = numpy::ndarray::Array3::from_shape_vec((self.core.len(), 3, 2), flat)
            .map_err(|e| input_error(e.to_string()))?;
        Ok(a.into_pyarray(py).unbind())
    }

    /// The friction potential at the velocities `u`.
    fn energy(&self, py: Python<'_>, u: PyReadonlyArray2<'_, f64>, eps_v: f64) -> PyResult<f64> {
        let (u, d) = (self.input(&u)?, potential(eps_v)?);
        py.detach(|| d.energy(&self.core, u))
            .map_err(friction_error)
    }

    /// Its gradient, `3 n` entries.
    fn gradient(
        &self,
        py: Python<'_>,
        u: PyReadonlyArray2<'_, f64>,
        eps_v: f64,
    ) -> PyResult<Py<PyArray1<f64>>> {
        let (u, d) = (self.input(&u)?, potential(eps_v)?);
        let g = py
            .detach(|| d.gradient(&self.core, u))
            .map_err(friction_error)?;
        Ok(array1(py, g))
    }

    /// Its Hessian's CSR arrays, each collision's 2 x 2 block projected by `psd` (0 none,
    /// 1 clamp, 2 abs).
    fn hessian(
        &self,
        py: Python<'_>,
        u: PyReadonlyArray2<'_, f64>,
        eps_v: f64,
        psd: u8,
    ) -> PyResult<CsrArrays> {
        let (u, d, psd) = (self.input(&u)?, potential(eps_v)?, psd_of(psd)?);
        let h = py
            .detach(|| d.hessian(&self.core, u, psd))
            .map_err(friction_error)?;
        Ok(csr_arrays(py, &h))
    }
}

fn potential(eps_v: f64) -> PyResult<FrictionPotential> {
    FrictionPotential::new(eps_v).map_err(friction_error)
}

impl IpcTangentialCollisions {
    fn counts(&self) -> [usize; 4] {
        let c = &self.core;
        [
            c.vv_collisions.len(),
            c.ev_collisions.len(),
            c.ee_collisions.len(),
            c.fv_collisions.len(),
        ]
    }

    fn each(&self, py: Python<'_>, f: impl Fn(&TangentialCollision) -> f64) -> Py<PyArray1<f64>> {
        array1(py, self.core.iter().map(f).collect())
    }

    fn input<'a>(&self, u: &'a PyReadonlyArray2<'_, f64>) -> PyResult<&'a [[f64; 3]]> {
        let u = flat(u, "X")?;
        if u.len() / 3 < self.num_vertices {
            return Err(input_error(format!(
                "X has {} vertices, the collisions were built on {}",
                u.len() / 3,
                self.num_vertices
            )));
        }
        Ok(u.as_chunks::<3>().0)
    }
}
