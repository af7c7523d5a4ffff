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
//! Steps 1, 2 and 4 list the leaf pairs (and uncertified leaves) sequentially, a chunk of
//! [`CHUNK_ITEMS`] at a time; the leaf pairs whose smaller leaf has [`SPLIT_TRIANGLES`]
//! triangles or more are split into pairs of nodes of their two lazy hierarchies (one big
//! touching pair can hold much of a step's work); step 3 runs the chunk's units as parallel
//! tasks of consecutive units of about equal estimated cost ([`TrianglePairs`]), each task's
//! triangle pairs going to the query's narrow phase on the task's thread, the tasks' results
//! handed over in task order. Then the listing resumes where it paused, unless the query
//! stopped: a capped query whose report is full lists no more, so its lists stay bounded
//! where every pair of clusters overlaps. The chunks, the split and the tasks depend on the
//! clustering alone: the same candidates and the same report for any thread count.
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
//! the searched `[0, tmax]`. The same holds for two edges. With a minimum separation `> 0` the
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

use std::sync::{Mutex, PoisonError};

use super::tree::{ClusterTree, NONE};
use super::{Clustering, LeafCertificate};
use crate::broad::{Stopper, TaskPairs};
use crate::bvh::{run_batches, BvhWorkspace, Node, ParOptions};

/// Leaf clusters of at most this many triangles get no lazy hierarchy: their triangles'
/// volumes are tested directly against the other leaf cluster's triangles (or its hierarchy).
pub(crate) const DIRECT: usize = 4;

/// The triangle pairs of step 3 (and 4) run as parallel tasks of consecutive work items
/// (leaf pairs) of about equal estimated cost ([`item_cost`]): about `MAX_TASKS` tasks, each
/// of cost at least `MIN_TASK_COST` unless it is the last. The tasks depend on the items
/// alone, never on the thread count.
const MAX_TASKS: u64 = 512;
const MIN_TASK_COST: u64 = 16;

/// A leaf pair whose smaller leaf cluster has at least this many triangles is split into
/// pairs of nodes of the two lazy hierarchies, descended breadth-first until there are at
/// least `SPLIT_PAIRS` of them (or only leaf pairs are left): one big leaf pair can hold much
/// of a step's work (many candidates where two big leaves touch).
const SPLIT_TRIANGLES: usize = 256;
const SPLIT_PAIRS: usize = 32;

/// One unit of work of step 3: leaf clusters `a` and `b` (`a == b`: an uncertified leaf
/// against itself), whole when `na` is [`NONE`], else the overlapping pair of nodes `na` of
/// `a`'s lazy hierarchy and `nb` of `b`'s.
#[derive(Clone, Copy, Debug)]
struct Work {
    a: u32,
    b: u32,
    na: u32,
    nb: u32,
}

/// Whether a leaf cluster's certificate proves it free of self-contact. Written as an
/// exhaustive match so that a new kind of certificate must be classified here.
fn certified(certificate: LeafCertificate) -> bool {
    match certificate {
        LeafCertificate::SingleTriangle | LeafCertificate::Disk => true,
    }
}

/// Leaf pairs (work items of step 3) listed at most, give or take one pair of intermediate
/// clusters' worth, before the narrow phase takes them: steps 1 and 2 list a chunk of this
/// many, step 3 runs its tasks, and the listing resumes where it paused only if the query has
/// not stopped (its cap reached, a deadline). So the lists stay near 40 bytes times this many
/// (20 MiB) even where every pair of triangles touches (a collapsed step: `n^2 / 2` leaf
/// pairs). Cloth-funnel's step has far fewer leaf pairs and runs as one chunk; cloth-ball's
/// 1.35 million run as three. The chunks depend on the clustering alone, never on the
/// thread count.
pub(crate) const CHUNK_ITEMS: usize = 1 << 19;

/// Scratch memory of the traversal, reused across steps.
#[derive(Clone, Debug, Default)]
pub(crate) struct PairScratch {
    /// The paused traversal of the top tree against itself (step 1).
    top: Vec<(u32, u32)>,
    /// Overlapping pairs of intermediate clusters, of the chunk being listed.
    ic_pairs: Vec<(u32, u32)>,
    /// The work items of step 3 in the chunk: overlapping pairs `(a, b)`, `a != b`, of leaf
    /// clusters to test, and `(l, l)` for a leaf cluster without certificate, tested against
    /// itself (step 4).
    items: Vec<(u32, u32)>,
    /// Whether step 4's items were listed (after the last pair of intermediate clusters).
    tail_listed: bool,
    /// Whether the listing stopped, and why.
    lister: Lister,
    /// Whether each intermediate cluster is certified (all its leaves are).
    ic_certified: Vec<bool>,
    /// The work of step 3 in the chunk: the items, big leaf pairs split into node pairs.
    work: Vec<Work>,
    /// The estimated cost of each unit of `work`.
    work_cost: Vec<u64>,
    /// Ends of the chunk's tasks in `work`, increasing (the last is `work.len()`).
    task_ends: Vec<usize>,
    /// Scratch: node pairs of the split.
    pending: Vec<(u32, u32)>,
    next: Vec<(u32, u32)>,
    /// Leaf clusters that need a lazy hierarchy, first needed in the chunk, increasing.
    needed: Vec<u32>,
    /// Per leaf cluster: whether it has a lazy hierarchy this step (or needs none).
    marked: Vec<bool>,
}

/// The state of the pair lists' growth: how many pairs were listed, and whether the query
/// stopped or a list could not grow (then nothing more is listed).
#[derive(Clone, Copy, Debug, Default)]
struct Lister {
    listed: u64,
    halted: bool,
    failed: bool,
}

impl Lister {
    /// Whether to list the next pair: not once the query stopped (asked every 2^16 pairs) or
    /// a list failed to grow.
    #[inline]
    fn go_on(&mut self, stop: Option<&Stopper>) -> bool {
        self.listed += 1;
        if !self.halted && self.listed.is_multiple_of(1 << 16) {
            self.halted = stop.is_some_and(|s| s.stopped());
        }
        !self.halted && !self.failed
    }

    /// Pushes `p` on `v`, fallibly: a failure is recorded on the query's stop (without one, it
    /// aborts, as an infallible push does), and nothing more is listed.
    #[inline]
    fn push(&mut self, stop: Option<&Stopper>, v: &mut Vec<(u32, u32)>, p: (u32, u32)) {
        if self.failed {
            return;
        }
        if let Err(e) = crate::alloc::try_push(v, p, "cluster pairs") {
            self.fail(stop, e);
        }
    }

    #[cold]
    fn fail(&mut self, stop: Option<&Stopper>, e: crate::alloc::AllocError) {
        if self.failed {
            return;
        }
        self.failed = true;
        match stop {
            Some(s) => s.fail(e),
            None => Stopper(std::sync::Arc::new(|| true), None).fail(e),
        }
    }

    /// Whether the listing ended early.
    fn stopped(&self) -> bool {
        self.halted || self.failed
    }
}

/// What the traversal did.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Counts {
    /// Bounding-volume overlap tests, at every level.
    pub bv_tests: u64,
    /// Lazy hierarchies built.
    pub lazy_bvhs: usize,
    /// Of those, how many had been built ahead, while the clustering grew.
    pub lazy_ahead: usize,
    /// Leaf pairs whose triangles were tested.
    pub leaf_pairs: u64,
    /// Leaf clusters tested for self-contact because they carry no certificate.
    pub uncertified_leaves: usize,
    /// Time spent building the lazy hierarchies, in seconds.
    pub lazy_seconds: f64,
    /// Chunks of work items listed ([`CHUNK_ITEMS`]).
    pub chunks: usize,
}

/// What the traversal needs besides the hierarchy.
pub(crate) struct Inputs<'a> {
    /// The step's clustering.
    pub clustering: &'a Clustering,
    /// `false` treats every leaf cluster as uncertified (every pair is then tested: a check
    /// of the traversal itself, used by the tests).
    pub trust: bool,
    /// The query's stop: once it says stop, no more leaf pairs are listed (a collapsed step
    /// has one per pair of triangles).
    pub stop: Option<&'a Stopper>,
    /// Work items per chunk, `>= 1` ([`CHUNK_ITEMS`] but in tests).
    pub chunk: usize,
}

/// Starts the traversal of a step: the certificates of the intermediate clusters, the top
/// tree's self-traversal (step 1) paused before its first pair. `tree` must have been built
/// for this step and clustering.
pub(crate) fn begin<const H: usize>(
    tree: &ClusterTree<H>,
    input: &Inputs<'_>,
    scratch: &mut PairScratch,
) {
    let c = input.clustering;
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
    tree.top.self_pairs_start(&mut scratch.top);
    scratch.tail_listed = false;
    scratch.lister = Lister::default();
    scratch.marked.clear();
    scratch.marked.resize(c.leaves.len(), false);
}

/// Lists the next chunk of work items (steps 1, 2 and 4 of the traversal, see the module
/// documentation, from where [`begin`] or the last chunk paused), builds the lazy
/// hierarchies they need that are not built yet, in parallel, and splits them into units of
/// work and tasks ([`PairScratch::task_ends`]). Adds what it did to `counts`. Returns whether
/// items are left for another chunk.
pub(crate) fn next_chunk<const H: usize>(
    tree: &mut ClusterTree<H>,
    input: &Inputs<'_>,
    scratch: &mut PairScratch,
    ws: &mut BvhWorkspace,
    counts: &mut Counts,
) -> bool {
    let c = input.clustering;
    let stop = input.stop;
    let chunk = input.chunk.max(1);
    counts.chunks += 1;
    let PairScratch {
        top,
        ic_pairs,
        items,
        lister,
        ..
    } = scratch;
    items.clear();
    // Steps 1 and 2: leaf pairs of distinct intermediate clusters, a piece of the top tree's
    // traversal at a time (an overlapping pair of intermediate clusters gives at least one leaf
    // pair when either has a single leaf), until the chunk is full.
    while !top.is_empty() && items.len() < chunk && !lister.stopped() {
        ic_pairs.clear();
        let want = chunk - items.len();
        counts.bv_tests += tree.top.self_pairs_resume(top, want, |i, j| {
            if lister.go_on(stop) {
                lister.push(stop, ic_pairs, (i.min(j), i.max(j)));
            }
        });
        for &(i, j) in ic_pairs.iter() {
            if !lister.go_on(stop) {
                break;
            }
            let (si, sj) = (tree.sub_of_ic[i as usize], tree.sub_of_ic[j as usize]);
            let (li, lj) = (
                c.intermediate_leaves(i as usize),
                c.intermediate_leaves(j as usize),
            );
            counts.bv_tests += match (si == NONE, sj == NONE) {
                (true, true) => {
                    lister.push(stop, items, (li[0], lj[0]));
                    0
                }
                (true, false) => {
                    let v = &tree.leaf[li[0] as usize].volume;
                    (tree.sub(j)).volume_leaves(v, ws, |b| lister.push(stop, items, (li[0], b)))
                }
                (false, true) => {
                    let v = &tree.leaf[lj[0] as usize].volume;
                    (tree.sub(i)).volume_leaves(v, ws, |a| lister.push(stop, items, (a, lj[0])))
                }
                (false, false) => tree
                    .sub(i)
                    .tree_pairs(tree.sub(j), ws, |a, b| lister.push(stop, items, (a, b))),
            };
        }
    }
    let last = top.is_empty() || lister.stopped();
    if last && !scratch.tail_listed {
        scratch.tail_listed = true;
        // Step 4: leaf pairs inside an intermediate cluster without certificate.
        for (i, &ok) in scratch.ic_certified.iter().enumerate() {
            if !ok && tree.sub_of_ic[i] != NONE {
                counts.bv_tests += tree
                    .sub(i as u32)
                    .self_pairs(ws, |a, b| lister.push(stop, items, (a, b)));
            }
        }
        counts.leaf_pairs += items.len() as u64;
        // Step 4: leaf clusters without certificate, against themselves.
        for (l, leaf) in c.leaves.iter().enumerate() {
            if (input.trust && certified(leaf.certificate)) || leaf.triangles.len() < 2 {
                continue;
            }
            counts.uncertified_leaves += 1;
            lister.push(stop, items, (l as u32, l as u32));
        }
    } else {
        counts.leaf_pairs += items.len() as u64;
    }
    // Room for a unit of work per item (big items split into a few more).
    let n = items.len();
    let grown = crate::alloc::grow(&mut scratch.work, n, "cluster work")
        .and_then(|()| crate::alloc::grow(&mut scratch.work_cost, n, "cluster work"));
    if let Err(e) = grown {
        lister.fail(stop, e);
    }
    if lister.failed {
        // The query winds down: no work.
        items.clear();
    }

    // The lazy hierarchies: every leaf cluster of more than `DIRECT` triangles in an item,
    // unless an earlier chunk built it.
    let t = Instant::now();
    scratch.needed.clear();
    for &(a, b) in items.iter() {
        for l in [a, b] {
            if !scratch.marked[l as usize] && c.leaves[l as usize].triangles.len() > DIRECT {
                scratch.marked[l as usize] = true;
                scratch.needed.push(l);
            }
        }
    }
    scratch.needed.sort_unstable();
    counts.lazy_ahead += tree.build_lazies(c, &scratch.needed);
    counts.lazy_bvhs += scratch.needed.len();
    counts.lazy_seconds += t.elapsed().as_secs_f64();

    // The work: big leaf pairs split into node pairs.
    scratch.work.clear();
    scratch.work_cost.clear();
    for &(a, b) in scratch.items.iter() {
        let cost = item_cost(c, a, b);
        let (na, nb) = (
            c.leaves[a as usize].triangles.len(),
            c.leaves[b as usize].triangles.len(),
        );
        if a == b || na.min(nb) < SPLIT_TRIANGLES {
            scratch.work.push(Work { a, b, na: NONE, nb: NONE });
            scratch.work_cost.push(cost);
            continue;
        }
        let (xa, xb) = (tree.lazy(a).nodes(), tree.lazy(b).nodes());
        counts.bv_tests += 1;
        if !xa[0].volume.overlaps(&xb[0].volume) {
            continue;
        }
        let (pending, next) = (&mut scratch.pending, &mut scratch.next);
        pending.clear();
        pending.push((0, 0));
        while pending.len() < SPLIT_PAIRS {
            next.clear();
            let mut descended = false;
            for &(x, y) in pending.iter() {
                let (kx, ky) = (xa[x as usize].children(), xb[y as usize].children());
                if kx.is_none() && ky.is_none() {
                    next.push((x, y));
                    continue;
                }
                descended = true;
                for i in kx.unwrap_or([x, NONE]).into_iter().filter(|&i| i != NONE) {
                    for j in ky.unwrap_or([y, NONE]).into_iter().filter(|&j| j != NONE) {
                        counts.bv_tests += 1;
                        if xa[i as usize].volume.overlaps(&xb[j as usize].volume) {
                            next.push((i, j));
                        }
                    }
                }
            }
            std::mem::swap(pending, next);
            if !descended {
                break;
            }
        }
        let share = cost / pending.len().max(1) as u64 + 1;
        for &(x, y) in pending.iter() {
            scratch.work.push(Work { a, b, na: x, nb: y });
            scratch.work_cost.push(share);
        }
    }

    // The tasks: consecutive units of work of about equal cost.
    let total: u64 = scratch.work_cost.iter().sum();
    let target = total.div_ceil(MAX_TASKS).max(MIN_TASK_COST);
    scratch.task_ends.clear();
    let mut acc = 0;
    for (k, &cost) in scratch.work_cost.iter().enumerate() {
        acc += cost;
        if acc >= target {
            scratch.task_ends.push(k + 1);
            acc = 0;
        }
    }
    if scratch.task_ends.last() != Some(&scratch.work.len()) && !scratch.work.is_empty() {
        scratch.task_ends.push(scratch.work.len());
    }
    !last
}

/// A rough estimate of the work of item `(a, b)` (the traversal and the narrow phase of its
/// triangle pairs), in arbitrary units: for the task split only.
fn item_cost(c: &Clustering, a: u32, b: u32) -> u64 {
    let (na, nb) = (
        c.leaves[a as usize].triangles.len() as u64,
        c.leaves[b as usize].triangles.len() as u64,
    );
    if a == b {
        4 + na
    } else {
        4 + na.min(nb)
    }
}

/// The traversal of one step after [`begin`]: the hierarchy, the pair lists and what they
/// did, behind the lock of [`TrianglePairs`].
struct Traversal<'a, const H: usize> {
    tree: &'a mut ClusterTree<H>,
    input: &'a Inputs<'a>,
    scratch: &'a mut PairScratch,
    counts: Counts,
}

/// The triangle pairs of the traversal started by [`begin`], chunk by chunk
/// ([`next_chunk`]), as a source of parallel tasks ([`TaskPairs`]). The lock is taken once,
/// by the one call of [`TaskPairs::pairs`]; the tasks read the chunk through it.
pub(crate) struct TrianglePairs<'a, const H: usize>(Mutex<Traversal<'a, H>>);

impl<'a, const H: usize> TrianglePairs<'a, H> {
    /// The source of the traversal [`begin`] started on `tree` with `input` and `scratch`.
    pub fn new(
        tree: &'a mut ClusterTree<H>,
        input: &'a Inputs<'a>,
        scratch: &'a mut PairScratch,
    ) -> Self {
        Self(Mutex::new(Traversal {
            tree,
            input,
            scratch,
            counts: Counts::default(),
        }))
    }

    /// What the traversal did.
    pub fn counts(self) -> Counts {
        self.0.into_inner().unwrap_or_else(PoisonError::into_inner).counts
    }
}

impl<const H: usize> Traversal<'_, H> {
    /// Step 3 (and 4) for one work item: every overlapping pair of triangles to `emit`.
    /// Returns the bounding-volume tests.
    fn work(
        &self,
        w: &Work,
        (ws, stack): &mut (BvhWorkspace, Vec<(u32, u32)>),
        emit: &mut impl FnMut(u32, u32),
    ) -> u64 {
        let (tree, c) = (&*self.tree, self.input.clustering);
        let (a, b) = (w.a, w.b);
        if w.na != NONE {
            let (xa, xb) = (tree.lazy(a).nodes(), tree.lazy(b).nodes());
            return node_pairs(xa, xb, (w.na, w.nb), stack, emit);
        }
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
    /// Lists the work items chunk by chunk ([`next_chunk`]) and runs each chunk's items as
    /// tasks of consecutive items (their number depends on the items alone), batch by batch
    /// on the rayon pool, each task's accumulator finished on its thread and handed to
    /// `consume` in task order, the tasks numbered across chunks. Once `consume` breaks (the
    /// report is full, the query stopped), no other chunk is listed.
    fn pairs<T: Send>(
        &self,
        ws: &mut BvhWorkspace,
        par: &ParOptions,
        make: impl Fn(usize) -> T + Sync + Send,
        pair: impl Fn(&mut T, u32, u32) + Sync + Send,
        finish: impl Fn(&mut T) + Sync + Send,
        mut consume: impl FnMut(T) -> std::ops::ControlFlow<()>,
        skip: &(dyn Fn(&T) -> bool + Sync),
    ) -> u64 {
        let mut guard = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        let t = &mut *guard;
        let (mut tests, mut first) = (0, 0);
        loop {
            let more = next_chunk(t.tree, t.input, t.scratch, ws, &mut t.counts);
            let view = &*t;
            let work = &view.scratch.work[..];
            let mut start = 0;
            let tasks: Vec<&[Work]> = (view.scratch.task_ends.iter())
                .map(|&end| {
                    let task = &work[start..end];
                    start = end;
                    task
                })
                .collect();
            let body = |ws: &mut _, task: &&[Work], acc: &mut T| {
                let mut tests = 0;
                for work in task.iter() {
                    tests += view.work(work, ws, &mut |x, y| pair(acc, x, y));
                }
                tests
            };
            let numbered = |i| make(first + i);
            let mut ended = false;
            let mut handed = |acc| {
                let flow = consume(acc);
                ended |= flow.is_break();
                flow
            };
            let f = (numbered, &finish, skip);
            tests += run_batches(&tasks, par, Default::default, body, f, &mut handed);
            first += tasks.len();
            if ended || !more {
                break;
            }
        }
        tests
    }
}

/// Every overlapping pair of leaves under the overlapping nodes `start` of the tree `xa` and
/// of the tree `xb` (leaf ids: triangles) to `emit`, each once. Returns the overlap tests.
fn node_pairs<V: crate::bvh::BoundingVolume>(
    xa: &[Node<V>],
    xb: &[Node<V>],
    start: (u32, u32),
    stack: &mut Vec<(u32, u32)>,
    emit: &mut impl FnMut(u32, u32),
) -> u64 {
    let mut tests = 0;
    stack.clear();
    stack.push(start);
    while let Some((x, y)) = stack.pop() {
        let (nx, ny) = (&xa[x as usize], &xb[y as usize]);
        let (kx, ky) = (nx.children(), ny.children());
        if let (Some(i), Some(j)) = (nx.leaf(), ny.leaf()) {
            emit(i, j);
            continue;
        }
        for i in kx.unwrap_or([x, NONE]).into_iter().filter(|&i| i != NONE) {
            for j in ky.unwrap_or([y, NONE]).into_iter().filter(|&j| j != NONE) {
                tests += 1;
                if xa[i as usize].volume.overlaps(&xb[j as usize].volume) {
                    stack.push((i, j));
                }
            }
        }
    }
    tests
}
