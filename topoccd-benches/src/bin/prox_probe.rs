//! Runs the proximity query on one frame repeatedly, for profilers and quick timings: prints
//! the figures of every repetition as one JSON object per line (CPU seconds of the process).
//!
//! Usage: `prox_probe FRAME.ply [REPS] [kept|fresh|floor]`. `dhat` is 1e-3 x the bounding-box
//! diagonal, as `scripts/ipc_loop.py` takes it; one thread.
//!
//! `floor` times the query's parts one by one instead (median of REPS, CPU seconds; see
//! `topoccd::proximity_floor`): the features' boxes and the refit, the traversal alone, the
//! traversal writing the candidate feature pairs, the exact kernels over the candidates and
//! over the reported pairs only (precomputed lists, tight loop), and the report's sort. The
//! floor of issue 42 is the cheapest broad phase + the kernels over the reported pairs + the
//! sort.

use topoccd::{Ccd, Configuration, ProximityOptions};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: prox_probe FRAME [REPS] [kept|fresh]");
        std::process::exit(2);
    };
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    let fresh = args.get(3).is_some_and(|s| s == "fresh");
    let floor = args.get(3).is_some_and(|s| s == "floor");
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
    if floor {
        let f =
            topoccd::proximity_floor::floor(&config, &options, reps, &topoccd_benches::cpu_seconds)
                .expect("valid options");
        println!("{f:#?}");
        let ms = |s: f64| s * 1e3;
        println!("part, ms (median of {reps}, CPU, one thread)");
        println!("query (kept Ccd, refit + traversal) {:9.3}", ms(f.query));
        println!("query (kept Ccd, kept pairs reused) {:9.3}", ms(f.reuse));
        println!("boxes + refit                      {:9.3}", ms(f.fit));
        println!(
            "traversal, leaf pairs counted      {:9.3}",
            ms(f.leaf_pairs_seconds)
        );
        println!(
            "traversal + feature boxes, listed  {:9.3}",
            ms(f.candidates_seconds)
        );
        println!(
            "kernels over the candidates        {:9.3}",
            ms(f.kernels_candidates)
        );
        println!(
            "kernels over the reported pairs    {:9.3}",
            ms(f.kernels_reported)
        );
        println!("sort of the report                 {:9.3}", ms(f.sort));
        let broad = f.fit + f.candidates_seconds;
        println!(
            "floor = boxes+refit + traversal with feature boxes + kernels(reported) + sort = {:.3} ms",
            ms(broad + f.kernels_reported + f.sort)
        );
        return;
    }
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
