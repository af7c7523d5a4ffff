//! The whole-step query: [`Ccd`] keeps scratch memory across steps; [`query`] is the one-shot
//! form. The pipeline: features and pair filter ([`mesh`](crate::mesh)), one broad phase
//! ([`broad`](crate::broad)), the narrow phase, the report.

use std::sync::Arc;
use std::time::Instant;

use crate::contact::limits::{CancelToken, Limits, Phase, StopReason, Truncation};
use crate::contact::driver::{self as narrow_phase, Context, FirstPass, Found, Stream};
use crate::contact::report::{Contact, Report, Seconds, Stats};
use super::{Method, OptionsError, QueryOptions};
use crate::broad::brute::Brute;
use crate::broad::bvh::BvhPhase;
use crate::broad::cluster::phase::ClusterPhase;
use crate::broad::tasks::{Out, Passes, TaskBuffers, Totals, TASK_CHUNK};
use crate::broad::codim::combined_edges;
use crate::broad::{self, BroadInput, BroadPhase, BroadStats, Candidates, CHUNK};
use crate::contact::report::split_points;
use crate::mesh::codim::Codim;
use crate::bvh::BvhWorkspace;
use crate::kdop::DopKind;
use crate::mesh::features::Features;
use crate::mesh::filter::PairFilter;
use crate::mesh::star::Stars;
use crate::mesh::Step;
use crate::narrow::Certainty;

/// A reusable whole-step CCD query. Keep one per simulation and call [`Ccd::query`] every step:
/// its buffers (hierarchy, candidate pairs, per-feature data) are reused, and the topology may
/// change freely from one step to the next. What it carries over is checked, never trusted:
/// the topology and the per-step hierarchy's shape are kept only for the very same triangles
/// (compared exactly), the hierarchy refitted to the new volumes; the cluster method's leaves
/// are re-certified on the new positions.
#[derive(Clone, Debug, Default)]
pub struct Ccd {
    features: Features,
    canon: Vec<u32>,
    /// Rule 6 of the pair filter: the certified vertex stars.
    stars: Stars,
    /// With `true`, rule 6 is off (for the crate's tests, [`Ccd::distrust_stars`]).
    distrust_stars: bool,
    ws: BvhWorkspace,
    /// The broad phases' states, each kept across steps ([`BroadPhase`]).
    bvh: BvhPhase,
    cluster: ClusterPhase,
    /// With `record`, every candidate of the last query (for the crate's tests).
    recorded: Candidates,
    record: bool,
    /// Buffer limits (candidate pairs) of a traversal task and of a sequential broad phase;
    /// `0` means the default ([`TASK_CHUNK`], [`CHUNK`]).
    limits: (usize, usize),
    /// The method and k-DOP type of the last hierarchy built, if the last query built one.
    last_tree: Option<(Method, DopKind)>,
    /// Stops the queries from another thread ([`Ccd::cancel_token`]).
    cancel: CancelToken,
    /// With free edges or points: the driver's edges (`broad::codim::combined_edges`).
    codim_edges: Vec<[u32; 2]>,
    /// The traversal tasks' candidate buffers, kept across steps.
    task_buffers: TaskBuffers,
    /// The proximity query's primitives and hierarchy ([`Ccd::proximity`]).
    pub(crate) proximity: crate::proximity::State,
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
    /// pair filter (see [`Step`]), and come within `options.narrow.min_distance` during
    /// `[0, options.narrow.tmax]`, is reported with the elementary tests' conservative time of
    /// impact and its [`Certainty`], in [`Mode::All`](super::Mode::All); only the earliest
    /// pair(s) in [`Mode::Earliest`](super::Mode::Earliest). Each feature pair is tested at
    /// most once. The result does not depend on the method, the thread count or earlier
    /// queries. A step with edges ([`Step::with_edges`]) adds the pairs of its free edges and
    /// points ([`Report::ve`], [`Report::vv`]): every method finds them with the same sort and
    /// sweep, after its triangle work.
    ///
    /// Inside the input range ([`range`](crate::range): finite coordinates, differences
    /// within a pair up to `1e300`, at any uniform scale) every guarantee holds; a pair
    /// outside it is a contact at 0, [`Certainty::InvalidInput`], never `Resolved`.
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
        self.run(step, method, options, None)
    }

    /// [`Ccd::query`] in [`Mode::All`](super::Mode::All) that hands every contact to `each` as
    /// it is found, and keeps none: memory stays bounded however many contacts the step has.
    /// `each` is called from the query's threads, in no particular order (the contacts, each
    /// once, are those [`Ccd::query`] reports, with their times). The report returned has no
    /// contacts, but its `earliest` contact, its statistics and
    /// [`truncated`](Report::truncated). With
    /// [`max_contacts`](QueryOptions::max_contacts), at most that many are handed over (which
    /// ones depends on timing), then the query stops, truncated. Refuses
    /// [`Mode::Earliest`](super::Mode::Earliest) ([`OptionsError::Streaming`]), whose pairs are
    /// known only at the end.
    ///
    /// ```
    /// use std::sync::atomic::{AtomicUsize, Ordering};
    /// use topoccd::{Ccd, Method, QueryOptions, Step};
    /// let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
    ///           [0.2, 0.2, 1.0], [0.3, 0.2, 1.5], [0.2, 0.3, 1.5]];
    /// let mut x1 = x0;
    /// for p in &mut x1[3..] { p[2] -= 2.0; }
    /// let step = Step::new(&x0, &x1, &[[0u32, 1, 2], [3, 4, 5]])?;
    /// let count = AtomicUsize::new(0);
    /// let mut ccd = Ccd::new();
    /// let report = ccd.for_each_contact(&step, Method::Bvh, &QueryOptions::default(), |_c| {
    ///     count.fetch_add(1, Ordering::Relaxed); // e.g. write it to a file under a lock
    /// })?;
    /// let all = ccd.query(&step, Method::Bvh, &QueryOptions::default())?;
    /// assert_eq!(count.into_inner(), all.contact_count());
    /// assert_eq!(report.earliest, all.earliest);
    /// assert!(report.vf.is_empty() && report.truncated.is_none());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn for_each_contact(
        &mut self,
        step: &Step<'_>,
        method: Method,
        options: &QueryOptions,
        each: impl Fn(&Contact) + Sync,
    ) -> Result<Report, OptionsError> {
        if options.mode == super::Mode::Earliest {
            return Err(OptionsError::Streaming);
        }
        let stream = Stream::new(&each);
        self.run(step, method, options, Some(&stream))
    }

    /// A handle on this query object's [`CancelToken`]: cancelling it (from any thread) stops
    /// the query running, and every later one until the token is reset. Clones of a `Ccd`
    /// share its token.
    pub fn cancel_token(&self) -> CancelToken {
        self.cancel.clone()
    }

    /// Makes this query object obey `token` (e.g. one token for the `Ccd`s of several
    /// threads).
    pub fn set_cancel_token(&mut self, token: CancelToken) {
        self.cancel = token;
    }

    /// The query, its contacts kept in the report or handed to `stream`: the step's features,
    /// stars and pair filter, then one broad phase ([`BroadPhase`]), which runs the narrow
    /// phase on its candidates, then the report.
    fn run(
        &mut self,
        step: &Step<'_>,
        method: Method,
        options: &QueryOptions,
        stream: Option<&Stream<'_>>,
    ) -> Result<Report, OptionsError> {
        if rayon::current_thread_index().is_some() {
            return self.run_in_pool(step, method, options, stream);
        }
        // Called from outside the thread pool (the main thread of a program), each parallel
        // part of the query would hand its work to the pool and wait: a dozen hand-offs a
        // step. The whole query goes to the pool instead, as one job.
        rayon::scope(|_| self.run_in_pool(step, method, options, stream))
    }

    /// [`Ccd::run`] on a thread of the current pool.
    fn run_in_pool(
        &mut self,
        step: &Step<'_>,
        method: Method,
        options: &QueryOptions,
        stream: Option<&Stream<'_>>,
    ) -> Result<Report, OptionsError> {
        options.validate()?;
        let method = method.resolve(step.triangles().len());
        let start = Instant::now();
        let limits = Arc::new(Limits::new(
            options.max_contacts,
            options.deadline,
            Some(self.cancel.clone()),
        ));
        let sep = options.narrow.min_distance;
        // The triangles of the last step again (a simulator's everyday step): the topology is
        // kept, and the per-step hierarchy refitted.
        let same = self.features.same_topology(step);
        // Rule 6 of the pair filter (certified vertex stars) holds for contact only.
        let stars_on = sep == 0.0 && !self.distrust_stars;
        self.prepare(step, method, options, same, stars_on);
        self.last_tree = None;
        let filter = PairFilter::new(
            step,
            sep,
            options.narrow.tmax,
            options.crack_filter,
            &mut self.canon,
            stars_on.then(|| self.stars.view(step, &self.features.topo)),
        );
        let input = BroadInput {
            step,
            features: &self.features,
            filter: &filter,
        };
        let prepared = start.elapsed().as_secs_f64();
        let ctx = Context {
            limits: &limits,
            stream,
            step,
            edges: &self.features.topo.edges,
            options,
            coord: filter.coord(),
            first: FirstPass::new(step, &self.features.topo, options),
            whole: None,
        };
        let mut found = Found::default();
        // Where a stop found the query: before the candidates (the build), or among them.
        let built = !limits.poll(true);
        let mut totals = Totals::default();
        let recorded = &mut self.recorded;
        recorded.clear();
        let passes = Passes {
            input: &input,
            ctx: &ctx,
            limits: &limits,
            record: self.record,
            task_chunk: if self.limits.0 == 0 { TASK_CHUNK } else { self.limits.0 },
            chunk: if self.limits.1 == 0 { CHUNK } else { self.limits.1 },
            buffers: &self.task_buffers,
        };
        let out = Out {
            found: &mut found,
            totals: &mut totals,
            recorded,
        };
        let (phase, ws): (&mut dyn BroadPhase, _) = match method {
            Method::Bvh => (&mut self.bvh, &mut self.ws),
            Method::Cluster => (&mut self.cluster, &mut self.ws),
            Method::Brute => (&mut Brute, &mut self.ws),
            Method::Auto => unreachable!("Method::resolve never returns Auto"),
        };
        let broad = if built {
            phase.run(&passes, ws, out)
        } else {
            BroadStats::default()
        };
        if built && method != Method::Brute {
            self.last_tree = Some((method, options.kdop));
        }
        // Free edges and points: their pairs, after the triangles', the same for every method.
        let codim = Codim::new(step, &self.features.topo).filter(|c| !c.is_empty());
        let mut broad = broad;
        let codim_edges = &mut self.codim_edges;
        let topo_edges = &self.features.topo.edges;
        if let Some(codim) = codim.as_ref().filter(|&c| {
            built
                && !limits.poll(true)
                && limits.check(combined_edges(topo_edges, c, codim_edges))
        }) {
            let mesh = self.features.topo.edges.len();
            let ctx = Context {
                edges: &self.codim_edges,
                first: None,
                whole: None,
                ..ctx
            };
            let chunk = if self.limits.1 == 0 { CHUNK } else { self.limits.1 };
            let more = broad::codim::run(&input, codim, (&ctx, mesh), chunk, &mut found, &mut totals);
            broad.bv_tests += more.bv_tests;
            broad.build += more.build;
            broad.traverse += more.traverse;
            broad.narrow += more.narrow;
        }
        let BroadStats {
            bv_tests,
            build,
            traverse,
            mut narrow,
            cluster,
        } = broad;
        if let Some(failure) = limits.failure() {
            // An allocation failed: the query wound down; what it holds is freed on return.
            return Err(failure.into());
        }
        let t = Instant::now();
        let by_time = matches!(
            limits.stopped(),
            Some(StopReason::Deadline | StopReason::Cancelled)
        );
        let mut complete = true;
        let earliest = if by_time {
            // What was found by then depends on timing: the report keeps the earliest.
            found.earliest_only()
        } else if stream.is_some() {
            found.streamed
        } else {
            let earliest = narrow_phase::finish(&mut found, options)?;
            complete = narrow_phase::earliest_complete(&found, earliest, options);
            earliest
        };
        narrow += t.elapsed().as_secs_f64();
        let truncated = limits.stopped().map(|reason| Truncation {
            reason,
            phase: if built {
                Phase::Candidates
            } else {
                Phase::Build
            },
            tasks: totals.tasks,
        });
        let unresolved = found.streamed_unresolved
            + found
                .vf
                .iter()
                .filter(|c| c.certainty != Certainty::Resolved)
                .count()
            + found
                .ee
                .iter()
                .filter(|c| c.certainty != Certainty::Resolved)
                .count();
        let (ve, vv) = if codim.is_some() {
            split_points(&mut found.ee)?
        } else {
            Default::default()
        };
        Ok(Report {
            vf: found.vf,
            ee: found.ee,
            ve,
            vv,
            earliest,
            unresolved,
            earliest_complete: complete && truncated.is_none(),
            truncated,
            stats: Stats {
                method,
                bv_tests,
                vf_tests: totals.vf_tests,
                ee_tests: totals.ee_tests,
                peak_candidates: totals.peak as u64,
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

    /// The step's features and stars and, for the per-step hierarchy, its tree (beside them:
    /// it needs the positions only, so on two threads or more it is built at the same time).
    /// `same`: the step has the triangles of the last query; `stars_on`: rule 6 of the pair
    /// filter applies (no minimum separation).
    fn prepare(
        &mut self,
        step: &Step<'_>,
        method: Method,
        options: &QueryOptions,
        same: bool,
        stars_on: bool,
    ) {
        if method == Method::Bvh {
            // The per-step hierarchy needs the positions only: it is built beside the topology
            // and the features (at the same time on two threads or more), and asks about every
            // star, all certified at once. (A tree is refitted only if the last query built
            // this very tree, so over the same triangles; with a first look at the start of the
            // step, the features' boxes are swept over that start.)
            let refit = same && self.last_tree == Some((Method::Bvh, options.kdop));
            let boxes_end = self.bvh.boxes_end(options);
            let (features, stars, bvh, ws) =
                (&mut self.features, &mut self.stars, &mut self.bvh, &mut self.ws);
            let prepare = || {
                features.update(step, same, boxes_end);
                stars.reset(step.vertex_count(), same);
                if stars_on {
                    stars.certify_all(step, &features.topo);
                }
            };
            rayon::join(prepare, || bvh.build(step, options, refit, ws));
            // Rule 6 before the volumes: the traversal drops neighbours in a certified star.
            let topo = &self.features.topo;
            let view = stars_on.then(|| self.stars.view(step, topo));
            self.bvh
                .mark_stars(options.kdop, view, topo, step.triangles());
        } else {
            self.features.update(step, same, 1.0);
            self.stars.reset(step.vertex_count(), same);
            // The oracle asks about every star; the cluster method only about those of its
            // clusters' borders, one by one.
            if stars_on && method == Method::Brute {
                self.stars.certify_all(step, &self.features.topo);
            }
        }
    }
}

/// Diagnostics for the crate's own tests (feature `internals`).
#[cfg(feature = "internals")]
impl Ccd {
    /// The candidate feature pairs of the last query, recorded with
    /// [`Ccd::record_candidates`]: exactly the pairs given to the narrow phase
    /// ([`Stats::vf_tests`], [`Stats::ee_tests`]), each once.
    pub fn candidates(&self) -> CandidatePairs<'_> {
        CandidatePairs {
            vf: &self.recorded.vf,
            ee: &self.recorded.ee,
            edges: &self.features.topo.edges,
        }
    }

    /// Sets the most candidate pairs a buffer holds before the narrow phase takes it: per task
    /// of the parallel traversal, and for the sequential broad phases (`0`: the default).
    pub fn set_buffer_limits(&mut self, task: usize, sequential: usize) {
        self.limits = (task, sequential);
    }

    /// With `true`, later queries keep every candidate pair for [`Ccd::candidates`] (memory
    /// then grows with the candidates).
    pub fn record_candidates(&mut self, record: bool) {
        self.record = record;
    }

    /// The topology of the last step queried.
    pub fn topology(&self) -> &crate::mesh::Topology {
        &self.features.topo
    }

    /// Runs [`Bvh::validate`](crate::bvh::Bvh::validate) on the hierarchy built by the last
    /// query, `step` (for [`Method::Cluster`]: on every level of its hierarchy), against the
    /// volumes of the step's triangles. `Ok` when the last query built none (as
    /// [`Method::Brute`] does).
    pub fn validate_tree(&self, step: &Step<'_>) -> Result<(), crate::bvh::BvhError> {
        match self.last_tree {
            None => Ok(()),
            Some((Method::Cluster, kind)) => self.cluster.validate(kind),
            Some((_, kind)) => self.bvh.validate(kind, step),
        }
    }

    /// Whether the last query's per-step hierarchy ([`Method::Bvh`]) was the one of the step
    /// before, refitted to this step's volumes (the same triangles again), rather than rebuilt.
    pub fn tree_refitted(&self) -> bool {
        match self.last_tree {
            Some((Method::Bvh, kind)) => self.bvh.refitted(kind),
            _ => false,
        }
    }

    /// The clustering computed by the last [`Method::Cluster`] query (empty before the first).
    pub fn clustering(&self) -> &crate::broad::cluster::Clustering {
        &self.cluster.clustering
    }

    /// Whether the last [`Method::Cluster`] query, on `step`, put the features `a` and `b` (a
    /// vertex, an edge or a face, by their vertices) in one intermediate cluster, whose
    /// certificate proves that they never touch: the only pairs that method may leave out where
    /// the other methods report a contact, one the elementary test cannot tell from a touch
    /// (see [`Method`]). A scan of the step's triangles, for checks of a report.
    pub fn cluster_holds_both(&self, step: &Step<'_>, a: &[u32], b: &[u32]) -> bool {
        self.cluster.clustering.holds_both(step.triangles(), a, b)
    }

    /// With `true`, rule 6 of the pair filter is off: no vertex star counts as certified, and
    /// the neighbours in one give their candidates as with a minimum separation. A check of
    /// the certificate: the contacts must not change.
    pub fn distrust_stars(&mut self, distrust: bool) {
        self.distrust_stars = distrust;
    }

    /// With `true`, [`Method::Cluster`] treats every leaf cluster as uncertified: its
    /// candidates are then exactly those of [`Method::Bvh`]. A check of the traversal.
    pub fn distrust_certificates(&mut self, distrust: bool) {
        self.cluster.distrust = distrust;
    }

    /// On two threads or more, [`Method::Cluster`] builds the hierarchy over a leaf cluster's
    /// triangles while the other leaves grow when it has at least `triangles` triangles
    /// (`None`: the default, 1,024), whether or not the traversal will need it.
    pub fn set_ahead_triangles(&mut self, triangles: Option<usize>) {
        self.cluster.ahead = triangles;
    }

    /// How many of the lazy hierarchies of the last [`Method::Cluster`] query had been built
    /// ahead (see [`Ccd::set_ahead_triangles`]).
    pub fn lazy_built_ahead(&self) -> usize {
        self.cluster.last_ahead
    }

    /// Sets how many leaf pairs [`Method::Cluster`]'s traversal lists before their triangle
    /// pairs go to the narrow phase (`None`: the default, 2^19; `Some(0)` counts as 1). A query
    /// that stops (its cap reached) lists no further chunk; the contacts are those of the
    /// chunks' tasks in order, so a capped report may depend on this size, an uncapped one not.
    pub fn set_cluster_chunk(&mut self, items: Option<usize>) {
        self.cluster.chunk = items;
    }

    /// How many chunks of leaf pairs the last [`Method::Cluster`] query listed (see
    /// [`Ccd::set_cluster_chunk`]).
    pub fn cluster_chunks(&self) -> usize {
        self.cluster.last_chunks
    }
}

/// The candidate feature pairs of the last query (feature `internals`).
#[cfg(feature = "internals")]
#[derive(Clone, Copy, Debug)]
pub struct CandidatePairs<'a> {
    /// `[vertex, face]` pairs.
    pub vf: &'a [[u32; 2]],
    /// `[e, f]` pairs of indices into [`CandidatePairs::edges`], `e < f`.
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
