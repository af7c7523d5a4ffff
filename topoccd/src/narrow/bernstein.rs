//! Sign certificates of low-degree polynomials in time, from their Bernstein coefficients.
//!
//! Every quantity the clustering tests is a polynomial in the step's time `t` in `[0, 1]`:
//! a triple product `det(V, P(t), Q(t))` of a fixed direction and two linearly moving vectors is
//! a quadratic (the projected normal `n(t)·V` of a triangle, the star test `g(t)` of a boundary
//! edge), and the paper's characteristic function `phi(t) = n(t)·(v0(t) - O(t))` is a cubic.
//!
//! # Bernstein form
//! A polynomial of degree `d` is `p(t) = sum_i b_i C(d, i) t^i (1 - t)^(d - i)`. On `[0, 1]` the
//! basis functions are non-negative and sum to one, so `p(t)` is a convex combination of the
//! `b_i`: `min b_i <= p(t) <= max b_i`, and `p(0) = b_0`, `p(1) = b_d`. If every `b_i > 0`, then
//! `p > 0` on `[0, 1]`. De Casteljau's algorithm splits `[0, 1]` at `1/2` into two halves with
//! their own coefficients, which converge to the polynomial's values: inconclusive signs can be
//! settled by subdividing a few times.
//!
//! With linear `P(t) = P0 (1 - t) + P1 t` and `Q(t)` alike, `P x Q` has the Bernstein
//! coefficients `P0 x Q0`, `(P0 x Q1 + P1 x Q0) / 2`, `P1 x Q1`; multiplying the quadratic
//! `N(t)` by the linear `W(t)` gives the cubic coefficients `N0·W0`, `(2 N1·W0 + N0·W1) / 3`,
//! `(N2·W0 + 2 N1·W1) / 3`, `N2·W1`.
//!
//! # Rounding error (a priori bounds)
//! Write `u = 2^-53` and `gamma_k = k u / (1 - k u)`. A computed sum of products whose every term
//! went through at most `k` correctly rounded operations (counting the rounding of the input
//! differences) is within `gamma_k` times the sum of the absolute values of its exact terms of the
//! exact value (Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., section 3.1).
//!
//! - Triple product, `b_0 = V·(P0 x Q0)`: each of its 6 terms `V_i P_j Q_k` goes through the
//!   subtractions that form `P` and `Q` (2), the product `P_j Q_k` (1), the difference of the two
//!   products of a cross-product component (1), the product by `V_i` (1) and the sum of three (2):
//!   7 roundings. The middle coefficient adds one addition (the halving is exact): 8. The sum of
//!   absolute terms is at most `|V|_1 · 2 p q`, where `p` and `q` bound the absolute coordinates
//!   of `P0, P1` and `Q0, Q1`. So `|error| <= gamma_8 · 2 |V|_1 p q ~ 16 u |V|_1 p q`;
//!   [`TRIPLE_PRODUCT_ERROR`] is 32, twice that.
//! - Cubic `phi`: the longest path (coefficient 1 or 2) forms `P`, `Q` (2), the product and the
//!   difference of the cross product (2), the sum of two cross products (1), `W` (1), the product
//!   by `W_i` (1), the sum of three (2), the weighted sum of two dot products (1) and the division
//!   by 3 (1): 11 roundings. The weighted sum of absolute terms is at most `6 w p q`, where `w`
//!   bounds the coordinates of `W0, W1`. So `|error| <= gamma_11 · 6 w p q ~ 66 u w p q`;
//!   [`CUBIC_ERROR`] is 144, a little over twice that.
//! - Subdivision: each de Casteljau level forms every new coefficient by at most `d` nested
//!   averages `(x + y) / 2`, each adding at most `u max|b|`; averaging never increases the
//!   inherited error. Each level therefore adds `2 d u max|b|` (again twice the bound).
//! - Results in the subnormal range are not relatively accurate; [`UNDERFLOW_ERROR`](crate::math::UNDERFLOW_ERROR) is added
//!   as an absolute allowance.
//!
//! The bounds scale like the coefficients (both are products of the same lengths), so the
//! verdicts do not depend on the unit of length.

use crate::math::{max_abs, DVec3, UNDERFLOW_ERROR, UNIT_ROUNDOFF};

/// Error bound of a triple-product coefficient, in units of `u |V|_1 p q` (analysis: 16).
pub const TRIPLE_PRODUCT_ERROR: f64 = 32.0;
/// Error bound of a `phi` coefficient, in units of `u w p q` (analysis: 66).
pub const CUBIC_ERROR: f64 = 144.0;

/// A polynomial of degree `N - 1` on `[0, 1]`, by its computed Bernstein coefficients and a
/// bound on their absolute rounding error: each exact coefficient lies within `error` of the
/// computed one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bernstein<const N: usize> {
    /// Computed coefficients `b_0 ..= b_{N-1}`; `b_0 = p(0)` and `b_{N-1} = p(1)`.
    pub coeffs: [f64; N],
    /// Bound on `|computed - exact|` of every coefficient, `>= 0`, in the coefficients' units.
    pub error: f64,
}

/// The answer of a sign certificate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The property holds on all of `[0, 1]` (see each test for what exactly is guaranteed).
    Holds,
    /// The property fails: some value of the polynomial is certainly on the wrong side.
    Fails,
    /// Neither could be established within the subdivision budget.
    Undecided,
}

impl<const N: usize> Bernstein<N> {
    /// Exact polynomial value at `t` (in floating point, for tests and diagnostics), by de
    /// Casteljau's algorithm.
    pub fn eval(&self, t: f64) -> f64 {
        let mut b = self.coeffs;
        for level in 1..N {
            for i in 0..N - level {
                b[i] = b[i] * (1.0 - t) + b[i + 1] * t;
            }
        }
        b[0]
    }

    /// The two halves `[0, 1/2]` and `[1/2, 1]`, each reparametrised to `[0, 1]`, with the
    /// error bound grown as the module documentation derives.
    pub fn split(&self) -> (Self, Self) {
        let mut left = [0.0; N];
        let mut right = [0.0; N];
        let mut b = self.coeffs;
        let mut largest = 0.0f64;
        for level in 0..N {
            left[level] = b[0];
            right[N - 1 - level] = b[N - 1 - level];
            for i in 0..N - 1 - level {
                b[i] = (b[i] + b[i + 1]) * 0.5;
            }
        }
        for x in self.coeffs {
            largest = largest.max(x.abs());
        }
        let grown = self.error + 2.0 * (N as f64) * UNIT_ROUNDOFF * largest * (1.0 + 1e-12);
        (
            Self {
                coeffs: left,
                error: grown,
            },
            Self {
                coeffs: right,
                error: grown,
            },
        )
    }

    /// Certifies `p(t) > 0` for every `t` in `[0, 1]` (in exact arithmetic), subdividing at most
    /// `subdivisions` times where the coefficients are inconclusive. [`Verdict::Fails`] means
    /// `p(t) < 0` for some `t` is certain.
    pub fn positive(&self, subdivisions: u32) -> Verdict {
        let e = self.error;
        if self.coeffs.iter().all(|&b| b > e) {
            return Verdict::Holds;
        }
        if self.coeffs[0] < -e || self.coeffs[N - 1] < -e {
            return Verdict::Fails;
        }
        if subdivisions == 0 || !self.coeffs.iter().all(|b| b.is_finite()) {
            return Verdict::Undecided;
        }
        let (l, r) = self.split();
        combine(l.positive(subdivisions - 1), r.positive(subdivisions - 1))
    }

    /// Tests `p(t) >= 0` on `[0, 1]` up to rounding: [`Verdict::Holds`] when every computed
    /// coefficient (of the whole interval or of its pieces after at most `subdivisions`
    /// splittings) is at least `-error`, so the exact `p >= -2 error` on `[0, 1]`.
    /// [`Verdict::Fails`] means `p(t) < 0` for some `t` is certain. This is the non-strict
    /// test of the paper's criterion, which tolerates exactly coplanar (flat) patches, where the
    /// exact `p` is zero.
    pub fn nonnegative(&self, subdivisions: u32) -> Verdict {
        let e = self.error;
        if self.coeffs.iter().all(|&b| b >= -e) {
            return Verdict::Holds;
        }
        if self.coeffs[0] < -e || self.coeffs[N - 1] < -e {
            return Verdict::Fails;
        }
        if subdivisions == 0 || !self.coeffs.iter().all(|b| b.is_finite()) {
            return Verdict::Undecided;
        }
        let (l, r) = self.split();
        combine(
            l.nonnegative(subdivisions - 1),
            r.nonnegative(subdivisions - 1),
        )
    }
}

/// A property holds on `[0, 1]` iff it holds on both halves, fails iff it fails on one.
fn combine(a: Verdict, b: Verdict) -> Verdict {
    match (a, b) {
        (Verdict::Fails, _) | (_, Verdict::Fails) => Verdict::Fails,
        (Verdict::Holds, Verdict::Holds) => Verdict::Holds,
        _ => Verdict::Undecided,
    }
}

/// Largest absolute coordinate of two vectors.
#[inline]
fn max_abs2(a: DVec3, b: DVec3) -> f64 {
    max_abs(a).max(max_abs(b))
}

/// The quadratic `det(direction, P(t), Q(t)) = direction · (P(t) x Q(t))` for `P`, `Q` moving
/// linearly from `p_t0`, `q_t0` to `p_t1`, `q_t1`. The differences forming `P`, `Q` must each be
/// one rounded subtraction of exact inputs (or exact), as the error bound assumes.
#[inline]
pub fn triple_product(
    direction: DVec3,
    p_t0: DVec3,
    p_t1: DVec3,
    q_t0: DVec3,
    q_t1: DVec3,
) -> Bernstein<3> {
    let b0 = direction.dot(p_t0.cross(q_t0));
    let b1 = (direction.dot(p_t0.cross(q_t1)) + direction.dot(p_t1.cross(q_t0))) * 0.5;
    let b2 = direction.dot(p_t1.cross(q_t1));
    let v1 = direction.x.abs() + direction.y.abs() + direction.z.abs();
    let error =
        TRIPLE_PRODUCT_ERROR * UNIT_ROUNDOFF * v1 * max_abs2(p_t0, p_t1) * max_abs2(q_t0, q_t1)
            + UNDERFLOW_ERROR;
    Bernstein {
        coeffs: [b0, b1, b2],
        error,
    }
}

/// `n(t) · direction` for the triangle `tri` (corners `a, b, c`, normal `(b - a) x (c - a)`),
/// moving linearly from `tri_t0` to `tri_t1`. Positive means the triangle faces along
/// `direction`, i.e. its projection along `direction` is counter-clockwise seen from its tip.
#[inline]
pub fn normal_along(direction: DVec3, tri_t0: &[DVec3; 3], tri_t1: &[DVec3; 3]) -> Bernstein<3> {
    triple_product(
        direction,
        tri_t0[1] - tri_t0[0],
        tri_t1[1] - tri_t1[0],
        tri_t0[2] - tri_t0[0],
        tri_t1[2] - tri_t1[0],
    )
}

/// The star test `g(t) = direction · ((a(t) - c(t)) x (b(t) - c(t)))` of the directed segment
/// `a -> b` around the centre `c`, all three moving linearly (`[t0, t1]` pairs). Positive means
/// the projection of `a -> b` turns counter-clockwise around the projection of `c`.
#[inline]
pub fn star_around(direction: DVec3, a: [DVec3; 2], b: [DVec3; 2], c: [DVec3; 2]) -> Bernstein<3> {
    triple_product(
        direction,
        a[0] - c[0],
        a[1] - c[1],
        b[0] - c[0],
        b[1] - c[1],
    )
}

/// The paper's characteristic function (equation 1) `phi(t) = n(t) · (v0(t) - O(t))` of the
/// triangle `tri` (moving from `tri_t0` to `tri_t1`) with respect to the observation point `O`
/// (moving from `o[0]` to `o[1]`), as a cubic. `phi >= 0` means `O` is on the back side of the
/// triangle's plane.
#[inline]
pub fn phi(tri_t0: &[DVec3; 3], tri_t1: &[DVec3; 3], o: [DVec3; 2]) -> Bernstein<4> {
    let (p0, p1) = (tri_t0[1] - tri_t0[0], tri_t1[1] - tri_t1[0]);
    let (q0, q1) = (tri_t0[2] - tri_t0[0], tri_t1[2] - tri_t1[0]);
    let (w0, w1) = (tri_t0[0] - o[0], tri_t1[0] - o[1]);
    let n0 = p0.cross(q0);
    let n1 = (p0.cross(q1) + p1.cross(q0)) * 0.5;
    let n2 = p1.cross(q1);
    let coeffs = [
        n0.dot(w0),
        (2.0 * n1.dot(w0) + n0.dot(w1)) / 3.0,
        (n2.dot(w0) + 2.0 * n1.dot(w1)) / 3.0,
        n2.dot(w1),
    ];
    let error =
        CUBIC_ERROR * UNIT_ROUNDOFF * max_abs2(w0, w1) * max_abs2(p0, p1) * max_abs2(q0, q1)
            + UNDERFLOW_ERROR;
    Bernstein { coeffs, error }
}

/// The Bernstein coefficients on `[0, 1]` of the cubic `p(t) . (a(t) x b(t))` for `p`, `a`, `b`
/// moving linearly from their `[t0, t1]` values: the signed volume of the four points of a
/// vertex-face or edge-edge pair, zero when they are coplanar. Each coefficient is a sum of
/// triple products of end values; callers bound its rounding by their own analysis (it is
/// independent of the order of the sums).
#[inline]
pub fn coplanarity(p: [DVec3; 2], a: [DVec3; 2], b: [DVec3; 2]) -> [f64; 4] {
    let n = [a[0].cross(b[0]), a[1].cross(b[1])];
    let [c0, c3] = coplanarity_ends(p, n);
    let [c1, c2] = coplanarity_inner(p, a, b, n);
    [c0, c1, c2, c3]
}

/// The first and last coefficients of [`coplanarity`], the cubic's values at the ends, given
/// the normals `n = [a[0] x b[0], a[1] x b[1]]` (bit for bit as [`coplanarity`] computes them).
#[inline]
pub fn coplanarity_ends(p: [DVec3; 2], n: [DVec3; 2]) -> [f64; 2] {
    [p[0].dot(n[0]), p[1].dot(n[1])]
}

/// The two middle coefficients of [`coplanarity`], given the normals of
/// [`coplanarity_ends`] (bit for bit as [`coplanarity`] computes them).
#[inline]
pub fn coplanarity_inner(p: [DVec3; 2], a: [DVec3; 2], b: [DVec3; 2], n: [DVec3; 2]) -> [f64; 2] {
    let n01 = a[0].cross(b[1]);
    let n10 = a[1].cross(b[0]);
    [
        (p[1].dot(n[0]) + p[0].dot(n10) + p[0].dot(n01)) / 3.0,
        (p[0].dot(n[1]) + p[1].dot(n10) + p[1].dot(n01)) / 3.0,
    ]
}
