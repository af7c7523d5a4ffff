//! A k-DOP stored in `f32`, every bound rounded outward from the `f64` one it stands for: it
//! contains that k-DOP, so an overlap test on two of them can only say "may overlap" more often,
//! never less. Half the bytes of a [`Kdop`]: a hierarchy's node of 18-DOPs is 80 bytes instead
//! of 152, and its traversal, which waits on memory, makes fewer trips to it.

use super::Kdop;
use crate::math::DVec3;

/// A [`Kdop`] in `f32`, rounded outward ([`CompactKdop::outward`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompactKdop<const H: usize> {
    /// Lower end of each slab: the largest `f32` at most the `f64` one.
    pub lo: [f32; H],
    /// Upper end of each slab: the smallest `f32` at least the `f64` one.
    pub hi: [f32; H],
}

/// The largest `f32` that is at most `x` (`NaN` stays `NaN`; beyond `f32`'s range, an infinity
/// on the outer side or `f32::MAX` on the inner one). Without a branch (`f32::next_down` has
/// them), so that converting a volume's bounds vectorizes: the nearest `f32`, moved one step
/// down when it is above `x`. A step down from a zero goes to the smallest negative subnormal.
#[inline]
fn down(x: f64) -> f32 {
    let f = x as f32;
    let b = if f == 0.0 { 0x8000_0000 } else { f.to_bits() };
    let step = if (b as i32) < 0 { 1 } else { u32::MAX };
    let stepped = f32::from_bits(b.wrapping_add(step));
    if f64::from(f) > x {
        stepped
    } else {
        f
    }
}

/// The smallest `f32` that is at least `x` (see [`down`]).
#[inline]
fn up(x: f64) -> f32 {
    let f = x as f32;
    let b = if f == 0.0 { 0 } else { f.to_bits() };
    let step = if (b as i32) < 0 { u32::MAX } else { 1 };
    let stepped = f32::from_bits(b.wrapping_add(step));
    if f64::from(f) < x {
        stepped
    } else {
        f
    }
}

impl<const H: usize> CompactKdop<H> {
    /// The smallest `f32` k-DOP containing `k`: every bound rounded outward.
    #[inline]
    pub fn outward(k: &Kdop<H>) -> Self {
        Self {
            lo: k.lo.map(down),
            hi: k.hi.map(up),
        }
    }

    /// Whether some bound is `NaN` (a volume of coordinates near `f64::MAX`, whose projections
    /// overflow).
    pub fn has_nan(&self) -> bool {
        self.lo.iter().chain(&self.hi).any(|x| x.is_nan())
    }

    /// The summed widths of the first three slabs (the axes).
    pub fn extent(&self) -> f64 {
        (0..3.min(H)).map(|i| f64::from(self.hi[i]) - f64::from(self.lo[i])).sum()
    }
}

impl<const H: usize> crate::bvh::BoundingVolume for CompactKdop<H> {
    #[inline]
    fn merge(&self, other: &Self) -> Self {
        let mut out = *self;
        for i in 0..H {
            out.lo[i] = out.lo[i].min(other.lo[i]);
            out.hi[i] = out.hi[i].max(other.hi[i]);
        }
        out
    }

    /// As [`Kdop::overlaps`]: `&`, not `&&`, all `2H` comparisons without a branch.
    #[inline]
    fn overlaps(&self, other: &Self) -> bool {
        let mut ok = true;
        for i in 0..H {
            ok &= (self.lo[i] <= other.hi[i]) & (other.lo[i] <= self.hi[i]);
        }
        ok
    }

    fn contains(&self, other: &Self) -> bool {
        if (0..H).any(|i| other.lo[i] > other.hi[i]) {
            return true;
        }
        (0..H).all(|i| self.lo[i] <= other.lo[i] && other.hi[i] <= self.hi[i])
    }

    #[inline]
    fn center(&self) -> DVec3 {
        let c = |i: usize| 0.5 * (f64::from(self.lo[i]) + f64::from(self.hi[i]));
        DVec3::new(c(0), c(1), c(2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::BoundingVolume;
    use rand::{Rng, SeedableRng};

    /// Every bound is rounded outward, and by at most one `f32` step: the compact k-DOP
    /// contains the `f64` one, and two compact k-DOPs overlap whenever their `f64` ones do.
    #[test]
    fn rounded_outward_by_at_most_one_step() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut overlapping = 0;
        for round in 0..20_000 {
            let scale = [1e-30, 1e-3, 1.0, 1e7, 1e38, 1e300][round % 6];
            let mut p = || {
                DVec3::new(
                    rng.random_range(-scale..scale),
                    rng.random_range(-scale..scale),
                    rng.random_range(-scale..scale),
                )
            };
            let (a0, a1, b0, b1) = (p(), p(), p(), p());
            let a = Kdop::<9>::swept_point_until(a0, a1, 1.0).0;
            let b = Kdop::<9>::swept_point_until(b0, b1, 1.0).0;
            let (ca, cb) = (CompactKdop::outward(&a), CompactKdop::outward(&b));
            for i in 0..9 {
                let (lo, hi) = (f64::from(ca.lo[i]), f64::from(ca.hi[i]));
                assert!(lo <= a.lo[i] && a.hi[i] <= hi, "{round} slab {i}");
                assert!(ca.lo[i] == f32::MAX || f64::from(ca.lo[i].next_up()) > a.lo[i]);
                assert!(ca.hi[i] == f32::MIN || f64::from(ca.hi[i].next_down()) < a.hi[i]);
            }
            if a.overlaps(&b) {
                overlapping += 1;
                assert!(ca.overlaps(&cb), "{round}");
            }
        }
        assert!(overlapping > 1_000, "{overlapping}");
    }

    /// The branchless steps are `f32::next_down` and `f32::next_up`, where a step is needed.
    #[test]
    fn steps_are_the_standard_ones() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
        let special = [0.0, -0.0, 1e-46, -1e-46, 1e-300, -1e-300, 3.5e38, -3.5e38, 1e300, -1e300];
        for k in 0..200_000 {
            let x: f64 = if k < special.len() {
                special[k]
            } else {
                f64::from_bits(rng.random::<u64>())
            };
            if x.is_nan() {
                continue;
            }
            let f = x as f32;
            let expect_down = if f64::from(f) > x { f.next_down() } else { f };
            let expect_up = if f64::from(f) < x { f.next_up() } else { f };
            assert_eq!(down(x).to_bits(), expect_down.to_bits(), "{x:e}");
            assert_eq!(up(x).to_bits(), expect_up.to_bits(), "{x:e}");
        }
    }

    #[test]
    fn nan_and_infinite_bounds_stay_outward() {
        assert!(down(f64::NAN).is_nan() && up(f64::NAN).is_nan());
        assert_eq!(down(1e300), f32::MAX);
        assert_eq!(up(1e300), f32::INFINITY);
        assert_eq!(down(-1e300), f32::NEG_INFINITY);
        assert_eq!(up(-1e300), f32::MIN);
        assert_eq!(down(f64::INFINITY), f32::INFINITY);
        assert!(f64::from(down(0.1)) < 0.1 && f64::from(up(0.1)) > 0.1);
        assert_eq!((down(0.5), up(0.5)), (0.5, 0.5));
        let empty = CompactKdop::outward(&Kdop::<3>::EMPTY);
        assert!(!empty.overlaps(&empty));
    }
}
