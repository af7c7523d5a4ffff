//! The feature pairs of one leaf pair and the distance test that keeps or drops each: shared
//! by the hierarchy's traversal and the brute-force oracle.

use crate::alloc::{try_append, try_push, AllocError};
use crate::distance::{
    edge_edge_distance, extent, point_edge_distance, point_point_distance, point_triangle_distance,
    rounding_bound, sin2,
};
use crate::math::DVec3;
use crate::mesh::CanCollide;

use super::boxes::overlap;
use super::primitives::Kind;
use super::report::{EeProximity, VeProximity, VfProximity, VvProximity};
use super::slots::{Slot, Slots};

/// The largest extra term of [`rounding_bound`] for nearly parallel edges, per unit of
/// extent: `max_s min(s, 16 u / s) = 4 sqrt(u)`, rounded up.
pub(crate) const PARALLEL_EXTRA: f64 = 4.3e-8;

/// The pairs found by one task (or the whole query), unsorted, and the distances computed.
#[derive(Clone, Debug, Default)]
pub(crate) struct Found {
    pub vf: Vec<VfProximity>,
    pub ee: Vec<EeProximity>,
    pub ve: Vec<VeProximity>,
    pub vv: Vec<VvProximity>,
    pub tests: u64,
    /// With [`Test::r_list`]: the pairs closer than it (see `cache`).
    pub cands: Cands,
    /// The first allocation that failed: nothing more is kept (the query returns it).
    pub failure: Option<AllocError>,
    /// Some task stopped at its cap (see [`Found::full`]): the pairs are not all there.
    pub capped: bool,
    /// Some task gave up listing (its listing reached the cap): [`Found::cands`] is not the
    /// whole listing, and must not be kept.
    pub unlisted: bool,
}

/// Pushes `x` onto `v`, or records the allocation failure in `failure` (once).
#[inline]
fn put<T>(v: &mut Vec<T>, x: T, failure: &mut Option<AllocError>, what: &'static str) {
    if failure.is_none() {
        if let Err(e) = try_push(v, x, what) {
            *failure = Some(e);
        }
    }
}

/// Feature pairs past the boxes, kept to be evaluated again at nearby positions (see
/// `cache`): vertex-face (vertex, face), edge-edge, free point-free edge, free points.
#[derive(Clone, Debug, Default)]
pub(crate) struct Cands {
    pub vf: Vec<(u32, u32)>,
    pub ee: Vec<([u32; 2], [u32; 2])>,
    pub ve: Vec<(u32, [u32; 2])>,
    pub vv: Vec<(u32, u32)>,
}

impl Cands {
    pub fn len(&self) -> usize {
        self.vf.len() + self.ee.len() + self.ve.len() + self.vv.len()
    }

    pub fn append(&mut self, other: &mut Cands) -> Result<(), AllocError> {
        try_append(&mut self.vf, &mut other.vf, LISTED)?;
        try_append(&mut self.ee, &mut other.ee, LISTED)?;
        try_append(&mut self.ve, &mut other.ve, LISTED)?;
        try_append(&mut self.vv, &mut other.vv, LISTED)
    }
}

/// The most pairs a query lists (see `cache`) under a cap of `cap` pairs: a listing that
/// reaches it is given up (the query is answered, its listing not kept).
#[inline]
pub(crate) fn list_cap(cap: usize) -> usize {
    cap.max(1 << 20)
}

/// What the buffers are called in an allocation failure.
const LISTED: &str = "listed proximity pairs";
const PAIRS: &str = "proximity pairs";

impl Found {
    pub fn len(&self) -> usize {
        self.vf.len() + self.ee.len() + self.ve.len() + self.vv.len()
    }

    /// Whether this task's buffer has reached `cap` pairs: the task stops (and records
    /// [`Found::capped`]). It also gives up listing once its listing and `elsewhere` (the
    /// other tasks' listings) reach [`list_cap`]`(cap)` (recording [`Found::unlisted`] and
    /// freeing the listing), so that a task holds no more than about that many pairs of
    /// either kind.
    /// A task whose allocation failed stops too (the query returns the failure).
    #[inline]
    pub fn full(&mut self, cap: usize, elsewhere: usize) -> bool {
        if self.failure.is_some() {
            return true;
        }
        self.unlist_beyond(cap, elsewhere);
        if self.len() >= cap {
            self.capped = true;
            return true;
        }
        false
    }

    /// Gives up listing (freeing the listing, recording [`Found::unlisted`]) once it and
    /// `elsewhere` (the other tasks' listings) reach [`list_cap`]`(cap)`.
    #[inline]
    pub fn unlist_beyond(&mut self, cap: usize, elsewhere: usize) {
        if !self.unlisted && self.cands.len().saturating_add(elsewhere) >= list_cap(cap) {
            self.cands = Cands::default();
            self.unlisted = true;
        }
    }

    /// Appends `other`'s pairs; an error (`other`'s own, or this buffer's that cannot grow)
    /// is also recorded in [`Found::failure`].
    pub fn append(&mut self, other: &mut Found) -> Result<(), AllocError> {
        let result = (|| {
            if let Some(e) = other.failure.or(self.failure) {
                return Err(e);
            }
            try_append(&mut self.vf, &mut other.vf, PAIRS)?;
            try_append(&mut self.ee, &mut other.ee, PAIRS)?;
            try_append(&mut self.ve, &mut other.ve, PAIRS)?;
            try_append(&mut self.vv, &mut other.vv, PAIRS)?;
            self.tests += other.tests;
            self.capped |= other.capped;
            self.unlisted |= other.unlisted;
            self.cands.append(&mut other.cands)
        })();
        if let Err(e) = result {
            self.failure.get_or_insert(e);
        }
        result
    }
}

/// The distance test of one query: the positions, the threshold and the pair filter.
#[derive(Clone, Copy)]
pub(crate) struct Test<'a> {
    pub x: &'a [DVec3],
    /// `dhat + dmin`.
    pub r: f64,
    pub groups: Option<&'a [u32]>,
    pub can_collide: Option<CanCollide<'a>>,
    /// When listing (see `cache`), the listing threshold (above `r`): the boxes and the
    /// per-pair reject are for it, and the pairs whose computed distance is below it are
    /// written to [`Found::cands`]; the report is still for `r`. 0: not listing.
    pub r_list: f64,
}

/// The largest distance a kept pair of this extent may have for threshold `r` (the
/// threshold, the bound on the computed distance's excess and on its shortfall), plus a
/// margin: pairs whose boxes are farther apart than this are dropped before their distance
/// is computed. Increasing in `extent`.
#[inline]
pub(crate) fn reach(r: f64, extent: f64) -> f64 {
    (r + 2.0 * rounding_bound(extent, 1.0) + PARALLEL_EXTRA * extent) * (1.0 + 1e-12)
}

impl Test<'_> {
    /// Rules 3 and 4 of the pair filter (`mesh::filter`): whether some vertex pair across
    /// the features may collide. Features sharing a vertex never reach here.
    #[inline]
    fn allowed(&self, a: &[u32], b: &[u32]) -> bool {
        if let Some(groups) = self.groups {
            let g = |v: u32| groups[v as usize];
            if !a.iter().any(|&x| b.iter().any(|&y| g(x) != g(y))) {
                return false;
            }
        }
        if let Some(can) = self.can_collide {
            if !a.iter().any(|&x| b.iter().any(|&y| can(x, y))) {
                return false;
            }
        }
        true
    }

    /// Whether a computed squared distance `d2` of a pair of this extent is kept: below the
    /// threshold inflated by the rounding bound (`sin2` of the edges for an edge-edge pair,
    /// computed only when needed).
    #[inline]
    fn keep(&self, d2: f64, extent: f64, sin2: impl FnOnce() -> f64) -> bool {
        let base = self.r + rounding_bound(extent, 1.0);
        if d2 < base * base {
            return true;
        }
        let loose = base + PARALLEL_EXTRA * extent;
        if d2 >= loose * loose {
            return false;
        }
        let tight = self.r + rounding_bound(extent, sin2());
        d2 < tight * tight
    }

    /// [`reach`] at this query's threshold (the listing's when listing).
    #[inline]
    fn reach(&self, extent: f64) -> f64 {
        reach(self.r.max(self.r_list), extent)
    }

    /// Whether a pair past the per-pair reject (box gap `gap`), with computed squared
    /// distance `d2`, is reported: within [`reach`] of the report's threshold (always, when
    /// not listing) and kept.
    #[inline]
    fn report(&self, gap: f64, d2: f64, extent: f64, sin2: impl FnOnce() -> f64) -> bool {
        (self.r_list == 0.0 || gap <= reach(self.r, extent)) && self.keep(d2, extent, sin2)
    }

    /// Whether a pair is listed (see `cache`).
    #[inline]
    fn listed(&self, d2: f64) -> bool {
        self.r_list > 0.0 && d2 < self.r_list * self.r_list
    }

    /// Vertex `v` against triangle `face` (not containing `v`).
    #[inline]
    pub fn vf(&self, v: u32, face: u32, f: [u32; 3], out: &mut Found) {
        let x = self.x;
        let p = x[v as usize];
        let c = f.map(|i| x[i as usize]);
        let ext = extent(p, &c);
        // The point against the face's box, with the reach.
        let reach = self.reach(ext);
        let (lo, hi) = (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]));
        let gap = (lo - p).max_element().max((p - hi).max_element());
        if gap > reach {
            return;
        }
        if !self.allowed(&[v], &f) {
            return;
        }
        out.tests += 1;
        let (d2, kind) = point_triangle_distance(p, c[0], c[1], c[2]);
        if self.listed(d2) && !out.unlisted {
            put(&mut out.cands.vf, (v, face), &mut out.failure, LISTED);
        }
        if self.report(gap, d2, ext, || 1.0) {
            let pair = VfProximity {
                vertex: v,
                face,
                distance: d2.sqrt(),
                kind,
            };
            put(&mut out.vf, pair, &mut out.failure, PAIRS);
        }
    }

    /// Two edges sharing no vertex, each `[i, j]` with `i < j`.
    #[inline]
    pub fn ee(&self, a: [u32; 2], b: [u32; 2], out: &mut Found) {
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        let x = self.x;
        let (a0, a1, b0, b1) = (
            x[a[0] as usize],
            x[a[1] as usize],
            x[b[0] as usize],
            x[b[1] as usize],
        );
        let ext = extent(a0, &[a1, b0, b1]);
        let reach = self.reach(ext);
        let (alo, ahi, blo, bhi) = (a0.min(a1), a0.max(a1), b0.min(b1), b0.max(b1));
        let gap = (alo - bhi).max_element().max((blo - ahi).max_element());
        if gap > reach {
            return;
        }
        if !self.allowed(&a, &b) {
            return;
        }
        out.tests += 1;
        let (d2, kind) = edge_edge_distance(a0, a1, b0, b1);
        if self.listed(d2) && !out.unlisted {
            put(&mut out.cands.ee, (a, b), &mut out.failure, LISTED);
        }
        if self.report(gap, d2, ext, || sin2(a1 - a0, b1 - b0)) {
            let pair = EeProximity {
                a,
                b,
                distance: d2.sqrt(),
                kind,
            };
            put(&mut out.ee, pair, &mut out.failure, PAIRS);
        }
    }

    /// Free point `v` against edge `e` (`[i, j]`, `i < j`).
    #[inline]
    pub fn ve(&self, v: u32, e: [u32; 2], out: &mut Found) {
        let x = self.x;
        let (p, e0, e1) = (x[v as usize], x[e[0] as usize], x[e[1] as usize]);
        let ext = extent(p, &[e0, e1]);
        let gap = (e0.min(e1) - p)
            .max_element()
            .max((p - e0.max(e1)).max_element());
        if gap > self.reach(ext) {
            return;
        }
        if !self.allowed(&[v], &e) {
            return;
        }
        out.tests += 1;
        let (d2, kind) = point_edge_distance(p, e0, e1);
        if self.listed(d2) && !out.unlisted {
            put(&mut out.cands.ve, (v, e), &mut out.failure, LISTED);
        }
        if self.report(gap, d2, ext, || 1.0) {
            let pair = VeProximity {
                vertex: v,
                edge: e,
                distance: d2.sqrt(),
                kind,
            };
            put(&mut out.ve, pair, &mut out.failure, PAIRS);
        }
    }

    /// Two free points.
    #[inline]
    pub fn vv(&self, a: u32, b: u32, out: &mut Found) {
        let (a, b) = (a.min(b), a.max(b));
        let (p, q) = (self.x[a as usize], self.x[b as usize]);
        let ext = extent(p, &[q]);
        let gap = (q - p).abs().max_element();
        if gap > self.reach(ext) || !self.allowed(&[a], &[b]) {
            return;
        }
        out.tests += 1;
        let d2 = point_point_distance(p, q);
        if self.listed(d2) && !out.unlisted {
            put(&mut out.cands.vv, (a, b), &mut out.failure, LISTED);
        }
        if self.report(gap, d2, ext, || 1.0) {
            let pair = VvProximity {
                a,
                b,
                distance: d2.sqrt(),
            };
            put(&mut out.vv, pair, &mut out.failure, PAIRS);
        }
    }

    /// Every feature pair that the leaf pair `(a, b)` (`a != b`) owns (see `primitives`),
    /// each first through the features' boxes (see `boxes` and `slots`; the brute-force
    /// oracle goes without them).
    #[inline]
    pub fn leaf_pair(&self, s: &Slots, a: u32, b: u32, out: &mut Found) {
        let (sa, sb) = (s.slot_of[a as usize], s.slot_of[b as usize]);
        let (la, lb) = (&s.slots[sa as usize], &s.slots[sb as usize]);
        self.one_way(s, la, lb, sb, out);
        self.one_way(s, lb, la, sa, out);
        // Edges owned by both: each pair once, a's edge first.
        for i in la.e0..la.e0 + la.ne {
            let (ea, ba) = (s.edges[i as usize], &s.ebox[i as usize]);
            for j in lb.e0..lb.e0 + lb.ne {
                let eb = s.edges[j as usize];
                if overlap(ba, &s.ebox[j as usize])
                    && ea[0] != eb[0]
                    && ea[0] != eb[1]
                    && ea[1] != eb[0]
                    && ea[1] != eb[1]
                {
                    self.ee(ea, eb, out);
                }
            }
        }
        // (Two points' leaves overlap: their boxes are the leaves' boxes.)
        if la.kind == Kind::Point && lb.kind == Kind::Point {
            self.vv(la.verts[0], lb.verts[0], out);
        }
    }

    /// The pairs of the vertices `la` owns against leaf `lb` (slot `sb`): vertex-face when
    /// `lb` is a triangle, and a free point against a free edge.
    #[inline]
    fn one_way(&self, s: &Slots, la: &Slot, lb: &Slot, sb: u32, out: &mut Found) {
        if lb.kind == Kind::Triangle {
            let tb = &s.lbox[sb as usize];
            for i in la.v0..la.v0 + la.nv {
                let v = s.verts[i as usize];
                if overlap(&s.vbox[i as usize], tb) && !lb.verts.contains(&v) {
                    self.vf(v, lb.id, lb.verts, out);
                }
            }
        }
        // A free point against a free edge: its pairs with a triangle's edges are covered by
        // its vertex-face pairs with the triangle (never farther).
        if la.kind == Kind::Point && lb.kind == Kind::Edge {
            // (The edge's box is the leaf's box, which overlaps the point's.)
            for i in lb.e0..lb.e0 + lb.ne {
                self.ve(la.verts[0], s.edges[i as usize], out);
            }
        }
    }
}
