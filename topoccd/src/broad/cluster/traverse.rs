//! The candidate pairs of [`Method::Cluster`](crate::Method::Cluster): the traversal of the
//! cluster hierarchy ([`tree`](super::tree)) down to triangle pairs, which go
//! through the same ownership scheme ([`features`](crate::mesh::features)) and the same narrow phase
//! as the other methods.
//!
//! # Traversal
//! 1. The top tree against itself: every overlapping pair of *distinct* intermediate clusters
//!    `{I, J}`. A cluster is never paired with itself, so no node pair inside one intermediate
//!    cluster is ever tested.
//! 2. For each `{I, J}`: the overlapping pairs of a leaf cluster of `I` and one of `J` (the two
//!    sub-trees against each other; a single-leaf cluster's volume against the other's
//!    sub-tree; nothing more when both have one leaf, their volumes were just tested).
//! 3. For each such leaf pair `{a, b}`: the overlapping triangle pairs, from the two leaf
//!    clusters' triangle hierarchies, built (in parallel, each once per step) for the leaf
//!    clusters that some leaf pair needs. A leaf cluster of at most [`DIRECT`] triangles gets
//!    no hierarchy: its triangles' volumes are tested directly against the other leaf's
//!    triangles or tree.
//! 4. A leaf cluster without a certificate would be tested against itself, and the leaf pairs
//!    inside its intermediate cluster too (the clustering of this crate certifies every leaf,
//!    so this never runs, but it is not assumed).
//!
//! Steps 1, 2 and 4 list the leaf pairs (and uncertified leaves) sequentially; step 3 runs them
//! as parallel tasks of consecutive items, fixed by the number of items alone
//! ([`TrianglePairs`]), each task's triangle pairs going to the query's narrow phase on the
//! task's thread, the tasks' results handed over in task order: the same candidates and the
//! same report for any thread count.
//!
//! # Soundness: a skipped pair never touches
//! *Which pairs are skipped.* By the ownership scheme a vertex-face pair `(v, f)` is a
//! candidate only from the triangle pair `{owner(v), f}`, and an edge-edge pair `{e, e'}` only
//! from `{owner(e), owner(e')}`. The traversal visits every triangle pair `{A, B}` whose swept
//! k-DOPs overlap, except the pairs inside one certified intermediate cluster: if `A` is in leaf
//! `a` of intermediate cluster `I` and `B` in leaf `b` of `J != I`, the volume of `A` lies in
//! that of `a`, which lies in that of `I` (unions, computed exactly by min and max), and
//! likewise for `B`; so `I` and `J` overlap and step 1 reports them, `a` and `b` overlap and
//! step 2 reports them, `A` and `B` overlap and step 3 reports them. So a feature pair is
//! skipped, compared with [`Method::Bvh`](crate::Method::Bvh), only if `owner(v)` and `f` (or
//! `owner(e)` and `owner(e')`) lie in one certified intermediate cluster.
//!
//! *Why that is safe.* Then `v` is a vertex of the triangle `owner(v)`, so a feature of the
//! intermediate cluster, as is the face `f`; and the two share no vertex (pairs that do are
//! never candidates). The clustering's theorem ([`cluster`](super)): no two features of
//! one intermediate cluster that share no vertex touch at any time in `[0, 1]`, which contains
//! the searched `[0, t_max]`. The same holds for two edges. With a minimum separation `> 0` the
//! theorem says nothing about distances, and the clustering then makes every leaf a single
//! triangle and every intermediate cluster a single leaf: all of its features share a vertex, so
//! nothing is skipped that the other methods would test.
//!
//! *Each pair at most once.* Step 1 reports each pair of intermediate clusters once, step 2
//! each leaf pair of two given intermediate clusters once, step 3 each triangle pair of two
//! given leaves once, so each triangle pair is visited at most once, and by the ownership
//! scheme each feature pair is a candidate at most once.
//!
//! The narrow phase is conservative: near a contact it may report a pair that comes within its
//! tolerance without touching. Such a pair inside one intermediate cluster is provably not
//! touching and is not tested here, so the cluster method can only ever report fewer of these
//! false positives than the oracle, never miss a contact.

//! # Measured (2 shared, heavily loaded cores; `topoccd step --json`, methods alternated)
//! Table 2's figures, certificate growth (the default) / the paper's growth:
//!
//! | step | triangles | leaf clusters | intermediate | triangles per leaf | lazy BVHs |
//! |------|-----------|---------------|--------------|--------------------|-----------|
//! | cloth-funnel | 18 484 | 2 593 / 17 887 | 1 440 / 11 131 | 7.1 / 1.03 | 769 / 41 |
//! | cloth-ball | 92 230 | 24 996 / 85 499 | 15 510 / 56 339 | 3.7 / 1.08 | 3 142 / 491 |
//! | torn sheet 200 (50 strips) | 79 202 | 50 / 56 482 | 50 / 35 454 | 1 584 / 1.4 | 50 / 269 |
//!
//! The paper's `phi` test fails around almost every seed of curved cloth (the observation point
//! lies on the surface, so any hollow or saddle faces it), while the certificate alone keeps
//! whole strips of the torn sheet in one leaf; the certificate growth is the default because it
//! is faster and equally sound. Candidate pairs (vertex-face + edge-edge), BVH / cluster:
//! cloth-funnel 22 276 / 16 203, cloth-ball 5.04 M / 4.59 M, torn sheet 2.47 M / 0.37 M. The
//! cluster method's own phases (clustering + merging + build + traversal) beat the BVH
//! method's build + traversal on the torn sheet but not yet on the cloth steps, whose leaves
//! are mostly single triangles (median 1): there the two-level traversal visits 1.35 M leaf
//! pairs on cloth-ball, and the clustering itself (about 0.1 s + 0.1 s) is not repaid.

use std::time::Instant;

use rayon::prelude::*;

use super::tree::{ClusterTree, NONE};
use super::{Clustering, LeafCertificate};
use crate::broad::TaskPairs;
use crate::bvh::{BvhWorkspace, ParOptions};

/// Leaf clusters of at most this many triangles get no lazy hierarchy: their triangles'
/// volumes are tested directly against the other leaf cluster's triangles (or its hierarchy).
pub(crate) const DIRECT: usize = 4;

/// The triangle pairs of step 3 (and 4) run as parallel tasks of consecutive work items (leaf
/// pairs), at least this many items a task, and about this many tasks at most: the tasks
/// depend on the number of items alone, never on the thread count.
const TASK_ITEMS: usize = 8;
const MAX_TASKS: usize = 1024;

/// Whether a leaf cluster's certificate proves it free of self-contact. Written as an
/// exhaustive match so that a new kind of certificate must be classified here.
fn certified(certificate: LeafCertificate) -> bool {
    match certificate {
        LeafCertificate::SingleTriangle | LeafCertificate::Disk => true,
    }
}

/// Scratch memory of the traversal, reused across steps.
#[derive(Clone, Debug, Default)]
pub(crate) struct PairScratch {
    /// Overlapping pairs of intermediate clusters.
    ic_pairs: Vec<(u32, u32)>,
    /// The work items of step 3: overlapping pairs `(a, b)`, `a != b`, of leaf clusters to
    /// test, and `(l, l)` for a leaf cluster without certificate, tested against itself
    /// (step 4).
    items: Vec<(u32, u32)>,
    /// Whether each intermediate cluster is certified (all its leaves are).
    ic_certified: Vec<bool>,
    /// Leaf clusters that need a lazy hierarchy, increasing.
    needed: Vec<u32>,
    /// Per leaf cluster: whether it is in `needed`.
    marked: Vec<bool>,
}

/// What the traversal did.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Counts {
    /// Bounding-volume overlap tests, at every level.
    pub bv_tests: u64,
    /// Lazy hierarchies built.
    pub lazy_bvhs: usize,
    /// Leaf pairs whose triangles were tested.
    pub leaf_pairs: u64,
    /// Leaf clusters tested for self-contact because they carry no certificate.
    pub uncertified_leaves: usize,
    /// Time spent building the lazy hierarchies, in seconds.
    pub lazy_seconds: f64,
}

/// What the traversal needs besides the hierarchy.
pub(crate) struct Inputs<'a> {
    /// The step's clustering.
    pub clustering: &'a Clustering,
    /// `false` treats every leaf cluster as uncertified (every pair is then tested: a check
    /// of the traversal itself, used by the tests).
    pub trust: bool,
}

/// Steps 1, 2 and 4 of the traversal (see the module documentation) down to the work items of
/// step 3, into `scratch`, and the lazy hierarchies these need, built in parallel. `tree` must
/// have been built for this step and clustering. Returns the counts so far (with the
/// bounding-volume tests of steps 1 and 2).
pub(crate) fn prepare<const H: usize>(
    tree: &mut ClusterTree<H>,
    input: &Inputs<'_>,
    scratch: &mut PairScratch,
    ws: &mut BvhWorkspace,
) -> Counts {
    let c = input.clustering;
    let mut counts = Counts::default();

    // Certificates: an intermediate cluster is certified when all its leaves are.
    scratch.ic_certified.clear();
    scratch
        .ic_certified
        .extend((0..c.intermediates.len()).map(|i| {
            input.trust
                && c.intermediate_leaves(i)
                    .iter()
                    .all(|&l| certified(c.leaves[l as usize].certificate))
        }));

    // Steps 1 and 2: leaf pairs of distinct intermediate clusters.
    scratch.ic_pairs.clear();
    let ic_pairs = &mut scratch.ic_pairs;
    counts.bv_tests += tree
        .top
        .self_pairs(ws, |i, j| ic_pairs.push((i.min(j), i.max(j))));
    scratch.items.clear();
    let items = &mut scratch.items;
    for &(i, j) in &scratch.ic_pairs {
        let (si, sj) = (tree.sub_of_ic[i as usize], tree.sub_of_ic[j as usize]);
        let (li, lj) = (
            c.intermediate_leaves(i as usize),
            c.intermediate_leaves(j as usize),
        );
        counts.bv_tests += match (si == NONE, sj == NONE) {
            (true, true) => {
                items.push((li[0], lj[0]));
                0
            }
            (true, false) => {
                let v = &tree.leaf[li[0] as usize].volume;
                tree.sub(j).volume_leaves(v, ws, |b| items.push((li[0], b)))
            }
            (false, true) => {
                let v = &tree.leaf[lj[0] as usize].volume;
                tree.sub(i).volume_leaves(v, ws, |a| items.push((a, lj[0])))
            }
            (false, false) => tree
                .sub(i)
                .tree_pairs(tree.sub(j), ws, |a, b| items.push((a, b))),
        };
    }
    // Step 4: leaf pairs inside an intermediate cluster without certificate.
    for (i, &ok) in scratch.ic_certified.iter().enumerate() {
        if !ok && tree.sub_of_ic[i] != NONE {
            counts.bv_tests += tree
                .sub(i as u32)
                .self_pairs(ws, |a, b| items.push((a, b)));
        }
    }
    counts.leaf_pairs = items.len() as u64;
    // Step 4: leaf clusters without certificate, against themselves.
    for (l, leaf) in c.leaves.iter().enumerate() {
        if (input.trust && certified(leaf.certificate)) || leaf.triangles.len() < 2 {
            continue;
        }
        counts.uncertified_leaves += 1;
        items.push((l as u32, l as u32));
    }

    // The lazy hierarchies: every leaf cluster of more than `DIRECT` triangles in an item.
    let t = Instant::now();
    scratch.marked.clear();
    scratch.marked.resize(c.leaves.len(), false);
    for &(a, b) in items.iter() {
        for l in [a, b] {
            if c.leaves[l as usize].triangles.len() > DIRECT {
                scratch.marked[l as usize] = true;
            }
        }
    }
    scratch.needed.clear();
    scratch.needed.extend(
        (0..c.leaves.len() as u32).filter(|&l| scratch.marked[l as usize]),
    );
    tree.build_lazies(c, &scratch.needed);
    counts.lazy_bvhs = scratch.needed.len();
    counts.lazy_seconds = t.elapsed().as_secs_f64();
    counts
}

/// The triangle pairs of the work items prepared by [`prepare`], as a source of parallel
/// tasks ([`TaskPairs`]).
pub(crate) struct TrianglePairs<'a, const H: usize> {
    pub tree: &'a ClusterTree<H>,
    pub clustering: &'a Clustering,
    pub scratch: &'a PairScratch,
}

impl<const H: usize> TrianglePairs<'_, H> {
    /// Step 3 (and 4) for one work item: every overlapping pair of triangles to `emit`.
    /// Returns the bounding-volume tests.
    fn item(&self, (a, b): (u32, u32), ws: &mut BvhWorkspace, emit: &mut impl FnMut(u32, u32)) -> u64 {
        let (tree, c) = (self.tree, self.clustering);
        let mut tests = 0;
        if a == b {
            let tris = c.leaf_triangles(a as usize);
            if tris.len() <= DIRECT {
                for (k, &x) in tris.iter().enumerate() {
                    for &y in &tris[k + 1..] {
                        tests += 1;
                        if tree.tri[x as usize].overlaps(&tree.tri[y as usize]) {
                            emit(x, y);
                        }
                    }
                }
            } else {
                tests += tree.lazy(a).self_pairs(ws, emit);
            }
            return tests;
        }
        let (mut a, mut b) = (a, b);
        let (mut ta, mut tb) = (c.leaf_triangles(a as usize), c.leaf_triangles(b as usize));
        if ta.len() > tb.len() {
            (a, b, ta, tb) = (b, a, tb, ta);
        }
        if ta.len() <= DIRECT {
            if tb.len() <= DIRECT {
                for &x in ta {
                    let vx = &tree.tri[x as usize];
                    for &y in tb {
                        tests += 1;
                        if vx.overlaps(&tree.tri[y as usize]) {
                            emit(x, y);
                        }
                    }
                }
            } else {
                let lazy = tree.lazy(b);
                for &x in ta {
                    let vx = &tree.tri[x as usize];
                    tests += lazy.volume_leaves(vx, ws, |y| emit(x, y));
                }
            }
        } else {
            tests += tree.lazy(a).tree_pairs(tree.lazy(b), ws, &mut *emit);
        }
        tests
    }
}

impl<const H: usize> TaskPairs for TrianglePairs<'_, H> {
    /// Runs the work items as tasks of consecutive items (their number depends on the items
    /// alone), batch by batch on the rayon pool, each task's accumulator finished on its
    /// thread and handed to `consume` in task order.
    fn pairs<T: Send>(
        &self,
        _ws: &mut BvhWorkspace,
        par: &ParOptions,
        make: impl Fn() -> T + Sync + Send,
        pair: impl Fn(&mut T, u32, u32) + Sync + Send,
        finish: impl Fn(&mut T) + Sync + Send,
        mut consume: impl FnMut(T),
    ) -> u64 {
        let items = &self.scratch.items[..];
        let per_task = items.len().div_ceil(MAX_TASKS).max(TASK_ITEMS);
        let tasks: Vec<&[(u32, u32)]> = items.chunks(per_task).collect();
        let mut bv_tests = 0;
        for batch in tasks.chunks(par.batch.max(1)) {
            let done: Vec<(T, u64)> = batch
                .par_iter()
                .map_init(BvhWorkspace::default, |ws, task| {
                    let mut acc = make();
                    let mut tests = 0;
                    for &item in task.iter() {
                        tests += self.item(item, ws, &mut |x, y| pair(&mut acc, x, y));
                    }
                    finish(&mut acc);
                    (acc, tests)
                })
                .collect();
            for (acc, tests) in done {
                consume(acc);
                bv_tests += tests;
            }
        }
        bv_tests
    }
}
