//! The per-step hierarchy as one broad phase: a tree for each k-DOP kind, kept across steps,
//! and its passes over a step (in [`Mode::Earliest`](crate::Mode::Earliest), a first look at
//! the start of the step, then the whole step if that was not enough).

use std::time::Instant;

use super::PerStepBvh;
use crate::broad::tasks::{traverse_pass, Out, Passes};
use crate::broad::{BroadPhase, BroadStats};
use crate::bvh::{BvhError, BvhWorkspace};
use crate::kdop::DopKind;
use crate::mesh::features::FeatureBoxes;
use crate::mesh::star::StarView;
use crate::mesh::{Step, Topology};
use crate::contact::driver::{first_pass_tau, lower, Context, Found, WholeStep, EARLY};
use crate::contact::{Mode, QueryOptions};

/// The per-step hierarchy's state across steps: one tree per k-DOP kind (the kind of the last
/// query's), the features' boxes of an Earliest query's second pass, and whether the last
/// Earliest query found its contact late.
#[derive(Clone, Debug, Default)]
pub(crate) struct BvhPhase {
    k6: PerStepBvh<3>,
    k14: PerStepBvh<7>,
    k18: PerStepBvh<9>,
    k26: PerStepBvh<13>,
    /// The features' boxes over the whole step, for the second pass of an Earliest query
    /// whose first pass (which sweeps the features' own boxes over the start of the step only)
    /// did not find the answer; swept only then.
    late_boxes: FeatureBoxes,
    /// Whether the last Earliest query found its earliest contact late (after the step's first
    /// `1 / EARLY`): the next one then skips the first pass.
    late: bool,
    /// Whether the next first pass looks at every task: set when the last one did not give
    /// the answer and the second pass then found an early contact (one beyond the first
    /// pass's first batch, where it stopped); cleared when a contact comes late.
    whole_first: bool,
    /// The end of this step's first pass, if it makes one ([`BvhPhase::first_end`]).
    first_end: Option<f64>,
}

/// Dispatches on the k-DOP kind: `$f` applied to the tree of that kind.
macro_rules! with_tree {
    ($self:ident, $kind:expr, |$t:ident| $body:expr) => {
        match $kind {
            DopKind::K6 => {
                let $t = &mut $self.k6;
                $body
            }
            DopKind::K14 => {
                let $t = &mut $self.k14;
                $body
            }
            DopKind::K18 => {
                let $t = &mut $self.k18;
                $body
            }
            DopKind::K26 => {
                let $t = &mut $self.k26;
                $body
            }
        }
    };
}

impl BvhPhase {
    /// Fits the tree of `options.kdop` to the step (see [`PerStepBvh::build`]): over the start
    /// of the step when this query makes a first pass, else over `[0, tmax]`. `same_triangles`:
    /// the last query built this very tree over the same triangles. Returns the end of the
    /// features' boxes the query needs: the first pass's, or the whole step (1).
    pub fn build(
        &mut self,
        step: &Step<'_>,
        options: &QueryOptions,
        same_triangles: bool,
        ws: &mut BvhWorkspace,
    ) {
        self.first_end = first_pass_end(options, !self.late);
        let end = (
            self.first_end.unwrap_or(options.narrow.tmax),
            options.narrow.min_distance,
        );
        with_tree!(self, options.kdop, |t| t.build(step, end, same_triangles, ws))
    }

    /// The end of the times the features' boxes are swept over for this query: the first
    /// pass's, or the whole step (`1`). Decided by [`BvhPhase::build`]'s rule, so it may be
    /// asked before the build (for the features, prepared beside it).
    pub fn boxes_end(&self, options: &QueryOptions) -> f64 {
        first_pass_end(options, !self.late).unwrap_or(1.0)
    }

    /// [`PerStepBvh::mark_stars`] on the tree of `kind`, after its build.
    pub fn mark_stars(
        &mut self,
        kind: DopKind,
        stars: Option<StarView<'_>>,
        topo: &Topology,
        tris: &[[u32; 3]],
    ) {
        with_tree!(self, kind, |t| t.mark_stars(stars, topo, tris))
    }

    /// Checks the tree of `kind` against the leaves of `step` ([`PerStepBvh::validate`]).
    pub fn validate(&self, kind: DopKind, step: &Step<'_>) -> Result<(), BvhError> {
        match kind {
            DopKind::K6 => self.k6.validate(step),
            DopKind::K14 => self.k14.validate(step),
            DopKind::K18 => self.k18.validate(step),
            DopKind::K26 => self.k26.validate(step),
        }
    }

    /// Whether the last build of the tree of `kind` refitted it.
    pub fn refitted(&self, kind: DopKind) -> bool {
        match kind {
            DopKind::K6 => self.k6.refitted,
            DopKind::K14 => self.k14.refitted,
            DopKind::K18 => self.k18.refitted,
            DopKind::K26 => self.k26.refitted,
        }
    }
}

impl BroadPhase for BvhPhase {
    /// The passes of the tree [`BvhPhase::build`] fitted to this step ([`bvh_query`]).
    fn run(&mut self, passes: &Passes<'_, '_, '_>, ws: &mut BvhWorkspace, out: Out<'_>) -> BroadStats {
        let (first_end, late_boxes) = (self.first_end, &mut self.late_boxes);
        let options = passes.ctx.options;
        let first_look = first_end.map(|end| (end, self.whole_first));
        let (stats, late, first_failed) = with_tree!(self, options.kdop, |t| {
            bvh_query(t, passes, ws, late_boxes, first_look, out)
        });
        if options.mode == Mode::Earliest {
            self.late = late;
            if late {
                self.whole_first = false;
            } else if first_failed {
                self.whole_first = true;
            }
        }
        stats
    }
}

/// The end `tau` of the first pass of [`bvh_query`] ([`first_pass_tau`]), `None` when there
/// is only one pass (not in Earliest mode, not `early`, or an interval too short to split).
/// Only if the first pass finds no contact early enough does the query look at the whole step.
fn first_pass_end(options: &QueryOptions, early: bool) -> Option<f64> {
    let two_pass = early && options.mode == Mode::Earliest;
    first_pass_tau(options).filter(|_| two_pass)
}

/// The per-step hierarchy's query: the parallel traversal of the hierarchy the caller built,
/// whose tasks solve their own candidates in bounded buffers. Returns the broad phase's
/// figures; the narrow phase's time is inside the traversal's (the two run interleaved on
/// every thread).
///
/// In [`Mode::Earliest`], with `first_look` = `Some((tau, whole))`, `tau` from
/// [`first_pass_end`] (`tau = tmax / EARLY`), a first pass uses triangle volumes and feature
/// boxes (the features' own, swept by the caller over `[0, tau]`) and solves every
/// candidate over `[0, tau]` first. If it finds contacts whose earliest time `b` has
/// `b + 2 tolerance <= tau`, the answer is complete: a pair reported within the tolerance of
/// `b` is reported before `tau`, so its volumes over `[0, tau]` overlap (the narrow phase of
/// every method searches a pair they prove apart from `tau` only, [`FirstPass`](crate::contact::driver::FirstPass), even where
/// rounding keeps it from separating the features) and the first pass tested it. The first
/// pass keeps only contacts of pairs that a query in [`Mode::All`] looks at
/// ([`WholeStep`]), so that Earliest reports only All's pairs. Otherwise the hierarchy is
/// refitted to the volumes swept over `[0, tmax]`, its leaves in `Mode::All`, the features'
/// boxes over the whole step are swept into `late_boxes`, and the hierarchy is traversed
/// again, pruned with whatever the first pass found; pairs found twice are reported once.
/// The first pass pays
/// when contacts are dense at the start of the step (resting contact) and is wasted
/// otherwise, so it stops after its first batch of tasks unless that batch found a contact
/// early enough (or `whole` says to look at every task: the last query's early contact lay
/// beyond its first batch), and [`Ccd`](crate::Ccd) tries it only while the last Earliest
/// query's contact came early (`early`); the answer is the same either way (the second pass
/// alone is complete). Also returns whether this step's earliest contact came late (after
/// `tmax / EARLY`, or none), with one pass or two, and whether a first pass was made and
/// did not give the answer. `tree` must have been built for this
/// step, over `[0, tau]` for two passes, else over `[0, tmax]`.
fn bvh_query<const H: usize>(
    tree: &mut PerStepBvh<H>,
    passes: &Passes<'_, '_, '_>,
    ws: &mut BvhWorkspace,
    late_boxes: &mut FeatureBoxes,
    first_look: Option<(f64, bool)>,
    mut out: Out<'_>,
) -> (BroadStats, bool, bool) {
    let first_end = first_look.map(|(end, _)| end);
    let stop_first = first_look.is_some_and(|(_, whole)| !whole);
    let (input, ctx) = (passes.input, passes.ctx);
    // Whether or not there is a first pass, a contact is late after the first `1 / EARLY`.
    let tau = ctx.options.narrow.tmax / EARLY;
    let two_pass = first_end.is_some();
    let end = first_end.unwrap_or(f64::INFINITY);
    let mut build = 0.0;
    let mut first_failed = false;
    let t = Instant::now();
    // A first pass keeps only contacts that the whole step's pass would look at too.
    let topo = &input.features.topo;
    let first_ctx = Context {
        whole: two_pass.then(|| WholeStep::new(input.step, topo, ctx.options)),
        ..*ctx
    };
    let first = Passes {
        ctx: &first_ctx,
        ..*passes
    };
    let boxes = &input.features.boxes;
    let mut bv_tests = traverse_pass(tree, &first, ws, boxes, (end, stop_first), out.reborrow());
    let mut traverse = t.elapsed().as_secs_f64();
    if two_pass {
        let mut best = None;
        lower(&mut best, out.found.vf.iter().map(|c| c.toi));
        lower(&mut best, out.found.ee.iter().map(|c| c.toi));
        let complete = best.is_some_and(|b| ctx.limit(Some(b)) <= end);
        first_failed = !complete;
        if !complete && ctx.limits.stopped().is_none() {
            if ctx.limits.capped() {
                // The second pass finds again, with the same times, every contact of the
                // first that the report can hold, in its own order, which a cap follows.
                *out.found = Found::default();
            }
            let t = Instant::now();
            tree.refit_until_t_max(input);
            late_boxes.sweep(input.step, 1.0);
            build += t.elapsed().as_secs_f64();
            let t = Instant::now();
            let limit = ctx.limit(best);
            bv_tests += traverse_pass(tree, passes, ws, late_boxes, (limit, false), out.reborrow());
            // A contact of the first pass is found again, with the same time.
            let found = &mut *out.found;
            found.vf.sort_unstable_by_key(|c| (c.vertex, c.face));
            found.vf.dedup_by_key(|c| (c.vertex, c.face));
            found.ee.sort_unstable_by_key(|c| (c.a, c.b));
            found.ee.dedup_by_key(|c| (c.a, c.b));
            traverse += t.elapsed().as_secs_f64();
        }
    }
    let mut best = None;
    lower(&mut best, out.found.vf.iter().map(|c| c.toi));
    lower(&mut best, out.found.ee.iter().map(|c| c.toi));
    let late = !best.is_some_and(|b| ctx.limit(Some(b)) <= tau);
    let stats = BroadStats {
        bv_tests,
        build,
        traverse,
        ..BroadStats::default()
    };
    (stats, late, first_failed)
}

