//! Relative velocities of the contact stencils and their Jacobians.
//!
//! The relative velocity of a stencil is a fixed linear combination of its vertices'
//! velocities, `v_rel = sum_i gamma_i v_i`, with coefficients `gamma` that depend only on the
//! closest-point coordinates (lagged, so constant during a solve). Its Jacobian is the 3×3k
//! matrix `[gamma_0 I, gamma_1 I, ...]` (the IPC toolkit's `relative_velocity_jacobian`),
//! returned here as the coefficients `gamma`; [`jacobian_matrix`] expands them.
//!
//! Vertex order, as ipctk's stencils: point-point `[p0, p1]`, point-edge `[p, e0, e1]`,
//! edge-edge `[ea0, ea1, eb0, eb1]`, point-triangle `[p, t0, t1, t2]`.

use crate::math::DVec3;

/// Point-point: `v_rel = v0 - v1`, coefficients `[1, -1]`.
#[inline]
pub fn point_point_relative_velocity_jacobian() -> [f64; 2] {
    [1.0, -1.0]
}

/// Point-edge at edge parameter `alpha`: `v_rel = v_p - ((1 - alpha) v_e0 + alpha v_e1)`,
/// coefficients `[1, alpha - 1, -alpha]`.
#[inline]
pub fn point_edge_relative_velocity_jacobian(alpha: f64) -> [f64; 3] {
    [1.0, alpha - 1.0, -alpha]
}

/// Edge-edge at parameters `[a, b]`: the velocity of edge a's closest point minus edge b's,
/// coefficients `[1 - a, a, b - 1, -b]`.
#[inline]
pub fn edge_edge_relative_velocity_jacobian(ab: [f64; 2]) -> [f64; 4] {
    [1.0 - ab[0], ab[0], ab[1] - 1.0, -ab[1]]
}

/// Point-triangle at coordinates `[b1, b2]`: the point's velocity minus the velocity of the
/// triangle's point `t0 + b1 (t1 - t0) + b2 (t2 - t0)`, coefficients
/// `[1, b1 + b2 - 1, -b1, -b2]`.
#[inline]
pub fn point_triangle_relative_velocity_jacobian(b: [f64; 2]) -> [f64; 4] {
    [1.0, b[0] + b[1] - 1.0, -b[0], -b[1]]
}

/// `sum_i gamma_i v_i`: the relative velocity from a stencil's coefficients and its vertices'
/// velocities (in stencil order).
///
/// ```
/// use topoccd::ipc::friction::{point_edge_relative_velocity_jacobian, relative_velocity};
/// use topoccd::math::DVec3;
/// // A point moving along x over an edge that is at rest.
/// let g = point_edge_relative_velocity_jacobian(0.5);
/// let v = relative_velocity(&g, &[DVec3::X, DVec3::ZERO, DVec3::ZERO]);
/// assert_eq!(v, DVec3::X);
/// ```
#[inline]
pub fn relative_velocity(gamma: &[f64], velocities: &[DVec3]) -> DVec3 {
    debug_assert_eq!(gamma.len(), velocities.len());
    gamma
        .iter()
        .zip(velocities)
        .fold(DVec3::ZERO, |s, (g, v)| s + *v * *g)
}

/// The Jacobian `[gamma_0 I, gamma_1 I, ...]` as a row-major 3×3k matrix (`3 * 3k` entries).
pub fn jacobian_matrix(gamma: &[f64]) -> Vec<f64> {
    let n = 3 * gamma.len();
    let mut m = vec![0.0; 3 * n];
    for (i, g) in gamma.iter().enumerate() {
        for r in 0..3 {
            m[r * n + 3 * i + r] = *g;
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipc::friction::closest_point::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn point(rng: &mut ChaCha8Rng) -> DVec3 {
        DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
    }

    /// The relative velocity is the time derivative of the gap between the two closest
    /// points, with the closest-point coordinates held fixed: check it by moving the vertices.
    #[test]
    fn relative_velocity_is_the_gap_rate() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for _ in 0..100 {
            let x: Vec<DVec3> = (0..4).map(|_| point(&mut rng)).collect();
            let v: Vec<DVec3> = (0..4).map(|_| point(&mut rng)).collect();
            let at =
                |t: f64| -> Vec<DVec3> { x.iter().zip(&v).map(|(a, b)| *a + *b * t).collect() };
            let h = 1e-6;
            let rate = |gap: &dyn Fn(&[DVec3]) -> DVec3| (gap(&at(h)) - gap(&at(-h))) / (2.0 * h);

            let ab = edge_edge_closest_point(x[0], x[1], x[2], x[3]);
            let gap_ee =
                |y: &[DVec3]| (y[0] + (y[1] - y[0]) * ab[0]) - (y[2] + (y[3] - y[2]) * ab[1]);
            let g = edge_edge_relative_velocity_jacobian(ab);
            assert!((relative_velocity(&g, &v) - rate(&gap_ee)).length() < 1e-8);

            let b = point_triangle_closest_point(x[0], x[1], x[2], x[3]);
            let gap_pt = |y: &[DVec3]| y[0] - (y[1] + (y[2] - y[1]) * b[0] + (y[3] - y[1]) * b[1]);
            let g = point_triangle_relative_velocity_jacobian(b);
            assert!((relative_velocity(&g, &v) - rate(&gap_pt)).length() < 1e-8);

            let a = point_edge_closest_point(x[0], x[1], x[2]);
            let gap_pe = |y: &[DVec3]| y[0] - (y[1] + (y[2] - y[1]) * a);
            let g = point_edge_relative_velocity_jacobian(a);
            assert!((relative_velocity(&g, &v[..3]) - rate(&gap_pe)).length() < 1e-8);

            let gap_pp = |y: &[DVec3]| y[0] - y[1];
            let g = point_point_relative_velocity_jacobian();
            assert!((relative_velocity(&g, &v[..2]) - rate(&gap_pp)).length() < 1e-8);
        }
    }

    #[test]
    fn jacobian_matrix_times_velocities() {
        let g = [0.3, -0.7, 0.25, -0.85];
        let v = [
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(-1.0, 0.5, 0.0),
            DVec3::Y,
            DVec3::Z,
        ];
        let m = jacobian_matrix(&g);
        let flat: Vec<f64> = v.iter().flat_map(|p| p.to_array()).collect();
        let r = relative_velocity(&g, &v);
        for row in 0..3 {
            let s: f64 = (0..12).map(|c| m[row * 12 + c] * flat[c]).sum();
            assert!((s - r[row]).abs() < 1e-15);
        }
    }
}
