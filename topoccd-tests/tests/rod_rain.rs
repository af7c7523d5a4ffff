//! The generated scene with every kind of contact, `rod-rain` (particles rained onto a grid
//! of rods, pendulum rods swinging through it, a floor below), audited against oracles that
//! share nothing with the broad phases:
//!
//! - CCD: at every step of two seeded sequences, with and without a minimum separation, every
//!   method (one query object kept across the steps, as a simulator keeps it) on 1 and 2
//!   threads reports exactly the contacts of an all-pairs oracle (the elementary tests over
//!   every pair the documented pair set names), with the same times of impact up to the
//!   solver's tolerance (1 and 2 threads: the same reports, bit for bit);
//! - proximity: at every frame and two `dhat`, the hierarchy's pairs on 1 and 2 threads equal
//!   `ProximityMethod::Brute`'s, and the point-point and point-edge pairs equal the pairs a
//!   direct distance computation here finds below `dhat`.
//!
//! Both check that vertex-edge and vertex-vertex contacts (and pairs) really occur.

use std::collections::{BTreeMap, BTreeSet};

use topoccd::io::Mesh;
use topoccd::pair::{self, EdgeEdge, VertexEdge, VertexFace, VertexVertex};
use topoccd::{
    Ccd, Configuration, Method, NarrowOptions, ProximityMethod, ProximityOptions, ProximityReport,
    ProximityStats, QueryOptions, Report, Step,
};
use topoccd_scenes::codim::{codim_frames_scaled, CodimScene};

/// A contact as the oracle and the reports name it: kind (vf, ee, ve, vv) and vertices.
type Key = (u8, [u32; 4]);

fn pools() -> (rayon::ThreadPool, rayon::ThreadPool) {
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("thread pool")
    };
    (pool(1), pool(2))
}

/// The frames of the audited sequences: seed and count of frames.
fn sequence(seed: u64) -> Vec<Mesh> {
    codim_frames_scaled(CodimScene::RodRain, 6, seed, 1.0)
}

/// The sides of the triangles, sorted, each `[min, max]`.
fn sides(triangles: &[[u32; 3]]) -> Vec<[u32; 2]> {
    let mut out: Vec<[u32; 2]> = triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| [t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3])]))
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// The free points: vertices in no triangle and no edge.
fn free_points(mesh: &Mesh) -> Vec<u32> {
    let mut used = vec![false; mesh.positions.len()];
    for v in mesh
        .triangles
        .iter()
        .flatten()
        .chain(mesh.edges.iter().flatten())
    {
        used[*v as usize] = true;
    }
    (0..used.len() as u32)
        .filter(|&v| !used[v as usize])
        .collect()
}

/// Every contact of the step from `a` to `b` (the triangles and edges of `b`; the scene's do
/// not change), by the elementary tests over every pair of the documented pair set: every
/// vertex against every face, every two edges (the triangles' and the free ones), every free
/// point against every free edge, every two free points; features sharing a vertex left out.
fn ccd_oracle(a: &Mesh, b: &Mesh, options: &NarrowOptions) -> BTreeMap<Key, f64> {
    let (x0, x1) = (&a.positions, &b.positions);
    let shares = |p: &[u32], q: &[u32]| p.iter().any(|v| q.contains(v));
    let free_edges: Vec<[u32; 2]> = b
        .edges
        .iter()
        .map(|e| [e[0].min(e[1]), e[0].max(e[1])])
        .collect();
    let mut all_edges = sides(&b.triangles);
    all_edges.extend(&free_edges);
    all_edges.sort_unstable();
    all_edges.dedup();
    let points = free_points(b);
    let mut out = BTreeMap::new();
    for v in 0..x1.len() as u32 {
        for (fi, t) in b.triangles.iter().enumerate() {
            if shares(&[v], t) {
                continue;
            }
            let q = VertexFace::from_points([
                x0[v as usize],
                x0[t[0] as usize],
                x0[t[1] as usize],
                x0[t[2] as usize],
                x1[v as usize],
                x1[t[0] as usize],
                x1[t[1] as usize],
                x1[t[2] as usize],
            ]);
            if let Some(toi) = pair::vertex_face(&q, options).expect("finite").toi() {
                out.insert((0, [v, fi as u32, 0, 0]), toi);
            }
        }
    }
    for (i, ea) in all_edges.iter().enumerate() {
        for eb in &all_edges[i + 1..] {
            if shares(ea, eb) {
                continue;
            }
            let q = EdgeEdge::from_points([
                x0[ea[0] as usize],
                x0[ea[1] as usize],
                x0[eb[0] as usize],
                x0[eb[1] as usize],
                x1[ea[0] as usize],
                x1[ea[1] as usize],
                x1[eb[0] as usize],
                x1[eb[1] as usize],
            ]);
            if let Some(toi) = pair::edge_edge(&q, options).expect("finite").toi() {
                out.insert((1, [ea[0], ea[1], eb[0], eb[1]]), toi);
            }
        }
    }
    for &v in &points {
        for e in &free_edges {
            let q = VertexEdge::from_points([
                x0[v as usize],
                x0[e[0] as usize],
                x0[e[1] as usize],
                x1[v as usize],
                x1[e[0] as usize],
                x1[e[1] as usize],
            ]);
            if let Some(toi) = pair::vertex_edge(&q, options).expect("finite").toi() {
                out.insert((2, [v, e[0], e[1], 0]), toi);
            }
        }
        for &w in points.iter().filter(|&&w| w > v) {
            let q = VertexVertex::from_points([
                x0[v as usize],
                x0[w as usize],
                x1[v as usize],
                x1[w as usize],
            ]);
            if let Some(toi) = pair::vertex_vertex(&q, options).expect("finite").toi() {
                out.insert((3, [v, w, 0, 0]), toi);
            }
        }
    }
    out
}

fn keyed(report: &Report) -> BTreeMap<Key, f64> {
    let mut out = BTreeMap::new();
    for c in &report.vf {
        out.insert((0, [c.vertex, c.face, 0, 0]), c.toi);
    }
    for c in &report.ee {
        out.insert((1, [c.a[0], c.a[1], c.b[0], c.b[1]]), c.toi);
    }
    for c in &report.ve {
        out.insert((2, [c.vertex, c.edge[0], c.edge[1], 0]), c.toi);
    }
    for c in &report.vv {
        out.insert((3, [c.a, c.b, 0, 0]), c.toi);
    }
    out
}

#[test]
fn ccd_on_rod_rain_equals_the_oracle_on_one_and_two_threads() {
    let (one, two) = pools();
    let methods = [Method::Brute, Method::Bvh, Method::Cluster, Method::Auto];
    let mut kinds = [0usize; 4];
    let tolerance = NarrowOptions::default().tolerance;
    let mut largest_gap = 0.0f64;
    for seed in [1, 2] {
        let frames = sequence(seed);
        for min_distance in [0.0, 0.005] {
            let options = QueryOptions {
                narrow: NarrowOptions {
                    min_distance,
                    ..NarrowOptions::default()
                },
                ..QueryOptions::default()
            };
            // One query object per method, kept across the steps.
            let mut kept: Vec<Ccd> = methods.iter().map(|_| Ccd::new()).collect();
            for (s, w) in frames.windows(2).enumerate() {
                let truth = ccd_oracle(&w[0], &w[1], &options.narrow);
                if min_distance == 0.0 {
                    for k in truth.keys() {
                        kinds[k.0 as usize] += 1;
                    }
                }
                let step = Step::new(&w[0].positions, &w[1].positions, &w[1].triangles)
                    .and_then(|s| s.with_edges(&w[1].edges))
                    .expect("a generated step is valid");
                for (m, &method) in methods.iter().enumerate() {
                    let what = format!("seed {seed}, d={min_distance}, step {s}, {method:?}");
                    let report = two
                        .install(|| kept[m].query(&step, method, &options))
                        .expect("query");
                    assert!(report.truncated.is_none(), "{what}");
                    let got = keyed(&report);
                    for (k, t) in &truth {
                        let toi = got
                            .get(k)
                            .unwrap_or_else(|| panic!("{what}: missed {k:?} (oracle at {t})"));
                        // The library runs the same elementary tests through its batched path,
                        // whose rounding differs: the times agree to the solver's tolerance.
                        let gap = (toi - t).abs();
                        assert!(gap <= tolerance, "{what}: {k:?} at {toi}, oracle {t}");
                        largest_gap = largest_gap.max(gap);
                    }
                    assert_eq!(got.len(), truth.len(), "{what}: contacts the oracle lacks");
                    let alone = one
                        .install(|| Ccd::new().query(&step, method, &options))
                        .expect("query");
                    assert_eq!(
                        (&alone.vf, &alone.ee, &alone.ve, &alone.vv),
                        (&report.vf, &report.ee, &report.ve, &report.vv),
                        "{what}: 1 and 2 threads"
                    );
                }
            }
        }
    }
    eprintln!(
        "rod-rain oracle contacts (vf, ee, ve, vv): {kinds:?}; largest time difference \
         {largest_gap:e}"
    );
    assert!(kinds.iter().all(|&n| n > 0), "every kind occurs: {kinds:?}");
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The distance from `p` to the segment `e0 e1`: to the nearest point of the segment, the
/// projection onto its line clamped to it.
fn point_segment(p: [f64; 3], e0: [f64; 3], e1: [f64; 3]) -> f64 {
    let (d, w) = (sub(e1, e0), sub(p, e0));
    let s = (dot(w, d) / dot(d, d)).clamp(0.0, 1.0);
    let r = sub(w, [d[0] * s, d[1] * s, d[2] * s]);
    dot(r, r).sqrt()
}

/// The point-point and point-edge pairs of `mesh` nearer than `dhat`, computed here, and the
/// pairs within a relative `1e-9` of `dhat` (which either side may keep).
type NearPairs = (BTreeSet<Key>, BTreeSet<Key>);

fn near_points(mesh: &Mesh, dhat: f64) -> NearPairs {
    let x = &mesh.positions;
    let points = free_points(mesh);
    let (mut sure, mut edge) = (BTreeSet::new(), BTreeSet::new());
    let mut note = |key: Key, d: f64| {
        if (d - dhat).abs() <= 1e-9 * dhat {
            edge.insert(key);
        } else if d < dhat {
            sure.insert(key);
        }
    };
    for &v in &points {
        for e in &mesh.edges {
            let d = point_segment(x[v as usize], x[e[0] as usize], x[e[1] as usize]);
            note((2, [v, e[0].min(e[1]), e[0].max(e[1]), 0]), d);
        }
        for &w in points.iter().filter(|&&w| w > v) {
            let r = sub(x[v as usize], x[w as usize]);
            note((3, [v, w, 0, 0]), dot(r, r).sqrt());
        }
    }
    (sure, edge)
}

/// The pairs without the figures.
fn pairs(r: &ProximityReport) -> ProximityReport {
    ProximityReport {
        stats: ProximityStats::default(),
        ..r.clone()
    }
}

#[test]
fn proximity_on_rod_rain_equals_brute_force() {
    let (one, two) = pools();
    let mut found = [0usize; 4];
    for seed in [1, 2] {
        let frames = sequence(seed);
        let mut kept = Ccd::new();
        for (f, mesh) in frames.iter().enumerate() {
            for dhat in [0.01, 0.04] {
                let what = format!("seed {seed}, frame {f}, dhat {dhat}");
                let config = Configuration::new(&mesh.positions, &mesh.triangles, &mesh.edges)
                    .expect("a generated frame is valid");
                let options = ProximityOptions {
                    dhat,
                    max_contacts: None,
                    ..ProximityOptions::default()
                };
                let brute = ProximityOptions {
                    method: ProximityMethod::Brute,
                    ..options
                };
                let oracle = one
                    .install(|| Ccd::new().proximity(&config, &brute))
                    .expect("brute");
                let got = two
                    .install(|| kept.proximity(&config, &options))
                    .expect("hierarchy");
                assert_eq!(pairs(&got), pairs(&oracle), "{what}");
                let single = one
                    .install(|| Ccd::new().proximity(&config, &options))
                    .expect("hierarchy");
                assert_eq!(pairs(&single), pairs(&got), "{what}: 1 and 2 threads");
                // The codimensional pairs, against the distances computed here.
                let (sure, either) = near_points(mesh, dhat);
                let reported: BTreeSet<Key> = got
                    .ve
                    .iter()
                    .map(|p| {
                        (
                            2,
                            [
                                p.vertex,
                                p.edge[0].min(p.edge[1]),
                                p.edge[0].max(p.edge[1]),
                                0,
                            ],
                        )
                    })
                    .chain(
                        got.vv
                            .iter()
                            .map(|p| (3, [p.a.min(p.b), p.a.max(p.b), 0, 0])),
                    )
                    .collect();
                assert_eq!(
                    reported.len(),
                    got.ve.len() + got.vv.len(),
                    "{what}: repeats"
                );
                let missed: Vec<_> = sure.difference(&reported).collect();
                assert!(missed.is_empty(), "{what}: missed {missed:?}");
                let extra: Vec<_> = reported
                    .difference(&sure)
                    .filter(|k| !either.contains(k))
                    .collect();
                assert!(extra.is_empty(), "{what}: farther than dhat {extra:?}");
                found[0] += got.vf.len();
                found[1] += got.ee.len();
                found[2] += got.ve.len();
                found[3] += got.vv.len();
            }
        }
    }
    eprintln!("rod-rain proximity pairs (vf, ee, ve, vv): {found:?}");
    assert!(found.iter().all(|&n| n > 0), "every kind occurs: {found:?}");
}
