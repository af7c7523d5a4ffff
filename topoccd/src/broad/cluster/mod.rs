//! Dynamic clustering (section 4 of the paper): leaf clusters grown around observation points,
//! intermediate clusters merged from them, every intermediate cluster *proved* free of
//! self-contact over the step, so that a query may skip all feature pairs inside one.
//!
//! # What is guaranteed
//! For every intermediate cluster (and so every leaf cluster), no two of its features (vertices,
//! edges, faces of its triangles) that share no vertex touch at any time `t` in `[0, 1]`, in exact
//! arithmetic, with vertices moving linearly from `x0` to `x1`. Floating point only ever makes
//! the construction refuse a ring or a merge. With [`ClusterOptions::min_distance`] `> 0` the
//! certificates below say nothing about distances, so every leaf is then a single triangle and
//! every intermediate cluster a single leaf (a triangle's own features all share a vertex).
//!
//! # Why the paper's criterion is not enough
//! The paper accepts triangles with `phi(tau, O, t) = n(t)·(v0(t) - O(t)) >= 0` (all back-facing
//! from the observation point `O`). That does not make the radial projection from `O` one-to-one:
//! a helicoid winding around an axis through `O` faces away from `O` everywhere, yet a deformed
//! turn can pass through the turn below. And the seed triangle contains `O` (`phi = 0`: a
//! degenerate projection). The test `cluster_soundness.rs` builds such a helicoid and finds a
//! contact inside a cluster grown with `phi` alone. The paper's test is kept as a filter (the
//! issue asks for the paper's algorithm), and soundness comes from the following certificate.
//!
//! # The disk theorem (normal cone and contour test, as in Volino and Thalmann 1994)
//! Let `S` be a finite set of triangles (an abstract simplicial complex given by vertex indices)
//! and `V` a fixed non-zero vector; `pi` is the orthogonal projection along `V` onto the plane
//! `V^perp`, oriented by `V`. Suppose, at a time `t`:
//!
//! 1. every triangle `(a, b, c)` of `S` has `n·V > 0`, `n = (b - a) x (c - a)`;
//! 2. every edge lies in at most two triangles of `S`, in opposite directions when in two;
//! 3. `V - E + F = 1` (vertices, edges and triangles of `S`);
//! 4. for every boundary edge (in exactly one triangle) `a -> b`, directed as in its triangle,
//!    `g = V·((a - c) x (b - c)) > 0` for a point `c`;
//! 5. the projected angles of the boundary edges around `pi(c)` sum to `2 pi`.
//!
//! Then `S` is a topological closed disk and `pi`, applied to the points of `S` placed at their
//! positions at time `t`, is injective: no two distinct points of `S` coincide, so no two features
//! of `S` sharing no vertex (disjoint as subsets of `S`) touch.
//!
//! *Proof.* (a) *The boundary is one simple curve.* By 2 the directed boundary edges have, at
//! every vertex, as many edges in as out, so they split into closed directed cycles. By 4 every
//! boundary edge turns counter-clockwise around `pi(c)` by an angle in `(0, pi)`, so each cycle
//! winds at least once; by 5 the total winding is one, so there is exactly one cycle, its polar
//! angle around `pi(c)` increases strictly and covers `[0, 2 pi)` once: it visits no vertex
//! twice and its projection is a simple closed polygon `J` (it meets each ray from `pi(c)` once).
//! (b) *`S` is a disk.* Split every vertex whose triangles form several edge-connected fans
//! into one copy per fan (`k_v` copies): this gives a compact surface `S'` with boundary,
//! orientable by 2, and `chi(S) = chi(S') - sum_v (k_v - 1)`. A component of `S'` without
//! boundary would be a closed oriented surface, whose normals sum to zero (each directed edge
//! `a -> b` contributes `a x b`, cancelled by `b -> a`), impossible when every `n·V > 0`. So each
//! component of `S'` has boundary, and as the boundary is one cycle, `S'` is connected with one
//! boundary curve: `chi(S') = 1 - 2 genus`. With 3, `genus = 0` and every `k_v = 1`: `S = S'`
//! is a disk. (c) *Degree.* `pi` maps each triangle affinely and, by 1, orientation-preservingly
//! onto its image; across an interior edge the two triangles lie on opposite sides of the
//! projected edge (2 and 1), so `pi` is a local homeomorphism there; at an interior vertex the
//! projected fan winds `k >= 1` times around the vertex's image: a branch point of local degree
//! `k`. So every point of `S` off `dS` has local degree `>= 1` and `pi` is open on `S - dS`. For
//! `q` off `J`, the number of preimages counted with local degree is the degree of `pi` over `q`,
//! which for a map of a disk equals the winding number of `pi(dS) = J` around `q`: `0` or `1`
//! for a simple curve. So every `q` off `J` has at most one preimage. (d) *Injectivity.* Let
//! `p1 != p2` in `S` with `pi(p1) = pi(p2)`. Both on `dS` contradicts (a). Otherwise say `p2` is
//! not on `dS`; take disjoint neighbourhoods `U1` of `p1` and `U2` of `p2` with `pi(U2)` open.
//! Points of `U1 - dS` close to `p1` map, by openness, onto an open set close to `pi(p2)`; it
//! meets `pi(U2)` off the nowhere-dense `J`, giving a `q` off `J` with two preimages. Contradiction.
//!
//! Over the step: 1, 4 are certified for all `t` in `[0, 1]` at once (Bernstein coefficients with
//! rigorous error bounds, [`bernstein`](crate::narrow::bernstein)), with `c(t)` moving linearly; 2, 3 do not depend on `t`;
//! 5 is checked at `t = 0` with a rigorous bound on each computed angle ([`certificate`]), and
//! holds for all `t` because the winding number is an integer that varies continuously while no
//! `g` vanishes (by 4 `pi(c(t))` never meets `J(t)`).
//!
//! # Leaf clusters
//! A leaf grows from a seed (the lowest-numbered free triangle) by rings: `T1` = free triangles
//! incident to the seed's vertices, `T(k+1)` = free triangles incident to the new vertices of
//! `Tk`. With the paper's filter ([`ClusterOptions::phi_filter`]), or with
//! [`RingGrowth::Whole`], a ring is accepted only if all its triangles pass
//! `phi(tau, O, t) >= 0` (up to rounding, with the filter; `O` the seed's centroid, moving with
//! it) and the grown patch passes the disk theorem with `V` the seed's unit normal at t=0 and
//! `c = O` (or the mean of the patch's vertices); growth stops at the first ring that fails.
//!
//! Without the filter, by default ([`RingGrowth::Partial`]), `V` is the normalised sum of the
//! seed's unit normals at t=0 and t=1 ([`LeafDirection`]; any fixed `V` serves the theorem),
//! `c` starts at `O` and may move to the mean of the patch's vertices when the whole boundary
//! passes around it, and a ring is accepted in part: its
//! triangles are offered one at a time, in a fixed order, and each joins only if the patch with
//! it still satisfies hypotheses 1 to 5 ([`DiskBuilder::try_add`]: hypotheses 1, 2 and 4 are
//! checked for the new triangle and its new boundary edges, 3 by counting, 5 is preserved
//! exactly); refused triangles are offered again while others join, and in the next ring. The
//! accepted triangles form the leaf's ring `Tk`, and `T(k+1)` is gathered around their new
//! vertices. When growth ends the final patch is checked against hypotheses 3 to 5 in full
//! (every boundary edge, the winding number), so the theorem applies to each leaf as stated,
//! whatever the order of growth. A leaf of one triangle needs no certificate: its features all
//! share a vertex.
//!
//! # Leaf clusters over a sequence
//! The paper grows every step's leaves afresh. When a step has the triangles of the last step
//! clustered with the same workspace (no topology change), the last step's leaves are offered
//! first ([`ClusterOptions::reuse`]): each of two or more triangles is certified anew on the
//! new positions, in full, exactly as a grown leaf's final patch (hypotheses 1 and 2 for every
//! triangle, 3 to 5 for the whole boundary, with `V` chosen from the seed as for growth, around
//! the point of the mesh it was certified around before, else the seed's centroid, else the
//! mean of the patch's vertices). A leaf that passes is kept whole, with its rings (a single
//! triangle needs no certificate and is always kept). A leaf that fails is offered again as its
//! first rings, a few times, each patch certified in full the same way: from the most rings
//! whose triangles all pass hypotheses 1 and 2 (or one ring fewer, when only the boundary
//! failed) down to half of them. The triangles of the rings dropped, and of the leaves that
//! fail every time, are free. Then, by increasing seed as always, a kept leaf grows by partial
//! rings into the free triangles around it, as if it were a seed, and new leaves grow from the
//! free triangles left.
//! So every leaf carries a certificate of this step, whatever the last step was; the reuse only
//! saves the growth's trials. Leaves that fail leave holes where smaller leaves grow: once the
//! leaves number a quarter more than when last grown afresh, the next step grows afresh.
//!
//! # Intermediate clusters
//! Leaves are walked in a deterministic order; a leaf `LC_n` adjacent (sharing an edge) to the
//! last leaf `LC_p` of the current intermediate cluster `IC` joins it when: (i) algorithm 2: the
//! box `B_n` of `LC_n`'s swept triangles misses the box of every member of `IC` but `LC_p`;
//! (ii) algorithm 1: the last rings of `LC_p` and `LC_n` pass `phi >= 0` with respect to `O_n`
//! (equation 5; a filter only); (iii) either `LC_n` with the last ring `T^p` of `LC_p` is a
//! certified disk *and* `B_n` misses the box `B'_p` of `LC_p - T^p` (the paper's route), or the
//! union `LC_n + LC_p` is a certified disk (a fallback, since `LC_n + T^p` is an annulus whenever
//! `T^p` closes around `LC_p`). *Every pair is covered:* two features of one leaf by its disk;
//! of `LC_n` and its predecessor `LC_p`, by the disk of (iii) when the second feature lies in
//! that disk, else by the disjoint boxes (a linearly moving triangle stays in the convex hull, so
//! in the box, of its six end positions; disjoint closed boxes hold no common point); of `LC_n`
//! and an earlier member, by the disjoint boxes of (i). Pairs spanning two leaves are checked
//! when the later of the two joins. The boxes are axis-aligned; k-DOPs
//! (`topoccd::kdop`, not yet written) would merge more and can replace them.

pub mod certificate;
mod leaf;
mod merge;
pub(crate) mod phase;
mod reuse;
pub(crate) mod traverse;
pub(crate) mod tree;
mod types;

pub use certificate::{DiskBuilder, DiskFailure};
pub use types::{
    ClusterOptions, ClusterStats, Clustering, DiskFailureCounts, GrowthStop, IntermediateCluster,
    LeafCertificate, LeafCluster, LeafDirection, RingGrowth,
};

use crate::mesh::{Step, Topology};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, Receiver};
use std::time::Instant;

/// Scratch memory of [`cluster_with`], reused across steps to avoid reallocation.
#[derive(Clone, Debug, Default)]
pub struct ClusterWorkspace {
    disk: DiskBuilder,
    leaf: leaf::LeafScratch,
    /// The leaves of the last clustering made with this workspace ([`ClusterOptions::reuse`]).
    previous: reuse::Previous,
    /// One disk builder per thread for certifying those leaves anew.
    disks: Vec<DiskBuilder>,
}

#[cfg(feature = "internals")]
impl ClusterWorkspace {
    /// With `true`, leaf growth takes none of its shortcuts: every refused candidate is offered
    /// again after every pass that adds a triangle and in the next round. The clustering must
    /// be the same (tested).
    pub fn reference_growth(&mut self, on: bool) {
        self.leaf.reference = on;
    }
}

/// Clusters the triangles of one step (see the [module documentation](self) for the guarantee).
///
/// ```
/// use topoccd::broad::cluster::{cluster, ClusterOptions};
/// use topoccd::math::DVec3;
/// use topoccd::mesh::Topology;
/// use topoccd::Step;
/// // A flat 4x4 grid of squares, two triangles each, drifting upwards.
/// let n = 5u32;
/// let x0: Vec<DVec3> = (0..n * n).map(|i| DVec3::new((i % n) as f64, (i / n) as f64, 0.0)).collect();
/// let x1: Vec<DVec3> = x0.iter().map(|p| *p + DVec3::Z).collect();
/// let mut tris = Vec::new();
/// for j in 0..n - 1 {
///     for i in 0..n - 1 {
///         let v = j * n + i;
///         tris.push([v, v + 1, v + n + 1]);
///         tris.push([v, v + n + 1, v + n]);
///     }
/// }
/// let step = Step::new(x0, x1, tris).unwrap();
/// let topo = Topology::new(step.triangles(), step.vertex_count());
/// let c = cluster(&step, &topo, &ClusterOptions::default());
/// assert_eq!(c.leaf_of_triangle.len(), 32);
/// assert!(c.stats.triangles_per_leaf > 4.0);
/// ```
pub fn cluster(step: &Step, topo: &Topology, options: &ClusterOptions) -> Clustering {
    let mut workspace = ClusterWorkspace::default();
    cluster_with(step, topo, options, &mut workspace)
}

/// [`cluster`] with caller-owned scratch memory, for repeated use over many steps. With
/// [`ClusterOptions::reuse`], a step whose triangles are those of the last step clustered with
/// `workspace` (and the same options) starts from that step's leaf clusters, each certified
/// anew (see the [module documentation](self)): the clustering may then differ from a fresh
/// one, never its guarantee.
pub fn cluster_with(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    workspace: &mut ClusterWorkspace,
) -> Clustering {
    let mut out = Clustering::default();
    cluster_into(step, topo, options, workspace, &mut out);
    out
}

/// [`cluster_with`] writing into `out`, whose arrays are cleared and reused: once warm, a step
/// allocates little. Nothing of `out`'s previous content is used.
pub fn cluster_into(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    workspace: &mut ClusterWorkspace,
    out: &mut Clustering,
) {
    cluster_into_beside(step, topo, options, workspace, out, usize::MAX, |_, _| {});
}

/// A finished leaf cluster as [`cluster_into_beside`] sends it: its id and its triangles.
pub(crate) type GrownLeaf = (u32, Vec<u32>);

/// [`cluster_into`], running `beside` on the rayon pool while the leaves grow (at the same
/// time when a second thread is free; the leaf growth itself is sequential). `beside` receives
/// every leaf cluster of at least `min_triangles` triangles as soon as it is finished, by
/// increasing id, and a flag set when growth has ended (just before the channel closes). The
/// clustering does not depend on `beside`.
pub(crate) fn cluster_into_beside(
    step: &Step,
    topo: &Topology,
    options: &ClusterOptions,
    workspace: &mut ClusterWorkspace,
    out: &mut Clustering,
    min_triangles: usize,
    beside: impl FnOnce(Receiver<GrownLeaf>, &AtomicBool) + Send,
) {
    debug_assert_eq!(topo.triangle_edges.len(), step.triangles().len());
    out.clear();
    let out = &mut *out;
    let mut stats = ClusterStats::default();
    let started = Instant::now();
    let (send, receive) = channel();
    let done = AtomicBool::new(false);
    let mut grown = started;
    // The last step's leaves that still hold, found on the whole pool before growth starts.
    leaf::start_leaves(step, out, &mut workspace.leaf);
    let reuse = workspace.previous.applies(step, options);
    if reuse {
        reuse::keep_leaves(
            step,
            topo,
            options,
            &workspace.previous,
            &mut workspace.disks,
            out,
            &mut workspace.leaf,
            &mut stats,
        );
    }
    // No rayon call may run on the growth's side of the join while `send` lives: a thread
    // waiting there could take up `beside`, which waits for `send` to close. So the disk
    // builder stays on its thread while leaves are sent.
    workspace.disk.set_sequential(min_triangles != usize::MAX);
    rayon::join(
        || {
            let mut on_leaf = |id: u32, triangles: &[u32]| {
                if triangles.len() >= min_triangles {
                    // The receiver lives until the channel closes: a send cannot fail.
                    let _ = send.send((id, triangles.to_vec()));
                }
            };
            leaf::grow_leaves(
                step,
                topo,
                options,
                reuse.then_some(&workspace.previous),
                &mut workspace.leaf,
                &mut workspace.disk,
                out,
                &mut stats,
                &mut on_leaf,
            );
            grown = Instant::now();
            done.store(true, Ordering::Release);
            drop(send);
        },
        || beside(receive, &done),
    );
    workspace.disk.set_sequential(false);
    let merging = Instant::now();
    merge::merge_leaves(step, topo, options, &mut workspace.disk, out, &mut stats);
    stats.clustering_seconds = (grown - started).as_secs_f64();
    stats.merging_seconds = merging.elapsed().as_secs_f64();
    stats.triangles = step.triangles().len();
    stats.leaves = out.leaves.len();
    stats.intermediates = out.intermediates.len();
    if stats.leaves > 0 {
        stats.triangles_per_leaf = stats.triangles as f64 / stats.leaves as f64;
    }
    if stats.intermediates > 0 {
        stats.triangles_per_intermediate = stats.triangles as f64 / stats.intermediates as f64;
    }
    out.stats = stats;
    workspace.previous.save(step, options, out, &workspace.leaf, !reuse);
}
