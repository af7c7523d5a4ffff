//! Times the bounding-volume layer alone: the swept 18-DOPs of a step's triangles, the
//! hierarchy's build and its self-traversal, with a checksum of the pairs found, so two builds
//! can be compared on the same input (and under `valgrind --tool=callgrind`).
//!
//! Usage: `bvh_probe T0.ply T1.ply [REPS]`; prints one JSON object per repetition. With
//! `BVH_PROBE_BUILD_ONLY` set, only the volumes and the build are timed.

use std::path::Path;
use std::time::Instant;
use topoccd::math::DVec3;

use topoccd::bvh::{Bvh, BvhWorkspace, Leaf};
use topoccd::io::read_mesh;
use topoccd::kdop::Kdop;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 3 {
        eprintln!("usage: bvh_probe T0.ply T1.ply [REPS]");
        std::process::exit(2);
    }
    let m0 = read_mesh(Path::new(&args[1])).unwrap_or_else(|e| panic!("{}: {e}", args[1]));
    let m1 = read_mesh(Path::new(&args[2])).unwrap_or_else(|e| panic!("{}: {e}", args[2]));
    assert_eq!(
        m0.positions.len(),
        m1.positions.len(),
        "vertex counts differ"
    );
    let reps: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(5);
    let vectors = |p: &[[f64; 3]]| p.iter().map(|&q| DVec3::from(q)).collect::<Vec<_>>();
    let (x0, x1, tris) = (
        vectors(&m0.positions),
        vectors(&m1.positions),
        &m1.triangles,
    );
    let mut leaves: Vec<Leaf<Kdop<9>>> = Vec::new();
    let mut ws = BvhWorkspace::default();
    let mut bvh = Bvh::new();
    for _ in 0..reps {
        let t = Instant::now();
        leaves.clear();
        leaves.extend(tris.iter().enumerate().map(|(i, tri)| {
            let [a, b, c] = tri.map(|v| v as usize);
            Leaf {
                id: i as u32,
                volume: Kdop::swept_triangle(&[x0[a], x0[b], x0[c]], &[x1[a], x1[b], x1[c]], 0.0),
            }
        }));
        let volumes = t.elapsed().as_secs_f64();
        let t = Instant::now();
        bvh.rebuild(&leaves, &mut ws);
        let build = t.elapsed().as_secs_f64();
        if std::env::var_os("BVH_PROBE_BUILD_ONLY").is_some() {
            println!(
                "{{\"triangles\":{},\"volumes\":{volumes:.6},\"build\":{build:.6}}}",
                tris.len()
            );
            continue;
        }
        let t = Instant::now();
        let (mut pairs, mut sum) = (0u64, 0u64);
        let tests = bvh.self_pairs(&mut ws, |a, b| {
            let (a, b) = (a.min(b) as u64, a.max(b) as u64);
            pairs += 1;
            sum = sum.wrapping_add((a << 32 | b).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        });
        let traverse = t.elapsed().as_secs_f64();
        let par = par_traverse(&bvh, &mut ws, (pairs, sum, tests));
        println!(
            "{{\"triangles\":{},\"volumes\":{volumes:.6},\"build\":{build:.6},\"traverse\":{traverse:.6},{par}\"pairs\":{pairs},\"checksum\":{sum},\"bv_tests\":{tests},\"nodes\":{}}}",
            tris.len(),
            bvh.nodes().len()
        );
    }
}

/// Times `par_self_pairs` where the build has it (`--features par` of this probe), checking its
/// pairs against the sequential traversal's; empty otherwise.
#[cfg(feature = "par")]
fn par_traverse(bvh: &Bvh<Kdop<9>>, ws: &mut BvhWorkspace, seq: (u64, u64, u64)) -> String {
    let t = Instant::now();
    let out = bvh.par_self_pairs(
        ws,
        || (0u64, 0u64),
        |(n, sum), a, b| {
            let (a, b) = (a.min(b) as u64, a.max(b) as u64);
            *n += 1;
            *sum = sum.wrapping_add((a << 32 | b).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        },
    );
    let seconds = t.elapsed().as_secs_f64();
    let n: u64 = out.results.iter().map(|r| r.0).sum();
    let sum = out.results.iter().fold(0u64, |s, r| s.wrapping_add(r.1));
    assert_eq!((n, sum), (seq.0, seq.1), "parallel pairs differ");
    format!(
        "\"par_traverse\":{seconds:.6},\"par_tasks\":{},\"par_bv_tests\":{},",
        out.results.len(),
        out.bv_tests
    )
}

#[cfg(not(feature = "par"))]
fn par_traverse(_: &Bvh<Kdop<9>>, _: &mut BvhWorkspace, _: (u64, u64, u64)) -> String {
    String::new()
}
