//! The features' boxes of one query, computed once per query rather than once per pair: every
//! vertex, edge and triangle gets an axis-aligned box in `f32` (rounded outward), inflated by
//! half of one reach that covers every pair ([`inflation`]). Two features whose boxes are
//! disjoint are farther apart than any kept pair may be, so a pair is dropped on two box loads
//! before its positions are read; the pairs left go through the exact per-pair reject and
//! distance of `pairs`, so the pairs kept are the same. The leaves' boxes are the hierarchy's
//! leaves; `slots` keeps the features' boxes in the hierarchy's order.

use crate::kdop::{CompactKdop, Kdop};
use crate::math::{DVec3, UNIT_ROUNDOFF};

use super::pairs::reach;
use super::primitives::{Kind, Primitives};

/// An `f32` box, rounded outward.
pub(crate) type Box3 = CompactKdop<3>;

/// Whether two boxes share a point (every comparison made, no branch).
#[inline(always)]
pub(crate) fn overlap(a: &Box3, b: &Box3) -> bool {
    (a.lo[0] <= b.hi[0])
        & (b.lo[0] <= a.hi[0])
        & (a.lo[1] <= b.hi[1])
        & (b.lo[1] <= a.hi[1])
        & (a.lo[2] <= b.hi[2])
        & (b.lo[2] <= a.hi[2])
}

/// The box of `points`, each bound moved outward by `h`, rounded outward to `f32`.
#[inline]
pub(crate) fn inflated(points: &[DVec3], h: f64) -> Box3 {
    let (mut lo, mut hi) = (points[0], points[0]);
    for p in &points[1..] {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    Box3::outward(&Kdop {
        lo: (lo - h).to_array(),
        hi: (hi + h).to_array(),
    })
}

/// The largest coordinate difference within `points`.
#[inline]
fn side(points: &[DVec3]) -> f64 {
    let (mut lo, mut hi) = (points[0], points[0]);
    for p in &points[1..] {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (hi - lo).max_element()
}

/// The inflation of every feature's box at positions `x` for threshold `r`.
///
/// Why it is conservative: a pair is kept by `pairs` only if, on every axis, the gap between
/// its two features' boxes is at most `reach(r, ext)`, `ext` the pair's extent. A pair whose
/// gap passes that test has `ext <= side_a + side_b + gap`, so with `L` the largest feature
/// side, `ext <= 2 L + reach(r, ext)`; `reach` being `r (1 + 1e-12)` plus less than
/// `1e-7 ext`, `ext <= (2 L + 2 r) (1 + 1e-6)`. Each box is inflated by half of `reach` at
/// that extent (monotone in it), plus the rounding of the inflation (`8 u` times the largest
/// coordinate); `f32` rounding only moves bounds outward. So two boxes are disjoint only when
/// the per-pair test would drop the pair.
pub(crate) fn inflation(big: f64, x: &[DVec3], r: f64) -> f64 {
    let coord = x.iter().fold(0.0f64, |m, p| m.max(p.abs().max_element()));
    let ext = (2.0 * big + 2.0 * r) * (1.0 + 1e-6);
    0.5 * reach(r, ext) * (1.0 + 1e-6) + 8.0 * UNIT_ROUNDOFF * coord
}

/// The largest side (largest coordinate difference) of a triangle or free edge: `L` of
/// [`inflation`].
pub(crate) fn largest_side(prims: &Primitives, tris: &[[u32; 3]], x: &[DVec3]) -> f64 {
    (tris.iter().map(|t| side(&t.map(|v| x[v as usize]))))
        .chain((prims.edges[prims.mesh_edges..].iter()).map(|e| side(&e.map(|v| x[v as usize]))))
        .fold(0.0f64, f64::max)
}

/// The box of leaf `leaf` (see [`Primitives::leaves`]), inflated by `h`.
#[inline]
pub(crate) fn leaf_box(prims: &Primitives, x: &[DVec3], h: f64, leaf: u32) -> Box3 {
    let l = &prims.leaves[leaf as usize];
    match l.kind {
        Kind::Triangle => inflated(&l.verts.map(|v| x[v as usize]), h),
        Kind::Edge => inflated(&[x[l.verts[0] as usize], x[l.verts[1] as usize]], h),
        Kind::Point => inflated(&[x[l.verts[0] as usize]], h),
    }
}
