//! The geometry of a contact at its time of impact: closest points, barycentric coordinates
//! and a contact normal, for a simulator's response. Computed only for reported contacts.

use super::report::{EeGeometry, VfGeometry};
use crate::math::{lerp, max_abs, DVec3};
use crate::narrow::closest::{point_triangle, segment_segment_parameters};
use crate::narrow::{EdgeEdge, VertexFace};

/// `n` normalised and turned so that `side . n >= 0`; zero when `n` has no direction.
fn oriented_unit(n: DVec3, side: DVec3) -> DVec3 {
    let n = n.normalize_or_zero();
    if side.dot(n) < 0.0 {
        -n
    } else {
        n
    }
}

/// A power of two, and its inverse, each as two factors (powers of two of the normal range), that
/// bring the largest coordinate of a contact's eight points into `[1, 2)`, about. The geometry
/// is computed on the scaled points, where nothing overflows (the barycentric coordinates
/// multiply four coordinates, the edges' closest points too), and scaled back: multiplying by
/// a power of two is exact but for underflow, and rounding commutes with it, so on points
/// whose computation did not overflow the result is bit for bit the unscaled one.
#[derive(Clone, Copy, Debug)]
struct Scale {
    down: [f64; 2],
    up: [f64; 2],
}

impl Scale {
    fn of(points: &[DVec3; 8]) -> Self {
        let largest = points.iter().map(|&p| max_abs(p)).fold(0.0, f64::max);
        // The rounding of log2 only moves the scaled range by a factor of two.
        let k = if largest > 0.0 {
            largest.log2().floor() as i32
        } else {
            0
        };
        let (a, b) = (k / 2, k - k / 2);
        Self {
            down: [2f64.powi(-a), 2f64.powi(-b)],
            up: [2f64.powi(a), 2f64.powi(b)],
        }
    }

    fn down(&self, p: DVec3) -> DVec3 {
        p * self.down[0] * self.down[1]
    }

    fn up(&self, x: f64) -> f64 {
        x * self.up[0] * self.up[1]
    }
}

/// Barycentric coordinates of `p` (a point of triangle `abc`) on `a, b, c`.
fn barycentric(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> [f64; 3] {
    let (v0, v1, v2) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
    let (d20, d21) = (v2.dot(v0), v2.dot(v1));
    let denom = d00 * d11 - d01 * d01;
    if denom == 0.0 || !denom.is_finite() {
        return [1.0, 0.0, 0.0];
    }
    let v = ((d11 * d20 - d01 * d21) / denom).clamp(0.0, 1.0);
    let w = ((d00 * d21 - d01 * d20) / denom).clamp(0.0, 1.0 - v);
    [1.0 - v - w, v, w]
}

/// The geometry of a vertex-face contact at `toi`. The normal is the face's, turned towards
/// the vertex's side at t=0 (where it came from); if the face is degenerate at `toi`, the
/// direction from the face's closest point to the vertex at t=0.
pub(crate) fn vertex_face(q: &VertexFace, toi: f64) -> VfGeometry {
    let scale = Scale::of(&q.points());
    let q = &VertexFace::from_points(q.points().map(|p| scale.down(p)));
    let at = |p0: DVec3, p1: DVec3| lerp(p0, p1, toi);
    let (v, f0, f1, f2) = (
        at(q.v_t0, q.v_t1),
        at(q.f0_t0, q.f0_t1),
        at(q.f1_t0, q.f1_t1),
        at(q.f2_t0, q.f2_t1),
    );
    let p = point_triangle(v, f0, f1, f2).unwrap_or(f0);
    let side0 = q.v_t0 - point_triangle(q.v_t0, q.f0_t0, q.f1_t0, q.f2_t0).unwrap_or(q.f0_t0);
    let mut normal = oriented_unit((f1 - f0).cross(f2 - f0), side0);
    if normal == DVec3::ZERO {
        normal = side0.normalize_or_zero();
    }
    VfGeometry {
        barycentric: barycentric(p, f0, f1, f2),
        point: p.to_array().map(|x| scale.up(x)),
        normal: normal.to_array(),
        distance: scale.up((v - p).length()),
    }
}

/// The geometry of an edge-edge contact at `toi`. The normal is the cross product of the two
/// edges, turned towards edge `a`'s side at t=0; for parallel edges, the direction between
/// the closest points (at `toi`, or at t=0 if they meet).
pub(crate) fn edge_edge(q: &EdgeEdge, toi: f64) -> EeGeometry {
    let scale = Scale::of(&q.points());
    let q = &EdgeEdge::from_points(q.points().map(|p| scale.down(p)));
    let at = |p0: DVec3, p1: DVec3| lerp(p0, p1, toi);
    let (a0, a1, b0, b1) = (
        at(q.ea0_t0, q.ea0_t1),
        at(q.ea1_t0, q.ea1_t1),
        at(q.eb0_t0, q.eb0_t1),
        at(q.eb1_t0, q.eb1_t1),
    );
    let (s, t) = segment_segment_parameters(a0, a1, b0, b1);
    let (pa, pb) = (a0 + (a1 - a0) * s, b0 + (b1 - b0) * t);
    let (s0, t0) = segment_segment_parameters(q.ea0_t0, q.ea1_t0, q.eb0_t0, q.eb1_t0);
    let side0 = (q.ea0_t0 + (q.ea1_t0 - q.ea0_t0) * s0) - (q.eb0_t0 + (q.eb1_t0 - q.eb0_t0) * t0);
    let (da, db) = (a1 - a0, b1 - b0);
    let cross = da.cross(db);
    // Nearly parallel edges: the cross product's direction is noise.
    let mut normal = if cross.length() > 1e-9 * da.length() * db.length() {
        oriented_unit(cross, side0)
    } else {
        (pa - pb).normalize_or_zero()
    };
    if normal == DVec3::ZERO {
        normal = side0.normalize_or_zero();
    }
    EeGeometry {
        a_param: s,
        b_param: t,
        point: (0.5 * (pa + pb)).to_array().map(|x| scale.up(x)),
        normal: normal.to_array(),
        distance: scale.up((pa - pb).length()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    fn no_nan(xs: &[f64]) -> bool {
        xs.iter().all(|x| !x.is_nan())
    }

    /// Geometry is covariant under a scaling by a power of two: points and distances scale,
    /// barycentric coordinates, edge parameters and normals stay. Checked bit for bit over
    /// scales at which the products of coordinates (fourth powers in the barycentric
    /// coordinates) overflow or underflow.
    #[test]
    fn geometry_scales_with_its_points() {
        let vf = VertexFace::from_points([
            p(0.3, 0.2, 0.5),
            p(0.0, 0.0, 0.0),
            p(1.0, 0.0, 0.1),
            p(0.0, 1.0, -0.1),
            p(0.3, 0.25, -0.4),
            p(0.0, 0.0, 0.05),
            p(1.0, 0.1, 0.0),
            p(0.1, 1.0, 0.0),
        ]);
        let ee = EdgeEdge::from_points([
            p(-1.0, 0.0, 0.5),
            p(1.0, 0.1, 0.5),
            p(0.2, -1.0, -0.5),
            p(0.0, 1.0, -0.4),
            p(-1.0, 0.1, -0.5),
            p(1.0, 0.0, -0.6),
            p(0.1, -1.0, 0.5),
            p(0.0, 1.0, 0.4),
        ]);
        let toi = 0.4375;
        let (g, h) = (vertex_face(&vf, toi), edge_edge(&ee, toi));
        assert!(g.distance > 0.0 && g.barycentric.iter().all(|&b| b > 0.0), "{g:?}");
        assert!(h.a_param > 0.0 && h.a_param < 1.0 && h.b_param > 0.0, "{h:?}");
        for k in [-1000, -600, -1, 1, 600, 1000] {
            let s = 2f64.powi(k);
            let gs = vertex_face(&VertexFace::from_points(vf.points().map(|q| q * s)), toi);
            assert_eq!(gs.barycentric, g.barycentric, "2^{k}");
            assert_eq!(gs.normal, g.normal, "2^{k}");
            assert_eq!(gs.point, g.point.map(|x| x * s), "2^{k}");
            assert_eq!(gs.distance, g.distance * s, "2^{k}");
            let hs = edge_edge(&EdgeEdge::from_points(ee.points().map(|q| q * s)), toi);
            assert_eq!((hs.a_param, hs.b_param), (h.a_param, h.b_param), "2^{k}");
            assert_eq!(hs.normal, h.normal, "2^{k}");
            assert_eq!(hs.point, h.point.map(|x| x * s), "2^{k}");
            assert_eq!(hs.distance, h.distance * s, "2^{k}");
        }
    }

    /// The `step` fuzz target's contact: a vertex on a face's corner 4.7e104 away from the
    /// face's other corners, where the unscaled barycentric coordinates took `inf - inf`.
    #[test]
    fn a_far_corner_gives_its_barycentric_coordinates() {
        let far = p(0.0, 12.0, 4.717169818218967e104);
        let near = p(-0.015625, -0.015625, -0.015625);
        let o = p(0.0, 0.0, 0.0);
        let q = VertexFace::from_points([far, near, far, o, far, near, far, o]);
        let g = vertex_face(&q, 0.0);
        assert_eq!(g.barycentric, [0.0, 1.0, 0.0]);
        assert_eq!(g.point, far.to_array());
        assert_eq!(g.distance, 0.0);
    }

    /// Coordinates near the largest double, whose differences overflow (the elementary test
    /// reports such pairs conservatively): no NaN anywhere, barycentric coordinates and edge
    /// parameters in `[0, 1]`, the points finite.
    #[test]
    fn coordinates_near_the_largest_double_give_no_nan() {
        let m = 1.5e308;
        let vf = VertexFace::from_points([
            p(m, 0.0, 0.0),
            p(-m, -m, 0.0),
            p(-m, m, 0.0),
            p(m, 0.0, m),
            p(-m, 0.0, 0.0),
            p(-m, -m, m),
            p(m, m, 0.0),
            p(m, 0.0, -m),
        ]);
        let ee = EdgeEdge::from_points([
            p(-m, 0.0, m),
            p(m, 0.0, -m),
            p(0.0, -m, -m),
            p(0.0, m, m),
            p(m, m, 0.0),
            p(-m, -m, 0.0),
            p(-m, m, m),
            p(m, -m, -m),
        ]);
        for toi in [0.0, 0.5, 1.0] {
            let g = vertex_face(&vf, toi);
            assert!(no_nan(&g.barycentric) && no_nan(&g.normal) && !g.distance.is_nan());
            assert!(g.barycentric.iter().all(|b| (0.0..=1.0).contains(b)), "{g:?}");
            assert!((g.barycentric.iter().sum::<f64>() - 1.0).abs() < 1e-15, "{g:?}");
            assert!(g.point.iter().all(|x| x.is_finite()), "{g:?}");
            let h = edge_edge(&ee, toi);
            assert!(no_nan(&h.normal) && !h.distance.is_nan(), "{h:?}");
            assert!((0.0..=1.0).contains(&h.a_param) && (0.0..=1.0).contains(&h.b_param));
            assert!(h.point.iter().all(|x| x.is_finite()), "{h:?}");
        }
    }
}
