//! The tangential collision set: one tangential collision per normal collision, with the
//! quantities that friction lags from the positions at the start of the solve.

use super::closest_point::{
    edge_edge_closest_point, point_edge_closest_point, point_triangle_closest_point,
};
use super::relative_velocity::{
    edge_edge_relative_velocity_jacobian, point_edge_relative_velocity_jacobian,
    point_point_relative_velocity_jacobian, point_triangle_relative_velocity_jacobian,
};
use super::tangent_basis::{
    edge_edge_tangent_basis, point_edge_tangent_basis, point_point_tangent_basis,
    point_triangle_tangent_basis,
};
use super::FrictionError;
use crate::distance::{
    edge_edge_distance, point_edge_distance, point_point_distance, point_triangle_distance,
};
use crate::ipc::{BarrierPotential, NormalCollisions};
use crate::math::DVec3;

/// The kind of a contact stencil, named as the IPC toolkit's collision lists.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StencilKind {
    /// Vertex-vertex: stencil `[v0, v1]`.
    VertexVertex,
    /// Edge-vertex: stencil `[v, e0, e1]`.
    EdgeVertex,
    /// Edge-edge: stencil `[ea0, ea1, eb0, eb1]`.
    EdgeEdge,
    /// Face-vertex: stencil `[v, f0, f1, f2]`.
    FaceVertex,
}

impl StencilKind {
    /// Number of vertices of the stencil (2, 3 or 4).
    #[inline]
    pub fn num_vertices(self) -> usize {
        match self {
            StencilKind::VertexVertex => 2,
            StencilKind::EdgeVertex => 3,
            StencilKind::EdgeEdge | StencilKind::FaceVertex => 4,
        }
    }
}

/// One normal collision as friction needs it: its stencil's vertices (in the order of
/// [`StencilKind`]), its weight (multiplicity or area weight), its minimum distance `dmin`
/// and, for edge-edge collisions, the mollifier threshold `eps_x` on the squared norm of
/// the edges' cross product (at rest).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalStencil {
    /// The stencil's kind.
    pub kind: StencilKind,
    /// The ipctk primitive ids: `(v0, v1)`, `(edge, vertex)`, `(edge0, edge1)` or
    /// `(face, vertex)`.
    pub primitives: [usize; 2],
    /// The stencil's vertices; the unused tail is 0.
    pub vertices: [usize; 4],
    /// The collision's weight.
    pub weight: f64,
    /// The collision's minimum distance.
    pub dmin: f64,
    /// Edge-edge only: the parallel-edge mollifier's threshold (0 for the other kinds).
    pub eps_x: f64,
}

/// A tangential collision: a normal collision's stencil with its lagged closest point,
/// tangent basis and normal force (the attributes of ipctk's `TangentialCollision`).
#[derive(Clone, Debug, PartialEq)]
pub struct TangentialCollision {
    /// The stencil's kind.
    pub kind: StencilKind,
    /// The ipctk primitive ids (see [`NormalStencil::primitives`]).
    pub primitives: [usize; 2],
    /// The stencil's vertices; only the first [`num_vertices`](Self::num_vertices) count.
    pub vertices: [usize; 4],
    /// The closest-point coordinates: empty for vertex-vertex, `[alpha]` for edge-vertex,
    /// `[a, b]` for edge-edge (along edge a and edge b), `[b1, b2]` for face-vertex.
    pub closest_point: [f64; 2],
    /// The tangent basis' two columns (ipctk's 3×2 `tangent_basis`).
    pub tangent_basis: [DVec3; 2],
    /// The normal force magnitude at the lagged positions (without the weight).
    pub normal_force_magnitude: f64,
    /// The normal collision's weight.
    pub weight: f64,
    /// Static friction coefficient.
    pub mu_s: f64,
    /// Kinetic friction coefficient.
    pub mu_k: f64,
    /// The relative-velocity coefficients `gamma` (see
    /// [`relative_velocity`](super::relative_velocity)); the unused tail is 0.
    pub(crate) gamma: [f64; 4],
}

impl TangentialCollision {
    /// Number of vertices of the stencil.
    #[inline]
    pub fn num_vertices(&self) -> usize {
        self.kind.num_vertices()
    }

    /// The stencil's vertex ids.
    #[inline]
    pub fn vertex_ids(&self) -> &[usize] {
        &self.vertices[..self.num_vertices()]
    }

    /// The closest-point coordinates that apply (0, 1 or 2 of them).
    #[inline]
    pub fn closest_point(&self) -> &[f64] {
        let n = match self.kind {
            StencilKind::VertexVertex => 0,
            StencilKind::EdgeVertex => 1,
            _ => 2,
        };
        &self.closest_point[..n]
    }

    /// The relative velocity's coefficients, one per stencil vertex: its Jacobian is
    /// `[gamma_0 I, gamma_1 I, ...]`.
    #[inline]
    pub fn relative_velocity_jacobian(&self) -> &[f64] {
        &self.gamma[..self.num_vertices()]
    }

    /// The relative velocity of the stencil for the given vertex velocities.
    #[inline]
    pub fn relative_velocity(&self, velocities: &[DVec3]) -> DVec3 {
        self.vertex_ids()
            .iter()
            .zip(&self.gamma)
            .fold(DVec3::ZERO, |s, (&v, g)| s + velocities[v] * *g)
    }
}

/// The tangential collisions, in ipctk's four lists.
///
/// Built from the normal collisions at the lagged positions; it holds nothing of the mesh
/// beyond the stencils' vertex ids, so after a topology change it is simply built again from
/// the new normal collision set.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TangentialCollisions {
    /// Vertex-vertex collisions.
    pub vv_collisions: Vec<TangentialCollision>,
    /// Edge-vertex collisions.
    pub ev_collisions: Vec<TangentialCollision>,
    /// Edge-edge collisions (those of nearly parallel edges are left out, as ipctk does).
    pub ee_collisions: Vec<TangentialCollision>,
    /// Face-vertex collisions.
    pub fv_collisions: Vec<TangentialCollision>,
}

/// Friction coefficients: one pair for the whole mesh, or one pair per vertex, blended per
/// collision at its closest points (ipctk's default blend, the average of the two sides).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FrictionCoefficients<'a> {
    /// The same static and kinetic coefficients everywhere (`mu_s`, `mu_k`).
    Global {
        /// Static coefficient, `>= 0`.
        mu_s: f64,
        /// Kinetic coefficient, `>= 0`.
        mu_k: f64,
    },
    /// Per-vertex static and kinetic coefficients (one of each per vertex).
    PerVertex {
        /// Static coefficients.
        mu_s: &'a [f64],
        /// Kinetic coefficients.
        mu_k: &'a [f64],
    },
}

impl FrictionCoefficients<'_> {
    /// One coefficient `mu` for static and kinetic friction.
    pub fn uniform(mu: f64) -> Self {
        FrictionCoefficients::Global { mu_s: mu, mu_k: mu }
    }
}

impl TangentialCollisions {
    /// Builds the tangential collisions from normal-collision stencils at the lagged
    /// `positions`: per stencil, the closest point, the tangent basis, the normal force
    /// `normal_force(d2, dmin)` at the squared distance `d2`, and the blended coefficients.
    /// Edge-edge stencils whose edges' squared cross norm is below their `eps_x` are left
    /// out, as ipctk does.
    ///
    /// [`TangentialCollisions::build`] calls this with the normal collision set and the
    /// barrier potential; use this one with another normal potential.
    ///
    /// # Errors
    /// A stencil vertex out of range, coefficients of the wrong length or negative, or a
    /// degenerate stencil (no tangent plane: coincident points, a zero-length edge, a
    /// zero-area triangle).
    pub fn build_from_stencils(
        positions: &[[f64; 3]],
        stencils: impl IntoIterator<Item = NormalStencil>,
        normal_force: impl Fn(f64, f64) -> f64,
        mu: FrictionCoefficients<'_>,
    ) -> Result<Self, FrictionError> {
        let x: &[DVec3] = bytemuck::cast_slice(positions);
        check_coefficients(mu, x.len())?;
        let mut out = TangentialCollisions::default();
        for (index, s) in stencils.into_iter().enumerate() {
            let n = s.kind.num_vertices();
            if let Some(&v) = s.vertices[..n].iter().find(|&&v| v >= x.len()) {
                return Err(FrictionError::VertexOutOfRange {
                    vertex: v,
                    vertices: x.len(),
                });
            }
            let p = |i: usize| x[s.vertices[i]];
            let (d2, closest, basis, gamma) = match s.kind {
                StencilKind::VertexVertex => {
                    let g = point_point_relative_velocity_jacobian();
                    (
                        point_point_distance(p(0), p(1)),
                        [0.0; 2],
                        point_point_tangent_basis(p(0), p(1)),
                        [g[0], g[1], 0.0, 0.0],
                    )
                }
                StencilKind::EdgeVertex => {
                    let a = point_edge_closest_point(p(0), p(1), p(2));
                    let g = point_edge_relative_velocity_jacobian(a);
                    (
                        point_edge_distance(p(0), p(1), p(2)).0,
                        [a, 0.0],
                        point_edge_tangent_basis(p(0), p(1), p(2)),
                        [g[0], g[1], g[2], 0.0],
                    )
                }
                StencilKind::EdgeEdge => {
                    let cross = (p(1) - p(0)).cross(p(3) - p(2)).length_squared();
                    if cross < s.eps_x {
                        continue; // nearly parallel: no friction, as ipctk
                    }
                    let ab = edge_edge_closest_point(p(0), p(1), p(2), p(3));
                    (
                        edge_edge_distance(p(0), p(1), p(2), p(3)).0,
                        ab,
                        edge_edge_tangent_basis(p(0), p(1), p(2), p(3)),
                        edge_edge_relative_velocity_jacobian(ab),
                    )
                }
                StencilKind::FaceVertex => {
                    let b = point_triangle_closest_point(p(0), p(1), p(2), p(3));
                    (
                        point_triangle_distance(p(0), p(1), p(2), p(3)).0,
                        b,
                        point_triangle_tangent_basis(p(0), p(1), p(2), p(3)),
                        point_triangle_relative_velocity_jacobian(b),
                    )
                }
            };
            if !(basis[0].is_finite()
                && basis[1].is_finite()
                && closest.iter().all(|c| c.is_finite()))
            {
                return Err(FrictionError::DegenerateStencil {
                    kind: s.kind,
                    index,
                });
            }
            let (mu_s, mu_k) = blend(mu, s.kind, &s.vertices, closest);
            let c = TangentialCollision {
                kind: s.kind,
                primitives: s.primitives,
                vertices: s.vertices,
                closest_point: closest,
                tangent_basis: basis,
                normal_force_magnitude: normal_force(d2, s.dmin),
                weight: s.weight,
                mu_s,
                mu_k,
                gamma,
            };
            match s.kind {
                StencilKind::VertexVertex => out.vv_collisions.push(c),
                StencilKind::EdgeVertex => out.ev_collisions.push(c),
                StencilKind::EdgeEdge => out.ee_collisions.push(c),
                StencilKind::FaceVertex => out.fv_collisions.push(c),
            }
        }
        Ok(out)
    }

    /// Builds the tangential collisions from the normal collision set at the lagged
    /// `positions`, with the normal forces of the barrier potential (ipctk's
    /// `TangentialCollisions.build(mesh, x, collisions, B, mu_s, mu_k)`).
    ///
    /// The normal force of a collision is the barrier's force at the collision's squared
    /// distance `d2`: `N = -2 sqrt(d2) B'(d2)`, with the set's `dmin` (ipctk's
    /// `force_magnitude`), without the weight, which the potential applies.
    ///
    /// ```
    /// use topoccd::ipc::friction::{FrictionCoefficients, TangentialCollisions};
    /// use topoccd::ipc::{BarrierPotential, CollisionOptions, NormalCollisions};
    /// use topoccd::{Ccd, Configuration};
    /// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.2, 5e-4]];
    /// let config = Configuration::new(&x, &[[0u32, 1, 2]], &[])?;
    /// let options = CollisionOptions { dhat: 1e-3, ..Default::default() };
    /// let normal = NormalCollisions::build(&mut Ccd::new(), &config, &x, &options)?;
    /// let b = BarrierPotential::new(1e-3, 10.0);
    /// let t = TangentialCollisions::build(&x, &normal, &b, FrictionCoefficients::uniform(0.5))?;
    /// assert_eq!(t.fv_collisions.len(), 1);
    /// assert_eq!(t.fv_collisions[0].closest_point, [0.2, 0.2]);
    /// assert!(t.fv_collisions[0].normal_force_magnitude > 0.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// As [`build_from_stencils`](Self::build_from_stencils).
    pub fn build(
        positions: &[[f64; 3]],
        collisions: &NormalCollisions,
        barrier: &BarrierPotential,
        mu: FrictionCoefficients<'_>,
    ) -> Result<Self, FrictionError> {
        let dmin = collisions.dmin;
        let stencil = |kind, primitives: [u32; 2], v: [u32; 4], weight, eps_x| NormalStencil {
            kind,
            primitives: primitives.map(|p| p as usize),
            vertices: v.map(|p| p as usize),
            weight,
            dmin,
            eps_x,
        };
        let vv = collisions.vv.iter().map(|c| {
            let [a, b] = c.vertices;
            stencil(
                StencilKind::VertexVertex,
                [a, b],
                [a, b, 0, 0],
                c.weight,
                0.0,
            )
        });
        let ev = collisions.ev.iter().map(|c| {
            let v = [c.vertex, c.edge[0], c.edge[1], 0];
            stencil(
                StencilKind::EdgeVertex,
                [c.edge_id, c.vertex],
                v,
                c.weight,
                0.0,
            )
        });
        let ee = collisions.ee.iter().map(|c| {
            let v = [c.a[0], c.a[1], c.b[0], c.b[1]];
            stencil(StencilKind::EdgeEdge, c.edge_ids, v, c.weight, c.eps_x)
        });
        let fv = collisions.fv.iter().map(|c| {
            let [t0, t1, t2] = c.triangle;
            let v = [c.vertex, t0, t1, t2];
            stencil(
                StencilKind::FaceVertex,
                [c.face, c.vertex],
                v,
                c.weight,
                0.0,
            )
        });
        let force = |d2: f64, dmin: f64| -2.0 * d2.sqrt() * barrier.first_derivative(d2, dmin);
        Self::build_from_stencils(positions, vv.chain(ev).chain(ee).chain(fv), force, mu)
    }

    /// Number of tangential collisions.
    #[inline]
    pub fn len(&self) -> usize {
        self.vv_collisions.len()
            + self.ev_collisions.len()
            + self.ee_collisions.len()
            + self.fv_collisions.len()
    }

    /// Whether there are none.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// All collisions, in ipctk's order (vv, ev, ee, fv).
    pub fn iter(&self) -> impl Iterator<Item = &TangentialCollision> {
        self.vv_collisions
            .iter()
            .chain(&self.ev_collisions)
            .chain(&self.ee_collisions)
            .chain(&self.fv_collisions)
    }

    /// The collision at index `i` in ipctk's order (vv, ev, ee, fv), if any.
    pub fn get(&self, i: usize) -> Option<&TangentialCollision> {
        let mut i = i;
        for list in [
            &self.vv_collisions,
            &self.ev_collisions,
            &self.ee_collisions,
            &self.fv_collisions,
        ] {
            if i < list.len() {
                return Some(&list[i]);
            }
            i -= list.len();
        }
        None
    }
}

fn check_coefficients(mu: FrictionCoefficients<'_>, n: usize) -> Result<(), FrictionError> {
    let bad = |m: f64| !(m >= 0.0 && m.is_finite());
    match mu {
        FrictionCoefficients::Global { mu_s, mu_k } => {
            if bad(mu_s) || bad(mu_k) {
                return Err(FrictionError::BadCoefficient {
                    value: if bad(mu_s) { mu_s } else { mu_k },
                });
            }
        }
        FrictionCoefficients::PerVertex { mu_s, mu_k } => {
            for len in [mu_s.len(), mu_k.len()] {
                if len != n {
                    return Err(FrictionError::CoefficientsLength { len, vertices: n });
                }
            }
            if let Some(&m) = mu_s.iter().chain(mu_k).find(|&&m| bad(m)) {
                return Err(FrictionError::BadCoefficient { value: m });
            }
        }
    }
    Ok(())
}

/// The collision's coefficients: per-vertex ones interpolated on each side at the closest
/// point, then averaged between the two sides (ipctk's `default_blend_mu`).
fn blend(
    mu: FrictionCoefficients<'_>,
    kind: StencilKind,
    v: &[usize; 4],
    c: [f64; 2],
) -> (f64, f64) {
    let (ms, mk) = match mu {
        FrictionCoefficients::Global { mu_s, mu_k } => return (mu_s, mu_k),
        FrictionCoefficients::PerVertex { mu_s, mu_k } => (mu_s, mu_k),
    };
    let side = |m: &[f64]| -> f64 {
        let avg = |a: f64, b: f64| (a + b) / 2.0;
        match kind {
            StencilKind::VertexVertex => avg(m[v[0]], m[v[1]]),
            StencilKind::EdgeVertex => avg((m[v[2]] - m[v[1]]) * c[0] + m[v[1]], m[v[0]]),
            StencilKind::EdgeEdge => avg(
                (m[v[1]] - m[v[0]]) * c[0] + m[v[0]],
                (m[v[3]] - m[v[2]]) * c[1] + m[v[2]],
            ),
            StencilKind::FaceVertex => avg(
                m[v[1]] + c[0] * (m[v[2]] - m[v[1]]) + c[1] * (m[v[3]] - m[v[1]]),
                m[v[0]],
            ),
        }
    };
    (side(ms), side(mk))
}
