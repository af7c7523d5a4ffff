//! The narrow phase shared by every method: the elementary tests over a buffer of candidate
//! feature pairs, in either mode, in parallel, with the same output for any thread count.

use std::ops::ControlFlow;

use rayon::prelude::*;

use super::limits::{Limits, StopReason};
use super::report::{Contact, EeContact, VfContact};
use super::{Mode, QueryOptions};
use super::{triangle_volume, Candidates};
use crate::alloc::{self, AllocError};
use crate::kdop::DopKind;
use crate::mesh::features::SweptBox;
use crate::mesh::{Step, Topology};
use super::edge_edge::{ee_contact, ee_query, ee_solved};
use super::vertex_face::{vf_contact, vf_query, vf_solved};
use crate::narrow::prefilter::{ee_rest_unresolved, first_tests_x4, vf_rest_unresolved, Firsts, Rest};
use crate::narrow::{Certainty, NarrowOptions, Outcome};

/// Pairs solved between two updates of the best time in [`Mode::Earliest`]. Fixed, so that
/// what is pruned does not depend on the thread count.
const EARLIEST_CHUNK: usize = 4096;

/// What the narrow phase found, in the order found: batch of candidates by batch, the
/// vertex-face contacts of a batch before its edge-edge contacts (`marks`).
#[derive(Debug)]
pub(crate) struct Found {
    pub vf: Vec<VfContact>,
    pub ee: Vec<EeContact>,
    /// `[vf.len(), ee.len()]` after each batch solved.
    marks: Vec<[usize; 2]>,
    /// How many more contacts may be kept (`usize::MAX`: no cap). Solving stops when it
    /// reaches 0.
    pub room: usize,
    /// The most contacts this buffer may hold ([`Found::with_budget`]).
    budget: usize,
    /// In [`Mode::Earliest`], whether the earliest time is known to be 0 and the contacts
    /// after the tolerance were dropped ([`Found::settle`]).
    settled: bool,
    /// Streaming ([`Stream`]): the earliest contact handed over, and how many were.
    pub streamed: Option<Contact>,
    pub streamed_count: usize,
    /// Of those, the ones not [`Certainty::Resolved`].
    pub streamed_unresolved: usize,
    /// In [`Mode::Earliest`] under a cap, the earliest time of impact among the contacts
    /// dropped to keep the set of earliest pairs bounded ([`Found::bound`]).
    pub dropped: Option<f64>,
}

/// Keeps, of `v`'s elements from `from` on, those that `keep` accepts, in order, in place.
fn keep_tail<T: Copy>(v: &mut Vec<T>, from: usize, keep: impl Fn(&T) -> bool) {
    let mut kept = from;
    for i in from..v.len() {
        if keep(&v[i]) {
            v[kept] = v[i];
            kept += 1;
        }
    }
    v.truncate(kept);
}

impl Default for Found {
    fn default() -> Self {
        Self {
            vf: Vec::new(),
            ee: Vec::new(),
            marks: Vec::new(),
            room: usize::MAX,
            budget: usize::MAX,
            settled: false,
            streamed: None,
            streamed_count: 0,
            streamed_unresolved: 0,
            dropped: None,
        }
    }
}

impl Found {
    /// A buffer that keeps at most `budget` contacts: at once in [`Mode::All`]; in
    /// [`Mode::Earliest`] from the moment the earliest time is known to be 0 ([`Found::settle`],
    /// applied here already if `limit` shows it), since before then no contact may be dropped.
    pub fn with_budget(ctx: &Context, budget: usize, limit: f64) -> Self {
        let mut found = Self {
            budget,
            ..Self::default()
        };
        if ctx.options.mode == Mode::All {
            found.room = budget;
        }
        found.settle(ctx, limit);
        found
    }

    /// Contacts held.
    pub fn len(&self) -> usize {
        self.vf.len() + self.ee.len()
    }

    /// Whether the contacts held count against a cap: always in [`Mode::All`]; in
    /// [`Mode::Earliest`] once the earliest time is known to be 0 ([`Found::settle`]).
    pub fn counting(&self, ctx: &Context) -> bool {
        ctx.options.mode == Mode::All || self.settled
    }

    /// Closes a batch of the order.
    fn mark(&mut self) {
        let now = [self.vf.len(), self.ee.len()];
        if self.marks.last() != Some(&now) {
            self.marks.push(now);
        }
    }

    /// Keeps the first `n` contacts in the order found.
    pub fn keep_first(&mut self, n: usize) {
        self.mark();
        let (mut vf0, mut ee0, mut left) = (0, 0, n);
        for i in 0..self.marks.len() {
            let [vf1, ee1] = self.marks[i];
            if left <= vf1 - vf0 {
                self.vf.truncate(vf0 + left);
                self.ee.truncate(ee0);
                self.marks.truncate(i);
                self.mark();
                return;
            }
            left -= vf1 - vf0;
            if left <= ee1 - ee0 {
                self.vf.truncate(vf1);
                self.ee.truncate(ee0 + left);
                self.marks.truncate(i);
                self.mark();
                return;
            }
            left -= ee1 - ee0;
            (vf0, ee0) = (vf1, ee1);
        }
    }

    /// Drops the contacts whose time of impact is after `cut`, keeping the order of the rest.
    fn retain_until(&mut self, cut: f64) {
        self.retain_where(|c: &VfContact| c.toi <= cut, |c: &EeContact| c.toi <= cut);
    }

    /// Keeps the contacts that `vf_keep` and `ee_keep` accept, in order.
    fn retain_where(&mut self, vf_keep: impl Fn(&VfContact) -> bool, ee_keep: impl Fn(&EeContact) -> bool) {
        self.mark();
        let (mut vf0, mut ee0) = (0, 0);
        let (mut vf_kept, mut ee_kept) = (0, 0);
        let mut marks = Vec::with_capacity(self.marks.len());
        for &[vf1, ee1] in &self.marks {
            for i in vf0..vf1 {
                if vf_keep(&self.vf[i]) {
                    self.vf[vf_kept] = self.vf[i];
                    vf_kept += 1;
                }
            }
            for i in ee0..ee1 {
                if ee_keep(&self.ee[i]) {
                    self.ee[ee_kept] = self.ee[i];
                    ee_kept += 1;
                }
            }
            marks.push([vf_kept, ee_kept]);
            (vf0, ee0) = (vf1, ee1);
        }
        self.vf.truncate(vf_kept);
        self.ee.truncate(ee_kept);
        marks.dedup();
        self.marks = marks;
    }

    /// In [`Mode::Earliest`] with a cap, before the earliest time is known to be 0: once the
    /// buffer holds half as many contacts again as the cap, keeps only the `max_contacts`
    /// earliest (in [`Contact::earliest_order`], at least one), in their order, and records
    /// the earliest time dropped ([`Found::dropped`]). The earliest contact is never dropped,
    /// and the set kept is the same whatever the order the contacts came in, so memory stays
    /// bounded and the report does not depend on the thread count.
    pub fn bound(&mut self, ctx: &Context) {
        let cap = ctx.limits.max_contacts;
        if self.settled || ctx.options.mode != Mode::Earliest || !ctx.limits.capped() {
            return;
        }
        if self.len() > cap.saturating_add(cap / 2).saturating_add(64) {
            self.keep_earliest_n(cap.max(1));
        }
    }

    /// Keeps the `n` earliest contacts (in [`Contact::earliest_order`]), in their order,
    /// recording the earliest time dropped.
    pub fn keep_earliest_n(&mut self, n: usize) {
        if self.len() <= n {
            return;
        }
        let mut keys: Vec<EarliestKey> = (self.vf.iter().map(vf_key))
            .chain(self.ee.iter().map(ee_key))
            .collect();
        let (_, &mut nth, rest) = keys.select_nth_unstable(n - 1);
        let dropped = rest.iter().map(|k| f64::from_bits(k.0)).fold(f64::INFINITY, f64::min);
        drop(keys);
        self.retain_where(|c| vf_key(c) <= nth, |c| ee_key(c) <= nth);
        if self.dropped.is_none_or(|d| dropped < d) {
            self.dropped = Some(dropped);
        }
    }

    /// In [`Mode::Earliest`] with a cap, once the earliest time is known to be 0 (`limit` has
    /// come down to [`Context::limit`] of 0): drops the contacts after the tolerance (the
    /// report keeps none of them) and keeps at most the budget from now on, the first ones.
    /// In [`Mode::All`] nothing changes.
    pub fn settle(&mut self, ctx: &Context, limit: f64) {
        if self.settled || !ctx.known_zero(limit) || !ctx.limits.capped() {
            return;
        }
        self.settled = true;
        self.retain_until(ctx.options.narrow.tolerance);
        if self.len() > self.budget {
            self.keep_first(self.budget);
        }
        self.room = self.budget - self.len();
    }

    /// Keeps, of the contacts from `starts` on (`[vf, ee]` indices), those that a settled
    /// buffer keeps (at or before the tolerance) and at most `room` of them, the first ones,
    /// lowering `room`. Only in [`Mode::All`] or once settled.
    fn trim_from(&mut self, ctx: &Context, [vf0, ee0]: [usize; 2]) {
        if self.settled {
            // In place: no second buffer of the contacts.
            let tol = ctx.options.narrow.tolerance;
            keep_tail(&mut self.vf, vf0, |c| c.toi <= tol);
            keep_tail(&mut self.ee, ee0, |c| c.toi <= tol);
        }
        let vf_new = self.vf.len() - vf0;
        let vf_kept = vf_new.min(self.room);
        self.vf.truncate(vf0 + vf_kept);
        self.room -= vf_kept;
        let ee_new = self.ee.len() - ee0;
        let ee_kept = ee_new.min(self.room);
        self.ee.truncate(ee0 + ee_kept);
        self.room -= ee_kept;
    }

    /// Appends `other`'s contacts after this one's, in order (`other`'s are dropped if this
    /// buffer cannot grow).
    pub fn append(&mut self, other: &mut Found) -> Result<(), AllocError> {
        self.mark();
        other.mark();
        let [vf0, ee0] = [self.vf.len(), self.ee.len()];
        let marks = other.marks.iter().map(|&[v, e]| [vf0 + v, ee0 + e]);
        alloc::try_extend(&mut self.marks, marks, "batch marks")?;
        alloc::try_append(&mut self.vf, &mut other.vf, "vertex-face contacts")?;
        alloc::try_append(&mut self.ee, &mut other.ee, "edge-edge contacts")?;
        other.marks.clear();
        self.streamed_count += other.streamed_count;
        self.streamed_unresolved += other.streamed_unresolved;
        if let Some(d) = other.dropped.take() {
            if self.dropped.is_none_or(|s| d < s) {
                self.dropped = Some(d);
            }
        }
        if let Some(c) = other.streamed.take() {
            let earlier = |s: &Contact| c.earliest_order(s) == std::cmp::Ordering::Less;
            if self.streamed.as_ref().is_none_or(earlier) {
                self.streamed = Some(c);
            }
        }
        Ok(())
    }

    /// Forgets `task`'s contacts, but for the earliest of them (kept in `streamed`, as a
    /// stream's).
    fn keep_earliest(&mut self, task: &mut Found) {
        let contacts = (task.vf.iter().map(|&c| Contact::Vf(c)))
            .chain(task.ee.iter().map(|&c| Contact::from(c)));
        if let Some(c) = contacts.min_by(Contact::earliest_order) {
            let earlier = |s: &Contact| c.earliest_order(s) == std::cmp::Ordering::Less;
            if self.streamed.as_ref().is_none_or(earlier) {
                self.streamed = Some(c);
            }
        }
        *task = Found::default();
    }

    /// After a deadline or a cancellation: the contacts held are forgotten but for the
    /// earliest, returned (with any kept by [`Found::keep_earliest`] or streamed).
    pub fn earliest_only(&mut self) -> Option<Contact> {
        let mut all = std::mem::take(self);
        let streamed = all.streamed.take();
        self.keep_earliest(&mut all);
        match (self.streamed.take(), streamed) {
            (Some(a), Some(b)) => Some(std::cmp::min_by(a, b, Contact::earliest_order)),
            (a, b) => a.or(b),
        }
    }

    /// Hands what is held to the stream, if there is one, and forgets it.
    pub fn deliver(&mut self, ctx: &Context) {
        let Some(stream) = ctx.stream else { return };
        let contacts = (self.vf.drain(..).map(Contact::Vf)).chain(self.ee.drain(..).map(Contact::from));
        for c in contacts {
            if !stream.take_one(ctx.limits) {
                break;
            }
            (stream.each)(&c);
            self.streamed_count += 1;
            self.streamed_unresolved += usize::from(c.certainty() != Certainty::Resolved);
            let earlier = |s: &Contact| c.earliest_order(s) == std::cmp::Ordering::Less;
            if self.streamed.as_ref().is_none_or(earlier) {
                self.streamed = Some(c);
            }
        }
        self.vf.clear();
        self.ee.clear();
        self.marks.clear();
    }
}

/// A contact's place in [`Contact::earliest_order`]: its time's bits (times are never
/// negative, so their bits order them), vertex-face before edge-edge, then the indices.
type EarliestKey = (u64, u8, [u32; 4]);

fn toi_bits(toi: f64) -> u64 {
    // +0 and -0 alike; a time of impact is never negative.
    if toi == 0.0 {
        0
    } else {
        toi.to_bits()
    }
}

fn vf_key(c: &VfContact) -> EarliestKey {
    (toi_bits(c.toi), 0, [c.vertex, c.face, 0, 0])
}

fn ee_key(c: &EeContact) -> EarliestKey {
    // The driver's edge-edge pairs carry the free points' pairs too (an edge `[p, p]` is the
    // point `p`): each takes its kind's place.
    let bits = toi_bits(c.toi);
    match Contact::from(*c) {
        Contact::Ve(v) => (bits, 2, [v.vertex, v.edge[0], v.edge[1], 0]),
        Contact::Vv(v) => (bits, 3, [v.a, v.b, 0, 0]),
        _ => (bits, 1, [c.a[0], c.a[1], c.b[0], c.b[1]]),
    }
}

/// The consumer of a streaming query ([`Ccd::for_each_contact`](crate::Ccd::for_each_contact)):
/// every contact is handed to `each` on the thread that found it.
pub(crate) struct Stream<'f> {
    pub each: &'f (dyn Fn(&Contact) + Sync),
    /// Contacts handed over so far (for the cap).
    handed: std::sync::atomic::AtomicUsize,
}

impl<'f> Stream<'f> {
    pub fn new(each: &'f (dyn Fn(&Contact) + Sync)) -> Self {
        Self {
            each,
            handed: std::sync::atomic::AtomicUsize::new(0),
        }
    }

    /// Whether one more contact may be handed over (`false` once the cap is reached, which
    /// stops the query).
    fn take_one(&self, limits: &Limits) -> bool {
        if !limits.capped() {
            return true;
        }
        let n = self.handed.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        if n >= limits.max_contacts {
            limits.stop(StopReason::MaxContacts);
            return false;
        }
        true
    }
}

/// How many contacts each task of a traversal under a cap holds so far (that count against it:
/// [`Found::counting`]), so that a task keeps only what the tasks before it leave room for: the
/// report takes the first contacts in task order, and the counts only grow, so a task never
/// needs more than the room at its batch's start less what the tasks before it, not yet
/// handed over, hold already. Once earlier tasks fill the room, the later ones stop at once:
/// memory stays near the cap per thread, however many tasks a batch runs.
pub(crate) struct Progress {
    counts: Vec<std::sync::atomic::AtomicUsize>,
    /// Tasks handed over (their contacts are in the report, and in the room already).
    handed: std::sync::atomic::AtomicUsize,
}

impl Progress {
    /// Counts for the first `tasks` tasks (later ones keep their whole room).
    pub fn new(tasks: usize) -> Self {
        Self {
            counts: (0..tasks).map(|_| Default::default()).collect(),
            handed: Default::default(),
        }
    }

    /// Records that task `index` holds `count` contacts.
    pub fn set(&self, index: usize, count: usize) {
        if let Some(c) = self.counts.get(index) {
            c.store(count, std::sync::atomic::Ordering::Relaxed);
        }
    }

    /// Records that the tasks before `index` were handed over.
    pub fn handed_until(&self, index: usize) {
        self.handed.store(index, std::sync::atomic::Ordering::Relaxed);
    }

    /// The room task `index` has, out of `room` at its batch's start: less what the tasks
    /// before it, not handed over, hold.
    pub fn room(&self, index: usize, room: usize) -> usize {
        if index >= self.counts.len() {
            return room;
        }
        let from = self.handed.load(std::sync::atomic::Ordering::Relaxed).min(index);
        let ahead: usize = self.counts[from..index]
            .iter()
            .map(|c| c.load(std::sync::atomic::Ordering::Relaxed))
            .sum();
        room.saturating_sub(ahead)
    }
}

/// What the consumer of the traversal's tasks (or of a sequential broad phase's buffers) keeps
/// under a cap: the contacts of the tasks in their order, until more than `max_contacts` are
/// known (in [`Mode::Earliest`], counted once the earliest time is known to be 0: before, no
/// contact can be dropped); then the first `max_contacts` of them.
#[derive(Debug, Default)]
pub(crate) struct Keeper {
    /// Tasks (or buffers) whose contacts are held.
    pub tasks: u64,
    /// The earliest time held so far (Earliest only).
    best: Option<f64>,
    /// Whether the cap was reached: later tasks are not the report's.
    pub full: bool,
}

impl Keeper {
    /// Takes the contacts of the next task in order into `found`; `Break` once the report is
    /// full or the query stopped (a stop is recorded on the limits).
    pub fn take(&mut self, ctx: &Context, found: &mut Found, task: &mut Found) -> ControlFlow<()> {
        if self.full {
            return ControlFlow::Break(());
        }
        self.tasks += 1;
        let limits = ctx.limits;
        if matches!(
            limits.stopped(),
            Some(StopReason::Deadline | StopReason::Cancelled)
        ) {
            // The report of a query stopped by time keeps only its earliest contact.
            found.keep_earliest(task);
            return ControlFlow::Break(());
        }
        if limits.capped() && ctx.options.mode == Mode::Earliest {
            lower(&mut self.best, task.vf.iter().map(|c| c.toi));
            lower(&mut self.best, task.ee.iter().map(|c| c.toi));
            if self.best == Some(0.0) {
                let tol = ctx.options.narrow.tolerance;
                if !found.settled {
                    found.settled = true;
                    found.retain_until(tol);
                }
                task.retain_until(tol);
            }
        }
        if !limits.check(found.append(task)) {
            return ControlFlow::Break(());
        }
        found.bound(ctx);
        let counting = ctx.options.mode == Mode::All || found.settled;
        if limits.capped() && counting && found.len() > limits.max_contacts {
            found.keep_first(limits.max_contacts);
            self.full = true;
            limits.stop(StopReason::MaxContacts);
            return ControlFlow::Break(());
        }
        if limits.stopped().is_some() {
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }

    /// How many contacts a task of the next batch may keep ([`Found::with_budget`]): one more
    /// than the room left under the cap (one more tells that the step has more), the whole cap
    /// while the earliest time of an Earliest query is not known to be 0; `usize::MAX` without
    /// a cap.
    pub fn budget(&self, ctx: &Context, found: &Found) -> usize {
        let max = ctx.limits.max_contacts;
        if !ctx.limits.capped() {
            usize::MAX
        } else if ctx.options.mode == Mode::Earliest && !found.settled {
            max + 1
        } else {
            (max + 1).saturating_sub(found.len())
        }
    }
}

/// In [`Mode::Earliest`], the per-step hierarchy first looks at the first `1 / EARLY` of the
/// interval only (its volumes swept over that start are much smaller; see
/// [`Ccd`](crate::Ccd)).
pub(crate) const EARLY: f64 = 256.0;

/// The end `tau = tmax / EARLY` of the per-step hierarchy's first pass in
/// [`Mode::Earliest`], `None` when the interval is too short to split (`tau` within twice the
/// tolerance).
pub(crate) fn first_pass_tau(options: &QueryOptions) -> Option<f64> {
    let tau = options.narrow.tmax / EARLY;
    (tau > 2.0 * options.narrow.tolerance).then_some(tau)
}

/// Which feature pairs a pass of the per-step hierarchy looks at (the pair filter aside,
/// which every pass applies alike): those whose features' boxes swept over `[0, box_end]`
/// come within the minimum separation and whose owner triangles' k-DOPs of kind `kdop` swept
/// over `[0, volume_end]` overlap.
#[derive(Clone, Copy)]
struct PassView<'a, 's> {
    step: &'a Step<'s>,
    topo: &'a Topology,
    box_end: f64,
    volume_end: f64,
    kdop: DopKind,
    sep: f64,
}

impl PassView<'_, '_> {
    /// The box swept by vertex `v`, as [`FeatureBoxes::sweep`] computes it.
    ///
    /// [`FeatureBoxes::sweep`]: crate::mesh::features::FeatureBoxes::sweep
    fn vertex_box(&self, v: u32) -> SweptBox {
        let v = v as usize;
        SweptBox::vertex_until(self.step.pos0()[v], self.step.pos1()[v], self.box_end)
    }

    /// Whether the pass looks at the vertex-face pair `[v, f]`.
    fn vf_looked_at(&self, [v, f]: [u32; 2]) -> bool {
        let face = (self.step.triangles()[f as usize].iter())
            .fold(SweptBox::EMPTY, |b, &w| b.merge(&self.vertex_box(w)));
        let owner = self.topo.triangles_of(v)[0];
        self.vertex_box(v).near(&face, self.sep) && self.owners_overlap(owner, f)
    }

    /// Whether the pass looks at the edge-edge pair `[e, f]` (indices into the edges).
    fn ee_looked_at(&self, [e, f]: [u32; 2]) -> bool {
        let edge = |e: u32| {
            let [i, j] = self.topo.edges[e as usize];
            self.vertex_box(i).merge(&self.vertex_box(j))
        };
        let owner = |e: u32| self.topo.edge_owner[e as usize];
        edge(e).near(&edge(f), self.sep) && self.owners_overlap(owner(e), owner(f))
    }

    /// Whether the k-DOPs of triangles `a` and `b` overlap.
    fn owners_overlap(&self, a: u32, b: u32) -> bool {
        fn overlap<const H: usize>(w: &PassView, a: u32, b: u32) -> bool {
            let volume = triangle_volume::<H>(w.step, w.volume_end, w.sep);
            volume(a).overlaps(&volume(b))
        }
        match self.kdop {
            DopKind::K6 => overlap::<3>(self, a, b),
            DopKind::K14 => overlap::<7>(self, a, b),
            DopKind::K18 => overlap::<9>(self, a, b),
            DopKind::K26 => overlap::<13>(self, a, b),
        }
    }
}

/// The first pass's verdict, applied by the narrow phase of every method and mode. The first
/// pass never looks at a feature pair whose owner triangles' k-DOPs, or whose features' boxes,
/// swept over `[0, tau]` as it sweeps them, are apart. Such a pair has no contact before
/// `tau` (the volumes are conservative), but where the elementary test cannot separate its
/// features (rounding bounds wider than their gap, as with coordinates of 1e300 beside
/// coordinates of 1), it would report it at the earliest time it cannot rule out, possibly
/// before `tau`, where the first pass does not: so the narrow phase searches such a pair from
/// `tau`, whatever the method or mode, and every method and mode report the same pairs with
/// the same times.
///
/// The owners are tested with 26-DOPs: their slabs include those of the first pass's leaves
/// whatever its k (each direction's slab is computed alike for every k), so a pair whose
/// leaves are apart is apart here too, and the verdict does not depend on the k chosen.
#[derive(Clone, Copy)]
pub(crate) struct FirstPass<'a, 's> {
    view: PassView<'a, 's>,
}

impl<'a, 's> FirstPass<'a, 's> {
    /// The rule for this step and these options, `None` when there is no first pass to mirror
    /// (see [`first_pass_tau`]).
    pub(crate) fn new(
        step: &'a Step<'s>,
        topo: &'a Topology,
        options: &QueryOptions,
    ) -> Option<Self> {
        first_pass_tau(options).map(|tau| Self {
            view: PassView {
                step,
                topo,
                box_end: tau,
                volume_end: tau,
                kdop: DopKind::K26,
                sep: options.narrow.min_distance,
            },
        })
    }

    /// `start` (a time until which the pair is known apart), raised to `tau` when the first
    /// pass's volumes prove the pair apart until then (`apart`, asked only if it matters).
    #[inline]
    pub(super) fn raise(&self, start: f64, apart: impl FnOnce() -> bool) -> f64 {
        let tau = self.view.box_end;
        if start < tau && apart() {
            tau
        } else {
            start
        }
    }

    /// Whether the first pass leaves out the vertex-face pair `[v, f]`.
    pub(super) fn vf_apart(&self, pair: [u32; 2]) -> bool {
        !self.view.vf_looked_at(pair)
    }

    /// Whether the first pass leaves out the edge-edge pair `[e, f]` (indices into the edges).
    pub(super) fn ee_apart(&self, pair: [u32; 2]) -> bool {
        !self.view.ee_looked_at(pair)
    }
}

/// The whole step's verdict, applied to the contacts of the per-step hierarchy's first pass
/// in [`Mode::Earliest`]: a contact counts only if [`Mode::All`] looks at the pair too. The
/// first pass's volumes, swept over `[0, tau]`, are padded for the rounding of the positions
/// at `tau`, so they need not lie inside the whole step's (exact at t=1): the first pass may
/// look at a pair that the whole step's volumes prove apart, and where the elementary test's
/// rounding bounds are wider than the pair's gap (a gap of 1e-185 beside coordinates of one)
/// it reports the pair, conservatively, at a time it cannot rule out. `Mode::All` never looks
/// at that pair. So the first pass keeps a contact only when the pair is also a candidate of
/// the whole step, as [`Mode::All`] finds them (the pair filter being the same): its owner
/// triangles' k-DOPs swept over `[0, tmax]` (the per-step hierarchy's leaves in `Mode::All`)
/// overlap, and its features' boxes swept over the whole step come within the minimum
/// separation. Then Earliest reports only pairs All reports. The check costs a few volumes
/// per contact of the first pass, nothing per candidate.
#[derive(Clone, Copy)]
pub(crate) struct WholeStep<'a, 's> {
    view: PassView<'a, 's>,
}

impl<'a, 's> WholeStep<'a, 's> {
    /// The rule for this step and these options.
    pub(crate) fn new(step: &'a Step<'s>, topo: &'a Topology, options: &QueryOptions) -> Self {
        Self {
            view: PassView {
                step,
                topo,
                box_end: 1.0,
                volume_end: options.narrow.tmax,
                kdop: options.kdop,
                sep: options.narrow.min_distance,
            },
        }
    }

    /// Whether [`Mode::All`] looks at the vertex-face pair `[v, f]`.
    pub(super) fn vf_candidate(&self, pair: [u32; 2]) -> bool {
        self.view.vf_looked_at(pair)
    }

    /// Whether [`Mode::All`] looks at the edge-edge pair `[e, f]` (indices into the edges).
    pub(super) fn ee_candidate(&self, pair: [u32; 2]) -> bool {
        self.view.ee_looked_at(pair)
    }
}

/// Solves `pairs` in order, four at a time through the batched prefilter (`first` on the
/// pairs' `corners`, then `rest` on the query of each pair it leaves), appending the contacts
/// that `keep` accepts to `out` and, in [`Mode::Earliest`], lowering `limit` as they come
/// (`lowered`). A pair gets exactly what it gets alone (`alone`, [`vf_contact`]): where a
/// contact earlier in its four lowered the limit, it is solved alone with the new one. Stops
/// once `room` contacts were kept (each kept contact takes one) or the query stops (`limits`,
/// polled every [`POLL_FOURS`] fours).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn solve_in_fours<Q, C>(
    pairs: &[[u32; 2]],
    tmax: f64,
    (limit, room, limits): (&mut f64, &mut usize, &Limits),
    out: &mut Vec<C>,
    corners: impl Fn([u32; 2]) -> [u32; 4],
    first: impl Fn(&[[u32; 4]; 4], f64) -> Firsts,
    query: impl Fn([u32; 2]) -> Q,
    rest: impl Fn(&Q, f64, Rest) -> Option<f64>,
    solved: impl Fn(&Q, [u32; 2], f64, f64) -> Option<C>,
    alone: impl Fn([u32; 2], f64) -> Option<C>,
    (lowered, keep): (impl Fn(f64, &C) -> f64, impl Fn(f64, &C) -> bool),
) {
    let mut take = |c: C, limit: &mut f64, room: &mut usize| {
        *limit = lowered(*limit, &c);
        if keep(*limit, &c) {
            if !limits.check(alloc::try_push(out, c, "contacts")) {
                // The query winds down ([`Limits::fail`]); nothing more is kept here.
                *room = 0;
                return;
            }
            *room -= 1;
        }
    };
    let mut fours = pairs.chunks_exact(4);
    for (k, four) in (&mut fours).enumerate() {
        if *room == 0 || (k % POLL_FOURS == 0 && limits.poll(false)) {
            return;
        }
        // The limit the four's first tests ran with.
        let tested = *limit;
        let t_end = tested.min(tmax);
        let four = [four[0], four[1], four[2], four[3]];
        let passed = first(&four.map(&corners), t_end);
        for (i, pair) in four.into_iter().enumerate() {
            if *room == 0 {
                return;
            }
            let contact = if *limit == tested {
                passed.rest(i).and_then(|r| {
                    let q = query(pair);
                    let from = rest(&q, t_end, r)?;
                    solved(&q, pair, tested, from)
                })
            } else {
                alone(pair, *limit)
            };
            if let Some(c) = contact {
                take(c, limit, room);
            }
        }
    }
    for &pair in fours.remainder() {
        if *room == 0 {
            return;
        }
        if let Some(c) = alone(pair, *limit) {
            take(c, limit, room);
        }
    }
}

/// Fours of pairs [`solve_in_fours`] solves between two polls of the query's limits (the
/// cancel token, and every few polls the clock): a few dozen pairs, some microseconds.
const POLL_FOURS: usize = 16;

/// What the narrow phase reads besides the candidates.
#[derive(Clone, Copy)]
pub(crate) struct Context<'a, 's> {
    /// The query's cap, deadline and cancel token, polled as the candidates are solved.
    pub limits: &'a Limits,
    /// Streaming: where the contacts go as they are found ([`Found::deliver`]).
    pub stream: Option<&'a Stream<'a>>,
    pub step: &'a Step<'s>,
    /// The step's edges, sorted lexicographically (edge-edge candidates index them).
    pub edges: &'a [[u32; 2]],
    pub options: &'a QueryOptions,
    /// The largest absolute coordinate of the step's positions (the prefilter's rounding
    /// bounds hold for it).
    pub coord: f64,
    /// The per-step hierarchy's first pass, mirrored by every method ([`FirstPass`]).
    pub first: Option<FirstPass<'a, 's>>,
    /// In that first pass only, the whole step's verdict on its contacts ([`WholeStep`]).
    pub whole: Option<WholeStep<'a, 's>>,
}

impl Context<'_, '_> {
    /// The end of the interval that still matters once a contact at `best` is known: in
    /// [`Mode::Earliest`], `best + 2 tolerance` (a pair skipped with it has no contact before
    /// that, the solver being conservative on its interval, so every pair whose time is within
    /// the tolerance of the earliest is still found); unbounded in [`Mode::All`].
    pub fn limit(&self, best: Option<f64>) -> f64 {
        match (self.options.mode, best) {
            (Mode::Earliest, Some(b)) => b + 2.0 * self.options.narrow.tolerance,
            _ => f64::INFINITY,
        }
    }

    /// Whether `limit`, a limit of this query's narrow phase, shows that the earliest time is
    /// 0 (in [`Mode::Earliest`] a limit is never below [`Context::limit`] of 0, which only a
    /// contact at 0 brings it down to).
    pub fn known_zero(&self, limit: f64) -> bool {
        self.options.mode == Mode::Earliest && limit <= self.limit(Some(0.0))
    }

    /// Solves the candidates in order on this thread, appending the contacts to `found`
    /// (at most `found.room` of them, which it lowers). `limit` (see [`Context::limit`]) is
    /// lowered as contacts are found. Stops early if the query stops ([`Limits::poll`]). In
    /// [`Mode::Earliest`] with a cap, once the earliest time is known to be 0, contacts after
    /// the tolerance are not kept (no report keeps them).
    pub fn solve(&self, candidates: &Candidates, limit: &mut f64, found: &mut Found) {
        // An Earliest query with a cap settles ([`Found::settle`]) as soon as its earliest
        // time is known to be 0, so that a task holds few contacts beyond its room.
        let part = if self.limits.capped() && self.options.mode == Mode::Earliest {
            SETTLE_PAIRS
        } else {
            usize::MAX
        };
        for pairs in candidates.vf.chunks(part) {
            self.solve_vf(pairs, limit, found);
            found.settle(self, *limit);
            found.bound(self);
        }
        for pairs in candidates.ee.chunks(part) {
            self.solve_ee(pairs, limit, found);
            found.settle(self, *limit);
            found.bound(self);
        }
        found.mark();
    }

    /// The new limit after a contact at `toi` ([`Context::limit`]; unchanged in [`Mode::All`]).
    fn lowered(&self, limit: f64, toi: f64) -> f64 {
        if self.options.mode == Mode::Earliest {
            limit.min(self.limit(Some(toi)))
        } else {
            limit
        }
    }

    /// Whether a contact at `toi`, found with `limit`, may be kept: not after the tolerance
    /// once the earliest time of an Earliest query with a cap is known to be 0.
    fn keeps(&self, limit: f64, toi: f64) -> bool {
        let tol = self.options.narrow.tolerance;
        !(self.limits.capped() && toi > tol && self.known_zero(limit))
    }

    /// [`Context::solve`] for vertex-face candidates.
    fn solve_vf(&self, pairs: &[[u32; 2]], limit: &mut f64, found: &mut Found) {
        let (step, options, coord) = (self.step, self.options, self.coord);
        let (sep, tmax) = (options.narrow.min_distance, options.narrow.tmax);
        let (x, tris) = ((step.pos0(), step.pos1()), step.triangles());
        solve_in_fours(
            pairs,
            tmax,
            (limit, &mut found.room, self.limits),
            &mut found.vf,
            |[v, f]| {
                let [f0, f1, f2] = tris[f as usize];
                [v, f0, f1, f2]
            },
            |corners, t_end| first_tests_x4::<1>(x, corners, sep, t_end, coord),
            |pair| vf_query(step, pair),
            |q, t_end, r| vf_rest_unresolved(q, sep, t_end, coord, r),
            |q, pair, limit, from| vf_solved(self, q, pair, (limit, from)),
            |pair, limit| vf_contact(self, pair, limit),
            (
                |limit, c: &VfContact| self.lowered(limit, c.toi),
                |limit, c: &VfContact| self.keeps(limit, c.toi),
            ),
        );
    }

    /// [`Context::solve`] for edge-edge candidates.
    fn solve_ee(&self, pairs: &[[u32; 2]], limit: &mut f64, found: &mut Found) {
        let (step, edges, options, coord) = (self.step, self.edges, self.options, self.coord);
        let (sep, tmax) = (options.narrow.min_distance, options.narrow.tmax);
        let x = (step.pos0(), step.pos1());
        solve_in_fours(
            pairs,
            tmax,
            (limit, &mut found.room, self.limits),
            &mut found.ee,
            |[e, f]| {
                let ([a0, a1], [b0, b1]) = (edges[e as usize], edges[f as usize]);
                [a0, a1, b0, b1]
            },
            |corners, t_end| first_tests_x4::<2>(x, corners, sep, t_end, coord),
            |pair| ee_query(step, edges, pair),
            |q, t_end, r| ee_rest_unresolved(q, sep, t_end, coord, r),
            |q, pair, limit, from| ee_solved(self, q, pair, (limit, from)),
            |pair, limit| ee_contact(self, pair, limit),
            (
                |limit, c: &EeContact| self.lowered(limit, c.toi),
                |limit, c: &EeContact| self.keeps(limit, c.toi),
            ),
        );
    }

    /// Solves a buffer of candidates on the current rayon pool, appending the contacts to
    /// `found` in the buffer's order (at most `found.room` of them, which it lowers). The
    /// buffer goes in fixed chunks, between which the query's limits are polled; in
    /// [`Mode::Earliest`] each chunk is pruned with the best time of the chunks before
    /// (`best`, updated), so what is pruned does not depend on the thread count.
    pub fn solve_parallel(&self, candidates: &Candidates, best: &mut Option<f64>, found: &mut Found) {
        let (size, min_len) = match self.options.mode {
            Mode::All => (ALL_CHUNK, 256),
            Mode::Earliest => (EARLIEST_CHUNK, 64),
        };
        for chunk in candidates.vf.chunks(size) {
            if found.room == 0 || self.limits.poll(true) {
                break;
            }
            let limit = self.limit(*best);
            let start = found.vf.len();
            // Room for the chunk's every pair, so that `par_extend` need not grow the buffer.
            if !(self.limits).check(alloc::grow(&mut found.vf, chunk.len(), "vertex-face contacts")) {
                break;
            }
            found.vf.par_extend(
                chunk
                    .par_iter()
                    .with_min_len(min_len)
                    .filter_map(|&pair| vf_contact(self, pair, limit)),
            );
            self.settle_chunk(best, found, [start, found.ee.len()]);
        }
        for chunk in candidates.ee.chunks(size) {
            if found.room == 0 || self.limits.poll(true) {
                break;
            }
            let limit = self.limit(*best);
            let start = found.ee.len();
            if !(self.limits).check(alloc::grow(&mut found.ee, chunk.len(), "edge-edge contacts")) {
                break;
            }
            found.ee.par_extend(
                chunk
                    .par_iter()
                    .with_min_len(min_len)
                    .filter_map(|&pair| ee_contact(self, pair, limit)),
            );
            self.settle_chunk(best, found, [found.vf.len(), start]);
        }
        found.mark();
    }

    /// After a chunk of [`Context::solve_parallel`] appended the contacts from `starts` on:
    /// lowers `best` (Earliest), then, under a cap, keeps what the buffer may keep
    /// ([`Found::settle`], [`Found::trim_from`]).
    fn settle_chunk(&self, best: &mut Option<f64>, found: &mut Found, starts: [usize; 2]) {
        if self.options.mode == Mode::Earliest {
            lower(best, found.vf[starts[0]..].iter().map(|c| c.toi));
            lower(best, found.ee[starts[1]..].iter().map(|c| c.toi));
            if found.settled {
                found.trim_from(self, starts);
            } else {
                found.settle(self, self.limit(*best));
                found.bound(self);
            }
        } else if self.limits.capped() {
            found.trim_from(self, starts);
        }
    }
}

/// Candidates of a buffer of [`Context::solve_parallel`] solved between two polls of the
/// query's limits in [`Mode::All`]: some milliseconds of work.
const ALL_CHUNK: usize = 1 << 14;

/// Pairs [`Context::solve`] solves between two settlements of an Earliest query with a cap
/// (a multiple of four).
const SETTLE_PAIRS: usize = 256;

/// Sorts `v` by `key` (unique per element), on the rayon pool for long vectors: their keys
/// and positions are sorted, then the elements gathered in that order (contacts are over a
/// hundred bytes each: moving them once beats moving them at every level of a sort; a
/// collapsed step's millions of contacts sorted in place took most of a second).
fn sort_by_key<T, K>(
    v: &mut Vec<T>,
    key: impl Fn(&T) -> K + Sync,
    what: &'static str,
) -> Result<(), AllocError>
where
    T: Copy + Send + Sync,
    K: Ord + Send + Sync,
{
    if v.len() < 1 << 14 {
        v.sort_unstable_by_key(key);
        return Ok(());
    }
    // Both buffers reserved first, fallibly: the indexed `par_extend`s then fill them in place.
    let mut keys: Vec<(K, u32)> = alloc::with_capacity(v.len(), "sort keys")?;
    keys.par_extend((v.par_iter().enumerate()).map(|(i, c)| (key(c), i as u32)));
    keys.par_sort_unstable_by(|a, b| a.0.cmp(&b.0));
    let mut sorted: Vec<T> = alloc::with_capacity(v.len(), what)?;
    sorted.par_extend(keys.par_iter().map(|&(_, i)| v[i as usize]));
    *v = sorted;
    Ok(())
}

/// Lowers `best` to the smallest of `tois`.
pub(crate) fn lower(best: &mut Option<f64>, tois: impl Iterator<Item = f64>) {
    for t in tois {
        if best.is_none_or(|b| t < b) {
            *best = Some(t);
        }
    }
}

/// Sorts what was found, keeps in [`Mode::Earliest`] only the contacts within the tolerance of
/// the earliest, and returns the earliest contact (an error if the sort's buffers cannot be
/// allocated).
pub(crate) fn finish(found: &mut Found, options: &QueryOptions) -> Result<Option<Contact>, AllocError> {
    let earliest = found
        .vf
        .iter()
        .map(|&c| Contact::Vf(c))
        .chain(found.ee.iter().map(|&c| Contact::from(c)))
        .min_by(Contact::earliest_order);
    if options.mode == Mode::Earliest {
        // The bounded set of earliest pairs ([`Found::bound`]) keeps at most the cap.
        if let Some(cap) = options.max_contacts.filter(|_| !found.settled) {
            found.marks.clear();
            found.keep_earliest_n(cap.max(1));
        }
        let cut = earliest.map_or(f64::NEG_INFINITY, |c| c.toi() + options.narrow.tolerance);
        found.vf.retain(|c| c.toi <= cut);
        found.ee.retain(|c| c.toi <= cut);
    }
    sort_by_key(&mut found.vf, |c| (c.vertex, c.face), "vertex-face contacts")?;
    sort_by_key(&mut found.ee, |c| (c.a, c.b), "edge-edge contacts")?;
    Ok(earliest)
}

/// Whether the report lists every pair within the tolerance of the earliest time (in
/// [`Mode::Earliest`]; in [`Mode::All`], every contact): no contact at or before that time
/// was dropped to keep the set of earliest pairs bounded. (A truncated query is never
/// complete; the caller checks that.)
pub(crate) fn earliest_complete(found: &Found, earliest: Option<Contact>, options: &QueryOptions) -> bool {
    let cut = earliest.map_or(f64::INFINITY, |c| c.toi() + options.narrow.tolerance);
    found.dropped.is_none_or(|d| d > cut)
}

/// The time of impact and certainty over `[0, full.tmax]`, or `None` when the pair is
/// separated or has no contact before `limit`: solved first over the shorter interval up to
/// `limit`, and again over the full interval only if that finds a contact. `solve(options,
/// start)` searches from `start`, until which the pair is known apart: the prefilter's
/// `start` over `[0, limit]` for the shorter interval, and for the full one what `whole` gives
/// (the prefilter over the whole interval), so that the time found is the one a query without
/// a limit finds.
#[inline]
pub(super) fn pruned(
    full: &NarrowOptions,
    limit: f64,
    start: f64,
    whole: impl FnOnce() -> Option<f64>,
    solve: impl Fn(&NarrowOptions, f64) -> Outcome,
) -> Option<(f64, Certainty)> {
    let contact = |o: Outcome| match o {
        Outcome::Separated => None,
        Outcome::Contact { toi, certainty } => Some((toi, certainty)),
    };
    if limit >= full.tmax {
        return contact(solve(full, start));
    }
    if start > 0.0 && start >= limit {
        // Apart until the limit.
        return None;
    }
    let short = NarrowOptions {
        tmax: limit,
        ..*full
    };
    contact(solve(&short, start))?;
    contact(solve(full, whole()?))
}
