//! Intermediate clusters (section 4.2 of the paper, algorithms 1 and 2), made sound: a walk over
//! neighbouring leaf clusters that appends a leaf to the current intermediate cluster only when
//! every pair of leaves in it is covered by an argument (see the [module documentation](super)).

use crate::narrow::bernstein::{phi, Verdict};
use super::certificate::{DiskBuilder, DiskFailure};
use super::leaf::{corners, UNASSIGNED};
use super::{ClusterOptions, ClusterStats, Clustering, IntermediateCluster};
use crate::math::DVec3;
use crate::mesh::features::SweptBox;
use crate::mesh::{Step, Topology};
use rayon::prelude::*;

/// Box of the swept volumes of `triangles`: a triangle moving linearly stays, at every time, in
/// the convex hull of its six end positions, hence in their box. Inflated by `margin`.
fn swept_box(step: &Step, triangles: &[u32], margin: f64) -> SweptBox {
    let mut b = SweptBox::EMPTY;
    for &t in triangles {
        for &v in &step.triangles()[t as usize] {
            b.add(step.pos0()[v as usize]);
            b.add(step.pos1()[v as usize]);
        }
    }
    if triangles.is_empty() {
        return b;
    }
    SweptBox {
        lo: b.lo - DVec3::splat(margin),
        hi: b.hi + DVec3::splat(margin),
    }
}

/// Leaf adjacency (sharing an edge) as CSR: neighbours of leaf `i` are
/// `adjacent[offsets[i]..offsets[i + 1]]`, increasing.
fn leaf_adjacency(
    topo: &Topology,
    leaf_of_triangle: &[u32],
    leaves: usize,
) -> (Vec<u32>, Vec<u32>) {
    let mut first_leaf = vec![UNASSIGNED; topo.edges.len()];
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for (t, edges) in topo.triangle_edges.iter().enumerate() {
        let l = leaf_of_triangle[t];
        for &e in edges {
            let f = &mut first_leaf[e as usize];
            if *f == UNASSIGNED {
                *f = l;
            } else if *f != l {
                pairs.push((*f, l));
                pairs.push((l, *f));
            }
        }
    }
    pairs.par_sort_unstable();
    pairs.dedup();
    let mut offsets = vec![0u32; leaves + 1];
    for &(a, _) in &pairs {
        offsets[a as usize + 1] += 1;
    }
    for i in 0..leaves {
        offsets[i + 1] += offsets[i];
    }
    (offsets, pairs.into_iter().map(|(_, b)| b).collect())
}

/// Per-leaf data of the merge: boxes, observation point of equation 5.
struct LeafGeometry {
    /// `B_i`: the whole leaf.
    whole: SweptBox,
    /// `B'_i`: the leaf without its last ring (empty for a single-ring leaf).
    core: SweptBox,
    /// `O_i` of equation 5 at t=0 and t=1.
    observation: [DVec3; 2],
}

fn leaf_geometry(step: &Step, c: &Clustering, margin: f64) -> Vec<LeafGeometry> {
    (0..c.leaves.len())
        .into_par_iter()
        .with_min_len(64)
        .map(|i| {
            let leaf = &c.leaves[i];
            let tris = c.leaf_triangles(i);
            let last = c.last_ring(i);
            let core = &tris[..tris.len() - last.len()];
            let bar = c.last_ring_vertices(i);
            let observation = if bar.is_empty() {
                leaf.observation
            } else {
                let k = bar.len() as f64;
                let s0: DVec3 = bar.iter().map(|&v| step.pos0()[v as usize]).sum();
                let s1: DVec3 = bar.iter().map(|&v| step.pos1()[v as usize]).sum();
                [s0 / k, s1 / k]
            };
            LeafGeometry {
                whole: swept_box(step, tris, margin),
                core: swept_box(step, core, margin),
                observation,
            }
        })
        .collect()
}

/// Builds the intermediate clusters into `out` from its leaves.
pub(super) fn merge_leaves(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    disk: &mut DiskBuilder,
    out: &mut Clustering,
    stats: &mut ClusterStats,
) {
    let leaves = out.leaves.len();
    out.intermediate_of_leaf.clear();
    out.intermediate_of_leaf.resize(leaves, UNASSIGNED);
    let merging =
        options.merge && options.min_distance == 0.0 && options.max_intermediate_leaves > 1;
    let (offsets, adjacent) = if merging {
        leaf_adjacency(topo, &out.leaf_of_triangle, leaves)
    } else {
        (vec![0; leaves + 1], Vec::new())
    };
    let geometry = if merging {
        leaf_geometry(step, out, options.min_distance)
    } else {
        Vec::new()
    };
    let mut members: Vec<u32> = Vec::new();
    for start in 0..leaves as u32 {
        if out.intermediate_of_leaf[start as usize] != UNASSIGNED {
            continue;
        }
        let id = out.intermediates.len() as u32;
        members.clear();
        members.push(start);
        out.intermediate_of_leaf[start as usize] = id;
        'walk: while merging && members.len() < options.max_intermediate_leaves as usize {
            let prev = *members.last().unwrap_or(&start);
            let (lo, hi) = (
                offsets[prev as usize] as usize,
                offsets[prev as usize + 1] as usize,
            );
            for &next in &adjacent[lo..hi] {
                if out.intermediate_of_leaf[next as usize] != UNASSIGNED {
                    continue;
                }
                if can_merge(
                    step, topo, options, disk, out, &geometry, &members, next, stats,
                ) {
                    out.intermediate_of_leaf[next as usize] = id;
                    members.push(next);
                    continue 'walk;
                }
            }
            break;
        }
        let first = out.intermediate_leaves.len();
        out.intermediate_leaves.extend_from_slice(&members);
        let triangle_count = members
            .iter()
            .map(|&l| out.leaves[l as usize].triangles.len())
            .sum();
        out.intermediates.push(IntermediateCluster {
            leaves: first..out.intermediate_leaves.len(),
            triangle_count,
        });
    }
}

/// Algorithms 1 and 2 with the soundness conditions: may `next` follow the last of `members`?
#[allow(clippy::too_many_arguments)]
fn can_merge(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    disk: &mut DiskBuilder,
    c: &Clustering,
    geometry: &[LeafGeometry],
    members: &[u32],
    next: u32,
    stats: &mut ClusterStats,
) -> bool {
    let (n, p) = (next as usize, *members.last().unwrap_or(&next) as usize);
    let size = c.leaves[n].triangles.len() + c.leaves[p].triangles.len();
    if size > options.max_merge_triangles as usize {
        stats.merge_rejected_size += 1;
        return false;
    }
    let g_n = &geometry[n];
    // Algorithm 2: B_n must miss the boxes of all members but the predecessor.
    if members[..members.len() - 1]
        .iter()
        .any(|&j| geometry[j as usize].whole.overlaps(&g_n.whole))
    {
        stats.merge_rejected_box += 1;
        return false;
    }
    // Algorithm 1, the paper's test: the last rings of both leaves face away from O_n.
    let o = g_n.observation;
    let rings = c.last_ring(p).iter().chain(c.last_ring(n));
    for &t in rings.take_while(|_| options.phi_filter) {
        let (p0, p1) = corners(step, t);
        if phi(&p0, &p1, o).nonnegative(options.subdivisions) != Verdict::Holds {
            stats.merge_rejected_phi += 1;
            return false;
        }
    }
    let (leaf_n, leaf_p) = (&c.leaves[n], &c.leaves[p]);
    let direction = (leaf_n.direction + leaf_p.direction).normalize_or_zero();
    if direction == DVec3::ZERO {
        stats.merge_rejected_certificate += 1;
        return false;
    }
    let nv = step.vertex_count();
    let sub = options.subdivisions;
    // Route of the paper: LC_n with the last ring of LC_p is a certified disk, and B_n misses
    // B'_p (the rest of LC_p).
    if !g_n.whole.overlaps(&geometry[p].core) {
        disk.begin(topo, nv, direction, leaf_n.centre, sub);
        let ok = disk
            .extend(step, topo, c.leaf_triangles(n))
            .and_then(|()| disk.extend(step, topo, c.last_ring(p)))
            .and_then(|()| disk.check_boundary(step, topo, true));
        match ok {
            Ok(()) => {
                stats.merged_by_ring += 1;
                return true;
            }
            Err(f) => stats.disk_failures.record(f),
        }
    }
    // Fallback: the union of both leaves is a certified disk (star centre tried at the mean of
    // its vertices, then at either leaf's centre).
    disk.begin(topo, nv, direction, leaf_n.centre, sub);
    let built = disk
        .extend(step, topo, c.leaf_triangles(n))
        .and_then(|()| disk.extend(step, topo, c.leaf_triangles(p)));
    let mut last = built;
    if built.is_ok() {
        let union_centre = disk.vertex_centroid();
        for centre in [union_centre, leaf_n.centre, leaf_p.centre] {
            disk.set_centre(centre);
            last = disk.check_boundary(step, topo, true);
            match last {
                Ok(()) => {
                    stats.merged_by_union += 1;
                    return true;
                }
                Err(DiskFailure::Star | DiskFailure::Winding) => continue,
                Err(_) => break,
            }
        }
    }
    if let Err(f) = last {
        stats.disk_failures.record(f);
    }
    stats.merge_rejected_certificate += 1;
    false
}
