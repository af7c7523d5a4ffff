//! Benchmarks of topoccd live in `benches/`; the probes in `src/bin/` share the little below.

use topoccd::{Method, Mode};

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
