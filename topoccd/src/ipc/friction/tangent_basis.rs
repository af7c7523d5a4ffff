//! Tangent bases of the four contact stencils: two orthonormal vectors spanning the plane
//! orthogonal to the contact normal, as the IPC toolkit chooses them (same vectors, same
//! signs), so a tangential collision's basis can be compared with ipctk's entry by entry.
//!
//! A basis is returned as its two columns `[t0, t1]` (the toolkit's 3×2 matrix). The
//! potential depends only on the plane they span, not on the choice inside it.
//!
//! Degenerate stencils (coincident points, a zero-length edge, parallel edges, a zero-area
//! triangle) have no normal: the result is then not finite, and
//! [`TangentialCollisions::build`](super::TangentialCollisions::build) reports them.

use crate::math::DVec3;

/// Point-point: the normal is `p1 - p0`; the first tangent is `e × (p1 - p0)` for the axis
/// `e` (x or y) that gives the longer cross product, the second is `(p1 - p0) × t0`.
///
/// ```
/// use topoccd::ipc::friction::point_point_tangent_basis;
/// use topoccd::math::DVec3;
/// let [t0, t1] = point_point_tangent_basis(DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0));
/// assert!(t0.dot(DVec3::Z).abs() < 1e-15 && t1.dot(DVec3::Z).abs() < 1e-15);
/// ```
#[inline]
pub fn point_point_tangent_basis(p0: DVec3, p1: DVec3) -> [DVec3; 2] {
    let d = p1 - p0;
    let cross_x = DVec3::X.cross(d);
    let cross_y = DVec3::Y.cross(d);
    let c = if cross_x.length_squared() > cross_y.length_squared() {
        cross_x
    } else {
        cross_y
    };
    [normalized(c), normalized(d.cross(c))]
}

/// Point-edge: the normal is the component of `p - e0` orthogonal to the edge; the first
/// tangent is the edge direction, the second `e × (p - e0)`, normalised.
#[inline]
pub fn point_edge_tangent_basis(p: DVec3, e0: DVec3, e1: DVec3) -> [DVec3; 2] {
    let e = e1 - e0;
    [normalized(e), normalized(e.cross(p - e0))]
}

/// Edge-edge: the normal is `ea × eb`; the first tangent is edge a's direction, the second
/// `(ea × eb) × ea`, normalised.
#[inline]
pub fn edge_edge_tangent_basis(ea0: DVec3, ea1: DVec3, eb0: DVec3, eb1: DVec3) -> [DVec3; 2] {
    let ea = ea1 - ea0;
    let n = ea.cross(eb1 - eb0);
    [normalized(ea), normalized(n.cross(ea))]
}

/// Point-triangle: the normal is the triangle's, `(t1 - t0) × (t2 - t0)`; the first tangent
/// is the edge `t1 - t0`, the second `n × (t1 - t0)`, normalised. The point does not enter.
#[inline]
pub fn point_triangle_tangent_basis(_p: DVec3, t0: DVec3, t1: DVec3, t2: DVec3) -> [DVec3; 2] {
    let e0 = t1 - t0;
    let n = e0.cross(t2 - t0);
    [normalized(e0), normalized(n.cross(e0))]
}

/// `v / |v|` (Eigen's `normalized` leaves a zero vector unchanged; here it becomes NaN, which
/// the builder reports).
#[inline]
fn normalized(v: DVec3) -> DVec3 {
    v / v.length()
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

    /// Orthonormal, and orthogonal to `n`.
    fn check(b: [DVec3; 2], n: DVec3) {
        let n = n.normalize();
        assert!((b[0].length() - 1.0).abs() < 1e-14 && (b[1].length() - 1.0).abs() < 1e-14);
        assert!(b[0].dot(b[1]).abs() < 1e-14);
        assert!(
            b[0].dot(n).abs() < 1e-13 && b[1].dot(n).abs() < 1e-13,
            "{b:?} {n}"
        );
    }

    #[test]
    fn bases_are_orthonormal_and_tangent() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for _ in 0..1000 {
            let [a, b, c, d] = [0; 4].map(|_| point(&mut rng));
            check(point_point_tangent_basis(a, b), b - a);
            // Point-edge normal: p - e0 minus its projection on the edge.
            let e = c - b;
            let r = a - b;
            check(
                point_edge_tangent_basis(a, b, c),
                r - e * (r.dot(e) / e.dot(e)),
            );
            check(edge_edge_tangent_basis(a, b, c, d), (b - a).cross(d - c));
            check(
                point_triangle_tangent_basis(a, b, c, d),
                (c - b).cross(d - b),
            );
        }
        // Normals along the axes, where the point-point choice switches.
        for n in [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(1.0, 1.0, 0.0)] {
            check(point_point_tangent_basis(DVec3::ZERO, n), n);
            check(point_point_tangent_basis(n, DVec3::ZERO), n);
        }
    }

    #[test]
    fn degenerate_stencils_are_not_finite() {
        let p = DVec3::new(0.5, 0.25, 0.75);
        assert!(!point_point_tangent_basis(p, p)[0].is_finite());
        assert!(!point_edge_tangent_basis(DVec3::ZERO, p, p)[0].is_finite());
        let q = p * 2.0;
        assert!(!edge_edge_tangent_basis(DVec3::ZERO, p, DVec3::X, DVec3::X + q)[1].is_finite());
        assert!(!point_triangle_tangent_basis(DVec3::X, DVec3::ZERO, p, q)[1].is_finite());
    }
}
