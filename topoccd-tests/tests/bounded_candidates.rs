//! Candidates stream from the broad phase to the narrow phase in bounded buffers: a step with
//! far more candidates than a buffer holds never holds more than one buffer's worth at once
//! (per traversal task), and reports exactly what an unbounded run reports.

use topoccd::{Ccd, Method, Mode, QueryOptions, Step};
use topoccd_scenes::crumpled_sheet;

/// A crumpled sheet squeezed into a small box: nearly every triangle's swept volume overlaps
/// nearly every other's, so the candidates grow quadratically with the triangles (a small
/// version of the 249K-triangle sheet whose 1.6 billion candidates once took 12.7 GB).
fn squeezed(n: usize) -> Step<'static> {
    let step = crumpled_sheet(n, 5);
    let squeeze =
        |p: &[[f64; 3]]| -> Vec<[f64; 3]> { p.iter().map(|q| q.map(|c| 0.05 * c)).collect() };
    Step::new(
        squeeze(step.x0()),
        squeeze(step.x1()),
        step.triangles().to_vec(),
    )
    .expect("a valid step")
}

#[test]
fn the_candidate_buffers_stay_bounded_and_the_answer_does_not_change() {
    let step = squeezed(40);
    let (task_limit, sequential_limit) = (500, 2000);
    // Pairs a triangle pair can add past a full buffer (3 + 3 vertex-face, 9 edge-edge).
    let slack = 15;
    for mode in [Mode::All, Mode::Earliest] {
        let options = QueryOptions {
            mode,
            ..QueryOptions::default()
        };
        for method in [Method::Bvh, Method::Cluster, Method::Brute] {
            let unbounded = Ccd::new().query(&step, method, &options).unwrap();
            let mut ccd = Ccd::new();
            ccd.set_buffer_limits(task_limit, sequential_limit);
            let bounded = ccd.query(&step, method, &options).unwrap();
            let s = bounded.stats;
            let limit = if method == Method::Bvh {
                task_limit
            } else {
                sequential_limit
            };
            let what = format!("{method} {mode:?}");
            assert!(
                s.vf_tests + s.ee_tests > 20 * limit as u64,
                "{what}: the step must overflow the buffers many times ({} candidates)",
                s.vf_tests + s.ee_tests
            );
            assert!(
                s.peak_candidates <= (limit + slack) as u64,
                "{what}: {} candidates held at once, bound {}",
                s.peak_candidates,
                limit + slack
            );
            assert_eq!(bounded.vf, unbounded.vf, "{what}");
            assert_eq!(bounded.ee, unbounded.ee, "{what}");
            assert_eq!(bounded.earliest, unbounded.earliest, "{what}");
            if mode == Mode::All {
                assert_eq!(
                    (s.vf_tests, s.ee_tests),
                    (unbounded.stats.vf_tests, unbounded.stats.ee_tests),
                    "{what}: the same candidates"
                );
                assert!(unbounded.contact_count() > 0, "{what}: the sheet collides");
            }
        }
    }
}
