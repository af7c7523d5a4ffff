//! The bounding-volume layer alone: the swept 18-DOPs of the triangles of the two real cloth
//! steps of the shared data, the hierarchy's rebuild, and its self-traversal (sequential and,
//! with the `par` feature, parallel on the current rayon pool). Run:
//! `cargo bench -p topoccd-benches --bench bvh` (`RAYON_NUM_THREADS=1` for one thread).

use std::hint::black_box;
use std::path::PathBuf;
use topoccd::math::DVec3;

use criterion::{criterion_group, criterion_main, Criterion};
use topoccd::bvh::{Bvh, BvhWorkspace, Leaf};
use topoccd::io::{read_mesh, scene_frames};
use topoccd::kdop::Kdop;

/// The swept 18-DOPs of a real step's triangles (no inflation), or `None` without the data.
fn swept_leaves(name: &str) -> Option<Vec<Leaf<Kdop<9>>>> {
    let dir = std::env::var_os("TOPOCCD_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"))
        .join("scenes")
        .join(name);
    let frames = scene_frames(&dir).ok()?;
    let (m0, m1) = (read_mesh(&frames.t0).ok()?, read_mesh(&frames.t1).ok()?);
    let vectors = |p: &[[f64; 3]]| p.iter().map(|&q| DVec3::from(q)).collect::<Vec<_>>();
    let (x0, x1) = (vectors(&m0.positions), vectors(&m1.positions));
    Some(
        m1.triangles
            .iter()
            .enumerate()
            .map(|(i, tri)| {
                let [a, b, c] = tri.map(|v| v as usize);
                Leaf {
                    id: i as u32,
                    volume: Kdop::swept_triangle(
                        &[x0[a], x0[b], x0[c]],
                        &[x1[a], x1[b], x1[c]],
                        0.0,
                    ),
                }
            })
            .collect(),
    )
}

fn bvh(c: &mut Criterion) {
    for name in ["cloth-funnel", "cloth-ball"] {
        let Some(leaves) = swept_leaves(name) else {
            eprintln!("SKIPPED: no {name} data (set TOPOCCD_DATA)");
            continue;
        };
        let mut group = c.benchmark_group(format!("bvh/{name}"));
        group.sample_size(10);
        let mut ws = BvhWorkspace::default();
        let mut tree = Bvh::new();
        group.bench_function("rebuild", |b| {
            b.iter(|| {
                tree.rebuild(black_box(&leaves), &mut ws);
                tree.nodes().len()
            })
        });
        group.bench_function("self_pairs", |b| {
            b.iter(|| {
                let mut n = 0u64;
                let tests = tree.self_pairs(&mut ws, |x, y| n += u64::from(x ^ y) & 1);
                (n, tests)
            })
        });
        #[cfg(feature = "par")]
        group.bench_function("par_self_pairs", |b| {
            b.iter(|| {
                let out =
                    tree.par_self_pairs(&mut ws, || 0u64, |n, x, y| *n += u64::from(x ^ y) & 1);
                (out.results.iter().sum::<u64>(), out.bv_tests)
            })
        });
        group.finish();
    }
}

criterion_group!(benches, bvh);
criterion_main!(benches);
