//! The proximity query against analytic cases, near the threshold, and against the
//! brute-force oracle on random soups of triangles, free edges and free points (refitted and
//! rebuilt, on one and two threads).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;
use crate::distance::{EdgeEdgeType, PointEdgeType, PointTriangleType};
use crate::{Ccd, StopReason};

fn opts(dhat: f64) -> ProximityOptions {
    ProximityOptions {
        dhat,
        ..ProximityOptions::default()
    }
}

/// The brute-force oracle's report at `config` for `dhat`.
fn oracle(config: &Configuration<'_>, dhat: f64) -> ProximityReport {
    let brute = ProximityOptions {
        method: ProximityMethod::Brute,
        ..opts(dhat)
    };
    proximity(config, &brute).unwrap()
}

fn run(
    x: &[[f64; 3]],
    tris: &[[u32; 3]],
    edges: &[[u32; 2]],
    o: &ProximityOptions,
) -> ProximityReport {
    let config = Configuration::new(x, tris, edges).expect("valid input");
    proximity(&config, o).expect("valid options")
}

/// The pairs without the figures.
fn pairs(r: &ProximityReport) -> ProximityReport {
    ProximityReport {
        stats: ProximityStats::default(),
        ..r.clone()
    }
}

#[test]
fn every_kind_with_its_type() {
    // Triangle 0-1-2 in z=0; vertex 3 above its interior; edge 4-5 crossing over edge 0-1;
    // free point 6 near edge 4-5's end; free point 7 near 6.
    let x = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.25, 0.25, 0.004],   // 3
        [0.5, -1.0, 0.003],    // 4
        [0.5, -0.2, 0.003],    // 5
        [0.5, -0.198, 0.003],  // 6: 0.002 beyond 5 along the edge
        [0.5, -0.198, 0.0075], // 7: 0.0045 above 6
    ];
    let tris = [[0u32, 1, 2]];
    let edges = [[3u32, 4], [5, 4]];
    let r = run(&x, &tris, &edges, &opts(0.005));
    assert_eq!(r.vf.len(), 1);
    assert_eq!(
        (r.vf[0].vertex, r.vf[0].face, r.vf[0].kind),
        (3, 0, PointTriangleType::Interior)
    );
    assert!((r.vf[0].distance - 0.004).abs() < 1e-15);
    // Edge [4, 5] against [0, 1]: 0.2 from it in y, so not; edge [3, 4] runs from above the
    // triangle to beyond it, crossing above edge [0, 1]... at what height? Check with the
    // kernel instead of by hand.
    for p in &r.ee {
        assert!(p.a < p.b && p.a[0] < p.a[1] && p.b[0] < p.b[1]);
        assert!(p.distance < 0.005);
    }
    // Point 6 beyond the end 5 of edge [4, 5]; point 7 above it, sqrt(0.002^2 + 0.0045^2)
    // = 0.00492 from that end.
    assert_eq!(r.ve.len(), 2, "{:?}", r.ve);
    assert_eq!(
        (r.ve[0].vertex, r.ve[0].edge, r.ve[0].kind),
        (6, [4, 5], PointEdgeType::E1)
    );
    assert!((r.ve[0].distance - 0.002).abs() < 1e-12);
    assert_eq!((r.ve[1].vertex, r.ve[1].kind), (7, PointEdgeType::E1));
    assert!((r.ve[1].distance - 0.002f64.hypot(0.0045)).abs() < 1e-12);
    assert_eq!(r.vv.len(), 1);
    assert_eq!((r.vv[0].a, r.vv[0].b), (6, 7));
    assert!((r.vv[0].distance - 0.0045).abs() < 1e-12);
    let r2 = run(&x, &tris, &edges, &opts(0.0049));
    assert_eq!(r2.ve.len(), 1);
    assert_eq!(
        pairs(&r),
        pairs(&run(
            &x,
            &tris,
            &edges,
            &ProximityOptions {
                method: ProximityMethod::Brute,
                ..opts(0.005)
            }
        ))
    );
}

#[test]
fn edge_edge_types_in_the_report_order() {
    // Edge [2, 3] lies above edge [0, 1], crossing it at right angles: EaEb. The report
    // orders a < b, so a = [0, 1].
    let x = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, -0.5, 0.001],
        [0.5, 0.5, 0.001],
    ];
    let r = run(&x, &[], &[[3, 2], [0, 1]], &opts(0.002));
    assert_eq!(r.ee.len(), 1);
    assert_eq!(
        (r.ee[0].a, r.ee[0].b, r.ee[0].kind),
        ([0, 1], [2, 3], EdgeEdgeType::EaEb)
    );
    // Edge [2, 3] from beyond vertex 1: Ea1Eb0 with a = [0, 1].
    let x = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.001, 0.0, 0.0],
        [2.0, 0.0, 0.0],
    ];
    let r = run(&x, &[], &[[2, 3], [0, 1]], &opts(0.002));
    assert_eq!(
        (r.ee[0].a, r.ee[0].b, r.ee[0].kind),
        ([0, 1], [2, 3], EdgeEdgeType::Ea1Eb0)
    );
    assert!(r.vv.is_empty() && r.ve.is_empty());
}

/// Around the threshold: a vertex at `dhat (1 -+ delta)` above a face's interior, far from
/// the origin. Below is always kept; beyond by more than the documented bound never.
#[test]
fn near_the_threshold() {
    let dhat = 1e-3;
    for offset in [0.0, 1.0, 1e3, -7.5e4] {
        for (delta, kept) in [(-1e-9, true), (-1e-12, true), (1e-9, false), (1e-6, false)] {
            let z = dhat * (1.0 + delta);
            let x = [
                [offset, offset, offset],
                [offset + 0.01, offset, offset],
                [offset, offset + 0.01, offset],
                [offset + 0.002, offset + 0.002, offset + z],
            ];
            let r = run(&x, &[[0, 1, 2]], &[], &opts(dhat));
            // The input's own rounding: z is stored relative to `offset`.
            let input = (offset.abs() + z) * f64::EPSILON;
            let exact = (x[3][2] - x[0][2]).abs();
            if exact < dhat - input {
                assert_eq!(r.vf.len(), 1, "offset {offset} delta {delta}: missed");
            }
            let bound = crate::distance::rounding_bound(0.01 + offset.abs() * 0.0 + 0.002, 1.0);
            if exact > dhat + 2.0 * bound + input {
                assert!(
                    r.vf.is_empty(),
                    "offset {offset} delta {delta}: beyond the bound"
                );
            }
            let _ = kept;
        }
    }
}

#[test]
fn dmin_widens_the_threshold() {
    let x = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.2, 0.2, 0.0015],
    ];
    let t = [[0u32, 1, 2]];
    assert!(run(&x, &t, &[], &opts(1e-3)).vf.is_empty());
    let with = ProximityOptions {
        dmin: 1e-3,
        ..opts(1e-3)
    };
    assert_eq!(run(&x, &t, &[], &with).vf.len(), 1);
}

#[test]
fn groups_and_can_collide_apply() {
    let x = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.2, 0.2, 1e-4],
    ];
    let t = [[0u32, 1, 2]];
    let config = Configuration::new(&x, &t, &[]).unwrap();
    assert_eq!(proximity(&config, &opts(1e-3)).unwrap().vf.len(), 1);
    let groups = [1u32, 1, 1, 1];
    let config = Configuration::new(&x, &t, &[])
        .unwrap()
        .with_groups(&groups)
        .unwrap();
    assert!(proximity(&config, &opts(1e-3)).unwrap().is_empty());
    let never = |_: u32, _: u32| false;
    let config = Configuration::new(&x, &t, &[])
        .unwrap()
        .with_can_collide(&never);
    assert!(proximity(&config, &opts(1e-3)).unwrap().is_empty());
}

#[test]
fn bad_input_is_named() {
    let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    assert!(matches!(
        Configuration::new(&x, &[] as &[[u32; 3]], &[[0, 0]]),
        Err(ProximityError::EdgeRepeatedVertex { edge: 0, vertex: 0 })
    ));
    let nan = [[f64::NAN, 0.0, 0.0]];
    assert!(matches!(
        Configuration::new(&nan, &[] as &[[u32; 3]], &[]),
        Err(ProximityError::Input(_))
    ));
    let config = Configuration::new(&x, &[] as &[[u32; 3]], &[]).unwrap();
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let err = proximity(&config, &opts(bad)).unwrap_err();
        assert!(matches!(err, ProximityError::Dhat(_)), "{err}");
        assert!(err.to_string().starts_with("dhat must be finite and > 0"));
    }
    let o = ProximityOptions {
        dmin: -1.0,
        ..opts(1.0)
    };
    assert_eq!(proximity(&config, &o), Err(ProximityError::Dmin(-1.0)));
}

/// Positions, triangles, free edges.
type Soup = (Vec<[f64; 3]>, Vec<[u32; 3]>, Vec<[u32; 2]>);

/// A random soup in the unit cube: `nt` small triangles, `ne` free edges (some sharing
/// vertices: strands), `np` free points.
fn soup(seed: u64, nt: usize, ne: usize, np: usize) -> Soup {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut x = Vec::new();
    let p = |rng: &mut ChaCha8Rng| {
        [
            rng.random_range(0.0..1.0),
            rng.random_range(0.0..1.0),
            rng.random_range(0.0..1.0),
        ]
    };
    let mut tris = Vec::new();
    for _ in 0..nt {
        let c = p(&mut rng);
        let base = x.len() as u32;
        for _ in 0..3 {
            x.push([
                c[0] + rng.random_range(-0.05..0.05),
                c[1] + rng.random_range(-0.05..0.05),
                c[2] + rng.random_range(-0.05..0.05),
            ]);
        }
        tris.push([base, base + 1, base + 2]);
        // A neighbour sharing an edge.
        if rng.random_range(0..2) == 0 {
            x.push([
                c[0] + rng.random_range(-0.05..0.05),
                c[1] + rng.random_range(-0.05..0.05),
                c[2],
            ]);
            tris.push([base + 1, base, base + 3]);
        }
    }
    let mut edges = Vec::new();
    let mut last = None;
    for _ in 0..ne {
        let a = match last {
            Some(v) if rng.random_range(0..3) > 0 => v,
            _ => {
                x.push(p(&mut rng));
                x.len() as u32 - 1
            }
        };
        let q = x[a as usize];
        x.push([
            q[0] + rng.random_range(-0.06..0.06),
            q[1] + rng.random_range(-0.06..0.06),
            q[2] + rng.random_range(-0.06..0.06),
        ]);
        let b = x.len() as u32 - 1;
        edges.push([a, b]);
        last = Some(b);
    }
    // Some free edges along triangle sides (counted once) and a repeated one.
    if !tris.is_empty() {
        edges.push([tris[0][1], tris[0][0]]);
    }
    if let Some(&e) = edges.first() {
        edges.push(e);
    }
    for _ in 0..np {
        x.push(p(&mut rng));
    }
    (x, tris, edges)
}

#[test]
fn tree_equals_brute_force_on_soups() {
    let mut ccd = Ccd::new();
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let (mut ve, mut vv) = (0, 0);
    for seed in 0..6 {
        let (mut x, tris, edges) = soup(seed, 300, 200, 300);
        for (round, dhat) in [0.02, 0.05, 0.05, 0.1].into_iter().enumerate() {
            if round == 2 {
                // Move everything a little: the same primitives, refitted.
                let mut rng = ChaCha8Rng::seed_from_u64(seed + 100);
                for p in &mut x {
                    for c in p.iter_mut() {
                        *c += rng.random_range(-0.02..0.02);
                    }
                }
            }
            let config = Configuration::new(&x, &tris, &edges).unwrap();
            let brute = oracle(&config, dhat);
            let tree = two.install(|| ccd.proximity(&config, &opts(dhat)).unwrap());
            // Built first; refitted after a small move (a wider dhat may loosen it enough to
            // be rebuilt).
            if round < 3 {
                assert_eq!(tree.stats.refitted, round > 0, "seed {seed} round {round}");
            }
            assert_eq!(pairs(&tree), pairs(&brute), "seed {seed} dhat {dhat}");
            let single = one.install(|| Ccd::new().proximity(&config, &opts(dhat)).unwrap());
            assert_eq!(pairs(&single), pairs(&tree));
            assert!(
                brute.vf.len() > 10 && brute.ee.len() > 10,
                "seed {seed}: {} {}",
                brute.vf.len(),
                brute.ee.len()
            );
            ve += brute.ve.len();
            vv += brute.vv.len();
            // Every pair is within the threshold (plus the bound) by the kernels themselves.
            assert!(brute.vf.iter().all(|p| p.distance < dhat * (1.0 + 1e-9)));
        }
    }
    assert!(
        ve > 10 && vv > 10,
        "{ve} point-edge, {vv} point-point pairs"
    );
}

#[test]
fn max_contacts_and_deadline_truncate() {
    let (x, tris, edges) = soup(3, 300, 200, 300);
    let config = Configuration::new(&x, &tris, &edges).unwrap();
    let all = proximity(&config, &opts(0.05)).unwrap();
    assert!(all.truncated.is_none());
    let capped = ProximityOptions {
        max_contacts: Some(10),
        ..opts(0.05)
    };
    let r = proximity(&config, &capped).unwrap();
    assert_eq!(r.truncated, Some(StopReason::MaxContacts));
    assert_eq!(r.len(), 10);
    let again = proximity(&config, &capped).unwrap();
    assert_eq!(pairs(&again), pairs(&r));
    let late = ProximityOptions {
        deadline: Some(std::time::Instant::now()),
        ..opts(0.05)
    };
    let r = proximity(&config, &late).unwrap();
    assert_eq!(r.truncated, Some(StopReason::Deadline));
    assert!(r.len() < all.len());
}

#[test]
fn refit_follows_big_moves_and_topology_changes() {
    let mut ccd = Ccd::new();
    let (x, tris, edges) = soup(9, 200, 100, 100);
    let config = Configuration::new(&x, &tris, &edges).unwrap();
    let first = ccd.proximity(&config, &opts(0.05)).unwrap();
    assert!(!first.stats.refitted);
    // Mirrored: the same primitives far from where the tree was built.
    let mirrored: Vec<[f64; 3]> = x.iter().map(|p| [1.0 - p[0], p[2], p[1]]).collect();
    let config = Configuration::new(&mirrored, &tris, &edges).unwrap();
    let r = ccd.proximity(&config, &opts(0.05)).unwrap();
    let brute = oracle(&config, 0.05);
    assert_eq!(pairs(&r), pairs(&brute));
    // Other triangles: derived again, rebuilt.
    let fewer = &tris[..100];
    let config = Configuration::new(&mirrored, fewer, &edges).unwrap();
    let r = ccd.proximity(&config, &opts(0.05)).unwrap();
    assert!(!r.stats.refitted);
    let brute = oracle(&config, 0.05);
    assert_eq!(pairs(&r), pairs(&brute));
}

#[test]
fn candidates_kept_across_small_moves_equal_the_oracle() {
    // A solver's iterations: the positions move by shrinking fractions of a step, then by a
    // big one. A kept Ccd lists its candidates with a margin once it has seen a move, and
    // evaluates them again while the positions stay within it: the same pairs as the oracle.
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let (mut reused, mut traversed) = (0, 0);
    for seed in 0..4 {
        let (x0, tris, edges) = soup(seed, 300, 200, 300);
        let mut rng = ChaCha8Rng::seed_from_u64(seed + 200);
        let x1: Vec<[f64; 3]> = (x0.iter())
            .map(|p| p.map(|c| c + rng.random_range(-0.05..0.05)))
            .collect();
        let mut ccd = Ccd::new();
        let dhat = 0.04;
        let mut x = x0.clone();
        for alpha in [0.1, 0.3, 0.05, 0.01, 0.002, 0.0, 0.9, 0.001] {
            let config = Configuration::new(&x, &tris, &edges).unwrap();
            let brute = oracle(&config, dhat);
            let kept = one.install(|| ccd.proximity(&config, &opts(dhat)).unwrap());
            assert_eq!(pairs(&kept), pairs(&brute), "seed {seed} alpha {alpha}");
            if kept.stats.reused {
                reused += 1;
            } else {
                traversed += 1;
            }
            for (p, q) in x.iter_mut().zip(&x1) {
                for k in 0..3 {
                    p[k] += alpha * (q[k] - p[k]);
                }
            }
        }
        // A cap or a deadline never takes the kept candidates.
        let config = Configuration::new(&x, &tris, &edges).unwrap();
        let capped = ccd
            .proximity(
                &config,
                &ProximityOptions {
                    max_contacts: Some(5),
                    ..opts(dhat)
                },
            )
            .unwrap();
        assert!(!capped.stats.reused && capped.len() == 5);
    }
    assert!(
        reused >= 8 && traversed >= 8,
        "{reused} reused, {traversed} traversed"
    );
}

#[test]
fn a_kept_ccd_after_random_moves_equals_the_oracle() {
    // A kept Ccd through seeded random moves of every size against the threshold: none,
    // tiny, below and near the listing's cap (a quarter of dhat), about dhat and far beyond,
    // shrinking, growing and returning. Whether it lists, evaluates a listing or traverses
    // plainly, its report is the oracle's, on one thread and on two (the same pairs).
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let dhat = 0.04;
    let (mut reused, mut traversed) = (0, 0);
    for seed in 0..5 {
        let (x0, tris, edges) = soup(seed + 40, 250, 150, 200);
        let mut rng = ChaCha8Rng::seed_from_u64(seed + 300);
        let (mut kept1, mut kept2) = (Ccd::new(), Ccd::new());
        let mut x = x0.clone();
        for query in 0..24 {
            let config = Configuration::new(&x, &tris, &edges).unwrap();
            let brute = oracle(&config, dhat);
            let a = one.install(|| kept1.proximity(&config, &opts(dhat)).unwrap());
            let b = two.install(|| kept2.proximity(&config, &opts(dhat)).unwrap());
            assert_eq!(pairs(&a), pairs(&brute), "seed {seed} query {query}");
            assert_eq!(pairs(&b), pairs(&a), "seed {seed} query {query}");
            assert_eq!(a.stats.reused, b.stats.reused);
            if a.stats.reused {
                reused += 1;
            } else {
                traversed += 1;
            }
            // The next move: its largest coordinate step, as a fraction of dhat, from a
            // random pattern (kept a few queries, so that moves repeat and shrink).
            let scale = match (query / 3 + seed as usize) % 6 {
                0 => 0.0,
                1 => 1e-3,
                2 => 0.1,
                3 => 0.25,
                4 => 1.0,
                _ => 5.0,
            };
            let back = rng.random_range(0..4) == 0;
            for (p, q) in x.iter_mut().zip(&x0) {
                for k in 0..3 {
                    if back {
                        p[k] = q[k];
                    } else {
                        p[k] += scale * dhat * rng.random_range(-1.0..1.0);
                    }
                }
            }
        }
    }
    assert!(
        reused >= 10 && traversed >= 10,
        "{reused} reused, {traversed} traversed"
    );
}

#[test]
fn a_kept_ccd_does_not_list_after_a_first_or_growing_move() {
    // A listing (a wider traversal) only when the last move says it would pay: the first
    // move, and a move larger than the last, are traversed with the query's own boxes (as
    // many distance tests as a fresh Ccd); a move no larger than the last lists, and the
    // next query within it reuses the listing.
    let (x0, tris, edges) = soup(7, 300, 200, 300);
    let dhat = 0.04;
    let shifted = |s: f64| -> Vec<[f64; 3]> {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        (x0.iter())
            .map(|p| p.map(|c| c + s * dhat * rng.random_range(-1.0..1.0)))
            .collect()
    };
    let mut ccd = Ccd::new();
    let tests_fresh = |x: &[[f64; 3]]| {
        let config = Configuration::new(x, &tris, &edges).unwrap();
        proximity(&config, &opts(dhat))
            .unwrap()
            .stats
            .distance_tests
    };
    let mut ask = |x: &[[f64; 3]]| {
        let config = Configuration::new(x, &tris, &edges).unwrap();
        let r = ccd.proximity(&config, &opts(dhat)).unwrap();
        assert_eq!(pairs(&r), pairs(&oracle(&config, dhat)));
        r.stats
    };
    let (x1, x2, x3) = (shifted(0.1), shifted(0.25), shifted(0.15));
    ask(&x0);
    // The first move, then a growing one: no listing.
    let s = ask(&x1);
    assert!(!s.reused && s.distance_tests == tests_fresh(&x1));
    let s = ask(&x2);
    assert!(!s.reused && s.distance_tests == tests_fresh(&x2));
    // Back by a smaller move (0.1 against the last 0.15, per unit of the random pattern):
    // listed (more tests than a fresh query); then at x3 again and at x1 (0.05 from x3),
    // within the allowance: reused.
    let s = ask(&x3);
    assert!(!s.reused && s.distance_tests > tests_fresh(&x3));
    assert!(ask(&x3).reused);
    assert!(ask(&x1).reused);
}

/// The report of `method` at `config`.
fn with_method(config: &Configuration<'_>, dhat: f64, method: ProximityMethod) -> ProximityReport {
    let o = ProximityOptions {
        method,
        ..opts(dhat)
    };
    proximity(config, &o).unwrap()
}

#[test]
fn feature_tree_equals_brute_force_and_the_triangle_tree() {
    // Seeded soups of every primitive kind, one and two threads, kept and refitted: the
    // feature tree's report is the oracle's and the triangle tree's, pair for pair.
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    for seed in 0..5 {
        let (mut x, tris, edges) = soup(seed + 60, 250, 150, 150);
        let mut kept = Ccd::new();
        for round in 0..3 {
            let config = Configuration::new(&x, &tris, &edges).unwrap();
            let dhat = 0.03;
            let brute = oracle(&config, dhat);
            let tri = with_method(&config, dhat, ProximityMethod::TriangleTree);
            let wide = kept.proximity(&config, &opts(dhat)).unwrap();
            let wide2 = two.install(|| with_method(&config, dhat, ProximityMethod::Bvh));
            assert_eq!(pairs(&wide), pairs(&brute), "seed {seed} round {round}");
            assert_eq!(pairs(&wide2), pairs(&brute), "seed {seed} round {round}");
            assert_eq!(pairs(&tri), pairs(&brute), "seed {seed} round {round}");
            // The same candidates: each met once, as by the triangle tree.
            assert_eq!(wide2.stats.distance_tests, tri.stats.distance_tests);
            assert!(brute.vf.len() > 5 && brute.ee.len() > 5);
            let mut rng = ChaCha8Rng::seed_from_u64(seed + 900);
            for p in &mut x {
                for c in p.iter_mut() {
                    *c += rng.random_range(-0.01..0.01);
                }
            }
        }
    }
}

#[test]
fn feature_tree_on_degenerate_input_equals_brute_force() {
    // A flat grid of unit squares (two triangles each) with a second grid exactly `d` above
    // it, so that many pairs sit at the threshold; coincident vertices (a duplicated sheet);
    // free edges along the grid lines; free points at grid vertices; and every vertex at one
    // point.
    let n = 6usize;
    let mut x = Vec::new();
    let mut tris = Vec::new();
    let sheet = |z: f64, x: &mut Vec<[f64; 3]>, tris: &mut Vec<[u32; 3]>| {
        let base = x.len() as u32;
        for j in 0..=n {
            for i in 0..=n {
                x.push([i as f64, j as f64, z]);
            }
        }
        let id = |i: usize, j: usize| base + (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    };
    let d = 0.25;
    sheet(0.0, &mut x, &mut tris);
    sheet(d, &mut x, &mut tris);
    sheet(d, &mut x, &mut tris); // coincident with the second
    let mut edges = Vec::new();
    for i in 0..n as u32 {
        let a = x.len() as u32;
        x.push([i as f64, -0.5, 0.0]);
        x.push([i as f64 + 1.0, -0.5, 0.0]);
        edges.push([a, a + 1]);
    }
    for i in 0..4 {
        x.push([i as f64, -0.5, d]);
    }
    for dhat in [d, d * (1.0 - 1e-12), d * (1.0 + 1e-12), 0.5, 1e-9] {
        let config = Configuration::new(&x, &tris, &edges).unwrap();
        let brute = oracle(&config, dhat);
        let wide = with_method(&config, dhat, ProximityMethod::Bvh);
        assert_eq!(pairs(&wide), pairs(&brute), "dhat {dhat}");
        let tri = with_method(&config, dhat, ProximityMethod::TriangleTree);
        assert_eq!(pairs(&tri), pairs(&brute), "dhat {dhat}");
    }
    assert!(!oracle(&Configuration::new(&x, &tris, &edges).unwrap(), d)
        .vf
        .is_empty());
    // Every vertex at one point: every non-adjacent pair is at distance zero.
    let (x, tris, edges) = soup(5, 20, 10, 10);
    let one: Vec<[f64; 3]> = x.iter().map(|_| [0.5, 0.5, 0.5]).collect();
    let config = Configuration::new(&one, &tris, &edges).unwrap();
    let brute = oracle(&config, 1e-3);
    assert_eq!(
        pairs(&with_method(&config, 1e-3, ProximityMethod::Bvh)),
        pairs(&brute)
    );
    assert!(brute.len() > 100);
}

#[test]
fn a_capped_report_is_the_same_on_any_thread_count_and_part_of_the_whole() {
    // A soup big enough for many tasks of either tree. Under caps from one pair to beyond
    // the whole, each method's capped report is the same on one, two and three threads, holds
    // exactly the cap (or the whole when the cap exceeds it), says it is truncated when it
    // is, and every pair in it is in the uncapped report with the same distance and type.
    let pools: Vec<_> = (1..=3)
        .map(|n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        })
        .collect();
    let (x, tris, edges) = soup(77, 3000, 600, 600);
    let config = Configuration::new(&x, &tris, &edges).unwrap();
    let dhat = 0.02;
    let whole = pools[1].install(|| proximity(&config, &opts(dhat)).unwrap());
    assert!(whole.truncated.is_none());
    let n = whole.len();
    assert!(
        n > 20_000 && !whole.ee.is_empty() && !whole.vv.is_empty(),
        "{n} pairs"
    );
    let vf: std::collections::HashMap<_, _> = (whole.vf.iter())
        .map(|p| ((p.vertex, p.face), (p.distance, p.kind)))
        .collect();
    let ee: std::collections::HashMap<_, _> = (whole.ee.iter())
        .map(|p| ((p.a, p.b), (p.distance, p.kind)))
        .collect();
    let ve: std::collections::HashMap<_, _> = (whole.ve.iter())
        .map(|p| ((p.vertex, p.edge), (p.distance, p.kind)))
        .collect();
    let vv: std::collections::HashMap<_, _> = (whole.vv.iter())
        .map(|p| ((p.a, p.b), p.distance))
        .collect();
    for method in [ProximityMethod::Bvh, ProximityMethod::TriangleTree] {
        for cap in [1, 7, 1000, n / 3, n - 1, n + 1] {
            let o = ProximityOptions {
                method,
                max_contacts: Some(cap),
                ..opts(dhat)
            };
            let reports: Vec<_> = (pools.iter())
                .map(|p| p.install(|| proximity(&config, &o).unwrap()))
                .collect();
            let what = format!("{method:?}, cap {cap}");
            for r in &reports[1..] {
                assert_eq!(pairs(r), pairs(&reports[0]), "{what}");
            }
            let r = &reports[0];
            if cap < n {
                assert_eq!(r.len(), cap, "{what}");
                assert_eq!(r.truncated, Some(StopReason::MaxContacts), "{what}");
            } else {
                assert_eq!(pairs(r), pairs(&whole), "{what}");
            }
            for p in &r.vf {
                assert_eq!(
                    vf.get(&(p.vertex, p.face)),
                    Some(&(p.distance, p.kind)),
                    "{what}"
                );
            }
            for p in &r.ee {
                assert_eq!(ee.get(&(p.a, p.b)), Some(&(p.distance, p.kind)), "{what}");
            }
            for p in &r.ve {
                assert_eq!(
                    ve.get(&(p.vertex, p.edge)),
                    Some(&(p.distance, p.kind)),
                    "{what}"
                );
            }
            for p in &r.vv {
                assert_eq!(vv.get(&(p.a, p.b)), Some(&p.distance), "{what}");
            }
        }
    }
}

#[test]
fn a_task_gives_up_a_listing_at_its_cap_and_stops_at_its_pairs_cap() {
    use super::pairs::{list_cap, Found};
    // A listing at the cap is freed and marked, the pairs kept.
    let mut f = Found::default();
    f.cands.vf = vec![(0, 1); list_cap(10)];
    f.vf = vec![VfProximity {
        vertex: 0,
        face: 1,
        distance: 0.0,
        kind: PointTriangleType::Interior,
    }];
    assert!(!f.full(10, 0));
    assert!(f.unlisted && f.cands.len() == 0 && f.vf.len() == 1 && !f.capped);
    // So is one whose share with the other tasks' reaches it.
    let mut g = Found::default();
    g.cands.ee = vec![([0, 1], [2, 3]); 5];
    assert!(!g.full(10, list_cap(10) - 5));
    assert!(g.unlisted && g.cands.len() == 0);
    // Pairs at the cap stop the task.
    f.vf.resize(10, f.vf[0]);
    assert!(f.full(10, 0));
    assert!(f.capped);
}
