//! Leaf clusters (section 4.1 of the paper): rings of triangles grown around a seed triangle,
//! each ring accepted only when it passes the paper's `phi` test and the grown patch still passes
//! the disk certificate.

use crate::narrow::bernstein::{phi, Verdict};
use super::certificate::{DiskBuilder, DiskFailure};
use super::reuse::{emit_kept, grow_kept, Kept, Previous, RESERVED};
use super::{
    ClusterOptions, ClusterStats, Clustering, GrowthStop, LeafCertificate, LeafCluster,
    LeafDirection, RingGrowth,
};
use crate::math::DVec3;
use crate::mesh::{Step, Topology};

/// Marker of a triangle not yet in any leaf cluster.
pub(super) const UNASSIGNED: u32 = u32::MAX;

/// Scratch memory of the leaf growth, reused across steps.
#[derive(Clone, Debug, Default)]
pub(super) struct LeafScratch {
    tri_stamp: Vec<u32>,
    stamp: u32,
    ring: Vec<u32>,
    pub(super) frontier: Vec<u32>,
    /// Per triangle: the leaf stamp of the leaf whose `V` it failed (never retried there).
    refused: Vec<u32>,
    leaf_stamp: u32,
    /// Candidates of the current round and those refused in it (partial rings).
    pending: Vec<u32>,
    /// The candidates a round carries over to the next, with why they were last refused
    /// (`None`: never offered).
    retry: Vec<(u32, Option<DiskFailure>)>,
    /// Per candidate of the round (by position in `pending`): where it stands.
    entry: Vec<Entry>,
    /// Per triangle: its position in `pending` (valid for the round's candidates).
    position: Vec<u32>,
    /// Offer every refused candidate again after every pass that adds, and again in the next
    /// round, without the shortcuts that skip offers bound to be refused (a check that they
    /// change no decision).
    pub(super) reference: bool,
    /// The query's stop: once it says stop, the remaining leaves are single triangles.
    pub(crate) stop: Option<crate::broad::Stopper>,
    /// The leaves of the last step that passed their certificate on this one, by seed.
    pub(super) kept: Vec<Kept>,
    /// The `V-bar` of the kept leaves.
    pub(super) kept_bars: Vec<u32>,
    /// Per leaf of the clustering being made: how its star centre is defined, so that the
    /// next step can certify it around the same point of the mesh. `0`: the seed's centroid;
    /// `k > 0`: the mean of the vertices of its first `k` triangles (the patch when growth
    /// re-centred).
    pub(super) centre_prefix: Vec<u32>,
    /// [`LeafScratch::centre_prefix`] of the leaf being grown.
    pub(super) prefix: u32,
    /// Per vertex: whether a triangle around it was free once the kept leaves were reserved.
    pub(super) near_free: Vec<bool>,
}

/// Rounds of partial growth with at least this many candidates track which refused candidates
/// a new triangle may unblock; smaller ones offer them all again after every pass that adds.
const TRACKED_ROUND: usize = 32;

/// Where a candidate of a round of partial growth stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Entry {
    /// To be offered in the current pass (never offered, or its neighbourhood changed since).
    Untried,
    /// Refused for this reason, nothing around it changed since.
    Refused(DiskFailure),
    /// In the patch.
    Joined,
    /// Refused for the normal cone: never again for this leaf.
    Dropped,
}

impl LeafScratch {
    fn next_stamp(&mut self) -> u32 {
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.tri_stamp.iter_mut().for_each(|s| *s = 0);
            self.stamp = 1;
        }
        self.stamp
    }

    fn next_leaf_stamp(&mut self) -> u32 {
        self.leaf_stamp = self.leaf_stamp.wrapping_add(1);
        if self.leaf_stamp == 0 {
            self.refused.iter_mut().for_each(|s| *s = 0);
            self.leaf_stamp = 1;
        }
        self.leaf_stamp
    }
}

/// Makes every triangle of `step` free in `out.leaf_of_triangle` and forgets the kept leaves,
/// before [`keep_leaves`](super::reuse::keep_leaves) and [`grow_leaves`].
pub(super) fn start_leaves(step: &Step, out: &mut Clustering, scratch: &mut LeafScratch) {
    out.leaf_of_triangle.clear();
    out.leaf_of_triangle.resize(step.triangles().len(), UNASSIGNED);
    scratch.kept.clear();
}

/// Counts why a leaf stopped growing, and the certificate failure that stopped it if `failed`
/// (it happened on this step).
pub(super) fn count_stop(stats: &mut ClusterStats, stop: GrowthStop, failed: bool) {
    match stop {
        GrowthStop::Exhausted => stats.stops_exhausted += 1,
        GrowthStop::Phi => stats.stops_phi += 1,
        GrowthStop::Certificate(f) => {
            stats.stops_certificate += 1;
            if failed {
                stats.disk_failures.record(f);
            }
        }
        GrowthStop::Disabled => {}
    }
}

/// Corner positions of triangle `t` at t=0 and t=1.
#[inline]
pub(super) fn corners(step: &Step, t: u32) -> ([DVec3; 3], [DVec3; 3]) {
    let tri = step.triangles()[t as usize];
    (
        tri.map(|v| step.pos0()[v as usize]),
        tri.map(|v| step.pos1()[v as usize]),
    )
}

/// Grows the leaf clusters of `step` into `out` (whose leaf fields must be empty), seeds by
/// increasing triangle index. Fills `out.leaf_of_triangle`, `out.leaves`, `out.leaf_triangles`,
/// `out.ring_starts`, `out.last_ring_vertices` and the leaf counters of `stats`. Each leaf, once
/// finished, is shown to `on_leaf` (its id and triangles). Sequential: the only rayon calls are
/// `disk`'s, none when it is [sequential](DiskBuilder::set_sequential).
///
/// `out.leaf_of_triangle` must hold [`UNASSIGNED`] for every triangle, but those of the last
/// step's leaves kept by [`keep_leaves`](super::reuse::keep_leaves) ([`RESERVED`], listed in
/// `scratch.kept`; none without `previous`, see [`start_leaves`]): each kept leaf becomes the
/// leaf of its seed and grows into the free triangles around it; growth fills in around the
/// kept leaves.
#[allow(clippy::too_many_arguments)]
pub(super) fn grow_leaves(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    previous: Option<&Previous>,
    scratch: &mut LeafScratch,
    disk: &mut DiskBuilder,
    out: &mut Clustering,
    stats: &mut ClusterStats,
    on_leaf: &mut dyn FnMut(u32, &[u32]),
) {
    let n = step.triangles().len();
    debug_assert_eq!(out.leaf_of_triangle.len(), n);
    if scratch.tri_stamp.len() != n {
        scratch.tri_stamp.clear();
        scratch.tri_stamp.resize(n, 0);
        scratch.refused.clear();
        scratch.refused.resize(n, 0);
        scratch.position.clear();
        scratch.position.resize(n, 0);
    }
    let mut grow = options.min_distance == 0.0;
    scratch.centre_prefix.clear();
    let mut next_kept = 0;
    for seed in 0..n as u32 {
        // A query that stops: the leaves left are single triangles (valid, and quick).
        if grow && scratch.stop.as_ref().is_some_and(|s| s.stopped()) {
            grow = false;
        }
        let mark = out.leaf_of_triangle[seed as usize];
        if mark == RESERVED {
            // Kept leaves are sorted by seed, and a seed is its leaf's lowest triangle.
            if let (Some(previous), Some(kept)) = (previous, scratch.kept.get(next_kept)) {
                if kept.seed == seed {
                    let kept = kept.clone();
                    next_kept += 1;
                    let id = out.leaves.len() as u32;
                    emit_kept(previous, &kept, out, scratch, stats);
                    if grow {
                        grow_kept(step, topo, options, &kept, scratch, disk, out);
                    }
                    let leaf = &out.leaves[id as usize];
                    // A kept leaf that was neither trimmed nor grown met no failure on this step.
                    let grew = leaf.triangles.len() > kept.triangles as usize;
                    count_stop(stats, leaf.stop, grew || kept.trimmed.is_some());
                    on_leaf(id, &out.leaf_triangles[out.leaves[id as usize].triangles.clone()]);
                }
            }
            continue;
        }
        if mark != UNASSIGNED {
            continue;
        }
        let id = out.leaves.len() as u32;
        let first = out.leaf_triangles.len();
        let ring_first = out.ring_starts.len();
        scratch.prefix = 0;
        out.leaf_of_triangle[seed as usize] = id;
        out.leaf_triangles.push(seed);
        out.ring_starts.push(first as u32);

        let (s0, s1) = corners(step, seed);
        let observation = [(s0[0] + s0[1] + s0[2]) / 3.0, (s1[0] + s1[1] + s1[2]) / 3.0];
        let direction = if options.phi_filter || options.rings == RingGrowth::Whole {
            (s0[1] - s0[0]).cross(s0[2] - s0[0]).normalize_or_zero()
        } else {
            leaf_direction(step, topo, seed, options.direction)
        };
        scratch.frontier.clear();
        scratch
            .frontier
            .extend_from_slice(&step.triangles()[seed as usize]);

        let stop = if !grow {
            GrowthStop::Disabled
        } else if direction == DVec3::ZERO || !direction.is_finite() {
            GrowthStop::Certificate(DiskFailure::Normal)
        } else {
            disk.begin(
                topo,
                step.vertex_count(),
                direction,
                observation,
                options.subdivisions,
            );
            match disk
                .extend(step, topo, &[seed])
                .and_then(|()| disk.check_boundary(step, topo, false))
            {
                Err(f) => GrowthStop::Certificate(f),
                Ok(()) if options.phi_filter || options.rings == RingGrowth::Whole => {
                    grow_rings(step, topo, options, observation, scratch, disk, out, id)
                }
                Ok(()) => grow_partial_rings(step, topo, scratch, disk, out, id),
            }
        };
        let partial = grow && !options.phi_filter && options.rings == RingGrowth::Partial;
        // (After whole rings the builder holds the refused ring, so there is nothing to re-check:
        // each accepted ring was certified with the whole patch.)
        let stop = if partial && out.leaf_triangles.len() - first > 1 {
            // The certificate of the final patch, in full (growth only ever kept certified
            // patches; this makes the leaf's certificate independent of how it was grown).
            disk.end_batch();
            match disk.check_boundary(step, topo, true) {
                Ok(()) => stop,
                Err(f) => {
                    debug_assert!(false, "leaf {id} failed its final certificate: {f:?}");
                    // Fall back to the seed alone; the released triangles all come after the
                    // seed (it is the lowest-numbered free triangle), so later seeds take them.
                    for &t in &out.leaf_triangles[first + 1..] {
                        out.leaf_of_triangle[t as usize] = UNASSIGNED;
                    }
                    out.leaf_triangles.truncate(first + 1);
                    out.ring_starts.truncate(ring_first + 1);
                    scratch.frontier.clear();
                    scratch
                        .frontier
                        .extend_from_slice(&step.triangles()[seed as usize]);
                    GrowthStop::Certificate(f)
                }
            }
        } else {
            stop
        };
        count_stop(stats, stop, true);

        let bar_first = out.last_ring_vertices.len();
        out.last_ring_vertices.extend_from_slice(&scratch.frontier);
        let triangles = first..out.leaf_triangles.len();
        let triangles_len = triangles.len();
        let certificate = if triangles.len() == 1 {
            LeafCertificate::SingleTriangle
        } else {
            LeafCertificate::Disk
        };
        out.leaves.push(LeafCluster {
            triangles,
            rings: ring_first..out.ring_starts.len(),
            last_ring_vertices: bar_first..out.last_ring_vertices.len(),
            observation,
            direction,
            centre: if triangles_len > 1 {
                disk.centre()
            } else {
                observation
            },
            certificate,
            stop,
        });
        scratch
            .centre_prefix
            .push(if triangles_len > 1 { scratch.prefix } else { 0 });
        on_leaf(id, &out.leaf_triangles[first..]);
    }
}

/// Grows rings around the seed already in `disk` until one fails or none is left. On return,
/// `scratch.frontier` holds the new vertices of the last accepted ring (equation 4).
#[allow(clippy::too_many_arguments)]
fn grow_rings(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    observation: [DVec3; 2],
    scratch: &mut LeafScratch,
    disk: &mut DiskBuilder,
    out: &mut Clustering,
    id: u32,
) -> GrowthStop {
    loop {
        let stamp = scratch.next_stamp();
        scratch.ring.clear();
        for &v in &scratch.frontier {
            for &t in topo.triangles_of(v) {
                if out.leaf_of_triangle[t as usize] == UNASSIGNED
                    && scratch.tri_stamp[t as usize] != stamp
                {
                    scratch.tri_stamp[t as usize] = stamp;
                    scratch.ring.push(t);
                }
            }
        }
        if scratch.ring.is_empty() {
            return GrowthStop::Exhausted;
        }
        if options.phi_filter {
            for &t in &scratch.ring {
                let (p0, p1) = corners(step, t);
                if phi(&p0, &p1, observation).nonnegative(options.subdivisions) != Verdict::Holds {
                    return GrowthStop::Phi;
                }
            }
        }
        if let Err(f) = disk.extend(step, topo, &scratch.ring) {
            return GrowthStop::Certificate(f);
        }
        match disk.check_boundary(step, topo, false) {
            Ok(()) => {}
            Err(DiskFailure::Star | DiskFailure::Winding) => {
                // Seen from the current centre the boundary is not star-shaped: try the mean
                // of the patch's vertices, checking every boundary edge against it.
                let certified_centre = disk.centre();
                disk.set_centre(disk.vertex_centroid());
                if let Err(f) = disk.check_boundary(step, topo, true) {
                    // The leaf keeps the centre its accepted rings were certified with.
                    disk.set_centre(certified_centre);
                    return GrowthStop::Certificate(f);
                }
            }
            Err(f) => return GrowthStop::Certificate(f),
        }
        out.ring_starts.push(out.leaf_triangles.len() as u32);
        for &t in &scratch.ring {
            out.leaf_of_triangle[t as usize] = id;
            out.leaf_triangles.push(t);
        }
        debug_assert_eq!(
            disk.face_count(),
            out.leaf_triangles.len() - out.leaves_end_offset()
        );
        scratch.frontier.clear();
        scratch.frontier.extend_from_slice(disk.fresh_vertices());
    }
}

/// Grows partial rings around the seed already in `disk` (certified, its boundary checked
/// around the seed's centroid). Each round collects the free triangles around the vertices that
/// the last round added (and the triangles the last round refused for a reason other than the
/// normal cone) and adds them one at a time, in order, with [`DiskBuilder::try_add`], passing
/// over the refused ones again while a pass adds something; when star tests failed, the round
/// once tries re-centring `c` at the mean of the patch's vertices. The triangles a round adds
/// are the leaf's next ring. Growth ends at a round that adds nothing. On return,
/// `scratch.frontier` holds the new vertices of the last ring. Deterministic: every order is
/// that of the topology's incidence lists.
pub(super) fn grow_partial_rings(
    step: &Step,
    topo: &Topology,
    scratch: &mut LeafScratch,
    disk: &mut DiskBuilder,
    out: &mut Clustering,
    id: u32,
) -> GrowthStop {
    let leaf = scratch.next_leaf_stamp();
    scratch.retry.clear();
    loop {
        let stamp = scratch.next_stamp();
        scratch.ring.clear();
        let free = |t: u32, s: &LeafScratch| {
            out.leaf_of_triangle[t as usize] == UNASSIGNED && s.refused[t as usize] != leaf
        };
        // The candidates carried over come first, each with its last refusal.
        let mut carried = 0;
        for i in 0..scratch.retry.len() {
            let (t, _) = scratch.retry[i];
            if free(t, scratch) && scratch.tri_stamp[t as usize] != stamp {
                scratch.tri_stamp[t as usize] = stamp;
                scratch.ring.push(t);
                scratch.retry[carried] = scratch.retry[i];
                carried += 1;
            }
        }
        scratch.retry.truncate(carried);
        for i in 0..scratch.frontier.len() {
            let v = scratch.frontier[i];
            for &t in topo.triangles_of(v) {
                if free(t, scratch) && scratch.tri_stamp[t as usize] != stamp {
                    scratch.tri_stamp[t as usize] = stamp;
                    scratch.ring.push(t);
                }
            }
        }
        if scratch.ring.is_empty() {
            return GrowthStop::Exhausted;
        }
        disk.begin_batch();
        let ring_start = out.leaf_triangles.len();
        let mut first_failure = None;
        let mut recentred = false;
        std::mem::swap(&mut scratch.pending, &mut scratch.ring);
        // The passes over the round's candidates, in order, each over those the passes
        // before refused. A refused candidate is offered again only once a triangle sharing
        // one of its vertices has joined (or the centre moved): until then `try_add` would
        // refuse it again for the same reason, as its answer depends only on its vertices'
        // and edges' membership in the patch, the direction and the centre. So the
        // decisions are those of offering every refused candidate in every pass.
        let pending = &scratch.pending;
        scratch.entry.clear();
        scratch.entry.resize(pending.len(), Entry::Untried);
        // A candidate carried over was refused at the end of the last round, after the last
        // join around it and under the same centre; nothing of the patch changed since, so
        // it would be refused again, for the same reason, in the first pass: it starts as
        // refused (and so counts as the round's first failure, and among the stars refused).
        let mut star_refused = 0usize;
        let carried = if scratch.reference { 0 } else { scratch.retry.len() };
        for (k, &(_, refusal)) in scratch.retry[..carried].iter().enumerate() {
            if let Some(f) = refusal {
                first_failure.get_or_insert(f);
                star_refused += usize::from(f == DiskFailure::Star);
                scratch.entry[k] = Entry::Refused(f);
            }
        }
        // Small rounds offer every refused candidate again after a pass that added something
        // (as tracking their neighbourhoods would cost more than it saves).
        let track = !scratch.reference && pending.len() >= TRACKED_ROUND;
        if track {
            for (k, &t) in pending.iter().enumerate() {
                scratch.position[t as usize] = k as u32;
            }
        }
        let mut remaining = pending.len();
        loop {
            let mut added = false;
            for (k, &t) in pending.iter().enumerate() {
                if scratch.entry[k] != Entry::Untried {
                    continue;
                }
                match disk.try_add(step, topo, t) {
                    Ok(()) => {
                        added = true;
                        scratch.entry[k] = Entry::Joined;
                        remaining -= 1;
                        out.leaf_of_triangle[t as usize] = id;
                        out.leaf_triangles.push(t);
                        // Its neighbours among the refused candidates may now fit.
                        if !track {
                            continue;
                        }
                        for &v in &step.triangles()[t as usize] {
                            for &u in topo.triangles_of(v) {
                                if scratch.tri_stamp[u as usize] != stamp {
                                    continue;
                                }
                                let j = scratch.position[u as usize] as usize;
                                if let Entry::Refused(f) = scratch.entry[j] {
                                    star_refused -= usize::from(f == DiskFailure::Star);
                                    scratch.entry[j] = Entry::Untried;
                                }
                            }
                        }
                    }
                    Err(f) => {
                        first_failure.get_or_insert(f);
                        if f == DiskFailure::Normal {
                            scratch.refused[t as usize] = leaf;
                            scratch.entry[k] = Entry::Dropped;
                            remaining -= 1;
                        } else {
                            star_refused += usize::from(f == DiskFailure::Star);
                            scratch.entry[k] = Entry::Refused(f);
                        }
                    }
                }
            }
            if remaining == 0 {
                break;
            }
            if added && !track {
                for e in scratch.entry.iter_mut() {
                    if let Entry::Refused(_) = e {
                        *e = Entry::Untried;
                    }
                }
                star_refused = 0;
            }
            if !added {
                // Every remaining candidate was refused in this pass, by `try_add` or, its
                // neighbourhood unchanged, for the reason it was refused before.
                if star_refused == 0 || recentred {
                    break;
                }
                recentred = true;
                if disk
                    .try_recentre(step, topo, disk.vertex_centroid())
                    .is_err()
                {
                    break;
                }
                scratch.prefix = (out.leaf_triangles.len() - out.leaves_end_offset()) as u32;
                // Another centre: every star test may change.
                for e in scratch.entry.iter_mut() {
                    if let Entry::Refused(_) = e {
                        *e = Entry::Untried;
                    }
                }
                star_refused = 0;
            }
        }
        // What this round refused (but not for the normal cone) is retried next round, in
        // order.
        scratch.retry.clear();
        for (k, &t) in pending.iter().enumerate() {
            match scratch.entry[k] {
                Entry::Refused(f) => scratch.retry.push((t, Some(f))),
                Entry::Untried => scratch.retry.push((t, None)),
                Entry::Joined | Entry::Dropped => {}
            }
        }
        disk.end_batch();
        if out.leaf_triangles.len() == ring_start {
            return GrowthStop::Certificate(first_failure.unwrap_or(DiskFailure::Topology));
        }
        out.ring_starts.push(ring_start as u32);
        debug_assert_eq!(
            disk.face_count(),
            out.leaf_triangles.len() - out.leaves_end_offset()
        );
        scratch.frontier.clear();
        scratch.frontier.extend_from_slice(disk.fresh_vertices());
    }
}

/// Unit normal of triangle `t` at t=0 and at t=1 (zero when degenerate).
fn unit_normals(step: &Step, t: u32) -> [DVec3; 2] {
    let (p0, p1) = corners(step, t);
    [p0, p1].map(|p| (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero())
}

/// The direction `V` of a leaf grown from `seed` (any fixed vector serves the disk theorem; this
/// only decides how far the leaf can grow). Zero when the seed is degenerate.
pub(super) fn leaf_direction(
    step: &Step,
    topo: &Topology,
    seed: u32,
    choice: LeafDirection,
) -> DVec3 {
    let [n0, n1] = unit_normals(step, seed);
    if n0 == DVec3::ZERO || n1 == DVec3::ZERO {
        return DVec3::ZERO;
    }
    let mut sum = n0 + n1;
    if choice == LeafDirection::Neighbourhood {
        // The seed counts twice as much as each neighbour sharing one of its vertices.
        sum *= 2.0;
        for &v in &step.triangles()[seed as usize] {
            for &t in topo.triangles_of(v) {
                if t != seed {
                    let [m0, m1] = unit_normals(step, t);
                    sum += (m0 + m1) / topo.triangles_of(v).len() as f64;
                }
            }
        }
    }
    let direction = sum.normalize_or_zero();
    if direction.is_finite() {
        direction
    } else {
        DVec3::ZERO
    }
}
