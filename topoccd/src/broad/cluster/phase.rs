//! The cluster method as one broad phase: cluster the step, build the hierarchy over the
//! clusters, traverse it down to candidate pairs.

use std::time::Instant;

use super::traverse::{self, Inputs, PairScratch, TrianglePairs};
use super::tree::ClusterTree;
use super::{cluster_into, ClusterOptions, ClusterWorkspace, Clustering};
use crate::broad::{BroadInput, BroadStats, PairRunner};
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
            min_separation: input.filter.sep,
            phi_filter: paper_growth,
            ..ClusterOptions::default()
        };
        let topo = &input.features.topo;
        cluster_into(input.step, topo, &options, &mut self.ws, &mut self.clustering);
        let traversal = Inputs {
            clustering: &self.clustering,
            trust: !self.distrust,
        };
        let args = (&traversal, &mut self.pairs, ws, runner);
        let (stats, counts) = match kind {
            DopKind::K6 => run(&mut self.c6, input, args),
            DopKind::K14 => run(&mut self.c14, input, args),
            DopKind::K18 => run(&mut self.c18, input, args),
            DopKind::K26 => run(&mut self.c26, input, args),
        };
        let cs = &self.clustering.stats;
        let figures = ClusterFigures {
            leaf: cs.leaves,
            intermediate: cs.intermediates,
            triangles_per_leaf: cs.triangles_per_leaf,
            triangles_per_intermediate: cs.triangles_per_intermediate,
            lazy_bvhs: counts.lazy_bvhs,
            leaf_pairs: counts.leaf_pairs,
            uncertified_leaves: counts.uncertified_leaves,
            clustering_seconds: cs.clustering_seconds,
            merging_seconds: cs.merging_seconds,
        };
        (stats, figures)
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

type Args<'a, 'b, R> = (
    &'a Inputs<'b>,
    &'a mut PairScratch,
    &'a mut BvhWorkspace,
    &'a mut R,
);

/// Builds the cluster hierarchy and the lazy hierarchies (counted as build), then runs the
/// traversal's tasks (counted as traversal, with whatever `runner` does inside them).
fn run<const H: usize, R: PairRunner>(
    tree: &mut ClusterTree<H>,
    input: &BroadInput<'_, '_>,
    (traversal, pairs, ws, runner): Args<'_, '_, R>,
) -> (BroadStats, traverse::Counts) {
    let t = Instant::now();
    tree.build(input.step, traversal.clustering, input.filter.sep, ws);
    let built = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let mut counts = traverse::prepare(tree, traversal, pairs, ws);
    let source = TrianglePairs {
        tree,
        clustering: traversal.clustering,
        scratch: pairs,
    };
    counts.bv_tests += runner.run(&source, ws);
    let traversed = t.elapsed().as_secs_f64();
    let stats = BroadStats {
        bv_tests: counts.bv_tests,
        build: built + counts.lazy_seconds,
        traverse: (traversed - counts.lazy_seconds).max(0.0),
    };
    (stats, counts)
}
