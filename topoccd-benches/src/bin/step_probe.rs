//! Runs one step's query repeatedly on a warm [`Ccd`], for profilers (`perf record`,
//! `valgrind --tool=callgrind`) and quick timings: prints the per-phase seconds of every
//! repetition as one JSON object per line.
//!
//! Usage: `step_probe DIR|SCENE_DIR [bvh|cluster|brute|auto] [all|earliest] [REPS] [THREADS]`, where
//! DIR is a frame sequence (its first step, parents included) or a scene folder with `frames/`.
//! With `STEP_PROBE_FRESH` set, every repetition uses a new `Ccd` (as a one-step command does).
//!
//! Profilers need line tables, which the release profile no longer keeps: build with
//! `cargo build --profile profiling -p topoccd-benches` and run `target/profiling/step_probe`.

use std::time::Instant;

use topoccd::{Ccd, QueryOptions};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(dir) = args.get(1) else {
        eprintln!("usage: step_probe DIR [bvh|cluster|brute] [all|earliest] [REPS] [THREADS]");
        std::process::exit(2);
    };
    let method = topoccd_benches::method_arg(args.get(2));
    let mode = topoccd_benches::mode_arg(args.get(3));
    let reps: usize = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(5);
    let threads: usize = args.get(5).and_then(|s| s.parse().ok()).unwrap_or(1);
    topoccd_benches::with_first_step(dir, |step| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build_global()
            .expect("a thread pool");
        let options = QueryOptions {
            mode,
            ..QueryOptions::default()
        };
        let fresh = std::env::var_os("STEP_PROBE_FRESH").is_some();
        let mut ccd = Ccd::new();
        for _ in 0..reps {
            if fresh {
                ccd = Ccd::new();
            }
            let t = Instant::now();
            let report = ccd.query(step, method, &options).expect("valid options");
            let wall = t.elapsed().as_secs_f64();
            let s = &report.stats.seconds;
            println!(
            "{{\"wall\":{wall:.6},\"build\":{:.6},\"traverse\":{:.6},\"narrow\":{:.6},\"clustering\":{:.6},\"bv_tests\":{},\"candidates\":{},\"contacts\":{}}}",
            s.build,
            s.traverse,
            s.narrow,
            s.clustering.unwrap_or(0.0),
            report.stats.bv_tests,
            report.stats.vf_tests + report.stats.ee_tests,
            report.vf.len() + report.ee.len(),
        );
        }
    });
}
