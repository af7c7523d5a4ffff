//! `Method::Auto` runs the per-step hierarchy on small steps and the cluster method on large
//! ones, says which ran, and answers exactly as both.

use topoccd::{Ccd, Method, Mode, QueryOptions, Step, AUTO_CLUSTER_TRIANGLES};
use topoccd_scenes::crumpled_sheet;

/// The crumpled sheet's step cut to its first `fraction` (fewer contacts, a cheaper test).
fn start_of(step: &Step<'_>, fraction: f64) -> Step<'static> {
    let x1: Vec<[f64; 3]> = step
        .x0()
        .iter()
        .zip(step.x1())
        .map(|(a, b)| std::array::from_fn(|k| a[k] + fraction * (b[k] - a[k])))
        .collect();
    Step::new(step.x0().to_vec(), x1, step.triangles().to_vec()).unwrap()
}

#[test]
fn auto_picks_by_size_and_answers_as_the_others() {
    // 2 (n-1)^2 triangles: one sheet below the threshold, one above.
    let small = crumpled_sheet(40, 2);
    let large = start_of(&crumpled_sheet(232, 2), 0.6);
    assert!(small.triangles().len() < AUTO_CLUSTER_TRIANGLES);
    assert!(large.triangles().len() >= AUTO_CLUSTER_TRIANGLES);
    for (step, expected) in [(&small, Method::Bvh), (&large, Method::Cluster)] {
        for mode in [Mode::All, Mode::Earliest] {
            let options = QueryOptions {
                mode,
                ..QueryOptions::default()
            };
            let mut ccd = Ccd::new();
            let auto = ccd.query(step, Method::Auto, &options).unwrap();
            assert_eq!(auto.stats.method, expected);
            for other in [Method::Bvh, Method::Cluster] {
                let r = Ccd::new().query(step, other, &options).unwrap();
                assert_eq!(r.stats.method, other);
                let what = format!("{} triangles, {mode:?}, {other}", step.triangles().len());
                assert_eq!(auto.vf, r.vf, "{what}");
                assert_eq!(auto.ee, r.ee, "{what}");
                assert_eq!(auto.earliest, r.earliest, "{what}");
            }
            assert!(auto.contact_count() > 0, "the sheets fold onto themselves");
        }
    }
}
