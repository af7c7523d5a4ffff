//! Queries per second of the elementary tests on the shared Sample-Queries data (each kind).
//! Run: `cargo bench -p topoccd-benches --bench narrow`. The throughput line reads "elem/s":
//! queries per second.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use topoccd::io::queries::{find_query_files, read_query_file, QueryKind};
use topoccd::math::DVec3;
use topoccd::narrow::{edge_edge, vertex_face, EdgeEdge, NarrowOptions, VertexFace};

fn shared_data() -> PathBuf {
    std::env::var_os("TOPOCCD_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"))
}

fn load(kind: QueryKind) -> Vec<[DVec3; 8]> {
    let dir = shared_data().join("queries");
    let Ok(files) = find_query_files(&dir) else {
        eprintln!("SKIPPED: no query data at {}", dir.display());
        return vec![];
    };
    files
        .iter()
        .filter(|(k, _)| *k == kind)
        .filter_map(|(_, path)| read_query_file(path).ok())
        .flatten()
        .map(|q| q.points)
        .collect()
}

fn queries(c: &mut Criterion) {
    let options = NarrowOptions::default();
    let mut group = c.benchmark_group("sample-queries");
    let vf: Vec<VertexFace> = load(QueryKind::VertexFace)
        .into_iter()
        .map(VertexFace::from_points)
        .collect();
    let ee: Vec<EdgeEdge> = load(QueryKind::EdgeEdge)
        .into_iter()
        .map(EdgeEdge::from_points)
        .collect();
    if !vf.is_empty() {
        group.throughput(Throughput::Elements(vf.len() as u64));
        group.bench_function("vertex-face", |b| {
            b.iter(|| {
                vf.iter()
                    .filter(|q| vertex_face(black_box(q), &options).is_contact())
                    .count()
            })
        });
    }
    if !ee.is_empty() {
        group.throughput(Throughput::Elements(ee.len() as u64));
        group.bench_function("edge-edge", |b| {
            b.iter(|| {
                ee.iter()
                    .filter(|q| edge_edge(black_box(q), &options).is_contact())
                    .count()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, queries);
criterion_main!(benches);
