//! The geometry of a contact at its time of impact: closest points, barycentric coordinates
//! and a contact normal, for a simulator's response. Computed only for reported contacts.

use super::report::{EeGeometry, VfGeometry};
use crate::math::{lerp, DVec3};
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
        point: p.to_array(),
        normal: normal.to_array(),
        distance: (v - p).length(),
    }
}

/// The geometry of an edge-edge contact at `toi`. The normal is the cross product of the two
/// edges, turned towards edge `a`'s side at t=0; for parallel edges, the direction between
/// the closest points (at `toi`, or at t=0 if they meet).
pub(crate) fn edge_edge(q: &EdgeEdge, toi: f64) -> EeGeometry {
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
        point: (0.5 * (pa + pb)).to_array(),
        normal: normal.to_array(),
        distance: (pa - pb).length(),
    }
}
