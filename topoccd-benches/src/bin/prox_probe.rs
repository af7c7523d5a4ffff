//! Runs the proximity query on one frame repeatedly, for profilers and quick timings: prints
//! the figures of every repetition as one JSON object per line (CPU seconds of the process).
//!
//! Usage: `prox_probe FRAME.ply [REPS] [kept|fresh|floor]`, or `prox_probe FRAME.ply REPS moved
//! TARGET [FRAC]`. `dhat` is 1e-3 x the bounding-box diagonal, as `scripts/ipc_loop.py` takes
//! it; one thread.
//!
//! `moved` times a query at positions moved from FRAME's: to `FRAME + FRAC (TARGET - FRAME)`
//! for a TARGET frame (FRAC default 1), or, for TARGET `dhat`, every coordinate moved by a
//! seeded uniform amount in `[-FRAC dhat, FRAC dhat]`. Per repetition, in turn: a fresh `Ccd`
//! at the moved positions; a `Ccd` that was asked at FRAME's positions first (kept); and one
//! `Ccd` kept over all repetitions, asked at FRAME's and the moved positions in turn (timed at
//! the moved ones). Prints each repetition and the minimum of each (CPU seconds).
//!
//! `floor` times the query's parts one by one instead (median of REPS, CPU seconds; see
//! `topoccd::proximity_floor`): the features' boxes and the refit, the traversal alone, the
//! traversal writing the candidate feature pairs, the exact kernels over the candidates and
//! over the reported pairs only (precomputed lists, tight loop), and the report's sort. The
//! floor of issue 42 is the cheapest broad phase + the kernels over the reported pairs + the
//! sort.
//!
//! `PROX_METHOD=triangles` in the environment selects the binary tree of triangle leaves
//! (`ProximityMethod::TriangleTree`) instead of the default feature trees.

use topoccd::{Ccd, Configuration, ProximityMethod, ProximityOptions};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: prox_probe FRAME [REPS] [kept|fresh]");
        std::process::exit(2);
    };
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    let fresh = args.get(3).is_some_and(|s| s == "fresh");
    let moved = args.get(3).is_some_and(|s| s == "moved");
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
    let method = match std::env::var("PROX_METHOD").as_deref() {
        Ok("triangles") => ProximityMethod::TriangleTree,
        _ => ProximityMethod::Bvh,
    };
    let options = ProximityOptions {
        dhat,
        method,
        ..ProximityOptions::default()
    };
    if moved {
        let Some(target) = args.get(4) else {
            eprintln!("usage: prox_probe FRAME REPS moved TARGET|dhat [FRAC]");
            std::process::exit(2);
        };
        let frac: f64 = args.get(5).and_then(|s| s.parse().ok()).unwrap_or(1.0);
        let x0 = &mesh.positions;
        let x1: Vec<[f64; 3]> = if target == "dhat" {
            // A seeded xorshift: uniform in [-frac dhat, frac dhat] per coordinate.
            let mut state = 0x9E37_79B9_7F4A_7C15u64;
            let mut uniform = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
            };
            (x0.iter())
                .map(|p| p.map(|c| c + frac * dhat * uniform()))
                .collect()
        } else {
            let to = topoccd_benches::read_frame(target);
            assert_eq!(to.positions.len(), x0.len(), "frames of one mesh");
            (x0.iter().zip(&to.positions))
                .map(|(p, q)| std::array::from_fn(|k| p[k] + frac * (q[k] - p[k])))
                .collect()
        };
        let moved = Configuration::new(x1.as_slice(), mesh.triangles.as_slice(), &mesh.edges)
            .expect("a valid frame");
        let query = |ccd: &mut Ccd, c: &Configuration<'_>| {
            let t = topoccd_benches::cpu_seconds();
            let r = ccd.proximity(c, &options).expect("valid options");
            (topoccd_benches::cpu_seconds() - t, r)
        };
        let mut alternating = Ccd::new();
        alternating
            .proximity(&config, &options)
            .expect("valid options");
        let mut best = [f64::INFINITY; 3];
        for _ in 0..reps {
            let (fresh, rf) = query(&mut Ccd::new(), &moved);
            let mut kept = Ccd::new();
            kept.proximity(&config, &options).expect("valid options");
            let (once, rk) = query(&mut kept, &moved);
            let (alt, ra) = query(&mut alternating, &moved);
            alternating
                .proximity(&config, &options)
                .expect("valid options");
            assert!(
                rf.len() == rk.len() && rf.len() == ra.len(),
                "the same pairs"
            );
            for (b, t) in best.iter_mut().zip([fresh, once, alt]) {
                *b = b.min(t);
            }
            println!(
                "{{\"fresh\":{fresh:.6},\"kept\":{once:.6},\"kept_reused\":{},\"alternating\":{alt:.6},\"alternating_reused\":{},\"pairs\":{},\"distance_tests\":[{},{},{}]}}",
                rk.stats.reused,
                ra.stats.reused,
                rf.len(),
                rf.stats.distance_tests,
                rk.stats.distance_tests,
                ra.stats.distance_tests
            );
        }
        let ms = |s: f64| s * 1e3;
        println!(
            "min of {reps}, ms (CPU, one thread): fresh {:.3}, kept {:.3}, kept alternating {:.3}",
            ms(best[0]),
            ms(best[1]),
            ms(best[2])
        );
        return;
    }
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
        println!("feature tree: boxes + refit        {:9.3}", ms(f.wide_fit));
        println!(
            "feature tree: queries + kernels    {:9.3} ({} box tests)",
            ms(f.wide_find),
            f.wide_box_tests
        );
        println!(
            "feature tree floor = its fit + queries + sort = {:.3} ms",
            ms(f.wide_fit + f.wide_find + f.sort)
        );
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
