//! The input range: which coordinates every entry point answers with its guarantees intact.
//!
//! One rule, defined here and used by every test that decides something from coordinates (the
//! elementary tests behind [`query`](crate::query()), the per-pair calls of [`pair`](crate::pair),
//! the line-search helpers, and the static [`check`](crate::check)):
//!
//! - **Inside the range** the coordinates are finite and, within each elementary test (the
//!   eight points of a vertex-face or edge-edge pair, or the coordinates a static check
//!   compares), no two differ by more than [`MAX_DIFFERENCE`] (`1e300`). That holds at
//!   any uniform scale, from subnormal coordinates to `1e300`: a test first multiplies its
//!   difference vectors by a power of two (exact) that brings the largest near 1
//!   ([`normalizing_scale`]), so neither its products (cubes of the differences) overflow nor
//!   its error bounds underflow. Every guarantee holds there: no contact missed, and a
//!   [`Resolved`](crate::Certainty::Resolved) time within its documented bound.
//! - **Outside it** (a NaN or an infinite coordinate, or a difference beyond `1e300`) nothing
//!   can be decided: the pair is a contact at t=0 marked
//!   [`InvalidInput`](crate::Certainty::InvalidInput), never `Resolved`, never missed, and
//!   the static check returns an error.
//!
//! ```
//! use topoccd::range::{within_range, MAX_DIFFERENCE};
//! assert!(within_range(1e-320) && within_range(1e110) && within_range(MAX_DIFFERENCE));
//! assert!(!within_range(1e301) && !within_range(f64::INFINITY) && !within_range(f64::NAN));
//! ```

/// Largest coordinate difference inside the range (see the module documentation).
pub const MAX_DIFFERENCE: f64 = 1e300;

/// Whether a test whose largest coordinate difference is `largest` (an absolute value) lies
/// inside the range: `largest` is at most [`MAX_DIFFERENCE`] (NaN is not).
#[inline]
pub fn within_range(largest: f64) -> bool {
    largest <= MAX_DIFFERENCE
}

/// Below `2^-LOW` or from `2^HIGH` on, a test's largest difference is brought near 1. Between
/// (about `3e-39` to `3e38`) nothing is scaled, so everyday input is computed bit for bit as
/// without the scaling.
const LOW: i32 = 128;
/// See [`LOW`].
const HIGH: i32 = 128;

/// The power of two `s` by which a test whose largest coordinate difference is `largest`
/// (finite, `>= 0`) multiplies its differences: 1 for `largest` in `[2^-128, 2^128)` or 0,
/// else an even power of two that brings `largest * s` into `[1, 4)` (or, for subnormal
/// `largest`, at least `2^-52`). Multiplying by it is exact, square roots scale exactly
/// (the power is even), and so every computed quantity is the one at scale 1, scaled.
///
/// ```
/// use topoccd::range::normalizing_scale;
/// assert_eq!(normalizing_scale(3.0), 1.0);
/// let s = normalizing_scale(1e110);
/// assert!((1.0..4.0).contains(&(1e110 * s)));
/// assert!(normalizing_scale(1e-320) * 1e-320 >= 2f64.powi(-52));
/// ```
#[inline]
pub fn normalizing_scale(largest: f64) -> f64 {
    // (Everyday input returns here, before any logarithm.)
    if (power_of_two(-LOW)..power_of_two(HIGH)).contains(&largest)
        || largest == 0.0
        || !largest.is_finite()
    {
        return 1.0;
    }
    let e = largest.log2().floor() as i32;
    // Even, so that `largest * s` is in [1, 4); `log2` may be off by one near a power of two.
    let mut k = (-e + e.rem_euclid(2)).min(1022);
    while k > -1022 && largest * power_of_two(k) >= 4.0 {
        k -= 2;
    }
    while k < 1022 && largest * power_of_two(k) < 1.0 {
        k += 2;
    }
    power_of_two(k)
}

/// `2^k`, for `k` in `[-1022, 1023]` (normal numbers), exactly.
const fn power_of_two(k: i32) -> f64 {
    f64::from_bits(((k + 1023) as u64) << 52)
}
