//! Leaf clusters (section 4.1 of the paper): rings of triangles grown around a seed triangle,
//! each ring accepted only when it passes the paper's `phi` test and the grown patch still passes
//! the disk certificate.

use super::bernstein::{phi, Verdict};
use super::certificate::{DiskBuilder, DiskFailure};
use super::{ClusterOptions, ClusterStats, Clustering, GrowthStop, LeafCertificate, LeafCluster};
use crate::math::DVec3;
use crate::step::{Step, Topology};

/// Marker of a triangle not yet in any leaf cluster.
pub(super) const UNASSIGNED: u32 = u32::MAX;

/// Scratch memory of the leaf growth, reused across steps.
#[derive(Clone, Debug, Default)]
pub(super) struct LeafScratch {
    tri_stamp: Vec<u32>,
    stamp: u32,
    ring: Vec<u32>,
    frontier: Vec<u32>,
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
}

/// Corner positions of triangle `t` at t=0 and t=1.
#[inline]
pub(super) fn corners(step: &Step, t: u32) -> ([DVec3; 3], [DVec3; 3]) {
    let tri = step.triangles()[t as usize];
    (
        tri.map(|v| step.x0()[v as usize]),
        tri.map(|v| step.x1()[v as usize]),
    )
}

/// Grows the leaf clusters of `step` into `out` (whose leaf fields must be empty), seeds by
/// increasing triangle index. Fills `out.leaf_of_triangle`, `out.leaves`, `out.leaf_triangles`,
/// `out.ring_starts`, `out.last_ring_vertices` and the leaf counters of `stats`.
pub(super) fn grow_leaves(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    scratch: &mut LeafScratch,
    disk: &mut DiskBuilder,
    out: &mut Clustering,
    stats: &mut ClusterStats,
) {
    let n = step.triangles().len();
    out.leaf_of_triangle.clear();
    out.leaf_of_triangle.resize(n, UNASSIGNED);
    if scratch.tri_stamp.len() != n {
        scratch.tri_stamp.clear();
        scratch.tri_stamp.resize(n, 0);
    }
    let grow = options.min_separation == 0.0;
    for seed in 0..n as u32 {
        if out.leaf_of_triangle[seed as usize] != UNASSIGNED {
            continue;
        }
        let id = out.leaves.len() as u32;
        let first = out.leaf_triangles.len();
        let ring_first = out.ring_starts.len();
        out.leaf_of_triangle[seed as usize] = id;
        out.leaf_triangles.push(seed);
        out.ring_starts.push(first as u32);

        let (s0, s1) = corners(step, seed);
        let observation = [(s0[0] + s0[1] + s0[2]) / 3.0, (s1[0] + s1[1] + s1[2]) / 3.0];
        let normal = (s0[1] - s0[0]).cross(s0[2] - s0[0]);
        let direction = normal.normalize_or_zero();
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
                Ok(()) => grow_rings(step, topo, options, observation, scratch, disk, out, id),
            }
        };
        match stop {
            GrowthStop::Exhausted => stats.stops_exhausted += 1,
            GrowthStop::Phi => stats.stops_phi += 1,
            GrowthStop::Certificate(f) => {
                stats.stops_certificate += 1;
                stats.disk_failures.record(f);
            }
            GrowthStop::Disabled => {}
        }

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
                disk.set_centre(disk.vertex_centroid());
                if let Err(f) = disk.check_boundary(step, topo, true) {
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
