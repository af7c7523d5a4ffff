//! The one numeric module: `f64` vectors and the few helpers every stage shares.

pub use glam::DVec3;

/// Unit roundoff of `f64` (2^-53): the relative error of one correctly rounded operation.
pub const UNIT_ROUNDOFF: f64 = f64::EPSILON * 0.5;

/// Position at time `t` of a point moving linearly from `p_t0` to `p_t1`.
#[inline]
pub fn lerp(p_t0: DVec3, p_t1: DVec3, t: f64) -> DVec3 {
    p_t0 + (p_t1 - p_t0) * t
}

/// Largest absolute coordinate of a point.
#[inline]
pub fn max_abs(p: DVec3) -> f64 {
    p.abs().max_element()
}

/// Absolute allowance for products in the subnormal range, added to every rounding bound:
/// results there are not relatively accurate.
pub const UNDERFLOW_ERROR: f64 = 1e-290;
