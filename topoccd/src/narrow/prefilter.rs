//! A cheap conservative filter run before the elementary tests: the deforming non-penetration
//! filter (Tang et al. 2010). It proves a pair separated when the vertex stays strictly on one
//! side of the face's plane (or one edge on one side of the plane through the other edge
//! parallel to both) during the whole step, farther than `min_separation`.
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
use super::{EdgeEdge, VertexFace};

/// Margin on the coefficients, in units of `u P A B`.
const COEFFICIENT_ERROR: f64 = 256.0;

/// How many times the step is halved, at most, where the cubic changes sign (`2^DEPTH`
/// pieces).
const DEPTH: u32 = 3;

/// The four points of a pair (vertex and face corners, or edge ends) at t=0 and t=1.
type Points = [[DVec3; 4]; 2];

/// `true` when the pair provably stays farther apart than `sep` over the whole step: on every
/// piece of the step, either the cubic `p . (a x b)` (each of `p, a, b` linear from `_0` at
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
) -> bool {
    let c = coplanarity(p, a, b);
    let pm = max_abs(p[0]).max(max_abs(p[1]));
    let am = max_abs(a[0]).max(max_abs(a[1]));
    let bm = max_abs(b[0]).max(max_abs(b[1]));
    let ab = am * bm;
    let cm = c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    // Rounding of the triple products, then of up to DEPTH levels of halving.
    let mut margin = COEFFICIENT_ERROR * UNIT_ROUNDOFF * pm * ab
        + 4.0 * DEPTH as f64 * UNIT_ROUNDOFF * cm
        + UNDERFLOW_ERROR;
    if sep > 0.0 {
        // The normal n(t) = a(t) x b(t), a quadratic: its Bernstein coefficients.
        let n00 = a[0].cross(b[0]);
        let n11 = a[1].cross(b[1]);
        let n1 = 0.5 * (a[0].cross(b[1]) + a[1].cross(b[0]));
        let norm = n00.length().max(n1.length()).max(n11.length());
        margin += sep * (norm + COEFFICIENT_ERROR * UNIT_ROUNDOFF * ab);
    }
    let coord = pts.iter().flatten().fold(0.0f64, |m, x| m.max(max_abs(*x)));
    let piece = Piece {
        pts,
        split,
        sep,
        margin,
        // Each interpolated coordinate is within 3 u of the largest coordinate.
        pad: 4.0 * UNIT_ROUNDOFF * coord,
    };
    piece.separated(c, 0.0, 1.0, 0)
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
        let (lo, hi) = (
            c[0].min(c[1]).min(c[2].min(c[3])),
            c[0].max(c[1]).max(c[2].max(c[3])),
        );
        if lo > self.margin || hi < -self.margin {
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
                lo[f] = lo[f].min(x);
                hi[f] = hi[f].max(x);
            }
        }
        let gap = self.sep + 2.0 * self.pad;
        (lo[0] - hi[1]).max_element() > gap || (lo[1] - hi[0]).max_element() > gap
    }
}

/// `true` when the vertex provably stays farther than `sep` (`>= 0`) from the face's plane,
/// hence from the face, during the whole step.
#[inline]
pub fn vf_separated(q: &VertexFace, sep: f64) -> bool {
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
    )
}

/// `true` when the edges' lines provably stay farther apart than `sep` (`>= 0`), hence the
/// edges, during the whole step.
#[inline]
pub fn ee_separated(q: &EdgeEdge, sep: f64) -> bool {
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
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::narrow::{edge_edge, vertex_face, NarrowOptions};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn point(rng: &mut ChaCha8Rng) -> DVec3 {
        DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
    }

    /// The smallest distance between sampled points of the two features over sampled times
    /// (an upper bound of their true smallest distance).
    fn sampled_distance(q: &[DVec3; 8], vertex_face: bool) -> f64 {
        let n = 12;
        let mut best = f64::INFINITY;
        for k in 0..=32 {
            let t = k as f64 / 32.0;
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

    /// Whenever the filter rejects, sampled distances exceed `sep` and the solver finds no
    /// contact either.
    #[test]
    fn rejections_are_separated() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (mut rejected, mut total) = (0, 0);
        for sep in [0.0, 0.05] {
            let options = NarrowOptions {
                min_separation: sep,
                ..NarrowOptions::default()
            };
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
                let vf = VertexFace::from_points(pts);
                if vf_separated(&vf, sep) {
                    rejected += 1;
                    assert!(!vertex_face(&vf, &options).is_contact(), "{vf:?}");
                    assert!(sampled_distance(&pts, true) > sep, "{vf:?}");
                }
                let ee = EdgeEdge::from_points(pts);
                if ee_separated(&ee, sep) {
                    rejected += 1;
                    assert!(!edge_edge(&ee, &options).is_contact(), "{ee:?}");
                    assert!(sampled_distance(&pts, false) > sep, "{ee:?}");
                }
            }
        }
        assert!(
            rejected > total / 4,
            "the filter should reject often: {rejected} of {total}"
        );
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
        assert!(!vf_separated(&vf, 0.0));
        let above = VertexFace {
            v_t1: DVec3::new(0.2, 0.2, 0.1),
            ..vf
        };
        assert!(vf_separated(&above, 0.0));
        assert!(vf_separated(&above, 0.099));
        assert!(!vf_separated(&above, 0.1));
    }
}
