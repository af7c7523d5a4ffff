//! Codimensional geometry (free edges and points): the vertex-edge and vertex-vertex
//! elementary tests on analytic cases with known times, and whole steps with free edges and
//! points against an independent all-pairs oracle (the elementary tests over every pair the
//! documented pair set names, without any broad phase) on a generated sequence of 12 steps
//! with a cut: no false negative, times never later than exact, every method and both modes
//! agreeing, 1 and 2 threads identical.

use std::collections::BTreeMap;

use topoccd::pair::{self, VertexEdge, VertexVertex};
use topoccd::{Ccd, Contact, Method, Mode, NarrowOptions, QueryOptions, Report, Step};

const TOL: f64 = 1e-6;

fn opts(min_distance: f64) -> NarrowOptions {
    NarrowOptions {
        min_distance,
        ..NarrowOptions::default()
    }
}

/// Asserts that `toi` is never later than `exact` and within the tolerance of it.
fn assert_time(toi: Option<f64>, exact: f64, what: &str) {
    let toi = toi.unwrap_or_else(|| panic!("{what}: no contact, exact time {exact}"));
    assert!(toi <= exact, "{what}: {toi} later than exact {exact}");
    assert!(
        toi >= exact - 2.0 * TOL,
        "{what}: {toi} too early for {exact}"
    );
}

#[test]
fn points_crossing_points() {
    // Head on along x: a from -1 to 3, b from 1 to -3: distance 2 - 8t, zero at t = 1/4; with
    // min_distance d, at t = (2 - d) / 8.
    let q = VertexVertex {
        a_t0: [-1.0, 0.0, 0.0],
        a_t1: [3.0, 0.0, 0.0],
        b_t0: [1.0, 0.0, 0.0],
        b_t1: [-3.0, 0.0, 0.0],
    };
    for d in [0.0, 0.1, 0.5] {
        let toi = pair::vertex_vertex(&q, &opts(d)).unwrap().toi();
        assert_time(toi, (2.0 - d) / 8.0, &format!("head on, d={d}"));
    }
    // Passing at a closest distance of 0.3 (at t = 1/2): no contact below it, contact at the
    // time the distance is d above it: |(2 - 4t, 0.3)| = d.
    let q = VertexVertex {
        a_t0: [-1.0, 0.0, 0.0],
        a_t1: [1.0, 0.0, 0.0],
        b_t0: [1.0, 0.3, 0.0],
        b_t1: [-1.0, 0.3, 0.0],
    };
    assert!(!pair::vertex_vertex(&q, &opts(0.29)).unwrap().is_contact());
    let d: f64 = 0.5;
    let exact = (2.0 - (d * d - 0.09).sqrt()) / 4.0;
    assert_time(
        pair::vertex_vertex(&q, &opts(d)).unwrap().toi(),
        exact,
        "passing",
    );
    // Coincident at the start: contact at 0.
    let q = VertexVertex {
        a_t0: [0.5, 0.5, 0.5],
        a_t1: [1.0, 0.0, 0.0],
        b_t0: [0.5, 0.5, 0.5],
        b_t1: [0.0, 1.0, 0.0],
    };
    assert_eq!(
        pair::vertex_vertex(&q, &opts(0.0)).unwrap().toi(),
        Some(0.0)
    );
}

#[test]
fn points_crossing_edges() {
    // The point falls from z=1 to z=-1 at x=0.3 across the edge from (-1,0,0) to (1,0,0).
    let q = VertexEdge {
        v_t0: [0.3, 0.0, 1.0],
        v_t1: [0.3, 0.0, -1.0],
        e0_t0: [-1.0, 0.0, 0.0],
        e1_t0: [1.0, 0.0, 0.0],
        e0_t1: [-1.0, 0.0, 0.0],
        e1_t1: [1.0, 0.0, 0.0],
    };
    for d in [0.0, 0.05, 0.5] {
        let exact = (1.0 - d) / 2.0;
        assert_time(
            pair::vertex_edge(&q, &opts(d)).unwrap().toi(),
            exact,
            "crossing",
        );
    }
    // Falling beside the edge's end (x = 1.2): no contact; the nearest point is the end, 0.2
    // away, so a contact with min_distance 0.25 when |(0.2, 1 - 2t)| = 0.25.
    let beside = VertexEdge {
        v_t0: [1.2, 0.0, 1.0],
        v_t1: [1.2, 0.0, -1.0],
        ..q
    };
    assert!(!pair::vertex_edge(&beside, &opts(0.0)).unwrap().is_contact());
    let exact = (1.0 - (0.25f64 * 0.25 - 0.04).sqrt()) / 2.0;
    assert_time(
        pair::vertex_edge(&beside, &opts(0.25)).unwrap().toi(),
        exact,
        "beside",
    );
    // The edge moves and rotates onto a still point: the edge from (-1,-1,1)-(1,1,1) to
    // (-1,-1,-1)-(1,1,-1) crosses the point at the origin at t = 1/2.
    let moving = VertexEdge {
        v_t0: [0.0; 3],
        v_t1: [0.0; 3],
        e0_t0: [-1.0, -1.0, 1.0],
        e1_t0: [1.0, 1.0, 1.0],
        e0_t1: [-1.0, -1.0, -1.0],
        e1_t1: [1.0, 1.0, -1.0],
    };
    assert_time(
        pair::vertex_edge(&moving, &opts(0.0)).unwrap().toi(),
        0.5,
        "moving edge",
    );
    // With tmax before the contact: none.
    let short = NarrowOptions {
        tmax: 0.4,
        ..NarrowOptions::default()
    };
    assert!(!pair::vertex_edge(&moving, &short).unwrap().is_contact());
}

#[test]
fn a_point_sliding_along_an_edge() {
    // On the edge's line, from x=2 to x=0: it enters the edge [-1, 1] at its end at t = 1/2.
    let q = VertexEdge {
        v_t0: [2.0, 0.0, 0.0],
        v_t1: [0.0, 0.0, 0.0],
        e0_t0: [-1.0, 0.0, 0.0],
        e1_t0: [1.0, 0.0, 0.0],
        e0_t1: [-1.0, 0.0, 0.0],
        e1_t1: [1.0, 0.0, 0.0],
    };
    assert_time(
        pair::vertex_edge(&q, &opts(0.0)).unwrap().toi(),
        0.5,
        "sliding in",
    );
    // Parallel to the edge at height 0.1, from x=-3 to x=3: never within 0.05; within 0.1 at
    // once where it is over the edge (x = -1, t = 1/3), so with min_distance 0.1 at 1/3.
    let q = VertexEdge {
        v_t0: [-3.0, 0.1, 0.0],
        v_t1: [3.0, 0.1, 0.0],
        ..q
    };
    assert!(!pair::vertex_edge(&q, &opts(0.05)).unwrap().is_contact());
    assert_time(
        pair::vertex_edge(&q, &opts(0.1)).unwrap().toi(),
        1.0 / 3.0,
        "parallel",
    );
}

#[test]
fn rods_crossing_in_a_step() {
    // Two free edges (rods) in a step without triangles: rod 0-1 along x at z=0, rod 2-3 along
    // y falling from z=1 to z=-1: contact at 0.5; a particle (4) falls onto rod 0-1 at 0.25 and
    // another (5) meets it head on at 0.75.
    let x0 = [
        [-1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, -1.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.5, 0.0, 0.25],
        [0.5, 0.0, 5.0],
    ];
    let x1 = [
        [-1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, -1.0, -1.0],
        [0.0, 1.0, -1.0],
        [0.5, 0.0, -0.75],
        [0.5, 0.0, -5.0 / 3.0],
    ];
    let no_triangles: [[u32; 3]; 0] = [];
    let edges = [[0u32, 1], [2, 3]];
    let step = Step::new(&x0[..], &x1[..], &no_triangles[..])
        .unwrap()
        .with_edges(&edges)
        .unwrap();
    for method in [Method::Brute, Method::Bvh, Method::Cluster] {
        let report = Ccd::new()
            .query(&step, method, &QueryOptions::default())
            .unwrap();
        assert_eq!(report.ee.len(), 1, "{method:?}: {report:?}");
        assert_eq!((report.ee[0].a, report.ee[0].b), ([0, 1], [2, 3]));
        assert_time(Some(report.ee[0].toi), 0.5, "rods");
        let ve: Vec<_> = report.ve.iter().map(|c| (c.vertex, c.edge)).collect();
        // Particle 4 hits rod 0-1 at 0.25; particle 5 passes x=0.5 under rod 2-3 (at x=0),
        // apart from it; the particles meet each other at t where 0.25 - t = 5 - 20t/3.
        assert_eq!(ve, vec![(4, [0, 1]), (5, [0, 1])], "{method:?}");
        assert_time(Some(report.ve[0].toi), 0.25, "particle on rod");
        let vv: Vec<_> = report.vv.iter().map(|c| (c.a, c.b)).collect();
        assert_eq!(vv, vec![(4, 5)], "{method:?}");
        assert_time(
            Some(report.vv[0].toi),
            4.75 / (20.0 / 3.0 - 1.0),
            "particles",
        );
        // Particle 5 reaches rod 0-1 at z=0: 5 - 20t/3 = 0.
        assert_time(Some(report.ve[1].toi), 0.75, "particle 5 on rod");
        let earliest = report.earliest.unwrap();
        assert!(
            matches!(earliest, Contact::Ve(c) if c.vertex == 4),
            "{earliest:?}"
        );
    }
}

/// A small deterministic generator (no dependency on the scenes crate's internals).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// One step of the generated sequence: positions, triangles, parents, free edges.
struct Frame {
    x0: Vec<[f64; 3]>,
    x1: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    parents: Vec<[u32; 2]>,
    edges: Vec<[u32; 2]>,
}

/// A sheet of `n x n` quads in z=0 that waves, hair strands (free edges) hanging through it
/// and swaying, particles (free points) falling through it, and, from step 6 on, the sheet cut
/// in two along x = 0.5 (the cut's vertices split, the new copies appended with parents).
fn sequence(steps: usize) -> Vec<Frame> {
    let n = 6usize;
    let grid = |i: usize, j: usize| (i * (n + 1) + j) as u32;
    let sheet_vertices = (n + 1) * (n + 1);
    let strands = 5usize;
    let per_strand = 4usize; // vertices
    let particles = 12usize;
    let hair0 = sheet_vertices;
    let points0 = hair0 + strands * per_strand;
    let base = points0 + particles + 1;
    let cut_col = n / 2;
    let mut rng = Lcg(7);
    let strand_xy: Vec<[f64; 2]> = (0..strands)
        .map(|_| [0.1 + 0.8 * rng.next(), 0.1 + 0.8 * rng.next()])
        .collect();
    let particle_xyz: Vec<[f64; 3]> = (0..particles)
        .map(|_| {
            [
                0.05 + 0.9 * rng.next(),
                0.05 + 0.9 * rng.next(),
                0.3 + 0.6 * rng.next(),
            ]
        })
        .collect();
    let at = |t: f64, cut: bool| -> Vec<[f64; 3]> {
        let mut x = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let mut z = 0.08 * (6.0 * u + 2.0 * t).sin() * (4.0 * v).cos();
                if cut && j > cut_col {
                    z -= 0.1 * t; // the cut-off part sinks
                }
                x.push([u, v, z]);
            }
        }
        let strand = |s: usize, k: usize| {
            let [sx, sy] = strand_xy[s];
            let h = 0.35 - 0.2 * k as f64;
            let sway = 0.15 * (t * 1.3 + s as f64).sin() * (k as f64 / per_strand as f64);
            [
                sx + sway,
                sy + 0.5 * sway,
                h + 0.4 * (t * 0.7 + s as f64).cos() - 0.3,
            ]
        };
        for s in 0..strands {
            for k in 0..per_strand {
                x.push(strand(s, k));
            }
        }
        for p in 0..particles {
            let fall = 0.25 * t;
            // Particles 2i and 2i + 1 start at one place and swirl in opposite directions:
            // they meet whenever the swirl is 0.
            let phase = (t + (p / 2) as f64).sin();
            let swirl = if p % 2 == 0 {
                0.05 * phase
            } else {
                -0.05 * phase
            };
            let [qx, qy, qz] = particle_xyz[p - p % 2];
            x.push([qx + swirl, qy - swirl, qz - fall]);
        }
        // The last particle rides beside strand 0's vertex 1 and reaches it at t = 4.5.
        let [sx, sy, sz] = strand(0, 1);
        x.push([sx + 0.18 - 0.04 * t, sy, sz]);
        if cut {
            // The copies of the cut's column of sheet vertices (column cut_col + 1 side).
            for i in 0..=n {
                let mut p = x[grid(i, cut_col) as usize];
                p[2] -= 0.1 * t;
                x.push(p);
            }
        }
        x
    };
    let triangles = |cut: bool| -> Vec<[u32; 3]> {
        let mut tris = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let v = |a: usize, b: usize| {
                    if cut && b == cut_col && j >= cut_col {
                        (base + a) as u32 // the copy, on the cut-off side
                    } else {
                        grid(a, b)
                    }
                };
                tris.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
                tris.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
            }
        }
        tris
    };
    let edges: Vec<[u32; 2]> = (0..strands)
        .flat_map(|s| {
            (0..per_strand - 1).map(move |k| {
                let v = (hair0 + s * per_strand + k) as u32;
                [v, v + 1]
            })
        })
        .collect();
    let mut frames = Vec::new();
    for s in 0..steps {
        let (t0, t1) = (s as f64, s as f64 + 1.0);
        let cut_now = s == 6;
        let cut_before = s > 6;
        let mut x0 = at(t0, cut_before);
        let x1 = at(t1, cut_now || cut_before);
        let mut parents = Vec::new();
        if cut_now {
            // The copies are new vertices: they start at their parents.
            for i in 0..=n {
                parents.push([(base + i) as u32, grid(i, cut_col)]);
            }
            x0.truncate(base);
        }
        frames.push(Frame {
            x0,
            x1,
            triangles: triangles(cut_now || cut_before),
            parents,
            edges: edges.clone(),
        });
    }
    frames
}

/// A contact as the oracle and the reports name it: kind and vertices.
type Key = (u8, [u32; 4]);

/// Every contact of the step, by the elementary tests over every pair the documented pair set
/// names (every vertex in a triangle or a free edge, and every free point, against every face;
/// every two edges, the triangles' and the free ones; every free point against every free
/// edge; every two free points), features sharing a vertex (after the crack filter's parent
/// identification) left out.
fn oracle(f: &Frame, step: &Step, options: &NarrowOptions) -> BTreeMap<Key, f64> {
    let (x0, x1) = (step.x0(), step.x1());
    let n = x1.len();
    let mut canon: Vec<u32> = (0..n as u32).collect();
    for &[c, p] in &f.parents {
        canon[c as usize] = p;
    }
    let shares = |a: &[u32], b: &[u32]| {
        a.iter()
            .any(|&x| b.iter().any(|&y| canon[x as usize] == canon[y as usize]))
    };
    let mut in_tri = vec![false; n];
    let mut mesh_edges = Vec::new();
    for t in &f.triangles {
        for k in 0..3 {
            in_tri[t[k] as usize] = true;
            let (a, b) = (t[k], t[(k + 1) % 3]);
            mesh_edges.push([a.min(b), a.max(b)]);
        }
    }
    mesh_edges.sort_unstable();
    mesh_edges.dedup();
    let mut in_edge = vec![false; n];
    for e in &f.edges {
        in_edge[e[0] as usize] = true;
        in_edge[e[1] as usize] = true;
    }
    let mut all_edges = mesh_edges.clone();
    all_edges.extend(f.edges.iter().map(|e| [e[0].min(e[1]), e[0].max(e[1])]));
    all_edges.sort_unstable();
    all_edges.dedup();
    let points: Vec<u32> = (0..n as u32)
        .filter(|&v| !in_tri[v as usize] && !in_edge[v as usize])
        .collect();
    let p = |v: u32, t: usize| {
        if t == 0 {
            x0[v as usize]
        } else {
            x1[v as usize]
        }
    };
    let mut out = BTreeMap::new();
    for v in 0..n as u32 {
        for (fi, tri) in f.triangles.iter().enumerate() {
            if shares(&[v], tri) {
                continue;
            }
            let q = pair::VertexFace::from_points([
                p(v, 0),
                p(tri[0], 0),
                p(tri[1], 0),
                p(tri[2], 0),
                p(v, 1),
                p(tri[0], 1),
                p(tri[1], 1),
                p(tri[2], 1),
            ]);
            if let Some(toi) = pair::vertex_face(&q, options).unwrap().toi() {
                out.insert((0, [v, fi as u32, 0, 0]), toi);
            }
        }
    }
    for (i, a) in all_edges.iter().enumerate() {
        for b in &all_edges[i + 1..] {
            if shares(a, b) {
                continue;
            }
            let q = pair::EdgeEdge::from_points([
                p(a[0], 0),
                p(a[1], 0),
                p(b[0], 0),
                p(b[1], 0),
                p(a[0], 1),
                p(a[1], 1),
                p(b[0], 1),
                p(b[1], 1),
            ]);
            if let Some(toi) = pair::edge_edge(&q, options).unwrap().toi() {
                out.insert((1, [a[0], a[1], b[0], b[1]]), toi);
            }
        }
    }
    for &v in &points {
        for e in &f.edges {
            let e = [e[0].min(e[1]), e[0].max(e[1])];
            let q = VertexEdge::from_points([
                p(v, 0),
                p(e[0], 0),
                p(e[1], 0),
                p(v, 1),
                p(e[0], 1),
                p(e[1], 1),
            ]);
            if let Some(toi) = pair::vertex_edge(&q, options).unwrap().toi() {
                out.insert((2, [v, e[0], e[1], 0]), toi);
            }
        }
        for &w in points.iter().filter(|&&w| w > v) {
            let q = VertexVertex::from_points([p(v, 0), p(w, 0), p(v, 1), p(w, 1)]);
            if let Some(toi) = pair::vertex_vertex(&q, options).unwrap().toi() {
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

fn step_of(f: &Frame) -> Step<'_> {
    let step = if f.parents.is_empty() {
        Step::new(&f.x0[..], &f.x1[..], &f.triangles[..]).unwrap()
    } else {
        Step::with_parents(&f.x0[..], &f.x1[..], &f.triangles[..], &f.parents).unwrap()
    };
    step.with_edges(&f.edges).unwrap()
}

#[test]
fn a_codimensional_sequence_with_a_cut_matches_the_oracle() {
    let frames = sequence(12);
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let (one, two) = (pool(1), pool(2));
    let mut kinds = [0usize; 4];
    for min_distance in [0.0, 0.01] {
        let mut ccds: Vec<Ccd> = (0..3).map(|_| Ccd::new()).collect();
        for (s, f) in frames.iter().enumerate() {
            let step = step_of(f);
            let narrow = opts(min_distance);
            let truth = oracle(f, &step, &narrow);
            for k in truth.keys() {
                kinds[k.0 as usize] += 1;
            }
            let all = QueryOptions {
                narrow,
                ..QueryOptions::default()
            };
            let earliest_options = QueryOptions {
                mode: Mode::Earliest,
                ..all
            };
            for (m, method) in [Method::Brute, Method::Bvh, Method::Cluster]
                .into_iter()
                .enumerate()
            {
                let what = format!("step {s}, d={min_distance}, {method:?}");
                let report = two.install(|| ccds[m].query(&step, method, &all)).unwrap();
                let got = keyed(&report);
                // No false negative, and times never later than the oracle's (the same
                // elementary tests, searched alone).
                for (k, &t) in &truth {
                    let toi = got
                        .get(k)
                        .unwrap_or_else(|| panic!("{what}: missed {k:?} at {t}"));
                    assert!(*toi <= t + TOL, "{what}: {k:?} at {toi}, alone {t}");
                }
                for k in got.keys() {
                    assert!(
                        truth.contains_key(k),
                        "{what}: {k:?} not a contact of the oracle"
                    );
                }
                // Sorted, and the earliest the minimum.
                assert!(report
                    .ve
                    .windows(2)
                    .all(|w| (w[0].vertex, w[0].edge) < (w[1].vertex, w[1].edge)));
                assert!(report
                    .vv
                    .windows(2)
                    .all(|w| (w[0].a, w[0].b) < (w[1].a, w[1].b)));
                let min = got.values().copied().fold(f64::INFINITY, f64::min);
                assert_eq!(
                    report.earliest_toi().unwrap_or(f64::INFINITY),
                    min,
                    "{what}"
                );
                // One thread: the same report.
                let alone = one
                    .install(|| Ccd::new().query(&step, method, &all))
                    .unwrap();
                assert_eq!(
                    (&alone.vf, &alone.ee, &alone.ve, &alone.vv),
                    (&report.vf, &report.ee, &report.ve, &report.vv),
                    "{what}: threads"
                );
                // Earliest agrees with All.
                let early = two
                    .install(|| Ccd::new().query(&step, method, &earliest_options))
                    .unwrap();
                assert_eq!(early.earliest, report.earliest, "{what}: Earliest");
                for (k, t) in keyed(&early) {
                    assert_eq!(got.get(&k), Some(&t), "{what}: Earliest's {k:?}");
                    assert!(t <= min + TOL, "{what}: Earliest keeps {k:?} at {t}");
                }
                // Streaming hands over the same contacts.
                let streamed = std::sync::Mutex::new(Vec::new());
                two.install(|| {
                    Ccd::new().for_each_contact(&step, method, &all, |c| {
                        streamed.lock().unwrap().push(*c)
                    })
                })
                .unwrap();
                let mut streamed = streamed.into_inner().unwrap();
                streamed.sort_by(Contact::earliest_order);
                assert_eq!(streamed.len(), report.contact_count(), "{what}: streamed");
                assert_eq!(
                    streamed.first().copied(),
                    report.earliest,
                    "{what}: streamed earliest"
                );
                // A cap keeps the first contacts, of every kind.
                if report.contact_count() > 3 {
                    let capped = QueryOptions {
                        max_contacts: Some(3),
                        ..all
                    };
                    let r = two
                        .install(|| Ccd::new().query(&step, method, &capped))
                        .unwrap();
                    assert_eq!(r.contact_count(), 3, "{what}: cap");
                    assert!(r.truncated.is_some(), "{what}: cap");
                    for (k, t) in keyed(&r) {
                        assert_eq!(got.get(&k), Some(&t), "{what}: capped {k:?}");
                    }
                }
            }
        }
    }
    eprintln!("oracle contacts per kind (vf, ee, ve, vv): {kinds:?}");
    // The sequence exercises every kind.
    assert!(kinds.iter().all(|&k| k > 0), "contacts per kind: {kinds:?}");
}

#[test]
fn groups_and_can_collide_filter_the_new_kinds() {
    // Two particles falling across a rod: in a group of their own they still hit the rod;
    // all in one group, nothing; a predicate that pins particle 3 drops its pair.
    let x0 = [
        [-1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.2, 0.0, 3.0],
    ];
    let x1 = [
        [-1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 0.0, -1.0],
        [0.2, 0.0, -3.0],
    ];
    let none: [[u32; 3]; 0] = [];
    let edges = [[0u32, 1]];
    let base = Step::new(&x0[..], &x1[..], &none[..])
        .unwrap()
        .with_edges(&edges)
        .unwrap();
    let r = Ccd::new()
        .query(&base, Method::Bvh, &QueryOptions::default())
        .unwrap();
    assert_eq!(r.ve.len(), 2, "{r:?}");
    assert_eq!(r.vv.len(), 0, "the particles stay 0.2 apart along x");
    let groups = [0, 0, 1, 1];
    let grouped = base.clone().with_groups(&groups).unwrap();
    let r = Ccd::new()
        .query(&grouped, Method::Bvh, &QueryOptions::default())
        .unwrap();
    assert_eq!(r.ve.len(), 2);
    let same = [0, 0, 0, 0];
    let r = Ccd::new()
        .query(
            &base.clone().with_groups(&same).unwrap(),
            Method::Bvh,
            &QueryOptions::default(),
        )
        .unwrap();
    assert_eq!(r.contact_count(), 0);
    let pinned = |a: u32, b: u32| a != 3 && b != 3;
    let r = Ccd::new()
        .query(
            &base.with_can_collide(&pinned),
            Method::Bvh,
            &QueryOptions::default(),
        )
        .unwrap();
    assert_eq!(r.ve.iter().map(|c| c.vertex).collect::<Vec<_>>(), vec![2]);
}

#[test]
fn bad_edges_are_refused_with_their_index() {
    let x = [[0.0; 3], [1.0, 0.0, 0.0]];
    let none: [[u32; 3]; 0] = [];
    let step = Step::new(&x[..], &x[..], &none[..]).unwrap();
    let err = step.clone().with_edges(&[[0, 1], [1, 1]]).unwrap_err();
    assert_eq!(err.to_string(), "edge 1 joins vertex 1 to itself");
    let err = step.with_edges(&[[0, 2]]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "edge 0 names vertex 2, but there are only 2 vertices"
    );
}
