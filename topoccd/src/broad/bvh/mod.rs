//! The per-step hierarchy (the paper's baseline, as in Self-CCD): a k-DOP tree over the
//! triangles' swept volumes, traversed against itself; every overlapping triangle pair gives
//! the feature pairs its two triangles own.
//!
//! Kept across steps ([`BvhPhase`]): the tree is refitted while the triangles stay the same,
//! or while at most one in eight changes its corners (a cut or a tear re-indexes a few), as
//! long as it fits its leaves; otherwise it is rebuilt. With the tree comes its *front*
//! ([`Bvh::front_within`]): the highest pairs of subtrees that share no mesh vertex. Two subtrees
//! that share a vertex always overlap, so a traversal from the root descends them every step
//! down to neighbouring triangles, most of its tests. The front depends on the tree's shape
//! and the triangles only; it is computed with each build, updated where a cut changed the
//! triangles, and the traversal starts from it. The neighbouring triangles that rule 6 of the
//! pair filter does not drop (those sharing no vertex with a certified star) come from the
//! topology instead ([`neighbours`]).
//!
//! The traversal runs on the rayon pool as a fixed list of tasks (chunks of the front, or,
//! without a front, the tasks of [`Bvh::par_self_pairs_with`]); each task gets its own
//! accumulator, so the caller can run the narrow phase inside the tasks on bounded buffers.

use std::ops::ControlFlow;

use rayon::prelude::*;

mod neighbours;
mod phase;

pub(crate) use phase::BvhPhase;

use neighbours::neighbours;

use super::{corner_volumes, triangle_volume, triangle_volume_from, BroadInput, TaskPairs};
use crate::bvh::run_batches;
use crate::bvh::{Bvh, BvhError, BvhWorkspace, Front, Leaf, LeafCheck, ParOptions, TestAll};
use crate::kdop::{CompactKdop, Kdop};
use crate::math::{lerp, DVec3};
use crate::mesh::star::StarView;
use crate::mesh::{Step, Topology};

/// The hierarchy of one k-DOP type over the triangles' swept volumes (leaf `t` is triangle
/// `t`), kept for reuse across steps. The leaves' volumes live in the tree's nodes only: they
/// are computed from the positions where the build or the refit places them.
#[derive(Clone, Debug, Default)]
pub(crate) struct PerStepBvh<const H: usize> {
    bvh: Bvh<CompactKdop<H>>,
    /// The end of the times the leaves' volumes are swept over, and their inflation.
    swept: (f64, f64),
    /// What the tree's shape was built for, while it may still be refitted.
    shape: Option<Shape>,
    /// Whether the last [`PerStepBvh::build`] refitted the tree rather than rebuilt it.
    pub refitted: bool,
    /// Per node (meaningful for leaves only): the leaf triangle's corners and which of them
    /// have a certified star this step ([`PerStepBvh::mark_stars`]), beside the tree so that
    /// the traversal drops neighbours in a certified star without testing their volumes.
    corners: Vec<Corners>,
    /// Whether `corners` holds this step's certified stars: set by [`PerStepBvh::mark_stars`],
    /// cleared by every build, so a stale mark never drops a pair.
    marked: bool,
    /// The front of the tree's self-traversal for the relation "the triangles share a vertex"
    /// ([`Bvh::front_within`]), valid while `front_valid`: the tree's shape and its triangles are
    /// those it was computed for (a rebuild clears it; a refit keeps it).
    front: Front,
    front_valid: bool,
    /// Whether the search for the front of this tree's shape gave up ([`FRONT_BUDGET`]): the
    /// traversal then starts from the root until the tree is rebuilt.
    front_refused: bool,
    /// The parent of each node (the root's is itself), for the ancestors of changed leaves.
    parent: Vec<u32>,
    /// This step's neighbouring triangle pairs that share no vertex with a certified star
    /// ([`PerStepBvh::mark_stars`]): with the front, the traversal's only related pairs.
    neighbours: Vec<[u32; 2]>,
    /// The node of each leaf triangle.
    leaf_node: Vec<u32>,
    /// Scratch: the vertices' parts of this step's volumes ([`corner_volumes`]).
    corner_volumes: Vec<(Kdop<H>, DVec3)>,
    /// Each triangle's volume in `f64`, as the tree was last fitted. The tree's nodes hold
    /// them rounded outward to `f32` ([`CompactKdop`]): half the memory for the traversal,
    /// which finds a few more pairs of leaves that way; the pairs it reports are those whose
    /// `f64` volumes overlap, the same as a tree of `f64` volumes reports.
    leaf_volumes: Vec<Kdop<H>>,
}

/// Past one triangle in this many with other corners, a tree over as many triangles is rebuilt
/// rather than refitted.
const CHANGED_SHARE: usize = 8;

/// The node pairs the search for a front may look at, per leaf: about one full traversal's
/// bounding-volume tests (10 to 50 per leaf on the scenes measured), with room to spare. Past
/// it (a mesh collapsed to a few points, where every pair of subtrees overlaps and the search
/// would look at every pair of leaves before the query could stop) the tree has no front, and
/// its traversal from the root, which a cap, a deadline or a cancel stops, does the work.
const FRONT_BUDGET: u64 = 256;

/// Pairs of the front one task of the front's traversal takes (a fixed number, so the tasks do
/// not depend on the thread count).
const FRONT_TASK: usize = 1 << 10;
/// Neighbouring pairs one task takes.
const NEIGHBOUR_TASK: usize = 1 << 12;

/// A leaf's triangle, as the traversal's [`LeafCheck`] reads it.
#[derive(Clone, Copy, Debug, Default)]
#[repr(align(16))]
struct Corners {
    /// The triangle's vertices.
    vertices: [u32; 3],
    /// Bit `i`: the star of `vertices[i]` is certified (rule 6 of the pair filter).
    certified: u8,
}

/// Rule 6 of the pair filter before the volumes: two leaf triangles that share a vertex whose
/// star is certified give no candidate ([`Features::triangle_pair`] drops them first), so the
/// traversal need not test them. (Their volumes always overlap: both contain the shared
/// vertex's path.)
///
/// [`Features::triangle_pair`]: crate::mesh::features::Features::triangle_pair
struct CertifiedNeighbours<'a>(&'a [Corners]);

impl LeafCheck for CertifiedNeighbours<'_> {
    #[inline(always)]
    fn skip(&self, a: u32, b: u32) -> bool {
        let (x, y) = (&self.0[a as usize], &self.0[b as usize]);
        let mut shared = 0u8;
        for (i, v) in x.vertices.iter().enumerate() {
            let hit = *v == y.vertices[0] || *v == y.vertices[1] || *v == y.vertices[2];
            shared |= u8::from(hit) << i;
        }
        shared & x.certified != 0
    }
}

/// How well a hierarchy's shape fitted its volumes when built.
#[derive(Clone, Copy, Debug)]
struct Shape {
    /// [`spread`] right after the build; `None` until a refit first needs it (until then the
    /// tree is as built, so it is measured then).
    spread: Option<f64>,
}

/// A refitted tree is kept while its [`spread`] stays within this factor of its spread when
/// built; past it, the tree is rebuilt.
const REFIT_SPREAD: f64 = 1.25;

/// How loosely a tree fits its leaves: the sum of its internal nodes' extents (the widths of
/// their first three slabs, the axes) over the root's extent. A tree refitted to leaves that
/// moved apart from their neighbours of the build has bigger internal nodes, which overlap
/// more and cost the traversal more tests.
fn spread<const H: usize>(bvh: &Bvh<CompactKdop<H>>) -> f64 {
    let Some(root) = bvh.root_volume() else {
        return 0.0;
    };
    let inner: f64 = (bvh.nodes().iter())
        .filter(|n| n.children().is_some())
        .map(|n| n.volume.extent())
        .sum();
    inner / root.extent()
}

impl<const H: usize> PerStepBvh<H> {
    /// Fits the hierarchy to the volumes swept by the step's triangles over `[0, tmax]` (the
    /// whole step for `tmax >= 1`), inflated by `sep`. It needs the positions and triangles
    /// only, not the step's topology.
    ///
    /// With `same_triangles` (the step has the very triangles of the last step this was
    /// built for), or as many triangles of which at most one in [`CHANGED_SHARE`] have other
    /// corners (a cut), the last tree is refitted (`O(n)`, as Self-CCD does every step)
    /// rather than rebuilt, whatever times its volumes were swept over, unless the refitted
    /// tree fits its leaves much worse than when it was built ([`REFIT_SPREAD`]). Either way
    /// every node contains its leaves, so what the traversal reports is the same.
    pub fn build(
        &mut self,
        step: &Step,
        (tmax, sep): (f64, f64),
        same_triangles: bool,
        ws: &mut BvhWorkspace,
    ) {
        self.sweep_leaves(step, tmax, sep);
        let leaves = &self.leaf_volumes;
        let volume = move |t: u32| CompactKdop::outward(&leaves[t as usize]);
        self.swept = (tmax, sep);
        self.marked = false;
        let tris = step.triangles();
        // A tree over as many triangles, swept the same way, is refitted: over the very same
        // triangles (the everyday step), or over triangles of which a few changed their
        // corners (a cut or a tear re-indexes the triangles along it).
        let same_count = self.leaf_node.len() == tris.len();
        let changed = if same_triangles || !same_count {
            Vec::new()
        } else {
            self.changed_leaves(tris)
        };
        let count_kept =
            same_count && (same_triangles || changed.len() <= tris.len() / CHANGED_SHARE);
        if let Some(shape) = self.shape.filter(|_| count_kept) {
            let built = shape.spread.unwrap_or_else(|| spread(&self.bvh));
            self.bvh.refit(volume);
            self.refitted = spread(&self.bvh) <= REFIT_SPREAD * built;
            if self.refitted {
                self.shape = Some(Shape {
                    spread: Some(built),
                });
                self.update_corners(tris, &changed);
                return;
            }
        }
        self.refitted = false;
        self.front_valid = false;
        self.front_refused = false;
        let (x0, x1) = (step.pos0(), step.pos1());
        // A leaf stands for its triangle's box at 0 and at `tmax` when splitting.
        let t_end = tmax.clamp(0.0, 1.0);
        let center = |t: usize| {
            let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            for &v in &tris[t] {
                let (a, b) = (x0[v as usize], x1[v as usize]);
                let c = lerp(a, b, t_end);
                lo = lo.min(a).min(c);
                hi = hi.max(a).max(c);
            }
            (lo + hi) * 0.5
        };
        self.bvh.rebuild_from_fn(tris.len(), center, volume, ws);
        self.corners.clear();
        self.corners.extend(self.bvh.nodes().iter().map(|n| Corners {
            vertices: n.leaf().map_or([u32::MAX; 3], |t| tris[t as usize]),
            certified: 0,
        }));
        self.leaf_node.clear();
        self.leaf_node.resize(tris.len(), 0);
        self.parent.clear();
        self.parent.resize(self.bvh.nodes().len(), 0);
        for (i, n) in self.bvh.nodes().iter().enumerate() {
            match n.children() {
                None => self.leaf_node[n.leaf().expect("a leaf") as usize] = i as u32,
                Some([a, b]) => {
                    self.parent[a as usize] = i as u32;
                    self.parent[b as usize] = i as u32;
                }
            }
        }
        self.shape = Some(Shape { spread: None });
        self.find_front();
    }

    /// Computes the front of the tree as it is, unless it is valid already. A triangle's volume
    /// contains its corners' paths, so two triangles that share a vertex overlap, as
    /// [`Bvh::front_within`] needs; but not if a volume holds a NaN (coordinates near `f64::MAX`,
    /// whose projections overflow): then there is no front, and the traversal starts from the
    /// root as before.
    fn find_front(&mut self) {
        if self.front_valid || self.front_refused {
            return;
        }
        if !self.leaves_without_nan() {
            return;
        }
        let corners = &self.corners;
        let shares = |a: u32, b: u32| {
            let (x, y) = (&corners[a as usize].vertices, &corners[b as usize].vertices);
            x.iter().any(|v| y.contains(v))
        };
        let budget = self.front_budget();
        self.front_valid = self.bvh.front_within(&shares, &mut self.front, budget);
        self.front_refused = !self.front_valid;
    }

    /// The node pairs a search for the front may look at ([`FRONT_BUDGET`]).
    fn front_budget(&self) -> u64 {
        (FRONT_BUDGET * self.leaf_node.len() as u64).max(1 << 16)
    }

    /// Whether no leaf volume holds a NaN (see [`PerStepBvh::find_front`]).
    fn leaves_without_nan(&self) -> bool {
        !(self.bvh.nodes().iter()).any(|n| n.leaf().is_some() && n.volume.has_nan())
    }

    /// The leaf triangles whose corners are not those of `tris` (as many triangles as leaves).
    fn changed_leaves(&self, tris: &[[u32; 3]]) -> Vec<u32> {
        let corners = &self.corners;
        let node = &self.leaf_node;
        (0..tris.len() as u32)
            .filter(|&t| corners[node[t as usize] as usize].vertices != tris[t as usize])
            .collect()
    }

    /// Gives the `changed` triangles their new corners, and updates the front for them: only
    /// the blocks of their ancestors change ([`Bvh::update_front_within`]).
    fn update_corners(&mut self, tris: &[[u32; 3]], changed: &[u32]) {
        if changed.is_empty() {
            return self.find_front();
        }
        let mut dirty = vec![false; self.parent.len()];
        for &t in changed {
            let mut n = self.leaf_node[t as usize];
            self.corners[n as usize].vertices = tris[t as usize];
            while n != 0 && !dirty[self.parent[n as usize] as usize] {
                n = self.parent[n as usize];
                dirty[n as usize] = true;
            }
        }
        if !self.front_valid {
            return self.find_front();
        }
        // The recomputed blocks take disjoint volumes as unrelated (see `find_front`).
        if !self.leaves_without_nan() {
            self.front_valid = false;
            return;
        }
        let budget = self.front_budget();
        let corners = &self.corners;
        let shares = |a: u32, b: u32| {
            let (x, y) = (&corners[a as usize].vertices, &corners[b as usize].vertices);
            x.iter().any(|v| y.contains(v))
        };
        self.front_valid =
            self.bvh
                .update_front_within(&shares, &|n| dirty[n as usize], &mut self.front, budget);
        self.front_refused = !self.front_valid;
    }

    /// Records which leaf triangles' corners have a certified star this step (`None`: none,
    /// as with a minimum separation), for the traversal to drop the neighbours that rule 6 of
    /// the pair filter drops; and, with a front, lists the neighbouring triangles (of
    /// `topo`) that rule 6 keeps. Call it after [`PerStepBvh::build`], every step.
    pub fn mark_stars(&mut self, stars: Option<StarView<'_>>, topo: &Topology, tris: &[[u32; 3]]) {
        let mark = |c: &mut Corners| {
            c.certified = match (stars, c.vertices[0]) {
                (_, u32::MAX) | (None, _) => 0,
                (Some(s), _) => (0..3).fold(0, |m, i| m | u8::from(s.certified(c.vertices[i])) << i),
            };
        };
        if self.corners.len() >= 1 << 14 {
            self.corners.par_iter_mut().with_min_len(1 << 12).for_each(mark);
        } else {
            self.corners.iter_mut().for_each(mark);
        }
        self.marked = true;
        self.neighbours.clear();
        if self.front_valid {
            neighbours(stars, topo, tris, &mut self.neighbours);
        }
    }

    /// Refits the hierarchy to the volumes swept over the times searched, `[0, tmax]` (same
    /// tree, linear time): the leaves a build for those times has.
    pub fn refit_until_t_max(&mut self, input: &BroadInput<'_, '_>) {
        // The tree is about to stop being as built: measure its fit first.
        if let Some(shape) = &mut self.shape {
            if shape.spread.is_none() {
                shape.spread = Some(spread(&self.bvh));
            }
        }
        let (sep, tmax) = (input.filter.sep, input.filter.tmax());
        self.swept = (tmax, sep);
        self.sweep_leaves(input.step, tmax, sep);
        let leaves = &self.leaf_volumes;
        self.bvh
            .refit(move |t| CompactKdop::outward(&leaves[t as usize]));
    }

    /// The triangles' volumes swept over `[0, tmax]`, inflated by `sep`, into `leaf_volumes`.
    fn sweep_leaves(&mut self, step: &Step, tmax: f64, sep: f64) {
        corner_volumes(step, tmax, &mut self.corner_volumes);
        let volume = triangle_volume_from(step, &self.corner_volumes, tmax, sep);
        (0..step.triangles().len() as u32)
            .into_par_iter()
            .with_min_len(1 << 12)
            .map(volume)
            .collect_into_vec(&mut self.leaf_volumes);
    }

    /// Checks the hierarchy of the last step, `step`, against its leaves: the triangles'
    /// volumes swept over the times it was last fitted to.
    pub fn validate(&self, step: &Step) -> Result<(), BvhError> {
        let (tmax, sep) = self.swept;
        let volume = triangle_volume::<H>(step, tmax, sep);
        let leaves: Vec<Leaf<CompactKdop<H>>> = (0..step.triangles().len() as u32)
            .map(|t| Leaf {
                id: t,
                volume: CompactKdop::outward(&volume(t)),
            })
            .collect();
        self.bvh.validate(&leaves)
    }
}

/// Every overlapping pair of triangles of the hierarchy, each once (see [`TaskPairs`]).
impl<const H: usize> TaskPairs for PerStepBvh<H> {
    fn pairs<T: Send>(
        &self,
        ws: &mut BvhWorkspace,
        par: &ParOptions,
        make: impl Fn(usize) -> T + Sync + Send,
        pair: impl Fn(&mut T, u32, u32) + Sync + Send,
        finish: impl Fn(&mut T) + Sync + Send,
        consume: impl FnMut(T) -> ControlFlow<()>,
        skip: &(dyn Fn(&T) -> bool + Sync),
    ) -> u64 {
        // The tree's volumes are rounded outward: the pairs of leaves whose `f64` volumes
        // overlap.
        let leaves = &self.leaf_volumes;
        let pair = |acc: &mut T, a: u32, b: u32| {
            if leaves[a as usize].overlaps(&leaves[b as usize]) {
                pair(acc, a, b);
            }
        };
        if self.marked && self.front_valid {
            self.front_pairs(par, make, pair, finish, consume, skip)
        } else if self.marked {
            let check = CertifiedNeighbours(&self.corners);
            self.bvh
                .par_self_pairs_until(ws, par, &check, make, pair, finish, consume, skip)
        } else {
            self.bvh
                .par_self_pairs_until(ws, par, &TestAll, make, pair, finish, consume, skip)
        }
    }
}

/// A task of the traversal from the front: neighbouring pairs, or pairs of the front.
enum FrontTask<'a> {
    Neighbours(&'a [[u32; 2]]),
    Front(&'a [(u32, u32)]),
}

impl<const H: usize> PerStepBvh<H> {
    /// [`TaskPairs::pairs`] from the front: the neighbouring triangle pairs that rule 6 keeps
    /// (those whose volumes overlap), then the traversal from the front, in fixed tasks.
    /// The same triangle pairs as the traversal from the root with [`CertifiedNeighbours`],
    /// but for neighbours in a certified star, which neither reports to the caller's filter.
    fn front_pairs<T: Send>(
        &self,
        par: &ParOptions,
        make: impl Fn(usize) -> T + Sync + Send,
        pair: impl Fn(&mut T, u32, u32) + Sync + Send,
        finish: impl Fn(&mut T) + Sync + Send,
        mut consume: impl FnMut(T) -> ControlFlow<()>,
        skip: &(dyn Fn(&T) -> bool + Sync),
    ) -> u64 {
        // Task 0, before the batches, as the traversal from the root's first task (the pairs
        // found while splitting): here empty, so that the batches are the same in both (an
        // Earliest query's first look stops after its first batch).
        let mut first = make(0);
        finish(&mut first);
        if consume(first).is_break() {
            return 0;
        }
        let tasks: Vec<FrontTask<'_>> = (self.neighbours.chunks(NEIGHBOUR_TASK))
            .map(FrontTask::Neighbours)
            .chain(self.front.pairs.chunks(FRONT_TASK).map(FrontTask::Front))
            .collect();
        let body = |stack: &mut Vec<(u32, u32)>, task: &FrontTask<'_>, acc: &mut T| match task {
            FrontTask::Neighbours(list) => {
                // `pair` tests the triangles' own volumes.
                for &[s, t] in *list {
                    pair(acc, s, t);
                }
                list.len() as u64
            }
            FrontTask::Front(front) => {
                self.bvh.front_pairs(front, stack, &mut |a, b| pair(acc, a, b))
            }
        };
        let make = |i| make(i + 1);
        run_batches(&tasks, par, Vec::new, body, (make, finish, skip), &mut consume)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip of `n` triangles along x, each vertex at `place(i)`, not moving in the step.
    fn strip(n: u32, place: impl Fn(u32) -> DVec3) -> Step<'static> {
        let x: Vec<[f64; 3]> = (0..n + 2).map(|i| place(i).to_array()).collect();
        let tris: Vec<[u32; 3]> = (0..n).map(|i| [i, i + 1, i + 2]).collect();
        Step::new(x.clone(), x, tris).expect("a valid step")
    }

    /// The same triangles again are refitted while the tree fits them (over any times swept),
    /// and rebuilt once the refitted tree would fit them much worse; after a cut the tree is
    /// refitted, after a step of other triangles rebuilt. Every tree holds its leaves.
    #[test]
    fn refits_only_while_the_tree_fits() {
        let along = |i: u32| DVec3::new(i as f64 * 0.5, (i % 2) as f64, 0.0);
        let mut tree = PerStepBvh::<9>::default();
        let mut ws = BvhWorkspace::default();
        let whole = (1.0, 0.0);
        tree.build(&strip(400, along), whole, true, &mut ws);
        assert!(!tree.refitted, "nothing to refit at first");
        // Shifted and slightly stretched: the same neighbours, refitted.
        let moved = |i: u32| along(i) * 1.01 + DVec3::new(3.0, 1.0, 0.0);
        let step = strip(400, moved);
        tree.build(&step, whole, true, &mut ws);
        assert!(tree.refitted);
        assert_eq!(tree.validate(&step), Ok(()));
        // The strip folded in two onto itself: leaves far apart in the tree overlap now, and
        // the refitted tree fits them loosely.
        let folded = |i: u32| {
            let x = (i as f64 * 0.5) % 100.0;
            DVec3::new(if i < 201 { x } else { 100.0 - x }, (i % 2) as f64, 0.0)
        };
        let step = strip(400, folded);
        tree.build(&step, whole, true, &mut ws);
        assert!(!tree.refitted, "a tree this loose is rebuilt");
        assert_eq!(tree.validate(&step), Ok(()));
        // Other times swept (an Earliest query's first look at the start of the step): the
        // same tree serves, refitted while it fits.
        tree.build(&step, (0.5, 0.0), true, &mut ws);
        assert!(tree.refitted, "other times swept");
        assert_eq!(tree.validate(&step), Ok(()));
        // Other triangles: a cut (a few triangles take copies of two vertices) is refitted,
        // its front updated; most triangles changed, or another count, is rebuilt.
        let x: Vec<[f64; 3]> = (0..402).chain([201, 202]).map(|i| folded(i).to_array()).collect();
        let mut tris: Vec<[u32; 3]> = (0..400).map(|i| [i, i + 1, i + 2]).collect();
        for t in &mut tris[201..204] {
            *t = t.map(|v| if v == 201 || v == 202 { v + 201 } else { v });
        }
        let cut = Step::new(x.clone(), x, tris).expect("a valid step");
        tree.build(&cut, (0.5, 0.0), false, &mut ws);
        assert!(tree.refitted, "a cut");
        assert_eq!(tree.validate(&cut), Ok(()));
        let corners = &tree.corners;
        let shares = |a: u32, b: u32| {
            let (x, y) = (&corners[a as usize].vertices, &corners[b as usize].vertices);
            x.iter().any(|v| y.contains(v))
        };
        let mut fresh = Front::default();
        tree.bvh.front(&shares, &mut fresh);
        assert!(tree.front_valid);
        assert_eq!(tree.front.pairs, fresh.pairs, "the updated front");
        let x: Vec<[f64; 3]> = (0..402).map(|i| folded(i).to_array()).collect();
        let flipped = (0..400).map(|i| [i, i + 2, i + 1]).collect::<Vec<_>>();
        let flipped = Step::new(x.clone(), x, flipped).expect("a valid step");
        tree.build(&flipped, (0.5, 0.0), false, &mut ws);
        assert!(!tree.refitted, "other triangles");
        assert_eq!(tree.validate(&flipped), Ok(()));
        tree.build(&strip(300, folded), (0.5, 0.0), false, &mut ws);
        assert!(!tree.refitted, "fewer triangles");
        assert_eq!(tree.validate(&strip(300, folded)), Ok(()));
    }
}
