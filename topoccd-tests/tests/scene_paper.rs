//! The paper scene generators: determinism, sizes, an intersection-free first frame, contacts
//! in every step, topology changes, valid sequences on disk, and the collision response.

use std::path::PathBuf;

use topoccd::io::sequence::{write_frame, Sequence};
use topoccd::io::Mesh;
use topoccd::math::DVec3;
use topoccd::{Ccd, Method, QueryOptions, Step};
use topoccd_scenes::paper::{
    generate, generate_frames, initial_triangles, GenOptions, GeneratedFrame, PaperScene,
};

/// A fresh directory under the system temp dir, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("topoccd-paper-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        TempDir(dir)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A small scale per scene that keeps the tests fast (a few thousand to 16K triangles).
fn small_scale(scene: PaperScene) -> f64 {
    match scene {
        PaperScene::Nidus | PaperScene::NidusCut | PaperScene::Airbag => 0.1,
        PaperScene::Lion | PaperScene::Crash => 0.01,
        PaperScene::BunnyDragon => 0.03,
    }
}

fn options(scene: PaperScene, frames: usize, seed: u64) -> GenOptions {
    GenOptions {
        scale: small_scale(scene),
        frames,
        seed,
    }
}

/// Positions as vectors.
fn vectors(positions: &[[f64; 3]]) -> Vec<DVec3> {
    positions.iter().map(|&p| DVec3::from_array(p)).collect()
}

/// The step from frame `k` to `k + 1` as a reader builds it (new vertices at their parents).
fn step_of(frames: &[GeneratedFrame], k: usize) -> Step<'static> {
    let (a, b) = (&frames[k], &frames[k + 1]);
    let mut x0 = vectors(&a.mesh.positions);
    x0.extend(vectors(&b.mesh.positions[a.mesh.positions.len()..]));
    for &(new, parent) in &b.parents {
        x0[new as usize] = DVec3::from_array(a.mesh.positions[parent as usize]);
    }
    Step::new(x0, vectors(&b.mesh.positions), b.mesh.triangles.clone()).expect("valid step")
}

#[test]
fn names_round_trip() {
    for scene in PaperScene::ALL {
        assert_eq!(PaperScene::from_name(scene.name()), Some(scene));
        assert_eq!(scene.to_string(), scene.name());
    }
    assert_eq!(PaperScene::from_name("Nidus"), None);
}

#[test]
fn same_seed_same_frames_other_seed_other_frames() {
    for scene in PaperScene::ALL {
        let (a, sa) = generate_frames(scene, &options(scene, 3, 5));
        let (b, sb) = generate_frames(scene, &options(scene, 3, 5));
        let (c, _) = generate_frames(scene, &options(scene, 3, 6));
        assert_eq!(a, b, "{scene}: same seed, different frames");
        assert_eq!(sa.contacts, sb.contacts, "{scene}");
        assert_ne!(a, c, "{scene}: another seed gave the same frames");
    }
}

#[test]
fn triangle_counts_follow_the_paper_and_the_scale() {
    let near = |scene: PaperScene, scale: f64| {
        let n = initial_triangles(scene, scale) as f64;
        let want = scene.paper_triangles() as f64 * scale;
        assert!(
            (n - want).abs() <= 0.25 * want,
            "{scene} at scale {scale}: {n} triangles, paper x scale = {want}"
        );
        n
    };
    for scene in PaperScene::ALL {
        near(scene, 1.0);
        near(scene, 0.5);
    }
    for scene in [PaperScene::Nidus, PaperScene::NidusCut, PaperScene::Airbag] {
        let (a, b) = (near(scene, 0.05), near(scene, 0.1));
        assert!(
            (b / a - 2.0).abs() < 0.5,
            "{scene}: {a} -> {b} is not linear"
        );
    }
    // The counts computed without generating are the generated ones.
    for scene in PaperScene::ALL {
        let mut first = 0;
        let summary = generate(scene, &options(scene, 2, 1), |k, mesh: &Mesh, _| {
            if k == 0 {
                first = mesh.triangles.len();
            }
            Ok::<(), ()>(())
        })
        .expect("infallible sink");
        assert_eq!(
            first,
            initial_triangles(scene, small_scale(scene)),
            "{scene}"
        );
        assert_eq!(summary.triangles_first, first);
    }
}

/// Every scene: frame 0 has no contact as a static step; every step has a contact (checked
/// with the default query, not the generator's); the topology-changing scenes change their
/// triangles in most steps; the written sequence reads back step for step.
#[test]
fn scenes_collide_every_step_from_a_clean_start_and_read_back() {
    let frames = 5;
    for scene in PaperScene::ALL {
        let opts = options(scene, frames, 3);
        let dir = TempDir::new(scene.name());
        let mut kept = Vec::new();
        let summary = generate(scene, &opts, |k, mesh, parents| {
            kept.push(GeneratedFrame {
                mesh: mesh.clone(),
                parents: parents.to_vec(),
            });
            write_frame(&dir.0, k, mesh, parents).map(|_| ())
        })
        .expect("write frames");
        assert_eq!(kept.len(), frames);
        let mut ccd = Ccd::new();
        let first = &kept[0].mesh;
        let still = Step::new(
            vectors(&first.positions),
            vectors(&first.positions),
            first.triangles.clone(),
        )
        .expect("valid frame");
        let report = ccd
            .query(&still, Method::Bvh, &QueryOptions::default())
            .unwrap();
        assert_eq!(
            report.contact_count(),
            0,
            "{scene}: frame 0 intersects itself"
        );

        let sequence = Sequence::open(&dir.0).expect("the sequence opens");
        assert_eq!(sequence.steps(), frames - 1);
        let mut changed = 0;
        for (k, step) in sequence.iter().map(|r| r.expect("every step reads back")) {
            let ours = step_of(&kept, k);
            assert_eq!(step.pos0(), ours.pos0(), "{scene} step {k}");
            assert_eq!(step.pos1(), ours.pos1(), "{scene} step {k}");
            // Contacts along fresh cracks count here: the crack filter is off.
            let options = QueryOptions {
                crack_filter: false,
                ..QueryOptions::default()
            };
            let report = ccd.query(&step, Method::Bvh, &options).unwrap();
            assert!(
                report.contact_count() > 0,
                "{scene}: no contact in step {k}"
            );
            if kept[k].mesh.triangles != kept[k + 1].mesh.triangles {
                changed += 1;
            }
        }
        assert_eq!(changed, summary.topology_changes, "{scene}");
        if scene.changes_topology() {
            assert!(
                2 * changed > frames - 1,
                "{scene}: only {changed} of {} steps change the triangles",
                frames - 1
            );
            assert!(
                kept.iter().any(|f| !f.parents.is_empty()),
                "{scene}: no parents"
            );
        } else {
            assert_eq!(changed, 0, "{scene}");
        }
    }
}

/// Signed distance of `p` to the plane of triangle `t` of `mesh`-like positions.
fn plane_distance(x: &[DVec3], t: [u32; 3], p: DVec3) -> Option<(f64, [f64; 3])> {
    let [a, b, c] = t.map(|i| x[i as usize]);
    let n = (b - a).cross(c - a);
    let area2 = n.length_squared();
    if area2 < 1e-30 {
        return None;
    }
    let bary = [
        (c - b).cross(p - b).dot(n) / area2,
        (a - c).cross(p - c).dot(n) / area2,
        (b - a).cross(p - a).dot(n) / area2,
    ];
    Some(((p - a).dot(n) / area2.sqrt(), bary))
}

/// After a vertex crosses a face in a step (it ends on the other side of the face's plane,
/// over the face), the response keeps it from going deeper over the next two steps, while the
/// face still exists: for soft scenes it stops, for rigid pieces it bounces back.
#[test]
fn penetration_does_not_deepen_after_the_response() {
    for (scene, scale) in [
        (PaperScene::Nidus, 0.1),
        (PaperScene::Airbag, 0.1),
        (PaperScene::Lion, 0.01),
    ] {
        let opts = GenOptions {
            scale,
            frames: 8,
            seed: 2,
        };
        let (frames, _) = generate_frames(scene, &opts);
        let mut ccd = Ccd::new();
        let (mut checked, mut deeper) = (0, 0);
        for k in 0..frames.len() - 3 {
            let step = step_of(&frames, k);
            let report = ccd
                .query(&step, Method::Bvh, &QueryOptions::default())
                .unwrap();
            for c in &report.vf {
                let face = step.triangles()[c.face as usize];
                let v = c.vertex as usize;
                let Some((d0, _)) = plane_distance(step.pos0(), face, step.pos0()[v]) else {
                    continue;
                };
                let Some((d1, bary)) = plane_distance(step.pos1(), face, step.pos1()[v]) else {
                    continue;
                };
                // Started off the plane (not on a fresh crack), crossed during the step, and
                // ends over the face.
                if d0.abs() < 1e-9 || d0.signum() == d1.signum() || bary.iter().any(|&b| b < 0.0) {
                    continue;
                }
                let depth1 = -d1 * d0.signum();
                let mut worst: f64 = depth1;
                let mut alive = true;
                for later in &frames[k + 2..k + 4] {
                    if !later.mesh.triangles.contains(&face) {
                        alive = false;
                        break;
                    }
                    let x = &vectors(&later.mesh.positions);
                    if let Some((d, _)) = plane_distance(x, face, x[v]) {
                        worst = worst.max(-d * d0.signum());
                    }
                }
                if !alive {
                    continue;
                }
                checked += 1;
                if worst > depth1 + 1e-9 {
                    deeper += 1;
                }
            }
        }
        assert!(checked > 0, "{scene}: no crossing to check");
        assert!(
            deeper * 20 <= checked,
            "{scene}: {deeper} of {checked} crossings went deeper after the response"
        );
    }
}
