//! A cheap conservative filter run before the elementary tests. It first looks for one fixed
//! direction along which the features stay apart at both ends of the step, hence throughout
//! (see `direction_separated`; this rejects most neighbours in a mesh). Then it runs the
//! deforming non-penetration filter (Tang et al. 2010), which proves a pair separated when the
//! vertex stays strictly on one side of the face's plane (or one edge on one side of the plane
//! through the other edge parallel to both) during the whole step, farther than
//! `min_distance`. (Over a short start of the step, the filter's first test goes before the
//! direction's; see `separated`.) A traversal task runs these two first tests on four pairs at
//! once (`first_tests_x4`, each pair's verdict bit for bit its own), and where the filter does
//! not find a pair apart it says from when the elementary test must search (`unresolved`).
//!
//! For a vertex and a face, `f(t) = p(t) . (a(t) x b(t))` with `p = v - f0`, `a = f1 - f0`,
//! `b = f2 - f0` is the vertex's height over the face's plane times `|n(t)|`, `n = a x b`. For
//! two edges, `p = eb0 - ea0`, `a = ea1 - ea0`, `b = eb1 - eb0` give the distance between the
//! edges' lines times `|n(t)|`. Both are cubics in `t`, and with linear `p, a, b` their four
//! Bernstein coefficients on `[0, 1]` are sums of triple products of the end values. A cubic
//! lies between its smallest and largest Bernstein coefficient, and `|n(t)|` is at most the
//! largest norm of the Bernstein coefficients of the quadratic `n`. So if every coefficient of
//! `f` exceeds `min_distance * N` (or every one is below `-min_distance * N`), the plane
//! (or line) distance stays above `min_distance`, and so does the distance between the
//! features, which lie in that plane (on those lines).
//!
//! Rounding: each triple product of computed differences is within `54 u P A B` of the exact
//! one (`u = 2^-53`; `P, A, B` the largest coordinates of `p, a, b`); the filter demands a
//! margin of `256 u P A B`, and pads `N` likewise, so it never rejects a pair that comes within
//! `min_distance` in exact arithmetic. It rejects only; a pair it passes goes to the solver.

use crate::math::{lerp, DVec3, UNDERFLOW_ERROR, UNIT_ROUNDOFF};
use super::extremes::{lower3, raise3, raise_abs};
use super::lanes::{Real, Vector, F4, V3};
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
/// The test runs on one pair (`T = f64`) or on four side by side (`T = F4`, each lane exactly
/// as one pair alone); it answers per lane.
#[inline(always)]
fn direction_separated<T: Real, V: Vector<R = T>, const N: usize, const S: usize>(
    pts: &[[V; N]; 2],
    sep: f64,
    t_end: f64,
    coord: T,
) -> T::Mask {
    let (mut first, mut second) = (V::zero(), V::zero());
    for (k, (&p0, &p1)) in pts[0].iter().zip(&pts[1]).enumerate() {
        if k < S {
            first = first + (p0 + p1);
        } else {
            second = second + (p0 + p1);
        }
    }
    let d = second.scale(T::splat(S as f64)) - first.scale(T::splat((N - S) as f64));
    let rounding = if t_end < 1.0 { 48.0 } else { 16.0 };
    // (No square root without a separation: a `d` that is not finite still makes `need`
    // infinite or NaN through its 1-norm, and nothing passes.)
    let length = if sep > 0.0 { d.length() } else { T::splat(0.0) };
    let need = T::splat(sep) * length * T::splat(1.0 + 4.0 * UNIT_ROUNDOFF)
        + T::splat(rounding * UNIT_ROUNDOFF) * d.abs_sum() * coord
        + T::splat(UNDERFLOW_ERROR);
    let last: [V; N] = if t_end < 1.0 {
        let t = T::splat(t_end);
        std::array::from_fn(|k| pts[0][k] + (pts[1][k] - pts[0][k]).scale(t))
    } else {
        pts[1]
    };
    // Whether the second feature lies above the first along `d` at both ends, and below.
    let mut above = None;
    let mut below = None;
    for end in [&pts[0], &last] {
        let mut lo = [T::splat(f64::INFINITY); 2];
        let mut hi = [T::splat(f64::NEG_INFINITY); 2];
        for (k, p) in end.iter().enumerate() {
            let f = usize::from(k >= S);
            let x = d.dot(*p);
            lo[f] = T::lower(lo[f], x);
            hi[f] = T::raise(hi[f], x);
        }
        let (up, down) = ((lo[1] - hi[0]).gt(need), (lo[0] - hi[1]).gt(need));
        above = Some(above.map_or(up, |a| T::and(a, up)));
        below = Some(below.map_or(down, |b| T::and(b, down)));
    }
    match (above, below) {
        (Some(a), Some(b)) => T::or(a, b),
        _ => unreachable!("two ends"),
    }
}

/// The vertex-plane or line-line cubic `p . (a x b)` over `[0, t_end]` (`t_end` a power of two
/// at most 1): its Bernstein coefficients, and the margin they must clear for the pair to be
/// apart by `sep` (see the module documentation). Per lane, as [`direction_separated`].
#[inline(always)]
fn cubic<T: Real, V: Vector<R = T>>(p: [V; 2], a: [V; 2], b: [V; 2], sep: f64, t_end: f64) -> ([T; 4], T) {
    // The coefficients, as `bernstein::coplanarity` computes them.
    let n = [a[0].cross(b[0]), a[1].cross(b[1])];
    let n01 = a[0].cross(b[1]);
    let n10 = a[1].cross(b[0]);
    let third = T::splat(3.0);
    let mut c = [
        p[0].dot(n[0]),
        (p[1].dot(n[0]) + p[0].dot(n10) + p[0].dot(n01)) / third,
        (p[0].dot(n[1]) + p[1].dot(n10) + p[1].dot(n01)) / third,
        p[1].dot(n[1]),
    ];
    let pm = p[0].max_abs().max(p[1].max_abs());
    let am = a[0].max_abs().max(a[1].max_abs());
    let bm = b[0].max_abs().max(b[1].max_abs());
    let ab = am * bm;
    let cm = c.iter().fold(T::splat(0.0), |m, &x| T::raise(m, x.abs()));
    // Rounding of the triple products, then of up to DEPTH levels of halving (and of the
    // split at `t_end`, three levels of interpolation between values at most `cm`).
    let mut margin = T::splat(COEFFICIENT_ERROR * UNIT_ROUNDOFF) * pm * ab
        + T::splat(4.0 * (DEPTH + 4) as f64 * UNIT_ROUNDOFF) * cm
        + T::splat(UNDERFLOW_ERROR);
    if t_end < 1.0 {
        // De Casteljau at `t_end`: the coefficients of the cubic on `[0, t_end]`.
        let t = T::splat(t_end);
        let l = |x: T, y: T| x + (y - x) * t;
        let (c01, c12, c23) = (l(c[0], c[1]), l(c[1], c[2]), l(c[2], c[3]));
        let (c012, c123) = (l(c01, c12), l(c12, c23));
        c = [c[0], c01, c012, l(c012, c123)];
    }
    if sep > 0.0 {
        // The normal n(t) = a(t) x b(t), a quadratic: its Bernstein coefficients.
        let half = T::splat(0.5);
        let n1 = (n01 + n10).scale(half);
        let norm = n[0].length().max(n1.length()).max(n[1].length());
        margin = margin + T::splat(sep) * (norm + T::splat(COEFFICIENT_ERROR * UNIT_ROUNDOFF) * ab);
    }
    (c, margin)
}

/// The vectors of the cubic `p . (a x b)` at t=0 and t=1, from the four points of a pair (see
/// the module documentation): a vertex and a face's corners (`S = 1`), or two edges' ends
/// (`S = 2`).
#[inline(always)]
fn differences<V: Vector, const S: usize>(pts: &[[V; 4]; 2]) -> [[V; 2]; 3] {
    let d = |f: fn(&[V; 4]) -> V| [f(&pts[0]), f(&pts[1])];
    if S == 1 {
        [d(|x| x[0] - x[1]), d(|x| x[2] - x[1]), d(|x| x[3] - x[1])]
    } else {
        [d(|x| x[2] - x[0]), d(|x| x[1] - x[0]), d(|x| x[3] - x[2])]
    }
}

/// What is left to check of a pair that the first tests (the direction, the cubic's
/// coefficients over the whole interval) did not reject: those coefficients and their margin.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rest {
    c: [f64; 4],
    margin: f64,
}

/// `true` when the pair provably stays farther apart than `sep` over `[0, t_end]` (`t_end` as
/// given, rounded up to a power of two by [`dyadic_end`]): apart along a fixed direction
/// ([`direction_separated`]), or, on every piece of the interval, either the cubic `p . (a x b)`
/// (each of `p, a, b` linear from `_0` at t=0 to `_1` at t=1) keeps its sign beyond the margin,
/// or the axis-aligned boxes of the features over that piece stay farther apart than `sep`.
/// The pair's points are `pts`, the first feature's `..S`.
#[inline]
fn separated<const S: usize>(pts: &Points, sep: f64, t_end: f64, coord: f64) -> bool {
    unresolved::<S>(pts, sep, t_end, coord).is_none()
}

/// [`separated`], telling more when the pair is not found separated: `None` when it is,
/// else the start of the first piece of the interval not proved apart. The pair stays farther
/// apart than `sep` until then (every piece before it is proved apart), so a search for its
/// first contact may start there.
#[inline]
fn unresolved<const S: usize>(pts: &Points, sep: f64, t_end: f64, coord: f64) -> Option<f64> {
    let t_end = dyadic_end(t_end);
    let apart = || direction_separated::<f64, DVec3, 4, S>(pts, sep, t_end, coord);
    // Over the whole step the direction test rejects most pairs, and goes first. Over a short
    // start of it (an Earliest query's first pass, or one pruned by its best time) the features
    // have barely moved and the cubic, near the static plane distance, rejects most: on
    // cloth-ball's Earliest query 312K of 376K candidates, the direction 64K. There the
    // cubic's first test goes first. Either order rejects exactly the same pairs.
    let short = t_end <= SHORT;
    if !short && apart() {
        return None;
    }
    let [p, a, b] = differences::<DVec3, S>(pts);
    let (c, margin) = cubic(p, a, b, sep, t_end);
    if short && (keeps_sign(c, margin) || apart()) {
        return None;
    }
    rest_unresolved(pts, S, sep, t_end, coord, Rest { c, margin })
}

/// The first tests of [`unresolved`] on four pairs at once, each pair's verdict exactly the
/// one it gets alone: pair `i` has the points `x0[corners[i][k]]` at t=0 and
/// `x1[corners[i][k]]` at t=1, the first feature's `k < S` (`S = 1`: a vertex against the face
/// with corners `corners[i][1..]`; `S = 2`: the edge from `corners[i][0]` to `corners[i][1]`
/// against the one from `corners[i][2]` to `corners[i][3]`); see [`Firsts`]. `coord` is at
/// least the largest absolute coordinate of every pair's points (the rounding bounds hold for
/// any larger `M`, so a caller may pass one bound for a whole step). With AVX2 the four go side
/// by side in vector registers.
#[inline]
pub(crate) fn first_tests_x4<const S: usize>(
    x: (&[DVec3], &[DVec3]),
    corners: &[[u32; 4]; 4],
    sep: f64,
    t_end: f64,
    coord: f64,
) -> Firsts {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, just checked.
        return unsafe { first_tests_x4_avx2::<S>(x, corners, sep, t_end, coord) };
    }
    first_tests_x4_lanes::<S>(gather(x.0, x.1, corners), sep, t_end, coord)
}

/// [`first_tests_x4_lanes`] compiled for AVX2, the points gathered with AVX2's gathers.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn first_tests_x4_avx2<const S: usize>(
    (x0, x1): (&[DVec3], &[DVec3]),
    corners: &[[u32; 4]; 4],
    sep: f64,
    t_end: f64,
    coord: f64,
) -> Firsts {
    use std::arch::x86_64::{_mm256_i64gather_pd, _mm256_set_epi64x, _mm256_storeu_pd};
    const _: () = assert!(std::mem::size_of::<DVec3>() == 24);
    const _: () = assert!(std::mem::align_of::<DVec3>() == 8);
    let n = x0.len().min(x1.len());
    if corners.iter().flatten().any(|&c| c as usize >= n) {
        // (Never with a valid step; the indexing below then panics as the scalar path does.)
        return first_tests_x4_lanes::<S>(gather(x0, x1, corners), sep, t_end, coord);
    }
    let at = |x: &[DVec3], k: usize| {
        let i = |l: usize| 3 * i64::from(corners[l][k]);
        let index = _mm256_set_epi64x(i(3), i(2), i(1), i(0));
        let base = x.as_ptr().cast::<f64>();
        let coordinate = |c: usize| {
            let mut lanes = [0.0; 4];
            // SAFETY: `DVec3` is three `f64` without padding (size and alignment checked
            // above), so `base` points at `3 x.len()` aligned `f64`; every corner is below
            // `x.len()` (checked above), so each gathered `base[3 corner + c]`, `c < 3`, lies
            // inside `x`.
            unsafe { _mm256_storeu_pd(lanes.as_mut_ptr(), _mm256_i64gather_pd::<8>(base.add(c), index)) };
            F4(lanes)
        };
        V3 {
            x: coordinate(0),
            y: coordinate(1),
            z: coordinate(2),
        }
    };
    let v = [
        [at(x0, 0), at(x0, 1), at(x0, 2), at(x0, 3)],
        [at(x1, 0), at(x1, 1), at(x1, 2), at(x1, 3)],
    ];
    first_tests_x4_lanes::<S>(v, sep, t_end, coord)
}

/// The points of four pairs side by side: `[end][k]` holds the `k`-th point of each pair at
/// t=0 (`end` 0, from `x0`) or t=1 (from `x1`).
#[inline(always)]
fn gather(x0: &[DVec3], x1: &[DVec3], corners: &[[u32; 4]; 4]) -> [[V3; 4]; 2] {
    let at = |x: &[DVec3], k: usize| {
        let c = |i: usize| x[corners[i][k] as usize];
        V3::gather([c(0), c(1), c(2), c(3)])
    };
    [
        [at(x0, 0), at(x0, 1), at(x0, 2), at(x0, 3)],
        [at(x1, 0), at(x1, 1), at(x1, 2), at(x1, 3)],
    ]
}

/// [`first_tests_x4`] on [`F4`] lanes, the pairs' points side by side in `v` ([`gather`]).
#[inline(always)]
fn first_tests_x4_lanes<const S: usize>(v: [[V3; 4]; 2], sep: f64, t_end: f64, coord: f64) -> Firsts {
    let t_end = dyadic_end(t_end);
    let apart = direction_separated::<F4, V3, 4, S>(&v, sep, t_end, F4::splat(coord));
    if apart == [true; 4] {
        return Firsts {
            left: [false; 4],
            c: [F4::splat(0.0); 4],
            margin: F4::splat(0.0),
        };
    }
    let [p, a, b] = differences::<V3, S>(&v);
    let (c, margin) = cubic(p, a, b, sep, t_end);
    let keeps = keeps_sign(c, margin);
    let left = [0, 1, 2, 3].map(|i| !(apart[i] || keeps[i]));
    Firsts { left, c, margin }
}

/// What the first tests leave of four pairs ([`first_tests_x4`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Firsts {
    /// Whether pair `i` is left (neither test rejected it).
    left: [bool; 4],
    c: [F4; 4],
    margin: F4,
}

impl Firsts {
    /// `None` when pair `i` was found separated, else what [`rest_unresolved`] has left to
    /// check of it.
    #[inline(always)]
    pub fn rest(&self, i: usize) -> Option<Rest> {
        self.left[i].then(|| Rest {
            c: [self.c[0].0[i], self.c[1].0[i], self.c[2].0[i], self.c[3].0[i]],
            margin: self.margin.0[i],
        })
    }
}

/// The rest of [`unresolved`] for a pair (points `pts`, the first feature's `..split`) that
/// its first tests over `[0, t_end]` (a power of two) left as `rest`: the pieces.
fn rest_unresolved(
    pts: &Points,
    split: usize,
    sep: f64,
    t_end: f64,
    coord: f64,
    rest: Rest,
) -> Option<f64> {
    let piece = Piece {
        pts,
        split,
        sep,
        margin: rest.margin,
        // Each interpolated coordinate `a + (b - a) t` is within `5 u M` of the exact one
        // (`M` the largest coordinate): two roundings of at most `2 u M`, one of `u M`.
        pad: 8.0 * UNIT_ROUNDOFF * coord,
    };
    piece.unresolved(rest.c, 0.0, t_end, 0)
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
/// `-margin`: then so is the cubic over its interval. Per lane.
#[inline(always)]
fn keeps_sign<T: Real>(c: [T; 4], margin: T) -> T::Mask {
    let (lo, hi) = (
        c[0].min(c[1]).min(c[2].min(c[3])),
        c[0].max(c[1]).max(c[2].max(c[3])),
    );
    T::or(lo.gt(margin), hi.lt(-margin))
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
    /// `None` when the pair stays apart during `[ta, tb]`, where `c` are the cubic's Bernstein
    /// coefficients on that interval; else the start of the first piece (of the deepest level)
    /// of `[ta, tb]` not proved apart, the pieces before it all proved apart.
    fn unresolved(&self, c: [f64; 4], ta: f64, tb: f64, depth: u32) -> Option<f64> {
        if keeps_sign(c, self.margin) {
            return None;
        }
        if depth > 0 && self.boxes_apart(ta, tb) {
            return None;
        }
        if depth == DEPTH {
            return Some(ta);
        }
        // De Casteljau at the midpoint.
        let m01 = 0.5 * (c[0] + c[1]);
        let m12 = 0.5 * (c[1] + c[2]);
        let m23 = 0.5 * (c[2] + c[3]);
        let m012 = 0.5 * (m01 + m12);
        let m123 = 0.5 * (m12 + m23);
        let mid = 0.5 * (m012 + m123);
        let tm = 0.5 * (ta + tb);
        self.unresolved([c[0], m01, m012, mid], ta, tm, depth + 1)
            .or_else(|| self.unresolved([mid, m123, m23, c[3]], tm, tb, depth + 1))
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
    direction_separated::<f64, DVec3, 6, 3>(&pts, sep, dyadic_end(t_end), coord)
}

/// The largest absolute coordinate of the points at both ends (`M` of the rounding bounds).
#[inline]
fn largest_coordinate(pts: &Points) -> f64 {
    pts.iter().flatten().fold(0.0, |m, x| raise_abs(m, *x))
}

/// The points of a vertex-face pair: the vertex, then the face's corners, at t=0 and t=1.
#[inline(always)]
fn vf_points(q: &VertexFace) -> Points {
    [
        [q.v_t0, q.f0_t0, q.f1_t0, q.f2_t0],
        [q.v_t1, q.f0_t1, q.f1_t1, q.f2_t1],
    ]
}

/// The points of an edge-edge pair: the first edge's ends, then the second's, at t=0 and t=1.
#[inline(always)]
fn ee_points(q: &EdgeEdge) -> Points {
    [
        [q.ea0_t0, q.ea1_t0, q.eb0_t0, q.eb1_t0],
        [q.ea0_t1, q.ea1_t1, q.eb0_t1, q.eb1_t1],
    ]
}

/// `true` when the vertex provably stays farther than `sep` (`>= 0`) from the face during the
/// times `[0, t_end]` (clamped to the whole step; a little more may be looked at).
#[inline]
pub fn vf_separated(q: &VertexFace, sep: f64, t_end: f64) -> bool {
    let pts = vf_points(q);
    separated::<1>(&pts, sep, t_end, largest_coordinate(&pts))
}

/// `true` when the edges provably stay farther apart than `sep` (`>= 0`) during the times
/// `[0, t_end]` (clamped to the whole step; a little more may be looked at).
#[inline]
pub fn ee_separated(q: &EdgeEdge, sep: f64, t_end: f64) -> bool {
    let pts = ee_points(q);
    separated::<2>(&pts, sep, t_end, largest_coordinate(&pts))
}

/// [`vf_separated`] with `coord` as for [`first_tests_x4`], telling more when the pair is not
/// found separated: `None` when it is, else a time until which it stays apart (see
/// [`unresolved`]).
#[inline]
pub(crate) fn vf_unresolved(q: &VertexFace, sep: f64, t_end: f64, coord: f64) -> Option<f64> {
    unresolved::<1>(&vf_points(q), sep, t_end, coord)
}

/// [`vf_unresolved`] for edge-edge pairs.
#[inline]
pub(crate) fn ee_unresolved(q: &EdgeEdge, sep: f64, t_end: f64, coord: f64) -> Option<f64> {
    unresolved::<2>(&ee_points(q), sep, t_end, coord)
}

/// The rest of [`vf_unresolved`] for a pair that [`first_tests_x4`] left as `rest` (the same
/// `sep`, `t_end` and `coord`): what [`vf_unresolved`] gives the pair.
#[inline]
pub(crate) fn vf_rest_unresolved(
    q: &VertexFace,
    sep: f64,
    t_end: f64,
    coord: f64,
    rest: Rest,
) -> Option<f64> {
    rest_unresolved(&vf_points(q), 1, sep, dyadic_end(t_end), coord, rest)
}

/// [`vf_rest_unresolved`] for edge-edge pairs.
#[inline]
pub(crate) fn ee_rest_unresolved(
    q: &EdgeEdge,
    sep: f64,
    t_end: f64,
    coord: f64,
    rest: Rest,
) -> Option<f64> {
    rest_unresolved(&ee_points(q), 2, sep, dyadic_end(t_end), coord, rest)
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
                min_distance: sep,
                tmax: t_end,
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

    /// Four points near each other at t=0 and t=1: small features moving a lot, as in a
    /// crumpled cloth.
    fn moving_points(rng: &mut ChaCha8Rng) -> [DVec3; 8] {
        let base = point(rng);
        std::array::from_fn(|i| {
            let jitter = 0.3 * point(rng);
            if i < 4 {
                base + jitter
            } else {
                base + jitter + 0.4 * point(rng)
            }
        })
    }

    /// Whenever the filter rejects over `[0, t_end]`, sampled distances over that interval
    /// exceed `sep` and the solver finds no contact there either.
    #[test]
    fn rejections_are_separated() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (mut rejected, mut total) = (0, 0);
        for (sep, t_end, options) in cases() {
            for _ in 0..3000 {
                let pts = moving_points(&mut rng);
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

    /// Where the filter does not find a pair apart, it gives a time until which the pair is
    /// apart all the same (the start of its first piece not proved apart): sampled distances
    /// over `[0, start]` exceed `sep`, and the solver finds no contact there either.
    #[test]
    fn pairs_left_are_apart_until_their_start() {
        let mut rng = ChaCha8Rng::seed_from_u64(14);
        let (mut later, mut left) = (0, 0);
        for (sep, t_end, _) in cases() {
            for _ in 0..3000 {
                let pts = moving_points(&mut rng);
                let coord = pts.iter().fold(0.0, |m, p| raise_abs(m, *p));
                let (vf, ee) = (VertexFace::from_points(pts), EdgeEdge::from_points(pts));
                for (start, is_vf) in [
                    (vf_unresolved(&vf, sep, t_end, coord), true),
                    (ee_unresolved(&ee, sep, t_end, coord), false),
                ] {
                    let Some(start) = start else { continue };
                    left += 1;
                    assert!((0.0..dyadic_end(t_end)).contains(&start), "{start}");
                    if start > 0.0 {
                        later += 1;
                        let options = NarrowOptions {
                            min_distance: sep,
                            tmax: start,
                            ..NarrowOptions::default()
                        };
                        assert_apart(pts, is_vf, sep, start, &options);
                    }
                }
            }
        }
        assert!(later > left / 10, "starts after 0: {later} of {left}");
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

    /// The batched first tests ([`first_tests_x4`], with AVX2 where the CPU has it, and on
    /// plain lanes) give every pair exactly what it gets alone: the same verdict, and for a
    /// pair they leave, the same cubic coefficients and margin, bit for bit.
    #[test]
    fn four_at_once_is_one_at_a_time() {
        let mut rng = ChaCha8Rng::seed_from_u64(13);
        let (mut rejected, mut left) = (0, 0);
        for round in 0..400 {
            // A few vertices near each other, moving, at scales from tiny to huge; some
            // rounds with coincident or still points.
            let scale = 10f64.powi(rng.random_range(-200..200));
            let n = 12;
            let x0: Vec<DVec3> = (0..n).map(|_| scale * point(&mut rng)).collect();
            let x1: Vec<DVec3> = x0
                .iter()
                .map(|&p| if round % 7 == 0 { p } else { p + 0.6 * scale * point(&mut rng) })
                .collect();
            let coord = x0.iter().chain(&x1).fold(0.0, |m, p| raise_abs(m, *p));
            let corners: [[u32; 4]; 4] =
                std::array::from_fn(|_| std::array::from_fn(|_| rng.random_range(0..n as u32)));
            for (sep, t_end, _) in cases().chain([(0.0, 1.0 / 256.0, NarrowOptions::default())]) {
                let sep = sep * scale;
                let check = |firsts: Firsts, split: usize| {
                    let (mut rejected, mut left) = (0, 0);
                    for (i, c) in corners.iter().enumerate() {
                        let pts: Points = [0, 1].map(|e| c.map(|k| [&x0, &x1][e][k as usize]));
                        let alone = if split == 1 {
                            unresolved::<1>(&pts, sep, t_end, coord)
                        } else {
                            unresolved::<2>(&pts, sep, t_end, coord)
                        };
                        let t = dyadic_end(t_end);
                        let batched = match firsts.rest(i) {
                            None => {
                                rejected += 1;
                                None
                            }
                            Some(rest) => {
                                left += 1;
                                let [p, a, b] = if split == 1 {
                                    differences::<DVec3, 1>(&pts)
                                } else {
                                    differences::<DVec3, 2>(&pts)
                                };
                                let (c, margin) = cubic(p, a, b, sep, t);
                                assert_eq!(c.map(f64::to_bits), rest.c.map(f64::to_bits), "{pts:?}");
                                assert_eq!(margin.to_bits(), rest.margin.to_bits(), "{pts:?}");
                                rest_unresolved(&pts, split, sep, t, coord, rest)
                            }
                        };
                        assert_eq!(alone, batched, "{pts:?} sep {sep} t_end {t_end}");
                    }
                    (rejected, left)
                };
                let x = (&x0[..], &x1[..]);
                for (r, l) in [
                    check(first_tests_x4::<1>(x, &corners, sep, t_end, coord), 1),
                    check(first_tests_x4::<2>(x, &corners, sep, t_end, coord), 2),
                    check(first_tests_x4_lanes::<1>(gather(&x0, &x1, &corners), sep, t_end, coord), 1),
                    check(first_tests_x4_lanes::<2>(gather(&x0, &x1, &corners), sep, t_end, coord), 2),
                ] {
                    rejected += r;
                    left += l;
                }
            }
        }
        assert!(rejected > 1000 && left > 1000, "both outcomes: {rejected} rejected, {left} left");
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
