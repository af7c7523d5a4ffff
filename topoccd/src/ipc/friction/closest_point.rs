//! Closest-point coordinates of the contact stencils at the lagged positions: where on each
//! primitive the contact sits, as the IPC toolkit computes them for friction.
//!
//! These are the minimisers over the *lines* and the *plane*, not clamped to the segment or
//! the triangle: a normal collision has already been reduced to the closest-feature type whose
//! minimiser is inside (or, for nearly parallel edges, mollified), and ipctk keeps the
//! unclamped values.

use crate::math::DVec3;

/// The parameter `alpha` of the point of the line `e0 + alpha (e1 - e0)` closest to `p`
/// (not finite for a zero-length edge).
///
/// ```
/// use topoccd::ipc::friction::point_edge_closest_point;
/// use topoccd::math::DVec3;
/// let a = point_edge_closest_point(DVec3::new(0.25, 1.0, 0.0), DVec3::ZERO, DVec3::X);
/// assert_eq!(a, 0.25);
/// ```
#[inline]
pub fn point_edge_closest_point(p: DVec3, e0: DVec3, e1: DVec3) -> f64 {
    let e = e1 - e0;
    (p - e0).dot(e) / e.length_squared()
}

/// The parameters `[a, b]` of the closest points `ea0 + a (ea1 - ea0)` and
/// `eb0 + b (eb1 - eb0)` of the two lines (not finite for parallel lines).
#[inline]
pub fn edge_edge_closest_point(ea0: DVec3, ea1: DVec3, eb0: DVec3, eb1: DVec3) -> [f64; 2] {
    // Normal equations of min |ea0 - eb0 + a ea - b eb|^2:
    // [ea.ea, -ea.eb; -ea.eb, eb.eb] [a; b] = [-w.ea; w.eb], w = ea0 - eb0.
    let (ea, eb, w) = (ea1 - ea0, eb1 - eb0, ea0 - eb0);
    solve_sym2(ea.dot(ea), -ea.dot(eb), eb.dot(eb), [-w.dot(ea), w.dot(eb)])
}

/// The coordinates `[b1, b2]` of the point `t0 + b1 (t1 - t0) + b2 (t2 - t0)` of the
/// triangle's plane closest to `p` (not finite for a zero-area triangle).
#[inline]
pub fn point_triangle_closest_point(p: DVec3, t0: DVec3, t1: DVec3, t2: DVec3) -> [f64; 2] {
    let (e0, e1, r) = (t1 - t0, t2 - t0, p - t0);
    solve_sym2(e0.dot(e0), e0.dot(e1), e1.dot(e1), [e0.dot(r), e1.dot(r)])
}

/// Solves `[a, b; b, c] x = r` by Cramer's rule.
#[inline]
fn solve_sym2(a: f64, b: f64, c: f64, r: [f64; 2]) -> [f64; 2] {
    let det = a * c - b * b;
    [(c * r[0] - b * r[1]) / det, (a * r[1] - b * r[0]) / det]
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn point(rng: &mut ChaCha8Rng) -> DVec3 {
        DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
    }

    /// Brute-force minimisation of `f` over a 2-parameter box by shrinking grids.
    fn argmin2(f: impl Fn(f64, f64) -> f64, mut c: [f64; 2], mut h: f64) -> [f64; 2] {
        for _ in 0..160 {
            let mut best = (f(c[0], c[1]), c);
            for i in -4..=4 {
                for j in -4..=4 {
                    let x = [c[0] + i as f64 * h, c[1] + j as f64 * h];
                    let v = f(x[0], x[1]);
                    if v < best.0 {
                        best = (v, x);
                    }
                }
            }
            c = best.1;
            h *= 0.75;
        }
        c
    }

    #[test]
    fn closest_points_minimise_the_distance() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for _ in 0..200 {
            let [p, a, b, c] = [0; 4].map(|_| point(&mut rng));
            // Point-edge: 1-D, by golden-section-like grid refinement.
            let f = |s: f64, _t: f64| (p - (a + (b - a) * s)).length_squared();
            let s = argmin2(f, [0.5, 0.0], 8.0)[0];
            let alpha = point_edge_closest_point(p, a, b);
            assert!((alpha - s).abs() < 1e-6 * (1.0 + s.abs()), "{alpha} vs {s}");

            let g = |s: f64, t: f64| (a + (b - a) * s - (p + (c - p) * t)).length_squared();
            let st = argmin2(g, [0.5, 0.5], 8.0);
            let ab = edge_edge_closest_point(a, b, p, c);
            // Ill-conditioned pairs make the minimiser flat; compare the distances too.
            let gap = g(ab[0], ab[1]);
            assert!(gap <= g(st[0], st[1]) + 1e-12, "{ab:?} vs {st:?}");
            // First-order optimality: the gap is orthogonal to both lines.
            let gv = a + (b - a) * ab[0] - (p + (c - p) * ab[1]);
            let scale = gv.length() * (b - a).length().max((c - p).length());
            assert!(gv.dot(b - a).abs() < 1e-9 * scale.max(1e-12));
            assert!(gv.dot(c - p).abs() < 1e-9 * scale.max(1e-12));

            let h = |s: f64, t: f64| (p - (a + (b - a) * s + (c - a) * t)).length_squared();
            let st = argmin2(h, [0.3, 0.3], 8.0);
            let bc = point_triangle_closest_point(p, a, b, c);
            assert!(
                h(bc[0], bc[1]) <= h(st[0], st[1]) + 1e-12,
                "{bc:?} vs {st:?}"
            );
            let gv = p - (a + (b - a) * bc[0] + (c - a) * bc[1]);
            let scale = gv.length() * (b - a).length().max((c - a).length());
            assert!(gv.dot(b - a).abs() < 1e-9 * scale.max(1e-12));
            assert!(gv.dot(c - a).abs() < 1e-9 * scale.max(1e-12));
        }
    }

    #[test]
    fn analytic_cases() {
        let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        // Crossing lines: x axis and the line x = 3, z = 1 along y, from y = -1 to 1.
        let ab = edge_edge_closest_point(
            p(0.0, 0.0, 0.0),
            p(4.0, 0.0, 0.0),
            p(3.0, -1.0, 1.0),
            p(3.0, 1.0, 1.0),
        );
        assert_eq!(ab, [0.75, 0.5]);
        // Unclamped: the point projects outside the triangle.
        let bc = point_triangle_closest_point(
            p(2.0, 0.5, 1.0),
            p(0.0, 0.0, 0.0),
            p(1.0, 0.0, 0.0),
            p(0.0, 1.0, 0.0),
        );
        assert_eq!(bc, [2.0, 0.5]);
        assert!(!point_edge_closest_point(DVec3::X, DVec3::Y, DVec3::Y).is_finite());
    }
}
