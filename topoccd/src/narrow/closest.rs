//! Closest points of static features (after Ericson, *Real-Time Collision Detection*, 5.1.5
//! and 5.1.9). The solver uses them only to choose a separating direction, and verifies every
//! separation with rigorous error bounds, so these need to be accurate, not exact.

use crate::math::DVec3;

/// The point of triangle `abc` closest to `p`, or `None` if it could not be computed finitely
/// (degenerate triangle at the edge of the representable range).
pub fn point_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<DVec3> {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return finite(a);
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return finite(b);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return finite(a + ab * (d1 / (d1 - d3)));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return finite(c);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return finite(a + ac * (d2 / (d2 - d6)));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return finite(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    }
    let denom = 1.0 / (va + vb + vc);
    finite(a + ab * (vb * denom) + ac * (vc * denom))
}

/// The closest points `(on p1 q1, on p2 q2)` of two segments, or `None` if they could not be
/// computed finitely. Zero-length segments are handled as points.
pub fn segment_segment(p1: DVec3, q1: DVec3, p2: DVec3, q2: DVec3) -> Option<(DVec3, DVec3)> {
    let (s, t) = segment_segment_parameters(p1, q1, p2, q2);
    let c1 = p1 + (q1 - p1) * s;
    let c2 = p2 + (q2 - p2) * t;
    (c1.is_finite() && c2.is_finite()).then_some((c1, c2))
}

/// The parameters `(s, t)` in `[0, 1]^2` of the closest points `p1 + s (q1 - p1)` and
/// `p2 + t (q2 - p2)` of two segments (zero-length segments handled as points; `(0, 0)` when
/// nothing finite can be said).
pub fn segment_segment_parameters(p1: DVec3, q1: DVec3, p2: DVec3, q2: DVec3) -> (f64, f64) {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.length_squared();
    let e = d2.length_squared();
    let f = d2.dot(r);
    let (s, t) = if a == 0.0 && e == 0.0 {
        (0.0, 0.0)
    } else if a == 0.0 {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(r);
        if e == 0.0 {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let mut s = if denom > 0.0 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
            (s, t)
        }
    };
    if s.is_finite() && t.is_finite() {
        (s, t)
    } else {
        (0.0, 0.0)
    }
}

fn finite(p: DVec3) -> Option<DVec3> {
    p.is_finite().then_some(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn point_triangle_regions() {
        let (a, b, c) = (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0));
        let cases = [
            (v(0.2, 0.2, 1.0), v(0.2, 0.2, 0.0)),  // face
            (v(-1.0, -1.0, 0.0), a),               // vertex a
            (v(2.0, -0.5, 0.0), b),                // vertex b
            (v(-0.5, 2.0, 3.0), c),                // vertex c
            (v(0.5, -1.0, 0.0), v(0.5, 0.0, 0.0)), // edge ab
            (v(-1.0, 0.5, 0.0), v(0.0, 0.5, 0.0)), // edge ac
            (v(1.0, 1.0, 0.0), v(0.5, 0.5, 0.0)),  // edge bc
        ];
        for (p, want) in cases {
            let got = point_triangle(p, a, b, c).unwrap();
            assert!((got - want).length() < 1e-12, "{p:?}: {got:?} vs {want:?}");
        }
        // Degenerate triangles still give a point on them or None, never NaN.
        let o = v(0.0, 0.0, 0.0);
        assert_eq!(point_triangle(v(1.0, 1.0, 1.0), o, o, o), Some(o));
        let got = point_triangle(v(0.5, 1.0, 0.0), o, v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0));
        assert!(got.is_none_or(|p| p.is_finite()));
    }

    #[test]
    fn segment_segment_cases() {
        let (c1, c2) = segment_segment(
            v(-1.0, 0.0, 1.0),
            v(1.0, 0.0, 1.0),
            v(0.0, -1.0, 0.0),
            v(0.0, 1.0, 0.0),
        )
        .unwrap();
        assert!((c1 - v(0.0, 0.0, 1.0)).length() < 1e-12 && c2.length() < 1e-12);
        // Parallel segments, and points.
        let (c1, c2) = segment_segment(
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.5, 1.0, 0.0),
            v(2.0, 1.0, 0.0),
        )
        .unwrap();
        assert!(((c1 - c2).length() - 1.0).abs() < 1e-12);
        let p = v(3.0, 0.0, 0.0);
        let (c1, c2) = segment_segment(p, p, v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)).unwrap();
        assert_eq!((c1, c2), (p, v(1.0, 0.0, 0.0)));
    }
}
