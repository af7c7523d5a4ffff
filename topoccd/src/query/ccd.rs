//! The whole-step query: [`Ccd`] keeps scratch memory across steps; [`query`] is the one-shot
//! form. The pipeline: features and pair filter ([`mesh`](crate::mesh)), one broad phase
//! ([`broad`](crate::broad)), the narrow phase, the report.

use std::time::Instant;

use super::narrow_phase::{self, Found};
use super::report::{Report, Seconds, Stats};
use super::{ClusterGrowth, Method, OptionsError, QueryOptions};
use crate::broad::cluster::phase::ClusterPhase;
use crate::broad::{self, brute, bvh::PerStepBvh, BroadInput, BroadStats};
use crate::bvh::BvhWorkspace;
use crate::kdop::DopKind;
use crate::mesh::features::Features;
use crate::mesh::filter::PairFilter;
use crate::mesh::Step;
use crate::narrow::Certainty;

/// A reusable whole-step CCD query. Keep one per simulation and call [`Ccd::query`] every step:
/// its buffers (hierarchy, candidate pairs, per-feature data) are reused, while nothing about
/// the mesh is carried from one step to the next, so the topology may change freely.
#[derive(Clone, Debug, Default)]
pub struct Ccd {
    features: Features,
    canon: Vec<u32>,
    ws: BvhWorkspace,
    k6: PerStepBvh<3>,
    k14: PerStepBvh<7>,
    k18: PerStepBvh<9>,
    k26: PerStepBvh<13>,
    cluster: ClusterPhase,
    candidates: broad::Candidates,
    /// The method and k-DOP type of the last hierarchy built, if the last query built one.
    last_tree: Option<(Method, DopKind)>,
}

impl Ccd {
    /// A query with empty buffers.
    ///
    /// ```
    /// let mut ccd = topoccd::Ccd::new(); // keep it across steps
    /// # let _ = &mut ccd;
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// Runs continuous collision detection over one step, after checking `options`
    /// ([`QueryOptions::validate`]).
    ///
    /// Every vertex-face pair and every pair of edges that share no vertex and pass the step's
    /// pair filter (see [`Step`]), and come within `options.narrow.min_separation` during
    /// `[0, options.narrow.t_max]`, is reported with the elementary tests' conservative time of
    /// impact and its [`Certainty`], in [`Mode::All`](super::Mode::All); only the earliest
    /// pair(s) in [`Mode::Earliest`](super::Mode::Earliest). Each feature pair is tested at
    /// most once. The result does not depend on the method, the thread count or earlier
    /// queries.
    ///
    /// ```
    /// use topoccd::{Ccd, Method, QueryOptions, Step};
    /// // A vertex (3) falls through a fixed triangle (0, 1, 2); a small triangle carries it.
    /// let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
    ///           [0.2, 0.2, 1.0], [0.3, 0.2, 1.5], [0.2, 0.3, 1.5]];
    /// let mut x1 = x0;
    /// for p in &mut x1[3..] { p[2] -= 2.0; }
    /// let step = Step::new(&x0, &x1, &[[0u32, 1, 2], [3, 4, 5]])?;
    /// let mut ccd = Ccd::new();
    /// let report = ccd.query(&step, Method::Bvh, &QueryOptions::default())?;
    /// assert_eq!((report.vf[0].vertex, report.vf[0].face), (3, 0));
    /// assert!((report.vf[0].toi - 0.5).abs() < 1e-6);
    /// assert_eq!(report.unresolved, 0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn query(
        &mut self,
        step: &Step<'_>,
        method: Method,
        options: &QueryOptions,
    ) -> Result<Report, OptionsError> {
        options.validate()?;
        let start = Instant::now();
        let sep = options.narrow.min_separation;
        self.features.update(step);
        self.candidates.clear();
        self.last_tree = None;
        let filter = PairFilter::new(step, sep, options.crack_filter, &mut self.canon);
        let input = BroadInput {
            step,
            features: &self.features,
            filter: &filter,
        };
        let prepared = start.elapsed().as_secs_f64();
        let out = &mut self.candidates;
        let mut cluster = None;
        let broad = match method {
            Method::Brute => match options.kdop {
                DopKind::K6 => brute::candidates::<3>(&input, &mut Vec::new(), out),
                DopKind::K14 => brute::candidates::<7>(&input, &mut Vec::new(), out),
                DopKind::K18 => brute::candidates::<9>(&input, &mut Vec::new(), out),
                DopKind::K26 => brute::candidates::<13>(&input, &mut Vec::new(), out),
            },
            Method::Bvh => {
                self.last_tree = Some((Method::Bvh, options.kdop));
                let ws = &mut self.ws;
                match options.kdop {
                    DopKind::K6 => self.k6.candidates(&input, ws, out),
                    DopKind::K14 => self.k14.candidates(&input, ws, out),
                    DopKind::K18 => self.k18.candidates(&input, ws, out),
                    DopKind::K26 => self.k26.candidates(&input, ws, out),
                }
            }
            Method::Cluster => {
                self.last_tree = Some((Method::Cluster, options.kdop));
                let paper = options.growth == ClusterGrowth::Paper;
                let (stats, figures) =
                    self.cluster
                        .candidates(&input, options.kdop, paper, &mut self.ws, out);
                cluster = Some(figures);
                stats
            }
        };
        let BroadStats {
            bv_tests,
            build,
            traverse,
        } = broad;
        let t = Instant::now();
        let mut found = Found::default();
        let edges = &self.features.topo.edges;
        narrow_phase::run(step, edges, out, options, &mut None, &mut found);
        let earliest = narrow_phase::finish(&mut found, options);
        let narrow = t.elapsed().as_secs_f64();
        let unresolved = found
            .vf
            .iter()
            .filter(|c| c.certainty != Certainty::Resolved)
            .count()
            + found
                .ee
                .iter()
                .filter(|c| c.certainty != Certainty::Resolved)
                .count();
        Ok(Report {
            vf: found.vf,
            ee: found.ee,
            earliest,
            unresolved,
            stats: Stats {
                bv_tests,
                vf_tests: self.candidates.vf.len() as u64,
                ee_tests: self.candidates.ee.len() as u64,
                seconds: Seconds {
                    build: prepared + build,
                    traverse,
                    narrow,
                    total: start.elapsed().as_secs_f64(),
                    clustering: cluster.map(|c| c.clustering_seconds),
                    merging: cluster.map(|c| c.merging_seconds),
                },
                cluster,
            },
        })
    }
}

/// Diagnostics for the crate's own tests (feature `internals`).
#[cfg(feature = "internals")]
impl Ccd {
    /// The candidate feature pairs of the last query: exactly the pairs given to the narrow
    /// phase ([`Stats::vf_tests`], [`Stats::ee_tests`]), each once.
    pub fn candidates(&self) -> Candidates<'_> {
        Candidates {
            vf: &self.candidates.vf,
            ee: &self.candidates.ee,
            edges: &self.features.topo.edges,
        }
    }

    /// The topology of the last step queried.
    pub fn topology(&self) -> &crate::mesh::Topology {
        &self.features.topo
    }

    /// Runs [`Bvh::validate`](crate::bvh::Bvh::validate) on the hierarchy built by the last
    /// query (for [`Method::Cluster`]: on every level of its hierarchy). `Ok` when the last
    /// query built none (as [`Method::Brute`] does).
    pub fn validate_tree(&self) -> Result<(), crate::bvh::BvhError> {
        match self.last_tree {
            None => Ok(()),
            Some((Method::Cluster, kind)) => self.cluster.validate(kind),
            Some((_, DopKind::K6)) => self.k6.validate(),
            Some((_, DopKind::K14)) => self.k14.validate(),
            Some((_, DopKind::K18)) => self.k18.validate(),
            Some((_, DopKind::K26)) => self.k26.validate(),
        }
    }

    /// The clustering computed by the last [`Method::Cluster`] query (empty before the first).
    pub fn clustering(&self) -> &crate::broad::cluster::Clustering {
        &self.cluster.clustering
    }

    /// With `true`, [`Method::Cluster`] treats every leaf cluster as uncertified: its
    /// candidates are then exactly those of [`Method::Bvh`]. A check of the traversal.
    pub fn distrust_certificates(&mut self, distrust: bool) {
        self.cluster.distrust = distrust;
    }
}

/// The candidate feature pairs of the last query (feature `internals`).
#[cfg(feature = "internals")]
#[derive(Clone, Copy, Debug)]
pub struct Candidates<'a> {
    /// `[vertex, face]` pairs.
    pub vf: &'a [[u32; 2]],
    /// `[e, f]` pairs of indices into [`Candidates::edges`], `e < f`.
    pub ee: &'a [[u32; 2]],
    /// The step's edges, `[i, j]` with `i < j`, sorted lexicographically.
    pub edges: &'a [[u32; 2]],
}

/// One-shot form of [`Ccd::query`] (allocates fresh buffers).
///
/// ```
/// use topoccd::{query, Method, QueryOptions, Step};
/// let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.2, 1.0], [0.3, 0.2, 1.5], [0.2, 0.3, 1.5]];
/// let mut x1 = x0;
/// for p in &mut x1[3..] { p[2] -= 2.0; }
/// let step = Step::new(&x0, &x1, &[[0u32, 1, 2], [3, 4, 5]])?;
/// let options = QueryOptions::default();
/// let bvh = query(&step, Method::Bvh, &options)?;
/// let brute = query(&step, Method::Brute, &options)?;
/// assert!(bvh.contact_count() > 0);
/// assert_eq!((bvh.vf, bvh.ee), (brute.vf, brute.ee));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn query(
    step: &Step<'_>,
    method: Method,
    options: &QueryOptions,
) -> Result<Report, OptionsError> {
    Ccd::new().query(step, method, options)
}
