//! `Mode::Earliest` on the per-step BVH looks first at the step's start while the previous
//! Earliest query found its contact early, and at the whole step at once otherwise: both give
//! the same answer, that of `Mode::All` restricted to the earliest pairs.

mod mesh_util;

use topoccd::{Ccd, Method, Mode, QueryOptions, Step};
use topoccd_scenes::SceneKind;

/// A step with no contact at all: two far apart triangles, at rest.
fn quiet() -> Step<'static> {
    let x = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [10.0, 0.0, 0.0],
        [11.0, 0.0, 0.0],
        [10.0, 1.0, 0.0],
    ];
    Step::new(x.clone(), x, vec![[0, 1, 2], [3, 4, 5]]).expect("valid")
}

/// Checks that a fresh Earliest query (which tries the first pass) and one after a step
/// without contact (the whole step at once) both give the earliest pairs of `Mode::All`.
/// Returns the earliest time of impact.
fn check_both_passes(step: &Step<'_>, what: &str) -> Option<f64> {
    let earliest = QueryOptions {
        mode: Mode::Earliest,
        ..QueryOptions::default()
    };
    let reference = Ccd::new()
        .query(step, Method::Bvh, &QueryOptions::default())
        .unwrap();
    let first = Ccd::new().query(step, Method::Bvh, &earliest).unwrap();
    let mut ccd = Ccd::new();
    ccd.query(&quiet(), Method::Bvh, &earliest).unwrap();
    let whole = ccd.query(step, Method::Bvh, &earliest).unwrap();
    for report in [&first, &whole] {
        assert_eq!(report.earliest, reference.earliest, "{what}");
        mesh_util::assert_earliest_pairs(&reference, report, earliest.narrow.tolerance, what);
    }
    reference.earliest.map(|c| c.toi())
}

#[test]
fn both_passes_give_the_earliest_pairs_of_all() {
    let mut checked = 0;
    for kind in [
        SceneKind::CrumpledSheet,
        SceneKind::FoldedSheet,
        SceneKind::SmallObjects,
    ] {
        for seed in 0..4 {
            let step = kind.generate(16, seed);
            let what = format!("{} seed {seed}", kind.name());
            checked += usize::from(check_both_passes(&step, &what).is_some());
        }
    }
    assert!(checked > 6, "the scenes must collide");
}

/// Sheets big enough for the traversal to run in several batches of tasks: a first pass that
/// finds nothing early in its first batch stops there (the rest of the step goes to the second
/// pass), one that does goes on; the answer is the same either way, and it is that of
/// `Mode::All`.
#[test]
fn a_first_pass_cut_short_gives_the_same_answer() {
    // Later than this, the first pass (over the step's first 1/256) cannot settle the answer.
    let settles = 1.0 / 256.0 + 2.0 * QueryOptions::default().narrow.tolerance;
    let (mut late, mut early) = (0, 0);
    for kind in [SceneKind::CrumpledSheet, SceneKind::FoldedSheet] {
        for seed in 0..3 {
            let step = kind.generate(60, seed);
            let what = format!("{} seed {seed}", kind.name());
            assert!(step.triangles().len() > 5000, "{what} is too small");
            // Both kinds of steps occur: without an early contact (the first pass stops after
            // its first batch) and with one (it goes on).
            match check_both_passes(&step, &what) {
                Some(t) if t > settles => late += 1,
                Some(_) => early += 1,
                None => {}
            }
        }
    }
    assert!(late > 0 && early > 0, "late {late}, early {early}");
}
