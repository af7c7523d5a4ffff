//! Issue 51: a proximity query on the integer-cast cloth-funnel frame (every vertex on one of
//! ten points, n² pairs within `dhat`), with the defaults, returns a truncated report within
//! 500 MB of peak memory (the child's `ru_maxrss`). Its wall time is printed, not asserted.
//! One test in this file, so that the peak is this child's.

mod common;

use std::process::Command;
use std::time::Instant;

use common::{integer_cast_funnel, TempDir};

/// `struct rusage` of 64-bit Linux: two `timeval`s, then 14 `long`s (`ru_maxrss`, in KiB,
/// first).
#[repr(C)]
struct Rusage {
    times: [i64; 4],
    maxrss: i64,
    rest: [i64; 13],
}

extern "C" {
    fn getrusage(who: i32, usage: *mut Rusage) -> i32;
}

/// The largest resident set of the children waited for, in bytes.
fn children_peak() -> u64 {
    const RUSAGE_CHILDREN: i32 = -1;
    let mut usage = Rusage {
        times: [0; 4],
        maxrss: 0,
        rest: [0; 13],
    };
    // SAFETY: `usage` is a valid, writable `struct rusage`.
    let rc = unsafe { getrusage(RUSAGE_CHILDREN, &mut usage) };
    assert_eq!(rc, 0, "getrusage");
    usage.maxrss as u64 * 1024
}

#[test]
fn proximity_on_the_integer_cast_funnel_is_truncated_and_bounded() {
    let dir = TempDir::new("proximity-cap", "funnel");
    let Some([frame, _]) = integer_cast_funnel(&dir) else {
        return;
    };
    let started = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_topoccd"))
        .arg("proximity")
        .arg(&frame)
        // The library's default threshold (the command asks for one).
        .args(["--dhat", "1e-3"])
        .arg("--json")
        .env_remove("TOPOCCD_MAX_MEMORY")
        .output()
        .expect("topoccd runs");
    let seconds = started.elapsed().as_secs_f64();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    let json: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON object");
    assert_eq!(json["truncated"], serde_json::Value::Bool(true), "{stdout}");
    let peak = children_peak();
    println!(
        "integer-cast cloth-funnel 227, proximity with defaults: {seconds:.3} s wall, \
         peak RSS {:.1} MB",
        peak as f64 / 1e6
    );
    assert!(peak < 500_000_000, "peak RSS {peak} bytes");
}
