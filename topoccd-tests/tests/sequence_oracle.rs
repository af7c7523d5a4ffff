//! The oracle over whole sequences, each method's query object kept across every step as a
//! simulator keeps it, so that whatever a [`Ccd`] carries from one step to the next (the
//! topology, the per-step hierarchy refitted, the cluster method's leaves, the Earliest
//! mode's choice of passes) is checked at every step against a fresh `Method::Brute` query.
//!
//! The sequences (eight seeds, eleven steps each, every k-DOP, with and without a minimum
//! separation): a sheet under a smooth random warp whose motion per step grows linearly (21
//! times larger in the last step than in the first), torn half-way through the sequence along
//! a column of vertices (a topology change through parents), its flap then folding over the
//! tear, onto the rest and through it, by about 86 degrees a step. The test also checks that
//! the hierarchy was carried: refitted, not rebuilt, on most steps whose triangles did not
//! change, after the tear too, among them late steps with contacts that a hierarchy left as it
//! was in the step before would miss (their triangles' volumes of that step are apart); and
//! that the cluster method carried its leaves over, on steps with contacts that the last
//! step's intermediate clusters, trusted, would hide.
//!
//! `cargo test --release -p topoccd --test sequence_oracle -- --nocapture` prints per step what
//! was carried and the contacts a stale hierarchy would miss.

mod mesh_util;

use std::collections::HashMap;

use topoccd::broad::cluster::Clustering;
use topoccd::kdop::DopKind;
use topoccd::math::DVec3;
use topoccd::{Ccd, Method, Mode, QueryOptions, Report, Step};

/// Frames per sequence (steps plus one).
const FRAMES: usize = 12;
/// The frame at which the sheet is torn: step `TEAR - 1` (frame `TEAR - 1` to `TEAR`) changes
/// the triangles, the steps before and after keep theirs.
const TEAR: usize = 6;
/// The flap's fold by the last frame, in radians (past pi, its lower rows pass through the
/// left part).
const FOLD: f64 = 2.4 * std::f64::consts::PI;
/// The methods a simulator may keep a query object for, and the modes.
const METHODS: [Method; 3] = [Method::Bvh, Method::Cluster, Method::Auto];
const MODES: [Mode; 2] = [Mode::All, Mode::Earliest];

/// One frame: positions, triangles, and the `[child, parent]` rows of its new vertices.
struct Frame {
    x: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    parents: Vec<[u32; 2]>,
}

/// The frames of sequence `seed`: an `nu x nv` sheet (the sheet of
/// [`mesh_util::warped_step`]) warped by [`mesh_util::warped_frame`] at `(k / (FRAMES - 1))^2`
/// of its full strength (the motion per step grows linearly), torn at frame [`TEAR`] along the
/// column `u = 1/2` from the bottom to 5/8 of its height (the column's vertices duplicated for
/// the right flap, each copy's parent its original). From then on the flap folds over the
/// tear onto the left part and through it, its rows ever less the higher they are (angle
/// `FOLD w (k - TEAR) / (FRAMES - 1 - TEAR)`, `w` from 1 at the bottom to 0 at the top of
/// the tear), so that rows pass through the left part in each of the last steps. The fold
/// acts on the sheet at rest, before the warp.
fn frames(seed: u64) -> Vec<Frame> {
    let (nu, nv) = [(20, 14), (24, 12), (16, 16), (22, 14)][seed as usize % 4];
    let sheet = |u: f64, v: f64| DVec3::new(u, v, 0.1 * (3.0 * u).sin());
    let rest = mesh_util::grid(nu, nv, sheet, sheet);
    let side = nu + 1;
    let (col, row) = (|v: u32| v % side, |v: u32| v / side);
    let tear_top = nv * 5 / 8;
    // The torn triangles: the right flap's use copies of the tear's vertices.
    let mut copy_of = HashMap::new();
    let mut parents = Vec::new();
    let torn: Vec<[u32; 3]> = (rest.triangles().iter())
        .map(|t| {
            let right = t.iter().any(|&v| col(v) > nu / 2);
            t.map(|v| {
                if !right || col(v) != nu / 2 || row(v) >= tear_top {
                    return v;
                }
                *copy_of.entry(v).or_insert_with(|| {
                    let child = rest.vertex_count() as u32 + parents.len() as u32;
                    parents.push([child, v]);
                    child
                })
            })
        })
        .collect();
    // The torn sheet at rest, and how much each vertex belongs to the flap (0 on the left part
    // and above the tear, 1 at the bottom edge).
    let at_rest: Vec<DVec3> = (rest.pos0().iter().copied())
        .chain(parents.iter().map(|&[_, p]| rest.pos0()[p as usize]))
        .collect();
    let flap: Vec<f64> = (0..rest.vertex_count() as u32)
        .map(|v| (col(v) > nu / 2, row(v)))
        .chain(parents.iter().map(|&[_, p]| (true, row(p))))
        .map(|(right, r)| {
            let h = r as f64 / tear_top as f64;
            if right && h < 1.0 {
                1.0 - h
            } else {
                0.0
            }
        })
        .collect();
    let hinge = sheet(0.5, 0.0);
    // `warped_frame(seed, j, J)` warps by `j / (J - 1)`: `j = k^2` gives the quadratic schedule.
    let last = FRAMES - 1;
    (0..FRAMES)
        .map(|k| {
            let warp = mesh_util::warped_frame(seed, k * k, last * last + 1);
            if k < TEAR {
                return Frame {
                    x: rest.pos0().iter().map(|&p| warp(p)).collect(),
                    triangles: rest.triangles().to_vec(),
                    parents: Vec::new(),
                };
            }
            let angle = FOLD * (k - TEAR) as f64 / (last - TEAR) as f64;
            let fold = |(p, w): (&DVec3, &f64)| {
                let (sin, cos) = (angle * w).sin_cos();
                let d = *p - hinge;
                let x = hinge.x + d.x * cos - d.z * sin;
                DVec3::new(x, p.y, hinge.z + d.x * sin + d.z * cos)
            };
            Frame {
                x: at_rest.iter().zip(&flap).map(fold).map(&warp).collect(),
                triangles: torn.clone(),
                parents: if k == TEAR {
                    parents.clone()
                } else {
                    Vec::new()
                },
            }
        })
        .collect()
}

/// Step `k` of `frames`: frame `k` to `k + 1`, across the parents of frame `k + 1`.
fn step(frames: &[Frame], k: usize) -> Step<'static> {
    let (a, b) = (&frames[k], &frames[k + 1]);
    let x0: Vec<[f64; 3]> = a.x.iter().map(|p| p.to_array()).collect();
    let x1: Vec<[f64; 3]> = b.x.iter().map(|p| p.to_array()).collect();
    Step::with_parents(x0, x1, b.triangles.clone(), &b.parents).expect("a valid step")
}

/// The triangles' axis-aligned boxes over the step, both ends.
fn swept_boxes(step: &Step) -> Vec<(DVec3, DVec3)> {
    (step.triangles().iter())
        .map(|t| {
            let points = t.iter().flat_map(|&v| {
                let v = v as usize;
                [step.pos0()[v], step.pos1()[v]]
            });
            points.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p), hi.max(p))
            })
        })
        .collect()
}

/// The contacts of `now` (a report of a step with the triangles of `before`) that a broad
/// phase which leaves out every triangle pair `skips` names would miss: every triangle incident
/// to one feature and every triangle incident to the other make such a pair, so whichever
/// triangles own the two features, their pair is left out.
fn missed(before: &Step, now: &Report, skips: impl Fn(u32, u32) -> bool) -> usize {
    let mut incident: Vec<Vec<u32>> = vec![Vec::new(); before.vertex_count()];
    for (t, tri) in before.triangles().iter().enumerate() {
        for &v in tri {
            incident[v as usize].push(t as u32);
        }
    }
    let of_edge = |e: [u32; 2]| -> Vec<u32> {
        let on = &incident[e[1] as usize];
        (incident[e[0] as usize].iter())
            .filter(|t| on.contains(t))
            .copied()
            .collect()
    };
    let all = |a: &[u32], b: &[u32]| a.iter().all(|&s| b.iter().all(|&t| skips(s, t)));
    let vf = (now.vf.iter())
        .filter(|c| all(&incident[c.vertex as usize], &[c.face]))
        .count();
    let ee = (now.ee.iter())
        .filter(|c| all(&of_edge(c.a), &of_edge(c.b)))
        .count();
    vf + ee
}

/// The contacts of `now` that a hierarchy fitted to the volumes of `before` (a step with the
/// same triangles) and not refitted would miss: the boxes of their triangles over `before` are
/// apart by more than twice the volumes' inflation `sep`, plus a margin far above rounding
/// (the hierarchy's k-DOP volumes lie inside these boxes so inflated, up to rounding).
fn stale_tree_misses(before: &Step, now: &Report, sep: f64) -> usize {
    let boxes = swept_boxes(before);
    let margin = 2.0 * sep + 1e-6;
    missed(before, now, |a, b| {
        let ((lo_a, hi_a), (lo_b, hi_b)) = (boxes[a as usize], boxes[b as usize]);
        (0..3).any(|i| lo_a[i] > hi_b[i] + margin || lo_b[i] > hi_a[i] + margin)
    })
}

/// The contacts of `now` that the clustering of the step before, trusted without being
/// certified anew, would miss: their triangles lay in one intermediate cluster (whose pairs
/// the cluster method does not test).
fn stale_clustering_misses(before: &Step, now: &Report, clustering: &Clustering) -> usize {
    let cluster = |t: u32| {
        let leaf = clustering.leaf_of_triangle[t as usize];
        clustering.intermediate_of_leaf[leaf as usize]
    };
    missed(before, now, |a, b| cluster(a) == cluster(b))
}

/// The options of sequence `seed`: every k-DOP in turn, and a minimum separation on every
/// third sequence.
fn options(seed: u64) -> QueryOptions {
    let mut options = QueryOptions {
        kdop: DopKind::ALL[seed as usize % DopKind::ALL.len()],
        ..QueryOptions::default()
    };
    if seed % 3 == 2 {
        options.narrow.min_distance = 1e-3;
        // The elementary tests slow down when the separation is large against the tolerance.
        options.narrow.tolerance = 1e-3;
    }
    options
}

/// What one sequence showed, for the assertions over all of them.
#[derive(Default)]
struct Seen {
    /// Steps with the triangles of the step before (after the first).
    same_steps: usize,
    /// Of them, per (method, mode): those whose per-step hierarchy was refitted, those after
    /// the tear, and those whose cluster query carried leaves over.
    refitted: HashMap<(Method, Mode), usize>,
    refitted_after_tear: HashMap<(Method, Mode), usize>,
    carried_leaves: HashMap<(Method, Mode), usize>,
    /// Steps in the second half, refitted by the BVH in `Mode::All`, with contacts a stale tree
    /// would miss; and those contacts over all steps.
    late_refitted_with_stale_misses: usize,
    stale_tree_misses: usize,
    /// Contacts the last step's clustering, trusted, would miss, on steps whose cluster query
    /// (`Mode::All`) carried leaves over.
    stale_clustering_misses: usize,
    /// The oracle's contacts after the start of each of the last three steps.
    late_contacts: Vec<usize>,
    /// Whether `Method::Auto` chose the cluster method on some step.
    auto_ran_cluster: bool,
}

/// Runs sequence `seed` through one query object per method and mode, each step against the
/// oracle from nothing.
fn check_sequence(seed: u64) -> Seen {
    let frames = frames(seed);
    let steps: Vec<Step> = (0..FRAMES - 1).map(|k| step(&frames, k)).collect();
    assert!(
        steps[TEAR - 1].vertex_count() > steps[TEAR - 2].vertex_count()
            && !steps[TEAR - 1].parents().is_empty(),
        "sequence {seed}: the tear must add vertices through parents"
    );
    let all = options(seed);
    let earliest = QueryOptions {
        mode: Mode::Earliest,
        ..all
    };
    // One query object per method and mode, kept across the whole sequence.
    let mut ccds: HashMap<(Method, Mode), Ccd> = HashMap::new();
    let mut seen = Seen::default();
    for (k, step) in steps.iter().enumerate() {
        let what = format!("sequence {seed} step {k}");
        let oracle = Ccd::new().query(step, Method::Brute, &all).unwrap();
        let oracle_earliest = Ccd::new().query(step, Method::Brute, &earliest).unwrap();
        let same = k > 0 && step.triangles() == steps[k - 1].triangles();
        seen.same_steps += usize::from(same);
        let tree_misses = if same {
            stale_tree_misses(&steps[k - 1], &oracle, all.narrow.min_distance)
        } else {
            0
        };
        seen.stale_tree_misses += tree_misses;
        let mut carried = Vec::new();
        for method in METHODS {
            for mode in MODES {
                let what = format!("{what} {method} {mode:?}");
                let ccd = ccds.entry((method, mode)).or_default();
                let before = (same && method == Method::Cluster && mode == Mode::All)
                    .then(|| ccd.clustering().clone());
                let options = if mode == Mode::All { &all } else { &earliest };
                let report = ccd.query(step, method, options).unwrap();
                assert_eq!(ccd.validate_tree(step), Ok(()), "{what}");
                let reference = if mode == Mode::All {
                    &oracle
                } else {
                    &oracle_earliest
                };
                // Bitwise: the same pairs, times and certainties as the oracle from nothing.
                assert_eq!(report.vf, reference.vf, "{what}: vertex-face");
                assert_eq!(report.ee, reference.ee, "{what}: edge-edge");
                assert_eq!(report.earliest, reference.earliest, "{what}: earliest");
                assert_eq!(report.unresolved, reference.unresolved, "{what}");
                if mode == Mode::Earliest {
                    let tolerance = earliest.narrow.tolerance;
                    mesh_util::assert_earliest_pairs(&oracle, &report, tolerance, &what);
                }
                // What was carried: the hierarchy refitted, the leaves carried over.
                let ran = report.stats.method;
                seen.auto_ran_cluster |= method == Method::Auto && ran == Method::Cluster;
                let refitted = ran == Method::Bvh && ccd.tree_refitted();
                let leaves = (report.stats.cluster).map_or(0, |c| c.reused_leaves);
                assert!(
                    k > 0 || (!refitted && leaves == 0),
                    "{what}: carried from nothing"
                );
                if same {
                    let key = (method, mode);
                    *seen.refitted.entry(key).or_default() += usize::from(refitted);
                    *seen.refitted_after_tear.entry(key).or_default() +=
                        usize::from(refitted && k >= TEAR);
                    *seen.carried_leaves.entry(key).or_default() += usize::from(leaves > 0);
                }
                let bvh_all = method == Method::Bvh && mode == Mode::All;
                if bvh_all && refitted && k >= FRAMES / 2 && tree_misses > 0 {
                    seen.late_refitted_with_stale_misses += 1;
                }
                if let Some(before) = before.filter(|_| leaves > 0) {
                    let misses = stale_clustering_misses(&steps[k - 1], &oracle, &before);
                    seen.stale_clustering_misses += misses;
                }
                carried.push(format!(
                    "{method}/{mode:?}: {}",
                    match ran {
                        Method::Bvh if refitted => "refitted".to_string(),
                        Method::Bvh => "built".to_string(),
                        _ => format!("{leaves} leaves carried"),
                    }
                ));
            }
        }
        // The contacts after the step's start (not those at time 0 along the tear, where
        // copies touch their originals).
        let during = oracle.vf.iter().filter(|c| c.toi > 0.0).count()
            + oracle.ee.iter().filter(|c| c.toi > 0.0).count();
        if k + 3 >= FRAMES - 1 {
            seen.late_contacts.push(during);
        }
        println!(
            "{what}: {} contacts ({during} after the start), {tree_misses} a stale tree \
             misses; {}",
            oracle.contact_count(),
            carried.join(", ")
        );
    }
    seen
}

#[test]
fn sequences_kept_in_one_query_object_match_the_oracle_at_every_step() {
    let (mut tree_misses, mut clustering_misses) = (0, 0);
    for seed in 0..8 {
        let seen = check_sequence(seed);
        let what = format!("sequence {seed}");
        // Every step but the first and the tear keeps its triangles.
        assert_eq!(seen.same_steps, FRAMES - 3, "{what}");
        // The late steps collide during the step, so that a carried state has something to
        // miss.
        assert!(
            seen.late_contacts.iter().all(|&c| c > 0),
            "{what}: the last steps must collide after their start: {:?}",
            seen.late_contacts
        );
        // The hierarchy is carried, before and after the tear: refitted on most steps that keep
        // their triangles (a refit that would fit too loosely is rebuilt), in both modes; the
        // cluster method's leaves carried over.
        for mode in MODES {
            let refitted = seen.refitted[&(Method::Bvh, mode)];
            assert!(
                refitted * 2 >= seen.same_steps,
                "{what} {mode:?}: refitted on {refitted} of {} steps",
                seen.same_steps
            );
            let after = seen.refitted_after_tear[&(Method::Bvh, mode)];
            assert!(after > 0, "{what} {mode:?}: never refitted after the tear");
            // (With a minimum separation the cluster method has no certificate: no leaves.)
            let separated = options(seed).narrow.min_distance > 0.0;
            let carried = seen.carried_leaves[&(Method::Cluster, mode)];
            assert!(
                carried * 2 >= seen.same_steps || separated,
                "{what} {mode:?}: leaves carried on {carried} of {} steps",
                seen.same_steps
            );
            // Auto carries whatever the method it chose carries.
            let auto =
                seen.refitted[&(Method::Auto, mode)] + seen.carried_leaves[&(Method::Auto, mode)];
            assert!(
                auto * 2 >= seen.same_steps || (separated && seen.auto_ran_cluster),
                "{what} {mode:?}: Auto carried on {auto} of {} steps",
                seen.same_steps
            );
        }
        // And carried where it matters: late steps refitted whose contacts a tree left as it
        // was in the step before would miss.
        assert!(
            seen.late_refitted_with_stale_misses > 0,
            "{what}: no late refitted step has contacts a stale tree would miss ({} over all \
             steps)",
            seen.stale_tree_misses
        );
        tree_misses += seen.stale_tree_misses;
        clustering_misses += seen.stale_clustering_misses;
    }
    println!(
        "contacts a stale tree would miss: {tree_misses}; a stale clustering: {clustering_misses}"
    );
    // Some contacts lie inside an intermediate cluster of the step before, on steps whose
    // cluster query carried leaves over: the clustering must have been certified anew.
    assert!(
        clustering_misses > 0,
        "no contact a stale clustering would miss"
    );
}
