//! Running minima and maxima that skip NaN, one comparison each.
//!
//! `f64::min` and `f64::max` return the other operand when one is NaN, which on x86-64 costs a
//! comparison for unordered operands and a blend besides the `minsd` / `maxsd` itself. The hot
//! loops of the elementary tests only fold values into an accumulator that starts at an
//! infinity or at zero and so is never NaN; for them [`lower`] and [`raise`] give the same value
//! as `acc.min(x)` and `acc.max(x)` (a NaN `x` leaves `acc` as it is, as `f64::min` does) and
//! compile to the bare instruction. The one difference, which of `+0` and `-0` is kept when both
//! meet, cannot change a verdict: every folded value is only ever compared.

use super::lanes::Real;
use crate::math::DVec3;

/// `acc.min(x)` for an accumulator `acc` that is not NaN.
#[inline(always)]
pub(crate) fn lower(acc: f64, x: f64) -> f64 {
    <f64 as Real>::lower(acc, x)
}

/// `acc.max(x)` for an accumulator `acc` that is not NaN.
#[inline(always)]
pub(crate) fn raise(acc: f64, x: f64) -> f64 {
    <f64 as Real>::raise(acc, x)
}

/// [`lower`] per coordinate.
#[inline(always)]
pub(crate) fn lower3(acc: DVec3, x: DVec3) -> DVec3 {
    DVec3::new(lower(acc.x, x.x), lower(acc.y, x.y), lower(acc.z, x.z))
}

/// [`raise`] per coordinate.
#[inline(always)]
pub(crate) fn raise3(acc: DVec3, x: DVec3) -> DVec3 {
    DVec3::new(raise(acc.x, x.x), raise(acc.y, x.y), raise(acc.z, x.z))
}

/// `acc.max(max_abs(x))` for an accumulator `acc` that is not NaN: the largest of `acc` and the
/// absolute coordinates of `x` that are not NaN.
#[inline(always)]
pub(crate) fn raise_abs(acc: f64, x: DVec3) -> f64 {
    raise(raise(raise(acc, x.x.abs()), x.y.abs()), x.z.abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Agreement with `f64::min` / `f64::max` on accumulators that are not NaN, NaN included
    /// among the folded values.
    #[test]
    fn as_min_and_max() {
        let values = [
            -2.0,
            -0.5,
            0.0,
            1.0,
            3.5,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        for acc in values.into_iter().filter(|a| !a.is_nan()) {
            for x in values {
                assert_eq!(lower(acc, x), acc.min(x));
                assert_eq!(raise(acc, x), acc.max(x));
            }
        }
        let p = DVec3::new(-3.0, f64::NAN, 2.0);
        assert_eq!(raise_abs(0.0, p), 3.0);
        assert_eq!(raise_abs(4.0, p), 4.0);
        assert_eq!(lower3(DVec3::ZERO, p), DVec3::new(-3.0, 0.0, 0.0));
        assert_eq!(raise3(DVec3::ZERO, p), DVec3::new(0.0, 0.0, 2.0));
    }
}
