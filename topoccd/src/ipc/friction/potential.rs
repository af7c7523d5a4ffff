//! The smooth friction dissipative potential over the tangential collisions (ipctk's
//! `FrictionPotential`): energy, gradient, Hessian and force, on velocities.
//!
//! Per collision `k`, with the lagged tangent basis `P` (3×2), relative-velocity coefficients
//! `gamma` and `u = P^T sum_i gamma_i v_i` (the tangential slip velocity, 2-vector):
//!
//! - energy `w N g0(|u|)`, with `g0` = [`smooth_mu_f0`];
//! - gradient, vertex `i`: `gamma_i P (w N g1(|u|)/|u| u)`, `g1` = `mu f1`;
//! - Hessian, block `(i, j)`: `gamma_i gamma_j P H P^T`, with the 2×2
//!   `H = w N (g2(|u|) |u| - g1(|u|))/|u|^3 u u^T + w N g1(|u|)/|u| I`.
//!
//! The derivation: `d|u|/du = u/|u|`, so `grad_u g0(|u|) = g1 u/|u|`; differentiating
//! `g1(|u|)/|u|` gives `(g2 |u| - g1)/|u|^3 u^T`. Above `eps_v`, `g1 = mu_k`, `g2 = 0`, and `H` is
//! `w N mu_k/|u|` times the projector on the direction orthogonal to `u`: positive
//! semi-definite, as at `u = 0` where `H = w N g1/|u| I`. In between, only the 2×2 `H` is
//! projected, as ipctk does.

use super::mollifier::{smooth_mu_f0, smooth_mu_f1_over_x, smooth_mu_f2_x_minus_mu_f1_over_x3};
use super::tangential_collisions::{TangentialCollision, TangentialCollisions};
use super::FrictionError;
use crate::ipc::{PsdProjection, SparseMatrix};
use crate::math::DVec3;

/// The friction dissipative potential with the smooth mollifier's threshold `eps_v`.
///
/// ```
/// use topoccd::ipc::friction::{FrictionPotential, NormalStencil, StencilKind,
///     TangentialCollisions, FrictionCoefficients};
/// // A vertex 0.01 above a triangle, pressed with a unit normal force.
/// let x = [[0.2, 0.2, 0.01], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let fv = NormalStencil { kind: StencilKind::FaceVertex, primitives: [0, 0],
///     vertices: [0, 1, 2, 3], weight: 1.0, dmin: 0.0, eps_x: 0.0 };
/// let c = TangentialCollisions::build_from_stencils(&x, [fv], |_, _| 1.0,
///     FrictionCoefficients::uniform(0.5))?;
/// let d = FrictionPotential::new(1e-3)?;
/// // Sliding along x at speed 1: the energy is mu N |u| and the force opposes the motion.
/// let v = [[1.0, 0.0, 0.0], [0.0; 3], [0.0; 3], [0.0; 3]];
/// assert!((d.energy(&c, &v)? - 0.5).abs() < 1e-12);
/// assert!((d.gradient(&c, &v)?[0] - 0.5).abs() < 1e-12);
/// # Ok::<(), topoccd::ipc::friction::FrictionError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionPotential {
    eps_v: f64,
}

impl FrictionPotential {
    /// A friction potential with threshold `eps_v > 0` (a speed, in the unit of the
    /// velocities it is evaluated on: with velocities `(x - x^t)/h`, ipctk's `eps_v`; the
    /// older IPC papers' `eps_v h` when evaluated on displacements).
    ///
    /// # Errors
    /// `eps_v` not positive and finite.
    pub fn new(eps_v: f64) -> Result<Self, FrictionError> {
        if !(eps_v > 0.0 && eps_v.is_finite()) {
            return Err(FrictionError::BadEpsV { eps_v });
        }
        Ok(Self { eps_v })
    }

    /// The mollifier's threshold.
    #[inline]
    pub fn eps_v(&self) -> f64 {
        self.eps_v
    }

    /// The potential `D(v)`, summed over the collisions.
    ///
    /// # Errors
    /// A collision's vertex outside `velocities`.
    pub fn energy(
        &self,
        collisions: &TangentialCollisions,
        velocities: &[[f64; 3]],
    ) -> Result<f64, FrictionError> {
        let v = check(collisions, velocities)?;
        Ok(collisions.iter().map(|c| self.local_energy(c, v)).sum())
    }

    /// The gradient of `D` with respect to the velocities, `3 n` entries (`x y z` per vertex).
    ///
    /// # Errors
    /// A collision's vertex outside `velocities`.
    pub fn gradient(
        &self,
        collisions: &TangentialCollisions,
        velocities: &[[f64; 3]],
    ) -> Result<Vec<f64>, FrictionError> {
        let v = check(collisions, velocities)?;
        let mut g = vec![0.0; 3 * v.len()];
        for c in collisions.iter() {
            let (_, dir) = self.slip(c, v);
            for (&vi, &gi) in c.vertex_ids().iter().zip(&c.gamma) {
                let d = dir * gi;
                g[3 * vi] += d.x;
                g[3 * vi + 1] += d.y;
                g[3 * vi + 2] += d.z;
            }
        }
        Ok(g)
    }

    /// The friction force `-grad D` (ipctk's `force` with the lagged normal forces kept from
    /// the build), `3 n` entries.
    ///
    /// # Errors
    /// A collision's vertex outside `velocities`.
    pub fn force(
        &self,
        collisions: &TangentialCollisions,
        velocities: &[[f64; 3]],
    ) -> Result<Vec<f64>, FrictionError> {
        let mut g = self.gradient(collisions, velocities)?;
        g.iter_mut().for_each(|x| *x = -*x);
        Ok(g)
    }

    /// The Hessian of `D` with respect to the velocities, `3n × 3n`, with each collision's
    /// 2×2 inner matrix projected to PSD by `project` (no projection with
    /// [`PsdProjection::None`]).
    ///
    /// # Errors
    /// A collision's vertex outside `velocities`.
    pub fn hessian(
        &self,
        collisions: &TangentialCollisions,
        velocities: &[[f64; 3]],
        project: PsdProjection,
    ) -> Result<SparseMatrix, FrictionError> {
        let v = check(collisions, velocities)?;
        // The local 3k×3k blocks end to end, assembled once by vertex blocks.
        let mut ids: Vec<u32> = Vec::with_capacity(4 * collisions.len());
        let mut offsets = Vec::with_capacity(collisions.len() + 1);
        let mut vals = Vec::with_capacity(144 * collisions.len());
        offsets.push(0);
        for c in collisions.iter() {
            let m = self.local_tangent_hessian(c, v, project);
            if m == [[0.0; 3]; 3] {
                continue;
            }
            let k = c.num_vertices();
            ids.extend(c.vertex_ids().iter().map(|&i| i as u32));
            offsets.push(ids.len());
            for a in 0..k {
                for r in &m {
                    for b in 0..k {
                        let s = c.gamma[a] * c.gamma[b];
                        vals.extend(r.iter().map(|x| s * x));
                    }
                }
            }
        }
        Ok(SparseMatrix::from_vertex_blocks(
            v.len(),
            &ids,
            &offsets,
            &vals,
        ))
    }

    /// One collision's energy.
    #[inline]
    fn local_energy(&self, c: &TangentialCollision, v: &[DVec3]) -> f64 {
        let r = c.relative_velocity(v);
        let y = tangential(c, r).length();
        c.weight * c.normal_force_magnitude * smooth_mu_f0(y, c.mu_s, c.mu_k, self.eps_v)
    }

    /// One collision's slip `u` and the 3-vector `P (w N g1/|u| u)` of its gradient.
    #[inline]
    fn slip(&self, c: &TangentialCollision, v: &[DVec3]) -> ([f64; 2], DVec3) {
        let r = c.relative_velocity(v);
        let u = tangential(c, r);
        let y = u.length();
        let s = c.weight
            * c.normal_force_magnitude
            * smooth_mu_f1_over_x(y, c.mu_s, c.mu_k, self.eps_v);
        let [t0, t1] = c.tangent_basis;
        ([u.x, u.y], t0 * (s * u.x) + t1 * (s * u.y))
    }

    /// One collision's `P H P^T` (3×3, symmetric), the Hessian block before the `gamma_i
    /// gamma_j` factors.
    fn local_tangent_hessian(
        &self,
        c: &TangentialCollision,
        v: &[DVec3],
        project: PsdProjection,
    ) -> [[f64; 3]; 3] {
        let r = c.relative_velocity(v);
        let u = tangential(c, r);
        let y = u.length();
        let scale = c.weight * c.normal_force_magnitude;
        let projecting = project != PsdProjection::None;
        let f1x = smooth_mu_f1_over_x(y, c.mu_s, c.mu_k, self.eps_v);
        let h: [[f64; 2]; 2] = if y > self.eps_v {
            // Sliding: w N g1/|u| times the projector on u's orthogonal, already PSD.
            if projecting && scale <= 0.0 {
                return [[0.0; 3]; 3];
            }
            let k = scale * f1x / (y * y);
            let p = [-u.y, u.x];
            [
                [k * p[0] * p[0], k * p[0] * p[1]],
                [k * p[1] * p[0], k * p[1] * p[1]],
            ]
        } else if y == 0.0 {
            if projecting && scale <= 0.0 {
                return [[0.0; 3]; 3];
            }
            let k = scale * f1x;
            [[k, 0.0], [0.0, k]]
        } else {
            let f2 = smooth_mu_f2_x_minus_mu_f1_over_x3(y, c.mu_s, c.mu_k, self.eps_v);
            let h = [
                [scale * (f2 * u.x * u.x + f1x), scale * (f2 * u.x * u.y)],
                [scale * (f2 * u.y * u.x), scale * (f2 * u.y * u.y + f1x)],
            ];
            project_2x2(h, project)
        };
        // P H P^T with P = [t0 t1].
        let [t0, t1] = c.tangent_basis;
        let a = t0 * h[0][0] + t1 * h[1][0]; // P H e0
        let b = t0 * h[0][1] + t1 * h[1][1]; // P H e1
        let mut m = [[0.0; 3]; 3];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = a[i] * t0[j] + b[i] * t1[j];
            }
        }
        m
    }
}

/// `P^T r` as a 2-vector (in a `DVec3` with z = 0, for its length).
#[inline]
fn tangential(c: &TangentialCollision, r: DVec3) -> DVec3 {
    DVec3::new(c.tangent_basis[0].dot(r), c.tangent_basis[1].dot(r), 0.0)
}

/// The velocities as `DVec3`, after checking that every collision's vertex is among them.
fn check<'a>(
    collisions: &TangentialCollisions,
    velocities: &'a [[f64; 3]],
) -> Result<&'a [DVec3], FrictionError> {
    let n = velocities.len();
    if let Some(&v) = collisions
        .iter()
        .flat_map(|c| c.vertex_ids())
        .find(|&&v| v >= n)
    {
        return Err(FrictionError::VertexOutOfRange {
            vertex: v,
            vertices: n,
        });
    }
    Ok(bytemuck::cast_slice(velocities))
}

/// Projects a symmetric 2×2 matrix to PSD: its negative eigenvalues set to 0 (clamp) or to
/// their absolute values (abs); unchanged when both are non-negative.
pub(crate) fn project_2x2(h: [[f64; 2]; 2], method: PsdProjection) -> [[f64; 2]; 2] {
    if method == PsdProjection::None {
        return h;
    }
    let (a, b, d) = (h[0][0], 0.5 * (h[0][1] + h[1][0]), h[1][1]);
    let mean = 0.5 * (a + d);
    let rad = (0.25 * (a - d) * (a - d) + b * b).sqrt();
    let (l0, l1) = (mean - rad, mean + rad); // l0 <= l1
    if l0 >= 0.0 {
        return h;
    }
    let fix = |l: f64| {
        if l >= 0.0 {
            l
        } else if method == PsdProjection::Abs {
            -l
        } else {
            0.0
        }
    };
    // Unit eigenvector of l1: (b, l1 - a) or (l1 - d, b), whichever is better conditioned.
    let (e0, e1) = if (l1 - a).abs() >= (l1 - d).abs() {
        (b, l1 - a)
    } else {
        (l1 - d, b)
    };
    let len = (e0 * e0 + e1 * e1).sqrt();
    let (c, s) = if len > 0.0 {
        (e0 / len, e1 / len)
    } else {
        (1.0, 0.0)
    };
    // V = [q1 q0] with q1 = (c, s) for l1 and q0 = (-s, c) for l0.
    let (m1, m0) = (fix(l1), fix(l0));
    [
        [m1 * c * c + m0 * s * s, (m1 - m0) * c * s],
        [(m1 - m0) * c * s, m1 * s * s + m0 * c * c],
    ]
}
