//! The crack filter on the generated cut and fracture scenes: with it (the default), pairs
//! joined through the step's parent list (a new vertex and its parent count as one vertex) are
//! not reported; every other contact is reported exactly as without it.
//!
//! `cargo test --release -p topoccd --test crack_filter -- --nocapture` prints the contacts the
//! filter removes per scene.

use std::collections::HashSet;
use std::path::Path;

use topoccd::io::sequence::step_from_frames;
use topoccd::{Ccd, Method, QueryOptions, Report, Step};
use topoccd_scenes::paper::{generate_frames, GenOptions, PaperScene};

/// Each vertex's representative: its parent if it is a new vertex of the step, else itself.
fn representatives(step: &Step) -> Vec<u32> {
    let mut canon: Vec<u32> = (0..step.vertex_count() as u32).collect();
    for &[child, parent] in step.parents() {
        canon[child as usize] = parent;
    }
    canon
}

/// Whether two features (vertex lists) share a vertex once children are their parents.
fn joined(canon: &[u32], a: &[u32], b: &[u32]) -> bool {
    a.iter()
        .any(|&x| b.iter().any(|&y| canon[x as usize] == canon[y as usize]))
}

/// Checks one step; returns (contacts without the filter, contacts it removed).
fn check_step(ccd: &mut Ccd, step: &Step, what: &str) -> (usize, usize) {
    let on = QueryOptions::default();
    assert!(on.crack_filter, "the crack filter is on by default");
    let off = QueryOptions {
        crack_filter: false,
        ..on
    };
    let filtered: Report = ccd.query(step, Method::Bvh, &on).unwrap();
    let all: Report = ccd.query(step, Method::Bvh, &off).unwrap();
    let canon = representatives(step);
    let tris = step.triangles();
    let kept_vf: HashSet<_> = filtered.vf.iter().map(|c| (c.vertex, c.face)).collect();
    let kept_ee: HashSet<_> = filtered.ee.iter().map(|c| (c.a, c.b)).collect();
    let mut removed = 0;
    for c in &all.vf {
        let crack = joined(&canon, &[c.vertex], &tris[c.face as usize]);
        assert_eq!(
            kept_vf.contains(&(c.vertex, c.face)),
            !crack,
            "{what}: vf {c:?}, along a fresh crack: {crack}"
        );
        removed += usize::from(crack);
    }
    for c in &all.ee {
        let crack = joined(&canon, &c.a, &c.b);
        assert_eq!(
            kept_ee.contains(&(c.a, c.b)),
            !crack,
            "{what}: ee {c:?}, along a fresh crack: {crack}"
        );
        removed += usize::from(crack);
    }
    // What is kept is reported exactly as without the filter (same pairs, same times).
    let unfiltered_vf: Vec<_> = all
        .vf
        .iter()
        .filter(|c| kept_vf.contains(&(c.vertex, c.face)))
        .copied()
        .collect();
    let unfiltered_ee: Vec<_> = all
        .ee
        .iter()
        .filter(|c| kept_ee.contains(&(c.a, c.b)))
        .copied()
        .collect();
    assert_eq!(filtered.vf, unfiltered_vf, "{what}");
    assert_eq!(filtered.ee, unfiltered_ee, "{what}");
    if step.parents().is_empty() {
        assert_eq!(removed, 0, "{what}: no topology change, nothing to filter");
    }
    (all.contact_count(), removed)
}

fn check_scene(scene: PaperScene) {
    let mut ccd = Ccd::new();
    let (mut total, mut removed, mut changes) = (0, 0, 0);
    let gen = GenOptions {
        scale: 0.1,
        frames: 4,
        seed: 1,
    };
    let (frames, _) = generate_frames(scene, &gen);
    for (k, pair) in frames.windows(2).enumerate() {
        let step = step_from_frames(
            &pair[0].mesh,
            &pair[1].mesh,
            &pair[1].parents,
            Path::new("(generated)"),
            k,
        )
        .expect("generated steps are valid");
        changes += usize::from(!step.parents().is_empty());
        let (t, r) = check_step(&mut ccd, &step, &format!("{scene} step {k}"));
        total += t;
        removed += r;
    }
    eprintln!(
        "{scene}: {removed} of {total} contacts removed by the crack filter over {} steps ({changes} with a topology change)",
        frames.len() - 1
    );
    if changes > 0 {
        assert!(
            removed > 0,
            "{scene}: cracks opened but nothing was filtered"
        );
    }
}

#[test]
fn crack_filter_on_nidus_cut() {
    check_scene(PaperScene::NidusCut);
}

#[test]
fn crack_filter_on_lion() {
    check_scene(PaperScene::Lion);
}

#[test]
fn crack_filter_on_bunny_dragon() {
    check_scene(PaperScene::BunnyDragon);
}

#[test]
fn crack_filter_on_crash() {
    check_scene(PaperScene::Crash);
}

/// A sphere cut in two halves that then fly apart: at t=0 the two sides of the cut touch
/// everywhere, yet nothing collides, so with the filter there is no contact at all.
#[test]
fn a_fresh_cut_alone_is_no_contact() {
    // A strip of two triangles cut along its middle edge (1, 2): 4 and 5 copy 1 and 2.
    let x0 = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [2.0, 0.5, 0.0],
    ];
    let x1 = [
        [-1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [3.0, 0.5, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 1.0, 0.0],
    ];
    let triangles = [[0u32, 1, 2], [4, 3, 5]];
    let step = Step::with_parents(&x0, &x1, &triangles, &[[4, 1], [5, 2]]).unwrap();
    let on = QueryOptions::default();
    let off = QueryOptions {
        crack_filter: false,
        ..on
    };
    for method in [Method::Brute, Method::Bvh, Method::Cluster] {
        let filtered = topoccd::query(&step, method, &on).unwrap();
        assert_eq!(filtered.contact_count(), 0, "{method}");
        assert_eq!(filtered.earliest_toi(), None, "{method}");
        let unfiltered = topoccd::query(&step, method, &off).unwrap();
        assert_eq!(
            unfiltered.earliest_toi(),
            Some(0.0),
            "{method}: the cut touches at t=0"
        );
    }
}
