//! Splitting a polygon face into triangles: a fan for convex polygons, ear clipping for the
//! others.
//!
//! Why both: a fan from the first vertex is what modelers and most readers do for quads and
//! convex n-gons, it keeps the triangles' numbering predictable (sub-triangle `i` is
//! `(v0, v(i+1), v(i+2))`), and it is exact for any convex polygon. On a non-convex polygon a
//! fan can produce triangles outside the polygon (overlapping ones), which would show up as
//! spurious contacts; ear clipping in the polygon's best-fit plane (Newell's normal) gives
//! triangles inside the polygon for any simple (non-self-intersecting) polygon that is planar
//! or close to it. A polygon that ear clipping cannot split (self-intersecting, folded, without
//! area) is finished as a fan and reported as irregular.

use crate::math::DVec3;

/// How [`triangulate_polygon`] split a polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PolygonSplit {
    /// Three vertices: the polygon is a triangle.
    Triangle,
    /// Convex (in its best-fit plane): a fan from the first vertex.
    Fan,
    /// Not convex: ear clipping.
    EarClipped,
    /// No plane (zero area) or ear clipping found no ear (self-intersecting or folded polygon):
    /// split as a fan from the first vertex (of what was left).
    Irregular,
}

/// Splits the polygon `corners` (vertex ids in order, at least three, each in range of
/// `positions`) into `corners.len() - 2` triangles appended to `out`, with the polygon's winding.
///
/// Convex polygons (in their best-fit plane, Newell's normal) are split as a fan from the
/// first vertex: what modelers and most readers do for quads and convex n-gons, exact for any
/// convex polygon, and predictable (sub-triangle `i` is `(v0, v(i+1), v(i+2))`). On a
/// non-convex polygon a fan can make triangles outside the polygon (overlapping ones, which
/// would show up as spurious contacts), so those are ear-clipped in the best-fit plane, which
/// gives triangles inside any simple polygon that is planar or close to it. A polygon that ear
/// clipping cannot split (self-intersecting, folded, without area) is finished as a fan and
/// reported as [`PolygonSplit::Irregular`].
///
/// ```
/// use topoccd::io::{triangulate_polygon, PolygonSplit};
/// // An L-shaped hexagon: not convex, so a fan from vertex 0 would leave the polygon.
/// let p = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [1.0, 1.0, 0.0],
///          [1.0, 2.0, 0.0], [0.0, 2.0, 0.0]];
/// let mut out = Vec::new();
/// assert_eq!(triangulate_polygon(&p, &[0, 1, 2, 3, 4, 5], &mut out), PolygonSplit::EarClipped);
/// assert_eq!(out.len(), 4);
/// out.clear();
/// assert_eq!(triangulate_polygon(&p, &[0, 1, 2, 5], &mut out), PolygonSplit::Fan);
/// assert_eq!(out, vec![[0, 1, 2], [0, 2, 5]]);
/// ```
pub fn triangulate_polygon(
    positions: &[[f64; 3]],
    corners: &[u32],
    out: &mut Vec<[u32; 3]>,
) -> PolygonSplit {
    debug_assert!(corners.len() >= 3);
    debug_assert!(corners.iter().all(|&c| (c as usize) < positions.len()));
    if corners.len() == 3 {
        out.push([corners[0], corners[1], corners[2]]);
        return PolygonSplit::Triangle;
    }
    let point = |c: u32| DVec3::from_array(positions[c as usize]);
    let normal = newell_normal(corners.iter().map(|&c| point(c)));
    let length = normal.length();
    if !(length > 0.0 && length.is_finite()) {
        fan(corners, out);
        return PolygonSplit::Irregular;
    }
    let (u, v) = (normal / length).any_orthonormal_pair();
    let flat: Vec<[f64; 2]> = corners
        .iter()
        .map(|&c| {
            let p = point(c);
            [p.dot(u), p.dot(v)]
        })
        .collect();
    let n = flat.len();
    let convex = (0..n).all(|i| turn(flat[i], flat[(i + 1) % n], flat[(i + 2) % n]) >= 0.0);
    if convex {
        fan(corners, out);
        return PolygonSplit::Fan;
    }
    if ear_clip(&flat, corners, out) {
        PolygonSplit::EarClipped
    } else {
        PolygonSplit::Irregular
    }
}

/// Newell's normal: twice the vector area of the polygon; its direction makes the polygon
/// counter-clockwise, and it is well defined for non-planar polygons too.
fn newell_normal(points: impl Iterator<Item = DVec3> + Clone) -> DVec3 {
    let first = points.clone().next().unwrap_or_default();
    // Centred on the first vertex, for accuracy far from the origin.
    let next = points.clone().skip(1).chain(std::iter::once(first));
    points.zip(next).fold(DVec3::ZERO, |sum, (a, b)| {
        let (a, b) = (a - first, b - first);
        sum + DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        )
    })
}

/// Twice the signed area of the 2D triangle `a, b, c` (positive when counter-clockwise).
fn turn(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// A fan from the first corner.
fn fan(corners: &[u32], out: &mut Vec<[u32; 3]>) {
    for w in corners[1..].windows(2) {
        out.push([corners[0], w[0], w[1]]);
    }
}

/// Ear clipping of the counter-clockwise 2D polygon `flat` (corner ids `corners`). Returns
/// false if at some point no ear was found; the rest is then split as a fan.
fn ear_clip(flat: &[[f64; 2]], corners: &[u32], out: &mut Vec<[u32; 3]>) -> bool {
    let mut left: Vec<usize> = (0..flat.len()).collect();
    while left.len() > 3 {
        let m = left.len();
        let ear = (0..m).find(|&i| {
            let (a, b, c) = (left[(i + m - 1) % m], left[i], left[(i + 1) % m]);
            let (pa, pb, pc) = (flat[a], flat[b], flat[c]);
            turn(pa, pb, pc) > 0.0
                && left.iter().all(|&j| {
                    let q = flat[j];
                    j == a || j == b || j == c || q == pa || q == pb || q == pc || {
                        // Outside (or on the boundary of) the ear: some edge sees it on its right.
                        turn(pa, pb, q) < 0.0 || turn(pb, pc, q) < 0.0 || turn(pc, pa, q) < 0.0
                    }
                })
        });
        let Some(i) = ear else {
            let rest: Vec<u32> = left.iter().map(|&j| corners[j]).collect();
            fan(&rest, out);
            return false;
        };
        let (a, b, c) = (left[(i + m - 1) % m], left[i], left[(i + 1) % m]);
        out.push([corners[a], corners[b], corners[c]]);
        left.remove(i);
    }
    out.push([corners[left[0]], corners[left[1]], corners[left[2]]]);
    true
}
