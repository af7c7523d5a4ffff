//! Runs each Rust entry point of issue 43 on the cloth-funnel step 227 -> 228 with its
//! positions cast to integers (every vertex on one of 10 points), with the defaults, and
//! prints one JSON line per entry point: wall seconds, peak resident memory, the answer.
//!
//! Usage: `bounded_probe FRAMES_DIR [CASE] [THREADS] [TIMEOUT] [METHOD]`, where FRAMES_DIR
//! holds `227.ply` and `228.ply`; CASE is `stepsize`, `free`, `earliest`, `all`, `check` or
//! `every` (the default); TIMEOUT (seconds, `-` for none) sets a deadline; METHOD (`auto`,
//! the default, `bvh`, `cluster`, `brute`) is the queries' method.

use std::path::Path;
use std::time::{Duration, Instant};

use topoccd::line_search::{collision_free_stepsize, is_step_collision_free, LineSearchOptions};
use topoccd::{query, Method, Mode, QueryOptions, Step};

fn peak_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb: f64 = status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.0);
    kb / 1024.0
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(dir) = args.get(1) else {
        eprintln!("usage: bounded_probe FRAMES_DIR [CASE] [THREADS] [TIMEOUT] [METHOD]");
        std::process::exit(2);
    };
    let case = args.get(2).map(String::as_str).unwrap_or("every");
    let threads: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let timeout: Option<f64> = args.get(4).and_then(|s| s.parse().ok());
    let method = match args.get(5) {
        Some(name) => topoccd_benches::method_arg(Some(name)),
        None => Method::Auto,
    };
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
        .expect("a thread pool");
    let read = |name: &str| {
        topoccd::io::read_mesh(&Path::new(dir).join(name)).unwrap_or_else(|e| {
            eprintln!("{e}");
            std::process::exit(2)
        })
    };
    let (m0, m1) = (read("227.ply"), read("228.ply"));
    let cast = |x: &[[f64; 3]]| -> Vec<[f64; 3]> {
        x.iter().map(|p| p.map(|c| c as i32 as f64)).collect()
    };
    let (x0, x1) = (cast(&m0.positions), cast(&m1.positions));
    let tris = m1.triangles;
    let mut options = LineSearchOptions::default();
    let deadline = || timeout.map(|s| Instant::now() + Duration::from_secs_f64(s));
    let cases: Vec<&str> = if case == "every" {
        vec!["stepsize", "free", "earliest", "all", "check"]
    } else {
        vec![case]
    };
    for case in cases {
        options.query.deadline = deadline();
        let t = Instant::now();
        let answer = match case {
            "stepsize" => format!(
                "{:?}",
                collision_free_stepsize(&x0, &x1, &tris, &options).map(|s| s.alpha)
            ),
            "free" => format!(
                "{:?}",
                is_step_collision_free(&x0, &x1, &tris, &options).map(|s| s.is_collision_free())
            ),
            "earliest" | "all" => {
                let step = Step::new(&x0, &x1, &tris).expect("a valid step");
                let q = QueryOptions {
                    mode: if case == "all" {
                        Mode::All
                    } else {
                        Mode::Earliest
                    },
                    ..options.query
                };
                match query(&step, method, &q) {
                    Ok(r) => format!(
                        "{} contacts, earliest {:?}, truncated {:?}",
                        r.contact_count(),
                        r.earliest_toi(),
                        r.truncated.map(|t| t.reason)
                    ),
                    Err(e) => format!("error: {e}"),
                }
            }
            "check" => {
                let step = Step::new(&x0, &x0, &tris).expect("a valid step");
                let limits = topoccd::check::CheckLimits {
                    deadline: deadline(),
                    ..Default::default()
                };
                match topoccd::check::step_intersections_within(
                    &step,
                    topoccd::Frame::Start,
                    &limits,
                ) {
                    Ok(r) => format!("{} intersections", r.len()),
                    Err(e) => format!("error: {e}"),
                }
            }
            other => {
                eprintln!("unknown case {other:?}");
                std::process::exit(2)
            }
        };
        let wall = t.elapsed().as_secs_f64();
        println!(
            "{{\"case\":\"{case}\",\"threads\":{threads},\"wall\":{wall:.3},\"peak_mb\":{:.0},\"answer\":{:?}}}",
            peak_mb(),
            answer
        );
    }
}
