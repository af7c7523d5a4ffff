//! The disk certificate: a patch of triangles that can be shown free of self-contact over the
//! whole step. The theorem and its proof are in the [module documentation](super); this file
//! checks its hypotheses, incrementally, with reusable scratch memory.
//!
//! A [`DiskBuilder`] is started with a direction `V` and a moving centre `c(t)`, then given the
//! patch's triangles in one or more batches ([`DiskBuilder::extend`], one batch per ring). After
//! each batch, [`DiskBuilder::check_boundary`] certifies the boundary. Checked:
//!
//! 1. every triangle has `n(t)·V > 0` on `[0, 1]` (in [`DiskBuilder::extend`]);
//! 2. every edge lies in at most two triangles of the patch, and in opposite directions when in
//!    two (consistent orientation; in [`DiskBuilder::extend`]);
//! 3. `V - E + F = 1` (Euler characteristic of a disk);
//! 4. every boundary edge `a -> b` (directed as in its triangle) has
//!    `g(t) = V·((a - c) x (b - c)) > 0` on `[0, 1]`;
//! 5. the boundary's projected angles around `c(0)` sum to `2 pi` (winding number one), with a
//!    rigorous bound on the rounding of each angle.
//!
//! A batch that breaks 1 or 2 leaves the builder unusable until the next
//! [`DiskBuilder::begin`]; so does a failed boundary check.
//!
//! Partial rings grow a certified patch one triangle at a time instead
//! ([`DiskBuilder::try_add`]): each triangle is checked against hypotheses 1 to 4 locally and
//! refused without changing the patch, so one bad triangle no longer stops a whole ring.

use crate::narrow::bernstein::{normal_along, star_around, Verdict};
use crate::math::{max_abs, DVec3, UNIT_ROUNDOFF};
use crate::mesh::{Step, Topology};
use rayon::prelude::*;

/// Which hypothesis of the disk theorem a patch failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiskFailure {
    /// A triangle's projected normal `n(t)·V` is not certified positive on `[0, 1]`.
    Normal,
    /// An edge lies in three or more triangles of the patch, or in two with the same direction.
    NonManifold,
    /// The Euler characteristic is not one (a ring closed into an annulus, a pinched vertex...).
    Topology,
    /// A boundary edge's star test `g(t)` is not certified positive on `[0, 1]`.
    Star,
    /// The boundary does not wind exactly once around the centre at `t = 0`.
    Winding,
}

/// Error bound of the computed coordinates `(x, y)` of a projected angle, in units of
/// `u |A|_inf |B|_inf` (see [`DiskBuilder::check_boundary`]; analysis about 60).
const ANGLE_ERROR: f64 = 128.0;

/// Incremental checker of the disk certificate, with scratch memory reused across patches and
/// steps. Per-edge and per-vertex state is tagged with a generation stamp, so starting a new
/// patch costs nothing.
#[derive(Clone, Debug, Default)]
pub struct DiskBuilder {
    stamp: u32,
    edge_stamp: Vec<u32>,
    /// Per edge: bits 0-1 the number of patch triangles (0..=2), bit 2 set when the first
    /// triangle traverses the edge from its smaller to its larger vertex index.
    edge_state: Vec<u8>,
    vertex_stamp: Vec<u32>,
    /// Current boundary edges, those with exactly one patch triangle.
    boundary: Vec<u32>,
    /// `boundary[fresh_from..]` became boundary edges in the last batch.
    fresh_from: usize,
    /// Edges whose count changed in the current batch.
    touched: Vec<u32>,
    /// Vertices first met in the last batch.
    fresh_vertices: Vec<u32>,
    scratch: Vec<u32>,
    faces: usize,
    edges: usize,
    vertices: usize,
    /// Sums of the patch's vertex positions at t=0 and t=1.
    vertex_sum: [DVec3; 2],
    direction: DVec3,
    centre: [DVec3; 2],
    subdivisions: u32,
    /// Per triangle: the patch stamp under which hypothesis 1 was computed for it by
    /// [`DiskBuilder::try_add`] (the direction is fixed for a
    /// patch, so the test need not be repeated when a refused triangle is offered again)...
    normal_gen: Vec<u32>,
    /// ... and whether it holds.
    normal_ok: Vec<bool>,
    /// Generation of the pair (patch, centre): bumped whenever either changes.
    centre_gen: u32,
    /// Per edge: the generation of `star_bits`.
    star_gen: Vec<u32>,
    /// Per edge: the star tests of [`DiskBuilder::try_add`] known under `star_gen`, for each
    /// direction (see [`STAR_KNOWN`], [`STAR_HOLDS`]): the test is a function of the directed
    /// edge, the direction and the centre alone, so its result is reused, never recomputed
    /// differently.
    star_bits: Vec<u8>,
    /// Whether [`DiskBuilder::check_boundary`] must stay on the calling thread (no rayon call).
    sequential: bool,
}

/// Boundaries of at least this many edges are checked in parallel
/// ([`DiskBuilder::check_boundary`]) unless the builder is [sequential](DiskBuilder::set_sequential).
pub const PARALLEL_TESTS: usize = 256;

/// In `star_bits`: the star test of the edge from its smaller to its larger vertex is known
/// (shift left by 2 for the other direction).
const STAR_KNOWN: u8 = 0b01;
/// In `star_bits`: that test holds.
const STAR_HOLDS: u8 = 0b10;

const COUNT_MASK: u8 = 0b11;
const FORWARD: u8 = 0b100;

impl DiskBuilder {
    /// With `true`, no method makes a rayon call: big boundaries are checked on the calling
    /// thread too (the same verdicts). For a caller that must not wait on the pool.
    pub fn set_sequential(&mut self, sequential: bool) {
        self.sequential = sequential;
    }

    /// Starts a new, empty patch for the topology `topo` (edges) of a step with `vertex_count`
    /// vertices. `direction` is `V` (any non-zero finite vector: the certificate holds for the
    /// vector as computed), `centre` the star centre `c` at t=0 and t=1, `subdivisions` the
    /// de Casteljau budget of each polynomial test.
    pub fn begin(
        &mut self,
        topo: &Topology,
        vertex_count: usize,
        direction: DVec3,
        centre: [DVec3; 2],
        subdivisions: u32,
    ) {
        if self.edge_stamp.len() != topo.edges.len() {
            self.edge_stamp.clear();
            self.edge_stamp.resize(topo.edges.len(), 0);
            self.edge_state.resize(topo.edges.len(), 0);
        }
        if self.star_gen.len() != topo.edges.len() {
            self.star_gen.clear();
            self.star_gen.resize(topo.edges.len(), 0);
            self.star_bits.resize(topo.edges.len(), 0);
        }
        if self.vertex_stamp.len() != vertex_count {
            self.vertex_stamp.clear();
            self.vertex_stamp.resize(vertex_count, 0);
        }
        if self.normal_gen.len() != topo.triangle_edges.len() {
            self.normal_gen.clear();
            self.normal_gen.resize(topo.triangle_edges.len(), 0);
            self.normal_ok.resize(topo.triangle_edges.len(), false);
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            // Wrapped around: old stamps could alias the new one. Clear everything once.
            self.edge_stamp.iter_mut().for_each(|s| *s = 0);
            self.vertex_stamp.iter_mut().for_each(|s| *s = 0);
            self.normal_gen.iter_mut().for_each(|s| *s = 0);
            self.stamp = 1;
        }
        self.next_centre_gen();
        self.boundary.clear();
        self.fresh_from = 0;
        self.fresh_vertices.clear();
        self.faces = 0;
        self.edges = 0;
        self.vertices = 0;
        self.vertex_sum = [DVec3::ZERO; 2];
        self.direction = direction;
        self.centre = centre;
        self.subdivisions = subdivisions;
    }

    /// A new generation for the star tests' memory (the patch or its centre changed).
    fn next_centre_gen(&mut self) {
        self.centre_gen = self.centre_gen.wrapping_add(1);
        if self.centre_gen == 0 {
            self.star_gen.iter_mut().for_each(|s| *s = 0);
            self.centre_gen = 1;
        }
    }

    /// Hypothesis 4 for the new boundary edge `e` directed `a -> b`, around the current
    /// centre: [`star_around`], computed at most once per directed edge and generation.
    fn star_holds(&mut self, e: usize, a: u32, b: u32, x0: &[DVec3], x1: &[DVec3]) -> bool {
        if self.star_gen[e] != self.centre_gen {
            self.star_gen[e] = self.centre_gen;
            self.star_bits[e] = 0;
        }
        let shift = if a < b { 0 } else { 2 };
        let bits = self.star_bits[e] >> shift;
        if bits & STAR_KNOWN != 0 {
            return bits & STAR_HOLDS != 0;
        }
        let holds = self.star_test(a, b, x0, x1);
        self.remember_star(e, a < b, holds);
        holds
    }

    /// The star test of the edge `a -> b` around the current centre, computed.
    fn star_test(&self, a: u32, b: u32, x0: &[DVec3], x1: &[DVec3]) -> bool {
        let (a, b) = (a as usize, b as usize);
        star_around(self.direction, [x0[a], x1[a]], [x0[b], x1[b]], self.centre)
            .positive(self.subdivisions)
            == Verdict::Holds
    }

    /// Stores the star test of edge `e` in the direction `forward`.
    fn remember_star(&mut self, e: usize, forward: bool, holds: bool) {
        if self.star_gen[e] != self.centre_gen {
            self.star_gen[e] = self.centre_gen;
            self.star_bits[e] = 0;
        }
        let shift = if forward { 0 } else { 2 };
        let found = STAR_KNOWN | if holds { STAR_HOLDS } else { 0 };
        self.star_bits[e] |= found << shift;
    }


    /// Vertices that the last [`DiskBuilder::extend`] added to the patch (equation 4's
    /// `V-bar` when the batch is a ring).
    pub fn fresh_vertices(&self) -> &[u32] {
        &self.fresh_vertices
    }

    /// Number of triangles in the patch.
    pub fn face_count(&self) -> usize {
        self.faces
    }

    /// Hypothesis 1 for one triangle: its normal faces the patch's direction over the whole
    /// step (certified).
    fn faces_direction(&self, tri: [u32; 3], x0: &[DVec3], x1: &[DVec3]) -> bool {
        let p0 = tri.map(|v| x0[v as usize]);
        let p1 = tri.map(|v| x1[v as usize]);
        normal_along(self.direction, &p0, &p1).positive(self.subdivisions) == Verdict::Holds
    }

    /// Counts vertex `v` into the patch, the first time it is seen.
    fn add_vertex(&mut self, v: u32, x0: &[DVec3], x1: &[DVec3]) {
        if self.vertex_stamp[v as usize] != self.stamp {
            self.vertex_stamp[v as usize] = self.stamp;
            self.vertices += 1;
            self.fresh_vertices.push(v);
            self.vertex_sum[0] += x0[v as usize];
            self.vertex_sum[1] += x1[v as usize];
        }
    }

    /// Adds a batch of triangles (ids into `step.triangles()`, each at most once per patch) and
    /// checks hypotheses 1 and 2 for them. The boundary is updated; call
    /// [`DiskBuilder::check_boundary`] before relying on the patch.
    pub fn extend(
        &mut self,
        step: &Step,
        topo: &Topology,
        batch: &[u32],
    ) -> Result<(), DiskFailure> {
        let (x0, x1, tris) = (step.pos0(), step.pos1(), step.triangles());
        self.touched.clear();
        self.fresh_vertices.clear();
        for &t in batch {
            let tri = tris[t as usize];
            if !self.faces_direction(tri, x0, x1) {
                return Err(DiskFailure::Normal);
            }
            self.faces += 1;
            for (k, &v) in tri.iter().enumerate() {
                self.add_vertex(v, x0, x1);
                let e = topo.triangle_edges[t as usize][k] as usize;
                let forward = if v < tri[(k + 1) % 3] { FORWARD } else { 0 };
                if self.edge_stamp[e] != self.stamp {
                    self.edge_stamp[e] = self.stamp;
                    self.edge_state[e] = 1 | forward;
                    self.edges += 1;
                    self.touched.push(e as u32);
                } else {
                    let state = self.edge_state[e];
                    if state & COUNT_MASK != 1 || state & FORWARD == forward {
                        return Err(DiskFailure::NonManifold);
                    }
                    self.edge_state[e] = 2 | (state & FORWARD);
                }
            }
        }
        // New boundary: old boundary edges still single, then edges first met in this batch
        // that stayed single (an edge met twice in the batch is interior).
        self.scratch.clear();
        for &e in &self.boundary {
            if self.edge_state[e as usize] & COUNT_MASK == 1 {
                self.scratch.push(e);
            }
        }
        self.fresh_from = self.scratch.len();
        for &e in &self.touched {
            if self.edge_state[e as usize] & COUNT_MASK == 1 {
                self.scratch.push(e);
            }
        }
        std::mem::swap(&mut self.boundary, &mut self.scratch);
        Ok(())
    }

    /// Starts a batch of single-triangle additions ([`DiskBuilder::try_add`]): clears
    /// [`DiskBuilder::fresh_vertices`].
    pub fn begin_batch(&mut self) {
        self.fresh_vertices.clear();
        self.fresh_from = self.boundary.len();
    }

    /// Adds triangle `t` to a non-empty patch if the patch stays certified, and leaves the
    /// patch unchanged otherwise (unlike [`DiskBuilder::extend`]).
    ///
    /// Requires (and keeps) the invariant that the patch satisfies hypotheses 1 to 5 with the
    /// current centre, every boundary edge having passed the star test with it (true after a
    /// successful [`DiskBuilder::check_boundary`] with `all_edges`, or after the seed with
    /// `all_edges` false, which then covers every edge). `t` is accepted when:
    ///
    /// - its edges already in the patch (`k` of them) are boundary edges traversed by `t` in the
    ///   opposite direction, and `k >= 1` (hypothesis 2 and connectedness);
    /// - it brings `2 - k` new vertices, so `V - E + F` is unchanged (hypothesis 3: an ear with
    ///   one new apex when `k = 1`, a notch filled when `k = 2`);
    /// - `n(t)·V > 0` on `[0, 1]` (hypothesis 1);
    /// - each of its other `3 - k` edges, the new boundary edges, passes the star test around
    ///   the current centre (hypothesis 4; the removed boundary edges had passed it before).
    ///
    /// Hypothesis 5 then holds exactly for the new patch: its boundary chain is the old one plus
    /// the boundary of `t` (a shared edge cancels against its reverse), and the projected angles
    /// of `t`'s three edges around `c` sum to zero because `c` lies strictly outside `t`'s
    /// projection (across a shared edge `e`, `g_t(e) = -g_S(e) < 0`, while `t`'s projection is
    /// counter-clockwise). So the winding number stays one. The grower still re-checks the
    /// final patch in full ([`DiskBuilder::check_boundary`] with `all_edges`), so that the
    /// certificate never rests on this argument.
    pub fn try_add(&mut self, step: &Step, topo: &Topology, t: u32) -> Result<(), DiskFailure> {
        let (x0, x1) = (step.pos0(), step.pos1());
        let tri = step.triangles()[t as usize];
        let edges = topo.triangle_edges[t as usize];
        let (mut shared, mut new_vertices) = (0u32, 0u32);
        let mut is_shared = [false; 3];
        for k in 0..3 {
            let v = tri[k];
            if self.vertex_stamp[v as usize] != self.stamp {
                new_vertices += 1;
            }
            let e = edges[k] as usize;
            if self.edge_stamp[e] == self.stamp {
                let forward = if v < tri[(k + 1) % 3] { FORWARD } else { 0 };
                let state = self.edge_state[e];
                if state & COUNT_MASK != 1 || state & FORWARD == forward {
                    return Err(DiskFailure::NonManifold);
                }
                shared += 1;
                is_shared[k] = true;
            }
        }
        if shared == 0 || shared + new_vertices != 2 {
            return Err(DiskFailure::Topology);
        }
        if self.normal_gen[t as usize] != self.stamp {
            self.normal_gen[t as usize] = self.stamp;
            self.normal_ok[t as usize] = self.faces_direction(tri, x0, x1);
        }
        if !self.normal_ok[t as usize] {
            return Err(DiskFailure::Normal);
        }
        for k in (0..3).filter(|&k| !is_shared[k]) {
            if !self.star_holds(edges[k] as usize, tri[k], tri[(k + 1) % 3], x0, x1) {
                return Err(DiskFailure::Star);
            }
        }
        // Commit.
        self.faces += 1;
        for k in 0..3 {
            let v = tri[k];
            self.add_vertex(v, x0, x1);
            let e = edges[k] as usize;
            if is_shared[k] {
                self.edge_state[e] = 2 | (self.edge_state[e] & FORWARD);
            } else {
                let forward = if v < tri[(k + 1) % 3] { FORWARD } else { 0 };
                self.edge_stamp[e] = self.stamp;
                self.edge_state[e] = 1 | forward;
                self.edges += 1;
                self.boundary.push(e as u32);
            }
        }
        Ok(())
    }

    /// Drops the edges that [`DiskBuilder::try_add`] made interior from the boundary list.
    pub fn end_batch(&mut self) {
        let state = &self.edge_state;
        self.boundary
            .retain(|&e| state[e as usize] & COUNT_MASK == 1);
        // Positions moved: count every edge as fresh (a conservative star re-check).
        self.fresh_from = 0;
    }

    /// Tries the star centre `centre`: keeps it if the whole boundary passes hypotheses 3 to 5
    /// around it, otherwise restores the previous centre (which still certifies the patch).
    pub fn try_recentre(
        &mut self,
        step: &Step,
        topo: &Topology,
        centre: [DVec3; 2],
    ) -> Result<(), DiskFailure> {
        self.end_batch();
        let old = self.centre;
        self.set_centre(centre);
        let checked = self.check_boundary(step, topo, true);
        if checked.is_err() {
            self.set_centre(old);
        }
        checked
    }

    /// Checks hypotheses 3 to 5. With `all_edges` false, only the boundary edges that appeared
    /// in the last batch get the star test (the others passed it with the same centre before);
    /// with `all_edges` true, all do (use after [`DiskBuilder::set_centre`]).
    pub fn check_boundary(
        &self,
        step: &Step,
        topo: &Topology,
        all_edges: bool,
    ) -> Result<(), DiskFailure> {
        if self.vertices + self.faces != self.edges + 1 {
            return Err(DiskFailure::Topology);
        }
        let from = if all_edges { 0 } else { self.fresh_from };
        let (x0, x1) = (step.pos0(), step.pos1());
        let v = self.direction;
        let star = |&e: &u32| {
            let [a, b] = self.directed(topo, e);
            let pa = [x0[a as usize], x1[a as usize]];
            let pb = [x0[b as usize], x1[b as usize]];
            star_around(v, pa, pb, self.centre).positive(self.subdivisions) == Verdict::Holds
        };
        let fresh = &self.boundary[from..];
        let stars = if !self.sequential && fresh.len() >= PARALLEL_TESTS {
            fresh.par_iter().with_min_len(64).all(star)
        } else {
            fresh.iter().all(star)
        };
        if !stars {
            return Err(DiskFailure::Star);
        }
        // Winding number at t = 0. Each projected angle theta_e is in (0, pi) (the star test
        // holds); its computed value is off by at most `bound` (below), so the sum decides the
        // winding number when the total error stays under pi.
        let vv = v.dot(v);
        let c0 = self.centre[0];
        // The angle of each boundary edge and the bound on its error, `None` when too close to
        // the centre to bound.
        let angle = |&e: &u32| {
            let [a, b] = self.directed(topo, e);
            let (pa, pb) = (x0[a as usize] - c0, x0[b as usize] - c0);
            // (x, y) is |V|^2 times the projected (dot, cross) pair, up to the factor |V| ~ 1 on y.
            let y = v.dot(pa.cross(pb));
            let x = pa.dot(pb) * vv - pa.dot(v) * pb.dot(v);
            let e_xy = ANGLE_ERROR * UNIT_ROUNDOFF * max_abs(pa) * max_abs(pb) * vv.max(1.0);
            let r = x.hypot(y);
            // Also rejects a NaN r.
            if r.partial_cmp(&(4.0 * e_xy)) != Some(std::cmp::Ordering::Greater) {
                return None;
            }
            // Direction error of a vector perturbed by at most sqrt(2) e_xy, plus atan2's own.
            Some((y.atan2(x), 4.0 * e_xy / r + 4.0 * UNIT_ROUNDOFF))
        };
        let (mut sum, mut error) = (0.0f64, 0.0f64);
        // Summed in boundary order either way, so the same sums for any thread count.
        let mut add = |term: Option<(f64, f64)>| {
            let (theta, bound) = term.ok_or(DiskFailure::Winding)?;
            sum += theta;
            error += bound;
            Ok(())
        };
        if !self.sequential && self.boundary.len() >= PARALLEL_TESTS {
            let terms: Vec<_> = self.boundary.par_iter().with_min_len(64).map(angle).collect();
            terms.into_iter().try_for_each(&mut add)?;
        } else {
            self.boundary.iter().map(angle).try_for_each(&mut add)?;
        }
        let n = self.boundary.len() as f64;
        error += 2.0 * n * UNIT_ROUNDOFF * sum.abs();
        let two_pi = std::f64::consts::TAU;
        if (sum - two_pi).abs() + error < std::f64::consts::PI {
            Ok(())
        } else {
            Err(DiskFailure::Winding)
        }
    }

    /// Mean of the patch's vertices at t=0 and t=1: a star centre to try when the current one
    /// fails (any linearly moving point will do for the theorem).
    pub fn vertex_centroid(&self) -> [DVec3; 2] {
        let k = self.vertices.max(1) as f64;
        [self.vertex_sum[0] / k, self.vertex_sum[1] / k]
    }

    /// The current star centre at t=0 and t=1.
    pub fn centre(&self) -> [DVec3; 2] {
        self.centre
    }

    /// Replaces the star centre (for another [`DiskBuilder::check_boundary`] with `all_edges`).
    pub fn set_centre(&mut self, centre: [DVec3; 2]) {
        self.centre = centre;
        self.next_centre_gen();
    }

    /// The boundary edge `e` directed as its one patch triangle traverses it.
    fn directed(&self, topo: &Topology, e: u32) -> [u32; 2] {
        let [i, j] = topo.edges[e as usize];
        debug_assert_eq!(self.edge_state[e as usize] & COUNT_MASK, 1);
        if self.edge_state[e as usize] & FORWARD != 0 {
            [i, j]
        } else {
            [j, i]
        }
    }
}
