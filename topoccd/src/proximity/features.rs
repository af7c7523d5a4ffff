//! Leaves by feature, in one wide hierarchy (`bvh::wide`): the leaves of `primitives`
//! (triangles, free edges, free points, with the features each owns), their boxes inflated by
//! `h` (half the reach, see `boxes::inflation`), four children per node tested in one SIMD
//! pass. The query is by feature, not by leaf pair: every vertex against the tree (a face is
//! paired with the vertex, a free edge or a later free point with a free point), every owned
//! edge against the leaves after its owner (each unordered pair once), then against the edges
//! those own. So each candidate pair is met once, with no leaf pair of triangles to unfold:
//! the same candidates as the binary tree's leaf pairs (the same boxes, the same per-pair test
//! of `pairs`), so the same report once sorted.
//!
//! Adjacent pairs are skipped where they are met: a face is not paired with its own corners,
//! two edges sharing a vertex are not paired (a compare of indices, before any position is
//! read).
//!
//! The boxes are those of `boxes::inflated`: a vertex's box is computed once per query, and a
//! leaf's or an edge's is the union of its vertices' (the same `f32` bounds: subtracting `h`
//! and rounding outward are both monotone, so they commute with the minimum). The tree is kept
//! and refitted across queries while the primitives stay the same, rebuilt when refitting has
//! loosened it too much.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use rayon::prelude::*;

use crate::bvh::wide::{Box3, WideBvh, WIDTH};
use crate::bvh::{BoundingVolume, BvhWorkspace};
use crate::math::DVec3;

use super::boxes::{inflated, overlap};
use super::pairs::{Found, Test};
use super::primitives::{Kind, Primitives};
use super::run::Stop;

/// Rebuild once the refitted tree's child boxes have grown this much (their summed extents,
/// net of a change of the inflation) over the tree's as built.
const LOOSENESS: f64 = 1.5;

/// Queries per task: vertices, or leaves whose edges are queried.
const CHUNK: usize = 1024;

/// Marks a vertex that is not a free point (see [`FeatureTree::verts`]).
const NOT_POINT: u32 = u32::MAX;

/// One leaf at its position in the tree.
#[derive(Clone, Copy, Debug)]
struct Slot {
    kind: Kind,
    /// The leaf's id (a triangle's is its index).
    id: u32,
    /// Its vertices (unused ones `u32::MAX`).
    verts: [u32; 3],
    /// The edges it owns: `FeatureTree::edges[e0..e0 + ne]`.
    e0: u32,
    ne: u32,
}

/// The tree, the leaves in its order, and this query's vertex boxes.
#[derive(Clone, Debug, Default)]
pub(crate) struct FeatureTree {
    tree: WideBvh,
    /// The leaves by position.
    slots: Vec<Slot>,
    /// The owned edges (`[i, j]`, `i < j`), leaf by leaf in position order.
    edges: Vec<[u32; 2]>,
    /// The owned vertices, leaf by leaf in position order, each with its leaf's position if
    /// it is a free point, else [`NOT_POINT`].
    verts: Vec<(u32, u32)>,
    /// Every vertex's box (this query's).
    vbox: Vec<Box3>,
    /// The summed extents of the child boxes when built, and the inflation.
    built: (f64, f64),
    valid: bool,
}

/// One task: a range of the vertices queried, or of the leaf positions whose edges are.
#[derive(Clone, Copy, Debug)]
enum Job {
    Vertices(usize, usize),
    Edges(usize, usize),
}

/// The box of vertices `v` (unused ones `u32::MAX`, after the used ones).
#[inline]
fn box_of(vbox: &[Box3], v: &[u32]) -> Box3 {
    let mut b = vbox[v[0] as usize];
    for &w in &v[1..] {
        if w != u32::MAX {
            b = b.merge(&vbox[w as usize]);
        }
    }
    b
}

impl FeatureTree {
    /// Forgets the tree (the primitives changed).
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Fits the tree to positions `x` with the boxes inflated by `h`: refits the tree kept
    /// (same primitives) unless it has loosened too much; else builds it. Returns whether it
    /// was refitted.
    pub fn fit(&mut self, prims: &Primitives, x: &[DVec3], h: f64, ws: &mut BvhWorkspace) -> bool {
        self.vbox.clear();
        self.vbox.extend(x.iter().map(|p| inflated(&[*p], h)));
        let vbox = &self.vbox;
        let lbox = |i: u32| box_of(vbox, &prims.leaves[i as usize].verts);
        if self.valid && self.tree.leaf_count() == prims.leaves.len() {
            let (size, count) = self.tree.refit(lbox);
            let (built, built_h) = self.built;
            // Each box widens by twice the change of inflation on each of the three axes.
            let s = size - 6.0 * count as f64 * (h - built_h);
            if s.is_finite() && s <= LOOSENESS * built {
                return true;
            }
        }
        let center = |i: usize| {
            let l = &prims.leaves[i];
            let (lo, hi) = (l.vertices().iter())
                .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(x[v as usize]), hi.max(x[v as usize]))
                });
            (lo + hi) * 0.5
        };
        self.tree.rebuild(prims.leaves.len(), center, lbox, ws);
        self.built = (self.tree.size().0, h);
        self.slots.clear();
        self.edges.clear();
        self.verts.clear();
        for (pos, &id) in self.tree.ids().iter().enumerate() {
            let l = &prims.leaves[id as usize];
            self.slots.push(Slot {
                kind: l.kind,
                id,
                verts: l.verts,
                e0: self.edges.len() as u32,
                ne: u32::from(l.ne),
            });
            (self.edges).extend(
                l.owned_e[..l.ne as usize]
                    .iter()
                    .map(|&e| prims.edges[e as usize]),
            );
            let point = if l.kind == Kind::Point {
                pos as u32
            } else {
                NOT_POINT
            };
            (self.verts).extend(l.owned_v[..l.nv as usize].iter().map(|&v| (v, point)));
        }
        self.valid = true;
        false
    }

    /// Every pair of `test` among the primitives, unsorted, with the box tests made (node
    /// visits times the width). A stop (`stop`) is checked per task.
    ///
    /// Under a cap of `max` pairs the answer is the same for any thread count: the tasks are
    /// taken in their fixed order, each stopping once it holds `max` pairs
    /// ([`Found::full`]), until the pairs taken reach `max` ([`Found::capped`] then says
    /// that pairs were left out). The tasks run in parallel; once the finished ones hold
    /// `max` pairs no other starts, and a task of the order's prefix that did not run is run
    /// afterwards. So no more than `max` pairs are held per running task, plus `max` taken.
    pub fn find(&self, test: &Test<'_>, stop: &Stop, max: usize) -> (Found, u64) {
        let mut jobs = Vec::new();
        let chunks = |n: usize, f: fn(usize, usize) -> Job, jobs: &mut Vec<Job>| {
            jobs.extend((0..n).step_by(CHUNK).map(|s| f(s, (s + CHUNK).min(n))));
        };
        chunks(self.verts.len(), Job::Vertices, &mut jobs);
        chunks(self.slots.len(), Job::Edges, &mut jobs);
        // The pairs and the listed pairs of the tasks finished, and whether an allocation
        // failed (then no other task starts: the query returns the failure).
        let (held, listed) = (AtomicUsize::new(0), AtomicUsize::new(0));
        let failed = AtomicBool::new(false);
        let run = |job: Job, stack: &mut Vec<u32>| {
            let mut out = Found::default();
            let visits = self.job(job, test, stack, &mut out, max, &listed);
            held.fetch_add(out.len(), Ordering::Relaxed);
            listed.fetch_add(out.cands.len(), Ordering::Relaxed);
            if out.failure.is_some() {
                failed.store(true, Ordering::Relaxed);
            }
            (out, visits)
        };
        let mut parts: Vec<Option<(Found, u64)>> = if rayon::current_num_threads() == 1 {
            // In order, below.
            (0..jobs.len()).map(|_| None).collect()
        } else {
            (jobs.par_iter())
                .with_max_len(1)
                .map_init(Vec::new, |stack, &job| {
                    if held.load(Ordering::Relaxed) >= max
                        || failed.load(Ordering::Relaxed)
                        || stop.check()
                    {
                        return None;
                    }
                    Some(run(job, stack))
                })
                .collect()
        };
        if let Some(failure) = parts.iter().flatten().find_map(|(f, _)| f.failure) {
            let found = Found {
                failure: Some(failure),
                ..Found::default()
            };
            return (found, 0);
        }
        let mut found = Found::default();
        let mut visits = 0;
        let mut stack = Vec::new();
        for (part, &job) in parts.iter_mut().zip(&jobs) {
            if found.len() >= max {
                found.capped = true;
                break;
            }
            let Some((mut f, v)) = part
                .take()
                .or_else(|| (!stop.check()).then(|| run(job, &mut stack)))
            else {
                break;
            };
            visits += v;
            // An allocation failure is kept in `found.failure`, which the query returns.
            if found.append(&mut f).is_err() {
                break;
            }
        }
        drop(parts);
        found.unlist_beyond(max, 0);
        (found, visits * WIDTH as u64)
    }

    /// The queries of one task into `out` (stopping once it holds `max` pairs); returns the
    /// node visits.
    fn job(
        &self,
        job: Job,
        test: &Test<'_>,
        stack: &mut Vec<u32>,
        out: &mut Found,
        max: usize,
        listed: &AtomicUsize,
    ) -> u64 {
        let (vbox, slots, edges) = (&self.vbox, &self.slots, &self.edges);
        let mut visits = 0;
        match job {
            Job::Vertices(s, e) => {
                for &(v, point) in &self.verts[s..e] {
                    visits += self.tree.query(&vbox[v as usize], 0, stack, |pos| {
                        let l = &slots[pos as usize];
                        match l.kind {
                            Kind::Triangle
                                if l.verts[0] != v && l.verts[1] != v && l.verts[2] != v =>
                            {
                                test.vf(v, l.id, l.verts, out);
                            }
                            // A free point against a free edge, and a later free point.
                            Kind::Edge if point != NOT_POINT => {
                                test.ve(v, edges[l.e0 as usize], out);
                            }
                            Kind::Point if point != NOT_POINT && pos > point => {
                                test.vv(v, l.verts[0], out);
                            }
                            _ => {}
                        }
                    });
                    if out.full(max, listed.load(Ordering::Relaxed)) {
                        break;
                    }
                }
            }
            Job::Edges(s, e) => {
                for (p, l) in slots.iter().enumerate().take(e).skip(s) {
                    for &ea in &edges[l.e0 as usize..(l.e0 + l.ne) as usize] {
                        let q = box_of(vbox, &ea);
                        visits += self.tree.query(&q, p as u32 + 1, stack, |pos| {
                            let m = &slots[pos as usize];
                            for &eb in &edges[m.e0 as usize..(m.e0 + m.ne) as usize] {
                                if ea[0] != eb[0]
                                    && ea[0] != eb[1]
                                    && ea[1] != eb[0]
                                    && ea[1] != eb[1]
                                    && overlap(&q, &box_of(vbox, &eb))
                                {
                                    test.ee(ea, eb, out);
                                }
                            }
                        });
                    }
                    if out.full(max, listed.load(Ordering::Relaxed)) {
                        break;
                    }
                }
            }
        }
        visits
    }
}
