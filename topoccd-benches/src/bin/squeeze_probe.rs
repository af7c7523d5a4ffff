//! Memory of a step with a huge number of candidate pairs: a crumpled sheet of `n * n` vertices
//! squeezed into a small box (as in `topoccd/tests/bounded_candidates.rs`, at any size), so
//! that nearly every triangle's swept volume overlaps nearly every other's. Runs one query and
//! prints the candidates, the contacts, the most candidates held at once, the seconds and the
//! process's peak resident memory (`VmHWM`).
//!
//! Usage: `squeeze_probe N [bvh|cluster|brute] [all|earliest] [SCALE]` (SCALE: the box's size
//! relative to the unit sheet, default 0.05).

use std::time::Instant;

use topoccd::{Ccd, QueryOptions, Step};
use topoccd_scenes::crumpled_sheet;

/// The process's peak resident memory in MiB, from `/proc/self/status` (Linux).
fn peak_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(100);
    let method = topoccd_benches::method_arg(args.get(2));
    let mode = topoccd_benches::mode_arg(args.get(3));
    let scale: f64 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(0.05);
    let sheet = crumpled_sheet(n, 5);
    let squeeze =
        |p: &[[f64; 3]]| -> Vec<[f64; 3]> { p.iter().map(|q| q.map(|c| scale * c)).collect() };
    let step = Step::new(
        squeeze(sheet.x0()),
        squeeze(sheet.x1()),
        sheet.triangles().to_vec(),
    )
    .expect("a valid step");
    drop(sheet);
    let before = peak_mib().unwrap_or(f64::NAN);
    let options = QueryOptions {
        mode,
        ..QueryOptions::default()
    };
    let t = Instant::now();
    let report = Ccd::new()
        .query(&step, method, &options)
        .expect("valid options");
    let seconds = t.elapsed().as_secs_f64();
    let s = &report.stats;
    println!(
        "{{\"triangles\":{},\"method\":\"{method}\",\"mode\":\"{mode:?}\",\"candidates\":{},\"contacts\":{},\"peak_candidates\":{},\"seconds\":{seconds:.3},\"peak_mib_before_query\":{before:.1},\"peak_mib\":{:.1}}}",
        step.triangles().len(),
        s.vf_tests + s.ee_tests,
        report.vf.len() + report.ee.len(),
        s.peak_candidates,
        peak_mib().unwrap_or(f64::NAN),
    );
}
