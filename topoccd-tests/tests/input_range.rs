//! The ends of f64's range (issue 43): a step near 1e308, where the k-DOP projections
//! (`x + y`, `x + y + z`) and their padding overflow, must still give its contacts (the volumes
//! go to infinity on their outer side instead of NaN, which overlaps nothing), never a silent
//! empty report.

use topoccd::{query, Method, Mode, QueryOptions, Step};

/// The two triangles near (1e308, 1e308, 0), scaled by `s`: triangle 1 (vertices 3,
/// 4, 5) falls flat through triangle 0, every one of its corners over triangle 0's interior,
/// crossing its plane at t = 1/2 exactly (z goes from 1e299 to -1e299, times `s`).
fn near_the_end(s: f64) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let x0 = vec![
        [1e308, 1e308, 0.0],
        [1.000000005e308, 1e308, 0.0],
        [1e308, 1.000000005e308, 0.0],
        [1.000000001e308, 1.000000001e308, 1e299],
        [1.000000002e308, 1.000000001e308, 1e299],
        [1.000000001e308, 1.000000002e308, 1e299],
    ];
    let mut x1 = x0.clone();
    for p in &mut x1[3..] {
        p[2] = -1e299;
    }
    let scale = |x: Vec<[f64; 3]>| x.into_iter().map(|p| p.map(|c| c * s)).collect();
    (scale(x0), scale(x1))
}

#[test]
fn contacts_near_the_end_of_f64_are_reported() {
    let tris = [[0u32, 1, 2], [3, 4, 5]];
    for s in [1.0, 0.1] {
        let (x0, x1) = near_the_end(s);
        // Each corner of triangle 1 lies over triangle 0's interior: by its offsets from
        // corner 0, in units of 1e299 (x s): (1, 1), (2, 1), (1, 2), each with a sum below 5.
        let step = Step::new(&x0, &x1, &tris).expect("finite coordinates");
        for method in [Method::Brute, Method::Bvh, Method::Cluster] {
            let all = query(&step, method, &QueryOptions::default()).unwrap();
            let mut pairs: Vec<_> = all.vf.iter().map(|c| (c.vertex, c.face)).collect();
            pairs.sort_unstable();
            for v in [3, 4, 5] {
                assert!(pairs.contains(&(v, 0)), "scale {s}, {method}: {pairs:?}");
            }
            // Never later than the contact, at t = 1/2.
            for c in all.vf.iter().filter(|c| c.face == 0) {
                assert!(c.toi <= 0.5, "scale {s}, {method}: {c:?}");
            }
            let earliest = QueryOptions {
                mode: Mode::Earliest,
                ..QueryOptions::default()
            };
            let first = query(&step, method, &earliest).unwrap();
            assert!(
                first.earliest_toi().is_some_and(|t| t <= 0.5),
                "scale {s}, {method}: {:?}",
                first.earliest
            );
        }
    }
}

/// The case at scale 1e110, scaled to `s` (its coordinates are in units of 1e110):
/// triangle 0 = (0,0,0), (1,0,0), (0,1,0) at rest; triangle 1 falls through it. The exact
/// first contacts are vf (4, 0) at 3/4, ee (0,1)-(3,4) at 11/16 and ee (0,1)-(4,5) at 7/8;
/// no other pair touches during the step.
fn scaled_case(s: f64) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let x0 = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, -0.75, 0.5],
        [0.5, 0.25, 0.75],
        [0.75, -0.25, 1.0],
    ];
    let mut x1 = x0;
    for (p, z) in x1[3..].iter_mut().zip([-0.5, -0.25, 0.0]) {
        p[2] = z;
    }
    let scale = |x: [[f64; 3]; 6]| x.iter().map(|p| p.map(|c| c * s)).collect();
    (scale(x0), scale(x1))
}

/// The exact contacts of [`scaled_case`]: `(kind, pair, first contact)`.
const EXACT: [(&str, [u32; 4], f64); 3] = [
    ("vf", [4, 0, 0, 0], 0.75),
    ("ee", [0, 1, 3, 4], 0.6875),
    ("ee", [0, 1, 4, 5], 0.875),
];

#[test]
fn resolved_times_keep_their_bound_at_every_scale() {
    use topoccd::Certainty;
    let tris = [[0u32, 1, 2], [3, 4, 5]];
    let mut failures = Vec::new();
    // Every power of ten, and every one near where the products used to overflow or underflow
    // (1e110, the case, and 1e-100, its mirror, among them).
    for e in -320..=300 {
        if e % 10 != 0 && !(-150..=-70).contains(&e) && !(70..=150).contains(&e) {
            continue;
        }
        let s: f64 = format!("1e{e}").parse().unwrap();
        let (x0, x1) = scaled_case(s);
        let step = Step::new(&x0, &x1, &tris).expect("finite coordinates");
        for method in [Method::Brute, Method::Bvh, Method::Cluster] {
            let r = query(&step, method, &QueryOptions::default()).unwrap();
            let mut found: Vec<(&str, [u32; 4], f64, Certainty)> =
                r.vf.iter()
                    .map(|c| ("vf", [c.vertex, c.face, 0, 0], c.toi, c.certainty))
                    .collect();
            found.extend(
                r.ee.iter()
                    .map(|c| ("ee", [c.a[0], c.a[1], c.b[0], c.b[1]], c.toi, c.certainty)),
            );
            // None missed: each exact contact is reported, no later than it happens.
            for (kind, pair, t) in EXACT {
                if !found.iter().any(|f| f.0 == kind && f.1 == pair && f.2 <= t) {
                    failures.push(format!("1e{e} {method}: missed {kind} {pair:?} at {t}"));
                }
            }
            // No false claim: a resolved contact is an exact one, within the tolerance (1e-6;
            // twice that for the rounding of the time).
            for (kind, pair, toi, certainty) in &found {
                if *certainty != Certainty::Resolved {
                    continue;
                }
                let ok = EXACT
                    .iter()
                    .any(|(k, p, t)| k == kind && p == pair && *toi <= *t && *toi >= t - 2e-6);
                if !ok {
                    failures.push(format!("1e{e} {method}: resolved {kind} {pair:?} at {toi}"));
                }
            }
            // Earliest mode: the first contact is ee (0,1)-(3,4) at 11/16, never later.
            let earliest = QueryOptions {
                mode: Mode::Earliest,
                ..QueryOptions::default()
            };
            let first = query(&step, method, &earliest).unwrap();
            match first.earliest_toi() {
                Some(t) if (0.6875 - 2e-6..=0.6875).contains(&t) => {}
                t => failures.push(format!("1e{e} {method}: earliest {t:?}")),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
