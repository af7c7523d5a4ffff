//! The k-DOP volume: construction, merging, inflation and the overlap test.

// Slab loops index several parallel arrays (`lo`, `hi`, projections, norms) by slab.
#![allow(clippy::needless_range_loop)]

use super::norms;
use crate::math::{DVec3, UNIT_ROUNDOFF};

/// A k-DOP with `H = k/2` slabs (`H` = 3, 7, 9 or 13; see [`DopKind`](super::DopKind)).
/// Slab `i` is `lo[i] <= n_i . x <= hi[i]` for the `i`-th direction of
/// [`DopKind::directions`](super::DopKind::directions). An *empty* k-DOP has `lo > hi`
/// (`+inf` and `-inf`); it contains nothing and overlaps nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kdop<const H: usize> {
    /// Lower end of each slab, in the coordinates' units times the direction's norm.
    pub lo: [f64; H],
    /// Upper end of each slab.
    pub hi: [f64; H],
}

/// The projections of `p` on the `H` slab directions (small integer vectors, so each is one or
/// two additions).
#[inline(always)]
fn project<const H: usize>(p: DVec3) -> [f64; H] {
    let (x, y, z) = (p.x, p.y, p.z);
    let mut o = [0.0; H];
    o[0] = x;
    o[1] = y;
    o[2] = z;
    let cube = |o: &mut [f64; H], at: usize| {
        o[at] = x + y + z;
        o[at + 1] = x - y + z;
        o[at + 2] = x + y - z;
        o[at + 3] = x - y - z;
    };
    let edge = |o: &mut [f64; H], at: usize| {
        o[at] = x + y;
        o[at + 1] = x + z;
        o[at + 2] = y + z;
        o[at + 3] = x - y;
        o[at + 4] = x - z;
        o[at + 5] = y - z;
    };
    match H {
        3 => {}
        7 => cube(&mut o, 3),
        9 => edge(&mut o, 3),
        13 => {
            cube(&mut o, 3);
            edge(&mut o, 7);
        }
        _ => unreachable!("a k-DOP has 3, 7, 9 or 13 slabs, not {H}"),
    }
    o
}

impl<const H: usize> Default for Kdop<H> {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl<const H: usize> Kdop<H> {
    /// The empty k-DOP, neutral for [`Kdop::merge`].
    pub const EMPTY: Self = Self {
        lo: [f64::INFINITY; H],
        hi: [f64::NEG_INFINITY; H],
    };

    /// The smallest k-DOP containing a point.
    ///
    /// ```
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let d = Kdop::<9>::from_point(DVec3::new(1.0, 2.0, 3.0));
    /// assert_eq!(d.lo, d.hi);
    /// assert_eq!(d.lo[3], 3.0); // the direction x + y
    /// ```
    #[inline]
    pub fn from_point(p: DVec3) -> Self {
        let x = project::<H>(p);
        Self { lo: x, hi: x }
    }

    /// The smallest k-DOP containing the points (the slabs' ends are the computed projections;
    /// see [`Kdop::swept_triangle`] for a volume padded against their rounding). Empty for no
    /// points.
    ///
    /// ```
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let d = Kdop::<3>::from_points(&[DVec3::ZERO, DVec3::new(1.0, -2.0, 0.5)]);
    /// assert_eq!((d.lo, d.hi), ([0.0, -2.0, 0.0], [1.0, 0.0, 0.5]));
    /// ```
    pub fn from_points(points: &[DVec3]) -> Self {
        let mut out = Self::EMPTY;
        for &p in points {
            out.add_point(p);
        }
        out
    }

    /// Grows the k-DOP to contain `p`.
    #[inline]
    pub fn add_point(&mut self, p: DVec3) {
        let x = project::<H>(p);
        for i in 0..H {
            self.lo[i] = self.lo[i].min(x[i]);
            self.hi[i] = self.hi[i].max(x[i]);
        }
    }

    /// The swept volume of a triangle moving linearly from `t0` to `t1` during the step: the
    /// k-DOP of its six positions, inflated by `inflation` (a distance in the coordinates'
    /// units, `>= 0`, usually the `min_distance`) and padded outward by a few units of
    /// rounding of the projections. A linearly moving triangle stays inside the convex hull of
    /// its six positions, so this volume contains it at every time in `[0, 1]`.
    ///
    /// ```
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let t0 = [DVec3::ZERO, DVec3::X, DVec3::Y];
    /// let t1 = t0.map(|p| p + DVec3::Z);
    /// let d = Kdop::<9>::swept_triangle(&t0, &t1, 0.1);
    /// assert!(d.contains_point(DVec3::new(0.2, 0.2, 0.5)));
    /// assert!(d.contains_point(DVec3::new(0.0, 0.0, 1.09)));
    /// assert!(!d.contains_point(DVec3::new(0.0, 0.0, 1.2)));
    /// ```
    #[inline]
    pub fn swept_triangle(t0: &[DVec3; 3], t1: &[DVec3; 3], inflation: f64) -> Self {
        let mut out = Self::from_point(t0[0]);
        let mut m = t0[0].abs();
        for &p in t0[1..].iter().chain(t1) {
            out.add_point(p);
            m = m.max(p.abs());
        }
        // Each projection sums at most three coordinates: two roundings, each at most
        // u * (|x| + |y| + |z|). Pad by twice that.
        let pad = 4.0 * UNIT_ROUNDOFF * (m.x + m.y + m.z);
        out.inflate_padded(inflation, pad);
        out
    }

    /// The swept volume of a triangle moving linearly from `t0` (time 0) to `t1` (time 1),
    /// over the times `[0, tmax]` only: the k-DOP of its positions at 0 and at `tmax`,
    /// inflated by `inflation` and padded against the rounding of the interpolation and the
    /// projections. For a query that already knows a contact at `tmax` and only looks for
    /// earlier ones. `tmax` is clamped to `[0, 1]`; at 1 this is
    /// [`Kdop::swept_triangle`].
    ///
    /// ```
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let t0 = [DVec3::ZERO, DVec3::X, DVec3::Y];
    /// let t1 = t0.map(|p| p + DVec3::Z);
    /// let d = Kdop::<9>::swept_triangle_until(&t0, &t1, 0.25, 0.0);
    /// assert!(d.contains_point(DVec3::new(0.2, 0.2, 0.25)));
    /// assert!(!d.contains_point(DVec3::new(0.2, 0.2, 0.3)));
    /// ```
    pub fn swept_triangle_until(
        t0: &[DVec3; 3],
        t1: &[DVec3; 3],
        tmax: f64,
        inflation: f64,
    ) -> Self {
        // Not `!(tmax < 1.0)`-style tricks: a NaN `tmax` gives the whole step.
        if tmax.is_nan() || tmax >= 1.0 {
            return Self::swept_triangle(t0, t1, inflation);
        }
        let t = tmax.max(0.0);
        let mut out = Self::EMPTY;
        let mut m = DVec3::ZERO;
        for k in 0..3 {
            let (a, b) = (t0[k], t1[k]);
            out.add_point(a);
            out.add_point(a + (b - a) * t);
            m = m.max(a.abs()).max(b.abs());
        }
        // The interpolation `a + (b - a) t` rounds three times, each by at most
        // u * 2 max(|a|, |b|) per coordinate, so a coordinate is off by at most
        // 6 u max(|a|, |b|) (plus second-order terms); the projections sum three coordinates
        // and round twice more (see `swept_triangle`). Pad by more than both.
        let pad = 32.0 * UNIT_ROUNDOFF * (m.x + m.y + m.z);
        out.inflate_padded(inflation, pad);
        out
    }

    /// The part of [`Kdop::swept_triangle_until`] that one corner contributes: the k-DOP of the
    /// point's positions at 0 and at `tmax` (at 1 for `tmax >= 1` or NaN), not padded, and
    /// the largest absolute coordinates of its positions at 0 and 1. A mesh's vertices are
    /// shared by about six triangles each: projecting each once and merging three per
    /// triangle ([`Kdop::swept_triangle_from`]) gives the same volumes for less work.
    ///
    /// ```
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let t0 = [DVec3::ZERO, DVec3::X, DVec3::Y];
    /// let t1 = t0.map(|p| p + DVec3::Z);
    /// for tmax in [0.3, 1.0] {
    ///     let corners = [0, 1, 2].map(|k| Kdop::<9>::swept_point_until(t0[k], t1[k], tmax));
    ///     let from = Kdop::swept_triangle_from(&corners, tmax, 0.1);
    ///     assert_eq!(from, Kdop::swept_triangle_until(&t0, &t1, tmax, 0.1));
    /// }
    /// ```
    #[inline]
    pub fn swept_point_until(a: DVec3, b: DVec3, tmax: f64) -> (Self, DVec3) {
        let end = if tmax.is_nan() || tmax >= 1.0 {
            b
        } else {
            a + (b - a) * tmax.max(0.0)
        };
        let mut out = Self::from_point(a);
        out.add_point(end);
        (out, a.abs().max(b.abs()))
    }

    /// [`Kdop::swept_triangle_until`] from its corners' [`Kdop::swept_point_until`] over the
    /// same `tmax`: the same volume (min and max are exact, so the order of merging does not
    /// matter).
    #[inline]
    pub fn swept_triangle_from(corners: &[(Self, DVec3); 3], tmax: f64, inflation: f64) -> Self {
        let [(a, ma), (b, mb), (c, mc)] = corners;
        let mut out = a.merge(b).merge(c);
        let m = ma.max(*mb).max(*mc);
        // The paddings of `swept_triangle` and `swept_triangle_until`.
        let units = if tmax.is_nan() || tmax >= 1.0 { 4.0 } else { 32.0 };
        let pad = units * UNIT_ROUNDOFF * (m.x + m.y + m.z);
        out.inflate_padded(inflation, pad);
        out
    }

    /// Inflates the k-DOP by `distance` (in the coordinates' units, `>= 0`): every point within
    /// `distance` of the old volume lies in the new one. Slab `i` moves outward by
    /// `distance * |n_i|`, since the directions are not unit vectors.
    ///
    /// ```
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let mut d = Kdop::<9>::from_point(DVec3::ZERO);
    /// d.inflate(1.0);
    /// assert_eq!(d.hi[0], 1.0);
    /// assert_eq!(d.hi[3], std::f64::consts::SQRT_2);
    /// ```
    pub fn inflate(&mut self, distance: f64) {
        self.inflate_padded(distance, 0.0);
    }

    #[inline]
    fn inflate_padded(&mut self, distance: f64, pad: f64) {
        debug_assert!(distance >= 0.0 && pad >= 0.0);
        let n = norms::<H>();
        for i in 0..H {
            let d = distance * n[i] + pad;
            // Near f64's end a projection or its padding overflows, and `inf - inf` is NaN,
            // which would overlap nothing: such a bound goes to the infinity on its outer side.
            let (lo, hi) = (self.lo[i] - d, self.hi[i] + d);
            self.lo[i] = if lo.is_nan() { f64::NEG_INFINITY } else { lo };
            self.hi[i] = if hi.is_nan() { f64::INFINITY } else { hi };
        }
    }

    /// The smallest k-DOP containing both.
    #[inline]
    pub fn merge(&self, other: &Self) -> Self {
        let mut out = *self;
        for i in 0..H {
            out.lo[i] = out.lo[i].min(other.lo[i]);
            out.hi[i] = out.hi[i].max(other.hi[i]);
        }
        out
    }

    /// Whether the two k-DOPs share a point, as far as their slabs tell (touching counts):
    /// `false` proves them disjoint.
    ///
    /// ```
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let a = Kdop::<9>::from_points(&[DVec3::ZERO, DVec3::X]);
    /// let b = Kdop::<9>::from_points(&[DVec3::X, DVec3::Y]);
    /// let c = Kdop::<9>::from_points(&[DVec3::new(0.6, 0.6, 0.0), DVec3::ONE]);
    /// assert!(a.overlaps(&b));
    /// assert!(!a.overlaps(&c)); // an AABB would overlap; the slab x + y separates them
    /// ```
    #[inline]
    pub fn overlaps(&self, other: &Self) -> bool {
        // `&`, not `&&`: all 2H comparisons, without a branch. With `&&` the compiler emits a
        // conditional jump per slab, which mispredict on a traversal's mix of overlapping
        // and disjoint pairs (three times slower per test, measured).
        let mut ok = true;
        for i in 0..H {
            ok &= (self.lo[i] <= other.hi[i]) & (other.lo[i] <= self.hi[i]);
        }
        ok
    }

    /// Whether `other` lies inside `self`, slab by slab. Every k-DOP contains the empty one.
    pub fn contains(&self, other: &Self) -> bool {
        if other.is_empty() {
            return true;
        }
        (0..H).all(|i| self.lo[i] <= other.lo[i] && other.hi[i] <= self.hi[i])
    }

    /// Whether the point's (computed) projections lie in every slab.
    pub fn contains_point(&self, p: DVec3) -> bool {
        let x = project::<H>(p);
        (0..H).all(|i| self.lo[i] <= x[i] && x[i] <= self.hi[i])
    }

    /// `true` when some slab is empty (`lo > hi`), as for [`Kdop::EMPTY`].
    pub fn is_empty(&self) -> bool {
        (0..H).any(|i| self.lo[i] > self.hi[i])
    }

    /// The centre of the k-DOP's axis-aligned box (its first three slabs).
    #[inline]
    pub fn center(&self) -> DVec3 {
        DVec3::new(
            0.5 * (self.lo[0] + self.hi[0]),
            0.5 * (self.lo[1] + self.hi[1]),
            0.5 * (self.lo[2] + self.hi[2]),
        )
    }
}

impl<const H: usize> crate::bvh::BoundingVolume for Kdop<H> {
    #[inline]
    fn merge(&self, other: &Self) -> Self {
        Kdop::merge(self, other)
    }

    #[inline]
    fn overlaps(&self, other: &Self) -> bool {
        Kdop::overlaps(self, other)
    }

    fn contains(&self, other: &Self) -> bool {
        Kdop::contains(self, other)
    }

    #[inline]
    fn center(&self) -> DVec3 {
        Kdop::center(self)
    }
}

#[cfg(test)]
mod tests {
    use super::super::DopKind;
    use super::*;

    #[test]
    fn projections_match_directions() {
        let p = DVec3::new(0.3, -1.7, 2.9);
        fn check<const H: usize>(kind: DopKind, p: DVec3) {
            let x = project::<H>(p);
            let n = norms::<H>();
            for (i, d) in kind.directions().iter().enumerate() {
                let dir = DVec3::new(d[0] as f64, d[1] as f64, d[2] as f64);
                assert!((x[i] - dir.dot(p)).abs() < 1e-12, "{kind} slab {i}");
                assert!((n[i] - dir.length()).abs() < 1e-15, "{kind} norm {i}");
            }
        }
        check::<3>(DopKind::K6, p);
        check::<7>(DopKind::K14, p);
        check::<9>(DopKind::K18, p);
        check::<13>(DopKind::K26, p);
    }

    /// Merged from the corners' parts, the volume is the one computed from the triangle.
    #[test]
    fn swept_triangle_from_corners_is_the_same_volume() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for round in 0..3000 {
            let scale = [1e-3, 1.0, 1e4, 1e150][round % 4];
            let mut p = || DVec3::new(rng.random_range(-scale..scale), rng.random_range(-scale..scale), rng.random_range(-scale..scale));
            let t0 = [p(), p(), p()];
            let t1 = [p(), p(), p()];
            let tmax = [0.0, 1.0 / 256.0, 0.37, 1.0, 2.0][round % 5];
            let inflation = [0.0, 1e-3][round % 2];
            let corners = [0, 1, 2].map(|k| Kdop::<13>::swept_point_until(t0[k], t1[k], tmax));
            let from = Kdop::swept_triangle_from(&corners, tmax, inflation);
            let direct = Kdop::<13>::swept_triangle_until(&t0, &t1, tmax, inflation);
            // Equal, up to the sign of a zero (min and max of +0 and -0).
            for i in 0..13 {
                assert!(from.lo[i] == direct.lo[i] && from.hi[i] == direct.hi[i], "round {round}");
            }
        }
    }

    /// The volume over `[0, tmax]` contains the triangle at every time in it, is smaller than
    /// the whole step's, and is the whole step's at `tmax = 1`.
    #[test]
    fn swept_until_contains_the_triangle_before_t_max() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut p = |scale: f64| {
            DVec3::new(
                rng.random_range(-scale..scale),
                rng.random_range(-scale..scale),
                rng.random_range(-scale..scale),
            )
        };
        for round in 0..300 {
            let scale = [1e-3, 1.0, 1e4][round % 3];
            let c = p(scale);
            let t0 = [p(scale) + c, p(scale) + c, p(scale) + c];
            let t1 = t0.map(|q| q + DVec3::splat(scale) + p(scale));
            let whole = Kdop::<9>::swept_triangle(&t0, &t1, 0.0);
            assert_eq!(Kdop::<9>::swept_triangle_until(&t0, &t1, 1.0, 0.0), whole);
            assert_eq!(
                Kdop::<9>::swept_triangle_until(&t0, &t1, f64::NAN, 0.0),
                whole
            );
            let tmax = (round as f64 / 300.0).powi(3);
            let until = Kdop::<9>::swept_triangle_until(&t0, &t1, tmax, 0.0);
            assert!(until.hi[0] - until.lo[0] <= whole.hi[0] - whole.lo[0] + 1e-9 * scale);
            for k in 0..20 {
                let t = tmax * k as f64 / 19.0;
                for (u, v) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (0.3, 0.3)] {
                    let at = |i: usize| t0[i] + (t1[i] - t0[i]) * t;
                    let q = at(0) + (at(1) - at(0)) * u + (at(2) - at(0)) * v;
                    assert!(until.contains_point(q), "round {round} t {t} of {tmax}");
                }
            }
        }
    }
}
