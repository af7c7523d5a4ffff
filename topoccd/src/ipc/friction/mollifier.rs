//! The smooth friction mollifier and the smooth static-to-kinetic coefficient, as the IPC
//! toolkit defines them (`smooth_friction_f0` ... `smooth_mu_f2_x_minus_mu_f1_over_x3`).
//!
//! All functions take a tangential speed `y` (a norm, so `y >= 0` in use; the formulas are
//! even or odd in `y` as noted) and the mollifier's threshold `eps_v > 0`, in the same unit as
//! `y` (a velocity when the potential is evaluated on velocities).
//!
//! The mollifier replaces the non-smooth `|y|` of Coulomb friction below `eps_v`:
//!
//! - `f0(y) = y^2/eps_v - y^3/(3 eps_v^2) + eps_v/3` for `|y| < eps_v`, else `|y|`
//!   (C1 at `eps_v`, with `f0(0) = eps_v/3`);
//! - `f1 = f0'` rises from 0 to 1, `f2 = f1'`.
//!
//! With different static and kinetic coefficients the coefficient itself is smoothed,
//! `mu(y)`, two quadratic pieces from `mu_s` at 0 to `mu_k` at `eps_v`, and the potential
//! uses `g0(y) = integral of mu(t) f1(t) dt`, with the constant chosen so that
//! `g0(y) = mu_k y` from `eps_v` on.

/// `f0(y)`: the smooth stand-in for `|y|` (even in `y`).
///
/// ```
/// use topoccd::ipc::friction::smooth_friction_f0;
/// assert_eq!(smooth_friction_f0(2.0, 1.0), 2.0);
/// assert!((smooth_friction_f0(0.0, 1.0) - 1.0 / 3.0).abs() < 1e-16);
/// ```
#[inline]
pub fn smooth_friction_f0(y: f64, eps_v: f64) -> f64 {
    debug_assert!(eps_v > 0.0);
    let a = y.abs();
    if a >= eps_v {
        return a;
    }
    // eps_v (s^2 - s^3/3 + 1/3) with s = a / eps_v.
    let s = a / eps_v;
    eps_v * (s * s * (1.0 - s / 3.0) + 1.0 / 3.0)
}

/// `f1(y) = f0'(y)` for `y >= 0`: 0 at rest, 1 from `eps_v` on.
#[inline]
pub fn smooth_friction_f1(y: f64, eps_v: f64) -> f64 {
    debug_assert!(eps_v > 0.0);
    if y.abs() >= eps_v {
        return 1.0;
    }
    let s = y / eps_v;
    s * (2.0 - s)
}

/// `f2(y) = f1'(y)` for `y >= 0`.
#[inline]
pub fn smooth_friction_f2(y: f64, eps_v: f64) -> f64 {
    debug_assert!(eps_v > 0.0);
    if y.abs() >= eps_v {
        return 0.0;
    }
    2.0 * (1.0 - y / eps_v) / eps_v
}

/// `f1(y) / y`, finite at 0 (`2 / eps_v`).
#[inline]
pub fn smooth_friction_f1_over_x(y: f64, eps_v: f64) -> f64 {
    debug_assert!(eps_v > 0.0);
    if y.abs() >= eps_v {
        return 1.0 / y;
    }
    (2.0 - y / eps_v) / eps_v
}

/// `(f2(y) y - f1(y)) / y^3`: the coefficient of `u u^T` in the Hessian of `f0(|u|)`.
#[inline]
pub fn smooth_friction_f2_x_minus_f1_over_x3(y: f64, eps_v: f64) -> f64 {
    debug_assert!(eps_v > 0.0);
    if y.abs() >= eps_v {
        return -1.0 / (y * y * y);
    }
    // (2 y/eps - 2 y^2/eps^2 - 2 y/eps + y^2/eps^2) / y^3 = -1 / (y eps^2)
    -1.0 / (y * eps_v * eps_v)
}

/// The smooth friction coefficient `mu(y)`: `mu_s` at 0, `mu_k` from `eps_v` on, two
/// quadratic pieces meeting at `eps_v / 2` (C1; even in `y`).
///
/// ```
/// use topoccd::ipc::friction::smooth_mu;
/// assert_eq!(smooth_mu(0.0, 0.8, 0.5, 1.0), 0.8);
/// assert_eq!(smooth_mu(1.0, 0.8, 0.5, 1.0), 0.5);
/// assert!((smooth_mu(0.5, 0.8, 0.5, 1.0) - 0.65).abs() < 1e-15);
/// ```
#[inline]
pub fn smooth_mu(y: f64, mu_s: f64, mu_k: f64, eps_v: f64) -> f64 {
    debug_assert!(eps_v > 0.0);
    let a = y.abs();
    if mu_s == mu_k || a >= eps_v {
        return mu_k;
    }
    let delta = mu_k - mu_s;
    let z = a / eps_v;
    if a < 0.5 * eps_v {
        mu_s + 2.0 * delta * z * z
    } else {
        let w = z - 1.0;
        mu_k - 2.0 * delta * w * w
    }
}

/// `d mu / dy` for `y >= 0`.
#[inline]
pub fn smooth_mu_derivative(y: f64, mu_s: f64, mu_k: f64, eps_v: f64) -> f64 {
    debug_assert!(eps_v > 0.0);
    let a = y.abs();
    if mu_s == mu_k || a >= eps_v {
        return 0.0;
    }
    let delta = mu_k - mu_s;
    let z = a / eps_v;
    if a < 0.5 * eps_v {
        4.0 * delta * z / eps_v
    } else {
        -4.0 * delta * (z - 1.0) / eps_v
    }
}

/// `g0(y)`: the friction potential's profile, `mu_k f0(y)` when `mu_s == mu_k`, otherwise
/// the antiderivative of `mu(y) f1(y)` that equals `mu_k y` from `eps_v` on (even in `y`).
///
/// ```
/// use topoccd::ipc::friction::{smooth_friction_f0, smooth_mu_f0};
/// assert_eq!(smooth_mu_f0(0.3, 0.5, 0.5, 1.0), 0.5 * smooth_friction_f0(0.3, 1.0));
/// assert_eq!(smooth_mu_f0(2.0, 0.8, 0.5, 1.0), 1.0);
/// ```
#[inline]
pub fn smooth_mu_f0(y: f64, mu_s: f64, mu_k: f64, eps_v: f64) -> f64 {
    debug_assert!(eps_v > 0.0);
    let a = y.abs();
    if mu_s == mu_k || a >= eps_v {
        return mu_k * smooth_friction_f0(y, eps_v);
    }
    let delta = mu_k - mu_s;
    let z = a / eps_v;
    if a < 0.5 * eps_v {
        // With s = t/eps, mu f1 = (mu_s + 2 delta s^2)(2 s - s^2): integrated from 0,
        // eps (mu_s (z^2 - z^3/3) + delta (z^4 - 0.4 z^5)), plus the constant that joins the
        // upper piece at z = 1/2.
        let poly = z * z * (mu_s * (1.0 - z / 3.0) + delta * z * z * (1.0 - 0.4 * z));
        eps_v * (poly + 9.0 / 16.0 * mu_k - 11.0 / 48.0 * mu_s)
    } else {
        // With w = s - 1: mu f1 = (mu_k - 2 delta w^2)(1 - w^2); integrated from w = 0
        // (where g0 = mu_k eps): mu_k w - (mu_k + 2 delta) w^3/3 + 0.4 delta w^5.
        let w = z - 1.0;
        let w2 = w * w;
        eps_v * (mu_k + w * (mu_k - w2 * ((mu_k + 2.0 * delta) / 3.0 - 0.4 * delta * w2)))
    }
}

/// `mu(y) f1(y)`: the friction force's profile.
#[inline]
pub fn smooth_mu_f1(y: f64, mu_s: f64, mu_k: f64, eps_v: f64) -> f64 {
    smooth_mu(y, mu_s, mu_k, eps_v) * smooth_friction_f1(y, eps_v)
}

/// `d/dy (mu(y) f1(y))` for `y >= 0`.
#[inline]
pub fn smooth_mu_f2(y: f64, mu_s: f64, mu_k: f64, eps_v: f64) -> f64 {
    smooth_mu_derivative(y, mu_s, mu_k, eps_v) * smooth_friction_f1(y, eps_v)
        + smooth_mu(y, mu_s, mu_k, eps_v) * smooth_friction_f2(y, eps_v)
}

/// `mu(y) f1(y) / y`, finite at 0 (`2 mu_s / eps_v`).
#[inline]
pub fn smooth_mu_f1_over_x(y: f64, mu_s: f64, mu_k: f64, eps_v: f64) -> f64 {
    smooth_mu(y, mu_s, mu_k, eps_v) * smooth_friction_f1_over_x(y, eps_v)
}

/// `(d/dy(mu f1) y - mu f1) / y^3` for `y > 0`: the coefficient of `u u^T` in the Hessian of
/// `g0(|u|)`.
#[inline]
pub fn smooth_mu_f2_x_minus_mu_f1_over_x3(y: f64, mu_s: f64, mu_k: f64, eps_v: f64) -> f64 {
    debug_assert!(eps_v > 0.0);
    let a = y.abs();
    if mu_s == mu_k || a >= eps_v {
        return mu_k * smooth_friction_f2_x_minus_f1_over_x3(y, eps_v);
    }
    // mu (f2 y - f1)/y^3 + mu' f1/y^2, with (f2 y - f1)/y^3 = -1/(y eps^2) and
    // f1/y^2 = (2 - s)/(eps y), s = y/eps.
    let delta = mu_k - mu_s;
    let s = y / eps_v;
    let e2 = eps_v * eps_v;
    if a < 0.5 * eps_v {
        // mu' = 4 delta s/eps: mu' f1/y^2 = 4 delta (2 - s)/eps^3, and the 2 delta s^2 part of
        // mu gives -2 delta s/eps^3.
        (delta * (8.0 - 6.0 * s) / eps_v - mu_s / y) / e2
    } else {
        let mu = smooth_mu(y, mu_s, mu_k, eps_v);
        let dmu = -4.0 * delta * (s - 1.0) / eps_v;
        (-mu / e2 + dmu * (2.0 - s) / eps_v) / y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const EPS: f64 = 0.7;

    /// Central difference of `f` at `y`.
    fn fd(f: impl Fn(f64) -> f64, y: f64) -> f64 {
        let h = 1e-6;
        (f(y + h) - f(y - h)) / (2.0 * h)
    }

    fn samples() -> Vec<f64> {
        // Avoid the joints (eps/2, eps), where one-sided derivatives differ at second order.
        (1..200)
            .map(|i| i as f64 * 0.0101 * EPS)
            .filter(|y| (y - EPS).abs() > 1e-4 && (y - 0.5 * EPS).abs() > 1e-4)
            .collect()
    }

    #[test]
    fn f0_f1_f2_are_derivatives() {
        for y in samples() {
            let d0 = fd(|t| smooth_friction_f0(t, EPS), y);
            assert!((d0 - smooth_friction_f1(y, EPS)).abs() < 1e-8, "f1 at {y}");
            let d1 = fd(|t| smooth_friction_f1(t, EPS), y);
            assert!((d1 - smooth_friction_f2(y, EPS)).abs() < 1e-7, "f2 at {y}");
            let r = smooth_friction_f1_over_x(y, EPS) * y;
            assert!((r - smooth_friction_f1(y, EPS)).abs() < 1e-14);
            let c = (smooth_friction_f2(y, EPS) * y - smooth_friction_f1(y, EPS)) / (y * y * y);
            let got = smooth_friction_f2_x_minus_f1_over_x3(y, EPS);
            assert!((c - got).abs() <= 1e-10 * got.abs(), "{c} vs {got} at {y}");
        }
    }

    #[test]
    fn f0_analytic_values() {
        // f0 is C1 at eps_v, with f0(0) = eps/3, f1(eps/2) = 3/4, f2(0) = 2/eps.
        assert!((smooth_friction_f0(0.0, EPS) - EPS / 3.0).abs() < 1e-16);
        assert!((smooth_friction_f0(EPS * (1.0 - 1e-12), EPS) - EPS).abs() < 1e-11);
        assert!((smooth_friction_f1(0.5 * EPS, EPS) - 0.75).abs() < 1e-15);
        assert!((smooth_friction_f2(0.0, EPS) - 2.0 / EPS).abs() < 1e-15);
        assert!((smooth_friction_f1_over_x(0.0, EPS) - 2.0 / EPS).abs() < 1e-15);
        assert_eq!(smooth_friction_f0(-3.0, EPS), 3.0);
        // Below eps, f0(y) - y = (eps - y)^3 / (3 eps^2) >= 0.
        for y in samples() {
            let gap = smooth_friction_f0(y, EPS) - y;
            let exact = if y < EPS {
                (EPS - y).powi(3) / (3.0 * EPS * EPS)
            } else {
                0.0
            };
            assert!((gap - exact).abs() < 1e-14, "{gap} {exact} at {y}");
        }
    }

    #[test]
    fn smooth_mu_pieces() {
        let (ms, mk) = (0.9, 0.4);
        for y in samples() {
            let d = fd(|t| smooth_mu(t, ms, mk, EPS), y);
            assert!(
                (d - smooth_mu_derivative(y, ms, mk, EPS)).abs() < 1e-7,
                "mu' at {y}"
            );
            let g = fd(|t| smooth_mu_f0(t, ms, mk, EPS), y);
            assert!((g - smooth_mu_f1(y, ms, mk, EPS)).abs() < 1e-8, "g1 at {y}");
            let g2 = fd(|t| smooth_mu_f1(t, ms, mk, EPS), y);
            assert!(
                (g2 - smooth_mu_f2(y, ms, mk, EPS)).abs() < 1e-6,
                "g2 at {y}"
            );
            let c = (smooth_mu_f2(y, ms, mk, EPS) * y - smooth_mu_f1(y, ms, mk, EPS)) / y.powi(3);
            let got = smooth_mu_f2_x_minus_mu_f1_over_x3(y, ms, mk, EPS);
            assert!(
                (c - got).abs() <= 1e-9 * got.abs().max(1.0),
                "{c} vs {got} at {y}"
            );
            let r = smooth_mu_f1_over_x(y, ms, mk, EPS) * y;
            assert!((r - smooth_mu_f1(y, ms, mk, EPS)).abs() < 1e-14);
        }
        // Continuity: mu at the joint, g0 at eps and at the joint.
        let h = 1e-12;
        let j = 0.5 * EPS;
        assert!((smooth_mu(j - h, ms, mk, EPS) - smooth_mu(j, ms, mk, EPS)).abs() < 1e-10);
        assert!((smooth_mu(j, ms, mk, EPS) - 0.5 * (ms + mk)).abs() < 1e-15);
        assert!((smooth_mu_f0(EPS - h, ms, mk, EPS) - mk * EPS).abs() < 1e-10);
        assert!((smooth_mu_f0(j - h, ms, mk, EPS) - smooth_mu_f0(j, ms, mk, EPS)).abs() < 1e-10);
        // The integral of mu f1 from 0 to eps by Simpson's rule on each piece.
        let simpson = |a: f64, b: f64| {
            let n = 2000;
            let hh = (b - a) / n as f64;
            let f = |t: f64| smooth_mu_f1(t, ms, mk, EPS);
            let mut s = f(a) + f(b);
            for i in 1..n {
                s += f(a + i as f64 * hh) * if i % 2 == 1 { 4.0 } else { 2.0 };
            }
            s * hh / 3.0
        };
        let integral = simpson(0.0, j) + simpson(j, EPS);
        let got = smooth_mu_f0(EPS, ms, mk, EPS) - smooth_mu_f0(0.0, ms, mk, EPS);
        assert!((integral - got).abs() < 1e-12, "{integral} vs {got}");
    }

    #[test]
    fn equal_coefficients_reduce_to_the_mollifier() {
        for y in samples() {
            assert_eq!(
                smooth_mu_f0(y, 0.5, 0.5, EPS),
                0.5 * smooth_friction_f0(y, EPS)
            );
            assert_eq!(
                smooth_mu_f2_x_minus_mu_f1_over_x3(y, 0.5, 0.5, EPS),
                0.5 * smooth_friction_f2_x_minus_f1_over_x3(y, EPS)
            );
        }
    }
}
