//! Queries per second of the elementary tests on the shared Sample-Queries data (each kind) and
//! on the candidate pairs of the cloth-funnel step.
//! Run: `cargo bench -p topoccd-benches --bench narrow`. The throughput line reads "elem/s":
//! queries per second.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use topoccd::io::queries::{find_query_files, read_query_file, QueryKind};
use topoccd::io::{read_mesh, read_scene_truth, scene_frames};
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

/// The candidate pairs of cloth-funnel's step (the shared scene's own candidate list, 92
/// vertex-face and 263 edge-edge pairs, most of them touching).
fn cloth_funnel_candidates(c: &mut Criterion) {
    let dir = shared_data().join("scenes/cloth-funnel");
    let (Ok(frames), Ok(truth)) = (scene_frames(&dir), read_scene_truth(&dir)) else {
        eprintln!("SKIPPED: no cloth-funnel data at {}", dir.display());
        return;
    };
    let (Ok(m0), Ok(m1)) = (read_mesh(&frames.t0), read_mesh(&frames.t1)) else {
        eprintln!("SKIPPED: cloth-funnel frames unreadable");
        return;
    };
    let vectors = |positions: &[[f64; 3]]| -> Vec<DVec3> {
        positions.iter().map(|&p| DVec3::from_array(p)).collect()
    };
    let (x0, x1, tris) = (
        vectors(&m0.positions),
        vectors(&m1.positions),
        &m0.triangles,
    );
    let vf: Vec<VertexFace> = truth
        .vf_all
        .iter()
        .map(|&((v, f), _)| {
            let [a, b, c] = tris[f as usize].map(|i| i as usize);
            let v = v as usize;
            VertexFace::from_points([x0[v], x0[a], x0[b], x0[c], x1[v], x1[a], x1[b], x1[c]])
        })
        .collect();
    let ee: Vec<EdgeEdge> = truth
        .ee_all
        .iter()
        .map(|&((a, b), _)| {
            let i = [a[0], a[1], b[0], b[1]].map(|i| i as usize);
            EdgeEdge::from_points([
                x0[i[0]], x0[i[1]], x0[i[2]], x0[i[3]], x1[i[0]], x1[i[1]], x1[i[2]], x1[i[3]],
            ])
        })
        .collect();
    let options = NarrowOptions::default();
    let mut group = c.benchmark_group("cloth-funnel-candidates");
    group.throughput(Throughput::Elements(vf.len() as u64));
    group.bench_function("vertex-face", |b| {
        b.iter(|| {
            vf.iter()
                .filter(|q| vertex_face(black_box(q), &options).is_contact())
                .count()
        })
    });
    group.throughput(Throughput::Elements(ee.len() as u64));
    group.bench_function("edge-edge", |b| {
        b.iter(|| {
            ee.iter()
                .filter(|q| edge_edge(black_box(q), &options).is_contact())
                .count()
        })
    });
    group.finish();
}

criterion_group!(benches, queries, cloth_funnel_candidates);
criterion_main!(benches);
