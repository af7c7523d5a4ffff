//! Times the bounding-volume layer alone: the swept 18-DOPs of a step's triangles, the
//! hierarchy's build and its self-traversal, with a checksum of the pairs found, so two builds
//! can be compared on the same input (and under `valgrind --tool=callgrind`).
//!
//! Usage: `bvh_probe T0.ply T1.ply [REPS]`, or `bvh_probe DIR [REPS]` with DIR a frame sequence
//! (its first step, parents included) or a scene folder with `frames/`; prints one JSON object
//! per repetition. With `BVH_PROBE_BUILD_ONLY` set, only the volumes and the build are timed.
//! With `BVH_PROBE_IN_PLACE` set, the volumes are computed where the build places them (no
//! array of leaves, as the per-step query builds its tree), so `build` includes them and
//! `volumes` is 0: the first repetition of a fresh process is then the bounding-volume layer's
//! share of a one-step command, page faults of its fresh memory included. `neighbours` counts
//! the pairs whose triangles share a vertex (in an untimed second traversal of the first
//! repetition's tree).
//!
//! Under a profiler, use the build with line tables: `cargo build --profile profiling -p
//! topoccd-benches`, then `target/profiling/bvh_probe`.

use std::path::Path;
use std::time::Instant;
use topoccd::math::DVec3;

use topoccd::bvh::{Bvh, BvhWorkspace, Leaf};
use topoccd::io::read_mesh;
use topoccd::kdop::Kdop;

/// The step's positions at both ends and its triangles, from two meshes or a sequence folder.
type Input = (Vec<DVec3>, Vec<DVec3>, Vec<[u32; 3]>);

fn usage() -> ! {
    eprintln!("usage: bvh_probe T0.ply T1.ply [REPS] | bvh_probe DIR [REPS]");
    std::process::exit(2)
}

fn read_input(args: &[String]) -> (Input, usize) {
    let reps = |at: usize| args.get(at).and_then(|s| s.parse().ok()).unwrap_or(5);
    let Some(first) = args.get(1) else { usage() };
    if Path::new(first).is_dir() {
        let input = topoccd_benches::with_first_step(first, |step| {
            (
                step.pos0().to_vec(),
                step.pos1().to_vec(),
                step.triangles().to_vec(),
            )
        });
        return (input, reps(2));
    }
    let Some(second) = args.get(2) else { usage() };
    let read = |path: &str| {
        read_mesh(Path::new(path)).unwrap_or_else(|e| {
            eprintln!("{e}");
            std::process::exit(2)
        })
    };
    let (m0, m1) = (read(first), read(second));
    if m0.positions.len() != m1.positions.len() {
        eprintln!("{first} and {second}: the vertex counts differ");
        std::process::exit(2);
    }
    let vectors = |p: &[[f64; 3]]| p.iter().map(|&q| DVec3::from(q)).collect::<Vec<_>>();
    let input = (vectors(&m0.positions), vectors(&m1.positions), m1.triangles);
    (input, reps(3))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let ((x0, x1, tris), reps) = read_input(&args);
    let in_place = std::env::var_os("BVH_PROBE_IN_PLACE").is_some();
    let volume = |i: u32| {
        let [a, b, c] = tris[i as usize].map(|v| v as usize);
        Kdop::swept_triangle(&[x0[a], x0[b], x0[c]], &[x1[a], x1[b], x1[c]], 0.0)
    };
    // The centre of the triangle's box over the step, where the per-step query splits, so the
    // build in place makes the query's tree. The other build splits at the volumes' centres,
    // which their padding's rounding moves a little: its tree may differ (more or fewer
    // bounding-volume tests), its pairs do not.
    let center = |i: usize| {
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for &v in &tris[i] {
            for p in [x0[v as usize], x1[v as usize]] {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        (lo + hi) * 0.5
    };
    let mut leaves: Vec<Leaf<Kdop<9>>> = Vec::new();
    let mut ws = BvhWorkspace::default();
    let mut bvh = Bvh::new();
    let mut neighbours = None;
    for _ in 0..reps {
        let (volumes, build) = if in_place {
            let t = Instant::now();
            bvh.rebuild_from_fn(tris.len(), center, volume, &mut ws);
            (0.0, t.elapsed().as_secs_f64())
        } else {
            let t = Instant::now();
            leaves.clear();
            leaves.extend((0..tris.len() as u32).map(|id| Leaf {
                id,
                volume: volume(id),
            }));
            let volumes = t.elapsed().as_secs_f64();
            let t = Instant::now();
            bvh.rebuild(&leaves, &mut ws);
            (volumes, t.elapsed().as_secs_f64())
        };
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
        // Untimed, once (every repetition has the same pairs): how many of the pairs are mesh
        // neighbours (triangles sharing a vertex), which a hierarchy over triangles finds like
        // any other pair.
        let neighbours = *neighbours.get_or_insert_with(|| {
            let mut n = 0u64;
            bvh.self_pairs(&mut ws, |a, b| {
                let (ta, tb) = (tris[a as usize], tris[b as usize]);
                n += u64::from(ta.iter().any(|v| tb.contains(v)));
            });
            n
        });
        println!(
            "{{\"triangles\":{},\"volumes\":{volumes:.6},\"build\":{build:.6},\"traverse\":{traverse:.6},{par}\"pairs\":{pairs},\"neighbours\":{neighbours},\"checksum\":{sum},\"bv_tests\":{tests},\"nodes\":{}}}",
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
