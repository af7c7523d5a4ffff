//! A cheap conservative filter run before the elementary tests. It first looks for one fixed
//! direction along which the features stay apart at both ends of the step, hence throughout
//! (see `direction_separated`; this rejects most neighbours in a mesh). Then it runs the
//! deforming non-penetration filter (Tang et al. 2010), which proves a pair separated when the
//! vertex stays strictly on one side of the face's plane (or one edge on one side of the plane
//! through the other edge parallel to both) during the whole step, farther than
//! `min_separation`. (Over a short start of the step, the filter's first test goes before the
//! direction's; see `separated`.)
//!
//! For a vertex and a face, `f(t) = p(t) . (a(t) x b(t))` with `p = v - f0`, `a = f1 - f0`,
//! `b = f2 - f0` is the vertex's height over the face's plane times `|n(t)|`, `n = a x b`. For
//! two edges, `p = eb0 - ea0`, `a = ea1 - ea0`, `b = eb1 - eb0` give the distance between the
//! edges' lines times `|n(t)|`. Both are cubics in `t`, and with linear `p, a, b` their four
//! Bernstein coefficients on `[0, 1]` are sums of triple products of the end values. A cubic
//! lies between its smallest and largest Bernstein coefficient, and `|n(t)|` is at most the
//! largest norm of the Bernstein coefficients of the quadratic `n`. So if every coefficient of
//! `f` exceeds `min_separation * N` (or every one is below `-min_separation * N`), the plane
//! (or line) distance stays above `min_separation`, and so does the distance between the
//! features, which lie in that plane (on those lines).
//!
//! Rounding: each triple product of computed differences is within `54 u P A B` of the exact
//! one (`u = 2^-53`; `P, A, B` the largest coordinates of `p, a, b`); the filter demands a
//! margin of `256 u P A B`, and pads `N` likewise, so it never rejects a pair that comes within
//! `min_separation` in exact arithmetic. It rejects only; a pair it passes goes to the solver.

use crate::math::{lerp, max_abs, DVec3, UNDERFLOW_ERROR, UNIT_ROUNDOFF};
use super::bernstein::coplanarity;
use super::extremes::{lower, lower3, raise, raise3, raise_abs};
use super::{EdgeEdge, VertexFace};

/// Margin on the coefficients, in units of `u P A B`.
const COEFFICIENT_ERROR: f64 = 256.0;

/// How many times the step is halved, at most, where the cubic changes sign (`2^DEPTH`
/// pieces).
const DEPTH: u32 = 3;

/// The four points of a pair (vertex and face corners, or edge ends) at t=0 and t=1.
type Points = [[DVec3; 4]; 2];

/// `true` when, along one fixed direction `d` (from the first feature's mean point over the
/// step to the second's, times `S (N - S)`), the features' projections lie apart by more than
/// `sep |d|` at t=0 and at t=1, on the same side. Then they do so during the whole step: each
/// point's projection is linear in `t`, so the smallest projection of the one feature is
/// concave in `t`, the largest of the other convex, and their difference, concave, stays above
/// its smaller end value. The distance between the features is at least that difference over
/// `|d|`. The first feature is points `..S` of `pts`, the second the other `N - S`.
///
/// Rounding: each computed projection is within `3 u |d|_1 M` of the exact one (`M` the
/// largest coordinate), and the difference of two within `8 u |d|_1 M`; the test demands twice
/// that more, and pads `|d|`. The direction itself needs no care: any `d` serves.
///
/// Over `[0, t_end]` (`t_end` a power of two at most 1), the second end is the interpolated
/// position at `t_end`, off by at most `3 u M` per coordinate (the scaling by a power of two is
/// exact): the margin grows to `48 u |d|_1 M`. `coord` is `M`, the largest coordinate (or
/// anything larger).
#[inline]
fn direction_separated<const N: usize, const S: usize>(
    pts: &[[DVec3; N]; 2],
    sep: f64,
    t_end: f64,
    coord: f64,
) -> bool {
    let (mut first, mut second) = (DVec3::ZERO, DVec3::ZERO);
    for (k, (&p0, &p1)) in pts[0].iter().zip(&pts[1]).enumerate() {
        if k < S {
            first += p0 + p1;
        } else {
            second += p0 + p1;
        }
    }
    let d = second * S as f64 - first * (N - S) as f64;
    let rounding = if t_end < 1.0 { 48.0 } else { 16.0 };
    // (No square root without a separation: a `d` that is not finite still makes `need`
    // infinite or NaN through its 1-norm, and nothing passes.)
    let length = if sep > 0.0 { d.length() } else { 0.0 };
    let need = sep * length * (1.0 + 4.0 * UNIT_ROUNDOFF)
        + rounding * UNIT_ROUNDOFF * d.abs().element_sum() * coord
        + UNDERFLOW_ERROR;
    let last: [DVec3; N] = if t_end < 1.0 {
        std::array::from_fn(|k| lerp(pts[0][k], pts[1][k], t_end))
    } else {
        pts[1]
    };
    // Whether the second feature lies above the first along `d` at both ends, and below.
    let (mut above, mut below) = (true, true);
    for end in [&pts[0], &last] {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for (k, p) in end.iter().enumerate() {
            let f = usize::from(k >= S);
            let x = d.dot(*p);
            lo[f] = lower(lo[f], x);
            hi[f] = raise(hi[f], x);
        }
        above &= lo[1] - hi[0] > need;
        below &= lo[0] - hi[1] > need;
    }
    above || below
}

/// `true` when the pair provably stays farther apart than `sep` over the whole step: apart
/// along a fixed direction ([`direction_separated`]), or, on every piece of the step, either the cubic `p . (a x b)` (each of `p, a, b` linear from `_0` at
/// t=0 to `_1` at t=1) keeps its sign beyond the margin, or the axis-aligned boxes of the
/// features over that piece stay farther apart than `sep`.
#[inline]
fn separated(
    p: [DVec3; 2],
    a: [DVec3; 2],
    b: [DVec3; 2],
    sep: f64,
    pts: &Points,
    split: usize,
    t_end: f64,
) -> bool {
    let t_end = dyadic_end(t_end);
    // The largest coordinate of the points (`M` of the rounding bounds).
    let coord = pts.iter().flatten().fold(0.0, |m, x| raise_abs(m, *x));
    let apart = || {
        if split == 1 {
            direction_separated::<4, 1>(pts, sep, t_end, coord)
        } else {
            direction_separated::<4, 2>(pts, sep, t_end, coord)
        }
    };
    // Over the whole step the direction test rejects most pairs, and goes first. Over a short
    // start of it (an Earliest query's first pass, or one pruned by its best time) the features
    // have barely moved and the cubic, near the static plane distance, rejects most: on
    // cloth-ball's Earliest query 312K of 376K candidates, the direction 64K. There the
    // cubic's first test goes first. Either order rejects exactly the same pairs.
    let short = t_end <= SHORT;
    if !short && apart() {
        return true;
    }
    let mut c = coplanarity(p, a, b);
    let pm = max_abs(p[0]).max(max_abs(p[1]));
    let am = max_abs(a[0]).max(max_abs(a[1]));
    let bm = max_abs(b[0]).max(max_abs(b[1]));
    let ab = am * bm;
    let cm = c.iter().fold(0.0, |m, x| raise(m, x.abs()));
    // Rounding of the triple products, then of up to DEPTH levels of halving (and of the
    // split at `t_end`, three levels of interpolation between values at most `cm`).
    let mut margin = COEFFICIENT_ERROR * UNIT_ROUNDOFF * pm * ab
        + 4.0 * (DEPTH + 4) as f64 * UNIT_ROUNDOFF * cm
        + UNDERFLOW_ERROR;
    if t_end < 1.0 {
        // De Casteljau at `t_end`: the coefficients of the cubic on `[0, t_end]`.
        let l = |x: f64, y: f64| x + (y - x) * t_end;
        let (c01, c12, c23) = (l(c[0], c[1]), l(c[1], c[2]), l(c[2], c[3]));
        let (c012, c123) = (l(c01, c12), l(c12, c23));
        c = [c[0], c01, c012, l(c012, c123)];
    }
    if sep > 0.0 {
        // The normal n(t) = a(t) x b(t), a quadratic: its Bernstein coefficients.
        let n00 = a[0].cross(b[0]);
        let n11 = a[1].cross(b[1]);
        let n1 = 0.5 * (a[0].cross(b[1]) + a[1].cross(b[0]));
        let norm = n00.length().max(n1.length()).max(n11.length());
        margin += sep * (norm + COEFFICIENT_ERROR * UNIT_ROUNDOFF * ab);
    }
    if short && (keeps_sign(c, margin) || apart()) {
        return true;
    }
    let piece = Piece {
        pts,
        split,
        sep,
        margin,
        // Each interpolated coordinate `a + (b - a) t` is within `5 u M` of the exact one
        // (`M` the largest coordinate): two roundings of at most `2 u M`, one of `u M`.
        pad: 8.0 * UNIT_ROUNDOFF * coord,
    };
    piece.separated(c, 0.0, t_end, 0)
}

/// The smallest power of two at least `t` (1 for `t >= 1` or NaN, and at least
/// [`DYADIC_FLOOR`]), so that the pieces' ends `k t_end / 2^DEPTH` are exact and the cubic's
/// coefficients on each piece describe exactly the piece whose boxes are tested.
#[inline]
fn dyadic_end(t: f64) -> f64 {
    if t.is_nan() || t >= 1.0 {
        return 1.0;
    }
    if t <= DYADIC_FLOOR {
        return DYADIC_FLOOR;
    }
    // `t` is positive and normal: clearing its mantissa gives the power of two at most `t`.
    let below = f64::from_bits(t.to_bits() & 0x7ff0_0000_0000_0000);
    if below == t {
        t
    } else {
        2.0 * below
    }
}

/// The longest start of the step (a power of two) over which [`separated`] tests the cubic
/// before the direction.
const SHORT: f64 = 1.0 / 16.0;

/// The smallest end [`dyadic_end`] gives, `2^-897` (the first power of two below `1e-270`):
/// far above the subnormals, so the pieces' ends stay exact.
const DYADIC_FLOOR: f64 = f64::from_bits((1023 - 897) << 52);

/// Whether every Bernstein coefficient `c` of a cubic exceeds `margin`, or every one is below
/// `-margin`: then so is the cubic over its interval.
#[inline]
fn keeps_sign(c: [f64; 4], margin: f64) -> bool {
    let (lo, hi) = (
        c[0].min(c[1]).min(c[2].min(c[3])),
        c[0].max(c[1]).max(c[2].max(c[3])),
    );
    lo > margin || hi < -margin
}

/// The fixed data of the recursive check of one pair.
struct Piece<'a> {
    pts: &'a Points,
    /// Points `..split` form the first feature, `split..` the second.
    split: usize,
    sep: f64,
    margin: f64,
    pad: f64,
}

impl Piece<'_> {
    /// Whether the pair stays apart during `[ta, tb]`, where `c` are the cubic's Bernstein
    /// coefficients on that interval.
    fn separated(&self, c: [f64; 4], ta: f64, tb: f64, depth: u32) -> bool {
        if keeps_sign(c, self.margin) {
            return true;
        }
        if depth > 0 && self.boxes_apart(ta, tb) {
            return true;
        }
        if depth == DEPTH {
            return false;
        }
        // De Casteljau at the midpoint.
        let m01 = 0.5 * (c[0] + c[1]);
        let m12 = 0.5 * (c[1] + c[2]);
        let m23 = 0.5 * (c[2] + c[3]);
        let m012 = 0.5 * (m01 + m12);
        let m123 = 0.5 * (m12 + m23);
        let mid = 0.5 * (m012 + m123);
        let tm = 0.5 * (ta + tb);
        self.separated([c[0], m01, m012, mid], ta, tm, depth + 1)
            && self.separated([mid, m123, m23, c[3]], tm, tb, depth + 1)
    }

    /// Whether the features' boxes over `[ta, tb]` stay farther apart than `sep`.
    fn boxes_apart(&self, ta: f64, tb: f64) -> bool {
        let mut lo = [DVec3::INFINITY; 2];
        let mut hi = [DVec3::NEG_INFINITY; 2];
        for k in 0..4 {
            let f = usize::from(k >= self.split);
            for t in [ta, tb] {
                let x = lerp(self.pts[0][k], self.pts[1][k], t);
                lo[f] = lower3(lo[f], x);
                hi[f] = raise3(hi[f], x);
            }
        }
        let gap = DVec3::splat(self.sep + 2.0 * self.pad);
        (lo[0] - hi[1]).cmpgt(gap).any() || (lo[1] - hi[0]).cmpgt(gap).any()
    }
}

/// `true` when the triangles with corners `a` and `b` (indices into the positions at t=0, `x0`,
/// and at t=1, `x1`) provably stay farther apart than `sep` during `[0, t_end]` (clamped to
/// the whole step; a little more may be looked at): apart along the fixed direction between
/// their mean points over the step ([`direction_separated`], three points a side, the argument
/// unchanged). Then so is every feature of the one from every feature of the other. `coord`
/// is at least the largest absolute coordinate of the six corners at both ends (the rounding
/// bounds hold for any larger `M`, so a caller may pass one bound for a whole step).
#[inline]
pub(crate) fn triangles_separated(
    (x0, x1): (&[DVec3], &[DVec3]),
    a: [u32; 3],
    b: [u32; 3],
    sep: f64,
    t_end: f64,
    coord: f64,
) -> bool {
    let [a0, a1, a2, b0, b1, b2] = [a[0], a[1], a[2], b[0], b[1], b[2]].map(|i| i as usize);
    let pts = [
        [x0[a0], x0[a1], x0[a2], x0[b0], x0[b1], x0[b2]],
        [x1[a0], x1[a1], x1[a2], x1[b0], x1[b1], x1[b2]],
    ];
    direction_separated::<6, 3>(&pts, sep, dyadic_end(t_end), coord)
}

/// `true` when the vertex provably stays farther than `sep` (`>= 0`) from the face during the
/// times `[0, t_end]` (clamped to the whole step; a little more may be looked at).
#[inline]
pub fn vf_separated(q: &VertexFace, sep: f64, t_end: f64) -> bool {
    separated(
        [q.v_t0 - q.f0_t0, q.v_t1 - q.f0_t1],
        [q.f1_t0 - q.f0_t0, q.f1_t1 - q.f0_t1],
        [q.f2_t0 - q.f0_t0, q.f2_t1 - q.f0_t1],
        sep,
        &[
            [q.v_t0, q.f0_t0, q.f1_t0, q.f2_t0],
            [q.v_t1, q.f0_t1, q.f1_t1, q.f2_t1],
        ],
        1,
        t_end,
    )
}

/// `true` when the edges provably stay farther apart than `sep` (`>= 0`) during the times
/// `[0, t_end]` (clamped to the whole step; a little more may be looked at).
#[inline]
pub fn ee_separated(q: &EdgeEdge, sep: f64, t_end: f64) -> bool {
    separated(
        [q.eb0_t0 - q.ea0_t0, q.eb0_t1 - q.ea0_t1],
        [q.ea1_t0 - q.ea0_t0, q.ea1_t1 - q.ea0_t1],
        [q.eb1_t0 - q.eb0_t0, q.eb1_t1 - q.eb0_t1],
        sep,
        &[
            [q.ea0_t0, q.ea1_t0, q.eb0_t0, q.eb1_t0],
            [q.ea0_t1, q.ea1_t1, q.eb0_t1, q.eb1_t1],
        ],
        2,
        t_end,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::narrow::{edge_edge, vertex_face, NarrowOptions};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// `dyadic_end` is the smallest power of two at least `t` (halving 1 until the next half
    /// would be below `t`), 1 at and beyond 1 and for NaN, and never below `2^-897`.
    #[test]
    fn dyadic_end_is_the_next_power_of_two() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let floor = 0.5f64.powi(897);
        assert_eq!(DYADIC_FLOOR, floor);
        let mut ts = vec![f64::NAN, 1.0, 1.5, 0.5, 0.25, 0.3, 1e-6, 0.0, -1.0, 1e-300, floor];
        ts.extend((0..2000).map(|_| 10f64.powf(rng.random_range(-280.0..0.0))));
        ts.extend((1..60).map(|k| 0.5f64.powi(k)));
        for t in ts {
            let end = dyadic_end(t);
            if t.is_nan() || t >= 1.0 {
                assert_eq!(end, 1.0, "{t}");
            } else if t <= floor {
                assert_eq!(end, floor, "{t}");
            } else {
                let power = end.log2();
                assert_eq!(power, power.round(), "{t}: {end} is not a power of two");
                assert!(end >= t && end * 0.5 < t, "{t}: {end}");
            }
        }
    }

    fn point(rng: &mut ChaCha8Rng) -> DVec3 {
        DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
    }

    /// The smallest distance between sampled points of the two features over sampled times
    /// (an upper bound of their true smallest distance).
    fn sampled_distance(q: &[DVec3; 8], vertex_face: bool, t_end: f64) -> f64 {
        let n = 12;
        let mut best = f64::INFINITY;
        for k in 0..=32 {
            let t = t_end * k as f64 / 32.0;
            let x: [DVec3; 4] = std::array::from_fn(|i| lerp(q[i], q[i + 4], t));
            for i in 0..=n {
                for j in 0..=n {
                    let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                    let d = if vertex_face {
                        // The Duffy map u, u v covers the triangle.
                        x[0] - (x[1] + u * (x[2] - x[1]) + u * v * (x[3] - x[2]))
                    } else {
                        (x[0] + u * (x[1] - x[0])) - (x[2] + v * (x[3] - x[2]))
                    };
                    best = best.min(d.length());
                }
            }
        }
        best
    }

    /// The separations and ends of the interval looked at that the tests run over, each with
    /// the solver's options for it.
    fn cases() -> impl Iterator<Item = (f64, f64, NarrowOptions)> {
        let cases = [(0.0, 1.0), (0.05, 1.0), (0.0, 0.3), (0.05, 0.01)];
        cases.into_iter().map(|(sep, t_end)| {
            let options = NarrowOptions {
                min_separation: sep,
                t_max: t_end,
                ..NarrowOptions::default()
            };
            (sep, t_end, options)
        })
    }

    /// Asserts that the vertex-face (`vf`) or edge-edge pair of `pts` (four points at t=0, then
    /// the same at t=1) has no contact over `[0, t_end]`, by the solver and by sampled
    /// distances above `sep`.
    fn assert_apart(pts: [DVec3; 8], vf: bool, sep: f64, t_end: f64, options: &NarrowOptions) {
        if vf {
            let q = VertexFace::from_points(pts);
            assert!(!vertex_face(&q, options).is_contact(), "{q:?}");
        } else {
            let q = EdgeEdge::from_points(pts);
            assert!(!edge_edge(&q, options).is_contact(), "{q:?}");
        }
        assert!(sampled_distance(&pts, vf, t_end) > sep, "{pts:?}");
    }

    /// Whenever the filter rejects over `[0, t_end]`, sampled distances over that interval
    /// exceed `sep` and the solver finds no contact there either.
    #[test]
    fn rejections_are_separated() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (mut rejected, mut total) = (0, 0);
        for (sep, t_end, options) in cases() {
            for _ in 0..3000 {
                // Small features moving a lot, as in a crumpled cloth.
                let base = point(&mut rng);
                let pts: [DVec3; 8] = std::array::from_fn(|i| {
                    let jitter = 0.3 * point(&mut rng);
                    if i < 4 {
                        base + jitter
                    } else {
                        base + jitter + 0.4 * point(&mut rng)
                    }
                });
                total += 2;
                if vf_separated(&VertexFace::from_points(pts), sep, t_end) {
                    rejected += 1;
                    assert_apart(pts, true, sep, t_end, &options);
                }
                if ee_separated(&EdgeEdge::from_points(pts), sep, t_end) {
                    rejected += 1;
                    assert_apart(pts, false, sep, t_end, &options);
                }
            }
        }
        assert!(
            rejected > total / 4,
            "the filter should reject often: {rejected} of {total}"
        );
    }

    /// Whenever two triangles are found apart over `[0, t_end]`, every vertex of the one is
    /// apart from the other face, and every edge from every edge, by the solver and by sampled
    /// distances: the rule drops no contact.
    #[test]
    fn triangles_found_apart_have_no_feature_pair_in_contact() {
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let (mut rejected, mut total) = (0, 0);
        for (sep, t_end, options) in cases() {
            for _ in 0..1500 {
                let base = point(&mut rng);
                // Corners 0..3 the first triangle, 3..6 the second, at t=0 then t=1.
                let x0: Vec<DVec3> = (0..6).map(|_| base + 0.4 * point(&mut rng)).collect();
                let x1: Vec<DVec3> = x0.iter().map(|&p| p + 0.4 * point(&mut rng)).collect();
                let coord = x0.iter().chain(&x1).fold(0.0, |m, p| raise_abs(m, *p));
                let (a, b) = ([0, 1, 2], [3, 4, 5]);
                total += 1;
                if !triangles_separated((&x0, &x1), a, b, sep, t_end, coord) {
                    continue;
                }
                rejected += 1;
                // The points of four corners, at t=0 then at t=1.
                let at = |c: [u32; 4]| -> [DVec3; 8] {
                    std::array::from_fn(|i| if i < 4 { x0[c[i] as usize] } else { x1[c[i - 4] as usize] })
                };
                for (tv, tf) in [(a, b), (b, a)] {
                    for v in tv {
                        assert_apart(at([v, tf[0], tf[1], tf[2]]), true, sep, t_end, &options);
                    }
                }
                for k in 0..3 {
                    for l in 0..3 {
                        let pts = at([a[k], a[(k + 1) % 3], b[l], b[(l + 1) % 3]]);
                        assert_apart(pts, false, sep, t_end, &options);
                    }
                }
            }
        }
        assert!(
            rejected > total / 10 && rejected < total,
            "the rule should drop some pairs, not all: {rejected} of {total}"
        );
        // A triangle falling onto another from above, level with it: apart while it stays
        // above by more than the separation, never once it passes through.
        let x0 = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let moved = |z0: f64, z1: f64| {
            let up = |z| x0.iter().map(move |&p| p + DVec3::new(0.1, 0.1, z));
            ([&x0[..], &up(z0).collect::<Vec<_>>()].concat(), [&x0[..], &up(z1).collect::<Vec<_>>()].concat())
        };
        let apart = |(p0, p1): (Vec<DVec3>, Vec<DVec3>), sep| {
            triangles_separated((&p0, &p1), [0, 1, 2], [3, 4, 5], sep, 1.0, 2.0)
        };
        assert!(apart(moved(1.0, 0.5), 0.0));
        assert!(apart(moved(1.0, 0.5), 0.3));
        assert!(!apart(moved(1.0, 0.5), 0.55));
        assert!(!apart(moved(1.0, -1.0), 0.0));
    }

    #[test]
    fn a_vertex_through_a_face_passes() {
        let vf = VertexFace {
            v_t0: DVec3::new(0.2, 0.2, 1.0),
            f0_t0: DVec3::ZERO,
            f1_t0: DVec3::X,
            f2_t0: DVec3::Y,
            v_t1: DVec3::new(0.2, 0.2, -1.0),
            f0_t1: DVec3::ZERO,
            f1_t1: DVec3::X,
            f2_t1: DVec3::Y,
        };
        assert!(!vf_separated(&vf, 0.0, 1.0));
        // It crosses the face's plane at t = 0.5: apart before, not after (the interval is
        // rounded up to a power of two).
        assert!(vf_separated(&vf, 0.0, 0.2));
        assert!(vf_separated(&vf, 0.0, 0.25));
        assert!(!vf_separated(&vf, 0.0, 0.3));
        assert!(!vf_separated(&vf, 0.0, 0.5));
        assert!(!vf_separated(&vf, 0.0, 0.6));
        let above = VertexFace {
            v_t1: DVec3::new(0.2, 0.2, 0.1),
            ..vf
        };
        assert!(vf_separated(&above, 0.0, 1.0));
        assert!(vf_separated(&above, 0.099, 1.0));
        assert!(!vf_separated(&above, 0.1, 1.0));
    }
}
