//! The cluster method as one broad phase: cluster the step, build the hierarchy over the
//! clusters, traverse it down to candidate pairs.

use std::time::Instant;

use super::traverse::{self, Inputs, PairScratch, TrianglePairs};
use super::tree::ClusterTree;
use super::{cluster_into_beside, ClusterOptions, ClusterWorkspace, Clustering};
use std::sync::Arc;

use crate::broad::tasks::{Out, Passes, Runner};
use crate::broad::{BroadInput, BroadPhase, BroadStats, PairRunner, Stopper};
use crate::contact::ClusterGrowth;
use crate::bvh::{BvhError, BvhWorkspace};
use crate::kdop::DopKind;

/// The figures of the paper's table 2 and the lazy hierarchies of
/// [`Method::Cluster`](crate::Method::Cluster), as reported in
/// [`Stats::cluster`](crate::Stats::cluster).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ClusterFigures {
    /// Number of leaf clusters.
    pub leaf: usize,
    /// Number of intermediate clusters.
    pub intermediate: usize,
    /// Average triangles per leaf cluster (table 2's ratio).
    pub triangles_per_leaf: f64,
    /// Average triangles per intermediate cluster.
    pub triangles_per_intermediate: f64,
    /// Hierarchies built over a leaf cluster's triangles, each at most once per step, only for
    /// leaf clusters whose volume overlaps another's.
    pub lazy_bvhs: usize,
    /// Overlapping pairs of leaf clusters in different intermediate clusters (and leaf pairs
    /// inside an intermediate cluster without certificate, if any).
    pub leaf_pairs: u64,
    /// Leaf clusters tested for self-contact because they carry no certificate (always `0`
    /// with the clustering of this crate, whose leaves are all certified).
    pub uncertified_leaves: usize,
    /// Leaf clusters carried over from the last step (same triangles) and certified anew, not
    /// regrown: while a [`Ccd`](crate::Ccd) sees the same triangles, its cluster method seeds
    /// each step with the last step's leaves.
    pub reused_leaves: usize,
    /// Seconds spent growing the leaf clusters.
    pub clustering_seconds: f64,
    /// Seconds spent merging them into intermediate clusters.
    pub merging_seconds: f64,
}

/// The state of the cluster method, kept across steps for its buffers only.
#[derive(Clone, Debug, Default)]
pub(crate) struct ClusterPhase {
    c6: ClusterTree<3>,
    c14: ClusterTree<7>,
    c18: ClusterTree<9>,
    c26: ClusterTree<13>,
    /// The clustering of the last query, and its scratch memory.
    pub clustering: Clustering,
    ws: ClusterWorkspace,
    pairs: PairScratch,
    /// Treat every leaf cluster as uncertified (a check of the traversal, for tests).
    pub distrust: bool,
    /// Size from which leaf clusters get their hierarchies built ahead (`None`:
    /// [`AHEAD_TRIANGLES`]; tests lower it).
    pub ahead: Option<usize>,
    /// Lazy hierarchies of the last query that had been built ahead.
    pub last_ahead: usize,
    /// Work items the traversal lists per chunk (`None`: [`traverse::CHUNK_ITEMS`]; tests
    /// lower it).
    pub chunk: Option<usize>,
    /// Chunks the last query's traversal listed.
    pub last_chunks: usize,
}

impl ClusterPhase {
    /// Clusters the step, builds the hierarchy of `kind` over the clusters and hands the
    /// triangle pairs to test, as parallel tasks, to `runner`.
    pub fn candidates(
        &mut self,
        input: &BroadInput<'_, '_>,
        kind: DopKind,
        paper_growth: bool,
        ws: &mut BvhWorkspace,
        runner: &mut impl PairRunner,
    ) -> (BroadStats, ClusterFigures) {
        let options = ClusterOptions {
            min_distance: input.filter.sep,
            phi_filter: paper_growth,
            ..ClusterOptions::default()
        };
        let grow = Grow {
            options: &options,
            ws: &mut self.ws,
            clustering: &mut self.clustering,
            trust: !self.distrust,
            ahead: self.ahead.unwrap_or(AHEAD_TRIANGLES),
            chunk: self.chunk.unwrap_or(traverse::CHUNK_ITEMS).max(1),
        };
        let args = (grow, &mut self.pairs, ws, runner);
        let (stats, counts) = match kind {
            DopKind::K6 => run(&mut self.c6, input, args),
            DopKind::K14 => run(&mut self.c14, input, args),
            DopKind::K18 => run(&mut self.c18, input, args),
            DopKind::K26 => run(&mut self.c26, input, args),
        };
        self.last_ahead = counts.lazy_ahead;
        self.last_chunks = counts.chunks;
        let cs = &self.clustering.stats;
        let figures = ClusterFigures {
            leaf: cs.leaves,
            intermediate: cs.intermediates,
            triangles_per_leaf: cs.triangles_per_leaf,
            triangles_per_intermediate: cs.triangles_per_intermediate,
            lazy_bvhs: counts.lazy_bvhs,
            leaf_pairs: counts.leaf_pairs,
            uncertified_leaves: counts.uncertified_leaves,
            reused_leaves: cs.reused_leaves,
            clustering_seconds: cs.clustering_seconds,
            merging_seconds: cs.merging_seconds,
        };
        (stats, figures)
    }

    /// Makes the leaf growth of the next queries obey `stop` (`None`: never stop).
    pub fn set_stop(&mut self, stop: Option<crate::broad::Stopper>) {
        self.ws.leaf.stop = stop;
    }

    /// Validates the hierarchy of `kind` built by the last query (see
    /// [`ClusterTree::validate`]).
    pub fn validate(&self, kind: DopKind) -> Result<(), BvhError> {
        let c = &self.clustering;
        match kind {
            DopKind::K6 => self.c6.validate(c),
            DopKind::K14 => self.c14.validate(c),
            DopKind::K18 => self.c18.validate(c),
            DopKind::K26 => self.c26.validate(c),
        }
    }
}

impl BroadPhase for ClusterPhase {
    /// The cluster method's step ([`ClusterPhase::candidates`]), its traversal's tasks solving
    /// their own candidates, as the per-step hierarchy's do; the leaf growth stops with the
    /// query.
    fn run(&mut self, passes: &Passes<'_, '_, '_>, ws: &mut BvhWorkspace, out: Out<'_>) -> BroadStats {
        let options = passes.ctx.options;
        let paper = options.growth == ClusterGrowth::Paper;
        let stop = Arc::clone(passes.limits);
        let limits = Some(Arc::clone(passes.limits));
        self.set_stop(Some(Stopper(Arc::new(move || stop.poll(false)), limits)));
        let mut runner = Runner { passes, out };
        let (mut stats, figures) =
            self.candidates(passes.input, options.kdop, paper, ws, &mut runner);
        self.set_stop(None);
        stats.cluster = Some(figures);
        stats
    }
}

/// Leaf clusters of at least this many triangles get their hierarchy built while the clustering
/// grows, when a second thread is there to do it (whether or not the traversal will need it).
const AHEAD_TRIANGLES: usize = 1024;

/// What clusters the step: its options, scratch memory and output.
struct Grow<'a> {
    options: &'a ClusterOptions,
    ws: &'a mut ClusterWorkspace,
    clustering: &'a mut Clustering,
    /// Whether the traversal may trust the leaves' certificates.
    trust: bool,
    /// Leaf clusters of at least this many triangles get their hierarchies built ahead.
    ahead: usize,
    /// Work items the traversal lists per chunk ([`traverse::CHUNK_ITEMS`]).
    chunk: usize,
}

type Args<'a, R> = (
    Grow<'a>,
    &'a mut PairScratch,
    &'a mut BvhWorkspace,
    &'a mut R,
);

/// Clusters the step while the triangles' volumes are computed beside it (on the rayon pool,
/// so at the same time on two threads or more), builds the cluster hierarchy and the lazy
/// hierarchies (counted as build: the sweep counts only for the time it adds to the
/// clustering's), then runs the traversal's tasks (counted as traversal, with whatever `runner`
/// does inside them).
fn run<const H: usize, R: PairRunner>(
    tree: &mut ClusterTree<H>,
    input: &BroadInput<'_, '_>,
    (grow, pairs, ws, runner): Args<'_, R>,
) -> (BroadStats, traverse::Counts) {
    let t = Instant::now();
    let topo = &input.features.topo;
    let Grow {
        options,
        ws: cluster_ws,
        clustering,
        trust,
        ahead,
        chunk,
    } = grow;
    // With a second thread, the leaf clusters big enough to matter get their hierarchies while
    // the others grow; on one thread only those needed are built, after the clustering.
    let ahead = if rayon::current_num_threads() > 1 {
        ahead
    } else {
        usize::MAX
    };
    let step = input.step;
    cluster_into_beside(step, topo, options, cluster_ws, clustering, ahead, |leaves, grown| {
        tree.sweep(step, (input.filter.tmax(), input.filter.sep));
        tree.build_ahead(leaves, grown);
    });
    let c = &clustering.stats;
    let swept = (t.elapsed().as_secs_f64() - c.clustering_seconds - c.merging_seconds).max(0.0);
    let t = Instant::now();
    tree.build(clustering, ws);
    let built = swept + t.elapsed().as_secs_f64();
    let t = Instant::now();
    let traversal = Inputs {
        clustering,
        trust,
        stop: cluster_ws.leaf.stop.as_ref(),
        chunk,
    };
    traverse::begin(tree, &traversal, pairs);
    let source = TrianglePairs::new(tree, &traversal, pairs);
    let tests = runner.run(&source, ws);
    let mut counts = source.counts();
    counts.bv_tests += tests;
    let traversed = t.elapsed().as_secs_f64();
    let stats = BroadStats {
        bv_tests: counts.bv_tests,
        build: built + counts.lazy_seconds,
        traverse: (traversed - counts.lazy_seconds).max(0.0),
        ..BroadStats::default()
    };
    (stats, counts)
}
