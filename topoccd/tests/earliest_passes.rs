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

#[test]
fn both_passes_give_the_earliest_pairs_of_all() {
    let earliest = QueryOptions {
        mode: Mode::Earliest,
        ..QueryOptions::default()
    };
    let all = QueryOptions::default();
    let mut checked = 0;
    for kind in [
        SceneKind::CrumpledSheet,
        SceneKind::FoldedSheet,
        SceneKind::SmallObjects,
    ] {
        for seed in 0..4 {
            let step = kind.generate(16, seed);
            let reference = Ccd::new().query(&step, Method::Bvh, &all).unwrap();
            // A fresh query tries the first pass.
            let first = Ccd::new().query(&step, Method::Bvh, &earliest).unwrap();
            // After a step without contact, the whole step at once.
            let mut ccd = Ccd::new();
            ccd.query(&quiet(), Method::Bvh, &earliest).unwrap();
            let whole = ccd.query(&step, Method::Bvh, &earliest).unwrap();
            let what = format!("{} seed {seed}", kind.name());
            for report in [&first, &whole] {
                assert_eq!(report.earliest, reference.earliest, "{what}");
                mesh_util::assert_earliest_pairs(
                    &reference,
                    report,
                    earliest.narrow.tolerance,
                    &what,
                );
            }
            checked += usize::from(reference.earliest.is_some());
        }
    }
    assert!(checked > 6, "the scenes must collide");
}
