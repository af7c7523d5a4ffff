//! The result of the clustering: leaf and intermediate clusters, their options and statistics.

use super::certificate::DiskFailure;
use crate::math::DVec3;
use std::ops::Range;

/// Options of [`cluster`](super::cluster).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterOptions {
    /// Distance, in the coordinates' units, at or below which features count as touching, as in
    /// [`NarrowOptions`](crate::narrow::NarrowOptions). `>= 0`. The certificates hold for
    /// contact only, so any value `> 0` turns clustering off (single-triangle leaves, single-leaf
    /// intermediate clusters). Default `0`.
    pub min_distance: f64,
    /// Most de Casteljau subdivisions per polynomial sign test when its coefficients are
    /// inconclusive, `0..=8` sensibly (cost up to `2^subdivisions` per test). Default `2`.
    pub subdivisions: u32,
    /// Whether to merge leaf clusters into intermediate clusters at all. Default `true`.
    pub merge: bool,
    /// Most leaf clusters per intermediate cluster, `>= 1` (the box test of algorithm 2 is
    /// quadratic in it). Default `128`.
    pub max_intermediate_leaves: u32,
    /// Largest number of triangles two leaf clusters may hold together for a merge to be
    /// attempted. Every attempt certifies the union's disk from scratch, in time proportional
    /// to its size, and big leaves gain little from merging; `u32::MAX` attempts them all.
    /// Default 512.
    pub max_merge_triangles: u32,
    /// Whether to apply the paper's test `phi >= 0` (equation 2 for rings, algorithm 1 for
    /// merges). Soundness rests on the disk certificate alone, so turning it off stays sound;
    /// it exists to measure what the paper's criterion costs. Default `true` (the paper's
    /// algorithm).
    pub phi_filter: bool,
    /// How a ring of a leaf cluster is accepted when the paper's filter is off; with
    /// [`ClusterOptions::phi_filter`] the paper's whole rings are always used. Default
    /// [`RingGrowth::Partial`].
    pub rings: RingGrowth,
    /// The direction `V` of each leaf's disk certificate with [`RingGrowth::Partial`] (with
    /// whole rings or the paper's filter, the seed's normal at t=0). Default
    /// [`LeafDirection::Seed`].
    pub direction: LeafDirection,
    /// Whether a step whose triangles are those of the last step clustered with the same
    /// workspace and options (with [`RingGrowth::Partial`] and the paper's filter off) starts
    /// from the last step's leaf clusters: each of two or more triangles is certified anew,
    /// in full, on the new positions, and kept whole when it passes; the triangles of those
    /// that fail are grown afresh (see the [module documentation](super)). Soundness rests on
    /// the new certificate alone, as for a grown leaf. Default `true`.
    pub reuse: bool,
}

/// How a leaf cluster's direction `V` is chosen (any fixed vector makes the disk theorem hold;
/// a better one lets the leaf grow further).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LeafDirection {
    /// The normalised sum of the seed's unit normals at t=0 and t=1.
    #[default]
    Seed,
    /// That sum with the seed counted twice, plus the unit normals (t=0 and t=1) of the
    /// triangles around each seed vertex, weighted by one over the vertex's triangle count.
    Neighbourhood,
}

/// How leaf growth accepts the triangles of a ring (with the paper's filter off).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RingGrowth {
    /// A ring joins only if all its triangles do (the paper's rule).
    Whole,
    /// The ring's triangles join one at a time, each only if the patch stays a certified disk;
    /// the rest of the ring is left to later rings and other leaves.
    #[default]
    Partial,
}

impl Default for ClusterOptions {
    fn default() -> Self {
        Self {
            min_distance: 0.0,
            subdivisions: 2,
            merge: true,
            max_intermediate_leaves: 128,
            max_merge_triangles: 512,
            phi_filter: true,
            rings: RingGrowth::default(),
            direction: LeafDirection::default(),
            reuse: true,
        }
    }
}

/// Why a leaf cluster's growth ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GrowthStop {
    /// No free triangle was left around the last ring.
    Exhausted,
    /// A triangle of the next ring failed the paper's test `phi >= 0`.
    Phi,
    /// The patch with the next ring (or the seed itself) failed the disk certificate.
    Certificate(DiskFailure),
    /// Growth is off ([`ClusterOptions::min_distance`] `> 0`).
    Disabled,
}

/// What makes a leaf cluster free of self-contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LeafCertificate {
    /// One triangle: its features all share a vertex, there is nothing to test.
    SingleTriangle,
    /// Several triangles forming a certified disk (see the [module documentation](super)).
    Disk,
}

/// A leaf cluster: a seed triangle and the rings grown around it.
#[derive(Clone, Debug, PartialEq)]
pub struct LeafCluster {
    /// Range of its triangles in [`Clustering::leaf_triangles`], ring by ring, seed first.
    pub triangles: Range<usize>,
    /// Range of its rings in [`Clustering::ring_starts`] (ring 0 is the seed).
    pub rings: Range<usize>,
    /// Range of its `V-bar` (equation 4) in [`Clustering::last_ring_vertices`].
    pub last_ring_vertices: Range<usize>,
    /// Observation point `O` (the seed's centroid, equation 3) at t=0 and t=1.
    pub observation: [DVec3; 2],
    /// Direction `V` of the disk certificate: the seed's unit normal at t=0 with whole rings,
    /// the choice of [`ClusterOptions::direction`] with partial rings (zero if the seed is
    /// degenerate).
    pub direction: DVec3,
    /// Star centre `c` of its disk certificate at t=0 and t=1 (the observation point, or the
    /// mean of the patch's vertices when growth needed another centre).
    pub centre: [DVec3; 2],
    /// What makes it free of self-contact.
    pub certificate: LeafCertificate,
    /// Why it stopped growing (for a leaf kept from the last step that did not grow, why it
    /// stopped when it last grew).
    pub stop: GrowthStop,
}

/// An intermediate cluster: leaf clusters in the order they joined, each adjacent to the one
/// before. No two of its features that share no vertex touch during the step.
#[derive(Clone, Debug, PartialEq)]
pub struct IntermediateCluster {
    /// Range of its leaves in [`Clustering::intermediate_leaves`].
    pub leaves: Range<usize>,
    /// Number of triangles in its leaves.
    pub triangle_count: usize,
}

/// How often each hypothesis of the disk theorem failed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DiskFailureCounts {
    /// [`DiskFailure::Normal`].
    pub normal: usize,
    /// [`DiskFailure::NonManifold`].
    pub non_manifold: usize,
    /// [`DiskFailure::Topology`].
    pub topology: usize,
    /// [`DiskFailure::Star`].
    pub star: usize,
    /// [`DiskFailure::Winding`].
    pub winding: usize,
}

impl DiskFailureCounts {
    /// Counts one failure.
    pub fn record(&mut self, failure: DiskFailure) {
        match failure {
            DiskFailure::Normal => self.normal += 1,
            DiskFailure::NonManifold => self.non_manifold += 1,
            DiskFailure::Topology => self.topology += 1,
            DiskFailure::Star => self.star += 1,
            DiskFailure::Winding => self.winding += 1,
        }
    }
}

/// Counters and timings of one clustering.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ClusterStats {
    /// Number of triangles.
    pub triangles: usize,
    /// Number of leaf clusters.
    pub leaves: usize,
    /// Number of intermediate clusters.
    pub intermediates: usize,
    /// Average triangles per leaf cluster (table 2's ratio, per leaf).
    pub triangles_per_leaf: f64,
    /// Average triangles per intermediate cluster (table 2's ratio).
    pub triangles_per_intermediate: f64,
    /// Leaves that stopped because no free triangle was left.
    pub stops_exhausted: usize,
    /// Leaves that stopped at a ring failing the paper's `phi` test.
    pub stops_phi: usize,
    /// Leaves that stopped at a ring (or seed) failing the disk certificate.
    pub stops_certificate: usize,
    /// Disk certificate failures (leaf growth and merge attempts), by hypothesis.
    pub disk_failures: DiskFailureCounts,
    /// Merges by the paper's route (last ring in a disk, rest by boxes).
    pub merged_by_ring: usize,
    /// Merges by the fallback route (union of both leaves a disk).
    pub merged_by_union: usize,
    /// Merges not attempted: the two leaves hold more than `max_merge_triangles`.
    pub merge_rejected_size: usize,
    /// Merge attempts refused by algorithm 2's box test.
    pub merge_rejected_box: usize,
    /// Merge attempts refused by the paper's `phi` test of algorithm 1.
    pub merge_rejected_phi: usize,
    /// Merge attempts refused because neither certificate route held.
    pub merge_rejected_certificate: usize,
    /// Leaf clusters taken over from the last step and certified anew ([`ClusterOptions::reuse`]).
    pub reused_leaves: usize,
    /// Of those, the leaves kept only in part: their first rings (the others are free again).
    pub trimmed_leaves: usize,
    /// Leaf clusters of the last step that failed their new certificate and were grown afresh.
    pub regrown_leaves: usize,
    /// Wall time of the leaf clustering, in seconds.
    pub clustering_seconds: f64,
    /// Wall time of the merging into intermediate clusters, in seconds.
    pub merging_seconds: f64,
}

/// The clustering of one step. Triangle, leaf and intermediate ids index the arrays below.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Clustering {
    /// Leaf cluster of each triangle.
    pub leaf_of_triangle: Vec<u32>,
    /// The leaf clusters, by increasing seed triangle.
    pub leaves: Vec<LeafCluster>,
    /// Triangles of all leaves, leaf by leaf, ring by ring (see [`LeafCluster::triangles`]).
    pub leaf_triangles: Vec<u32>,
    /// Start of every ring in [`Clustering::leaf_triangles`] (see [`LeafCluster::rings`]).
    pub ring_starts: Vec<u32>,
    /// `V-bar` (equation 4) of all leaves: vertices of the last accepted ring not in earlier
    /// rings (the seed's three vertices for a one-triangle leaf).
    pub last_ring_vertices: Vec<u32>,
    /// The intermediate clusters.
    pub intermediates: Vec<IntermediateCluster>,
    /// Leaves of all intermediate clusters (see [`IntermediateCluster::leaves`]).
    pub intermediate_leaves: Vec<u32>,
    /// Intermediate cluster of each leaf.
    pub intermediate_of_leaf: Vec<u32>,
    /// Counters and timings.
    pub stats: ClusterStats,
}

impl Clustering {
    /// Empties every array (keeping its memory) and zeroes the statistics.
    pub fn clear(&mut self) {
        self.leaf_of_triangle.clear();
        self.leaves.clear();
        self.leaf_triangles.clear();
        self.ring_starts.clear();
        self.last_ring_vertices.clear();
        self.intermediates.clear();
        self.intermediate_leaves.clear();
        self.intermediate_of_leaf.clear();
        self.stats = ClusterStats::default();
    }

    /// Triangles of leaf `leaf`, ring by ring.
    pub fn leaf_triangles(&self, leaf: usize) -> &[u32] {
        &self.leaf_triangles[self.leaves[leaf].triangles.clone()]
    }

    /// Number of rings of leaf `leaf` (1 for the seed alone).
    pub fn ring_count(&self, leaf: usize) -> usize {
        self.leaves[leaf].rings.len()
    }

    /// Ring `k` of leaf `leaf` (ring 0 is the seed).
    pub fn ring(&self, leaf: usize, k: usize) -> &[u32] {
        let l = &self.leaves[leaf];
        let r = l.rings.start + k;
        debug_assert!(r < l.rings.end);
        let start = self.ring_starts[r] as usize;
        let end = if r + 1 < l.rings.end {
            self.ring_starts[r + 1] as usize
        } else {
            l.triangles.end
        };
        &self.leaf_triangles[start..end]
    }

    /// The last ring of leaf `leaf` (`T^i` of the paper).
    pub fn last_ring(&self, leaf: usize) -> &[u32] {
        self.ring(leaf, self.ring_count(leaf) - 1)
    }

    /// `V-bar` of leaf `leaf` (equation 4).
    pub fn last_ring_vertices(&self, leaf: usize) -> &[u32] {
        &self.last_ring_vertices[self.leaves[leaf].last_ring_vertices.clone()]
    }

    /// Whether a triangle holding all of the vertices `a` and one holding all of `b` lie in one
    /// intermediate cluster (`triangles`: the step's triangles, as clustered): where the
    /// cluster method may skip the pair of features `a` and `b` (a vertex, an edge or a face,
    /// by their vertices), its certificate proving that they never touch. A scan of the
    /// triangles, for checks of a report, not for a query.
    pub fn holds_both(&self, triangles: &[[u32; 3]], a: &[u32], b: &[u32]) -> bool {
        let cluster = |t: usize| {
            let leaf = *self.leaf_of_triangle.get(t)?;
            self.intermediate_of_leaf.get(leaf as usize).copied()
        };
        let holding = |f: &[u32]| -> Vec<u32> {
            (0..triangles.len())
                .filter(|&t| f.iter().all(|v| triangles[t].contains(v)))
                .filter_map(cluster)
                .collect()
        };
        let of_b = holding(b);
        holding(a).iter().any(|c| of_b.contains(c))
    }

    /// Leaves of intermediate cluster `ic`, in the order they joined.
    pub fn intermediate_leaves(&self, ic: usize) -> &[u32] {
        &self.intermediate_leaves[self.intermediates[ic].leaves.clone()]
    }

    /// Start of the triangles of the leaf being grown (the end of the finished leaves).
    pub(super) fn leaves_end_offset(&self) -> usize {
        self.leaves.last().map_or(0, |l| l.triangles.end)
    }
}
