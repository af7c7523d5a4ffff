//! The barrier potential over a collision set: energy, gradient and sparse Hessian (ipctk's
//! `BarrierPotential` and `NormalPotential`).

// Index loops over small fixed-size arrays read as the formulas do.
#![allow(clippy::needless_range_loop)]

use super::barrier::Barrier;
use super::collisions::{EeCollision, NormalCollisions};
use super::psd::{project_translation_free, PsdProjection};
use super::sparse::{BlockPattern, SparseMatrix};
use crate::distance::{
    edge_edge_distance_gradient, edge_edge_distance_hessian, edge_edge_distance_of_type,
    edge_edge_mollifier_gradient, edge_edge_mollifier_hessian, edge_edge_mollifier_scalar,
    point_line_distance, point_line_distance_gradient, point_line_distance_hessian,
    point_plane_distance, point_plane_distance_gradient, point_plane_distance_hessian,
};
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
        let mut add = |ids: &[u32], local: &[f64]| {
            for (k, &v) in ids.iter().enumerate() {
                let gv = &mut g[3 * v as usize..3 * v as usize + 3];
                for c in 0..3 {
                    gv[c] += local[3 * k + c];
                }
            }
        };
        let dmin = collisions.dmin;
        let p = |v: u32| DVec3::from(x[v as usize]);
        for c in &collisions.vv {
            let y = p(c.vertices[0]) - p(c.vertices[1]);
            let b1 = c.weight * self.first_derivative(y.length_squared(), dmin);
            if b1 != 0.0 {
                let s = 2.0 * b1 * y;
                add(&c.vertices, &[s.x, s.y, s.z, -s.x, -s.y, -s.z]);
            }
        }
        for c in &collisions.ev {
            let ids = [c.vertex, c.edge[0], c.edge[1]];
            let [q0, q1, q2] = ids.map(p);
            let b1 = c.weight * self.first_derivative(point_line_distance(q0, q1, q2), dmin);
            if b1 != 0.0 {
                add(
                    &ids,
                    &point_line_distance_gradient(q0, q1, q2).map(|v| b1 * v),
                );
            }
        }
        for c in &collisions.ee {
            let ids = [c.a[0], c.a[1], c.b[0], c.b[1]];
            if let Some(l) = self.edge_edge_local(c, ids.map(p), dmin, false) {
                add(&ids, &l.g);
            }
        }
        for c in &collisions.fv {
            let ids = [c.vertex, c.triangle[0], c.triangle[1], c.triangle[2]];
            let [q0, q1, q2, q3] = ids.map(p);
            let b1 = c.weight * self.first_derivative(point_plane_distance(q0, q1, q2, q3), dmin);
            if b1 != 0.0 {
                add(
                    &ids,
                    &point_plane_distance_gradient(q0, q1, q2, q3).map(|v| b1 * v),
                );
            }
        }
        g
    }

    /// The Hessian of [`energy`](Self::energy), `3 n x 3 n`, each collision's Hessian
    /// projected by `projection` before it is added (ipctk's `hessian(collisions, mesh, x,
    /// project_hessian_to_psd)`).
    ///
    /// The pattern is the union of the collisions' vertex blocks (3 x 3), found from the
    /// vertex indices alone before any Hessian is computed; each local Hessian is then
    /// projected in the complement of the translations (see
    /// [`project_to_psd`](super::project_to_psd) for the plain projection it equals) and
    /// added where it belongs, with no buffer of local matrices.
    pub fn hessian(
        &self,
        collisions: &NormalCollisions,
        x: &[[f64; 3]],
        projection: PsdProjection,
    ) -> SparseMatrix {
        let pattern = BlockPattern::new(x.len(), Stencils::of(collisions));
        let mut blocks = vec![0.0f64; pattern.nnz()];
        self.for_each_hessian(collisions, x, projection, |index, ids, h| {
            pattern.add(index, ids, h, &mut blocks);
        });
        pattern.into_matrix(blocks)
    }

    /// The hessian's parts timed one by one over the set, in seconds of `clock` (for the
    /// benchmarks; internals only): `[pattern, local Hessians, local Hessians projected,
    /// whole hessian]`; the projection is the third less the second, the assembly (scatter
    /// and CSR layout) the fourth less the first and third.
    #[cfg(feature = "internals")]
    #[doc(hidden)]
    pub fn hessian_parts(
        &self,
        collisions: &NormalCollisions,
        x: &[[f64; 3]],
        projection: PsdProjection,
        clock: impl Fn() -> f64,
    ) -> [f64; 4] {
        let t0 = clock();
        let pattern = BlockPattern::new(x.len(), Stencils::of(collisions));
        let t1 = clock();
        std::hint::black_box(&pattern);
        let mut sum = 0.0;
        let t2 = clock();
        self.for_each_hessian(collisions, x, PsdProjection::None, |_, _, h| sum += h[1]);
        let t3 = clock();
        self.for_each_hessian(collisions, x, projection, |_, _, h| sum += h[1]);
        let t4 = clock();
        std::hint::black_box(sum);
        std::hint::black_box(self.hessian(collisions, x, projection));
        let t5 = clock();
        [t1 - t0, t3 - t2, t4 - t3, t5 - t4]
    }

    /// Calls `f(collision index, vertex ids, local Hessian row-major)` for each collision
    /// with a nonzero Hessian, its Hessian projected by `projection`, kind by kind in the
    /// set's order (the order of [`Stencils`]).
    fn for_each_hessian(
        &self,
        collisions: &NormalCollisions,
        x: &[[f64; 3]],
        projection: PsdProjection,
        mut f: impl FnMut(usize, &[u32], &[f64]),
    ) {
        let dmin = collisions.dmin;
        let p = |v: u32| DVec3::from(x[v as usize]);
        let mut index = 0usize;
        for c in &collisions.vv {
            let y = p(c.vertices[0]) - p(c.vertices[1]);
            if let Some(h) = self.vertex_vertex_hessian(y, c.weight, dmin, projection) {
                f(index, &c.vertices, h.as_flattened());
            }
            index += 1;
        }
        for c in &collisions.ev {
            let ids = [c.vertex, c.edge[0], c.edge[1]];
            let [q0, q1, q2] = ids.map(p);
            let d2 = point_line_distance(q0, q1, q2);
            let (b1, b2) = self.derivatives(d2, c.weight, dmin);
            if b1 != 0.0 || b2 != 0.0 {
                let mut h = chain(
                    b1,
                    b2,
                    &point_line_distance_gradient(q0, q1, q2),
                    &point_line_distance_hessian(q0, q1, q2),
                );
                project_translation_free::<3, 2, 9, 6>(&mut h, projection);
                f(index, &ids, h.as_flattened());
            }
            index += 1;
        }
        for c in &collisions.ee {
            let ids = [c.a[0], c.a[1], c.b[0], c.b[1]];
            if let Some(mut l) = self.edge_edge_local(c, ids.map(p), dmin, true) {
                project_translation_free::<4, 3, 12, 9>(&mut l.h, projection);
                f(index, &ids, l.h.as_flattened());
            }
            index += 1;
        }
        for c in &collisions.fv {
            let ids = [c.vertex, c.triangle[0], c.triangle[1], c.triangle[2]];
            let [q0, q1, q2, q3] = ids.map(p);
            let d2 = point_plane_distance(q0, q1, q2, q3);
            let (b1, b2) = self.derivatives(d2, c.weight, dmin);
            if b1 != 0.0 || b2 != 0.0 {
                let mut h = chain(
                    b1,
                    b2,
                    &point_plane_distance_gradient(q0, q1, q2, q3),
                    &point_plane_distance_hessian(q0, q1, q2, q3),
                );
                project_translation_free::<4, 3, 12, 9>(&mut h, projection);
                f(index, &ids, h.as_flattened());
            }
            index += 1;
        }
    }

    /// `(w b'(d2), w b''(d2))`.
    #[inline]
    fn derivatives(&self, d2: f64, w: f64, dmin: f64) -> (f64, f64) {
        (
            w * self.first_derivative(d2, dmin),
            w * self.second_derivative(d2, dmin),
        )
    }

    /// A vertex-vertex collision's Hessian over `(p, q)`, `y = p - q`, projected in closed
    /// form: `[[K, -K], [-K, K]]` with `K = 2 b' I + 4 b'' y y^T`, whose reduced matrix
    /// `2 K` has the eigenvalue `2 b'` twice (across `y`) and `2 b' + 4 b'' |y|^2` (along
    /// `y`). `None` when the pair is beyond `dhat`.
    #[inline]
    fn vertex_vertex_hessian(
        &self,
        y: DVec3,
        w: f64,
        dmin: f64,
        projection: PsdProjection,
    ) -> Option<[[f64; 6]; 6]> {
        let yy = y.length_squared();
        let (b1, b2) = self.derivatives(yy, w, dmin);
        if b1 == 0.0 && b2 == 0.0 {
            return None;
        }
        let (across, along) = (2.0 * b1, 2.0 * b1 + 4.0 * b2 * yy);
        let map = |l: f64| match projection {
            PsdProjection::None => l,
            PsdProjection::Clamp => l.max(0.0),
            PsdProjection::Abs => l.abs(),
        };
        // K = a I + c y y^T: a the eigenvalue across y, a + c |y|^2 along it. ipctk leaves a
        // PSD matrix as it is: keep K's own entries then.
        let (a, c) = if projection == PsdProjection::None || (across >= 0.0 && along >= 0.0) {
            (across, 4.0 * b2)
        } else if yy > 0.0 {
            (map(across), (map(along) - map(across)) / yy)
        } else {
            (map(across), 0.0)
        };
        let ya = y.to_array();
        let mut h = [[0.0; 6]; 6];
        for i in 0..3 {
            for j in 0..3 {
                let k = c * ya[i] * ya[j] + if i == j { a } else { 0.0 };
                h[i][j] = k;
                h[i + 3][j + 3] = k;
                h[i][j + 3] = -k;
                h[i + 3][j] = -k;
            }
        }
        Some(h)
    }

    /// The edge-edge collision's gradient and (when `hess`) Hessian of `w m(x) b(d^2(x))`:
    /// the product rule with the mollifier `m` (1, with no derivatives, away from
    /// parallel). `None` when everything vanishes (the pair beyond `dhat`).
    #[inline]
    fn edge_edge_local(
        &self,
        c: &EeCollision,
        q: [DVec3; 4],
        dmin: f64,
        hess: bool,
    ) -> Option<Local12> {
        let [a0, a1, b0, b1] = q;
        let w = c.weight;
        let d2 = edge_edge_distance_of_type(a0, a1, b0, b1, c.kind);
        let (f1, f2) = self.derivatives(d2, w, dmin);
        let cross = (a1 - a0).cross(b1 - b0).length_squared();
        let dg = edge_edge_distance_gradient(a0, a1, b0, b1, c.kind);
        if cross >= c.eps_x {
            if f1 == 0.0 && f2 == 0.0 {
                return None;
            }
            let g = dg.map(|v| f1 * v);
            let h = if hess {
                chain(
                    f1,
                    f2,
                    &dg,
                    &edge_edge_distance_hessian(a0, a1, b0, b1, c.kind),
                )
            } else {
                [[0.0; 12]; 12]
            };
            return Some(Local12 { g, h });
        }
        let m = edge_edge_mollifier_scalar(cross, c.eps_x);
        let f = w * self.value(d2, dmin);
        if m <= 0.0 {
            // m = 0 only with a zero cross product, where grad m = 0 too.
            if !hess || f == 0.0 || !f.is_finite() {
                return None;
            }
            let hm = edge_edge_mollifier_hessian(a0, a1, b0, b1, c.eps_x);
            let h = hm.map(|row| row.map(|v| f * v));
            return Some(Local12 { g: [0.0; 12], h });
        }
        if f == 0.0 && f1 == 0.0 && f2 == 0.0 {
            return None;
        }
        let gm = edge_edge_mollifier_gradient(a0, a1, b0, b1, c.eps_x);
        // grad f = f1 grad d2.
        let gf = dg.map(|v| f1 * v);
        let mut g = [0.0; 12];
        for i in 0..12 {
            g[i] = f * gm[i] + m * gf[i];
        }
        let mut h = [[0.0; 12]; 12];
        if hess {
            let hm = edge_edge_mollifier_hessian(a0, a1, b0, b1, c.eps_x);
            let hd = edge_edge_distance_hessian(a0, a1, b0, b1, c.kind);
            for i in 0..12 {
                for j in 0..12 {
                    h[i][j] = f * hm[i][j]
                        + gf[i] * gm[j]
                        + gm[i] * gf[j]
                        + m * (f2 * dg[i] * dg[j] + f1 * hd[i][j]);
                }
            }
        }
        Some(Local12 { g, h })
    }
}

/// An edge-edge collision's local gradient and Hessian.
struct Local12 {
    g: [f64; 12],
    h: [[f64; 12]; 12],
}

/// `b1 hess d2 + b2 grad d2 grad d2^T`: the chain rule of `b(d2(x))`.
#[inline]
fn chain<const N: usize>(b1: f64, b2: f64, g: &[f64; N], h: &[[f64; N]; N]) -> [[f64; N]; N] {
    let mut out = [[0.0; N]; N];
    for i in 0..N {
        let s = b2 * g[i];
        for j in 0..N {
            out[i][j] = s * g[j] + b1 * h[i][j];
        }
    }
    out
}

/// The collisions' vertex stencils in the order of [`BarrierPotential::hessian`]: the
/// vertex-vertex, edge-vertex, edge-edge and face-vertex collisions, each as `visit`
/// names its vertices.
struct Stencils<'a>(&'a NormalCollisions);

impl<'a> Stencils<'a> {
    fn of(c: &'a NormalCollisions) -> Self {
        Self(c)
    }
}

impl super::sparse::StencilSource for Stencils<'_> {
    fn for_each(&self, mut f: impl FnMut(&[u32])) {
        let c = self.0;
        for v in &c.vv {
            f(&v.vertices);
        }
        for e in &c.ev {
            f(&[e.vertex, e.edge[0], e.edge[1]]);
        }
        for e in &c.ee {
            f(&[e.a[0], e.a[1], e.b[0], e.b[1]]);
        }
        for t in &c.fv {
            f(&[t.vertex, t.triangle[0], t.triangle[1], t.triangle[2]]);
        }
    }
}
