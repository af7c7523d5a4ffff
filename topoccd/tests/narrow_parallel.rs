//! Nearly parallel coplanar edges in resting contact keep the documented bound on how early a
//! time of impact can be (`NarrowOptions::tolerance`): issue 38's two triangles, whose first
//! contact is computed exactly here, and a family like them with dyadic coordinates.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use topoccd::pair::{edge_edge, EdgeEdge, Outcome};
use topoccd::{query, Method, NarrowOptions, QueryOptions, Step};

/// `x` as `m 2^e` exactly (finite `x`).
fn dyadic(x: f64) -> (i128, i32) {
    let bits = x.to_bits();
    let sign = if bits >> 63 == 0 { 1 } else { -1 };
    let exp = ((bits >> 52) & 0x7ff) as i32;
    let frac = (bits & ((1 << 52) - 1)) as i128;
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | (1 << 52), exp - 1075)
    };
    (sign * m, e)
}

/// The root `t* = -z0 / (z1 - z0)` of a gap moving linearly from `z0 < 0` to `z1 > 0`, exactly,
/// as `(num, den)` with `den > 0`.
fn root(z0: f64, z1: f64) -> (i128, i128) {
    let ((m0, e0), (m1, e1)) = (dyadic(z0), dyadic(z1));
    let e = e0.min(e1);
    let (a, b) = (m0 << (e0 - e), m1 << (e1 - e));
    (-a, b - a)
}

/// Whether `t <= num / den` exactly (`t >= 0`, `den > 0`, the numbers small enough).
fn at_most(t: f64, (num, den): (i128, i128)) -> bool {
    let (m, e) = dyadic(t);
    if e >= 0 {
        (m << e) * den <= num
    } else {
        m * den <= num << (-e)
    }
}

/// How early a time of impact may be, in time units, for a gap closing at `speed` (distance
/// per unit time), with the relative displacement `s_t` of the elementary test and `m` its
/// largest coordinate difference: the tolerance, plus the time the gap takes to close from the
/// documented bound `sqrt(3) tolerance s_t / 2` plus rounding (`4 sqrt(3)` static corner
/// bounds of `64 u m`, `u = 2^-53`).
fn allowance(tolerance: f64, s_t: f64, m: f64, speed: f64) -> f64 {
    let rounding = 4.0 * 3f64.sqrt() * 64.0 * f64::EPSILON / 2.0 * m;
    tolerance + (3f64.sqrt() * tolerance * s_t / 2.0 + rounding) / speed
}

/// Issue 38: two triangles 1e-7 apart; edge 0-2 and edge 3-5 lie on the line y = x + 0.5 in
/// the plane, on either side of the point (0.1875, 0.6875), where vertex 0 stays at z = 0 and
/// vertex 5 rises through it. The two triangles first touch when vertex 5 reaches vertex 0:
/// `t* = -z5(0) / (z5(1) - z5(0))`, about 0.0091240 (the triangles' other points stay apart:
/// every other vertex is off the other triangle's plane region or above it). The brute-force
/// method reported edge 0-2 against edge 3-5 at 0.0090740, 50 times the bound early.
#[test]
fn issue_38_two_triangles_keep_the_bound() {
    let z3 = [1.2205220021647507e-07, 6.875974083345478e-08];
    let z4 = [2.7730566641078804e-08, 2.146507796943457e-08];
    let z5 = [-1.2636215340423144e-09, 1.3723102709757466e-07];
    let frame = |k: usize| {
        vec![
            [0.1875, 0.6875, 0.0],
            [0.25, 0.6875, 0.0],
            [0.25, 0.75, 0.0],
            [0.125, 0.625, z3[k]],
            [0.1875, 0.625, z4[k]],
            [0.1875, 0.6875, z5[k]],
        ]
    };
    let step = Step::new(frame(0), frame(1), vec![[0u32, 1, 2], [3, 4, 5]]).unwrap();
    let star = root(z5[0], z5[1]);
    let t_star = star.0 as f64 / star.1 as f64;
    assert!((t_star - 0.009123973716872133).abs() < 1e-17, "{t_star}");
    let tolerance = NarrowOptions::default().tolerance;
    // A bound of S_t for every elementary test here (only z moves, by at most the largest
    // z change, and S_t sums three differences of the moving points' changes).
    let dz = [z3, z4, z5].map(|z| (z[1] - z[0]).abs());
    let s_t = 4.0 * dz.iter().copied().fold(0.0, f64::max);
    // The largest coordinate difference of any of its tests: below 0.125.
    let early = allowance(tolerance, s_t, 0.125, z5[1] - z5[0]);
    for method in [Method::Brute, Method::Bvh, Method::Cluster] {
        let report = query(&step, method, &QueryOptions::default()).unwrap();
        assert_eq!(report.contact_count(), 6, "{method}");
        let tois = report.vf.iter().map(|c| c.toi);
        for toi in tois.chain(report.ee.iter().map(|c| c.toi)) {
            assert!(
                at_most(toi, star),
                "{method}: {toi} after the first contact"
            );
            assert!(
                t_star - toi <= early,
                "{method}: {toi}, {} early",
                t_star - toi
            );
        }
        let ee = report.ee.iter().find(|c| c.a == [0, 2] && c.b == [3, 5]);
        let toi = ee.expect("edge 0-2 against edge 3-5").toi;
        assert!(t_star - toi < 2e-6, "{toi}");
    }
}

/// A family like issue 38's: edge `a` from `q` to `q + L d` at z = 0 (static), edge `b` from
/// `q - L' d` to `q` in the plane, its end at `q` rising through z = 0 and its far end resting
/// 1e-8..1e-7 above, `d` a dyadic direction of the plane (so the edges are exactly collinear in
/// the plane, and meet only where `b`'s near end reaches `q`). Every time of impact must be at
/// most the exact first contact, and at most the tolerance plus the graze of the documented
/// bound earlier.
#[test]
fn nearly_parallel_resting_edges_keep_the_bound() {
    let mut rng = ChaCha8Rng::seed_from_u64(38);
    let options = NarrowOptions::default();
    let (mut count, mut worst) = (0, 0.0f64);
    for _ in 0..2_000 {
        let dyad = |rng: &mut ChaCha8Rng, lo: i32, hi: i32| rng.random_range(lo..=hi) as f64 / 64.0;
        let q = [dyad(&mut rng, -64, 64), dyad(&mut rng, -64, 64), 0.0];
        let d = [dyad(&mut rng, 1, 8), dyad(&mut rng, -8, 8), 0.0];
        let (la, lb) = (
            rng.random_range(1..=4) as f64,
            rng.random_range(1..=4) as f64,
        );
        let along = |s: f64| [q[0] + s * d[0], q[1] + s * d[1]];
        let near0 = -rng.random_range(1e-10..2e-9);
        let near1 = rng.random_range(2e-8..2e-7);
        let far = [rng.random_range(1e-8..1e-7), rng.random_range(1e-8..1e-7)];
        let [a1, b0] = [along(la), along(-lb)];
        let e = EdgeEdge {
            ea0_t0: q,
            ea1_t0: [a1[0], a1[1], 0.0],
            eb0_t0: [b0[0], b0[1], far[0]],
            eb1_t0: [q[0], q[1], near0],
            ea0_t1: q,
            ea1_t1: [a1[0], a1[1], 0.0],
            eb0_t1: [b0[0], b0[1], far[1]],
            eb1_t1: [q[0], q[1], near1],
        };
        let Outcome::Contact { toi, .. } = edge_edge(&e, &options).unwrap() else {
            panic!("{e:?}: the edges meet")
        };
        let star = root(near0, near1);
        let t_star = star.0 as f64 / star.1 as f64;
        assert!(at_most(toi, star), "{e:?}: {toi} after {t_star}");
        // S_t of the edge-edge test: the largest coordinate change of P = ea0 - eb0 (the far
        // end's), of A = ea1 - ea0 (none) and of B = eb0 - eb1 (the two ends' difference).
        let (d_far, d_near) = (far[1] - far[0], near1 - near0);
        let s_t = d_far.abs() + (d_far - d_near).abs();
        let m = [a1[0] - q[0], a1[1] - q[1], q[0] - b0[0], q[1] - b0[1]]
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        let early = allowance(options.tolerance, s_t, m, near1 - near0);
        assert!(
            t_star - toi <= early,
            "{e:?}: {toi} is {} early",
            t_star - toi
        );
        worst = worst.max((t_star - toi) / early);
        count += 1;
    }
    assert_eq!(count, 2_000);
    eprintln!("worst: {worst:.3} of the allowance");
}
