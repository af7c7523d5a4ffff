//! The clustering against brute force: on smooth and adversarial deforming meshes, every feature
//! pair inside one intermediate cluster that shares no vertex is run through the narrow phase,
//! and none may touch. The adversarial meshes are shown to contain contacts, and the paper's
//! `phi` criterion alone is shown to put touching features in one cluster.

mod mesh_util;

use mesh_util::{grid, sphere};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use topoccd::broad::cluster::{
    cluster, cluster_into, ClusterOptions, ClusterWorkspace, Clustering,
};
use topoccd::math::DVec3;
use topoccd::mesh::Topology;
use topoccd::narrow::bernstein::{phi, Verdict};
use topoccd::narrow::{edge_edge, vertex_face, EdgeEdge, NarrowOptions, VertexFace};
use topoccd::Step;

// ---------------------------------------------------------------- brute force

/// Box of a feature's points at both times.
fn feature_box(step: &Step, vs: &[u32]) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for &v in vs {
        for p in [step.pos0()[v as usize], step.pos1()[v as usize]] {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    (lo, hi)
}

fn boxes_meet(a: (DVec3, DVec3), b: (DVec3, DVec3)) -> bool {
    a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
}

/// Feature pairs sharing no vertex among `tris` that the narrow phase reports touching, at most
/// `limit` of them. A swept box test filters the pairs first (exactly: features whose boxes of
/// end positions are disjoint cannot meet).
fn contacts_among(step: &Step, tris: &[u32], limit: usize) -> Vec<String> {
    let (x0, x1, t) = (step.pos0(), step.pos1(), step.triangles());
    let mut verts: Vec<u32> = tris.iter().flat_map(|&f| t[f as usize]).collect();
    verts.sort_unstable();
    verts.dedup();
    let mut edges: Vec<[u32; 2]> = tris
        .iter()
        .flat_map(|&f| {
            let [a, b, c] = t[f as usize];
            [
                [a.min(b), a.max(b)],
                [b.min(c), b.max(c)],
                [c.min(a), c.max(a)],
            ]
        })
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let opts = NarrowOptions::default();
    let mut found = Vec::new();
    let face_boxes: Vec<_> = tris
        .iter()
        .map(|&f| feature_box(step, &t[f as usize]))
        .collect();
    for &v in &verts {
        let vb = feature_box(step, &[v]);
        for (k, &f) in tris.iter().enumerate() {
            let tri = t[f as usize];
            if tri.contains(&v) || !boxes_meet(vb, face_boxes[k]) {
                continue;
            }
            let [a, b, c] = tri.map(|i| i as usize);
            let q = VertexFace {
                v_t0: x0[v as usize],
                f0_t0: x0[a],
                f1_t0: x0[b],
                f2_t0: x0[c],
                v_t1: x1[v as usize],
                f0_t1: x1[a],
                f1_t1: x1[b],
                f2_t1: x1[c],
            };
            if vertex_face(&q, &opts).is_contact() {
                found.push(format!("vertex {v} - face {f} {tri:?}"));
                if found.len() >= limit {
                    return found;
                }
            }
        }
    }
    let edge_boxes: Vec<_> = edges.iter().map(|e| feature_box(step, e)).collect();
    for i in 0..edges.len() {
        for j in i + 1..edges.len() {
            let ([a, b], [c, d]) = (edges[i], edges[j]);
            if a == c || a == d || b == c || b == d || !boxes_meet(edge_boxes[i], edge_boxes[j]) {
                continue;
            }
            let [a, b, c, d] = [a, b, c, d].map(|i| i as usize);
            let q = EdgeEdge {
                ea0_t0: x0[a],
                ea1_t0: x0[b],
                eb0_t0: x0[c],
                eb1_t0: x0[d],
                ea0_t1: x1[a],
                ea1_t1: x1[b],
                eb0_t1: x1[c],
                eb1_t1: x1[d],
            };
            if edge_edge(&q, &opts).is_contact() {
                found.push(format!("edge {:?} - edge {:?}", edges[i], edges[j]));
                if found.len() >= limit {
                    return found;
                }
            }
        }
    }
    found
}

/// The options of growth by the disk certificate alone (the paper's filter off), the query's.
fn certificate_growth() -> ClusterOptions {
    ClusterOptions {
        phi_filter: false,
        ..ClusterOptions::default()
    }
}

/// Clusters `step` with the paper's filter and without it (certificate alone), checks every
/// intermediate cluster by brute force and the bookkeeping; returns both clusterings.
fn check(name: &str, step: &Step) -> [Clustering; 2] {
    let with_phi = check_with(name, step, &ClusterOptions::default());
    let options = certificate_growth();
    let without = check_with(&format!("{name} (no phi)"), step, &options);
    [with_phi, without]
}

fn check_with(name: &str, step: &Step, options: &ClusterOptions) -> Clustering {
    let topo = Topology::new(step.triangles(), step.vertex_count());
    let c = cluster(step, &topo, options);
    verify(name, step, &c);
    c
}

/// Checks the bookkeeping of the clustering `c` of `step`, and every intermediate cluster by
/// brute force.
fn verify(name: &str, step: &Step, c: &Clustering) {
    let n = step.triangles().len();
    // Bookkeeping: every triangle in exactly one leaf, every leaf in exactly one IC.
    assert_eq!(c.leaf_of_triangle.len(), n);
    let mut seen = vec![0u32; n];
    for (l, leaf) in c.leaves.iter().enumerate() {
        for &t in c.leaf_triangles(l) {
            seen[t as usize] += 1;
            assert_eq!(c.leaf_of_triangle[t as usize], l as u32);
        }
        let rings: usize = (0..c.ring_count(l)).map(|k| c.ring(l, k).len()).sum();
        assert_eq!(rings, leaf.triangles.len());
    }
    assert!(
        seen.iter().all(|&s| s == 1),
        "{name}: a triangle is not in exactly one leaf"
    );
    let mut leaf_seen = vec![0u32; c.leaves.len()];
    for ic in 0..c.intermediates.len() {
        for &l in c.intermediate_leaves(ic) {
            leaf_seen[l as usize] += 1;
            assert_eq!(c.intermediate_of_leaf[l as usize], ic as u32);
        }
    }
    assert!(
        leaf_seen.iter().all(|&s| s == 1),
        "{name}: a leaf is not in exactly one IC"
    );
    // Soundness.
    for ic in 0..c.intermediates.len() {
        let tris: Vec<u32> = c
            .intermediate_leaves(ic)
            .iter()
            .flat_map(|&l| c.leaf_triangles(l as usize).iter().copied())
            .collect();
        let bad = contacts_among(step, &tris, 5);
        assert!(
            bad.is_empty(),
            "{name}: contacts inside intermediate cluster {ic}: {bad:?}"
        );
    }
    let s = &c.stats;
    println!(
        "{name}: {} triangles, {} leaves, {} ICs, {:.1} tri/leaf, {:.1} tri/IC; stops: \
         phi {} certificate {} exhausted {}; merges ring {} union {}, refused box {} phi {} cert {}; disk failures {:?}",
        s.triangles,
        s.leaves,
        s.intermediates,
        s.triangles_per_leaf,
        s.triangles_per_intermediate,
        s.stops_phi,
        s.stops_certificate,
        s.stops_exhausted,
        s.merged_by_ring,
        s.merged_by_union,
        s.merge_rejected_box,
        s.merge_rejected_phi,
        s.merge_rejected_certificate,
        s.disk_failures
    );
}

fn assert_has_contacts(name: &str, step: &Step) {
    let all: Vec<u32> = (0..step.triangles().len() as u32).collect();
    let found = contacts_among(step, &all, 1);
    assert!(
        !found.is_empty(),
        "{name}: the adversarial mesh has no contact at all"
    );
}

// ---------------------------------------------------------------- smooth meshes

#[test]
fn flat_sheet_gives_big_clusters() {
    let step = grid(
        30,
        30,
        |u, v| DVec3::new(u, v, 0.0),
        |u, v| DVec3::new(u + 0.05 * v, v + 0.02 * (3.0 * u).sin(), 0.3),
    );
    for c in check("flat sheet", &step) {
        assert!(c.stats.triangles_per_leaf > 100.0, "{:?}", c.stats);
    }
}

#[test]
fn gently_curved_dome() {
    // A convex cap (normals up, bulging up) flattening and drifting during the step: the
    // paper's criterion holds on convex parts.
    let step = grid(
        34,
        30,
        |u, v| DVec3::new(u, v, -0.3 * ((u - 0.5).powi(2) + (v - 0.5).powi(2))),
        |u, v| {
            DVec3::new(
                u + 0.03,
                v - 0.02,
                0.1 - 0.15 * ((u - 0.45).powi(2) + (v - 0.5).powi(2)),
            )
        },
    );
    for c in check("dome", &step) {
        assert!(c.stats.triangles_per_leaf > 50.0, "{:?}", c.stats);
    }
}

#[test]
fn wavy_sheets() {
    // Saddles and hollows everywhere: the paper's criterion (observation point on the surface)
    // fails at the first ring around most seeds; the certificate alone does not.
    for seed in 0..3u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (a, b, w) = (
            rng.random_range(0.02..0.08),
            rng.random_range(0.02..0.08),
            rng.random_range(2.0..5.0),
        );
        let step = grid(
            32,
            28,
            |u, v| DVec3::new(u, v, a * (w * u).sin() * (w * v).cos()),
            |u, v| DVec3::new(u + 0.02, v, b * (w * u + 0.7).sin() * (w * v).cos() + 0.05),
        );
        let [_, certificate_only] = check(&format!("wavy sheet {seed}"), &step);
        assert!(
            certificate_only.stats.triangles_per_leaf > 20.0,
            "{:?}",
            certificate_only.stats
        );
    }
}

#[test]
fn deforming_sphere() {
    let step = sphere(
        20,
        40,
        |p| p,
        |p| DVec3::new(1.2 * p.x, 0.9 * p.y, p.z + 0.1 * (3.0 * p.x).sin()) + DVec3::X * 0.2,
    );
    for c in check("sphere", &step) {
        assert!(c.stats.triangles_per_leaf > 20.0, "{:?}", c.stats);
        // No leaf can cover a closed surface.
        assert!(c.stats.leaves >= 2);
    }
}

// ---------------------------------------------------------------- adversarial meshes

#[test]
fn helicoid_with_a_turn_pushed_through_the_one_below() {
    let step = mesh_util::sinking_helicoid();
    assert_has_contacts("helicoid", &step);
    check("helicoid", &step);
}

#[test]
fn tight_fold() {
    let step = mesh_util::tight_fold();
    assert_has_contacts("tight fold", &step);
    check("tight fold", &step);
}

#[test]
fn crumpled_sheets() {
    for seed in 0..3u64 {
        let step = mesh_util::crumpled(24, 100 + seed);
        assert_has_contacts("crumpled sheet", &step);
        check(&format!("crumpled sheet {seed}"), &step);
    }
}

#[test]
fn torn_pieces_pressed_together() {
    let step = mesh_util::torn_pieces();
    assert_has_contacts("torn pieces", &step);
    check("torn pieces", &step);
}

#[test]
fn partial_tear_with_flaps_pressed_together() {
    let step = mesh_util::partial_tear();
    assert_has_contacts("partial tear", &step);
    check("partial tear", &step);
}

// ---------------------------------------------------------------- the paper's criterion alone

/// Leaf clusters grown with the paper's `phi >= 0` alone (no disk certificate).
fn phi_only_leaves(step: &Step, topo: &Topology) -> Vec<Vec<u32>> {
    let n = step.triangles().len();
    let mut taken = vec![false; n];
    let mut leaves = Vec::new();
    let corners = |t: u32| {
        let tri = step.triangles()[t as usize];
        (
            tri.map(|v| step.pos0()[v as usize]),
            tri.map(|v| step.pos1()[v as usize]),
        )
    };
    for seed in 0..n as u32 {
        if taken[seed as usize] {
            continue;
        }
        taken[seed as usize] = true;
        let (s0, s1) = corners(seed);
        let o = [(s0[0] + s0[1] + s0[2]) / 3.0, (s1[0] + s1[1] + s1[2]) / 3.0];
        let mut leaf = vec![seed];
        let mut verts: Vec<u32> = step.triangles()[seed as usize].to_vec();
        let mut frontier = verts.clone();
        loop {
            let mut ring: Vec<u32> = frontier
                .iter()
                .flat_map(|&v| topo.triangles_of(v).iter().copied())
                .filter(|&t| !taken[t as usize])
                .collect();
            ring.sort_unstable();
            ring.dedup();
            if ring.is_empty()
                || ring.iter().any(|&t| {
                    let (p0, p1) = corners(t);
                    phi(&p0, &p1, o).nonnegative(2) != Verdict::Holds
                })
            {
                break;
            }
            frontier.clear();
            for &t in &ring {
                taken[t as usize] = true;
                for v in step.triangles()[t as usize] {
                    if !verts.contains(&v) {
                        verts.push(v);
                        frontier.push(v);
                    }
                }
            }
            leaf.extend(ring);
        }
        leaves.push(leaf);
    }
    leaves
}

#[test]
fn paper_criterion_alone_is_unsound_on_a_helicoid() {
    let step = mesh_util::phi_adversarial_helicoid();
    let topo = Topology::new(step.triangles(), step.vertex_count());
    assert_has_contacts("phi helicoid", &step);
    let leaves = phi_only_leaves(&step, &topo);
    let biggest = leaves.iter().map(Vec::len).max().unwrap_or(0);
    let bad: Vec<_> = leaves
        .iter()
        .filter(|l| l.len() > 1)
        .flat_map(|l| contacts_among(&step, l, 1))
        .collect();
    println!(
        "phi-only on the helicoid: {} leaves, biggest {biggest} of {} triangles, contacts inside: {bad:?}",
        leaves.len(),
        step.triangles().len()
    );
    assert!(
        !bad.is_empty(),
        "phi alone should have put touching features in one cluster"
    );
    // The certified clustering of the same mesh has none, with or without the paper's filter.
    check("phi helicoid", &step);
}

// ---------------------------------------------------------------- randomized stress

#[test]
fn random_large_smooth_deformations() {
    // Sheets and blobs under random smooth deformations large enough to fold them through
    // themselves; every intermediate cluster brute-forced, with and without the paper's filter.
    let mut contacts = 0;
    for seed in 0..24u64 {
        let step = mesh_util::random_smooth(seed);
        let all: Vec<u32> = (0..step.triangles().len() as u32).collect();
        contacts += usize::from(!contacts_among(&step, &all, 1).is_empty());
        check(&format!("random {seed}"), &step);
    }
    println!("random deformations with contacts: {contacts} of 24");
    assert!(
        contacts >= 4,
        "the random deformations should often self-intersect"
    );
}

#[test]
fn positive_min_separation_turns_clustering_off() {
    let step = grid(
        8,
        8,
        |u, v| DVec3::new(u, v, 0.0),
        |u, v| DVec3::new(u, v, 0.1),
    );
    let topo = Topology::new(step.triangles(), step.vertex_count());
    let options = ClusterOptions {
        min_distance: 1e-3,
        ..ClusterOptions::default()
    };
    let c = cluster(&step, &topo, &options);
    assert_eq!(c.leaves.len(), step.triangles().len());
    assert_eq!(c.intermediates.len(), c.leaves.len());
    assert!(c
        .leaves
        .iter()
        .all(|l| l.certificate == topoccd::broad::cluster::LeafCertificate::SingleTriangle));
}

// ---------------------------------------------------------------- leaves carried over steps

/// Over sequences of one mesh deforming ever more, until it folds through itself, each step
/// clustered with the workspace of the last (`ClusterOptions::reuse`): the last step's leaves
/// are offered and certified anew. Every intermediate cluster of every step is brute-forced;
/// leaves must have been kept, some only their first rings, and others must have failed and
/// been regrown.
#[test]
fn leaves_carried_over_a_deforming_sequence_stay_sound() {
    let options = certificate_growth();
    let frames = 9;
    let (mut kept, mut trimmed, mut regrown, mut contacts) = (0, 0, 0, 0);
    for seed in 0..6u64 {
        let mut workspace = ClusterWorkspace::default();
        let mut c = Clustering::default();
        for k in 0..frames - 1 {
            let step = mesh_util::warped_step(seed, k, frames);
            let topo = Topology::new(step.triangles(), step.vertex_count());
            cluster_into(&step, &topo, &options, &mut workspace, &mut c);
            verify(&format!("sequence {seed} step {k}"), &step, &c);
            kept += c.stats.reused_leaves;
            trimmed += c.stats.trimmed_leaves;
            regrown += c.stats.regrown_leaves;
            let all: Vec<u32> = (0..step.triangles().len() as u32).collect();
            contacts += usize::from(!contacts_among(&step, &all, 1).is_empty());
        }
    }
    println!("kept {kept} ({trimmed} trimmed), regrown {regrown}, steps with contacts {contacts}");
    assert!(kept > 0, "no leaf was carried over");
    assert!(
        trimmed > 0,
        "no leaf was trimmed: the sequences do not test trimming"
    );
    assert!(
        regrown > 0,
        "every leaf passed again: the sequences do not test the regrowth"
    );
    assert!(
        contacts >= 3,
        "the sequences should fold through themselves"
    );
}

/// The leaves carried over a sequence, certified anew on the rayon pool, are the same on one
/// thread as on three.
#[test]
fn leaves_carried_over_are_the_same_on_any_thread_count() {
    let options = certificate_growth();
    let frames = 9;
    let on = |threads: usize, seed: u64| -> Vec<Clustering> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut workspace = ClusterWorkspace::default();
            (0..frames - 1)
                .map(|k| {
                    let step = mesh_util::warped_step(seed, k, frames);
                    let topo = Topology::new(step.triangles(), step.vertex_count());
                    let mut c = Clustering::default();
                    cluster_into(&step, &topo, &options, &mut workspace, &mut c);
                    c
                })
                .collect()
        })
    };
    for seed in [0, 3] {
        let (one, three) = (on(1, seed), on(3, seed));
        for (k, (a, b)) in one.iter().zip(&three).enumerate() {
            let what = format!("sequence {seed} step {k}");
            assert_eq!(a.leaves, b.leaves, "{what}");
            assert_eq!(a.leaf_triangles, b.leaf_triangles, "{what}");
            assert_eq!(a.last_ring_vertices, b.last_ring_vertices, "{what}");
            assert_eq!(a.intermediate_leaves, b.intermediate_leaves, "{what}");
            let counts = |c: &Clustering| {
                let s = &c.stats;
                (s.reused_leaves, s.trimmed_leaves, s.regrown_leaves)
            };
            assert_eq!(counts(a), counts(b), "{what}");
        }
        assert!(
            one.iter().any(|c| c.stats.reused_leaves > 0),
            "sequence {seed}"
        );
    }
}

/// The same step clustered again with the same workspace keeps every leaf as grown: the new
/// certificate of a kept leaf is that of its growth (same direction, same centre), so it
/// passes, and the clustering is the same.
#[test]
fn the_same_step_again_keeps_every_leaf() {
    let options = certificate_growth();
    for seed in 0..12u64 {
        let step = mesh_util::random_smooth(seed);
        let topo = Topology::new(step.triangles(), step.vertex_count());
        let mut workspace = ClusterWorkspace::default();
        let (mut first, mut again) = (Clustering::default(), Clustering::default());
        cluster_into(&step, &topo, &options, &mut workspace, &mut first);
        cluster_into(&step, &topo, &options, &mut workspace, &mut again);
        assert!(
            first.leaves.iter().any(|l| l.triangles.len() > 1),
            "random {seed}"
        );
        assert_eq!(first.stats.reused_leaves, 0, "random {seed}");
        assert_eq!(
            (again.stats.reused_leaves, again.stats.regrown_leaves),
            (first.leaves.len(), 0),
            "random {seed}"
        );
        assert_eq!(again.leaves, first.leaves, "random {seed}");
        assert_eq!(again.leaf_triangles, first.leaf_triangles, "random {seed}");
        assert_eq!(again.ring_starts, first.ring_starts, "random {seed}");
        assert_eq!(
            again.last_ring_vertices, first.last_ring_vertices,
            "random {seed}"
        );
        assert_eq!(
            again.intermediate_leaves, first.intermediate_leaves,
            "random {seed}"
        );
        // Without reuse, or with other triangles, nothing is carried over.
        let fresh = ClusterOptions {
            reuse: false,
            ..options
        };
        cluster_into(&step, &topo, &fresh, &mut workspace, &mut again);
        assert_eq!(again.stats.reused_leaves, 0, "random {seed}");
        assert_eq!(again.leaves, first.leaves, "random {seed}");
        let mut fewer = step.triangles().to_vec();
        fewer.pop();
        let (x0, x1) = (step.pos0().to_vec(), step.pos1().to_vec());
        let cut = Step::new(x0, x1, fewer).unwrap();
        let cut_topo = Topology::new(cut.triangles(), cut.vertex_count());
        cluster_into(&step, &topo, &options, &mut workspace, &mut again);
        cluster_into(&cut, &cut_topo, &options, &mut workspace, &mut again);
        assert_eq!(
            again.stats.reused_leaves + again.stats.regrown_leaves,
            0,
            "random {seed}"
        );
        verify(&format!("random {seed} cut"), &cut, &again);
    }
}
