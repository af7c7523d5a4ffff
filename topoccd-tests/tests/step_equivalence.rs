//! The BVH pipeline against the brute-force oracle on seeded random scenes: the same pairs,
//! bitwise the same times of impact, in both modes, for every k-DOP, with and without a
//! minimum separation; every feature pair tested at most once; the hierarchy validated after
//! every build.

mod mesh_util;

use std::collections::HashSet;

use topoccd::kdop::DopKind;
use topoccd::{Ccd, Contact, Method, Mode, QueryOptions, Report, Step};
use topoccd_scenes::SceneKind;

/// Sizes small enough for the whole file to run in seconds in release mode.
fn size(kind: SceneKind) -> usize {
    match kind {
        SceneKind::SmallObjects => 12,
        SceneKind::FoldedSheet => 11,
        _ => 14,
    }
}

/// Asserts that the last query tested no feature pair twice, and that the counts match.
fn assert_tested_once(ccd: &Ccd, report: &Report, what: &str) {
    let c = ccd.candidates();
    let vf: HashSet<[u32; 2]> = c.vf.iter().copied().collect();
    let ee: HashSet<[u32; 2]> = c.ee.iter().copied().collect();
    assert_eq!(
        vf.len(),
        c.vf.len(),
        "{what}: a vertex-face pair tested twice"
    );
    assert_eq!(
        ee.len(),
        c.ee.len(),
        "{what}: an edge-edge pair tested twice"
    );
    assert_eq!(report.stats.vf_tests, c.vf.len() as u64, "{what}");
    assert_eq!(report.stats.ee_tests, c.ee.len() as u64, "{what}");
    for &[e, f] in c.ee {
        assert!(e < f, "{what}: edge pair not ordered");
    }
}

/// Asserts that no reported pair shares a vertex, and the order and ordering rules.
fn assert_well_formed(step: &Step, report: &Report, what: &str) {
    for c in &report.vf {
        let tri = step.triangles()[c.face as usize];
        assert!(!tri.contains(&c.vertex), "{what}: {c:?} shares a vertex");
        assert!((0.0..=1.0).contains(&c.toi), "{what}: {c:?}");
    }
    for c in &report.ee {
        assert!(
            c.a[0] < c.a[1] && c.b[0] < c.b[1] && c.a < c.b,
            "{what}: {c:?}"
        );
        assert!(
            !c.a.iter().any(|v| c.b.contains(v)),
            "{what}: {c:?} shares a vertex"
        );
        assert!((0.0..=1.0).contains(&c.toi), "{what}: {c:?}");
    }
    assert!(report
        .vf
        .windows(2)
        .all(|w| (w[0].vertex, w[0].face) < (w[1].vertex, w[1].face)));
    assert!(report
        .ee
        .windows(2)
        .all(|w| (w[0].a, w[0].b) < (w[1].a, w[1].b)));
}

/// The earliest contact of an `All` report, recomputed from its lists.
fn min_contact(report: &Report) -> Option<Contact> {
    let all = report.vf.iter().map(|&c| Contact::Vf(c));
    all.chain(report.ee.iter().map(|&c| Contact::Ee(c)))
        .min_by(Contact::earliest_order)
}

fn check_scene(kind: SceneKind, seed: u64, min_distance: f64, ccd: &mut Ccd) -> usize {
    let step = kind.generate(size(kind), seed);
    let mut options = QueryOptions::default();
    options.narrow.min_distance = min_distance;
    if min_distance > 0.0 {
        // The elementary tests slow down when the separation is large against the tolerance.
        options.narrow.tolerance = min_distance;
    }
    let what = format!("{} seed {seed} sep {min_distance}", kind.name());

    let oracle = ccd.query(&step, Method::Brute, &options).unwrap();
    assert_tested_once(ccd, &oracle, &what);
    assert_well_formed(&step, &oracle, &what);
    assert!(oracle.contact_count() > 0, "{what}: the scene must collide");
    assert_eq!(oracle.earliest, min_contact(&oracle), "{what}");

    options.mode = Mode::Earliest;
    let oracle_earliest = ccd.query(&step, Method::Brute, &options).unwrap();
    assert_eq!(
        oracle_earliest.earliest, oracle.earliest,
        "{what}: brute earliest"
    );

    for kdop in DopKind::ALL {
        let what = format!("{what} k {kdop}");
        options.kdop = kdop;
        options.mode = Mode::All;
        let bvh = ccd.query(&step, Method::Bvh, &options).unwrap();
        assert_eq!(ccd.validate_tree(&step), Ok(()), "{what}");
        assert_tested_once(ccd, &bvh, &what);
        let all_vf: HashSet<[u32; 2]> = ccd.candidates().vf.iter().copied().collect();
        let all_ee: HashSet<[u32; 2]> = ccd.candidates().ee.iter().copied().collect();
        // Bitwise equal: same pairs, same narrow phase, same times.
        assert_eq!(bvh.vf, oracle.vf, "{what}: vertex-face");
        assert_eq!(bvh.ee, oracle.ee, "{what}: edge-edge");
        assert_eq!(bvh.earliest, oracle.earliest, "{what}");
        assert!(bvh.stats.bv_tests > 0);

        options.mode = Mode::Earliest;
        let earliest = ccd.query(&step, Method::Bvh, &options).unwrap();
        assert_eq!(ccd.validate_tree(&step), Ok(()), "{what}");
        // Earliest may look at the step in two passes (its start, then the whole step), so a
        // pair may be tested once per pass; every one is a candidate of All.
        let c = ccd.candidates();
        assert_eq!(earliest.stats.vf_tests, c.vf.len() as u64, "{what}");
        assert_eq!(earliest.stats.ee_tests, c.ee.len() as u64, "{what}");
        assert!(
            c.vf.iter().all(|p| all_vf.contains(p)),
            "{what}: earliest vf candidate not in All's"
        );
        assert!(
            c.ee.iter().all(|p| all_ee.contains(p)),
            "{what}: earliest ee candidate not in All's"
        );
        assert_eq!(earliest.earliest, oracle.earliest, "{what}: earliest");
        mesh_util::assert_earliest_pairs(&oracle, &earliest, options.narrow.tolerance, &what);
    }
    oracle.contact_count()
}

fn check_kind(kind: SceneKind) {
    let mut ccd = Ccd::new();
    ccd.record_candidates(true);
    let mut contacts = 0;
    for seed in 0..6 {
        for sep in [0.0, 1e-3] {
            contacts += check_scene(kind, seed, sep, &mut ccd);
        }
    }
    println!("{}: {contacts} contacts over 12 scenes", kind.name());
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

/// Rule 6 of the pair filter (neighbours in a certified vertex star give no candidate) drops
/// only pairs that never touch: with it off, every method tests more pairs, never fewer, and
/// reports bitwise the same contacts; the oracle too. And it does drop pairs.
#[test]
fn certified_stars_drop_only_pairs_that_never_touch() {
    let sorted = |mut v: Vec<[u32; 2]>| {
        v.sort_unstable();
        v
    };
    let mut ccd = Ccd::new();
    ccd.record_candidates(true);
    let mut dropped = 0;
    for kind in SceneKind::ALL {
        for seed in 0..3 {
            let step = kind.generate(size(kind), seed);
            let options = QueryOptions::default();
            for method in [Method::Brute, Method::Bvh, Method::Cluster] {
                let what = format!("{} seed {seed} {method}", kind.name());
                ccd.distrust_stars(false);
                let with = ccd.query(&step, method, &options).unwrap();
                let (vf, ee) = (
                    sorted(ccd.candidates().vf.to_vec()),
                    sorted(ccd.candidates().ee.to_vec()),
                );
                ccd.distrust_stars(true);
                let without = ccd.query(&step, method, &options).unwrap();
                let c = ccd.candidates();
                let (all_vf, all_ee): (HashSet<_>, HashSet<_>) = (
                    c.vf.iter().copied().collect(),
                    c.ee.iter().copied().collect(),
                );
                assert!(vf.iter().all(|p| all_vf.contains(p)), "{what}: vf");
                assert!(ee.iter().all(|p| all_ee.contains(p)), "{what}: ee");
                dropped += all_vf.len() + all_ee.len() - vf.len() - ee.len();
                assert_eq!(with.vf, without.vf, "{what}: vertex-face");
                assert_eq!(with.ee, without.ee, "{what}: edge-edge");
                assert_eq!(with.earliest, without.earliest, "{what}");
            }
        }
    }
    ccd.distrust_stars(false);
    println!("rule 6 dropped {dropped} candidate pairs");
    assert!(dropped > 1000, "rule 6 should drop pairs: {dropped}");
}

/// One query object over a sequence whose triangles stay the same, as a simulator's: from the
/// second step on, the topology is kept and the per-step hierarchy refitted to the new volumes
/// (rebuilt only when it fits them too loosely). Every step must still match the oracle, in
/// both modes, with the candidates of a query object that starts from nothing, and the tree
/// must hold its leaves. A step with other triangles in between is rebuilt from scratch.
#[test]
fn a_sequence_of_the_same_triangles_refits_the_tree_and_matches_the_oracle() {
    let mut collided = 0;
    for seed in 0..4 {
        let frames = 9;
        let mut ccd = Ccd::new();
        ccd.record_candidates(true);
        let mut refitted = 0;
        for k in 0..frames - 1 {
            let step = mesh_util::warped_step(seed, k, frames);
            let what = format!("warped sequence {seed} step {k}");
            let mut options = QueryOptions::default();
            let oracle = Ccd::new().query(&step, Method::Brute, &options).unwrap();
            collided += usize::from(oracle.contact_count() > 0);
            let mut fresh = Ccd::new();
            fresh.record_candidates(true);
            let cold = fresh.query(&step, Method::Bvh, &options).unwrap();
            let report = ccd.query(&step, Method::Bvh, &options).unwrap();
            assert_eq!(ccd.validate_tree(&step), Ok(()), "{what}");
            assert!(
                k > 0 || !ccd.tree_refitted(),
                "{what}: refitted from nothing"
            );
            refitted += usize::from(ccd.tree_refitted());
            assert_tested_once(&ccd, &report, &what);
            assert_eq!((&report.vf, &report.ee), (&oracle.vf, &oracle.ee), "{what}");
            let sorted = |c: &[[u32; 2]]| {
                let mut c = c.to_vec();
                c.sort_unstable();
                c
            };
            assert_eq!(
                (sorted(ccd.candidates().vf), sorted(ccd.candidates().ee)),
                (sorted(fresh.candidates().vf), sorted(fresh.candidates().ee)),
                "{what}: the candidates of a fresh query"
            );
            assert_eq!(report.stats.vf_tests, cold.stats.vf_tests, "{what}");
            if k % 3 == 2 {
                // Earliest in between: its first pass sweeps other times, so the tree is
                // rebuilt for them, and the next All query rebuilds it again.
                options.mode = Mode::Earliest;
                let earliest = ccd.query(&step, Method::Bvh, &options).unwrap();
                assert_eq!(ccd.validate_tree(&step), Ok(()), "{what} earliest");
                assert_eq!(earliest.earliest, oracle.earliest, "{what}: earliest");
                let tolerance = options.narrow.tolerance;
                mesh_util::assert_earliest_pairs(&oracle, &earliest, tolerance, &what);
            }
        }
        assert!(
            refitted >= 3,
            "warped sequence {seed}: {refitted} steps refitted"
        );
        // Other triangles (the other mesh of the warped sequences), then these again.
        let options = QueryOptions::default();
        for (s, k) in [(seed + 1, 0), (seed, frames - 2)] {
            let step = mesh_util::warped_step(s, k, frames);
            let oracle = Ccd::new().query(&step, Method::Brute, &options).unwrap();
            let report = ccd.query(&step, Method::Bvh, &options).unwrap();
            let what = format!("warped sequence {s} step {k} after another mesh");
            assert!(
                !ccd.tree_refitted(),
                "{what}: refitted across a change of triangles"
            );
            assert_eq!(ccd.validate_tree(&step), Ok(()), "{what}");
            assert_eq!((&report.vf, &report.ee), (&oracle.vf, &oracle.ee), "{what}");
        }
    }
    println!("{collided} of 32 steps collide");
    assert!(collided >= 6, "too few steps collide: {collided}");
}

/// Over a shorter interval (`tmax` = 0.4) every method tests owner triangles with their
/// k-DOPs swept over `[0, tmax]`, the per-step hierarchy's leaves: the BVH, the cluster method
/// with its certificates distrusted, and the oracle report bitwise the same contacts, in both
/// modes. Against the whole step's query: a pair it reports more than two tolerances before
/// `tmax` is reported over the shorter interval too, within the tolerance of the same time,
/// and nothing is reported after `tmax`.
#[test]
fn a_shorter_interval_matches_the_oracle() {
    let mut ccd = Ccd::new();
    let tmax = 0.4;
    let mut checked = 0;
    for kind in SceneKind::ALL {
        for seed in 0..3 {
            let step = kind.generate(size(kind), seed);
            let whole_options = QueryOptions::default();
            let tol = whole_options.narrow.tolerance;
            let whole = ccd.query(&step, Method::Brute, &whole_options).unwrap();
            let mut options = whole_options;
            options.narrow.tmax = tmax;
            for mode in [Mode::All, Mode::Earliest] {
                options.mode = mode;
                let what = format!("{} seed {seed} {mode:?}", kind.name());
                let oracle = ccd.query(&step, Method::Brute, &options).unwrap();
                assert_well_formed(&step, &oracle, &what);
                let bvh = ccd.query(&step, Method::Bvh, &options).unwrap();
                assert_eq!(ccd.validate_tree(&step), Ok(()), "{what}");
                ccd.distrust_certificates(true);
                let cluster = ccd.query(&step, Method::Cluster, &options).unwrap();
                ccd.distrust_certificates(false);
                for (name, r) in [("bvh", &bvh), ("cluster", &cluster)] {
                    assert_eq!(r.vf, oracle.vf, "{what} {name}: vertex-face");
                    assert_eq!(r.ee, oracle.ee, "{what} {name}: edge-edge");
                    assert_eq!(r.earliest, oracle.earliest, "{what} {name}");
                }
                if mode == Mode::Earliest {
                    continue;
                }
                for c in &oracle.vf {
                    assert!(c.toi <= tmax, "{what}: {c:?}");
                }
                for c in &oracle.ee {
                    assert!(c.toi <= tmax, "{what}: {c:?}");
                }
                for c in whole.vf.iter().filter(|c| c.toi < tmax - 2.0 * tol) {
                    let found = oracle
                        .vf
                        .iter()
                        .find(|d| (d.vertex, d.face) == (c.vertex, c.face));
                    assert!(
                        found.is_some_and(|d| (d.toi - c.toi).abs() <= tol),
                        "{what}: {c:?}"
                    );
                    checked += 1;
                }
                for c in whole.ee.iter().filter(|c| c.toi < tmax - 2.0 * tol) {
                    let found = oracle.ee.iter().find(|d| (d.a, d.b) == (c.a, c.b));
                    assert!(
                        found.is_some_and(|d| (d.toi - c.toi).abs() <= tol),
                        "{what}: {c:?}"
                    );
                    checked += 1;
                }
            }
        }
    }
    println!("{checked} contacts before tmax found again");
    assert!(checked > 100, "too few contacts before tmax: {checked}");
}
