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
