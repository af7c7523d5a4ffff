//! The distances and their derivatives over a batch of pairs of one kind, into buffers the
//! caller owns and reuses (no allocation): the hot loop of a contact potential.
//!
//! Each function checks the lengths once, then runs one straight loop over the pairs with
//! the per-type closed forms inlined, so that the compiler sees fixed-size array code and no
//! bounds checks. Gradients and Hessians are optional: an energy-only evaluation (a line
//! search) asks for the distances alone.

use super::by_type::{
    edge_edge_distance_gradient, edge_edge_distance_hessian, edge_edge_distance_of_type,
    point_edge_distance_gradient, point_edge_distance_hessian, point_edge_distance_of_type,
    point_triangle_distance_gradient, point_triangle_distance_hessian,
    point_triangle_distance_of_type,
};
use super::point_point::{
    point_point_distance, point_point_distance_gradient, point_point_distance_hessian,
};
use super::{EdgeEdgeType, PointEdgeType, PointTriangleType};
use crate::math::DVec3;
use thiserror::Error;

/// The output buffers of a batch of `n` pairs whose derivatives have `N` entries (3 per
/// point): `distances` (squared) has `n` entries; `gradients` and `hessians`, when given,
/// `n` entries each (row-major Hessians).
#[derive(Debug)]
pub struct BatchOutput<'a, const N: usize> {
    /// The squared distances, one per pair.
    pub distances: &'a mut [f64],
    /// The gradients, one per pair, or `None` to skip them.
    pub gradients: Option<&'a mut [[f64; N]]>,
    /// The Hessians, one per pair, or `None` to skip them.
    pub hessians: Option<&'a mut [[[f64; N]; N]]>,
}

/// A batch whose buffers do not have one entry per pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Error)]
#[error("distance batch: `{what}` has {found} entries, expected {expected} (one per pair)")]
pub struct BatchLengthError {
    /// The buffer at fault: `types`, `distances`, `gradients` or `hessians`.
    pub what: &'static str,
    /// The number of pairs.
    pub expected: usize,
    /// The buffer's length.
    pub found: usize,
}

impl<const N: usize> BatchOutput<'_, N> {
    fn check(&self, n: usize) -> Result<(), BatchLengthError> {
        let bad = |what, found| {
            if found == n {
                Ok(())
            } else {
                Err(BatchLengthError {
                    what,
                    expected: n,
                    found,
                })
            }
        };
        bad("distances", self.distances.len())?;
        if let Some(g) = &self.gradients {
            bad("gradients", g.len())?;
        }
        if let Some(h) = &self.hessians {
            bad("hessians", h.len())?;
        }
        Ok(())
    }
}

/// Runs `d`, `g`, `h` (value, gradient, Hessian of pair `i`) into `out`, whose lengths were
/// checked. Three passes, so that each loop stays small and branch-free in its body.
#[inline(always)]
fn run<const N: usize>(
    n: usize,
    out: BatchOutput<'_, N>,
    d: impl Fn(usize) -> f64,
    g: impl Fn(usize) -> [f64; N],
    h: impl Fn(usize) -> [[f64; N]; N],
) {
    for (i, o) in out.distances[..n].iter_mut().enumerate() {
        *o = d(i);
    }
    if let Some(gs) = out.gradients {
        for (i, o) in gs[..n].iter_mut().enumerate() {
            *o = g(i);
        }
    }
    if let Some(hs) = out.hessians {
        for (i, o) in hs[..n].iter_mut().enumerate() {
            *o = h(i);
        }
    }
}

fn check_types(n: usize, found: usize) -> Result<(), BatchLengthError> {
    if found == n {
        Ok(())
    } else {
        Err(BatchLengthError {
            what: "types",
            expected: n,
            found,
        })
    }
}

/// The squared distances of point-point pairs `[p, q]`, with gradients and Hessians on
/// request ([`point_point_distance_gradient`], [`point_point_distance_hessian`]).
///
/// ```
/// use topoccd::distance::{point_point_distance_batch, BatchOutput};
/// use topoccd::math::DVec3;
/// let pairs = [[DVec3::ZERO, DVec3::X], [DVec3::ZERO, DVec3::Y * 2.0]];
/// let (mut d, mut g) = ([0.0; 2], [[0.0; 6]; 2]);
/// point_point_distance_batch(&pairs, BatchOutput { distances: &mut d, gradients: Some(&mut g), hessians: None })?;
/// assert_eq!(d, [1.0, 4.0]);
/// assert_eq!(g[1][4], 4.0);
/// # Ok::<(), topoccd::distance::BatchLengthError>(())
/// ```
pub fn point_point_distance_batch(
    pairs: &[[DVec3; 2]],
    out: BatchOutput<'_, 6>,
) -> Result<(), BatchLengthError> {
    let n = pairs.len();
    out.check(n)?;
    run(
        n,
        out,
        |i| point_point_distance(pairs[i][0], pairs[i][1]),
        |i| point_point_distance_gradient(pairs[i][0], pairs[i][1]),
        |i| point_point_distance_hessian(pairs[i][0], pairs[i][1]),
    );
    Ok(())
}

/// The squared distances of point-edge pairs `[p, e0, e1]` of the given types, with
/// gradients and Hessians on request ([`point_edge_distance_of_type`] and its derivatives).
///
/// ```
/// use topoccd::distance::{point_edge_distance_batch, BatchOutput, PointEdgeType};
/// use topoccd::math::DVec3;
/// let pairs = [[DVec3::new(0.5, 2.0, 0.0), DVec3::ZERO, DVec3::X]];
/// let mut d = [0.0];
/// let out = BatchOutput { distances: &mut d, gradients: None, hessians: None };
/// point_edge_distance_batch(&pairs, &[PointEdgeType::Interior], out)?;
/// assert_eq!(d, [4.0]);
/// # Ok::<(), topoccd::distance::BatchLengthError>(())
/// ```
pub fn point_edge_distance_batch(
    pairs: &[[DVec3; 3]],
    types: &[PointEdgeType],
    out: BatchOutput<'_, 9>,
) -> Result<(), BatchLengthError> {
    let n = pairs.len();
    check_types(n, types.len())?;
    out.check(n)?;
    let (pairs, types) = (&pairs[..n], &types[..n]);
    run(
        n,
        out,
        |i| point_edge_distance_of_type(pairs[i][0], pairs[i][1], pairs[i][2], types[i]),
        |i| point_edge_distance_gradient(pairs[i][0], pairs[i][1], pairs[i][2], types[i]),
        |i| point_edge_distance_hessian(pairs[i][0], pairs[i][1], pairs[i][2], types[i]),
    );
    Ok(())
}

/// The squared distances of point-triangle pairs `[p, t0, t1, t2]` of the given types, with
/// gradients and Hessians on request ([`point_triangle_distance_of_type`] and its
/// derivatives).
///
/// ```
/// use topoccd::distance::{point_triangle_distance_batch, BatchOutput, PointTriangleType};
/// use topoccd::math::DVec3;
/// let pairs = [[DVec3::new(0.25, 0.25, 2.0), DVec3::ZERO, DVec3::X, DVec3::Y]];
/// let (mut d, mut g, mut h) = ([0.0], [[0.0; 12]], [[[0.0; 12]; 12]]);
/// let out = BatchOutput { distances: &mut d, gradients: Some(&mut g), hessians: Some(&mut h) };
/// point_triangle_distance_batch(&pairs, &[PointTriangleType::Interior], out)?;
/// assert_eq!((d[0], g[0][2], h[0][2][2]), (4.0, 4.0, 2.0));
/// # Ok::<(), topoccd::distance::BatchLengthError>(())
/// ```
pub fn point_triangle_distance_batch(
    pairs: &[[DVec3; 4]],
    types: &[PointTriangleType],
    out: BatchOutput<'_, 12>,
) -> Result<(), BatchLengthError> {
    let n = pairs.len();
    check_types(n, types.len())?;
    out.check(n)?;
    let (pairs, types) = (&pairs[..n], &types[..n]);
    run(
        n,
        out,
        |i| {
            let [p, t0, t1, t2] = pairs[i];
            point_triangle_distance_of_type(p, t0, t1, t2, types[i])
        },
        |i| {
            let [p, t0, t1, t2] = pairs[i];
            point_triangle_distance_gradient(p, t0, t1, t2, types[i])
        },
        |i| {
            let [p, t0, t1, t2] = pairs[i];
            point_triangle_distance_hessian(p, t0, t1, t2, types[i])
        },
    );
    Ok(())
}

/// The squared distances of edge-edge pairs `[ea0, ea1, eb0, eb1]` of the given types, with
/// gradients and Hessians on request ([`edge_edge_distance_of_type`] and its derivatives).
///
/// ```
/// use topoccd::distance::{edge_edge_distance_batch, BatchOutput, EdgeEdgeType};
/// use topoccd::math::DVec3;
/// let pairs = [[DVec3::ZERO, DVec3::X, DVec3::new(0.5, -1.0, 1.0), DVec3::new(0.5, 1.0, 1.0)]];
/// let mut d = [0.0];
/// let out = BatchOutput { distances: &mut d, gradients: None, hessians: None };
/// edge_edge_distance_batch(&pairs, &[EdgeEdgeType::EaEb], out)?;
/// assert_eq!(d, [1.0]);
/// // A buffer of the wrong length is an error, not a panic.
/// let out = BatchOutput { distances: &mut [], gradients: None, hessians: None };
/// assert!(edge_edge_distance_batch(&pairs, &[EdgeEdgeType::EaEb], out).is_err());
/// # Ok::<(), topoccd::distance::BatchLengthError>(())
/// ```
pub fn edge_edge_distance_batch(
    pairs: &[[DVec3; 4]],
    types: &[EdgeEdgeType],
    out: BatchOutput<'_, 12>,
) -> Result<(), BatchLengthError> {
    let n = pairs.len();
    check_types(n, types.len())?;
    out.check(n)?;
    let (pairs, types) = (&pairs[..n], &types[..n]);
    run(
        n,
        out,
        |i| {
            let [a0, a1, b0, b1] = pairs[i];
            edge_edge_distance_of_type(a0, a1, b0, b1, types[i])
        },
        |i| {
            let [a0, a1, b0, b1] = pairs[i];
            edge_edge_distance_gradient(a0, a1, b0, b1, types[i])
        },
        |i| {
            let [a0, a1, b0, b1] = pairs[i];
            edge_edge_distance_hessian(a0, a1, b0, b1, types[i])
        },
    );
    Ok(())
}
