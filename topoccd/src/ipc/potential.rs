//! The barrier potential over a collision set: energy, gradient and sparse Hessian (ipctk's
//! `BarrierPotential` and `NormalPotential`).

// Index loops over small fixed-size arrays read as the formulas do.
#![allow(clippy::needless_range_loop)]

use super::barrier::Barrier;
use super::collisions::NormalCollisions;
use super::deriv::{self, Local};
use super::psd::{project_to_psd, PsdProjection};
use super::sparse::SparseMatrix;
use crate::math::DVec3;

/// The barrier potential `kappa * sum_c w_c m_c(x) b(d_c(x)^2 - dmin^2, (2 dmin + dhat) dhat)`
/// (ipctk's `BarrierPotential`): `w_c` the collision's weight, `m_c` the edge-edge mollifier
/// (1 for the other kinds), `d_c^2` the squared distance of the collision's type, `b` the
/// [`Barrier`]. With `use_physical_barrier` the barrier is scaled by
/// `dhat / units((2 dmin + dhat) dhat)`, as ipctk does.
///
/// ```
/// use topoccd::ipc::{Barrier, BarrierPotential};
/// let b = BarrierPotential { barrier: Barrier::Cubic, ..BarrierPotential::new(1e-3, 1.0) };
/// assert_eq!(b.stiffness, 1.0);
/// // The value at one squared distance, as ipctk's `B(d^2, dmin)`.
/// let (d2, dh) = (0.25e-6f64, 1e-6f64);
/// assert!((b.value(d2, 0.0) - (-2.0 / 3.0 / dh * (d2 - dh).powi(3))).abs() < 1e-20);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BarrierPotential {
    /// The barrier function. Default [`Barrier::ClampedLog`].
    pub barrier: Barrier,
    /// The activation distance `dhat` (not squared), `> 0`.
    pub dhat: f64,
    /// The stiffness `kappa`, `> 0`.
    pub stiffness: f64,
    /// ipctk's `use_physical_barrier`. Default `false`.
    pub use_physical_barrier: bool,
}

impl BarrierPotential {
    /// The clamped log barrier with `dhat` and `stiffness` (ipctk's
    /// `BarrierPotential(dhat, stiffness)`).
    pub fn new(dhat: f64, stiffness: f64) -> Self {
        Self {
            barrier: Barrier::ClampedLog,
            dhat,
            stiffness,
            use_physical_barrier: false,
        }
    }

    /// The scale of the barrier: `kappa`, times `dhat / units` for the physical barrier.
    #[inline]
    fn scale(&self, dmin: f64) -> f64 {
        let dh = (2.0 * dmin + self.dhat) * self.dhat;
        if self.use_physical_barrier {
            self.stiffness * self.dhat / self.barrier.units(dh)
        } else {
            self.stiffness
        }
    }

    /// The potential of one squared distance `d2` (ipctk's `B(d2, dmin)`).
    pub fn value(&self, d2: f64, dmin: f64) -> f64 {
        let dh = (2.0 * dmin + self.dhat) * self.dhat;
        self.scale(dmin) * self.barrier.value(d2 - dmin * dmin, dh)
    }

    /// Its first derivative in `d2` (ipctk's `B.gradient(d2, dmin)`).
    pub fn first_derivative(&self, d2: f64, dmin: f64) -> f64 {
        let dh = (2.0 * dmin + self.dhat) * self.dhat;
        self.scale(dmin) * self.barrier.first_derivative(d2 - dmin * dmin, dh)
    }

    /// Its second derivative in `d2` (ipctk's `B.hessian(d2, dmin)`).
    pub fn second_derivative(&self, d2: f64, dmin: f64) -> f64 {
        let dh = (2.0 * dmin + self.dhat) * self.dhat;
        self.scale(dmin) * self.barrier.second_derivative(d2 - dmin * dmin, dh)
    }

    /// The energy over the collision set at positions `x` (ipctk's `B(collisions, mesh, x)`).
    pub fn energy(&self, collisions: &NormalCollisions, x: &[[f64; 3]]) -> f64 {
        let dmin = collisions.dmin;
        let p = |v: u32| DVec3::from(x[v as usize]);
        let mut e = 0.0;
        for c in &collisions.vv {
            let d2 = (p(c.vertices[0]) - p(c.vertices[1])).length_squared();
            e += c.weight * self.value(d2, dmin);
        }
        for c in &collisions.ev {
            let (pv, e0, e1) = (p(c.vertex), p(c.edge[0]), p(c.edge[1]));
            e += c.weight * self.value(super::types::point_line_sq(pv, e0, e1), dmin);
        }
        for c in &collisions.ee {
            let q = [c.a[0], c.a[1], c.b[0], c.b[1]].map(p);
            let d2 = super::types::edge_edge_sq(q[0], q[1], q[2], q[3], c.kind);
            let u = (q[1] - q[0]).cross(q[3] - q[2]).length_squared();
            let m = if u < c.eps_x {
                let r = u / c.eps_x;
                (2.0 - r) * r
            } else {
                1.0
            };
            e += c.weight * m * self.value(d2, dmin);
        }
        for c in &collisions.fv {
            let [t0, t1, t2] = c.triangle.map(p);
            e += c.weight * self.value(super::types::point_plane_sq(p(c.vertex), t0, t1, t2), dmin);
        }
        e
    }

    /// The gradient of [`energy`](Self::energy), dense, of length `3 n`
    /// (`x0 y0 z0 x1 ...`).
    pub fn gradient(&self, collisions: &NormalCollisions, x: &[[f64; 3]]) -> Vec<f64> {
        let mut g = vec![0.0; 3 * x.len()];
        self.visit(collisions, x, false, |ids, local_g, _| {
            for (k, &v) in ids.iter().enumerate() {
                for c in 0..3 {
                    g[3 * v as usize + c] += local_g[3 * k + c];
                }
            }
        });
        g
    }

    /// The Hessian of [`energy`](Self::energy), `3 n x 3 n`, each collision's Hessian
    /// projected by `projection` before it is added (ipctk's `hessian(collisions, mesh, x,
    /// project_hessian_to_psd)`).
    pub fn hessian(
        &self,
        collisions: &NormalCollisions,
        x: &[[f64; 3]],
        projection: PsdProjection,
    ) -> SparseMatrix {
        let mut ids_all: Vec<u32> = Vec::with_capacity(4 * collisions.len());
        let mut offsets: Vec<usize> = Vec::with_capacity(collisions.len() + 1);
        let mut vals: Vec<f64> = Vec::with_capacity(144 * collisions.len());
        offsets.push(0);
        self.visit(collisions, x, true, |ids, _, local_h| {
            let n = 3 * ids.len();
            let start = vals.len();
            vals.extend_from_slice(&local_h[..n * n]);
            project_to_psd(&mut vals[start..], n, projection);
            ids_all.extend_from_slice(ids);
            offsets.push(ids_all.len());
        });
        SparseMatrix::from_vertex_blocks(x.len(), &ids_all, &offsets, &vals)
    }

    /// Calls `f(vertex ids, local gradient, local Hessian row-major)` for each collision
    /// with a nonzero contribution, kind by kind in the set's order.
    fn visit(
        &self,
        collisions: &NormalCollisions,
        x: &[[f64; 3]],
        hess: bool,
        mut f: impl FnMut(&[u32], &[f64], &[f64]),
    ) {
        let dmin = collisions.dmin;
        let p = |v: u32| DVec3::from(x[v as usize]);
        let mut hbuf = [0.0f64; 144];
        let mut gbuf = [0.0f64; 12];
        for c in &collisions.vv {
            let l = deriv::vv(c.vertices.map(p), hess);
            if self.plain(l, c.weight, dmin, hess, &mut gbuf, &mut hbuf) {
                f(&c.vertices, &gbuf[..6], &hbuf[..36]);
            }
        }
        for c in &collisions.ev {
            let ids = [c.vertex, c.edge[0], c.edge[1]];
            let l = deriv::ev(ids.map(p), hess);
            if self.plain(l, c.weight, dmin, hess, &mut gbuf, &mut hbuf) {
                f(&ids, &gbuf[..9], &hbuf[..81]);
            }
        }
        for c in &collisions.ee {
            let ids = [c.a[0], c.a[1], c.b[0], c.b[1]];
            let q = ids.map(p);
            if self.mollified(
                q, c.kind, c.eps_x, c.weight, dmin, hess, &mut gbuf, &mut hbuf,
            ) {
                f(&ids, &gbuf, &hbuf);
            }
        }
        for c in &collisions.fv {
            let ids = [c.vertex, c.triangle[0], c.triangle[1], c.triangle[2]];
            let l = deriv::fv(ids.map(p), hess);
            if self.plain(l, c.weight, dmin, hess, &mut gbuf, &mut hbuf) {
                f(&ids, &gbuf, &hbuf);
            }
        }
    }

    /// `w b(d^2)`'s gradient `w b' grad d2` and Hessian `w (b'' grad d2 grad d2^T + b'
    /// hess d2)` into the buffers; `false` when both vanish (the pair beyond `dhat`).
    #[inline]
    fn plain<const N: usize>(
        &self,
        l: Local<N>,
        w: f64,
        dmin: f64,
        hess: bool,
        g: &mut [f64; 12],
        h: &mut [f64; 144],
    ) -> bool {
        let b1 = w * self.first_derivative(l.d2, dmin);
        let b2 = w * self.second_derivative(l.d2, dmin);
        if b1 == 0.0 && b2 == 0.0 {
            return false;
        }
        for i in 0..N {
            g[i] = b1 * l.g[i];
        }
        if hess {
            for i in 0..N {
                let s = b2 * l.g[i];
                for j in 0..N {
                    h[i * N + j] = s * l.g[j] + b1 * l.h[i][j];
                }
            }
        }
        true
    }

    /// The mollified edge-edge collision: the product rule on `w m(x) b(d^2(x))`.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn mollified(
        &self,
        q: [DVec3; 4],
        kind: crate::distance::EdgeEdgeType,
        eps_x: f64,
        w: f64,
        dmin: f64,
        hess: bool,
        g: &mut [f64; 12],
        h: &mut [f64; 144],
    ) -> bool {
        let (m, gm, hm) = deriv::mollifier(q, eps_x, hess);
        let l = deriv::ee(q, kind, hess);
        let f = w * self.value(l.d2, dmin);
        if m <= 0.0 {
            // m = 0 only with a zero cross product, where grad m = 0 too.
            if !hess || f == 0.0 || !f.is_finite() {
                return false;
            }
            g.fill(0.0);
            for i in 0..12 {
                for j in 0..12 {
                    h[i * 12 + j] = f * hm[i][j];
                }
            }
            return true;
        }
        let b1 = w * self.first_derivative(l.d2, dmin);
        let b2 = w * self.second_derivative(l.d2, dmin);
        if f == 0.0 && b1 == 0.0 && b2 == 0.0 {
            return false;
        }
        // grad f = b1 grad d2.
        let mut gf = [0.0; 12];
        for i in 0..12 {
            gf[i] = b1 * l.g[i];
            g[i] = f * gm[i] + m * gf[i];
        }
        if hess {
            for i in 0..12 {
                for j in 0..12 {
                    h[i * 12 + j] = f * hm[i][j]
                        + gf[i] * gm[j]
                        + gm[i] * gf[j]
                        + m * (b2 * l.g[i] * l.g[j] + b1 * l.h[i][j]);
                }
            }
        }
        true
    }
}
