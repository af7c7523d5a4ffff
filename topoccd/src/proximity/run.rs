//! The proximity query: [`Ccd::proximity`] (its primitives and hierarchy kept in the `Ccd`)
//! and the one-shot [`proximity`].

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use crate::alloc::AllocError;
use crate::bvh::{BvhWorkspace, ParOptions, TestAll};
use crate::query::{CancelToken, StopReason};
use crate::Ccd;

use super::boxes::{inflation, largest_side};
use super::brute::brute;
use super::cache::{evaluate, list_threshold, Cache};
use super::features::FeatureTree;
use super::pairs::{Found, Test};
use super::primitives::Primitives;
use super::report::ProximityStats;
use super::slots::Slots;
use super::tree::ProximityTree;
use super::{Configuration, ProximityError, ProximityMethod, ProximityOptions, ProximityReport};

/// What a [`Ccd`] keeps for its proximity queries: the primitives and their hierarchy.
#[derive(Clone, Debug, Default)]
pub(crate) struct State {
    pub(super) prims: Primitives,
    pub(super) tree: ProximityTree,
    /// The trees of feature leaves (see `features`).
    pub(super) features: FeatureTree,
    pub(super) slots: Slots,
    cache: Cache,
    pub(super) ws: BvhWorkspace,
}

/// The deadline and the cancel token of one query, and whether it stopped (and why).
pub(crate) struct Stop<'a> {
    deadline: Option<Instant>,
    cancel: &'a CancelToken,
    stopped: AtomicBool,
    cancelled: AtomicBool,
}

impl<'a> Stop<'a> {
    /// No deadline; stopped only by `cancel` (for the floor's timings).
    #[cfg_attr(not(feature = "internals"), allow(dead_code))]
    pub fn cancel_only(cancel: &'a CancelToken) -> Self {
        Stop {
            deadline: None,
            cancel,
            stopped: AtomicBool::new(false),
            cancelled: AtomicBool::new(false),
        }
    }

    /// Whether the query must stop now (and records it).
    pub fn check(&self) -> bool {
        if self.stopped.load(Ordering::Relaxed) {
            return true;
        }
        let cancelled = self.cancel.is_cancelled();
        if cancelled || self.deadline.is_some_and(|d| Instant::now() >= d) {
            self.cancelled.store(cancelled, Ordering::Relaxed);
            self.stopped.store(true, Ordering::Relaxed);
            return true;
        }
        false
    }

    fn reason(&self) -> Option<StopReason> {
        self.stopped.load(Ordering::Relaxed).then(|| {
            if self.cancelled.load(Ordering::Relaxed) {
                StopReason::Cancelled
            } else {
                StopReason::Deadline
            }
        })
    }
}

impl Ccd {
    /// Every primitive pair of `config` closer than `options.dhat + options.dmin`: vertex-face,
    /// edge-edge (triangles' edges and free edges), free point-free edge and free point-free
    /// point,
    /// with the distance and the closest features' type, after checking `options`. Features
    /// that share a vertex are not paired; groups and `can_collide` apply.
    ///
    /// No pair closer than the threshold is missed; a pair is reported beyond it only within
    /// the rounding bound of [`crate::distance::rounding_bound`] (relative to the pair's size).
    /// The primitives and their hierarchy are kept in this `Ccd`: while the triangles, edges
    /// and vertex count stay the same (compared exactly every call), the hierarchy is refitted
    /// to the new positions, not rebuilt. Runs on the caller's rayon pool; the report is the
    /// same for any thread count.
    ///
    /// A pair can repeat: every primitive pair is reported by its closest features, so a
    /// vertex near an edge or corner of the mesh comes back once for each face around it
    /// (`vf` pairs of the edge or corner types). The potentials' collision set
    /// (`topoccd::ipc::NormalCollisions`) merges repeats with their count as multiplicity.
    /// The report keeps at most [`ProximityOptions::max_contacts`] pairs (one million by
    /// default).
    ///
    /// ```
    /// use topoccd::{Ccd, Configuration, ProximityOptions};
    /// use topoccd::distance::PointTriangleType;
    /// // A vertex (3) 0.5e-3 above a triangle, and a far one (4).
    /// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.2, 0.5e-3], [0.2, 0.2, 1.0]];
    /// let config = Configuration::new(&x, &[[0u32, 1, 2]], &[[3, 4]])?;
    /// let mut ccd = Ccd::new(); // keep it across a solver's iterations
    /// let report = ccd.proximity(&config, &ProximityOptions { dhat: 1e-3, ..Default::default() })?;
    /// assert_eq!(report.vf.len(), 1);
    /// assert_eq!((report.vf[0].vertex, report.vf[0].face), (3, 0));
    /// assert_eq!(report.vf[0].kind, PointTriangleType::Interior);
    /// assert!((report.vf[0].distance - 0.5e-3).abs() < 1e-15);
    /// # Ok::<(), topoccd::ProximityError>(())
    /// ```
    pub fn proximity(
        &mut self,
        config: &Configuration<'_>,
        options: &ProximityOptions,
    ) -> Result<ProximityReport, ProximityError> {
        options.validate()?;
        let token = self.cancel_token();
        let state = &mut self.proximity;
        let report = if rayon::current_thread_index().is_some() {
            state.run(config, options, &token)
        } else {
            // One job on the pool rather than a hand-off per parallel part.
            rayon::scope(|_| state.run(config, options, &token))
        };
        Ok(report?)
    }
}

/// [`Ccd::proximity`] with a fresh `Ccd` (for one configuration; a solver keeps a `Ccd`).
///
/// ```
/// use topoccd::{proximity, Configuration, ProximityOptions};
/// // Two free points 1e-4 apart, and a third far away.
/// let x = [[0.0, 0.0, 0.0], [1e-4, 0.0, 0.0], [1.0, 0.0, 0.0]];
/// let config = Configuration::new(&x, &[] as &[[u32; 3]], &[])?;
/// let report = proximity(&config, &ProximityOptions { dhat: 1e-3, ..Default::default() })?;
/// assert_eq!((report.vv[0].a, report.vv[0].b), (0, 1));
/// assert_eq!(report.len(), 1);
/// # Ok::<(), topoccd::ProximityError>(())
/// ```
pub fn proximity(
    config: &Configuration<'_>,
    options: &ProximityOptions,
) -> Result<ProximityReport, ProximityError> {
    Ccd::new().proximity(config, options)
}

/// The distance test of a query on `config`.
pub(super) fn test<'a>(config: &'a Configuration<'_>, options: &ProximityOptions) -> Test<'a> {
    let step = config.step();
    Test {
        x: config.pos(),
        r: options.threshold(),
        groups: step.groups(),
        can_collide: step.can_collide(),
        r_list: 0.0,
    }
}

impl State {
    /// The features' boxes inflated by `h`, the hierarchy (refitted or built) and the leaves'
    /// layout at the positions of `config`. Returns whether the hierarchy was refitted.
    pub(super) fn fit(&mut self, config: &Configuration<'_>, h: f64) -> bool {
        let x = config.pos();
        let refitted = self.tree.fit(&self.prims, x, h, &mut self.ws);
        if !refitted {
            self.slots.arrange(&self.prims, &self.tree.bvh);
        }
        self.slots.fit(x, h);
        refitted
    }

    /// Every pair of `test`, by the triangle tree's leaf pairs, under a cap of `max` pairs
    /// (the same answer for any thread count): the traversal's tasks in their fixed order,
    /// each stopping at `max` pairs ([`Found::full`]), until the pairs taken reach `max`.
    /// Under a cap the tasks run a batch of twice the threads at a time, so that no more
    /// than `max` pairs per task of a batch are held beside the `max` taken.
    fn by_leaves(&mut self, test: &Test<'_>, stop: &Stop, max: usize) -> (Found, u64) {
        let listed = AtomicUsize::new(0);
        // Once an allocation failed no other task starts (the query returns the failure).
        let failed = AtomicBool::new(false);
        let mut found = Found::default();
        let slots = &self.slots;
        let skip = |_: &Found| failed.load(Ordering::Relaxed) || stop.check();
        let leaf_pair = |acc: &mut Found, a: u32, b: u32| {
            if !acc.full(max, listed.load(Ordering::Relaxed)) {
                test.leaf_pair(slots, a, b, acc);
            }
        };
        let finish = |acc: &mut Found| {
            listed.fetch_add(acc.cands.len(), Ordering::Relaxed);
            if acc.failure.is_some() {
                failed.store(true, Ordering::Relaxed);
            }
        };
        let consume = |mut f: Found| {
            if found.len() >= max {
                // Past the cap: this batch's later tasks are left out.
                found.capped = true;
                ControlFlow::Break(())
            } else if found.append(&mut f).is_err() {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        };
        let par = ParOptions {
            batch: if max == usize::MAX {
                usize::MAX
            } else {
                2 * rayon::current_num_threads()
            },
            ..ParOptions::default()
        };
        let visits = self.tree.bvh.par_self_pairs_until(
            &mut self.ws,
            &par,
            &TestAll,
            |_| Found::default(),
            leaf_pair,
            finish,
            consume,
            &skip,
        );
        found.unlist_beyond(max, 0);
        (found, visits)
    }

    fn run(
        &mut self,
        config: &Configuration<'_>,
        options: &ProximityOptions,
        token: &CancelToken,
    ) -> Result<ProximityReport, AllocError> {
        let start = Instant::now();
        let stop = Stop {
            deadline: options.deadline,
            cancel: token,
            stopped: AtomicBool::new(false),
            cancelled: AtomicBool::new(false),
        };
        if !self.prims.same(config) {
            self.prims.derive(config);
            self.tree.invalidate();
            self.features.invalidate();
            self.cache.clear();
        }
        let mut test = test(config, options);
        let mut stats = ProximityStats::default();
        let mut capped = false;
        let max = options.max_contacts.unwrap_or(usize::MAX);
        let found = match options.method {
            ProximityMethod::Brute => {
                stats.build_seconds = start.elapsed().as_secs_f64();
                brute(&self.prims, config.triangles(), &test, &stop)
            }
            ProximityMethod::Bvh | ProximityMethod::TriangleTree => {
                let (x, r) = (test.x, test.r);
                // The pairs kept across a solver's iterations (see `cache`): not under a
                // deadline, whose pairs depend on the order of work, nor with groups or a
                // predicate, which may change from one query to the next. Under a cap they
                // are kept and reused while the query stays under it (then the answer is the
                // uncapped one); a query that reaches the cap traverses, so that its pairs are
                // those of the first tasks of the fixed order of work, and keeps nothing. Nor
                // does a query whose listing outgrows `pairs::list_cap`.
                let plain = options.deadline.is_none()
                    && test.groups.is_none()
                    && test.can_collide.is_none();
                let cached = if plain {
                    self.cache.covering(x, r)
                } else {
                    None
                };
                let moved = if plain { self.cache.moved(x) } else { None };
                let reused = cached
                    .filter(|_| !stop.check())
                    .map(|cands| evaluate(cands, config.triangles(), &test))
                    .filter(|f| f.len() <= max);
                let found = if let Some(f) = reused {
                    stats.refitted = true;
                    stats.reused = true;
                    stats.build_seconds = start.elapsed().as_secs_f64();
                    f
                } else {
                    let allowance = if plain {
                        self.cache.allowance(moved, r)
                    } else {
                        0.0
                    };
                    let big = largest_side(&self.prims, config.triangles(), x);
                    if allowance > 0.0 {
                        test.r_list = list_threshold(r, allowance, big);
                    }
                    let h = inflation(big, x, r.max(test.r_list));
                    // The feature trees, unless under a deadline (whose pairs are the first
                    // of the triangle leaves' order of work) or asked for the triangle leaves.
                    let mut found;
                    if options.method == ProximityMethod::Bvh && options.deadline.is_none() {
                        let ws = &mut self.ws;
                        stats.refitted = self.features.fit(&self.prims, x, h, ws);
                        stats.build_seconds = start.elapsed().as_secs_f64();
                        (found, stats.bv_tests) = self.features.find(&test, &stop, max);
                    } else {
                        stats.refitted = self.fit(config, h);
                        stats.build_seconds = start.elapsed().as_secs_f64();
                        (found, stats.bv_tests) = self.by_leaves(&test, &stop, max);
                    }
                    capped |= found.capped;
                    let cands = std::mem::take(&mut found.cands);
                    if let Some(failure) = found.failure {
                        // What was found is freed; the listing is not complete.
                        self.cache.drop_listing();
                        return Err(failure);
                    }
                    if test.r_list > 0.0 && stop.reason().is_none() && !capped && !found.unlisted {
                        self.cache.keep(x, r, allowance, cands);
                    } else if plain {
                        // (A capped query leaves the listing: still valid where it covers.)
                        self.cache.drop_listing();
                    }
                    found
                };
                if plain {
                    self.cache.seen(x, moved);
                }
                found
            }
        };
        if let Some(failure) = found.failure {
            return Err(failure);
        }
        let t = Instant::now();
        stats.distance_tests = found.tests;
        let mut report = ProximityReport {
            vf: found.vf,
            ee: found.ee,
            ve: found.ve,
            vv: found.vv,
            truncated: None,
            stats,
        };
        report.sort();
        if report.len() > max {
            report.truncate(max);
            capped = true;
        }
        report.truncated = stop.reason().or(capped.then_some(StopReason::MaxContacts));
        report.stats.traverse_seconds =
            t.elapsed().as_secs_f64() + (t - start).as_secs_f64() - report.stats.build_seconds;
        report.stats.total_seconds = start.elapsed().as_secs_f64();
        Ok(report)
    }
}
