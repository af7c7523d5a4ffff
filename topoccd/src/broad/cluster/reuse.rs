//! Leaf clusters carried over from the last step (see "Leaf clusters over a sequence" in the
//! [module documentation](super)): the last step's leaves, kept when the triangles are the
//! same, certified anew on the new step whole or trimmed to their first rings, and grown again
//! into the triangles around them that are free.

use super::certificate::{DiskBuilder, DiskFailure};
use super::leaf::{corners, grow_partial_rings, leaf_direction, LeafScratch, UNASSIGNED};
use super::{
    ClusterOptions, ClusterStats, Clustering, GrowthStop, LeafCertificate, LeafCluster, RingGrowth,
};
use crate::math::DVec3;
use crate::mesh::{Step, Topology};
use rayon::prelude::*;

/// Marker of a triangle of a leaf cluster taken over from the last step, certified anew, whose
/// seed has not been reached yet (see [`Previous`]).
pub(super) const RESERVED: u32 = u32::MAX - 1;

/// The leaf clusters of the last step clustered with a workspace, kept for the next step when
/// its triangles are the same ([`ClusterOptions::reuse`]). Each is only a proposal: it is
/// certified anew, in full, on the new step's positions before it is used.
#[derive(Clone, Debug, Default)]
pub(super) struct Previous {
    /// The options of the clustering kept (`None`: none is).
    options: Option<ClusterOptions>,
    triangles: Vec<[u32; 3]>,
    vertex_count: usize,
    /// A fingerprint of the positions of the step clustered, taken only when the leaves are too
    /// fragmented to be offered to another step ([`Previous::applies`]).
    positions: Option<u64>,
    leaves: Vec<LeafCluster>,
    leaf_triangles: Vec<u32>,
    ring_starts: Vec<u32>,
    last_ring_vertices: Vec<u32>,
    /// Per leaf: see [`LeafScratch::centre_prefix`].
    centre_prefix: Vec<u32>,
    /// Leaves of the last clustering grown afresh, without reuse.
    fresh_leaves: usize,
}

/// Leaves that fail their new certificate leave holes, where smaller leaves grow: once the
/// leaves are this many times as many as when last grown afresh, the next step grows afresh.
const FRAGMENTATION: f64 = 1.25;

impl Previous {
    /// Remembers the leaf clusters of `out`, just made for `step` with `options` and the
    /// leaf scratch `scratch`, grown afresh when `fresh` (none offered).
    pub(super) fn save(
        &mut self,
        step: &Step,
        options: &ClusterOptions,
        out: &Clustering,
        scratch: &LeafScratch,
        fresh: bool,
    ) {
        if !reusable(options) {
            // (What is kept stays a valid proposal for later steps with its options.)
            return;
        }
        if fresh {
            self.fresh_leaves = out.leaves.len();
        }
        self.options = Some(*options);
        self.triangles.clear();
        self.triangles.extend_from_slice(step.triangles());
        self.vertex_count = step.vertex_count();
        self.leaves.clone_from(&out.leaves);
        self.leaf_triangles.clone_from(&out.leaf_triangles);
        self.ring_starts.clone_from(&out.ring_starts);
        self.last_ring_vertices.clone_from(&out.last_ring_vertices);
        self.centre_prefix.clone_from(&scratch.centre_prefix);
        debug_assert_eq!(self.centre_prefix.len(), self.leaves.len());
        self.positions = self.fragmented().then(|| fingerprint(step));
    }

    /// Whether the leaves are too many, against the last fresh growth ([`FRAGMENTATION`]).
    fn fragmented(&self) -> bool {
        self.leaves.len() as f64 > FRAGMENTATION * self.fresh_leaves as f64
    }

    /// Whether the leaves saved are proposed for `step` clustered with `options`: same options,
    /// same vertex count, same triangles in the same order, and the leaves not too fragmented
    /// ([`FRAGMENTATION`]) unless the step is the very one they were made for (where they are
    /// all kept, so that the same query twice gives the same clustering).
    pub(super) fn applies(&self, step: &Step, options: &ClusterOptions) -> bool {
        reusable(options)
            && self.options == Some(*options)
            && self.vertex_count == step.vertex_count()
            && self.triangles == step.triangles()
            && (!self.fragmented() || self.positions == Some(fingerprint(step)))
    }
}

/// A fingerprint of the step's positions (their bits, four lanes of multiply and rotate). Two
/// steps with the same one are taken to be the same step; should two different steps ever
/// share one, the leaves would still be certified anew on the step at hand.
fn fingerprint(step: &Step) -> u64 {
    const K: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut lanes = [1u64, 2, 3, 4];
    for p in step.pos0().iter().chain(step.pos1()) {
        for (lane, x) in lanes.iter_mut().zip([p.x, p.y, p.z, 0.0]) {
            *lane = (*lane ^ x.to_bits()).wrapping_mul(K).rotate_left(29);
        }
    }
    lanes.iter().fold(0, |h, &l| (h ^ l).wrapping_mul(K).rotate_left(31))
}

/// Whether `options` let a step start from the last step's leaves.
fn reusable(options: &ClusterOptions) -> bool {
    options.reuse
        && options.min_distance == 0.0
        && !options.phi_filter
        && options.rings == RingGrowth::Partial
}

/// A leaf of the last step that passed its certificate on this step, whole or its first rings.
#[derive(Clone, Debug)]
pub(super) struct Kept {
    pub(super) seed: u32,
    /// Its index in [`Previous::leaves`].
    leaf: u32,
    /// The rings kept, and their triangles.
    rings: u32,
    pub(super) triangles: u32,
    observation: [DVec3; 2],
    direction: DVec3,
    centre: [DVec3; 2],
    /// See [`LeafScratch::centre_prefix`].
    prefix: u32,
    /// Its `V-bar` in [`LeafScratch::kept_bars`].
    bar: std::ops::Range<u32>,
    /// Why the whole leaf failed on this step, when only its first rings are kept.
    pub(super) trimmed: Option<DiskFailure>,
}

/// Certifies every leaf of `previous` anew on `step` ([`recertify`]), whole or trimmed to
/// its first rings, on the current rayon pool (one builder of `disks` per thread, each leaf's
/// verdict its own, so the same for any thread count). The triangles kept are marked
/// [`RESERVED`] in `out.leaf_of_triangle` (which must hold [`UNASSIGNED`] only), and the kept
/// leaves listed in `scratch.kept` by seed; the rest stays free.
#[allow(clippy::too_many_arguments)]
pub(super) fn keep_leaves(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    previous: &Previous,
    disks: &mut Vec<DiskBuilder>,
    out: &mut Clustering,
    scratch: &mut LeafScratch,
    stats: &mut ClusterStats,
) {
    // Runs of leaves of about equal triangle counts, one per thread.
    let threads = rayon::current_num_threads().max(1);
    if disks.len() < threads {
        disks.resize_with(threads, DiskBuilder::default);
    }
    let per = previous.leaf_triangles.len().div_ceil(threads).max(1);
    let mut bounds = vec![0];
    let mut sum = 0;
    for (k, leaf) in previous.leaves.iter().enumerate() {
        sum += leaf.triangles.len();
        if sum >= per * bounds.len() && bounds.len() < threads {
            bounds.push(k + 1);
        }
    }
    if bounds.last() != Some(&previous.leaves.len()) {
        bounds.push(previous.leaves.len());
    }
    let runs: Vec<(Vec<Option<Kept>>, Vec<u32>)> = (disks[..bounds.len() - 1].par_iter_mut())
        .zip(bounds.par_windows(2))
        .map(|(disk, run)| {
            let mut bars = Vec::new();
            let kept = (run[0]..run[1])
                .map(|k| recertify(step, topo, options, previous, k, disk, &mut bars))
                .collect();
            (kept, bars)
        })
        .collect();
    scratch.kept_bars.clear();
    for ((verdicts, bars), run) in runs.into_iter().zip(bounds.windows(2)) {
        let shift = scratch.kept_bars.len() as u32;
        scratch.kept_bars.extend_from_slice(&bars);
        for (k, verdict) in (run[0]..run[1]).zip(verdicts) {
            let triangles = &previous.leaf_triangles[previous.leaves[k].triangles.clone()];
            let Some(mut kept) = verdict else {
                stats.regrown_leaves += 1;
                continue;
            };
            let mine = &triangles[..kept.triangles as usize];
            // (The last step's leaves are disjoint: a guard, never taken.)
            if mine.iter().any(|&t| out.leaf_of_triangle[t as usize] != UNASSIGNED) {
                stats.regrown_leaves += 1;
                continue;
            }
            for &t in mine {
                out.leaf_of_triangle[t as usize] = RESERVED;
            }
            stats.trimmed_leaves += usize::from(mine.len() < triangles.len());
            kept.bar = kept.bar.start + shift..kept.bar.end + shift;
            scratch.kept.push(kept);
        }
    }
    scratch.kept.sort_by_key(|k| k.seed);
    scratch.near_free.clear();
    scratch.near_free.resize(step.vertex_count(), false);
    for (t, tri) in step.triangles().iter().enumerate() {
        if out.leaf_of_triangle[t] == UNASSIGNED {
            for &v in tri {
                scratch.near_free[v as usize] = true;
            }
        }
    }
}

/// Leaf `k` of `previous`, certified anew on `step` ([`certify_patch`]): whole, else the patch
/// of its first `m` rings for the first `m` that passes, tried in a fixed order (a single
/// triangle needs no certificate). When a triangle fails hypothesis 1 or 2, `m` goes from the
/// most rings that hold none such down; else (the boundary failed) from `r - 1` (`r` its
/// rings). Its `V-bar` goes to the end of `bars`.
fn recertify(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    previous: &Previous,
    k: usize,
    disk: &mut DiskBuilder,
    bars: &mut Vec<u32>,
) -> Option<Kept> {
    let leaf = &previous.leaves[k];
    let triangles = &previous.leaf_triangles[leaf.triangles.clone()];
    let ring_starts = &previous.ring_starts[leaf.rings.clone()];
    // The end of the first `m` rings in `triangles`.
    let end = |m: usize| match ring_starts.get(m) {
        Some(&start) => start as usize - leaf.triangles.start,
        None => triangles.len(),
    };
    let seed = triangles[0];
    let (s0, s1) = corners(step, seed);
    let observation = [(s0[0] + s0[1] + s0[2]) / 3.0, (s1[0] + s1[1] + s1[2]) / 3.0];
    let direction = leaf_direction(step, topo, seed, options.direction);
    let bar_start = bars.len();
    let kept = |rings: usize, centre, prefix, bars: &Vec<u32>, trimmed| Kept {
        seed,
        leaf: k as u32,
        rings: rings as u32,
        triangles: end(rings) as u32,
        observation,
        direction,
        centre,
        prefix,
        bar: bar_start as u32..bars.len() as u32,
        trimmed,
    };
    if triangles.len() == 1 {
        // Its features all share a vertex: there is nothing to certify.
        bars.extend_from_slice(&previous.last_ring_vertices[leaf.last_ring_vertices.clone()]);
        return Some(kept(1, observation, 0, bars, None));
    }
    if direction == DVec3::ZERO || !direction.is_finite() {
        return None;
    }
    let prefix = previous.centre_prefix.get(k).copied().unwrap_or(0) as usize;
    let attempt = |m: usize, disk: &mut DiskBuilder, bars: &mut Vec<u32>| {
        bars.truncate(bar_start);
        let patch = Patch {
            triangles: &triangles[..end(m)],
            last_ring: end(m - 1),
            prefix: prefix.min(end(m)),
            observation,
            direction,
        };
        certify_patch(step, topo, options, disk, &patch, bars)
    };
    let r = ring_starts.len();
    let whole = attempt(r, disk, bars);
    let most = match whole {
        Ok((centre, prefix)) => return Some(kept(r, centre, prefix, bars, None)),
        Err(DiskFailure::Normal | DiskFailure::NonManifold) => {
            // The rings up to the first holding a triangle that fails them.
            let sub = options.subdivisions;
            disk.begin(topo, step.vertex_count(), direction, observation, sub);
            let ring = |m: usize| &triangles[end(m)..end(m + 1)];
            (0..r).take_while(|&m| disk.extend(step, topo, ring(m)).is_ok()).count()
        }
        Err(_) => r - 1,
    };
    let mut tried = [r; 4];
    let sizes = [most, most.saturating_sub(1), most.saturating_sub(3), most / 2];
    for (i, m) in sizes.into_iter().enumerate() {
        if m < 2 || tried.contains(&m) {
            continue;
        }
        tried[i] = m;
        if let Ok((centre, prefix)) = attempt(m, disk, bars) {
            return Some(kept(m, centre, prefix, bars, whole.err()));
        }
    }
    bars.truncate(bar_start);
    None
}

/// A patch of a leaf's first rings to certify.
struct Patch<'a> {
    triangles: &'a [u32],
    /// Where its last ring starts in `triangles`.
    last_ring: usize,
    /// The star centre to try first: see [`LeafScratch::centre_prefix`].
    prefix: usize,
    observation: [DVec3; 2],
    direction: DVec3,
}

/// The certificate of `patch` on `step`, in full, as a grown leaf's final check: hypotheses 1
/// and 2 for every triangle, 3 to 5 for the whole boundary, around the centre `patch.prefix`
/// defines, else the seed's centroid, else the mean of all the patch's vertices. On success,
/// the centre and its prefix, and the vertices of its last ring met in no earlier ring (`V-bar`)
/// appended to `bar`.
fn certify_patch(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    disk: &mut DiskBuilder,
    patch: &Patch<'_>,
    bar: &mut Vec<u32>,
) -> Result<([DVec3; 2], u32), DiskFailure> {
    let triangles = patch.triangles;
    disk.begin(
        topo,
        step.vertex_count(),
        patch.direction,
        patch.observation,
        options.subdivisions,
    );
    // In up to three batches, so as to read the centroid of the first `prefix` triangles and
    // the vertices first met in the last ring.
    let (p, q) = (patch.prefix, patch.last_ring);
    let mut head_centre = patch.observation;
    let mut from = 0;
    for to in [p.min(q), p.max(q), triangles.len()] {
        // (A batch may be empty.)
        disk.extend(step, topo, &triangles[from..to])?;
        if to == p && p > 0 {
            head_centre = disk.vertex_centroid();
        }
        if from >= q {
            bar.extend_from_slice(disk.fresh_vertices());
        }
        from = to;
    }
    let all = triangles.len() as u32;
    let centres = [
        (p as u32, head_centre),
        (0, patch.observation),
        (all, disk.vertex_centroid()),
    ];
    for (k, &(prefix, centre)) in centres.iter().enumerate() {
        if centres[..k].iter().any(|&(other, _)| other == prefix) {
            continue;
        }
        disk.set_centre(centre);
        match disk.check_boundary(step, topo, true) {
            Ok(()) => return Ok((centre, prefix)),
            Err(DiskFailure::Star | DiskFailure::Winding) if k + 1 < centres.len() => {}
            Err(f) => return Err(f),
        }
    }
    Err(DiskFailure::Star)
}

/// Appends the kept leaf `kept` to `out` as the next leaf: its first rings as on the last step,
/// its observation point, direction, centre and `V-bar` as certified on this one.
pub(super) fn emit_kept(
    previous: &Previous,
    kept: &Kept,
    out: &mut Clustering,
    scratch: &mut LeafScratch,
    stats: &mut ClusterStats,
) {
    scratch.centre_prefix.push(kept.prefix);
    let leaf = &previous.leaves[kept.leaf as usize];
    let id = out.leaves.len() as u32;
    let first = out.leaf_triangles.len();
    let ring_first = out.ring_starts.len();
    let shift = |start: u32| start - leaf.triangles.start as u32 + first as u32;
    let rings = leaf.rings.start..leaf.rings.start + kept.rings as usize;
    (out.ring_starts).extend(previous.ring_starts[rings].iter().map(|&r| shift(r)));
    let start = leaf.triangles.start;
    let triangles = &previous.leaf_triangles[start..start + kept.triangles as usize];
    out.leaf_triangles.extend_from_slice(triangles);
    for &t in triangles {
        out.leaf_of_triangle[t as usize] = id;
    }
    let bar_first = out.last_ring_vertices.len();
    let bar = kept.bar.start as usize..kept.bar.end as usize;
    out.last_ring_vertices.extend_from_slice(&scratch.kept_bars[bar]);
    stats.reused_leaves += 1;
    out.leaves.push(LeafCluster {
        triangles: first..out.leaf_triangles.len(),
        rings: ring_first..out.ring_starts.len(),
        last_ring_vertices: bar_first..out.last_ring_vertices.len(),
        observation: kept.observation,
        direction: kept.direction,
        centre: kept.centre,
        certificate: leaf.certificate,
        // A trimmed leaf stops where the whole leaf failed on this step.
        stop: kept.trimmed.map_or(leaf.stop, GrowthStop::Certificate),
    });
}

/// Grows the kept leaf just appended to `out` (as [`emit_kept`] left it) by partial rings into
/// the free triangles around it, if any (those of last step's leaves that failed their new
/// certificate): the kept leaf serves as a seed. The grown patch is checked in full, as a
/// grown leaf's; if it fails, the leaf stays as kept.
pub(super) fn grow_kept(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    kept: &Kept,
    scratch: &mut LeafScratch,
    disk: &mut DiskBuilder,
    out: &mut Clustering,
) {
    let Some(leaf) = out.leaves.pop() else {
        return;
    };
    // (Off the list while it grows, as a leaf being grown is.)
    let grown = grown_kept(step, topo, options, kept, &leaf, scratch, disk, out);
    out.leaves.push(grown.unwrap_or(leaf));
}

/// [`grow_kept`] for the kept leaf `leaf`, off `out.leaves`: the grown leaf, if it grew.
#[allow(clippy::too_many_arguments)]
fn grown_kept(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    kept: &Kept,
    leaf: &LeafCluster,
    scratch: &mut LeafScratch,
    disk: &mut DiskBuilder,
    out: &mut Clustering,
) -> Option<LeafCluster> {
    let id = out.leaves.len();
    let patch = &out.leaf_triangles[leaf.triangles.clone()];
    let tris = step.triangles();
    let free = |t: &u32| out.leaf_of_triangle[*t as usize] == UNASSIGNED;
    let near = |&v: &u32| scratch.near_free[v as usize] && topo.triangles_of(v).iter().any(free);
    let grows = |&t: &u32| tris[t as usize].iter().any(near);
    let direction = kept.direction;
    if direction == DVec3::ZERO || !direction.is_finite() || !patch.iter().any(grows) {
        return None;
    }
    // The certificate of the kept patch again, which leaves `disk` holding it, as growth
    // needs (the same tests as when it was kept, in one batch).
    disk.begin(
        topo,
        step.vertex_count(),
        direction,
        kept.centre,
        options.subdivisions,
    );
    let certified = disk.extend(step, topo, patch).is_ok()
        && disk.check_boundary(step, topo, true).is_ok();
    if !certified {
        // A single triangle may fail (as a seed may; it needs no certificate). A bigger patch
        // passed moments ago; should the order of its boundary ever tip a winding sum the
        // other way, it simply does not grow.
        return None;
    }
    scratch.frontier.clear();
    scratch.frontier.extend_from_slice(disk.fresh_vertices());
    scratch.prefix = kept.prefix;
    let stop = grow_partial_rings(step, topo, scratch, disk, out, id as u32);
    if out.leaf_triangles.len() == leaf.triangles.end {
        return None;
    }
    disk.end_batch();
    if disk.check_boundary(step, topo, true).is_err() {
        debug_assert!(false, "kept leaf {id} failed its certificate after growing");
        // Release what it grew: all of it comes after the seed, which is the lowest free
        // triangle, so later seeds take it.
        for &t in &out.leaf_triangles[leaf.triangles.end..] {
            out.leaf_of_triangle[t as usize] = UNASSIGNED;
        }
        out.leaf_triangles.truncate(leaf.triangles.end);
        out.ring_starts.truncate(leaf.rings.end);
        return None;
    }
    out.last_ring_vertices.truncate(leaf.last_ring_vertices.start);
    out.last_ring_vertices.extend_from_slice(&scratch.frontier);
    scratch.centre_prefix[id] = scratch.prefix;
    Some(LeafCluster {
        triangles: leaf.triangles.start..out.leaf_triangles.len(),
        rings: leaf.rings.start..out.ring_starts.len(),
        last_ring_vertices: leaf.last_ring_vertices.start..out.last_ring_vertices.len(),
        centre: disk.centre(),
        certificate: LeafCertificate::Disk,
        stop,
        ..leaf.clone()
    })
}

