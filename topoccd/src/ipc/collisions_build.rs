//! Building the normal collision set from a proximity report (ipctk's
//! `NormalCollisions::build` and its builder): each pair reduced to its closest features by
//! ipctk's classification, kept when the squared distance of its type is below
//! `(dhat + dmin)^2`, merged with the others of the same features by adding weights.

use std::collections::HashMap;

use super::collisions::{
    CollisionOptions, CollisionSetType, EeCollision, EvCollision, FvCollision, NormalCollisions,
    VvCollision,
};
use super::mesh::IpcMesh;
use super::types::{
    edge_edge_sq, edge_edge_type, mollifier_threshold, point_edge_sq, point_edge_type,
    point_triangle_sq, point_triangle_type,
};
use super::IpcError;
use crate::distance::{
    edge_edge_distance, point_edge_distance, point_point_distance, point_triangle_distance,
    EdgeEdgeType, PointEdgeType, PointTriangleType,
};
use crate::math::DVec3;
use crate::{Ccd, Configuration, ProximityOptions, ProximityReport};

impl CollisionOptions {
    /// Checks every option against its documented range.
    pub fn validate(&self) -> Result<(), IpcError> {
        if !(self.dhat.is_finite() && self.dhat > 0.0) {
            return Err(IpcError::Dhat(self.dhat));
        }
        if !(self.dmin.is_finite() && self.dmin >= 0.0) {
            return Err(IpcError::Dmin(self.dmin));
        }
        if self.enable_shape_derivatives {
            return Err(IpcError::ShapeDerivatives);
        }
        Ok(())
    }
}

mod improved;

/// An edge-edge collision's key: the lower edge id, the higher, and the type with the lower
/// edge as edge a and each edge in the mesh's orientation (`IpcMesh::edges`), so that two
/// collisions of the same features merge whatever order they name them in.
type EeKey = (u32, u32, EdgeEdgeType);

/// An edge-edge collision being merged: its edges' vertices and type as the first one added
/// named them, the weight so far and the mollifier threshold.
struct EeEntry {
    a: [u32; 2],
    b: [u32; 2],
    kind: EdgeEdgeType,
    weight: f64,
    eps_x: f64,
}

/// `ty` with edge a's endpoints exchanged: swap the edges, exchange b's, swap back.
fn flip_a(ty: EdgeEdgeType) -> EdgeEdgeType {
    flip_b(ty.swapped()).swapped()
}

/// `ty` with edge b's endpoints exchanged.
fn flip_b(ty: EdgeEdgeType) -> EdgeEdgeType {
    use EdgeEdgeType::*;
    match ty {
        Ea0Eb0 => Ea0Eb1,
        Ea0Eb1 => Ea0Eb0,
        Ea1Eb0 => Ea1Eb1,
        Ea1Eb1 => Ea1Eb0,
        EaEb0 => EaEb1,
        EaEb1 => EaEb0,
        other => other,
    }
}

/// The weights being merged, by kind and features.
#[derive(Default)]
pub(super) struct Builder {
    vv: HashMap<(u32, u32), f64>,
    ev: HashMap<(u32, u32), f64>,
    ee: HashMap<EeKey, EeEntry>,
    fv: Vec<FvCollision>,
}

impl Builder {
    fn add_vv(&mut self, a: u32, b: u32, w: f64) {
        *self.vv.entry((a.min(b), a.max(b))).or_insert(0.0) += w;
    }

    fn add_ev(&mut self, edge: u32, v: u32, w: f64) {
        *self.ev.entry((edge, v)).or_insert(0.0) += w;
    }

    /// Adds to the edge-edge collision of edges `ea` (vertices `a`) and `eb` (`b`) of type
    /// `ty` (of `a` and `b` in this order); an existing one of the same features takes the
    /// weight, whichever order and orientation it names them in.
    #[allow(clippy::too_many_arguments)]
    fn add_ee(
        &mut self,
        mesh: &IpcMesh,
        ea: u32,
        eb: u32,
        a: [u32; 2],
        b: [u32; 2],
        ty: EdgeEdgeType,
        eps_x: f64,
        w: f64,
    ) {
        let mut key = ty;
        if a != mesh.edges[ea as usize] {
            key = flip_a(key);
        }
        if b != mesh.edges[eb as usize] {
            key = flip_b(key);
        }
        if ea > eb {
            key = key.swapped();
        }
        self.ee
            .entry((ea.min(eb), ea.max(eb), key))
            .or_insert(EeEntry {
                a,
                b,
                kind: ty,
                weight: 0.0,
                eps_x,
            })
            .weight += w;
    }

    /// Adds a vertex-against-edge contribution reduced by its closest feature: a
    /// vertex-vertex one at an endpoint, else an edge-vertex one (ipctk's builder does the
    /// same for each point-edge type).
    fn add_point_edge(&mut self, edge: u32, ends: [u32; 2], v: u32, ty: PointEdgeType, w: f64) {
        match ty {
            PointEdgeType::E0 => self.add_vv(v, ends[0], w),
            PointEdgeType::E1 => self.add_vv(v, ends[1], w),
            PointEdgeType::Interior => self.add_ev(edge, v, w),
        }
    }
}

impl NormalCollisions {
    /// Builds the collision set from a proximity report of `config` (made with
    /// `dhat >= options.dhat` and `dmin >= options.dmin`, complete: not truncated), with the
    /// edge-edge mollifier thresholds and the area weights from `rest_positions` (one row
    /// per vertex; ipctk's `CollisionMesh::rest_positions`).
    ///
    /// The report's pairs are already filtered by the configuration's groups and
    /// `can_collide`.
    ///
    /// ```
    /// use topoccd::ipc::{CollisionOptions, NormalCollisions};
    /// use topoccd::{proximity, Configuration, ProximityOptions};
    /// // Two crossing free edges 1e-4 apart.
    /// let x = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, -1.0, 1e-4], [0.0, 1.0, 1e-4]];
    /// let config = Configuration::new(&x, &[] as &[[u32; 3]], &[[0, 1], [2, 3]])?;
    /// let report = proximity(&config, &ProximityOptions { dhat: 1e-3, ..Default::default() })?;
    /// let options = CollisionOptions { dhat: 1e-3, ..Default::default() };
    /// let c = NormalCollisions::from_proximity(&config, &report, &x, &options)?;
    /// assert_eq!(c.ee.len(), 1);
    /// assert_eq!((c.ee[0].a, c.ee[0].b), ([0, 1], [2, 3]));
    /// assert!((c.ee[0].eps_x - 1e-3 * 4.0 * 4.0).abs() < 1e-15);
    /// # Ok::<(), topoccd::ipc::IpcError>(())
    /// ```
    pub fn from_proximity(
        config: &Configuration<'_>,
        report: &ProximityReport,
        rest_positions: &[[f64; 3]],
        options: &CollisionOptions,
    ) -> Result<Self, IpcError> {
        options.validate()?;
        if let Some(r) = report.truncated {
            return Err(IpcError::Truncated(r));
        }
        let n = config.vertex_count();
        if rest_positions.len() != n {
            return Err(IpcError::RestPositions {
                got: rest_positions.len(),
                vertices: n,
            });
        }
        if let Some(i) = rest_positions
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(IpcError::RestNotFinite(i));
        }
        check_report(report, n, config.triangles().len())?;
        let rest: Vec<DVec3> = rest_positions.iter().map(|&p| DVec3::from(p)).collect();
        let x = config.pos();
        let triangles = config.triangles();
        let aw = options.use_area_weighting;
        let mesh = IpcMesh::new(n, triangles, config.edges(), &rest, aw);
        let r = options.dhat + options.dmin;
        let active = |d2: f64| d2 < r * r;
        let va = |v: u32| mesh.vertex_area[v as usize];
        let mut b = Builder::default();

        // Free points.
        for p in &report.vv {
            let d2 = (x[p.a as usize] - x[p.b as usize]).length_squared();
            if active(d2) {
                let w = if aw { 0.5 * (va(p.a) + va(p.b)) } else { 1.0 };
                b.add_vv(p.a, p.b, w);
            }
        }
        // Free point against free edge.
        for p in &report.ve {
            let [e0, e1] = p.edge;
            let (pv, p0, p1) = (x[p.vertex as usize], x[e0 as usize], x[e1 as usize]);
            let ty = point_edge_type(pv, p0, p1);
            if !active(point_edge_sq(pv, p0, p1, ty)) {
                continue;
            }
            let w = if aw { 0.5 * va(p.vertex) } else { 1.0 };
            b.add_point_edge(mesh.edge(e0, e1), [e0, e1], p.vertex, ty, w);
        }
        // Edge against edge.
        for p in &report.ee {
            let ([a0, a1], [b0, b1]) = (p.a, p.b);
            let [pa0, pa1, pb0, pb1] = [a0, a1, b0, b1].map(|v| x[v as usize]);
            let ty = edge_edge_type(pa0, pa1, pb0, pb1);
            if !active(edge_edge_sq(pa0, pa1, pb0, pb1, ty)) {
                continue;
            }
            let [ra0, ra1, rb0, rb1] = [a0, a1, b0, b1].map(|v| rest[v as usize]);
            let eps_x = mollifier_threshold(ra0, ra1, rb0, rb1);
            let cross = (pa1 - pa0).cross(pb1 - pb0).length_squared();
            let (ea, eb) = (mesh.edge(a0, a1), mesh.edge(b0, b1));
            let w = if aw {
                0.25 * (mesh.edge_area[ea as usize] + mesh.edge_area[eb as usize])
            } else {
                1.0
            };
            use EdgeEdgeType::*;
            if cross < eps_x {
                b.add_ee(&mesh, ea, eb, p.a, p.b, ty, eps_x, w);
                continue;
            }
            match ty {
                Ea0Eb0 => b.add_vv(a0, b0, w),
                Ea0Eb1 => b.add_vv(a0, b1, w),
                Ea1Eb0 => b.add_vv(a1, b0, w),
                Ea1Eb1 => b.add_vv(a1, b1, w),
                EaEb0 => b.add_ev(ea, b0, w),
                EaEb1 => b.add_ev(ea, b1, w),
                Ea0Eb => b.add_ev(eb, a0, w),
                Ea1Eb => b.add_ev(eb, a1, w),
                EaEb => b.add_ee(&mesh, ea, eb, p.a, p.b, ty, eps_x, w),
            }
        }
        // Vertex against face.
        for p in &report.vf {
            let t = triangles[p.face as usize];
            let pv = x[p.vertex as usize];
            let [p0, p1, p2] = t.map(|v| x[v as usize]);
            let ty = point_triangle_type(pv, p0, p1, p2);
            if !active(point_triangle_sq(pv, p0, p1, p2, ty)) {
                continue;
            }
            let w = if aw { 0.25 * va(p.vertex) } else { 1.0 };
            let fe = mesh.face_edges[p.face as usize];
            use PointTriangleType::*;
            match ty {
                T0 => b.add_vv(p.vertex, t[0], w),
                T1 => b.add_vv(p.vertex, t[1], w),
                T2 => b.add_vv(p.vertex, t[2], w),
                E0 => b.add_ev(fe[0], p.vertex, w),
                E1 => b.add_ev(fe[1], p.vertex, w),
                E2 => b.add_ev(fe[2], p.vertex, w),
                Interior => b.fv.push(FvCollision {
                    face: p.face,
                    triangle: t,
                    vertex: p.vertex,
                    weight: w,
                }),
            }
        }
        if options.collision_set_type == CollisionSetType::ImprovedMaxApprox {
            improved::add_corrections(&mut b, &mesh, x, &rest, triangles, report, options);
        }
        Ok(finish(b, mesh, options))
    }

    /// Runs [`Ccd::proximity`] on `config` with `options.dhat` and `options.dmin`, then
    /// [`from_proximity`](Self::from_proximity): ipctk's `NormalCollisions::build(mesh, x,
    /// dhat, dmin)`. Keep the `Ccd` across a solver's iterations: its hierarchy is refitted.
    pub fn build(
        ccd: &mut Ccd,
        config: &Configuration<'_>,
        rest_positions: &[[f64; 3]],
        options: &CollisionOptions,
    ) -> Result<Self, IpcError> {
        options.validate()?;
        let popts = ProximityOptions {
            dhat: options.dhat,
            dmin: options.dmin,
            ..ProximityOptions::default()
        };
        let report = ccd.proximity(config, &popts)?;
        Self::from_proximity(config, &report, rest_positions, options)
    }

    /// ipctk's `compute_minimum_distance`: the smallest **squared** distance over the
    /// collisions' primitive pairs at `x` (`+inf` for an empty set), the value ipctk's
    /// [`update_barrier_stiffness`](super::update_barrier_stiffness) expects. See
    /// [`minimum_distance`](Self::minimum_distance) for the distance itself.
    pub fn compute_minimum_distance(&self, x: &[[f64; 3]]) -> f64 {
        let d = self.minimum_distance(x);
        d * d
    }

    /// The smallest distance (not squared) over the collisions' primitive pairs at `x`
    /// (`+inf` for an empty set), with the robust kernels of [`crate::distance`]: never
    /// larger than the exact minimum by more than
    /// [`rounding_bound`](crate::distance::rounding_bound) of the closest pair. Each
    /// collision is measured between its whole primitives (a vertex-edge collision from
    /// the vertex to the segment), which for a set built at `x` is the distance of its type.
    pub fn minimum_distance(&self, x: &[[f64; 3]]) -> f64 {
        let p = |v: u32| DVec3::from(x[v as usize]);
        let mut m = f64::INFINITY;
        for c in &self.vv {
            m = m.min(point_point_distance(p(c.vertices[0]), p(c.vertices[1])));
        }
        for c in &self.ev {
            m = m.min(point_edge_distance(p(c.vertex), p(c.edge[0]), p(c.edge[1])).0);
        }
        for c in &self.ee {
            m = m.min(edge_edge_distance(p(c.a[0]), p(c.a[1]), p(c.b[0]), p(c.b[1])).0);
        }
        for c in &self.fv {
            let [t0, t1, t2] = c.triangle.map(p);
            m = m.min(point_triangle_distance(p(c.vertex), t0, t1, t2).0);
        }
        m.sqrt()
    }
}

/// Checks the report's indices against the configuration.
fn check_report(report: &ProximityReport, n: usize, faces: usize) -> Result<(), IpcError> {
    let v = |i: u32| {
        if (i as usize) < n {
            Ok(())
        } else {
            Err(IpcError::ReportIndex {
                what: "vertex",
                index: i,
            })
        }
    };
    for p in &report.vf {
        v(p.vertex)?;
        if p.face as usize >= faces {
            return Err(IpcError::ReportIndex {
                what: "face",
                index: p.face,
            });
        }
    }
    for p in &report.ee {
        for i in p.a.into_iter().chain(p.b) {
            v(i)?;
        }
    }
    for p in &report.ve {
        v(p.vertex)?;
        v(p.edge[0])?;
        v(p.edge[1])?;
    }
    for p in &report.vv {
        v(p.a)?;
        v(p.b)?;
    }
    Ok(())
}

/// The merged weights as sorted collision lists (zero weights dropped, as ipctk does).
fn finish(b: Builder, mesh: IpcMesh, options: &CollisionOptions) -> NormalCollisions {
    let mut vv: Vec<VvCollision> =
        b.vv.into_iter()
            .filter(|&(_, w)| w != 0.0)
            .map(|((a, c), weight)| VvCollision {
                vertices: [a, c],
                weight,
            })
            .collect();
    vv.sort_unstable_by_key(|c| c.vertices);
    let mut ev: Vec<EvCollision> =
        b.ev.into_iter()
            .filter(|&(_, w)| w != 0.0)
            .map(|((e, v), weight)| EvCollision {
                edge_id: e,
                edge: mesh.edges[e as usize],
                vertex: v,
                weight,
            })
            .collect();
    ev.sort_unstable_by_key(|c| {
        let [a, b] = c.edge;
        (a.min(b), a.max(b), c.vertex)
    });
    let mut ee: Vec<EeCollision> =
        b.ee.into_iter()
            .filter(|(_, e)| e.weight != 0.0)
            .map(|(_, e)| EeCollision {
                edge_ids: [mesh.edge(e.a[0], e.a[1]), mesh.edge(e.b[0], e.b[1])],
                a: e.a,
                b: e.b,
                eps_x: e.eps_x,
                kind: e.kind,
                weight: e.weight,
            })
            .collect();
    ee.sort_unstable_by_key(|c| (c.a, c.b, c.kind));
    let mut fv = b.fv;
    fv.sort_unstable_by_key(|c| (c.triangle, c.vertex));
    NormalCollisions {
        vv,
        ev,
        ee,
        fv,
        edges: mesh.edges,
        dmin: options.dmin,
        options: *options,
    }
}
