//! Analytic values of the derivatives (the random and dual-number checks are in
//! `topoccd-tests/tests/distance_derivatives.rs`).

use super::*;
use crate::math::DVec3;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A point at height `d` over a tilted triangle: the point's gradient is `2 d n`, its Hessian
/// block `2 n n^T`, and the gradient sums to zero over the four points (translation).
#[test]
fn point_over_plane_gradient_is_2_d_n() {
    let (t0, t1, t2) = (v(1.0, 2.0, 3.0), v(3.0, 2.5, 2.0), v(0.5, 4.0, 3.5));
    let n = (t1 - t0).cross(t2 - t0).normalize();
    let d = 0.7;
    let p = (t0 + t1 + t2) / 3.0 + n * d;
    assert!((point_plane_distance(p, t0, t1, t2) - d * d).abs() < 1e-14);
    let g = point_plane_distance_gradient(p, t0, t1, t2);
    let h = point_plane_distance_hessian(p, t0, t1, t2);
    for i in 0..3 {
        assert!((g[i] - 2.0 * d * n[i]).abs() < 1e-14, "{g:?}");
        // At the centroid each corner gets a third of the opposite.
        for k in 1..4 {
            assert!((g[3 * k + i] + 2.0 * d * n[i] / 3.0).abs() < 1e-14);
        }
        for j in 0..3 {
            assert!((h[i][j] - 2.0 * n[i] * n[j]).abs() < 1e-14);
        }
        let sum: f64 = (0..4).map(|k| g[3 * k + i]).sum();
        assert!(sum.abs() < 1e-14);
    }
}

/// Point-line: the point's Hessian block is twice the projector normal to the line.
#[test]
fn point_line_hessian_is_the_normal_projector() {
    let (e0, e1) = (v(0.0, 0.0, 0.0), v(2.0, 2.0, 0.0));
    let p = v(0.0, 2.0, 3.0);
    // r = (0, 2, 3), rejection from (1, 1, 0)/sqrt 2: (-1, 1, 3), squared 11.
    assert!((point_line_distance(p, e0, e1) - 11.0).abs() < 1e-14);
    let g = point_line_distance_gradient(p, e0, e1);
    assert_eq!(&g[..3], &[-2.0, 2.0, 6.0]);
    let h = point_line_distance_hessian(p, e0, e1);
    let u = (e1 - e0).normalize();
    for i in 0..3 {
        for j in 0..3 {
            let want = 2.0 * (f64::from(u8::from(i == j)) - u[i] * u[j]);
            assert!((h[i][j] - want).abs() < 1e-15);
        }
    }
}

/// Crossing lines: the gradient is along the common normal, split by the closest points'
/// parameters (here 1/4 along a, 1/2 along b).
#[test]
fn line_line_gradient_splits_by_parameters() {
    let (ea0, ea1) = (v(-1.0, 0.0, 0.0), v(3.0, 0.0, 0.0));
    let (eb0, eb1) = (v(0.0, -1.0, 2.0), v(0.0, 1.0, 2.0));
    assert_eq!(line_line_distance(ea0, ea1, eb0, eb1), 4.0);
    let g = line_line_distance_gradient(ea0, ea1, eb0, eb1);
    let want = [0.0, 0.0, -3.0, 0.0, 0.0, -1.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0];
    for (a, b) in g.iter().zip(want) {
        assert!((a - b).abs() < 1e-14, "{g:?}");
    }
}

/// The mollifier is 0 and 1 at the ends of its ramp, with slopes 2 / eps_x and 0.
#[test]
fn mollifier_ends() {
    let eps = 0.25;
    assert_eq!(edge_edge_mollifier_scalar(0.0, eps), 0.0);
    assert_eq!(edge_edge_mollifier_scalar(eps, eps), 1.0);
    assert_eq!(edge_edge_mollifier_derivative(0.0, eps), 8.0);
    assert_eq!(edge_edge_mollifier_derivative(eps, eps), 0.0);
    assert_eq!(edge_edge_mollifier_second_derivative(0.1, eps), -32.0);
    let (a0, a1, b0, b1) = (
        v(0.0, 0.0, 0.0),
        v(2.0, 0.0, 0.0),
        v(0.0, 1.0, 0.0),
        v(0.0, 1.0, 3.0),
    );
    assert_eq!(edge_edge_cross_squarednorm(a0, a1, b0, b1), 36.0);
    assert_eq!(edge_edge_mollifier_threshold(a0, a1, b0, b1), 36.0 * 1e-3);
}

/// Every type's derivatives have zeros exactly at the points it does not involve, and the
/// gradient sums to zero over the points (the distance is translation invariant).
#[test]
fn types_touch_only_their_points() {
    let x = [
        v(0.1, 0.2, 1.3),
        v(-0.5, 0.1, 0.0),
        v(1.0, -0.2, 0.1),
        v(0.2, 1.1, -0.1),
    ];
    let pt = [
        (PointTriangleType::T1, vec![1]),
        (PointTriangleType::E1, vec![1]),
        (PointTriangleType::E2, vec![2]),
        (PointTriangleType::Interior, vec![]),
    ];
    for (ty, unused) in pt {
        let g = point_triangle_distance_gradient(x[0], x[1], x[2], x[3], ty);
        let h = point_triangle_distance_hessian(x[0], x[1], x[2], x[3], ty);
        for k in unused {
            assert!(g[3 * k..3 * k + 3].iter().all(|&a| a == 0.0), "{ty:?}");
            assert!((0..12).all(|j| (0..3).all(|i| h[3 * k + i][j] == 0.0)));
        }
        for i in 0..3 {
            let s: f64 = (0..4).map(|k| g[3 * k + i]).sum();
            assert!(s.abs() < 1e-14, "{ty:?}");
        }
    }
    let g = edge_edge_distance_gradient(x[0], x[1], x[2], x[3], EdgeEdgeType::EaEb1);
    assert!(g[6..9].iter().all(|&a| a == 0.0));
    let g = point_edge_distance_gradient(x[0], x[1], x[2], PointEdgeType::E1);
    assert!(g[3..6].iter().all(|&a| a == 0.0));
}
