//! Friction as ipctk 1.6.1 defines it: tangential collisions from the normal collisions at
//! the lagged positions (closest-point coordinates, tangent basis, normal force magnitude of
//! the barrier, weight, coefficients; nearly parallel edge pairs are skipped), and the smooth
//! friction potential `sum w N mu f0(|P^T Gamma u|)` over them, with its gradient and Hessian.

use numpy::{IntoPyArray, PyArray1, PyArray3, PyReadonlyArray2};
use pyo3::prelude::*;

use super::barrier::Assembler;
use super::distance::{
    edge_edge_type, ee_distance2, pe_distance2, point_edge_type, point_triangle_type, pt_distance2,
};
use super::psd::{project, Psd};
use super::{csr_tuple, flat, psd_of, IpcBarrierPotential, IpcCollisions};
use crate::errors::{input_error, options_error};
use crate::report::{array1, array2};

type P = [f64; 3];

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: P, b: P) -> P {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: P) -> P {
    let n = dot(a, a).sqrt();
    [a[0] / n, a[1] / n, a[2] / n]
}

/// One tangential collision.
#[derive(Clone, Copy, Debug)]
struct Tangential {
    ids: [u32; 2],
    verts: [u32; 4],
    weight: f64,
    normal_force: f64,
    mu_s: f64,
    mu_k: f64,
    closest: [f64; 2],
    /// Columns of the tangent basis: `basis[c]` is column c.
    basis: [P; 2],
    /// The relative velocity's coefficient per stencil vertex.
    coef: [f64; 4],
    nverts: usize,
}

fn solve2(a: f64, b: f64, c: f64, r: [f64; 2]) -> [f64; 2] {
    let det = a * c - b * b;
    [(c * r[0] - b * r[1]) / det, (a * r[1] - b * r[0]) / det]
}

/// The smooth friction profile (ipctk's `smooth_friction_*`), mu constant.
fn f0(y: f64, eps: f64) -> f64 {
    if y.abs() >= eps {
        y
    } else {
        y * y * (1.0 - y / (3.0 * eps)) / eps + eps / 3.0
    }
}
fn f1_over_x(y: f64, eps: f64) -> f64 {
    if y.abs() >= eps {
        1.0 / y
    } else {
        (2.0 - y / eps) / eps
    }
}
fn f2_x_minus_f1_over_x3(y: f64, eps: f64) -> f64 {
    if y.abs() >= eps {
        -1.0 / (y * y * y)
    } else {
        -1.0 / (y * eps * eps)
    }
}

/// Tangential collisions (the native half of `topoccd.ipc.TangentialCollisions`).
#[pyclass(module = "topoccd", name = "IpcTangentialCollisions")]
pub struct IpcTangentialCollisions {
    items: Vec<Tangential>,
    counts: [usize; 4],
    num_vertices: usize,
}

fn point(x: &[f64], v: u32) -> P {
    let i = 3 * v as usize;
    [x[i], x[i + 1], x[i + 2]]
}

#[pymethods]
impl IpcTangentialCollisions {
    #[new]
    fn new(
        collisions: PyRef<'_, IpcCollisions>,
        potential: PyRef<'_, IpcBarrierPotential>,
        x: PyReadonlyArray2<'_, f64>,
        mu_s: f64,
        mu_k: f64,
    ) -> PyResult<Self> {
        if mu_s != mu_k {
            return Err(pyo3::exceptions::PyNotImplementedError::new_err(
                "topoccd.ipc's friction takes mu_s == mu_k for now (the smooth static-to-kinetic mu awaits topoccd::ipc)",
            ));
        }
        if !(mu_s.is_finite() && mu_s >= 0.0) {
            return Err(options_error(format!(
                "mu must be finite and >= 0, got {mu_s}"
            )));
        }
        let x = flat(&x, "vertices")?;
        collisions.check(x)?;
        let set = &collisions.set;
        let b = potential.b;
        let mut items = Vec::with_capacity(set.items.len());
        let mut counts = [0usize; 4];
        for c in &set.items {
            let v = |k: usize| point(x, c.verts[k]);
            let (d2, closest, basis, coef, nverts) = match c.kind {
                0 => {
                    let (p0, p1) = (v(0), v(1));
                    let d = sub(p1, p0);
                    let (cx, cy) = (cross([1.0, 0.0, 0.0], d), cross([0.0, 1.0, 0.0], d));
                    let t = if dot(cx, cx) > dot(cy, cy) { cx } else { cy };
                    (
                        dot(d, d),
                        [0.0; 2],
                        [unit(t), unit(cross(d, t))],
                        [1.0, -1.0, 0.0, 0.0],
                        2,
                    )
                }
                1 => {
                    let (p, e0, e1) = (v(0), v(1), v(2));
                    let e = sub(e1, e0);
                    let alpha = dot(sub(p, e0), e) / dot(e, e);
                    let d2 = pe_distance2(p, e0, e1, point_edge_type(p, e0, e1));
                    (
                        d2,
                        [alpha, 0.0],
                        [unit(e), unit(cross(e, sub(p, e0)))],
                        [1.0, alpha - 1.0, -alpha, 0.0],
                        3,
                    )
                }
                2 => {
                    let (a0, a1, b0, b1) = (v(0), v(1), v(2), v(3));
                    let (ea, eb) = (sub(a1, a0), sub(b1, b0));
                    let n = cross(ea, eb);
                    if dot(n, n) < c.eps_x {
                        continue; // nearly parallel: no friction, as ipctk
                    }
                    let w = sub(a0, b0);
                    let [s, t] = solve2(
                        dot(ea, ea),
                        -dot(ea, eb),
                        dot(eb, eb),
                        [-dot(w, ea), dot(w, eb)],
                    );
                    let d2 = ee_distance2(a0, a1, b0, b1, edge_edge_type(a0, a1, b0, b1));
                    (
                        d2,
                        [s, t],
                        [unit(ea), unit(cross(n, ea))],
                        [1.0 - s, s, t - 1.0, -t],
                        4,
                    )
                }
                _ => {
                    let (p, t0, t1, t2) = (v(0), v(1), v(2), v(3));
                    let (e0, e1) = (sub(t1, t0), sub(t2, t0));
                    let r = sub(p, t0);
                    let [b1, b2] = solve2(
                        dot(e0, e0),
                        dot(e0, e1),
                        dot(e1, e1),
                        [dot(e0, r), dot(e1, r)],
                    );
                    let n = cross(e0, e1);
                    let d2 = pt_distance2(p, t0, t1, t2, point_triangle_type(p, t0, t1, t2));
                    (
                        d2,
                        [b1, b2],
                        [unit(e0), unit(cross(n, e0))],
                        [1.0, b1 + b2 - 1.0, -b1, -b2],
                        4,
                    )
                }
            };
            counts[c.kind as usize] += 1;
            items.push(Tangential {
                ids: c.ids,
                verts: c.verts,
                weight: c.weight,
                normal_force: b.force_magnitude(d2, set.dmin),
                mu_s,
                mu_k,
                closest,
                basis,
                coef,
                nverts,
            });
        }
        Ok(Self {
            items,
            counts,
            num_vertices: x.len() / 3,
        })
    }

    fn __len__(&self) -> usize {
        self.items.len()
    }

    fn ids(&self, py: Python<'_>, kind: &str) -> PyResult<Py<numpy::PyArray2<i64>>> {
        let k = super::kind_code(kind)?;
        let start: usize = self.counts[..k].iter().sum();
        let sel = &self.items[start..start + self.counts[k]];
        array2(
            py,
            sel.len(),
            2,
            sel.iter()
                .flat_map(|c| [c.ids[0] as i64, c.ids[1] as i64])
                .collect(),
        )
    }

    #[getter]
    fn normal_force_magnitude(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        array1(py, self.items.iter().map(|c| c.normal_force).collect())
    }
    #[getter]
    fn mu_s(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        array1(py, self.items.iter().map(|c| c.mu_s).collect())
    }
    #[getter]
    fn mu_k(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        array1(py, self.items.iter().map(|c| c.mu_k).collect())
    }
    #[getter]
    fn weights(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        array1(py, self.items.iter().map(|c| c.weight).collect())
    }
    #[getter]
    fn closest_points(&self, py: Python<'_>) -> PyResult<Py<numpy::PyArray2<f64>>> {
        array2(
            py,
            self.items.len(),
            2,
            self.items.iter().flat_map(|c| c.closest).collect(),
        )
    }
    #[getter]
    fn tangent_bases(&self, py: Python<'_>) -> PyResult<Py<PyArray3<f64>>> {
        let flat: Vec<f64> = (self.items.iter())
            .flat_map(|c| (0..3).flat_map(move |r| [c.basis[0][r], c.basis[1][r]]))
            .collect();
        let a = numpy::ndarray::Array3::from_shape_vec((self.items.len(), 3, 2), flat)
            .map_err(|e| input_error(e.to_string()))?;
        Ok(a.into_pyarray(py).unbind())
    }

    fn energy(&self, py: Python<'_>, u: PyReadonlyArray2<'_, f64>, eps_v: f64) -> PyResult<f64> {
        let u = self.input(&u)?;
        Ok(py.detach(|| {
            self.items
                .iter()
                .map(|c| {
                    let t = tangential(c, u);
                    c.weight * c.normal_force * c.mu_k * f0(norm2(t), eps_v)
                })
                .sum()
        }))
    }

    fn gradient(
        &self,
        py: Python<'_>,
        u: PyReadonlyArray2<'_, f64>,
        eps_v: f64,
    ) -> PyResult<Py<PyArray1<f64>>> {
        let u = self.input(&u)?;
        let g = py.detach(|| {
            let mut g = vec![0.0; u.len()];
            for c in &self.items {
                let t = tangential(c, u);
                let s = c.weight * c.normal_force * c.mu_k * f1_over_x(norm2(t), eps_v);
                let gt = [s * t[0], s * t[1]];
                for k in 0..c.nverts {
                    for r in 0..3 {
                        g[3 * c.verts[k] as usize + r] +=
                            c.coef[k] * (c.basis[0][r] * gt[0] + c.basis[1][r] * gt[1]);
                    }
                }
            }
            g
        });
        Ok(array1(py, g))
    }

    fn hessian(
        &self,
        py: Python<'_>,
        u: PyReadonlyArray2<'_, f64>,
        eps_v: f64,
        psd: u8,
    ) -> PyResult<super::CsrArrays> {
        let u = self.input(&u)?;
        let psd = psd_of(psd)?;
        let m = py.detach(|| {
            let mut asm = Assembler::new(u.len());
            let mut h = [0.0; 144];
            let mut dofs = [0usize; 12];
            for c in &self.items {
                let t = tangential(c, u);
                let y = norm2(t);
                let scale = c.weight * c.normal_force;
                let mu = c.mu_k;
                let projecting = psd != Psd::None;
                let inner: [f64; 4] = if y >= eps_v {
                    if projecting && scale <= 0.0 {
                        [0.0; 4]
                    } else {
                        let k = scale * mu * f1_over_x(y, eps_v) / (y * y);
                        let p = [-t[1], t[0]];
                        [
                            k * p[0] * p[0],
                            k * p[0] * p[1],
                            k * p[1] * p[0],
                            k * p[1] * p[1],
                        ]
                    }
                } else if y == 0.0 {
                    if projecting && scale <= 0.0 {
                        [0.0; 4]
                    } else {
                        let k = scale * mu * f1_over_x(y, eps_v);
                        [k, 0.0, 0.0, k]
                    }
                } else {
                    let f2 = mu * f2_x_minus_f1_over_x3(y, eps_v);
                    let f1 = mu * f1_over_x(y, eps_v);
                    let mut a = [
                        scale * (f2 * t[0] * t[0] + f1),
                        scale * f2 * t[0] * t[1],
                        scale * f2 * t[1] * t[0],
                        scale * (f2 * t[1] * t[1] + f1),
                    ];
                    project(&mut a, 2, psd);
                    a
                };
                // P inner P^T (3 x 3), then the blocks c_k c_l (P inner P^T).
                let mut q = [[0.0; 3]; 3];
                for (r, row) in q.iter_mut().enumerate() {
                    let pr = [c.basis[0][r], c.basis[1][r]];
                    for (s, q_rs) in row.iter_mut().enumerate() {
                        let ps = [c.basis[0][s], c.basis[1][s]];
                        *q_rs = pr[0] * (inner[0] * ps[0] + inner[1] * ps[1])
                            + pr[1] * (inner[2] * ps[0] + inner[3] * ps[1]);
                    }
                }
                let m = 3 * c.nverts;
                for k in 0..c.nverts {
                    for l in 0..c.nverts {
                        for r in 0..3 {
                            for s in 0..3 {
                                h[(3 * k + r) * m + 3 * l + s] = c.coef[k] * c.coef[l] * q[r][s];
                            }
                        }
                    }
                    for r in 0..3 {
                        dofs[3 * k + r] = 3 * c.verts[k] as usize + r;
                    }
                }
                asm.add(&dofs[..m], &h[..m * m]);
            }
            asm.finish()
        });
        Ok(csr_tuple(py, m))
    }
}

impl IpcTangentialCollisions {
    fn input<'a>(&self, u: &'a PyReadonlyArray2<'_, f64>) -> PyResult<&'a [f64]> {
        let u = flat(u, "X")?;
        if u.len() / 3 < self.num_vertices {
            return Err(input_error(format!(
                "X has {} vertices, the collisions were built on {}",
                u.len() / 3,
                self.num_vertices
            )));
        }
        Ok(u)
    }
}

/// `P^T Gamma u`: the tangential relative velocity (2-vector).
fn tangential(c: &Tangential, u: &[f64]) -> [f64; 2] {
    let mut rel = [0.0; 3];
    for k in 0..c.nverts {
        let i = 3 * c.verts[k] as usize;
        for r in 0..3 {
            rel[r] += c.coef[k] * u[i + r];
        }
    }
    [dot(c.basis[0], rel), dot(c.basis[1], rel)]
}

fn norm2(t: [f64; 2]) -> f64 {
    (t[0] * t[0] + t[1] * t[1]).sqrt()
}
