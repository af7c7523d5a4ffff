//! Numbers in lanes: one `f64`, or four side by side ([`F4`]), behind one trait ([`Real`]), so
//! that one source serves the prefilter's scalar path and its batches of four pairs. Every
//! operation of an [`F4`] is the `f64` operation on each lane, in the same order, so a batch
//! gives each pair the very bits the scalar path gives it (no fused multiply-add, no
//! reassociation); the compiler turns the lane loops into vector instructions.

use std::ops::{Add, Div, Mul, Neg, Sub};

use crate::math::DVec3;

/// An `f64` or four, with the few operations the prefilter's first tests need.
pub(crate) trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// A comparison's answer, per lane.
    type Mask: Copy;
    /// Every lane `x`.
    fn splat(x: f64) -> Self;
    /// `f64::abs` per lane.
    fn abs(self) -> Self;
    /// `f64::sqrt` per lane.
    fn sqrt(self) -> Self;
    /// `f64::max` per lane.
    fn max(self, other: Self) -> Self;
    /// `f64::min` per lane.
    fn min(self, other: Self) -> Self;
    /// `self < other` per lane.
    fn lt(self, other: Self) -> Self::Mask;
    /// `self > other` per lane.
    fn gt(self, other: Self) -> Self::Mask;
    /// `a` where `mask`, else `b`, per lane.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// Logical and per lane.
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// Logical or per lane.
    fn or(a: Self::Mask, b: Self::Mask) -> Self::Mask;

    /// `x` where `x < acc`, else `acc`, per lane: `acc.min(x)` for an accumulator that is not
    /// NaN (see [`extremes`](super::extremes), whose `lower` this is for `f64`).
    #[inline(always)]
    fn lower(acc: Self, x: Self) -> Self {
        Self::select(x.lt(acc), x, acc)
    }

    /// `x` where `x > acc`, else `acc`, per lane: `acc.max(x)` for an accumulator that is not
    /// NaN (`extremes::raise` for `f64`).
    #[inline(always)]
    fn raise(acc: Self, x: Self) -> Self {
        Self::select(x.gt(acc), x, acc)
    }
}

impl Real for f64 {
    type Mask = bool;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64::abs(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f64::max(self, other)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        f64::min(self, other)
    }
    #[inline(always)]
    fn lt(self, other: Self) -> bool {
        self < other
    }
    #[inline(always)]
    fn gt(self, other: Self) -> bool {
        self > other
    }
    #[inline(always)]
    fn select(mask: bool, a: Self, b: Self) -> Self {
        if mask {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn and(a: bool, b: bool) -> bool {
        a & b
    }
    #[inline(always)]
    fn or(a: bool, b: bool) -> bool {
        a | b
    }
}

/// Four `f64` lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct F4(pub [f64; 4]);

/// Applies `f` to each lane of `a` and `b`.
#[inline(always)]
fn zip<T>(F4(a): F4, F4(b): F4, f: impl Fn(f64, f64) -> T) -> [T; 4] {
    // (Written out: the lane loops must inline into the caller, AVX2 or not.)
    [f(a[0], b[0]), f(a[1], b[1]), f(a[2], b[2]), f(a[3], b[3])]
}

macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for F4 {
            type Output = F4;
            #[inline(always)]
            fn $method(self, other: F4) -> F4 {
                F4(zip(self, other, |x, y| x $op y))
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl Neg for F4 {
    type Output = F4;
    #[inline(always)]
    fn neg(self) -> F4 {
        F4(zip(self, self, |x, _| -x))
    }
}

impl Real for F4 {
    type Mask = [bool; 4];
    #[inline(always)]
    fn splat(x: f64) -> Self {
        F4([x; 4])
    }
    #[inline(always)]
    fn abs(self) -> Self {
        F4(zip(self, self, |x, _| x.abs()))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        F4(zip(self, self, |x, _| x.sqrt()))
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        F4(zip(self, other, f64::max))
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        F4(zip(self, other, f64::min))
    }
    #[inline(always)]
    fn lt(self, other: Self) -> [bool; 4] {
        zip(self, other, |x, y| x < y)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> [bool; 4] {
        zip(self, other, |x, y| x > y)
    }
    #[inline(always)]
    fn select(mask: [bool; 4], a: Self, b: Self) -> Self {
        let pick = |i: usize| if mask[i] { a.0[i] } else { b.0[i] };
        F4([pick(0), pick(1), pick(2), pick(3)])
    }
    #[inline(always)]
    fn and(a: [bool; 4], b: [bool; 4]) -> [bool; 4] {
        [a[0] & b[0], a[1] & b[1], a[2] & b[2], a[3] & b[3]]
    }
    #[inline(always)]
    fn or(a: [bool; 4], b: [bool; 4]) -> [bool; 4] {
        [a[0] | b[0], a[1] | b[1], a[2] | b[2], a[3] | b[3]]
    }
}

/// A point or vector whose coordinates are [`Real`]s: glam's `DVec3`, or four of them side by
/// side ([`V3`]), whose operations are `DVec3`'s on each lane, formula for formula.
pub(crate) trait Vector: Copy + Add<Output = Self> + Sub<Output = Self> {
    /// The coordinates' type.
    type R: Real;
    /// Every coordinate zero.
    fn zero() -> Self;
    /// Each coordinate times `s`.
    fn scale(self, s: Self::R) -> Self;
    /// `DVec3::dot`.
    fn dot(self, o: Self) -> Self::R;
    /// `DVec3::cross`.
    fn cross(self, o: Self) -> Self;
    /// `DVec3::length`.
    fn length(self) -> Self::R;
    /// `DVec3::abs().element_sum()`.
    fn abs_sum(self) -> Self::R;
    /// `math::max_abs`: `DVec3::abs().max_element()`.
    fn max_abs(self) -> Self::R;
}

impl Vector for DVec3 {
    type R = f64;
    #[inline(always)]
    fn zero() -> Self {
        DVec3::ZERO
    }
    #[inline(always)]
    fn scale(self, s: f64) -> Self {
        self * s
    }
    #[inline(always)]
    fn dot(self, o: Self) -> f64 {
        DVec3::dot(self, o)
    }
    #[inline(always)]
    fn cross(self, o: Self) -> Self {
        DVec3::cross(self, o)
    }
    #[inline(always)]
    fn length(self) -> f64 {
        DVec3::length(self)
    }
    #[inline(always)]
    fn abs_sum(self) -> f64 {
        self.abs().element_sum()
    }
    #[inline(always)]
    fn max_abs(self) -> f64 {
        crate::math::max_abs(self)
    }
}

/// Four points side by side: lane `i` of each coordinate is the `i`-th point's.
#[derive(Clone, Copy, Debug)]
pub(crate) struct V3 {
    pub x: F4,
    pub y: F4,
    pub z: F4,
}

impl V3 {
    /// The four points side by side, lane `i` the `i`-th.
    #[inline(always)]
    pub fn gather(p: [DVec3; 4]) -> Self {
        V3 {
            x: F4([p[0].x, p[1].x, p[2].x, p[3].x]),
            y: F4([p[0].y, p[1].y, p[2].y, p[3].y]),
            z: F4([p[0].z, p[1].z, p[2].z, p[3].z]),
        }
    }
}

impl Vector for V3 {
    type R = F4;
    #[inline(always)]
    fn zero() -> Self {
        let z = F4::splat(0.0);
        V3 { x: z, y: z, z }
    }
    #[inline(always)]
    fn scale(self, s: F4) -> Self {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
    #[inline(always)]
    fn dot(self, o: Self) -> F4 {
        (self.x * o.x) + (self.y * o.y) + (self.z * o.z)
    }
    #[inline(always)]
    fn cross(self, o: Self) -> Self {
        V3 {
            x: self.y * o.z - o.y * self.z,
            y: self.z * o.x - o.z * self.x,
            z: self.x * o.y - o.x * self.y,
        }
    }
    #[inline(always)]
    fn length(self) -> F4 {
        self.dot(self).sqrt()
    }
    #[inline(always)]
    fn abs_sum(self) -> F4 {
        self.x.abs() + self.y.abs() + self.z.abs()
    }
    #[inline(always)]
    fn max_abs(self) -> F4 {
        // glam's `max_element`: `max(x, max(y, z))` with `max(a, b) = if a > b { a } else { b }`.
        // (`max(a, b)` is `raise(b, a)`.)
        F4::raise(F4::raise(self.z.abs(), self.y.abs()), self.x.abs())
    }
}

impl Add for V3 {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl Sub for V3 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Each lane of every operation is bit for bit the `f64` (and `DVec3`) operation.
    #[test]
    fn lanes_are_the_scalar_operations() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let value = |rng: &mut ChaCha8Rng| match rng.random_range(0..8) {
            0 => 0.0,
            1 => -0.0,
            2 => 1e-310,
            _ => rng.random_range(-1.0..1.0) * 10f64.powi(rng.random_range(-20..20)),
        };
        for _ in 0..2000 {
            let p: [DVec3; 4] = std::array::from_fn(|_| DVec3::new(value(&mut rng), value(&mut rng), value(&mut rng)));
            let q: [DVec3; 4] = std::array::from_fn(|_| DVec3::new(value(&mut rng), value(&mut rng), value(&mut rng)));
            let (a, b) = (V3::gather(p), V3::gather(q));
            for i in 0..4 {
                let same = |x: f64, y: f64| assert_eq!(x.to_bits(), y.to_bits(), "{p:?} {q:?}");
                same(a.dot(b).0[i], p[i].dot(q[i]));
                let c = p[i].cross(q[i]);
                for (x, y) in [(a.cross(b).x.0[i], c.x), (a.cross(b).y.0[i], c.y), (a.cross(b).z.0[i], c.z)] {
                    same(x, y);
                }
                same(a.length().0[i], p[i].length());
                same(a.abs_sum().0[i], p[i].abs().element_sum());
                same(a.max_abs().0[i], crate::math::max_abs(p[i]));
                same((a - b).scale(F4::splat(3.0)).z.0[i], ((p[i] - q[i]) * 3.0).z);
                same(V3::zero().y.0[i], DVec3::ZERO.y);
                same((a + b).x.0[i], (p[i] + q[i]).x);
                same(a.x.max(b.x).0[i], p[i].x.max(q[i].x));
                assert_eq!(a.x.lt(b.y)[i], p[i].x < q[i].y);
            }
        }
    }
}
