//! Benchmarks of topoccd live in `benches/`; the probes in `src/bin/` share the little below.

use std::path::Path;

use topoccd::io::sequence::Sequence;
use topoccd::{Method, Mode, Step};

/// The method named by a probe's argument (`bvh` when absent); exits with a message otherwise.
pub fn method_arg(arg: Option<&String>) -> Method {
    let name = arg.map(String::as_str).unwrap_or("bvh");
    name.parse().unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    })
}

/// The mode named by a probe's argument (`all` when absent); exits with a message otherwise.
pub fn mode_arg(arg: Option<&String>) -> Mode {
    match arg.map(String::as_str).unwrap_or("all") {
        "all" => Mode::All,
        "earliest" => Mode::Earliest,
        other => {
            eprintln!("unknown mode {other:?} (expected all or earliest)");
            std::process::exit(2)
        }
    }
}

/// Runs `f` on the first step of `dir` (a frame sequence, parents included, or a scene folder
/// with `frames/`); exits with a message when the folder does not give one.
pub fn with_first_step<R>(dir: &str, f: impl FnOnce(&Step<'_>) -> R) -> R {
    // The sequence's errors name the folder or file; the step's do not.
    let fail = |e: String| -> ! {
        eprintln!("{e}");
        std::process::exit(2)
    };
    let sequence = Sequence::open(Path::new(dir)).unwrap_or_else(|e| fail(e.to_string()));
    let frames = sequence.load(0).unwrap_or_else(|e| fail(e.to_string()));
    let step = Step::with_parents(
        frames.x0.as_slice(),
        frames.x1.as_slice(),
        frames.triangles.as_slice(),
        &frames.parents,
    )
    .unwrap_or_else(|e| fail(format!("{dir}: {e}")));
    f(&step)
}

/// Reads one mesh file (a frame); exits with a message when it cannot.
pub fn read_frame(path: &str) -> topoccd::io::Mesh {
    topoccd::io::read_mesh(Path::new(path)).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    })
}

/// The proximity threshold of the issue-42 measurements: 1e-3 x the bounding-box diagonal.
pub fn dhat_of(x: &[[f64; 3]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in x {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    1e-3 * (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

/// The CPU time of this process, in seconds (all its threads): on a machine shared with
/// other work, wall time measures the load as much as the code.
pub fn cpu_seconds() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec to write; the clock id is a constant the OS knows.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}
