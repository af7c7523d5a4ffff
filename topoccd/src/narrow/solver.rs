//! The inclusion-based root finder shared by the vertex-face and edge-edge tests.
//!
//! # The problem
//! Both tests ask whether a function `F(t, u, v)` from the box `[0, t_max] x [0, 1] x [0, 1]` to
//! 3-space has a zero (or a point within `min_separation` of zero), and for the smallest such `t`.
//! `F` is the vector between the two closest candidates:
//!
//! - vertex-face: `F = v(t) - x(t, u, v)` where `x(t, u, v) = f0 + u (f1 - f0) + u v (f2 - f1)`
//!   sweeps the triangle exactly once as `(u, v)` covers the unit square (a Duffy-type
//!   parametrisation: no part of the square maps outside the triangle, so nothing is tested
//!   beyond the triangle's edges);
//! - edge-edge: `F = ea(t, u) - eb(t, v)` with `ea = ea0 + u (ea1 - ea0)`, `eb = eb0 + v (eb1 - eb0)`.
//!
//! In both cases `F = P(t) + u A(t) + w B(t)` with `w = u v` (vertex-face) or `w = v` (edge-edge)
//! and `P, A, B` linear in `t`: `F` is multilinear (degree one in each of `t`, `u`, `v`). A
//! multilinear function on a box takes every value as a convex combination of its eight corner
//! values, so the image of a box lies in the convex hull of the images of its corners. If a plane
//! separates that hull from the ball of radius `min_separation` around the origin, the box holds
//! no contact.
//!
//! # The search
//! Boxes are examined best-first: smallest start time first, then deepest first. A box is
//! *excluded* when one of these directions separates its corner images from the origin:
//! the three coordinate axes, the direction of the mean of the corner images (which is the value
//! of `F` at the centre of the box), and the normal `A x B` at both ends of the box's time
//! interval (the face normal for vertex-face, the common normal of the edges for edge-edge).
//! Otherwise the box is split in half along its unresolved dimension of largest extent in
//! `F`-space. A dimension is *resolved* when its width is at most `tolerance` (or `F` does not
//! depend on it). A box that cannot be excluded and has every dimension resolved is a contact at
//! its start time. Because boxes leave the queue in order of start time and an excluded box holds
//! no contact, the reported time is never later than the first true contact, and when the
//! reported box holds that contact it is within `tolerance` of it.
//!
//! # Floating point
//! The corner values are computed in `f64` and may be wrong by rounding. Each difference vector
//! (`P`, `A`, `B` at t=0 and t=1) is one rounded subtraction of input coordinates, so it is exact
//! to a relative `2^-53`. Following every later operation (a lerp in `t`, two scaled additions)
//! bounds the error of each computed corner coordinate by `33 u M`, where `u = 2^-53` and `M` is the
//! largest coordinate of the six difference vectors; a projection on a direction `n` adds
//! `30 u M |n|_1`. The test uses `64 u M` and `128 u M |n|_1`, about twice these, and excludes a
//! box only when the separation exceeds `min_separation` plus that bound. No exclusion is
//! therefore wrong in exact arithmetic: the test never misses a contact. The bound is relative
//! to the size of the difference vectors, not to the absolute coordinates, so the answers do not
//! depend on where the features sit (up to the one rounding of each input difference) nor on the
//! scale of the coordinates.
//!
//! # False positives
//! A box reported as a contact was not separated along the coordinate axes, and each of its
//! dimensions is at most `tolerance` wide. Its corner images therefore span, per coordinate, at
//! most `tolerance (S_t + S_u + S_v)`, where `S_t` is how fast `F` changes in time (the relative
//! displacement of the features over the step) and `S_u + S_v` at most twice the features' size.
//! So a contact is reported only if the features come within
//! `sqrt(3) (min_separation + tolerance (S_t + S_u + S_v) + 64 u M)` of each other at a time in
//! `[toi, toi + tolerance]`. With the default tolerance that is about a millionth of the size
//! and motion of the features; in practice far less, since the centroid direction separates
//! boxes whose image stays off the origin by more than their own size.
//!
//! # Iteration limit
//! When `max_iterations` boxes have been examined, the answer is a contact at the start time of
//! the next box in the queue, the earliest time not yet ruled out ([`Certainty::IterationLimit`]).

use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;

use super::{Certainty, EdgeEdge, NarrowOptions, Outcome, VertexFace};
use crate::math::{max_abs, DVec3, UNIT_ROUNDOFF};

/// Bound on the rounding error of a computed corner coordinate, in units of `u M` (see the
/// module documentation: the analysis gives 33; this keeps a factor of about two in reserve).
const CORNER_ERROR: f64 = 64.0;
/// Bound on the rounding error of a projection, in units of `u M |n|_1`.
const PROJECTION_ERROR: f64 = 128.0;
/// Absolute error allowance for results in the subnormal range, where rounding is not relative.
const UNDERFLOW_ERROR: f64 = 1e-290;

/// Which multilinear form `F = P + u A + w B` takes: `w = u v` or `w = v`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Weight {
    /// `w = u v`: the vertex-face parametrisation of the triangle.
    Product,
    /// `w = v`: the edge-edge parametrisation.
    Plain,
}

/// One elementary test, reduced to the multilinear function `F = P(t) + u A(t) + w B(t)`.
#[derive(Clone, Copy, Debug)]
pub struct Problem {
    p: [DVec3; 2],
    a: [DVec3; 2],
    b: [DVec3; 2],
    weight: Weight,
    finite: bool,
}

impl Problem {
    /// The vertex-face problem `F = v - f0 + u (f0 - f1) + u v (f1 - f2)`.
    pub fn vertex_face(q: &VertexFace) -> Self {
        Self::new(
            [q.v_t0 - q.f0_t0, q.v_t1 - q.f0_t1],
            [q.f0_t0 - q.f1_t0, q.f0_t1 - q.f1_t1],
            [q.f1_t0 - q.f2_t0, q.f1_t1 - q.f2_t1],
            Weight::Product,
            &q.points(),
        )
    }

    /// The edge-edge problem `F = ea0 - eb0 + u (ea1 - ea0) + v (eb0 - eb1)`.
    pub fn edge_edge(q: &EdgeEdge) -> Self {
        Self::new(
            [q.ea0_t0 - q.eb0_t0, q.ea0_t1 - q.eb0_t1],
            [q.ea1_t0 - q.ea0_t0, q.ea1_t1 - q.ea0_t1],
            [q.eb0_t0 - q.eb1_t0, q.eb0_t1 - q.eb1_t1],
            Weight::Plain,
            &q.points(),
        )
    }

    fn new(p: [DVec3; 2], a: [DVec3; 2], b: [DVec3; 2], weight: Weight, pts: &[DVec3; 8]) -> Self {
        let finite = pts.iter().all(|x| x.is_finite())
            && p.iter().chain(&a).chain(&b).all(|x| x.is_finite());
        Self {
            p,
            a,
            b,
            weight,
            finite,
        }
    }
}

/// A box of the parameter domain. Intervals are `[lo, hi]`.
#[derive(Clone, Copy, Debug)]
struct Cell {
    t: [f64; 2],
    u: [f64; 2],
    v: [f64; 2],
    depth: u32,
}

/// Queue entry: earliest start time first, then deepest first (a depth-first dive towards the
/// first contact), then insertion order, so the search is deterministic.
struct Entry(Cell);

impl Entry {
    fn key(&self) -> (Reverse<u64>, u32) {
        // Start times are non-negative finite floats, whose bit patterns order like the values.
        (Reverse(self.0.t[0].to_bits()), self.0.depth)
    }
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.key() == other.key()
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        self.key().cmp(&other.key())
    }
}

/// Constants of one search, derived from the problem and the options.
struct Search<'a> {
    problem: &'a Problem,
    dp: DVec3,
    da: DVec3,
    db: DVec3,
    /// Error bound of a corner coordinate.
    eps: f64,
    /// Error bound of a projection, per unit of `|n|_1`.
    eps_proj: f64,
    sep: f64,
    tol: f64,
    /// How much `F` changes, per unit width, along t, u, v.
    rate: [f64; 3],
}

/// Result of examining one box.
enum Verdict {
    Excluded,
    Contact,
    Split(usize),
}

/// Runs the search of the module documentation. Returns the outcome and the number of boxes
/// examined.
pub fn solve_counted(problem: &Problem, options: &NarrowOptions) -> (Outcome, u32) {
    if !problem.finite {
        let outcome = Outcome::Contact {
            toi: 0.0,
            certainty: Certainty::InvalidInput,
        };
        return (outcome, 0);
    }
    let t_max = if options.t_max.is_nan() {
        1.0
    } else {
        options.t_max.clamp(0.0, 1.0)
    };
    let tol = if options.tolerance > 0.0 {
        options.tolerance.min(1.0)
    } else {
        NarrowOptions::default().tolerance
    };
    let sep = if options.min_separation > 0.0 && options.min_separation.is_finite() {
        options.min_separation
    } else {
        0.0
    };
    let max_iterations = options.max_iterations.max(1);

    let [p0, p1] = problem.p;
    let [a0, a1] = problem.a;
    let [b0, b1] = problem.b;
    let m = [p0, p1, a0, a1, b0, b1]
        .iter()
        .map(|x| max_abs(*x))
        .fold(0.0, f64::max);
    let eps = CORNER_ERROR * UNIT_ROUNDOFF * m + UNDERFLOW_ERROR;
    let (dp, da, db) = (p1 - p0, a1 - a0, b1 - b0);
    let size_a = max_abs(a0).max(max_abs(a1));
    let size_b = max_abs(b0).max(max_abs(b1));
    let rate_t = max_abs(dp) + max_abs(da) + max_abs(db);
    let rate = match problem.weight {
        Weight::Product => [rate_t, size_a + size_b, size_b],
        Weight::Plain => [rate_t, size_a, size_b],
    };
    let search = Search {
        problem,
        dp,
        da,
        db,
        eps,
        eps_proj: PROJECTION_ERROR * UNIT_ROUNDOFF * m + UNDERFLOW_ERROR,
        sep,
        tol,
        rate,
    };

    let mut queue = BinaryHeap::with_capacity(64);
    queue.push(Entry(Cell {
        t: [0.0, t_max],
        u: [0.0, 1.0],
        v: [0.0, 1.0],
        depth: 0,
    }));
    let mut iterations = 0u32;
    while let Some(Entry(cell)) = queue.pop() {
        if iterations >= max_iterations {
            let outcome = Outcome::Contact {
                toi: cell.t[0],
                certainty: Certainty::IterationLimit,
            };
            return (outcome, iterations);
        }
        iterations += 1;
        match search.examine(&cell) {
            Verdict::Excluded => {}
            Verdict::Contact => {
                let outcome = Outcome::Contact {
                    toi: cell.t[0],
                    certainty: Certainty::Resolved,
                };
                return (outcome, iterations);
            }
            Verdict::Split(dim) => {
                let (lo, hi) = split(&cell, dim);
                queue.push(Entry(lo));
                queue.push(Entry(hi));
            }
        }
    }
    (Outcome::Separated, iterations)
}

/// Runs the search of the module documentation.
pub fn solve(problem: &Problem, options: &NarrowOptions) -> Outcome {
    solve_counted(problem, options).0
}

fn split(cell: &Cell, dim: usize) -> (Cell, Cell) {
    let mut lo = *cell;
    let mut hi = *cell;
    lo.depth += 1;
    hi.depth += 1;
    let (a, b) = match dim {
        0 => (&mut lo.t, &mut hi.t),
        1 => (&mut lo.u, &mut hi.u),
        _ => (&mut lo.v, &mut hi.v),
    };
    let mid = 0.5 * (a[0] + a[1]);
    a[1] = mid;
    b[0] = mid;
    (lo, hi)
}

impl Search<'_> {
    fn examine(&self, cell: &Cell) -> Verdict {
        let corners = self.corners(cell);
        if self.separated(&corners, cell) {
            return Verdict::Excluded;
        }
        let widths = [
            cell.t[1] - cell.t[0],
            cell.u[1] - cell.u[0],
            cell.v[1] - cell.v[0],
        ];
        let mut best: Option<(usize, f64)> = None;
        for dim in 0..3 {
            let resolved = widths[dim] <= self.tol || self.rate[dim] == 0.0;
            if !resolved {
                let extent = widths[dim] * self.rate[dim];
                if best.is_none_or(|(_, e)| extent > e) {
                    best = Some((dim, extent));
                }
            }
        }
        match best {
            None => Verdict::Contact,
            Some((dim, _)) => Verdict::Split(dim),
        }
    }

    /// Values of `F` at the eight corners, `t` slowest, then `u`, then `v`.
    fn corners(&self, cell: &Cell) -> [DVec3; 8] {
        let pr = self.problem;
        let mut out = [DVec3::ZERO; 8];
        let mut k = 0;
        for &t in &cell.t {
            let p = pr.p[0] + self.dp * t;
            let a = pr.a[0] + self.da * t;
            let b = pr.b[0] + self.db * t;
            for &u in &cell.u {
                let pu = p + a * u;
                for &v in &cell.v {
                    let w = match pr.weight {
                        Weight::Product => u * v,
                        Weight::Plain => v,
                    };
                    out[k] = pu + b * w;
                    k += 1;
                }
            }
        }
        out
    }

    fn separated(&self, corners: &[DVec3; 8], cell: &Cell) -> bool {
        // Coordinate axes.
        let mut lo = corners[0];
        let mut hi = corners[0];
        for c in &corners[1..] {
            lo = lo.min(*c);
            hi = hi.max(*c);
        }
        let margin = self.sep + self.eps;
        if lo.max_element() > margin || hi.min_element() < -margin {
            return true;
        }
        // Direction of F at the centre of the box.
        let centre = corners.iter().fold(DVec3::ZERO, |s, c| s + *c);
        if self.separated_along(corners, centre, false) {
            return true;
        }
        // Face normal (vertex-face) or common normal of the edges (edge-edge), at both ends.
        let pr = self.problem;
        for &t in &cell.t {
            let a = pr.a[0] + self.da * t;
            let b = pr.b[0] + self.db * t;
            if self.separated_along(corners, a.cross(b), true) {
                return true;
            }
        }
        false
    }

    /// Whether all corner projections on `n` exceed the margin (on the positive side, or on
    /// either side if `both_sides`).
    fn separated_along(&self, corners: &[DVec3; 8], n: DVec3, both_sides: bool) -> bool {
        let n1 = n.x.abs() + n.y.abs() + n.z.abs();
        if n1 == 0.0 || !n1.is_finite() {
            return false;
        }
        // |n|_2 rounded up generously; the margin must not shrink below min_separation |n|_2.
        let n2 = n.length() * (1.0 + 8.0 * UNIT_ROUNDOFF);
        let margin = self.sep * n2 + self.eps_proj * n1;
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for c in corners {
            let s = c.dot(n);
            lo = lo.min(s);
            hi = hi.max(s);
        }
        lo > margin || (both_sides && hi < -margin)
    }
}
