//! Runs a whole frame sequence the way a simulator does (every frame read first, then one
//! [`Ccd`] kept across the steps), repeated, for profilers and quick timings of the everyday
//! step without file reading: prints one JSON object per step and repetition.
//!
//! Usage: `seq_probe DIR [bvh|cluster|brute|auto] [all|earliest] [REPS] [THREADS] [STEPS]`.
//! Each repetition starts from a new `Ccd`, so step 0 always starts from nothing.
//! `SEQ_PROBE_MAX_CONTACTS=N` (or `off`) sets `QueryOptions::max_contacts`.

use std::path::Path;
use std::time::Instant;

use topoccd::io::sequence::Sequence;
use topoccd::{Ccd, QueryOptions, Step};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(dir) = args.get(1) else {
        eprintln!(
            "usage: seq_probe DIR [bvh|cluster|brute|auto] [all|earliest] [REPS] [THREADS] [STEPS]"
        );
        std::process::exit(2);
    };
    let method = topoccd_benches::method_arg(args.get(2));
    let mode = topoccd_benches::mode_arg(args.get(3));
    let reps: usize = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(3);
    let threads: usize = args.get(5).and_then(|s| s.parse().ok()).unwrap_or(1);
    let fail = |e: String| -> ! {
        eprintln!("{e}");
        std::process::exit(2)
    };
    let sequence = Sequence::open(Path::new(dir)).unwrap_or_else(|e| fail(e.to_string()));
    let steps: usize = args
        .get(6)
        .and_then(|s| s.parse().ok())
        .unwrap_or(usize::MAX)
        .min(sequence.steps());
    let frames: Vec<_> = (0..steps)
        .map(|k| sequence.load(k).unwrap_or_else(|e| fail(e.to_string())))
        .collect();
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
        .expect("a thread pool");
    // `SEQ_PROBE_MAX_CONTACTS=N` (or `off`) sets the cap; e.g. 1 with `earliest` is the
    // query the line-search helpers run.
    let max_contacts = match std::env::var("SEQ_PROBE_MAX_CONTACTS").ok().as_deref() {
        None => QueryOptions::default().max_contacts,
        Some("off") => None,
        Some(n) => Some(n.parse().unwrap_or_else(|_| fail(format!("bad cap {n:?}")))),
    };
    let options = QueryOptions {
        mode,
        max_contacts,
        ..QueryOptions::default()
    };
    for rep in 0..reps {
        let mut ccd = Ccd::new();
        for (k, f) in frames.iter().enumerate() {
            let step = Step::with_parents(
                f.x0.as_slice(),
                f.x1.as_slice(),
                f.triangles.as_slice(),
                &f.parents,
            )
            .unwrap_or_else(|e| fail(format!("{dir}: step {k}: {e}")));
            let t = Instant::now();
            let report = ccd.query(&step, method, &options).expect("valid options");
            let wall = t.elapsed().as_secs_f64();
            let s = &report.stats.seconds;
            println!(
                "{{\"rep\":{rep},\"step\":{k},\"wall\":{wall:.6},\"build\":{:.6},\"traverse\":{:.6},\"narrow\":{:.6},\"bv_tests\":{},\"candidates\":{},\"contacts\":{}}}",
                s.build,
                s.traverse,
                s.narrow,
                report.stats.bv_tests,
                report.stats.vf_tests + report.stats.ee_tests,
                report.vf.len() + report.ee.len(),
            );
        }
    }
}
