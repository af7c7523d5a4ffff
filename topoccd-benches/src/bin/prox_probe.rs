//! Runs the proximity query on one frame repeatedly, for profilers and quick timings: prints
//! the figures of every repetition as one JSON object per line (CPU seconds of the process).
//!
//! Usage: `prox_probe FRAME.ply [REPS] [kept|fresh]`. `dhat` is 1e-3 x the bounding-box
//! diagonal, as `scripts/ipc_loop.py` takes it; one thread.

use topoccd::{Ccd, Configuration, ProximityOptions};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: prox_probe FRAME [REPS] [kept|fresh]");
        std::process::exit(2);
    };
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    let fresh = args.get(3).is_some_and(|s| s == "fresh");
    let mesh = topoccd_benches::read_frame(path);
    let dhat = topoccd_benches::dhat_of(&mesh.positions);
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build_global()
        .expect("a thread pool");
    let config = Configuration::new(
        mesh.positions.as_slice(),
        mesh.triangles.as_slice(),
        &mesh.edges,
    )
    .expect("a valid frame");
    let options = ProximityOptions {
        dhat,
        ..ProximityOptions::default()
    };
    let mut ccd = Ccd::new();
    for _ in 0..reps {
        if fresh {
            ccd = Ccd::new();
        }
        let t = topoccd_benches::cpu_seconds();
        let report = ccd.proximity(&config, &options).expect("valid options");
        let cpu = topoccd_benches::cpu_seconds() - t;
        let s = &report.stats;
        println!(
            "{{\"cpu\":{cpu:.6},\"build\":{:.6},\"traverse\":{:.6},\"refitted\":{},\"bv_tests\":{},\"distance_tests\":{},\"pairs\":{}}}",
            s.build_seconds,
            s.traverse_seconds,
            s.refitted,
            s.bv_tests,
            s.distance_tests,
            report.len()
        );
    }
}
