//! What the fuzz targets of `fuzz/` found, kept as tests: each case is the fuzzer's input (or
//! a smaller case built from it) with the answer now expected. See `fuzz/README.md`.

use std::path::Path;
use topoccd::io::{read_ply, read_ply_from, IoError};
use topoccd::math::DVec3;
use topoccd::narrow::{
    edge_edge, vertex_face, Certainty, EdgeEdge, NarrowOptions, Outcome, VertexFace,
};
use topoccd::{Ccd, Contact, Method, Mode, QueryOptions, Step};

fn p(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// The elementary test's input for vertex `v` against the face with corners `f`.
fn vf_query(x0: &[DVec3], x1: &[DVec3], v: usize, [f0, f1, f2]: [usize; 3]) -> VertexFace {
    VertexFace {
        v_t0: x0[v],
        f0_t0: x0[f0],
        f1_t0: x0[f1],
        f2_t0: x0[f2],
        v_t1: x1[v],
        f0_t1: x1[f0],
        f1_t1: x1[f1],
        f2_t1: x1[f2],
    }
}

/// `step` target: three triangles sharing the edge (4, 3), a non-manifold fan, with vertices
/// already touching the fan at t=0. Under `max_iterations = 1` the elementary test of
/// (vertex 0, face 2) cannot rule out a contact over [0, 1], so `Mode::All` reports it at
/// toi 0, but `Mode::Earliest` may first solve it over [0, 2 tolerance] after finding (1, 0) at
/// toi 0, where one iteration does rule it out: the two modes may name different contacts,
/// both at the earliest time 0, both conservative, and both marked `IterationLimit`. This was
/// the fuzz target's assumption, not a bug: at the default iteration limit both modes agree
/// exactly, and under a small limit Earliest names one of All's contacts.
#[test]
fn earliest_names_one_of_alls_contacts_under_an_iteration_limit() {
    let x0 = vec![
        p(-0.015625, -0.015625, -0.015625),
        p(-0.03125, -0.03125, -0.03125),
        p(-0.046875, -0.046875, -0.046875),
        p(-0.03125, -0.03125, -0.03125),
        p(-0.0625, -0.0625, -0.0625),
    ];
    let x1 = vec![
        p(-5.953125, -5.953125, -5.953125),
        p(-5.96875, -5.96875, -5.96875),
        p(-5.984375, -0.109375, -0.109375),
        p(2.59375, -5.96875, -5.96875),
        p(-0.0625, -6.0, -6.0),
    ];
    let step = Step::new(x0, x1, vec![[4, 3, 0], [4, 3, 1], [4, 3, 2]]).expect("valid step");
    let mut ccd = Ccd::new();
    for max_iterations in [1, 64, 1_000_000] {
        let mut options = QueryOptions::default();
        options.narrow.max_iterations = max_iterations;
        options.kdop = topoccd::kdop::DopKind::K6;
        let all = ccd.query(&step, Method::Bvh, &options).unwrap();
        assert_eq!(
            all.vf,
            ccd.query(&step, Method::Brute, &options).unwrap().vf
        );
        assert_eq!(all.earliest_toi(), Some(0.0), "{max_iterations}");
        options.mode = Mode::Earliest;
        for method in [Method::Bvh, Method::Brute] {
            let earliest = ccd.query(&step, method, &options).unwrap().earliest;
            let Some(Contact::Vf(c)) = earliest else {
                panic!("{max_iterations}: {earliest:?}");
            };
            assert!(
                all.vf.contains(&c),
                "{max_iterations}: {c:?} not in {:?}",
                all.vf
            );
            if max_iterations > 1 {
                assert_eq!(earliest, all.earliest, "{max_iterations}");
            } else {
                assert_eq!(c.certainty, Certainty::IterationLimit, "{c:?}");
            }
        }
    }
}

/// `step` target, after the batched prefilter: vertices 1 and 2 at 1e300 beside vertices near
/// the origin, all moving by (-7.875, -7.875, -7.875) (the huge coordinates do not move). The
/// elementary test cannot separate the edges of triangle (2, 1, 5) from those of the two small
/// triangles (its rounding bounds, from coordinates of 1e300, dwarf their gap), so over the whole
/// step it reported eight edge pairs at toi 0. In `Mode::Earliest` the per-step hierarchy first
/// sweeps its volumes over `[0, 1/256]` only, where those pairs' boxes are apart (vertex 5's
/// edges stay below y = -3 and the small edges above y = -1.2 until then): it never looked at
/// them, and reported 4 of All's 12 pairs at toi 0 where brute force and the cluster method
/// reported all 12. Now every method and mode search such a pair from `1/256`: the same pairs,
/// with the same times, everywhere, and none of the eight before `1/256`, which the positions
/// rule out by themselves (checked below from the coordinates, not by the library).
#[test]
fn pairs_the_first_pass_proves_apart_are_searched_from_its_end() {
    let big = 1e300;
    let x0 = vec![
        p(1.328125, -1.109375, 1.953125),
        p(big, 0.0, 10.25),
        p(0.0, -big, -big),
        p(1.3125, -1.125, 0.359375),
        p(1.296875, -1.140625, 0.34375),
        p(2.0625, -3.078125, -0.03125),
    ];
    let d = p(-7.875, -7.875, -7.875);
    let x1: Vec<DVec3> = x0.iter().map(|&a| a + d).collect();
    assert_eq!(x1[1], p(big, -7.875, 2.375));
    let tris = vec![[3, 4, 0], [1, 3, 0], [2, 1, 5]];
    let step = Step::new(x0.clone(), x1.clone(), tris).expect("valid step");
    let tau = 1.0 / 256.0;
    let mut ccd = Ccd::new();
    let all = ccd
        .query(&step, Method::Brute, &QueryOptions::default())
        .unwrap();
    assert_eq!(all.earliest_toi(), Some(0.0));
    assert_eq!((all.vf.len(), all.ee.len()), (5, 9));
    // The coordinate ranges of an edge over [0, tau], from the positions (each coordinate of a
    // vertex moves linearly, so its range is between its values at 0 and tau).
    let range = |[i, j]: [u32; 2], k: usize| {
        let ends = [i, j].map(|v| {
            let a = x0[v as usize][k];
            [a, a + tau * d[k]]
        });
        let all = ends.as_flattened();
        (
            all.iter().copied().fold(f64::MAX, f64::min),
            all.iter().copied().fold(f64::MIN, f64::max),
        )
    };
    // Eight of the twelve pairs are apart by more than a half along some axis over [0, tau]
    // (vertex 5's edges against the small triangles, and edge (1, 3) against (2, 5)): none of
    // them may be reported before tau. The other one touches at t=0 (up to rounding at 1e300).
    // (Three more edge pairs were reported at t=0, and two fewer vertex-face pairs, before the
    // solver scaled its differences near 1, issue 43: its cubes of 1e300 overflowed.)
    let mut apart = 0;
    for c in &all.ee {
        let gap = (0..3)
            .map(|k| {
                let ((a0, a1), (b0, b1)) = (range(c.a, k), range(c.b, k));
                (b0 - a1).max(a0 - b1)
            })
            .fold(f64::MIN, f64::max);
        if gap > 0.5 {
            assert!(c.toi >= tau, "{c:?} reported before the positions allow");
            apart += 1;
        } else {
            assert_eq!(c.toi, 0.0, "{c:?}");
        }
    }
    assert_eq!(apart, 8);
    for method in [Method::Bvh, Method::Cluster] {
        let other = ccd.query(&step, method, &QueryOptions::default()).unwrap();
        assert_eq!((&other.vf, &other.ee), (&all.vf, &all.ee), "{method}");
    }
    let options = QueryOptions {
        mode: Mode::Earliest,
        ..QueryOptions::default()
    };
    let cut = |c: f64| c <= options.narrow.tolerance;
    for method in [Method::Bvh, Method::Brute, Method::Cluster] {
        let earliest = ccd.query(&step, method, &options).unwrap();
        assert_eq!(earliest.earliest, all.earliest, "{method}");
        let vf: Vec<_> = all.vf.iter().filter(|c| cut(c.toi)).copied().collect();
        let ee: Vec<_> = all.ee.iter().filter(|c| cut(c.toi)).copied().collect();
        assert_eq!((earliest.vf, earliest.ee), (vf, ee), "{method}");
    }
}

/// `step` target, after `Method::Cluster` joined it: six triangles on the edge (7, 8), two of
/// them the same triangle (1 and 5, flipped), most vertices touching at t=0. Under
/// `max_iterations = 1` brute force (and the BVH) report (vertex 4, face 5) at toi 0, a pair
/// one iteration cannot resolve; the cluster method skips it, as its certificate proves that
/// features of one intermediate cluster sharing no vertex never touch. With 64 iterations the
/// elementary test rules the pair out as well and all methods agree. Not a bug: under a small
/// iteration limit the cluster method reports a subset of brute force's contacts; at the
/// default limit, the same.
#[test]
fn cluster_skips_an_unresolved_pair_its_certificate_rules_out() {
    let x0 = vec![
        p(0.0, 0.0, 0.0),
        p(0.0, 0.0, 0.0),
        p(0.0, 0.0, 0.0),
        p(-0.015625, -0.015625, -0.015625),
        p(-0.03125, -0.03125, -0.03125),
        p(-0.015625, -0.015625, -0.140625),
        p(-0.03125, -0.03125, -0.03125),
        p(-0.015625, -0.015625, -0.015625),
        p(-0.03125, -0.03125, -1.5),
    ];
    let x1 = vec![
        p(-5.9375, -5.9375, -0.0625),
        p(0.0, -0.0625, 2.0625),
        p(-0.3125, 0.0, 0.0),
        p(-5.953125, -5.953125, -0.078125),
        p(-0.03125, -0.09375, 2.03125),
        p(-0.328125, -0.015625, -0.140625),
        p(-5.96875, -5.96875, -0.09375),
        p(-0.015625, -0.078125, 2.046875),
        p(-0.34375, -0.03125, -1.5),
    ];
    let triangles = vec![
        [7, 8, 0],
        [7, 8, 1],
        [7, 8, 2],
        [7, 8, 3],
        [7, 8, 4],
        [8, 7, 1],
    ];
    let step = Step::new(x0, x1, triangles).expect("valid step");
    let mut ccd = Ccd::new();
    for max_iterations in [1, 64, 1_000_000] {
        let mut options = QueryOptions::default();
        options.narrow.max_iterations = max_iterations;
        options.kdop = topoccd::kdop::DopKind::K6;
        let brute = ccd.query(&step, Method::Brute, &options).unwrap();
        let bvh = ccd.query(&step, Method::Bvh, &options).unwrap();
        assert_eq!(
            (&bvh.vf, &bvh.ee),
            (&brute.vf, &brute.ee),
            "{max_iterations}"
        );
        let cluster = ccd.query(&step, Method::Cluster, &options).unwrap();
        assert_eq!(ccd.validate_tree(&step), Ok(()));
        let unresolved = brute.vf.iter().any(|c| (c.vertex, c.face) == (4, 5));
        assert_eq!(unresolved, max_iterations == 1, "{max_iterations}");
        assert!(!cluster.vf.iter().any(|c| (c.vertex, c.face) == (4, 5)));
        if max_iterations == 1 {
            assert_eq!(cluster.vf.len() + 1, brute.vf.len());
            assert!(cluster.vf.iter().all(|c| brute.vf.contains(c)));
            assert_eq!(cluster.ee, brute.ee);
        } else {
            assert_eq!((&cluster.vf, &cluster.ee), (&brute.vf, &brute.ee));
            assert_eq!(cluster.earliest, brute.earliest);
        }
    }
}

/// `step` target, at the default iteration limit with the tolerance 0.5: vertex 4 passes the
/// plane of face 2 once, at t = 0.0687, 0.16% of the face's size outside its edge (6, 0) (in
/// exact arithmetic, the coplanarity polynomial is 11362960 t^2 + 1554248 t - 160395 over
/// 2^17, and there the vertex's barycentric coordinates on the edges from corner 7 sum to
/// 1.0016); edge (0, 4) meets the line of edge (6, 7) at the same time, which is when the four
/// points are coplanar, 0.4% of its length beyond vertex 6 (and 2.47 lengths along its own
/// line, beyond vertex 4). Within the tolerance of 0.5 in the features' parameters the
/// elementary test cannot tell these from touches, and brute force and the BVH report both
/// pairs at toi 0, `Resolved`; the cluster method's certificate proves that features of one
/// intermediate cluster never touch, and it skips them. So the cluster method reports brute force's contacts but for
/// near misses (and unresolved pairs) inside its clusters; with its certificates distrusted,
/// exactly brute force's. The fuzz target had assumed equality at the default iteration limit.
#[test]
fn cluster_skips_a_near_miss_its_certificate_rules_out() {
    let (o, c, q) = (
        p(0.0, 0.0, 0.0),
        p(-0.015625, -1.6875, -1.109375),
        p(1.328125, 1.328125, 1.328125),
    );
    let x0 = vec![o, o, c, c, c, q, p(-0.03125, -3.296875, -2.71875), q, o];
    let x1 = vec![
        p(-6.4375, 5.875, -6.4375),
        p(-6.3125, 7.6875, 0.0),
        p(-6.453125, -8.125, -7.546875),
        c,
        p(-6.453125, 4.1875, -7.546875),
        p(-4.984375, 9.015625, 1.328125),
        p(-6.46875, -9.734375, -9.15625),
        q,
        p(-6.4375, 5.875, -6.4375),
    ];
    // The vertex and the face's corners at t: where the vertex crosses the face's plane, and
    // its barycentric coordinates there (on the edges from corner 7 to 6 and to 0).
    let at = |i: usize, t: f64| x0[i] + (x1[i] - x0[i]) * t;
    let plane = |t: f64| {
        let (a, b, c, v) = (at(7, t), at(6, t), at(0, t), at(4, t));
        (b - a).cross(c - a).dot(v - a)
    };
    let samples: Vec<f64> = (0..=1000).map(|i| plane(i as f64 / 1000.0)).collect();
    let crossings: Vec<usize> = (0..1000)
        .filter(|&i| (samples[i] < 0.0) != (samples[i + 1] < 0.0))
        .collect();
    assert_eq!(
        crossings,
        vec![68],
        "one crossing, between t = 0.068 and 0.069"
    );
    let (mut lo, mut hi) = (0.068, 0.069);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if (plane(mid) < 0.0) == (plane(lo) < 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (a, b, c, v) = (at(7, lo), at(6, lo), at(0, lo), at(4, lo));
    let (e1, e2, w) = (b - a, c - a, v - a);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = d11 * d22 - d12 * d12;
    let s = (d22 * e1.dot(w) - d12 * e2.dot(w)) / det;
    let u = (d11 * e2.dot(w) - d12 * e1.dot(w)) / det;
    assert!(
        s > 0.0 && u > 0.0 && s + u > 1.0015,
        "outside the face: {s} + {u}"
    );
    // The lines of edges (0, 4) and (6, 7) at that time: where they meet, on each.
    let (p1, d1, p2, d2) = (
        at(0, lo),
        at(4, lo) - at(0, lo),
        at(6, lo),
        at(7, lo) - at(6, lo),
    );
    let r = p1 - p2;
    let (a, b, e) = (d1.dot(d1), d1.dot(d2), d2.dot(d2));
    let det = a * e - b * b;
    let along1 = (b * d2.dot(r) - e * d1.dot(r)) / det;
    let along2 = (a * d2.dot(r) - b * d1.dot(r)) / det;
    assert!(
        along1 > 2.0 && along2 < -0.004,
        "outside both edges: {along1}, {along2}"
    );
    assert!(
        (p1 + d1 * along1 - (p2 + d2 * along2)).length() < 1e-9,
        "the lines meet"
    );

    let step = Step::new(
        x0.clone(),
        x1.clone(),
        vec![
            [6, 4, 0],
            [5, 3, 2],
            [7, 6, 0],
            [7, 6, 1],
            [7, 6, 2],
            [5, 3, 2],
        ],
    )
    .expect("valid step");
    let mut options = QueryOptions::default();
    options.narrow.tolerance = 0.5;
    options.kdop = topoccd::kdop::DopKind::K6;
    let mut ccd = Ccd::new();
    let brute = ccd.query(&step, Method::Brute, &options).unwrap();
    let bvh = ccd.query(&step, Method::Bvh, &options).unwrap();
    assert_eq!((&bvh.vf, &bvh.ee), (&brute.vf, &brute.ee));
    let near = |c: &&topoccd::VfContact| (c.vertex, c.face) == (4, 2);
    let reported: Vec<_> = brute.vf.iter().filter(near).collect();
    assert_eq!(reported.len(), 1);
    assert_eq!(
        (reported[0].toi, reported[0].certainty),
        (0.0, Certainty::Resolved)
    );
    let near_ee = |c: &&topoccd::EeContact| (c.a, c.b) == ([0, 4], [6, 7]);
    assert_eq!(brute.ee.iter().filter(near_ee).count(), 1);
    let cluster = ccd.query(&step, Method::Cluster, &options).unwrap();
    let vf: Vec<_> = brute.vf.iter().filter(|c| !near(c)).copied().collect();
    let ee: Vec<_> = brute.ee.iter().filter(|c| !near_ee(c)).copied().collect();
    assert_eq!((&cluster.vf, &cluster.ee), (&vf, &ee));
    ccd.distrust_certificates(true);
    let distrusted = ccd.query(&step, Method::Cluster, &options).unwrap();
    assert_eq!((&distrusted.vf, &distrusted.ee), (&brute.vf, &brute.ee));
    // At the default tolerance the elementary test rules the pair out: all methods agree.
    options.narrow.tolerance = QueryOptions::default().narrow.tolerance;
    ccd.distrust_certificates(false);
    let brute = ccd.query(&step, Method::Brute, &options).unwrap();
    assert!(!brute.vf.iter().any(|c| near(&c)) && !brute.ee.iter().any(|c| near_ee(&c)));
    let cluster = ccd.query(&step, Method::Cluster, &options).unwrap();
    assert_eq!((&cluster.vf, &cluster.ee), (&brute.vf, &brute.ee));
}

/// `step` target, at the default iteration limit: two vertices at y = 6.8e298 beside vertices
/// within 5 of the origin. Brute force and the BVH report (vertex 0, face 1) at toi 0 as a
/// contact they could not resolve over [0, 1] (`IterationLimit`, the earliest by the order
/// of contacts), and the edges (0, 1) and (2, 3) at toi 0, `Resolved`. The BVH's
/// `Mode::Earliest` finds the edges' contact first and then solves (0, face 1) over the
/// shorter interval up to the tolerance, where it is ruled out: its report names the edges
/// (brute force's and the cluster method's Earliest meet the vertex-face pair first and keep
/// it). Both are conservative and give the earliest time 0. So Earliest reports All's
/// contacts within the tolerance of the earliest where All resolved them; a pair All gave up
/// on it may leave out, depending on the order in which it meets the pairs. (Since the solver
/// scales its differences near 1, issue 43, its cubes of 6.8e298 no longer overflow: All
/// resolves (0, face 1) at 0, every method's Earliest keeps it, and (2, face 0) is resolved at
/// 1/256, after the earliest time.)
#[test]
fn earliest_may_leave_out_a_pair_all_gave_up_on() {
    let far = 6.803609974008846e298;
    let x0 = vec![
        p(-0.015625, -0.015625, -0.015625),
        p(-0.03125, -0.03125, -0.03125),
        p(-0.046875, -0.046875, -0.046875),
        p(0.0, far, -1.2338788307466547e-178),
        p(-1.90625, far, -1.96875),
    ];
    let x1 = vec![
        p(-0.078125, -0.078125, -4.078125),
        p(2.28125, -0.09375, -0.21875),
        p(-0.109375, -0.109375, -0.109375),
        p(-0.0625, far, -0.0625),
        p(-1.96875, far, -2.03125),
    ];
    let step = Step::new(x0, x1, vec![[0, 1, 4], [2, 3, 1]]).expect("valid step");
    let mut options = QueryOptions {
        kdop: topoccd::kdop::DopKind::K26,
        ..QueryOptions::default()
    };
    let mut ccd = Ccd::new();
    let brute = ccd.query(&step, Method::Brute, &options).unwrap();
    let Some(Contact::Vf(first)) = brute.earliest else {
        panic!("{:?}", brute.earliest);
    };
    assert_eq!((first.vertex, first.face, first.toi), (0, 1, 0.0));
    assert_eq!(first.certainty, Certainty::Resolved);
    let edges = brute.ee.iter().find(|c| (c.a, c.b) == ([0, 1], [2, 3]));
    assert!(edges.is_some_and(|c| c.toi == 0.0 && c.certainty == Certainty::Resolved));
    options.mode = Mode::Earliest;
    for method in [Method::Brute, Method::Bvh, Method::Cluster] {
        let earliest = ccd.query(&step, method, &options).unwrap();
        assert_eq!(earliest.earliest_toi(), Some(0.0), "{method}");
        assert!(earliest.vf.iter().all(|c| brute.vf.contains(c)), "{method}");
        assert!(earliest.ee.iter().all(|c| brute.ee.contains(c)), "{method}");
        // What Earliest leaves out of All's contacts at toi 0 are pairs All gave up on.
        for c in brute
            .vf
            .iter()
            .filter(|c| c.toi == 0.0 && !earliest.vf.contains(c))
        {
            assert_eq!(c.certainty, Certainty::IterationLimit, "{method}: {c:?}");
        }
        for c in brute
            .ee
            .iter()
            .filter(|c| c.toi == 0.0 && !earliest.ee.contains(c))
        {
            assert_eq!(c.certainty, Certainty::IterationLimit, "{method}: {c:?}");
        }
        // Resolved by All since the solver scales its differences (issue 43): every method's
        // Earliest keeps it now, the BVH's too.
        assert!(
            earliest.vf.contains(&first),
            "{method}: which pair came first"
        );
    }
}

/// `step` target, a slow unit (86 s under the address sanitizer, 1.5 s in a release build,
/// for 12 feature pairs): three triangles on an edge with one end at y = z = -1e300 while the
/// other vertices stay within 10 of the origin. The differences are within the solver's range
/// (`MAX_DIFFERENCE`), but spanning 300 orders of magnitude half the pairs could not be
/// resolved: each ran to the iteration limit (hundreds of milliseconds at the default 10^6) and
/// was reported as a conservative contact. Since the solver scales its differences near 1
/// (issue 43, `range::normalizing_scale`) its cubes no longer overflow and every pair is
/// isolated, at its exact time 0. Kept at a small limit so the test stays fast; what must
/// hold is that every pair is reported, identically by every method, at a time in [0, 1].
#[test]
fn mixed_scales_exhaust_the_iteration_limit_and_stay_conservative() {
    let x0 = vec![
        p(0.0, -1e300, -1e300),
        p(0.890625, -0.03125, 0.171875),
        p(0.0, 0.0, 0.0),
        p(0.0, 0.0, 0.0),
        p(0.0, 0.0, 0.0),
    ];
    let x1 = vec![
        p(-2.875, -1e300, -1e300),
        p(-5.046875, -5.96875, -5.765625),
        p(-2.875, 6.5, -7.0625),
        p(7.6875, 0.0, 0.0),
        p(2.0625, -0.0625, -5.9375),
    ];
    let step = Step::new(x0, x1, vec![[0, 1, 2], [0, 1, 3], [0, 1, 4]]).expect("valid step");
    let mut options = QueryOptions::default();
    options.narrow.max_iterations = 10_000;
    options.narrow.min_distance = 1e-6;
    let mut ccd = Ccd::new();
    let brute = ccd.query(&step, Method::Brute, &options).unwrap();
    assert_eq!((brute.stats.vf_tests, brute.stats.ee_tests), (6, 6));
    assert_eq!(
        (brute.vf.len(), brute.ee.len()),
        (6, 6),
        "every pair is a contact"
    );
    for c in &brute.vf {
        assert!((0.0..=1.0).contains(&c.toi), "{c:?}");
    }
    for method in [Method::Bvh, Method::Cluster] {
        let report = ccd.query(&step, method, &options).unwrap();
        assert_eq!((&report.vf, &report.ee), (&brute.vf, &brute.ee), "{method}");
    }
    // Three of the six vertex-face pairs gave up at the iteration limit while the solver's
    // cubes of 1e300 overflowed; with its differences scaled near 1 (issue 43), every pair is
    // isolated.
    let (x0, x1) = (step.pos0(), step.pos1());
    let mut certainties = Vec::new();
    for c in &brute.vf {
        let face = step.triangles()[c.face as usize].map(|i| i as usize);
        let q = vf_query(x0, x1, c.vertex as usize, face);
        match vertex_face(&q, &options.narrow) {
            Outcome::Contact { toi, certainty } => {
                assert_eq!(toi, c.toi);
                certainties.push(certainty);
            }
            Outcome::Separated => panic!("{c:?}"),
        }
    }
    // Each is exact: vertices 2, 3 and 4 coincide at t=0, and each pair's vertex sits on the
    // face's corner among them, so the pair touches at 0.
    assert!(
        certainties.iter().all(|c| *c == Certainty::Resolved),
        "{certainties:?}"
    );
    assert!(brute.vf.iter().all(|c| c.toi == 0.0), "{:?}", brute.vf);
}

/// `step` target (6-DOPs, the default tolerance and iteration limit): vertex 1 starts at the
/// origin and rises; face 11 = (3, 7, 2) has its corner 7 at z = -2.4e-185 and its other
/// corners far below, so the plane z = -1.2e-185 separates them during the whole step. The
/// elementary test cannot tell a gap of 1e-185 beside coordinates of 1 from a touch and
/// reports a contact at toi 0; `Mode::All` never asks it, since the features' boxes over the
/// whole step (exact) are apart. The per-step hierarchy's first pass in `Mode::Earliest`
/// sweeps the boxes over `[0, tmax / 256]`, padded for the rounding of the positions at its
/// end, which closes the gap: it asked the elementary test and reported the pair, a contact
/// that All does not report. Now the first pass keeps only contacts of pairs All looks at, and
/// Earliest reports exactly All's contacts within the tolerance of the earliest.
#[test]
fn earliest_reports_no_pair_all_leaves_out() {
    let (o, c) = (p(0.0, 0.0, 0.0), p(-0.015625, 1.0, -1.109375));
    let a = p(6.952545964187599e-284, 0.0, -2.3902098226829796e-185);
    let x0 = vec![o, o, c, c, c, p(1.5625, 1.59375, -0.015625), a, a, o];
    let x1 = vec![
        p(5.875, -6.4375, -6.3125),
        p(0.0, -0.0625, 7.6875),
        p(-6.453125, -5.4375, -7.546875),
        c,
        p(5.859375, -5.4375, -7.421875),
        p(1.5625, 1.53125, 7.671875),
        p(-6.4375, -6.4375, -6.4375),
        a,
        p(5.875, -6.4375, -6.3125),
    ];
    let tris = vec![
        [6, 4, 0],
        [6, 4, 1],
        [6, 4, 2],
        [6, 4, 3],
        [4, 3, 2],
        [7, 6, 0],
        [7, 6, 1],
        [7, 6, 2],
        [4, 5, 3],
        [3, 7, 0],
        [3, 7, 1],
        [3, 7, 2],
        [6, 4, 3],
    ];
    // Positions move linearly: the face stays below z = a.z / 2 and the vertex above it.
    let face = [3usize, 7, 2];
    let top = face
        .iter()
        .map(|&i| x0[i].z.max(x1[i].z))
        .fold(f64::MIN, f64::max);
    assert!(top < a.z / 2.0 && a.z / 2.0 < x0[1].z.min(x1[1].z));
    // The elementary test alone reports it.
    let options = QueryOptions {
        kdop: topoccd::kdop::DopKind::K6,
        ..QueryOptions::default()
    };
    let q = vf_query(&x0, &x1, 1, face);
    assert!(matches!(
        vertex_face(&q, &options.narrow),
        Outcome::Contact { toi, .. } if toi == 0.0
    ));
    let step = Step::new(x0, x1, tris).expect("valid step");
    let is_it = |c: &topoccd::VfContact| (c.vertex, c.face) == (1, 11);
    for method in [Method::Bvh, Method::Brute, Method::Cluster] {
        // A fresh `Ccd`: the per-step hierarchy makes its first pass.
        let mut ccd = Ccd::new();
        let all = ccd.query(&step, method, &options).unwrap();
        assert!(!all.vf.iter().any(is_it), "{method}");
        assert_eq!(all.unresolved, 0, "{method}");
        let earliest = ccd
            .query(
                &step,
                method,
                &QueryOptions {
                    mode: Mode::Earliest,
                    ..options
                },
            )
            .unwrap();
        assert!(!earliest.vf.iter().any(is_it), "{method}");
        // All resolved every contact: Earliest reports exactly its contacts within the
        // tolerance of the earliest (here all of them, at toi 0).
        let cut = all.earliest_toi().unwrap() + options.narrow.tolerance;
        let within = |t: f64| t <= cut;
        let vf: Vec<_> = all.vf.iter().filter(|c| within(c.toi)).copied().collect();
        let ee: Vec<_> = all.ee.iter().filter(|c| within(c.toi)).copied().collect();
        assert_eq!((earliest.vf, earliest.ee), (vf, ee), "{method}");
        assert_eq!(earliest.earliest, all.earliest, "{method}");
    }
}

/// `step` target (26-DOPs, tolerance 0.1, minimum separation 1e-6, the default iteration
/// limit): three triangles on the edge (9, 8). Edges (0, 8) and (1, 9) never come closer than
/// about 0.11, but within the tolerance of 0.1 in their parameters the elementary test over the
/// whole step cannot tell them from a touch, and `Mode::All` reports them at toi 0, `Resolved`.
/// `Mode::Earliest` of the cluster method, having found another pair at toi 0,
/// solves them over `[0, 2 tolerance]` first, rules them out there, and leaves them out: both answers are conservative, and
/// Earliest's, from the shorter search, is the sharper. The fuzz target had expected Earliest
/// to report exactly All's contacts within the tolerance of the earliest whenever All resolved
/// them all; what holds is that a pair Earliest leaves out is not touching by then.
#[test]
fn earliest_may_leave_out_a_near_miss_all_reports() {
    let x0 = vec![
        p(1.09375, 1.09375, 1.109375),
        p(1.15625, 1.078125, -0.484375),
        p(1.140625, 1.0625, -0.5),
        p(0.890625, 1.046875, -0.5),
        p(-0.296875, -0.328125, 0.03125),
    ];
    let x1 = vec![
        p(1.21875, 1.03125, 3.296875),
        p(1.09375, 5.890625, -6.109375),
        p(1.265625, 1.0, 1.6875),
        p(1.015625, 0.984375, 1.6875),
        p(-0.359375, 4.484375, -5.59375),
    ];
    // The fuzzer's vertices 0, 1, 2, 8 and 9 (the others belong to no triangle).
    let tris = vec![[4, 3, 0], [4, 3, 1], [4, 3, 2]];
    let (near_a, near_b) = ([0, 3], [1, 4]);
    let options = QueryOptions {
        kdop: topoccd::kdop::DopKind::K26,
        narrow: NarrowOptions {
            tolerance: 0.1,
            min_distance: 1e-6,
            ..NarrowOptions::default()
        },
        ..QueryOptions::default()
    };
    // With a tight tolerance the elementary test proves the edges apart over the whole step.
    let q = EdgeEdge {
        ea0_t0: x0[0],
        ea1_t0: x0[3],
        eb0_t0: x0[1],
        eb1_t0: x0[4],
        ea0_t1: x1[0],
        ea1_t1: x1[3],
        eb0_t1: x1[1],
        eb1_t1: x1[4],
    };
    let tight = NarrowOptions {
        tolerance: 1e-9,
        ..options.narrow
    };
    assert_eq!(edge_edge(&q, &tight), Outcome::Separated);
    let step = Step::new(x0, x1, tris).expect("valid step");
    let is_it = |c: &topoccd::EeContact| (c.a, c.b) == (near_a, near_b);
    for method in [Method::Bvh, Method::Brute, Method::Cluster] {
        let mut ccd = Ccd::new();
        let all = ccd.query(&step, method, &options).unwrap();
        assert_eq!(all.unresolved, 0, "{method}");
        let reported = all.ee.iter().find(|c| is_it(c)).copied();
        assert!(
            reported.is_some_and(|c| c.toi == 0.0),
            "{method}: {:?}",
            all.ee
        );
        let earliest_options = QueryOptions {
            mode: Mode::Earliest,
            ..options
        };
        let earliest = ccd.query(&step, method, &earliest_options).unwrap();
        assert_eq!(earliest.earliest_toi(), Some(0.0), "{method}");
        // Which pair a method meets first decides: brute force meets this one, and so does
        // the per-step hierarchy, which looks at neighbouring triangles (here all three pairs)
        // first, in the order of their shared vertices; the cluster method does not.
        let kept = earliest.ee.iter().any(is_it);
        assert_eq!(
            kept,
            method != Method::Cluster,
            "{method}: which pair came first"
        );
        // Everything else All reports at toi 0 is there, unchanged.
        for c in all.vf.iter().filter(|c| c.toi == 0.0) {
            assert!(earliest.vf.contains(c), "{method}: {c:?}");
        }
        for c in all.ee.iter().filter(|c| c.toi == 0.0 && !is_it(c)) {
            assert!(earliest.ee.contains(c), "{method}: {c:?}");
        }
        assert!(earliest.ee.iter().all(|c| all.ee.contains(c)), "{method}");
    }
}

/// `step` target (26-DOPs, the default tolerance and iteration limit): vertices 3, 4, 6, 7 and 8
/// stay at z = -1e300 while the others stay within 8 of the origin. Face 0 = (6, 4, 0) meets
/// the plane z = -1e300 only along its edge (6, 4) (corner 0 is 1e300 away), so vertex 3 can
/// touch it only there: in the plane, it crosses the line of that edge once, at t = 0.0624,
/// 0.81 of the way along the edge (checked below from the coordinates). Over the whole step the
/// elementary test cannot tell the pair from a touch at t = 0 (its rounding bounds, relative to
/// the 1e300 of the pair's coordinate differences, dwarf the gap of 0.78), and `Mode::All`
/// reports (3, face 0) at toi 0, `Resolved`: conservative, 0.0624 early. The BVH's
/// `Mode::Earliest` looks at the pair over a start of the step only (its first pass's 1/256,
/// or `[0, 2 tolerance]` once edge pairs at toi 0 are known), where its prefilter proves it
/// apart, and leaves it out (and (3, face 1), alike); brute force and the cluster method meet
/// it before any contact at toi 0, search it further and keep it. So the pairs Earliest may
/// leave out include one that grazes at scales this far apart and touches only later; what
/// holds is that it does not touch within the tolerance of the earliest time. The fuzz target
/// had expected exact agreement whenever All resolved every pair at the default tolerance.
/// (Since the solver scales its differences near 1, issue 43, the cluster method leaves the
/// pair out too; brute force keeps it.)
#[test]
fn earliest_may_leave_out_a_pair_that_grazes_at_mixed_scales() {
    let far = -1e300;
    let x0 = vec![
        p(1.09375, 1.09375, 1.109375),
        p(1.015625, 1.078125, -0.859375),
        p(0.921875, -0.609375, -0.0625),
        p(0.0, 0.0, far),
        p(-0.015625, -0.78125, far),
        p(1.078125, 1.078125, 1.09375),
        p(-0.015625, -0.84375, far),
        p(-1.59375, -1.453125, far),
        p(-1.609375, -1.46875, far),
    ];
    let x1 = vec![
        p(-5.34375, -5.34375, -5.328125),
        p(-5.421875, -5.359375, -7.359375),
        p(-5.515625, -7.046875, -6.5),
        p(-6.4375, -6.4375, far),
        p(-6.828125, 6.90625, far),
        p(-5.359375, -5.609375, 5.34375),
        p(-3.453125, -0.84375, far),
        p(-8.03125, -7.890625, far),
        p(-8.046875, -7.90625, far),
    ];
    let tris = vec![
        [6, 4, 0],
        [6, 4, 1],
        [6, 4, 2],
        [5, 3, 2],
        [7, 6, 0],
        [7, 6, 1],
        [7, 6, 2],
        [7, 6, 0],
    ];
    // In the plane z = -1e300, where vertices 3, 4 and 6 stay: `side(t)`, twice the signed area
    // of (6, 4, 3), is a quadratic in t with positive leading coefficient (a convex function),
    // computed exactly here (dyadic coordinates of few bits, t a power of two or zero).
    let at = |v: usize, t: f64| x0[v] + (x1[v] - x0[v]) * t;
    let side = |t: f64| {
        let (a, b, c) = (at(6, t), at(4, t), at(3, t));
        (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
    };
    let tau = 1.0 / 256.0;
    // Negative at 0 and at 1/256, so on all of [0, 1/256] (convexity): no contact there.
    assert!(side(0.0) < 0.0 && side(tau) < 0.0);
    // It changes sign before 1/16, vertex 3 then lying 0.81 along the edge: the pair touches.
    assert!(side(0.0625) > 0.0);
    let (a, b, c) = (at(6, 0.0624), at(4, 0.0624), at(3, 0.0624));
    let along = (c - a).truncate().dot((b - a).truncate()) / (b - a).truncate().length_squared();
    assert!((0.8..0.82).contains(&along), "{along}");
    // The elementary test alone cannot tell, even over [0, 1/256].
    let q = vf_query(&x0, &x1, 3, [6, 4, 0]);
    let short = NarrowOptions {
        tmax: tau,
        ..NarrowOptions::default()
    };
    assert!(matches!(
        vertex_face(&q, &short),
        Outcome::Contact { toi, certainty: Certainty::Resolved } if toi == 0.0
    ));
    let step = Step::new(x0, x1, tris).expect("valid step");
    let options = QueryOptions {
        kdop: topoccd::kdop::DopKind::K26,
        ..QueryOptions::default()
    };
    let grazes = |c: &topoccd::VfContact| c.vertex == 3 && [0, 1].contains(&c.face);
    for method in [Method::Bvh, Method::Brute, Method::Cluster] {
        let mut ccd = Ccd::new();
        let all = ccd.query(&step, method, &options).unwrap();
        assert_eq!(all.unresolved, 0, "{method}");
        let at_zero = all.vf.iter().filter(|c| grazes(c) && c.toi == 0.0);
        assert_eq!(at_zero.count(), 2, "{method}");
        let earliest_options = QueryOptions {
            mode: Mode::Earliest,
            ..options
        };
        let earliest = ccd.query(&step, method, &earliest_options).unwrap();
        assert_eq!(earliest.earliest_toi(), Some(0.0), "{method}");
        assert!(earliest.vf.iter().all(|c| all.vf.contains(c)), "{method}");
        assert!(earliest.ee.iter().all(|c| all.ee.contains(c)), "{method}");
        // Of All's contacts at toi 0, Earliest leaves out at most the two grazing pairs.
        for c in all.vf.iter().filter(|c| c.toi == 0.0 && !grazes(c)) {
            assert!(earliest.vf.contains(c), "{method}: {c:?}");
        }
        for c in all.ee.iter().filter(|c| c.toi == 0.0) {
            assert!(earliest.ee.contains(c), "{method}: {c:?}");
        }
        // Which pair a method meets first decides.
        let kept = earliest.vf.iter().filter(|c| grazes(c)).count();
        // (Since the solver scales its differences, issue 43, the cluster method leaves them
        // out as the BVH does.)
        let expected = if method == Method::Brute { 2 } else { 0 };
        assert_eq!(kept, expected, "{method}: which pair came first");
    }
}

/// `step` target: vertex 5 sits on corner 4 of face 0 at t=0, and both lie 4.7e104 away from
/// the face's other corners, near the origin. The contact's geometry took `inf - inf` in its
/// barycentric coordinates ([NaN, 1, NaN]), so a report did not even equal itself and every
/// comparison of two reports failed. The geometry is now computed on the points scaled by a
/// power of two: every contact of every method and mode has geometry without NaN, with
/// barycentric coordinates in [0, 1] that sum to 1 (this one [0, 1, 0], on the corner), and
/// the methods' reports are equal.
#[test]
fn a_far_corner_gives_geometry_without_nan() {
    let far = p(0.0, 12.0, 4.717169818218967e104);
    let x0 = vec![
        p(0.0, 0.0, 0.0),
        far,
        far,
        p(-0.015625, -0.015625, -0.015625),
        far,
        far,
        p(-0.015625, -0.015625, -0.015625),
        p(-1.625, -1.59375, -1.625),
        far,
    ];
    let z = far.z;
    let x1 = vec![
        p(5.875, -6.4375, -6.4375),
        p(-6.3125, 19.6875, z),
        p(-6.4375, 5.5625, z),
        p(-0.015625, -0.015625, -0.015625),
        p(5.875, 5.5625, z),
        p(-6.3125, 19.6875, z),
        p(-6.453125, -6.453125, -6.453125),
        p(-1.625, -1.59375, -1.625),
        p(5.875, 5.5625, z),
    ];
    let step = Step::new(x0, x1, vec![[6, 4, 0], [5, 7, 4]]).expect("valid step");
    let mut options = QueryOptions::default();
    options.narrow.tolerance = 0.1;
    options.narrow.tmax = 1.1125369292536007e-308;
    options.kdop = topoccd::kdop::DopKind::K26;
    options.geometry = true;
    let mut ccd = Ccd::new();
    for mode in [Mode::All, Mode::Earliest] {
        options.mode = mode;
        let brute = ccd.query(&step, Method::Brute, &options).unwrap();
        // (Since the solver scales its differences near 1, issue 43, (vertex 0, face 1) is a
        // contact at 0 too, earlier by the order of contacts: 2.3 apart, far within the
        // rounding of coordinates of 4.7e104, so conservative.)
        assert_eq!(brute.earliest_toi(), Some(0.0), "{mode:?}");
        let Some(c) = brute.vf.iter().find(|c| (c.vertex, c.face) == (5, 0)) else {
            panic!("{mode:?}: {:?}", brute.vf);
        };
        assert_eq!(c.toi, 0.0, "{mode:?}");
        let g = c.geometry.expect("geometry was asked for");
        assert_eq!(g.barycentric, [0.0, 1.0, 0.0], "{mode:?}");
        assert_eq!((g.point, g.distance), (far.to_array(), 0.0), "{mode:?}");
        for method in [Method::Brute, Method::Bvh, Method::Cluster] {
            let report = ccd.query(&step, method, &options).unwrap();
            assert_eq!(
                report,
                report.clone(),
                "{mode:?} {method}: NaN in the report"
            );
            assert_eq!(
                (&report.vf, &report.ee),
                (&brute.vf, &brute.ee),
                "{mode:?} {method}"
            );
            for c in &report.vf {
                let g = c.geometry.expect("geometry was asked for");
                assert!(
                    g.barycentric.iter().all(|b| (0.0..=1.0).contains(b)),
                    "{c:?}"
                );
                assert!(
                    (g.barycentric.iter().sum::<f64>() - 1.0).abs() < 1e-15,
                    "{c:?}"
                );
                assert!(
                    g.point.iter().chain(&g.normal).all(|x| x.is_finite()),
                    "{c:?}"
                );
            }
            for c in &report.ee {
                let g = c.geometry.expect("geometry was asked for");
                assert!((0.0..=1.0).contains(&g.a_param) && (0.0..=1.0).contains(&g.b_param));
                assert!(
                    g.point.iter().chain(&g.normal).all(|x| x.is_finite()),
                    "{c:?}"
                );
            }
        }
    }
}

/// `ply` target: a header line that quotes the name of the file the target wrote (the fuzzer
/// learnt it from the error messages). Read from bytes and from a file, the error must be the
/// same but for the file's name in front; the target had replaced the name everywhere, also
/// inside the quoted line. A fault of the target, kept to pin down that both ways agree.
#[test]
fn a_header_line_quoting_the_file_name_gives_the_same_error_from_bytes_and_file() {
    let bytes: &[u8] = b"ply\nformat binary_little_endian 1.0\ncomment hand-made\n\
        elopoccd-fuzz-24496fuzz.plyty double x double x\nprope\nproperty doubty float quality\n\
        element edge 1\nprope\x00\x00\x00\x00\x00\xf0?pl";
    let from_bytes = read_ply_from(bytes, Path::new("fuzz.ply")).expect_err("bad header");
    let path = std::env::temp_dir().join(format!(
        "topoccd-fuzz-regression-{}.ply",
        std::process::id()
    ));
    std::fs::write(&path, bytes).expect("write");
    let from_file = read_ply(&path).expect_err("bad header");
    std::fs::remove_file(&path).expect("remove");
    for e in [&from_bytes, &from_file] {
        assert!(
            matches!(e, IoError::PlyHeader { line: Some(4), .. }),
            "{e:?}"
        );
    }
    let quoted = ": invalid PLY header at line 4: Couldn't parse line in \
                  'elopoccd-fuzz-24496fuzz.plyty double x double x'";
    assert_eq!(from_bytes.to_string(), format!("fuzz.ply{quoted}"));
    assert_eq!(from_file.to_string(), format!("{}{quoted}", path.display()));
}
