//! The elementary tests on the candidate pairs of the real cloth steps (`../shared/data/scenes`):
//! every touching pair found, and on cloth-funnel, whose exact times of impact are given, every
//! reported time no later than the exact first root and within the tolerance of it.

use std::fs;
use std::path::PathBuf;

use topoccd::io::{read_mesh, read_scene_truth, scene_frames, SceneTruth};
use topoccd::math::DVec3;
use topoccd::narrow::{edge_edge, vertex_face, EdgeEdge, NarrowOptions, Outcome, VertexFace};

fn scene(name: &str) -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data/scenes")
        .join(name);
    if dir.is_dir() {
        Some(dir)
    } else {
        assert!(
            std::env::var_os("TOPOCCD_REQUIRE_DATA").is_none(),
            "TOPOCCD_REQUIRE_DATA is set but the shared data is absent (see the README)"
        );
        eprintln!("SKIPPED: scene data absent at {}", dir.display());
        None
    }
}

struct Loaded {
    x0: Vec<DVec3>,
    x1: Vec<DVec3>,
    tris: Vec<[u32; 3]>,
    truth: SceneTruth,
}

/// Positions as vectors.
fn vectors(positions: &[[f64; 3]]) -> Vec<DVec3> {
    positions.iter().map(|&p| DVec3::from_array(p)).collect()
}

fn load(dir: &std::path::Path) -> Loaded {
    let frames = scene_frames(dir).expect("frames");
    let m0 = read_mesh(&frames.t0).expect("t0");
    let m1 = read_mesh(&frames.t1).expect("t1");
    Loaded {
        x0: vectors(&m0.positions),
        x1: vectors(&m1.positions),
        tris: m0.triangles,
        truth: read_scene_truth(dir).expect("truth"),
    }
}

fn vf(l: &Loaded, v: u32, f: u32, opts: &NarrowOptions) -> Outcome {
    let [a, b, c] = l.tris[f as usize].map(|i| i as usize);
    let v = v as usize;
    let q = VertexFace::from_points([
        l.x0[v], l.x0[a], l.x0[b], l.x0[c], l.x1[v], l.x1[a], l.x1[b], l.x1[c],
    ]);
    vertex_face(&q, opts)
}

fn ee(l: &Loaded, ea: [u32; 2], eb: [u32; 2], opts: &NarrowOptions) -> Outcome {
    let [a0, a1, b0, b1] = [ea[0], ea[1], eb[0], eb[1]].map(|i| i as usize);
    let q = EdgeEdge::from_points([
        l.x0[a0], l.x0[a1], l.x0[b0], l.x0[b1], l.x1[a0], l.x1[a1], l.x1[b0], l.x1[b1],
    ]);
    edge_edge(&q, opts)
}

/// Distance between segments `p0 p1` and `q0 q1` (closed form with clamping; f64 is ample for
/// comparing with the documented false-positive distance).
fn segment_distance(p0: DVec3, p1: DVec3, q0: DVec3, q1: DVec3) -> f64 {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f, c, b) = (d1.dot(d1), d2.dot(d2), d2.dot(r), d1.dot(r), d1.dot(d2));
    let clamp = |x: f64| x.clamp(0.0, 1.0);
    let mut candidates = vec![];
    let den = a * e - b * b;
    if den > 0.0 {
        let s = clamp((b * f - c * e) / den);
        candidates.push((s, clamp((b * s + f) / e)));
    }
    for s in [0.0, 1.0] {
        candidates.push((s, clamp((b * s + f) / e.max(f64::MIN_POSITIVE))));
    }
    for t in [0.0, 1.0] {
        candidates.push((clamp((b * t - c) / a.max(f64::MIN_POSITIVE)), t));
    }
    candidates
        .iter()
        .map(|&(s, t)| ((p0 + d1 * s) - (q0 + d2 * t)).length())
        .fold(f64::INFINITY, f64::min)
}

/// Earliest exact roots of the touching pairs, in file order (`pair_index earliest roots...`).
fn exact_tois(path: PathBuf) -> Vec<(usize, f64)> {
    fs::read_to_string(&path)
        .expect("toi file")
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f[0].parse().expect("index"), f[1].parse().expect("toi"))
        })
        .collect()
}

#[test]
fn every_touching_candidate_found_on_both_cloth_steps() {
    let opts = NarrowOptions::default();
    for name in ["cloth-funnel", "cloth-ball"] {
        let Some(dir) = scene(name) else { return };
        let l = load(&dir);
        let (mut missed, mut false_pos) = (0, 0);
        for &((v, f), touch) in &l.truth.vf_all {
            let hit = vf(&l, v, f, &opts).is_contact();
            missed += usize::from(touch && !hit);
            false_pos += usize::from(!touch && hit);
        }
        for &((a, b), touch) in &l.truth.ee_all {
            let hit = ee(&l, a, b, &opts).is_contact();
            missed += usize::from(touch && !hit);
            false_pos += usize::from(!touch && hit);
        }
        eprintln!(
            "{name}: {} vf + {} ee candidates, {missed} missed, {false_pos} false positives",
            l.truth.vf_all.len(),
            l.truth.ee_all.len()
        );
        assert_eq!(missed, 0, "{name}: touching pairs missed");
    }
}

#[test]
fn cloth_funnel_times_of_impact_are_conservative_and_accurate() {
    let Some(dir) = scene("cloth-funnel") else {
        return;
    };
    let l = load(&dir);
    let opts = NarrowOptions::default();
    let vf_pairs: Vec<_> = l.truth.vf_all.iter().map(|p| p.0).collect();
    let ee_pairs: Vec<_> = l.truth.ee_all.iter().map(|p| p.0).collect();
    let mut earliest = [f64::INFINITY; 2];
    let mut exact_earliest = [f64::INFINITY; 2];
    let mut earliest_grazes = [false; 2];
    let mut early = 0;
    for (kind, file) in [(0, "227vf_toi.txt"), (1, "227ee_toi.txt")] {
        let rows = exact_tois(dir.join("toi").join(file));
        assert!(!rows.is_empty());
        for (index, exact) in rows {
            let outcome = if kind == 0 {
                let (v, f) = vf_pairs[index];
                vf(&l, v, f, &opts)
            } else {
                let (a, b) = ee_pairs[index];
                ee(&l, a, b, &opts)
            };
            let toi = outcome.toi().expect("touching pair must be found");
            assert!(
                toi <= exact,
                "pair {index}: toi {toi} later than exact {exact}"
            );
            exact_earliest[kind] = exact_earliest[kind].min(exact);
            let grazes = toi < exact - opts.tolerance;
            if toi < earliest[kind] {
                earliest[kind] = toi;
                earliest_grazes[kind] = grazes;
            }
            if !grazes {
                continue;
            }
            // Earlier than the tolerance allows: only if the features already come within the
            // documented distance at the reported time (see `narrow::solver`, "False positives"):
            // tolerance S_t / 2 with S_t <= twice the largest displacement of the four points plus
            // the change of the two edge vectors; checked here, generously, against
            // sqrt(3) tolerance (2 motion + 2 size).
            assert_eq!(
                kind, 1,
                "vertex-face pair {index}: toi {toi} vs exact {exact}"
            );
            let (a, b) = ee_pairs[index];
            let at = |i: u32, t: f64| l.x0[i as usize] + (l.x1[i as usize] - l.x0[i as usize]) * t;
            let ends = [a[0], a[1], b[0], b[1]];
            let motion = ends
                .iter()
                .map(|&i| (l.x1[i as usize] - l.x0[i as usize]).length())
                .fold(0.0, f64::max);
            let size = (at(a[0], 0.0) - at(a[1], 0.0))
                .length()
                .max((at(b[0], 0.0) - at(b[1], 0.0)).length());
            let allowed = 3f64.sqrt() * opts.tolerance * (2.0 * motion + 2.0 * size);
            let gap = segment_distance(at(a[0], toi), at(a[1], toi), at(b[0], toi), at(b[1], toi));
            eprintln!(
                "ee pair {index}: toi {toi} < exact {exact}; distance then {gap:e} <= {allowed:e}"
            );
            assert!(
                gap <= allowed,
                "pair {index}: distance {gap:e} at toi {toi} > {allowed:e}"
            );
            early += 1;
        }
    }
    eprintln!("{early} edge-edge pairs reported more than the tolerance early (grazing)");
    // The data README gives the step's earliest exact times: 0.0452322 (vf), 0.183231 (ee).
    assert!((exact_earliest[0] - 0.0452322).abs() < 1e-6);
    assert!((exact_earliest[1] - 0.183231).abs() < 1e-6);
    for k in 0..2 {
        assert!(earliest[k] <= exact_earliest[k]);
        // Within the tolerance, unless the pair attaining it grazes (validated above).
        assert!(
            earliest_grazes[k] || earliest[k] >= exact_earliest[k] - opts.tolerance,
            "{} vs {}",
            earliest[k],
            exact_earliest[k]
        );
    }
}
