//! Ground truth of the shared whole-step scenes: counts from the data README, the id mapping
//! checked independently (incidence, libigl edge order, geometry), and malformed scene
//! directories built in a temp dir.

#[path = "../../topoccd/tests/io_util/mod.rs"]
mod io_util;

use io_util::{scene_dir, TempDir};
use std::collections::{HashMap, HashSet};
use topoccd::io::{
    libigl_edges, read_ply, read_scene_truth, scene_frames, write_ply, IoError, Mesh,
};
use topoccd::math::DVec3;
use topoccd::mesh::Topology;

/// What the data README and the files say about a scene.
struct Case {
    scene: &'static str,
    frames: [&'static str; 2],
    vertices: usize,
    faces: usize,
    /// Candidate pairs in the files (touching or not), and touching ones (README).
    vf: [usize; 2],
    ee: [usize; 2],
}

const SCENES: [Case; 2] = [
    Case {
        scene: "cloth-funnel",
        frames: ["227.ply", "228.ply"],
        vertices: 9_450,
        faces: 18_484,
        vf: [92, 27],
        ee: [263, 107],
    },
    Case {
        scene: "cloth-ball",
        frames: ["cloth_ball92.ply", "cloth_ball93.ply"],
        vertices: 46_598,
        faces: 92_230,
        vf: [19_034, 19_032],
        ee: [94_825, 94_822],
    },
];

#[test]
fn counts_match_the_data_readme() {
    for case in SCENES {
        let scene = case.scene;
        let Some(dir) = scene_dir(scene) else { return };
        let frames = scene_frames(&dir).expect("frames");
        let [f0, f1] = case.frames;
        assert!(
            frames.t0.ends_with(f0) && frames.t1.ends_with(f1),
            "{frames:?}"
        );
        let truth = read_scene_truth(&dir).expect("truth");
        assert_eq!(
            (truth.vertices, truth.faces),
            (case.vertices, case.faces),
            "{scene}"
        );
        assert_eq!([truth.vf_candidates, truth.vf.len()], case.vf, "{scene}");
        assert_eq!([truth.ee_candidates, truth.ee.len()], case.ee, "{scene}");
    }
}

#[test]
fn edges_are_the_mesh_edges_in_libigl_order() {
    for Case { scene, .. } in SCENES {
        let Some(dir) = scene_dir(scene) else { return };
        let truth = read_scene_truth(&dir).expect("truth");
        let mesh = read_ply(&scene_frames(&dir).expect("frames").t0).expect("mesh");
        // Same set as the step's topology (which sorts by (i, j)).
        let mut by_i = truth.edges.clone();
        by_i.sort_unstable();
        assert_eq!(
            by_i,
            Topology::new(&mesh.triangles, mesh.positions.len()).edges,
            "{scene}"
        );
        // libigl order: i < j, strictly increasing in (j, i).
        assert!(truth.edges.iter().all(|&[i, j]| i < j));
        assert!(truth
            .edges
            .windows(2)
            .all(|w| (w[0][1], w[0][0]) < (w[1][1], w[1][0])));
    }
}

#[test]
fn touching_pairs_are_well_formed_and_not_incident() {
    for Case { scene, .. } in SCENES {
        let Some(dir) = scene_dir(scene) else { return };
        let truth = read_scene_truth(&dir).expect("truth");
        let mesh = read_ply(&scene_frames(&dir).expect("frames").t0).expect("mesh");
        let edges: HashSet<[u32; 2]> = truth.edges.iter().copied().collect();
        for &(v, f) in &truth.vf {
            assert!((v as usize) < truth.vertices && (f as usize) < truth.faces);
            assert!(
                !mesh.triangles[f as usize].contains(&v),
                "{scene}: vertex {v} is a corner of face {f}"
            );
        }
        let vf: HashSet<_> = truth.vf.iter().collect();
        assert_eq!(vf.len(), truth.vf.len(), "{scene}: repeated vf pair");
        for &(a, b) in &truth.ee {
            assert!(a < b, "{scene}: pair {a:?} {b:?} not ordered");
            assert!(
                edges.contains(&a) && edges.contains(&b),
                "{scene}: {a:?} {b:?} not edges"
            );
            assert!(
                !a.iter().any(|v| b.contains(v)),
                "{scene}: edges {a:?} {b:?} share a vertex"
            );
        }
        let ee: HashSet<_> = truth.ee.iter().collect();
        assert_eq!(ee.len(), truth.ee.len(), "{scene}: repeated ee pair");
    }
}

/// Bounding box of points swept linearly from t=0 to t=1.
fn swept_box(x0: &[DVec3], x1: &[DVec3], ids: &[u32]) -> (DVec3, DVec3) {
    let points = ids.iter().flat_map(|&i| [x0[i as usize], x1[i as usize]]);
    points.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
        (lo.min(p), hi.max(p))
    })
}

fn boxes_overlap(a: (DVec3, DVec3), b: (DVec3, DVec3)) -> bool {
    a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
}

/// Features that touch during the step must have overlapping swept boxes; a wrong id mapping
/// (vertex/edge/face offsets, edge order) would pair features far apart.
#[test]
fn touching_pairs_are_geometrically_close() {
    for Case { scene, .. } in SCENES {
        let Some(dir) = scene_dir(scene) else { return };
        let truth = read_scene_truth(&dir).expect("truth");
        let frames = scene_frames(&dir).expect("frames");
        let (m0, m1) = (
            read_ply(&frames.t0).expect("t0"),
            read_ply(&frames.t1).expect("t1"),
        );
        let vectors = |positions: &[[f64; 3]]| -> Vec<DVec3> {
            positions.iter().map(|&p| DVec3::from_array(p)).collect()
        };
        let (x0, x1) = (&vectors(&m0.positions), &vectors(&m1.positions));
        for &(v, f) in &truth.vf {
            let face = m0.triangles[f as usize];
            assert!(
                boxes_overlap(swept_box(x0, x1, &[v]), swept_box(x0, x1, &face)),
                "{scene}: vertex {v} and face {f} never come close"
            );
        }
        for &(a, b) in &truth.ee {
            assert!(
                boxes_overlap(swept_box(x0, x1, &a), swept_box(x0, x1, &b)),
                "{scene}: edges {a:?} and {b:?} never come close"
            );
        }
        // Control: had the edges been numbered in plain lexicographic order (the likely
        // mistake), most pairs would fall apart.
        let lexicographic = Topology::new(&m0.triangles, x0.len()).edges;
        let index: HashMap<[u32; 2], usize> = truth
            .edges
            .iter()
            .enumerate()
            .map(|(k, &e)| (e, k))
            .collect();
        let wrong = |e: [u32; 2]| lexicographic[index[&e]];
        let still_close = truth
            .ee
            .iter()
            .filter(|&&(a, b)| {
                boxes_overlap(swept_box(x0, x1, &wrong(a)), swept_box(x0, x1, &wrong(b)))
            })
            .count();
        eprintln!(
            "{scene}: {still_close} of {} ee pairs close under the wrong edge order",
            truth.ee.len()
        );
        assert!(
            still_close * 2 < truth.ee.len(),
            "{scene}: the geometric check cannot tell orders apart"
        );
    }
}

#[test]
fn funnel_touching_pairs_match_the_toi_files() {
    let Some(dir) = scene_dir("cloth-funnel") else {
        return;
    };
    let truth = read_scene_truth(&dir).expect("truth");
    for (kind, expected) in [("vf", truth.vf.len()), ("ee", truth.ee.len())] {
        let text =
            std::fs::read_to_string(dir.join(format!("toi/227{kind}_toi.txt"))).expect("toi");
        assert_eq!(
            text.lines().filter(|l| !l.trim().is_empty()).count(),
            expected,
            "{kind}"
        );
    }
}

/// A scene with two triangles `[0, 1, 2]`, `[2, 1, 3]`: 4 vertices, edges in libigl order
/// `[0,1] [0,2] [1,2] [1,3] [2,3]` (ids 4..9), faces ids 9 and 10.
fn fake_scene(
    tmp: &TempDir,
    frame_names: &[&str],
    vf: &str,
    vf_bool: &str,
    ee: &str,
    ee_bool: &str,
) {
    let mesh = Mesh {
        positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0; 3]],
        triangles: vec![[0, 1, 2], [2, 1, 3]],
        ..Mesh::default()
    };
    std::fs::create_dir_all(tmp.path("frames")).expect("mkdir");
    for name in frame_names {
        write_ply(&tmp.path(&format!("frames/{name}")), &mesh).expect("write frame");
    }
    tmp.file("boxes/9vf.json", vf);
    tmp.file("mma_bool/9vf_mma_bool.json", vf_bool);
    tmp.file("boxes/9ee.json", ee);
    tmp.file("mma_bool/9ee_mma_bool.json", ee_bool);
}

#[test]
fn id_mapping_on_a_hand_made_scene() {
    let tmp = TempDir::new("io-truth-fake");
    // frame10 sorts before frame9 as text: the numeric order must win.
    fake_scene(
        &tmp,
        &["frame10.ply", "frame9.ply"],
        "[[3, 9], [0, 10]]",
        "[true, false]",
        "[[4, 8], [6, 7], [5, 7]]",
        "[true, false, true]",
    );
    let frames = scene_frames(&tmp.0).expect("frames");
    assert!(frames.t0.ends_with("frame9.ply") && frames.t1.ends_with("frame10.ply"));
    let truth = read_scene_truth(&tmp.0).expect("truth");
    assert_eq!(truth.edges, libigl_edges(&[[0, 1, 2], [2, 1, 3]]));
    assert_eq!(truth.edges, vec![[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]]);
    assert_eq!(truth.vf, vec![(3, 0)]);
    // Edge 0 = [0,1] with edge 4 = [2,3]; edge 1 = [0,2] with edge 3 = [1,3].
    assert_eq!(truth.ee, vec![([0, 1], [2, 3]), ([0, 2], [1, 3])]);
    assert_eq!((truth.vf_candidates, truth.ee_candidates), (2, 3));
}

#[test]
fn malformed_scenes_are_refused_with_clear_errors() {
    let frames = ["a9.ply", "a10.ply"];
    let ok_ee = ("[[4, 8]]", "[true]");
    let cases: [(&str, &str, &str, &str, &str); 7] = [
        ("count", "[[3, 9], [0, 10]]", "[true]", ok_ee.0, "counts"),
        (
            "reversed",
            "[[9, 3]]",
            "[true]",
            ok_ee.0,
            "expected [vertex, face], found [face, vertex]",
        ),
        (
            "edge-as-face",
            "[[3, 5]]",
            "[true]",
            ok_ee.0,
            "found [vertex, edge]",
        ),
        (
            "face-range",
            "[[3, 11]]",
            "[true]",
            ok_ee.0,
            "found [vertex, out of range]",
        ),
        (
            "ee-vertex",
            "[[3, 9]]",
            "[true]",
            "[[2, 8]]",
            "expected [edge, edge], found [vertex, edge]",
        ),
        (
            "ee-self",
            "[[3, 9]]",
            "[true]",
            "[[5, 5]]",
            "an edge paired with itself",
        ),
        (
            "json",
            "[[3, 9],\n [0, -1]]",
            "[true, true]",
            ok_ee.0,
            "invalid JSON at line 2",
        ),
    ];
    for (name, vf, vf_bool, ee, what) in cases {
        let tmp = TempDir::new("io-truth-bad");
        fake_scene(&tmp, &frames, vf, vf_bool, ee, ok_ee.1);
        let e = read_scene_truth(&tmp.0).expect_err(name);
        let message = e.to_string();
        let file = if name.starts_with("ee") {
            "9ee.json"
        } else {
            "9vf.json"
        };
        assert!(message.contains(file), "{name}: {message}");
        match name {
            "count" => {
                assert!(
                    matches!(
                        e,
                        IoError::CountMismatch {
                            pairs: 2,
                            bools: 1,
                            ..
                        }
                    ),
                    "{e:?}"
                );
                assert!(
                    message.contains("lists 2 pairs")
                        && message.contains("9vf_mma_bool.json has 1"),
                    "{message}"
                );
            }
            "json" => assert!(matches!(e, IoError::Json { line: 2, .. }), "{e:?}"),
            _ => {
                assert!(
                    matches!(e, IoError::BadPair { pair: 0, .. }),
                    "{name}: {e:?}"
                );
                assert!(message.contains(what), "{name}: {message}");
            }
        }
    }
}

#[test]
fn scene_directories_without_two_numbered_frames_are_refused() {
    for (frames, what) in [
        (&["a1.ply"][..], "expected two .ply frame files, found 1"),
        (&["a1.ply", "a2.ply", "a3.ply"][..], "found 3"),
        (
            &["a1.ply", "b1.ply"][..],
            "both .ply files carry the frame number 1",
        ),
        (&["a1.ply", "last.ply"][..], "must end in its frame number"),
    ] {
        let tmp = TempDir::new("io-truth-frames");
        fake_scene(&tmp, frames, "[]", "[]", "[]", "[]");
        let e = scene_frames(&tmp.0).expect_err(what);
        assert!(matches!(e, IoError::SceneLayout { .. }), "{e:?}");
        assert!(e.to_string().contains(what), "{e}");
    }
    let tmp = TempDir::new("io-truth-noframes");
    let e = read_scene_truth(&tmp.0).expect_err("no frames dir");
    assert!(matches!(e, IoError::Io { .. }), "{e:?}");
    assert!(e.to_string().contains("frames"), "{e}");
}
