//! Whole-step queries: the two real cloth steps of the shared data and seeded generated scenes,
//! for each method. Run: `cargo bench -p topoccd-benches --bench step`.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use topoccd::io::{read_mesh, scene_frames};
use topoccd::math::DVec3;
use topoccd::{Ccd, Method, QueryOptions, Step};
use topoccd_scenes::SceneKind;

fn real_step(name: &str) -> Option<Step<'static>> {
    let dir = std::env::var_os("TOPOCCD_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"))
        .join("scenes")
        .join(name);
    let frames = scene_frames(&dir).ok()?;
    let (m0, m1) = (read_mesh(&frames.t0).ok()?, read_mesh(&frames.t1).ok()?);
    let vectors = |positions: &[[f64; 3]]| -> Vec<DVec3> {
        positions.iter().map(|&p| DVec3::from_array(p)).collect()
    };
    Step::new(vectors(&m0.positions), vectors(&m1.positions), m1.triangles).ok()
}

fn methods() -> Vec<Method> {
    vec![Method::Bvh]
}

fn real_steps(c: &mut Criterion) {
    let options = QueryOptions::default();
    for name in ["cloth-funnel", "cloth-ball"] {
        let Some(step) = real_step(name) else {
            eprintln!("SKIPPED: no {name} data");
            continue;
        };
        let mut group = c.benchmark_group(name);
        group.sample_size(10);
        let mut ccd = Ccd::new();
        for method in methods() {
            group.bench_function(method.to_string(), |b| {
                b.iter(|| {
                    ccd.query(black_box(&step), method, &options)
                        .unwrap()
                        .contact_count()
                })
            });
        }
        group.finish();
    }
}

fn generated(c: &mut Criterion) {
    let options = QueryOptions::default();
    let mut group = c.benchmark_group("generated");
    group.sample_size(10);
    let mut ccd = Ccd::new();
    for kind in SceneKind::ALL {
        let step = kind.generate(40, 7);
        for method in methods() {
            group.bench_function(format!("{}/{method}", kind.name()), |b| {
                b.iter(|| {
                    ccd.query(black_box(&step), method, &options)
                        .unwrap()
                        .contact_count()
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, real_steps, generated);
criterion_main!(benches);
