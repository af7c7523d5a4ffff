//! The distances against analytic cases and against an independent reference: nested ternary
//! searches over the features' parameters (the squared distance is convex in them), on seeded
//! random pairs, including degenerate triangles and nearly parallel edges.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;
use crate::math::DVec3;

/// The minimum of a convex function on `[lo, hi]`, by ternary search.
fn ternary(lo: f64, hi: f64, f: impl Fn(f64) -> f64) -> f64 {
    let (mut lo, mut hi) = (lo, hi);
    for _ in 0..90 {
        let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if f(m1) <= f(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    f(0.5 * (lo + hi)).min(f(lo)).min(f(hi))
}

fn reference_pt(p: DVec3, t: [DVec3; 3]) -> f64 {
    ternary(0.0, 1.0, |s| {
        ternary(0.0, 1.0 - s, |r| {
            let q = t[0] + (t[1] - t[0]) * s + (t[2] - t[0]) * r;
            (p - q).length()
        })
    })
}

fn reference_ee(a: [DVec3; 2], b: [DVec3; 2]) -> f64 {
    ternary(0.0, 1.0, |s| {
        let pa = a[0] + (a[1] - a[0]) * s;
        ternary(0.0, 1.0, |r| (pa - (b[0] + (b[1] - b[0]) * r)).length())
    })
}

fn point(rng: &mut ChaCha8Rng) -> DVec3 {
    DVec3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    )
}

#[test]
fn analytic_point_triangle_types() {
    let t = [
        DVec3::ZERO,
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.0, 2.0, 0.0),
    ];
    let d = |p: [f64; 3]| point_triangle_distance(DVec3::from(p), t[0], t[1], t[2]);
    use PointTriangleType::*;
    assert_eq!(d([0.5, 0.5, -3.0]), (9.0, Interior));
    assert_eq!(d([1.0, -2.0, 0.0]), (4.0, E0));
    assert_eq!(d([2.0, 2.0, 0.0]), (2.0, E1));
    assert_eq!(d([-1.0, 1.0, 1.0]), (2.0, E2));
    assert_eq!(d([3.0, -1.0, 0.0]), (2.0, T1));
    assert_eq!(d([-1.0, 3.0, 0.0]), (2.0, T2));
    // On the triangle: 0.
    assert_eq!(d([0.5, 0.5, 0.0]).0, 0.0);
    // A degenerate triangle (collinear corners): the distance to its longest side.
    let (dd, ty) = point_triangle_distance(
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::ZERO,
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(2.0, 0.0, 0.0),
    );
    assert_eq!(dd, 1.0);
    assert!(matches!(ty, T1 | E0 | E1 | E2));
}

#[test]
fn analytic_edge_edge_types() {
    use EdgeEdgeType::*;
    let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let d = |a: [DVec3; 2], b: [DVec3; 2]| edge_edge_distance(a[0], a[1], b[0], b[1]);
    let a = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0)];
    assert_eq!(d(a, [p(-1.0, 0.0, 0.0), p(-1.0, 1.0, 0.0)]), (1.0, Ea0Eb0));
    assert_eq!(d(a, [p(-1.0, 1.0, 0.0), p(-1.0, 0.0, 0.0)]), (1.0, Ea0Eb1));
    assert_eq!(d(a, [p(2.0, 0.0, 0.0), p(2.0, 1.0, 0.0)]), (1.0, Ea1Eb0));
    assert_eq!(d(a, [p(0.5, 1.0, 0.0), p(0.5, 3.0, 0.0)]), (1.0, EaEb0));
    assert_eq!(d(a, [p(0.5, 3.0, 0.0), p(0.5, 1.0, 0.0)]), (1.0, EaEb1));
    assert_eq!(d(a, [p(-1.0, -1.0, 0.0), p(-1.0, 1.0, 0.0)]), (1.0, Ea0Eb));
    assert_eq!(d(a, [p(2.0, -1.0, 0.0), p(2.0, 1.0, 0.0)]), (1.0, Ea1Eb));
    assert_eq!(d(a, [p(0.5, -1.0, 2.0), p(0.5, 1.0, 2.0)]), (4.0, EaEb));
    // Crossing: 0.
    assert_eq!(d(a, [p(0.5, -1.0, 0.0), p(0.5, 1.0, 0.0)]).0, 0.0);
    // Swapping the edges swaps the type.
    for b in [
        [p(0.5, 1.0, 0.0), p(0.5, 3.0, 0.0)],
        [p(2.0, 0.0, 0.0), p(2.0, 1.0, 0.0)],
    ] {
        let (x, tx) = d(a, b);
        let (y, ty) = d(b, a);
        assert!((x - y).abs() <= 1e-15);
        assert_eq!(tx.swapped(), ty);
    }
}

/// Random pairs, plain and degenerate: every distance within the rounding bound (plus the
/// reference's own error) of the reference.
#[test]
fn random_pairs_match_the_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    for case in 0..1500 {
        let p = point(&mut rng);
        let mut t = [point(&mut rng), point(&mut rng), point(&mut rng)];
        match case % 5 {
            // Collinear corners.
            1 => t[2] = t[0] + (t[1] - t[0]) * rng.random_range(-1.0..2.0),
            // A sliver.
            2 => t[2] = t[0] + (t[1] - t[0]) * 0.5 + point(&mut rng) * 1e-9,
            // The point near the plane.
            3 => {
                let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
                let q = (t[0] + t[1] + t[2]) / 3.0;
                let p = q + n * 1e-12 + (t[1] - t[0]) * 0.1;
                let (d, _) = point_triangle_distance(p, t[0], t[1], t[2]);
                let r = reference_pt(p, t);
                assert!(
                    (d.sqrt() - r).abs() <= 1e-9,
                    "case {case}: {} vs {r}",
                    d.sqrt()
                );
                continue;
            }
            _ => {}
        }
        let (d, _) = point_triangle_distance(p, t[0], t[1], t[2]);
        let r = reference_pt(p, t);
        assert!(
            (d.sqrt() - r).abs() <= 1e-9,
            "case {case}: {} vs {r}",
            d.sqrt()
        );

        let a = [point(&mut rng), point(&mut rng)];
        let mut b = [point(&mut rng), point(&mut rng)];
        match case % 4 {
            // Parallel.
            1 => b[1] = b[0] + (a[1] - a[0]) * rng.random_range(-2.0..2.0),
            // Nearly parallel.
            2 => b[1] = b[0] + (a[1] - a[0]) * 0.7 + point(&mut rng) * 1e-7,
            // A degenerate edge.
            3 => b[1] = b[0],
            _ => {}
        }
        let (d, _) = edge_edge_distance(a[0], a[1], b[0], b[1]);
        let r = reference_ee(a, b);
        assert!(
            (d.sqrt() - r).abs() <= 1e-9,
            "case {case}: {} vs {r}",
            d.sqrt()
        );
        let (d2, _) = edge_edge_distance(b[0], b[1], a[0], a[1]);
        assert!((d2.sqrt() - r).abs() <= 1e-9, "case {case} swapped");
    }
}

/// The distance agrees with the type it reports: recomputed on the reported features alone.
#[test]
fn types_name_the_closest_features() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for _ in 0..2000 {
        let p = point(&mut rng);
        let t = [point(&mut rng), point(&mut rng), point(&mut rng)];
        let (d, ty) = point_triangle_distance(p, t[0], t[1], t[2]);
        use PointTriangleType::*;
        let again = match ty {
            T0 | T1 | T2 => point_point_distance(p, t[ty as usize]),
            E0 | E1 | E2 => {
                let k = ty as usize - 3;
                point_edge_distance(p, t[k], t[(k + 1) % 3]).0
            }
            Interior => {
                let n = (t[1] - t[0]).cross(t[2] - t[0]);
                let h = n.dot(p - t[0]);
                h * h / n.length_squared()
            }
        };
        assert!(
            (d.sqrt() - again.sqrt()).abs() <= 1e-12,
            "{ty:?}: {d} vs {again}"
        );
    }
}

/// Translation: far from the origin, the error stays relative to the pair's size.
#[test]
fn far_from_the_origin() {
    let offset = DVec3::splat(1e6);
    let t = [DVec3::ZERO, DVec3::X, DVec3::Y].map(|c| c * 1e-3 + offset);
    let p = DVec3::new(0.25e-3, 0.25e-3, 1e-9) + offset;
    let (d, ty) = point_triangle_distance(p, t[0], t[1], t[2]);
    assert_eq!(ty, PointTriangleType::Interior);
    let bound = rounding_bound(2e-3, 1.0) + 1e6 * f64::EPSILON; // the input's own rounding
    assert!((d.sqrt() - 1e-9).abs() <= bound, "{}", d.sqrt());
}
