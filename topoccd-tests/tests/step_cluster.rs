//! The cluster method (the paper's section 4.3) against the oracle: the same pairs and bitwise the
//! same times of impact on the seeded scenes of the equivalence suite, on adversarial meshes
//! built to break the paper's clustering criterion, on a sequence whose topology changes every
//! step, and on both real cloth steps (every ground-truth pair found). Structurally: every
//! feature pair tested at most once, the trees validated after every query, and the pairs it
//! skips compared with the per-step BVH are exactly those inside one intermediate cluster.

mod mesh_util;

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use topoccd::io::{read_mesh, read_scene_truth, scene_frames};
use topoccd::kdop::{DopKind, Kdop};
use topoccd::narrow::{edge_edge, vertex_face, EdgeEdge, NarrowOptions, VertexFace};
use topoccd::{Ccd, ClusterGrowth, Method, Mode, QueryOptions, Report, Step};
use topoccd_scenes::SceneKind;

const GROWTHS: [ClusterGrowth; 2] = [ClusterGrowth::Paper, ClusterGrowth::Certificate];

/// The candidate pairs of the last query, sorted (after checking that none repeats).
struct CandidateSets {
    vf: Vec<[u32; 2]>,
    /// Edge pairs by vertex indices, so that they compare across steps' edge numberings.
    ee: Vec<([u32; 2], [u32; 2])>,
}

/// Sorts `v` and asserts that no element repeats.
fn sorted_unique<T: Ord + Copy + std::fmt::Debug>(mut v: Vec<T>, what: &str) -> Vec<T> {
    v.sort_unstable();
    if let Some(w) = v.windows(2).find(|w| w[0] == w[1]) {
        panic!("{what}: candidate {:?} tested twice", w[0]);
    }
    v
}

/// The elements of sorted `a` missing from sorted `b`.
fn missing<T: Ord + Copy>(a: &[T], b: &[T]) -> Vec<T> {
    a.iter()
        .filter(|x| b.binary_search(x).is_err())
        .copied()
        .collect()
}

fn candidate_sets(ccd: &Ccd, report: &Report, what: &str) -> CandidateSets {
    let c = ccd.candidates();
    let vf = sorted_unique(c.vf.to_vec(), what);
    let ee =
        c.ee.iter()
            .map(|&[e, f]| {
                assert!(e < f, "{what}: edge pair not ordered");
                (c.edges[e as usize], c.edges[f as usize])
            })
            .collect();
    let ee = sorted_unique(ee, what);
    assert_eq!(report.stats.vf_tests, c.vf.len() as u64, "{what}");
    assert_eq!(report.stats.ee_tests, c.ee.len() as u64, "{what}");
    CandidateSets { vf, ee }
}

/// The owner of each vertex and edge (its incident triangle of lowest index), computed here
/// independently of the crate.
struct Owners {
    vertex: Vec<u32>,
    edge: HashMap<[u32; 2], u32>,
}

fn owners(step: &Step) -> Owners {
    let mut vertex = vec![u32::MAX; step.vertex_count()];
    let mut edge = HashMap::new();
    for (t, tri) in step.triangles().iter().enumerate() {
        for k in 0..3 {
            let v = &mut vertex[tri[k] as usize];
            *v = (*v).min(t as u32);
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            edge.entry([a.min(b), a.max(b)]).or_insert(t as u32);
        }
    }
    Owners { vertex, edge }
}

/// Whether two triangles lie in one intermediate cluster of the last cluster query.
fn same_ic(ccd: &Ccd, a: u32, b: u32) -> bool {
    let c = ccd.clustering();
    let ic = |t: u32| c.intermediate_of_leaf[c.leaf_of_triangle[t as usize] as usize];
    ic(a) == ic(b)
}

/// The cluster method's candidates are the BVH method's minus exactly the pairs whose owner
/// triangles lie in one intermediate cluster. Returns the pairs skipped.
fn assert_skips_only_inside_clusters(
    step: &Step,
    ccd: &Ccd,
    cluster: &CandidateSets,
    bvh: &CandidateSets,
    what: &str,
) -> CandidateSets {
    let own = owners(step);
    for p in &cluster.vf {
        assert!(
            !same_ic(ccd, own.vertex[p[0] as usize], p[1]),
            "{what}: {p:?} tested inside one cluster"
        );
    }
    assert!(
        missing(&cluster.vf, &bvh.vf).is_empty(),
        "{what}: not BVH candidates"
    );
    assert!(
        missing(&cluster.ee, &bvh.ee).is_empty(),
        "{what}: not BVH candidates"
    );
    let vf = missing(&bvh.vf, &cluster.vf);
    let ee = missing(&bvh.ee, &cluster.ee);
    for p in &vf {
        assert!(
            same_ic(ccd, own.vertex[p[0] as usize], p[1]),
            "{what}: {p:?} skipped across clusters"
        );
    }
    for (a, b) in &ee {
        assert!(
            same_ic(ccd, own.edge[a], own.edge[b]),
            "{what}: {a:?} {b:?} skipped across clusters"
        );
    }
    CandidateSets { vf, ee }
}

/// Runs the cluster method in both modes, for both growths and the given k-DOPs, and checks it
/// bitwise against `reference` (an All report of the oracle, or of the BVH method where the
/// two differ by proved near-misses). With `structure`, at k = 18 also checks the skipped pairs
/// against the BVH method's, and that without trusting the certificates the candidates are
/// exactly the BVH method's.
fn check_cluster(
    step: &Step,
    options: &QueryOptions,
    reference: &Report,
    kinds: &[DopKind],
    structure: bool,
    ccd: &mut Ccd,
    what: &str,
) {
    for growth in GROWTHS {
        for &kdop in kinds {
            let what = format!("{what} {growth} k {kdop}");
            let mut options = QueryOptions {
                growth,
                kdop,
                mode: Mode::All,
                ..*options
            };
            let report = ccd.query(step, Method::Cluster, &options).unwrap();
            assert_eq!(ccd.validate_tree(step), Ok(()), "{what}");
            let sets = candidate_sets(ccd, &report, &what);
            assert_eq!(report.vf, reference.vf, "{what}: vertex-face");
            assert_eq!(report.ee, reference.ee, "{what}: edge-edge");
            assert_eq!(report.earliest, reference.earliest, "{what}");
            let figures = report.stats.cluster.expect("cluster figures");
            assert_eq!(figures.leaf, ccd.clustering().leaves.len(), "{what}");
            assert_eq!(figures.uncertified_leaves, 0, "{what}");
            assert!(report.stats.seconds.clustering.is_some(), "{what}");

            if structure && kdop == DopKind::K18 {
                // All pairs: Earliest's per-step hierarchy may look at the step in two passes.
                let quick = QueryOptions {
                    mode: Mode::All,
                    ..options
                };
                let clustering = ccd.clustering().clone();
                let bvh = ccd.query(step, Method::Bvh, &quick).unwrap();
                let bvh_sets = candidate_sets(ccd, &bvh, &what);
                // The BVH query leaves the last clustering in place.
                assert_skips_only_inside_clusters(step, ccd, &sets, &bvh_sets, &what);
                ccd.distrust_certificates(true);
                let all = ccd.query(step, Method::Cluster, &quick).unwrap();
                ccd.distrust_certificates(false);
                assert_eq!(ccd.validate_tree(step), Ok(()), "{what}");
                let again = ccd.clustering();
                assert!(
                    again.leaf_of_triangle == clustering.leaf_of_triangle
                        && again.leaves == clustering.leaves
                        && again.intermediate_leaves == clustering.intermediate_leaves,
                    "{what}: the clustering is not deterministic"
                );
                let all_sets = candidate_sets(ccd, &all, &what);
                assert!(
                    all_sets.vf == bvh_sets.vf && all_sets.ee == bvh_sets.ee,
                    "{what}: without certificates the candidates must be the BVH method's"
                );
                let multi = clustering.leaves.iter().filter(|l| l.triangles.len() > 1);
                let distrusted = all.stats.cluster.map(|f| f.uncertified_leaves);
                assert_eq!(distrusted, Some(multi.count()), "{what}");
            }

            options.mode = Mode::Earliest;
            let earliest = ccd.query(step, Method::Cluster, &options).unwrap();
            assert_eq!(ccd.validate_tree(step), Ok(()), "{what}");
            candidate_sets(ccd, &earliest, &what);
            assert_eq!(earliest.earliest, reference.earliest, "{what}: earliest");
            mesh_util::assert_earliest_pairs(reference, &earliest, options.narrow.tolerance, &what);
        }
    }
}

/// Checks the cluster method on `step` ([`check_cluster`]) against the oracle. With `exact`,
/// the reference is the oracle's report. Without, it is the BVH method's: where the two
/// differ, every pair only the oracle reports must be a conservative near-miss of the narrow
/// phase whose owner triangles' swept 18-DOPs are disjoint (so the pair provably does not
/// touch, and neither hierarchy method tests it).
fn check_step(
    step: &Step,
    min_distance: f64,
    kinds: &[DopKind],
    exact: bool,
    ccd: &mut Ccd,
    what: &str,
) {
    let mut options = QueryOptions::default();
    options.narrow.min_distance = min_distance;
    if min_distance > 0.0 {
        // The elementary tests slow down when the separation is large against the tolerance.
        options.narrow.tolerance = min_distance;
    }
    let what = format!("{what} sep {min_distance}");
    let oracle = ccd.query(step, Method::Brute, &options).unwrap();
    assert!(oracle.contact_count() > 0, "{what}: the step must collide");
    let reference = if exact {
        oracle
    } else {
        let bvh = ccd.query(step, Method::Bvh, &options).unwrap();
        let near_misses = assert_near_misses(step, &oracle, &bvh, min_distance, &what);
        println!("{what}: the oracle reports {near_misses} proved near-misses");
        bvh
    };
    check_cluster(step, &options, &reference, kinds, true, ccd, &what);
}

/// Every pair of `oracle` missing from `bvh` (which must hold no other) has owner triangles
/// with disjoint swept 18-DOPs. Returns their number.
fn assert_near_misses(step: &Step, oracle: &Report, bvh: &Report, sep: f64, what: &str) -> usize {
    let own = owners(step);
    let volume = |t: u32| {
        let tri = step.triangles()[t as usize];
        Kdop::<9>::swept_triangle(
            &tri.map(|v| step.pos0()[v as usize]),
            &tri.map(|v| step.pos1()[v as usize]),
            sep,
        )
    };
    let disjoint = |a: u32, b: u32| !volume(a).overlaps(&volume(b));
    let vf: HashSet<_> = oracle.vf.iter().map(|c| (c.vertex, c.face)).collect();
    let ee: HashSet<_> = oracle.ee.iter().map(|c| (c.a, c.b)).collect();
    assert!(
        bvh.vf.iter().all(|c| vf.contains(&(c.vertex, c.face))),
        "{what}"
    );
    assert!(bvh.ee.iter().all(|c| ee.contains(&(c.a, c.b))), "{what}");
    let bvh_vf: HashSet<_> = bvh.vf.iter().map(|c| (c.vertex, c.face)).collect();
    let bvh_ee: HashSet<_> = bvh.ee.iter().map(|c| (c.a, c.b)).collect();
    let mut count = 0;
    for &(v, f) in vf.difference(&bvh_vf) {
        assert!(disjoint(own.vertex[v as usize], f), "{what}: ({v}, {f})");
        count += 1;
    }
    for (a, b) in ee.difference(&bvh_ee) {
        assert!(disjoint(own.edge[a], own.edge[b]), "{what}: {a:?} {b:?}");
        count += 1;
    }
    count
}

/// Sizes of the equivalence suite.
fn size(kind: SceneKind) -> usize {
    match kind {
        SceneKind::SmallObjects => 12,
        SceneKind::FoldedSheet => 11,
        _ => 14,
    }
}

fn check_kind(kind: SceneKind) {
    let mut ccd = Ccd::new();
    ccd.record_candidates(true);
    for seed in 0..4 {
        for sep in [0.0, 1e-3] {
            let step = kind.generate(size(kind), seed);
            // Every k on half the scenes, the paper's 18-DOP on the others.
            let kinds: &[DopKind] = if seed % 2 == 0 {
                &DopKind::ALL
            } else {
                &[DopKind::K18]
            };
            let what = format!("{} {seed}", kind.name());
            check_step(&step, sep, kinds, true, &mut ccd, &what);
        }
    }
}

#[test]
fn crumpled_sheets_match_the_oracle() {
    check_kind(SceneKind::CrumpledSheet);
}

#[test]
fn folded_sheets_match_the_oracle() {
    check_kind(SceneKind::FoldedSheet);
}

#[test]
fn small_objects_match_the_oracle() {
    check_kind(SceneKind::SmallObjects);
}

#[test]
fn torn_sheets_match_the_oracle() {
    check_kind(SceneKind::TornSheet);
}

#[test]
fn adversarial_meshes_match_the_oracle() {
    let mut ccd = Ccd::new();
    ccd.record_candidates(true);
    let mut steps = vec![
        ("sinking helicoid", mesh_util::sinking_helicoid_with(161)),
        ("phi helicoid", mesh_util::phi_adversarial_helicoid()),
        ("tight fold", mesh_util::tight_fold()),
        ("torn pieces", mesh_util::torn_pieces()),
        ("partial tear", mesh_util::partial_tear()),
    ];
    for seed in 0..3 {
        steps.push(("crumpled", mesh_util::crumpled(24, 100 + seed)));
    }
    // The seeds whose deformation folds the mesh through itself.
    for seed in [2, 5, 8, 14, 17, 19, 22, 23] {
        steps.push(("random smooth", mesh_util::random_smooth(seed)));
    }
    for (name, step) in &steps {
        check_step(step, 0.0, &[DopKind::K18], false, &mut ccd, name);
        // The clusters must be big somewhere, or nothing was tested.
        ccd.query(step, Method::Cluster, &QueryOptions::default())
            .unwrap();
        let c = ccd.clustering();
        let biggest = (0..c.intermediates.len())
            .map(|i| c.intermediates[i].triangle_count)
            .max()
            .unwrap_or(0);
        assert!(biggest >= 8, "{name}: biggest cluster {biggest} triangles");
    }
}

/// Step `k` of a sequence whose topology changes every step: a crumpled sheet with some faces
/// removed (a different set every step) and cut along a row and, on odd steps, a column (the
/// vertices of the cut duplicated), the pieces pressed into each other.
fn changing_step(k: u64) -> Step<'static> {
    let n = 16usize;
    let base = mesh_util::crumpled(n, 500 + k);
    let side = n + 1;
    let row = |v: u32| v as usize / side;
    let col = |v: u32| v as usize % side;
    let (mut x0, mut x1) = (base.pos0().to_vec(), base.pos1().to_vec());
    let cut_row = 4 + 2 * k as usize;
    let cut_col = if k % 2 == 1 {
        Some(5 + k as usize)
    } else {
        None
    };
    let h = 1.0 / n as f64;
    let mut copies: HashMap<(u32, u8), u32> = HashMap::new();
    let mut triangles = Vec::new();
    for (f, tri) in base.triangles().iter().enumerate() {
        if (f as u64 * 7 + k * 13).is_multiple_of(11) {
            continue; // removed this step
        }
        let upper = tri.iter().any(|&v| row(v) > cut_row);
        let right = cut_col.is_some_and(|c| tri.iter().any(|&v| col(v) > c));
        let piece = u8::from(upper) + 2 * u8::from(right);
        let mapped = tri.map(|v| {
            let on_cut = (upper && row(v) == cut_row) || (right && Some(col(v)) == cut_col);
            if piece == 0 || !on_cut {
                return v;
            }
            *copies.entry((v, piece)).or_insert_with(|| {
                x0.push(x0[v as usize]);
                x1.push(x1[v as usize]);
                (x0.len() - 1) as u32
            })
        });
        triangles.push(mapped);
    }
    // Press the pieces into each other: every vertex of a piece other than 0 moves with it.
    let mut moved = vec![false; x1.len()];
    for tri in &triangles {
        let upper = tri
            .iter()
            .any(|&v| v as usize >= side * side || row(v) > cut_row);
        for &v in tri {
            if upper && !moved[v as usize] && (v as usize >= side * side || row(v) >= cut_row) {
                moved[v as usize] = true;
                x1[v as usize] += topoccd::math::DVec3::new(0.0, -1.5 * h, -0.3 * h);
            }
        }
    }
    Step::new(x0, x1, triangles).expect("valid step")
}

#[test]
fn topology_changing_sequence_matches_the_oracle_at_every_step() {
    // One query object for the whole sequence: only scratch memory carries over.
    let mut ccd = Ccd::new();
    ccd.record_candidates(true);
    let mut last_triangles = Vec::new();
    for k in 0..6 {
        let step = changing_step(k);
        assert_ne!(
            step.triangles(),
            &last_triangles[..],
            "step {k}: same topology"
        );
        last_triangles = step.triangles().to_vec();
        let what = format!("changing step {k}");
        check_step(&step, 0.0, &[DopKind::K18], true, &mut ccd, &what);
    }
}

#[test]
fn deforming_sequence_matches_the_oracle_at_every_step() {
    // One query object for the whole sequence of one mesh, deforming ever more until it folds
    // through itself: the cluster method starts each step from the last step's leaves.
    for seed in [1, 3] {
        let mut ccd = Ccd::new();
        ccd.record_candidates(true);
        let frames = 9;
        let (mut collided, mut carried) = (0, 0);
        for k in 0..frames - 1 {
            let step = mesh_util::warped_step(seed, k, frames);
            let oracle = Ccd::new()
                .query(&step, Method::Brute, &QueryOptions::default())
                .unwrap();
            collided += usize::from(oracle.contact_count() > 0);
            let what = format!("warped sequence {seed} step {k}");
            let options = QueryOptions::default();
            // First from the last step's leaves, then every check on this step's.
            let report = ccd.query(&step, Method::Cluster, &options).unwrap();
            assert_eq!((&report.vf, &report.ee), (&oracle.vf, &oracle.ee), "{what}");
            let reused = ccd.clustering().stats.reused_leaves;
            assert!(
                k > 0 || reused == 0,
                "{what}: a leaf carried over from nothing"
            );
            carried += reused;
            check_cluster(
                &step,
                &options,
                &oracle,
                &[DopKind::K18],
                true,
                &mut ccd,
                &what,
            );
        }
        assert!(
            collided >= 3,
            "warped sequence {seed}: too few steps collide"
        );
        assert!(carried > 0, "warped sequence {seed}: no leaf carried over");
    }
}

// ---------------------------------------------------------------- the real cloth steps

/// The directory of a shared whole-step scene, or `None` (with a loud message) if absent.
fn scene_dir(scene: &str) -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data/scenes")
        .join(scene);
    if dir.is_dir() {
        Some(dir)
    } else {
        assert!(
            std::env::var_os("TOPOCCD_REQUIRE_DATA").is_none(),
            "TOPOCCD_REQUIRE_DATA is set but the shared data is absent (see the README)"
        );
        eprintln!(
            "\n!!!!! SKIPPED: shared data not found at {} -- this test checked NOTHING !!!!!\n",
            dir.display()
        );
        None
    }
}

fn read_real_step(dir: &Path) -> Step<'static> {
    let frames = scene_frames(dir).expect("frames");
    let m0 = read_mesh(&frames.t0).expect("t0");
    let m1 = read_mesh(&frames.t1).expect("t1");
    assert_eq!(m0.triangles, m1.triangles, "the frames' faces differ");
    let vectors = |positions: &[[f64; 3]]| -> Vec<topoccd::math::DVec3> {
        positions
            .iter()
            .map(|&p| topoccd::math::DVec3::from_array(p))
            .collect()
    };
    Step::new(vectors(&m0.positions), vectors(&m1.positions), m0.triangles).expect("valid step")
}

/// Every ground-truth touching pair is in the report.
fn assert_truth_found(dir: &Path, report: &Report, what: &str) {
    let truth = read_scene_truth(dir).expect("truth");
    let vf: HashSet<(u32, u32)> = report.vf.iter().map(|c| (c.vertex, c.face)).collect();
    let ee: HashSet<([u32; 2], [u32; 2])> = report.ee.iter().map(|c| (c.a, c.b)).collect();
    for p in &truth.vf {
        assert!(vf.contains(p), "{what}: touching {p:?} missed");
    }
    for p in &truth.ee {
        assert!(ee.contains(p), "{what}: touching {p:?} missed");
    }
    println!(
        "{what}: all {} vf and {} ee ground-truth pairs found ({} vf, {} ee reported)",
        truth.vf.len(),
        truth.ee.len(),
        report.vf.len(),
        report.ee.len()
    );
}

#[test]
fn cloth_funnel_matches_the_oracle_and_the_ground_truth() {
    let Some(dir) = scene_dir("cloth-funnel") else {
        return;
    };
    let step = read_real_step(&dir);
    let mut ccd = Ccd::new();
    ccd.record_candidates(true);
    let options = QueryOptions::default();
    let oracle = ccd.query(&step, Method::Brute, &options).unwrap();
    assert_truth_found(&dir, &oracle, "cloth-funnel oracle");
    check_cluster(
        &step,
        &options,
        &oracle,
        &[DopKind::K18],
        true,
        &mut ccd,
        "cloth-funnel",
    );
    let report = ccd.query(&step, Method::Cluster, &options).unwrap();
    assert_truth_found(&dir, &report, "cloth-funnel cluster");
}

#[test]
fn cloth_ball_matches_the_bvh_method_and_the_ground_truth() {
    let Some(dir) = scene_dir("cloth-ball") else {
        return;
    };
    let step = read_real_step(&dir);
    let mut ccd = Ccd::new();
    ccd.record_candidates(true);
    let options = QueryOptions::default();
    let report = ccd.query(&step, Method::Cluster, &options).unwrap();
    assert_eq!(ccd.validate_tree(&step), Ok(()));
    assert_truth_found(&dir, &report, "cloth-ball cluster");
    let cluster = candidate_sets(&ccd, &report, "cloth-ball");
    let earliest = QueryOptions {
        mode: Mode::Earliest,
        ..options
    };
    let cluster_earliest = ccd.query(&step, Method::Cluster, &earliest).unwrap();
    assert_eq!(cluster_earliest.earliest, report.earliest);

    // The BVH method gives its candidates and earliest contact (in All mode: Earliest's first
    // pass looks at the start of the step only). The pairs it tests and the cluster method skips all lie inside one intermediate cluster, and
    // none of them touches even without the prefilter, so the BVH method's All report (the
    // narrow phase over its candidates) is the cluster method's: the same pairs, bitwise the
    // same times (the BVH method is itself tested equal to the oracle).
    let bvh_all = ccd.query(&step, Method::Bvh, &options).unwrap();
    assert_eq!(bvh_all.earliest, report.earliest);
    // All three methods report the same pairs with the same times on the real step.
    let brute = Ccd::new().query(&step, Method::Brute, &options).unwrap();
    assert_eq!(
        (&brute.vf, &brute.ee),
        (&bvh_all.vf, &bvh_all.ee),
        "cloth-ball brute vs bvh"
    );
    assert_eq!(
        (&report.vf, &report.ee),
        (&bvh_all.vf, &bvh_all.ee),
        "cloth-ball cluster vs bvh"
    );
    let bvh = candidate_sets(&ccd, &bvh_all, "cloth-ball bvh");
    let bvh_earliest = ccd.query(&step, Method::Bvh, &earliest).unwrap();
    assert_eq!(bvh_earliest.earliest, report.earliest);
    // The BVH query leaves the last clustering in place.
    let skipped = assert_skips_only_inside_clusters(&step, &ccd, &cluster, &bvh, "cloth-ball");
    let (x0, x1) = (step.pos0(), step.pos1());
    let narrow = NarrowOptions::default();
    for &[v, f] in &skipped.vf {
        let [a, b, c] = step.triangles()[f as usize].map(|i| i as usize);
        let v = v as usize;
        let q = VertexFace {
            v_t0: x0[v],
            f0_t0: x0[a],
            f1_t0: x0[b],
            f2_t0: x0[c],
            v_t1: x1[v],
            f0_t1: x1[a],
            f1_t1: x1[b],
            f2_t1: x1[c],
        };
        assert!(!vertex_face(&q, &narrow).is_contact(), "skipped {v} {f}");
    }
    for &([a0, a1], [b0, b1]) in &skipped.ee {
        let [a0, a1, b0, b1] = [a0, a1, b0, b1].map(|i| i as usize);
        let q = EdgeEdge {
            ea0_t0: x0[a0],
            ea1_t0: x0[a1],
            eb0_t0: x0[b0],
            eb1_t0: x0[b1],
            ea0_t1: x1[a0],
            ea1_t1: x1[a1],
            eb0_t1: x1[b0],
            eb1_t1: x1[b1],
        };
        assert!(
            !edge_edge(&q, &narrow).is_contact(),
            "skipped {a0} {a1} {b0} {b1}"
        );
    }
    let figures = report.stats.cluster.expect("figures");
    println!(
        "cloth-ball: {} of {} vf and {} of {} ee BVH candidates skipped inside clusters; {figures:?}",
        skipped.vf.len(),
        bvh.vf.len(),
        skipped.ee.len(),
        bvh.ee.len()
    );
}

/// On two threads the hierarchies over big leaf clusters are built while the other leaves grow
/// (here every leaf's, whether needed or not): the same report, candidates and clustering as on
/// one thread, where none is built ahead, and valid trees.
#[test]
fn hierarchies_built_ahead_change_nothing() {
    let pool = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool")
    };
    let mut taken = 0;
    for kind in SceneKind::ALL {
        let step = kind.generate(size(kind), 1);
        for mode in [Mode::All, Mode::Earliest] {
            let what = format!("{} {mode:?}", kind.name());
            let options = QueryOptions {
                mode,
                ..QueryOptions::default()
            };
            let run = |threads, ahead| {
                pool(threads).install(|| {
                    let mut ccd = Ccd::new();
                    ccd.record_candidates(true);
                    ccd.set_ahead_triangles(ahead);
                    let report = ccd.query(&step, Method::Cluster, &options).unwrap();
                    assert_eq!(ccd.validate_tree(&step), Ok(()), "{what}");
                    let sets = candidate_sets(&ccd, &report, &what);
                    let lazies = report.stats.cluster.map(|f| f.lazy_bvhs);
                    let clustering = ccd.clustering().clone();
                    (report, sets, lazies, clustering, ccd.lazy_built_ahead())
                })
            };
            let one = run(1, Some(1));
            let two = run(2, Some(1));
            assert_eq!(one.4, 0, "{what}: one thread builds nothing ahead");
            assert_eq!(
                two.4,
                two.2.unwrap_or(0),
                "{what}: every lazy hierarchy built ahead"
            );
            taken += two.4;
            assert_eq!((&one.0.vf, &one.0.ee), (&two.0.vf, &two.0.ee), "{what}");
            assert_eq!(one.0.earliest, two.0.earliest, "{what}");
            assert!(
                one.1.vf == two.1.vf && one.1.ee == two.1.ee,
                "{what}: candidates"
            );
            assert_eq!(one.2, two.2, "{what}: lazy hierarchies");
            let (a, b) = (&one.3, &two.3);
            assert!(
                a.leaf_of_triangle == b.leaf_of_triangle
                    && a.leaves == b.leaves
                    && a.intermediate_leaves == b.intermediate_leaves,
                "{what}: clustering"
            );
        }
    }
    assert!(
        taken > 0,
        "no lazy hierarchy was needed: the test shows nothing"
    );
}
