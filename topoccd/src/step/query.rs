//! The whole-step query: [`Ccd`] keeps scratch memory across steps; [`query`] is the one-shot
//! form.

use std::time::Instant;

use super::cluster_query::{self, Counts, Inputs, PairScratch};
use super::cluster_tree::ClusterTree;
use super::features::Features;
use super::report::{ClusterFigures, Report, Seconds, Stats};
use super::{brute, narrow_phase, ClusterGrowth, Method, QueryOptions, Step, Topology};
use crate::bvh::{Bvh, BvhError, BvhWorkspace, Leaf};
use crate::cluster::{cluster_into, ClusterOptions, ClusterWorkspace, Clustering};
use crate::kdop::{DopKind, Kdop};

/// The leaves and hierarchy of one k-DOP type, kept for reuse.
#[derive(Clone, Debug, Default)]
struct Tree<const H: usize> {
    leaves: Vec<Leaf<Kdop<H>>>,
    bvh: Bvh<Kdop<H>>,
}

impl<const H: usize> Tree<H> {
    /// Builds the swept k-DOPs of the triangles and the hierarchy over them.
    fn build(&mut self, step: &Step, inflation: f64, ws: &mut BvhWorkspace) {
        let (x0, x1) = (step.x0(), step.x1());
        self.leaves.clear();
        self.leaves
            .extend(step.triangles().iter().enumerate().map(|(t, tri)| {
                let [a, b, c] = tri.map(|i| i as usize);
                Leaf {
                    id: t as u32,
                    volume: Kdop::swept_triangle(
                        &[x0[a], x0[b], x0[c]],
                        &[x1[a], x1[b], x1[c]],
                        inflation,
                    ),
                }
            }));
        self.bvh.rebuild(&self.leaves, ws);
    }

    fn validate(&self) -> Result<(), BvhError> {
        self.bvh.validate(&self.leaves)
    }
}

/// A reusable whole-step CCD query. Keep one per simulation and call [`Ccd::query`] every step:
/// its buffers (hierarchy, candidate pairs, per-feature data) are reused, while nothing about
/// the mesh is carried from one step to the next, so the topology may change freely.
#[derive(Clone, Debug, Default)]
pub struct Ccd {
    features: Features,
    ws: BvhWorkspace,
    k6: Tree<3>,
    k14: Tree<7>,
    k18: Tree<9>,
    k26: Tree<13>,
    /// The hierarchies of [`Method::Cluster`], one per k-DOP type.
    c6: ClusterTree<3>,
    c14: ClusterTree<7>,
    c18: ClusterTree<9>,
    c26: ClusterTree<13>,
    /// The clustering of the last [`Method::Cluster`] query, and its scratch memory.
    clustering: Clustering,
    cluster_ws: ClusterWorkspace,
    pairs: PairScratch,
    /// Treat every leaf cluster as uncertified (see [`Ccd::distrust_certificates`]).
    distrust: bool,
    /// The method and k-DOP type of the last hierarchy built, if the last query built one.
    last_tree: Option<(Method, DopKind)>,
    vf: Vec<[u32; 2]>,
    ee: Vec<[u32; 2]>,
}

/// The candidate feature pairs of the last query, each given once to the narrow phase.
#[derive(Clone, Copy, Debug)]
pub struct Candidates<'a> {
    /// `[vertex, face]` pairs.
    pub vf: &'a [[u32; 2]],
    /// `[e, f]` pairs of indices into [`Candidates::edges`], `e < f`.
    pub ee: &'a [[u32; 2]],
    /// The step's edges, `[i, j]` with `i < j`, sorted lexicographically.
    pub edges: &'a [[u32; 2]],
}

impl Ccd {
    /// A query with empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// Runs continuous collision detection over one step.
    ///
    /// Every vertex-face pair and every pair of edges, sharing no vertex, that comes within
    /// `options.narrow.min_separation` during `[0, options.narrow.t_max]` is reported (with the
    /// elementary tests' conservative time of impact), in [`Mode::All`](super::Mode::All); only
    /// the earliest in [`Mode::Earliest`](super::Mode::Earliest). Each feature pair is tested at
    /// most once. The result does not depend on the method, the thread count or earlier
    /// queries.
    ///
    /// ```
    /// use topoccd::math::DVec3;
    /// use topoccd::step::{Ccd, Method, QueryOptions, Step};
    /// // A vertex (3) falls through a fixed triangle (0, 1, 2); a small triangle carries it.
    /// let tri = [DVec3::ZERO, DVec3::X, DVec3::Y];
    /// let carrier = [DVec3::new(0.2, 0.2, 1.0), DVec3::new(0.3, 0.2, 1.5), DVec3::new(0.2, 0.3, 1.5)];
    /// let x0: Vec<DVec3> = tri.iter().chain(&carrier).copied().collect();
    /// let x1: Vec<DVec3> = tri.iter().copied().chain(carrier.iter().map(|p| *p - 2.0 * DVec3::Z)).collect();
    /// let step = Step::new(x0, x1, vec![[0, 1, 2], [3, 4, 5]]).unwrap();
    /// let mut ccd = Ccd::new();
    /// let report = ccd.query(&step, Method::Bvh, &QueryOptions::default());
    /// assert_eq!((report.vf[0].vertex, report.vf[0].face), (3, 0));
    /// assert!((report.vf[0].toi - 0.5).abs() < 1e-6);
    /// ```
    pub fn query(&mut self, step: &Step, method: Method, options: &QueryOptions) -> Report {
        let start = Instant::now();
        let sep = options.narrow.min_separation.max(0.0);
        let sep = if sep.is_finite() { sep } else { 0.0 };
        self.features.update(step);
        self.vf.clear();
        self.ee.clear();
        self.last_tree = None;
        let mut bv_tests = 0;
        let mut cluster = None;
        let (mut clustering, mut merging) = (None, None);
        let (build, traverse) = match method {
            Method::Brute => {
                let t = Instant::now();
                bv_tests = brute::candidates(
                    step.triangles(),
                    &self.features,
                    sep,
                    &mut self.vf,
                    &mut self.ee,
                );
                let sweep = t.elapsed().as_secs_f64();
                (start.elapsed().as_secs_f64() - sweep, sweep)
            }
            Method::Cluster => {
                let prepared = start.elapsed().as_secs_f64();
                let copts = ClusterOptions {
                    min_separation: sep,
                    phi_filter: options.growth == ClusterGrowth::Paper,
                    ..ClusterOptions::default()
                };
                let topo = &self.features.topo;
                cluster_into(
                    step,
                    topo,
                    &copts,
                    &mut self.cluster_ws,
                    &mut self.clustering,
                );
                let cs = self.clustering.stats;
                clustering = Some(cs.clustering_seconds);
                merging = Some(cs.merging_seconds);
                self.last_tree = Some((Method::Cluster, options.kdop));
                let s = &mut *self;
                let input = Inputs {
                    clustering: &s.clustering,
                    triangles: step.triangles(),
                    features: &s.features,
                    sep,
                    trust: !s.distrust,
                };
                let args = (&input, &mut s.pairs, &mut s.ws, &mut s.vf, &mut s.ee);
                let (build, traverse, counts) = match options.kdop {
                    DopKind::K6 => cluster_candidates(&mut s.c6, step, args),
                    DopKind::K14 => cluster_candidates(&mut s.c14, step, args),
                    DopKind::K18 => cluster_candidates(&mut s.c18, step, args),
                    DopKind::K26 => cluster_candidates(&mut s.c26, step, args),
                };
                bv_tests = counts.bv_tests;
                cluster = Some(ClusterFigures {
                    leaf: cs.leaves,
                    intermediate: cs.intermediates,
                    triangles_per_leaf: cs.triangles_per_leaf,
                    triangles_per_intermediate: cs.triangles_per_intermediate,
                    lazy_bvhs: counts.lazy_bvhs,
                    leaf_pairs: counts.leaf_pairs,
                    uncertified_leaves: counts.uncertified_leaves,
                });
                (prepared + build, traverse)
            }
            Method::Bvh => {
                self.last_tree = Some((Method::Bvh, options.kdop));
                let s = &mut *self;
                let args = (&s.features, &mut s.ws, &mut s.vf, &mut s.ee);
                let traverse = match options.kdop {
                    DopKind::K6 => bvh_candidates(&mut s.k6, step, sep, args, &mut bv_tests),
                    DopKind::K14 => bvh_candidates(&mut s.k14, step, sep, args, &mut bv_tests),
                    DopKind::K18 => bvh_candidates(&mut s.k18, step, sep, args, &mut bv_tests),
                    DopKind::K26 => bvh_candidates(&mut s.k26, step, sep, args, &mut bv_tests),
                };
                (start.elapsed().as_secs_f64() - traverse, traverse)
            }
        };
        let t = Instant::now();
        let found = narrow_phase::run(step, &self.features.topo.edges, &self.vf, &self.ee, options);
        let narrow = t.elapsed().as_secs_f64();
        Report {
            vf: found.vf,
            ee: found.ee,
            earliest: found.earliest,
            stats: Stats {
                bv_tests,
                vf_tests: self.vf.len() as u64,
                ee_tests: self.ee.len() as u64,
                seconds: Seconds {
                    build,
                    traverse,
                    narrow,
                    total: start.elapsed().as_secs_f64(),
                    clustering,
                    merging,
                },
                cluster,
            },
        }
    }

    /// The candidate feature pairs of the last query: exactly the pairs given to the narrow
    /// phase ([`Stats::vf_tests`], [`Stats::ee_tests`]), each once. For tests and diagnostics.
    pub fn candidates(&self) -> Candidates<'_> {
        Candidates {
            vf: &self.vf,
            ee: &self.ee,
            edges: &self.features.topo.edges,
        }
    }

    /// The topology of the last step queried.
    pub fn topology(&self) -> &Topology {
        &self.features.topo
    }

    /// Runs [`Bvh::validate`] on the hierarchy built by the last query (for
    /// [`Method::Cluster`]: on the tree over the intermediate clusters, every sub-tree over
    /// leaf clusters and every lazy hierarchy built, and checks that each cluster's volume
    /// contains its parts'). `Ok` when the last query built none (as [`Method::Brute`] does).
    pub fn validate_tree(&self) -> Result<(), BvhError> {
        let c = &self.clustering;
        match self.last_tree {
            None => Ok(()),
            Some((Method::Cluster, kind)) => match kind {
                DopKind::K6 => self.c6.validate(c),
                DopKind::K14 => self.c14.validate(c),
                DopKind::K18 => self.c18.validate(c),
                DopKind::K26 => self.c26.validate(c),
            },
            Some((_, DopKind::K6)) => self.k6.validate(),
            Some((_, DopKind::K14)) => self.k14.validate(),
            Some((_, DopKind::K18)) => self.k18.validate(),
            Some((_, DopKind::K26)) => self.k26.validate(),
        }
    }

    /// The clustering computed by the last [`Method::Cluster`] query (empty before the first).
    /// For tests and diagnostics: nothing of it is used by the next query.
    pub fn clustering(&self) -> &Clustering {
        &self.clustering
    }

    /// With `true`, [`Method::Cluster`] treats every leaf cluster as if it carried no
    /// certificate: every leaf cluster is tested against itself and every pair of leaves inside
    /// an intermediate cluster against each other, so its candidates are exactly those of
    /// [`Method::Bvh`]. A check of the traversal's general path, for tests; `false` (the
    /// default) trusts the certificates.
    #[doc(hidden)]
    pub fn distrust_certificates(&mut self, distrust: bool) {
        self.distrust = distrust;
    }
}

/// The mutable state the BVH phase needs besides its tree.
type Scratch<'a> = (
    &'a Features,
    &'a mut BvhWorkspace,
    &'a mut Vec<[u32; 2]>,
    &'a mut Vec<[u32; 2]>,
);

/// Builds the k-DOP hierarchy and collects the candidate feature pairs of every overlapping
/// triangle pair. Returns the traversal time in seconds; adds the overlap tests to `bv_tests`.
fn bvh_candidates<const H: usize>(
    tree: &mut Tree<H>,
    step: &Step,
    sep: f64,
    (features, ws, vf, ee): Scratch<'_>,
    bv_tests: &mut u64,
) -> f64 {
    tree.build(step, sep, ws);
    let t = Instant::now();
    let tris = step.triangles();
    *bv_tests += tree.bvh.self_pairs(ws, |a, b| {
        features.triangle_pair(tris, a, b, sep, vf, ee);
    });
    t.elapsed().as_secs_f64()
}

/// The mutable state the cluster traversal needs besides its hierarchy.
type ClusterArgs<'a, 'b> = (
    &'a Inputs<'b>,
    &'a mut PairScratch,
    &'a mut BvhWorkspace,
    &'a mut Vec<[u32; 2]>,
    &'a mut Vec<[u32; 2]>,
);

/// Builds the cluster hierarchy and collects the candidate feature pairs. Returns the build
/// time (lazy hierarchies included) and the traversal time (without them), in seconds.
fn cluster_candidates<const H: usize>(
    tree: &mut ClusterTree<H>,
    step: &Step,
    (input, pairs, ws, vf, ee): ClusterArgs<'_, '_>,
) -> (f64, f64, Counts) {
    let t = Instant::now();
    tree.build(step, input.clustering, input.sep, ws);
    let built = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let counts = cluster_query::candidates(tree, input, pairs, ws, vf, ee);
    let traversed = t.elapsed().as_secs_f64();
    (
        built + counts.lazy_seconds,
        (traversed - counts.lazy_seconds).max(0.0),
        counts,
    )
}

/// One-shot form of [`Ccd::query`] (allocates fresh buffers).
///
/// ```
/// use topoccd::scene;
/// use topoccd::step::{query, Method, QueryOptions};
/// let step = scene::folded_sheet(8, 1);
/// let options = QueryOptions::default();
/// let bvh = query(&step, Method::Bvh, &options);
/// let brute = query(&step, Method::Brute, &options);
/// assert!(bvh.contact_count() > 0);
/// assert_eq!((bvh.vf, bvh.ee), (brute.vf, brute.ee));
/// ```
pub fn query(step: &Step, method: Method, options: &QueryOptions) -> Report {
    Ccd::new().query(step, method, options)
}
