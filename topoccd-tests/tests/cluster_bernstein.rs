//! Sign certificates of the clustering: quadratics and cubics with known signs, roots just
//! inside or outside `[0, 1]`, scale and translation invariance.

use topoccd::math::DVec3;
use topoccd::narrow::bernstein::{
    normal_along, phi, star_around, triple_product, Bernstein, Verdict,
};

/// Bernstein coefficients of a quadratic given by its power-basis coefficients `c0 + c1 t + c2 t^2`.
fn quad(c0: f64, c1: f64, c2: f64, error: f64) -> Bernstein<3> {
    Bernstein {
        coeffs: [c0, c0 + c1 / 2.0, c0 + c1 + c2],
        error,
    }
}

/// Bernstein coefficients of `a (t - r1)(t - r2)(t - r3)` (power basis converted exactly enough).
fn cubic_roots(a: f64, r: [f64; 3], error: f64) -> Bernstein<4> {
    // Power coefficients.
    let c3 = a;
    let c2 = -a * (r[0] + r[1] + r[2]);
    let c1 = a * (r[0] * r[1] + r[0] * r[2] + r[1] * r[2]);
    let c0 = -a * r[0] * r[1] * r[2];
    Bernstein {
        coeffs: [
            c0,
            c0 + c1 / 3.0,
            c0 + 2.0 * c1 / 3.0 + c2 / 3.0,
            c0 + c1 + c2 + c3,
        ],
        error,
    }
}

#[test]
fn quadratic_with_known_sign() {
    // 1 + t^2 > 0.
    assert_eq!(quad(1.0, 0.0, 1.0, 1e-15).positive(0), Verdict::Holds);
    // (t - 0.5)^2 + 0.01 > 0, but the middle coefficient is negative: needs subdivision.
    let p = quad(0.26, -1.0, 1.0, 1e-15);
    assert_eq!(p.positive(0), Verdict::Undecided);
    assert_eq!(p.positive(4), Verdict::Holds);
    // -(t - 0.5)^2 + 0.01 < 0 at the ends.
    assert_eq!(quad(-0.24, 1.0, -1.0, 1e-15).positive(4), Verdict::Fails);
    // (t - 0.5)^2 >= 0 touches zero: positive never holds, nonnegative does after subdivision.
    let touch = quad(0.25, -1.0, 1.0, 1e-15);
    assert_ne!(touch.positive(6), Verdict::Holds);
    assert_eq!(touch.nonnegative(6), Verdict::Holds);
    // Identically zero: non-negative up to rounding, not positive.
    let zero = quad(0.0, 0.0, 0.0, 1e-15);
    assert_eq!(zero.nonnegative(0), Verdict::Holds);
    assert_ne!(zero.positive(3), Verdict::Holds);
}

#[test]
fn roots_just_inside_or_outside_the_interval() {
    for &d in &[1e-9, 1e-7, 1e-3] {
        // Linear-ish quadratic t - r, root just outside [0, 1] (r = -d or 1 + d) or inside.
        let outside_low = quad(d, 1.0, 0.0, 1e-16);
        assert_eq!(outside_low.positive(0), Verdict::Holds, "root at -{d}");
        let inside_low = quad(-d, 1.0, 0.0, 1e-16);
        assert_eq!(inside_low.positive(8), Verdict::Fails, "root at {d}");
        let outside_high = quad(1.0 + d, -1.0, 0.0, 1e-16); // 1 + d - t
        assert_eq!(outside_high.positive(0), Verdict::Holds);
        let inside_high = quad(1.0 - d, -1.0, 0.0, 1e-16);
        assert_eq!(inside_high.positive(8), Verdict::Fails);
        // Cubic with a root just outside / inside: (t + d)(t - 2)(t - 3) > 0 on [0, 1].
        let c = cubic_roots(1.0, [-d, 2.0, 3.0], 1e-15);
        assert_eq!(c.positive(2), Verdict::Holds);
        let c = cubic_roots(1.0, [d, 2.0, 3.0], 1e-15);
        assert_eq!(c.positive(8), Verdict::Fails);
        let c = cubic_roots(1.0, [-1.0, 1.0 + d, 5.0], 1e-15);
        assert_eq!(c.positive(3), Verdict::Holds, "root at 1 + {d}");
        let c = cubic_roots(1.0, [-1.0, 1.0 - d, 5.0], 1e-15);
        assert_eq!(c.positive(8), Verdict::Fails);
    }
}

#[test]
fn double_root_inside_is_never_certified() {
    // (t - 0.3)^2 (t + 1): zero at 0.3, positive elsewhere.
    let c = cubic_roots(1.0, [0.3, 0.3, -1.0], 1e-15);
    assert_ne!(c.positive(10), Verdict::Holds);
    assert!(c.eval(0.3).abs() < 1e-12);
}

#[test]
fn subdivision_keeps_values_and_grows_the_error() {
    let c = cubic_roots(2.0, [0.2, 0.7, 1.5], 1e-14);
    let (l, r) = c.split();
    for k in 0..=10 {
        let s = k as f64 / 10.0;
        assert!((l.eval(s) - c.eval(s / 2.0)).abs() < 1e-13);
        assert!((r.eval(s) - c.eval(0.5 + s / 2.0)).abs() < 1e-13);
    }
    assert!(l.error > c.error && r.error == l.error);
}

fn tri(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [DVec3; 3] {
    [DVec3::from(a), DVec3::from(b), DVec3::from(c)]
}

#[test]
fn triangle_normal_flipping_during_the_step() {
    let t0 = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    // Corner c moves across edge ab: the normal flips at t = 0.5.
    let mut t1 = t0;
    t1[2] = DVec3::new(0.0, -1.0, 0.0);
    assert_eq!(normal_along(DVec3::Z, &t0, &t1).positive(6), Verdict::Fails);
    // Stops just short (at y = 1e-9): still positive.
    t1[2] = DVec3::new(0.0, 1e-9, 0.0);
    assert_eq!(normal_along(DVec3::Z, &t0, &t1).positive(2), Verdict::Holds);
    // Passes to exactly zero at t = 1: not certified.
    t1[2] = DVec3::new(0.5, 0.0, 0.0);
    assert_ne!(normal_along(DVec3::Z, &t0, &t1).positive(8), Verdict::Holds);
}

#[test]
fn scale_and_translation_invariance() {
    let t0 = tri([0.1, 0.2, 0.0], [1.3, 0.1, 0.2], [0.2, 1.1, -0.1]);
    let t1 = tri([0.2, 0.3, 0.5], [1.2, 0.4, 0.3], [0.4, 1.0, 0.9]);
    let o = [DVec3::new(0.4, 0.4, -0.3), DVec3::new(0.5, 0.5, 0.2)];
    let v = DVec3::new(0.1, -0.2, 1.0).normalize();
    let base_n = normal_along(v, &t0, &t1).positive(2);
    let base_phi = phi(&t0, &t1, o).nonnegative(2);
    let base_star = star_around(v, [t0[0], t1[0]], [t0[1], t1[1]], o).positive(2);
    for &s in &[1e-6, 1e-3, 1.0, 1e3, 1e8] {
        for &shift in &[DVec3::ZERO, DVec3::new(1e3, -2e3, 5e2)] {
            let m = |p: DVec3| p * s + shift * s;
            let (a0, a1) = (t0.map(m), t1.map(m));
            let om = [m(o[0]), m(o[1])];
            assert_eq!(normal_along(v, &a0, &a1).positive(2), base_n);
            assert_eq!(phi(&a0, &a1, om).nonnegative(2), base_phi);
            let st = star_around(v, [a0[0], a1[0]], [a0[1], a1[1]], om).positive(2);
            assert_eq!(st, base_star);
            // Error bounds scale like the coefficients.
            let q = triple_product(
                v,
                a0[1] - a0[0],
                a1[1] - a1[0],
                a0[2] - a0[0],
                a1[2] - a1[0],
            );
            assert!(q.error < 1e-12 * q.coeffs[0].abs().max(1e-300));
        }
    }
}

#[test]
fn phi_sign_of_observation_point() {
    let t = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let below = [DVec3::new(0.2, 0.2, -1.0); 2];
    let above = [DVec3::new(0.2, 0.2, 1.0); 2];
    let inside = [DVec3::new(0.2, 0.2, 0.0); 2];
    assert_eq!(phi(&t, &t, below).positive(0), Verdict::Holds);
    assert_eq!(phi(&t, &t, above).nonnegative(2), Verdict::Fails);
    // O in the triangle's plane (the seed itself): phi = 0, accepted up to rounding only.
    assert_eq!(phi(&t, &t, inside).nonnegative(0), Verdict::Holds);
    assert_ne!(phi(&t, &t, inside).positive(2), Verdict::Holds);
    // O crossing the plane during the step: fails.
    assert_eq!(
        phi(&t, &t, [below[0], above[0]]).nonnegative(4),
        Verdict::Fails
    );
}
