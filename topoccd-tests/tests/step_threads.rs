//! The whole-step report does not depend on the number of threads.

use topoccd::{query, Method, Mode, QueryOptions, Report};
use topoccd_scenes::SceneKind;

fn run_with(threads: usize, f: impl FnOnce() -> Report + Send) -> Report {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
        .install(f)
}

/// The pairs with their times' bits, and the earliest time's bits.
type Key = (
    Vec<(u32, u32, u64)>,
    Vec<([u32; 2], [u32; 2], u64)>,
    Option<u64>,
);

fn key(r: &Report) -> Key {
    (
        r.vf.iter()
            .map(|c| (c.vertex, c.face, c.toi.to_bits()))
            .collect(),
        r.ee.iter().map(|c| (c.a, c.b, c.toi.to_bits())).collect(),
        r.earliest_toi().map(f64::to_bits),
    )
}

#[test]
fn same_report_on_one_and_several_threads() {
    for kind in SceneKind::ALL {
        for seed in 0..3 {
            let step = kind.generate(24, seed);
            for mode in [Mode::All, Mode::Earliest] {
                let options = QueryOptions {
                    mode,
                    ..QueryOptions::default()
                };
                for method in [Method::Bvh, Method::Cluster] {
                    let one = run_with(1, || query(&step, method, &options).unwrap());
                    let four = run_with(4, || query(&step, method, &options).unwrap());
                    assert_eq!(
                        key(&one),
                        key(&four),
                        "{} seed {seed} {mode:?} {method}",
                        kind.name()
                    );
                    assert!(one.contact_count() > 0 || mode == Mode::Earliest);
                }
            }
        }
    }
}
