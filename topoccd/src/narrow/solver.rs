//! The inclusion-based root finder shared by the vertex-face and edge-edge tests.
//!
//! # The problem
//! Both tests ask whether a function `F(t, u, v)` from the box `[0, tmax] x [0, 1] x [0, 1]` to
//! 3-space has a zero (or a point within `min_distance` of zero), and for the smallest such `t`.
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
//! separates that hull from the ball of radius `min_distance` around the origin, the box holds
//! no contact.
//!
//! # The search
//! At a fixed time the image `{F(t, u, v)}` of the whole feature domain is convex: the triangle
//! seen from the vertex (`P, P + A, P + A + B`), or the parallelogram of differences of points of
//! the two edges. So a box spanning the whole `(u, v)` domain and a short time interval has a
//! corner hull within `w S_t / 2` of that convex image at its mid time (`w` the box's width in t,
//! `S_t = |dP| + |dA| + |dB|` how fast `F` can change), and the best direction to separate it is
//! `F` at the features' closest points at mid time (point-triangle or segment-segment closest
//! points, [`closest`]). The search is then a bisection in t alone.
//!
//! A box is *excluded* when one of these directions separates its corner images from the ball of
//! radius `min_distance`: the three coordinate axes, the closest points' direction, the normal
//! `A x B` at both ends of the box's time interval (the face normal for vertex-face, the common
//! normal of the edges for edge-edge), and, for the coplanarity of the four points that any
//! contact needs, the Bernstein coefficients of the coplanarity cubic `P . (A x B)` on the box's
//! time interval (with `min_distance = 0`). Where that cubic changes sign, the box is split
//! around its predicted crossing (the Illinois method) into an earlier box, a slab of width
//! `tolerance` and a later box; otherwise in half. A box that cannot be excluded is split in t until its width is at most `tolerance`; it is then a
//! *contact box*.
//!
//! Only for degenerate features, whose closest points cannot be computed (a zero-area triangle
//! at the edge of the representable range), the box is split in every dimension: along its
//! unresolved dimension of largest extent (how much `F` can change across the box along it), a
//! dimension being resolved when its extent is at most `tolerance` times the largest extent along
//! it over the whole domain. Those boxes also try the centre direction with its component along
//! each edge removed (the gap between nearly parallel edges, or between a vertex and a face edge
//! within the face's plane).
//!
//! The boxes are searched depth first, earlier half first, as a branch and bound: once a contact
//! box starting at time `T` is found, every other box is clipped to end at `T`, or dropped if it
//! starts at `T` or later. The answer is the smallest `T` found. It is never later than the first
//! true contact `t*`: the box holding `t*` is never excluded, so it (or a part of it starting at or
//! before `t*`) is either a contact box (then `T <= t*`) or dropped because `T` was already at most
//! its start. When the answer's box holds that contact, `T >= t* - tolerance`. Clipping is what
//! keeps contact sets shaped as lines or surfaces cheap (two parallel edges overlapping, a vertex
//! sliding in a face): once `T` is known, the clipped boxes hold no contact and are excluded at
//! once instead of being refined along the whole set.
//!
//! # Floating point
//! The corner values are computed in `f64` and may be wrong by rounding. Each difference vector
//! (`P`, `A`, `B` at t=0 and t=1) is one rounded subtraction of input coordinates, so it is exact
//! to a relative `u = 2^-53`. Two bounds of the rounding error are used, and a box is excluded only
//! when the separation exceeds `min_distance` plus the bound, so no exclusion is wrong in exact
//! arithmetic and the test never misses a contact:
//! - a static bound, the fast path: following every operation (a lerp in `t`, two scaled
//!   additions) bounds the error of each computed corner coordinate by `33 u M`, where `M` is the
//!   largest coordinate of the six difference vectors; the test uses `64 u M`;
//! - a running bound, where the static one cannot separate the box: each operation `z = x op y`
//!   adds `u |z|` to the propagated bounds of its operands (Wilkinson's running error analysis),
//!   then doubled. It is far tighter near the origin of `F`, where near-misses live.
//!
//! A projection on a direction `n` adds the propagated error `e . |n|` and the rounding of the dot
//! product (`gamma_3 < 4u`, doubled). Both bounds are relative to the size of the difference
//! vectors, not to the absolute coordinates, so the answers do not depend on where the features
//! sit (up to the one rounding of each input difference) nor on the scale of the coordinates.
//! Differences larger than [`MAX_DIFFERENCE`] (where an intermediate could overflow) and
//! non-finite input are refused with a conservative contact at t=0.
//!
//! # False positives, and how early a time of impact can be
//! A contact box `[T, T + w]` (`w <= tolerance`) spanning the whole feature domain was not
//! separated along the closest points' direction `d` at its mid time. Every corner lies within
//! `sqrt(3) w S_t / 2` of the image at mid time (`S_t` bounds each coordinate's rate, so the
//! Euclidean distance takes `sqrt(3)`), whose projections on the exact closest direction are all
//! at least the features' distance. So when `d` is that direction, the features come within
//! `B = min_distance + sqrt(3) tolerance S_t / 2 + rounding` of each other at a time in
//! `[T, T + tolerance]`. With the default tolerance that is about a millionth of the features'
//! relative displacement over the step. This bounds the false positives, and also how early a
//! reported time can be: when two features graze (come within `B` well before they touch), the
//! reported time is the start of the first such interval, possibly earlier than
//! `t* - tolerance`, never later than `t*`.
//!
//! The closest points are computed in floating point, and where the features are nearly
//! parallel edges (or a vertex near a face edge) their direction can be off by more than the
//! gap allows: two sheets 1e-7 apart in resting contact have coplanar edges parallel to 1e-6,
//! and a direction off by 1e-6 radians over edges 0.06 long misses a gap of 1e-12. A contact
//! box whose `|d|` (at least the features' distance, up to its rounding) exceeds `B` is therefore
//! tried along `d` with its component along each edge removed, the direction across nearly
//! parallel edges, which such a gap does not blur; only if that fails too is it a contact. (Such
//! boxes reported times up to 0.024 early in resting contact, at 50 times the bound; the case is
//! a test.) Where rounding dominates the features' gaps (coordinates of 1e300 beside
//! coordinates of 1), `B`'s rounding term is what it is, and the bound holds only with the
//! rounding of the closest points too.
//! (For degenerate features, the bound is `sqrt(3) (min_distance + tolerance (S_t + S_u + S_v)
//! + rounding)`, `S_u + S_v` being at most twice the features' size.)
//!
//! # Iteration limit
//! When `max_iterations` boxes have been examined, the answer is a contact at the start time of
//! the next box in the queue, the earliest time not yet ruled out ([`Certainty::IterationLimit`]).
//!
//! # Features that share a point at t=0
//! When the vertex sits exactly on a corner of the face at t=0, or an end of one edge exactly on
//! an end of the other (equal coordinates), the features touch at 0: the first contact is 0,
//! exactly, and no search can answer anything else. With at least [`SHARED_POINT_ITERATIONS`]
//! iterations allowed, the answer is that contact, [`Certainty::Resolved`], without a search.
//! (With fewer, the search runs as for any pair: it answers 0 too, as
//! [`Certainty::IterationLimit`] when rounding keeps it from isolating the contact within its
//! budget, as with coordinates of 1e300 beside coordinates of 1.) Positions cast to integers
//! collapse onto a few points and give hundreds of millions of such pairs, each answered in
//! nanoseconds instead of microseconds.

use super::bernstein::{coplanarity_ends, coplanarity_inner};
use super::extremes::{lower, lower3, raise, raise3, raise_abs};
use super::{closest, Certainty, EdgeEdge, NarrowOptions, Outcome, VertexFace};
use crate::math::{max_abs, DVec3, UNDERFLOW_ERROR, UNIT_ROUNDOFF};
use crate::range::{normalizing_scale, within_range};

/// Bound on the rounding error of a computed corner coordinate, in units of `u M` (see the
/// module documentation: the analysis gives 33; this keeps a factor of about two in reserve).
const CORNER_ERROR: f64 = 64.0;
/// Most steps of the crossing prediction ([`Search::predict_crossing`]).
const CROSSING_STEPS: usize = 32;
/// Largest coordinate difference accepted; larger ones count as invalid input (the answer is
/// then a conservative contact at t=0). The input range's bound,
/// [`range::MAX_DIFFERENCE`](crate::range::MAX_DIFFERENCE).
pub const MAX_DIFFERENCE: f64 = crate::range::MAX_DIFFERENCE;

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
    /// The power of two `p`, `a` and `b` were multiplied by ([`normalizing_scale`]); the
    /// search multiplies `min_distance` by it too.
    scale: f64,
    /// Whether the features share a point at t=0: the vertex sits exactly on a corner of the
    /// face, or an end of one edge exactly on an end of the other (equal coordinates).
    shared_at_start: bool,
}

impl Problem {
    /// The vertex-face problem `F = v - f0 + u (f0 - f1) + u v (f1 - f2)`.
    pub fn vertex_face(q: &VertexFace) -> Self {
        let shared = [q.f0_t0, q.f1_t0, q.f2_t0].contains(&q.v_t0);
        Self::new(
            [q.v_t0 - q.f0_t0, q.v_t1 - q.f0_t1],
            [q.f0_t0 - q.f1_t0, q.f0_t1 - q.f1_t1],
            [q.f1_t0 - q.f2_t0, q.f1_t1 - q.f2_t1],
            Weight::Product,
            &q.points(),
            shared,
        )
    }

    /// The edge-edge problem `F = ea0 - eb0 + u (ea1 - ea0) + v (eb0 - eb1)`.
    pub fn edge_edge(q: &EdgeEdge) -> Self {
        let shared = [q.eb0_t0, q.eb1_t0].contains(&q.ea0_t0) || [q.eb0_t0, q.eb1_t0].contains(&q.ea1_t0);
        Self::new(
            [q.ea0_t0 - q.eb0_t0, q.ea0_t1 - q.eb0_t1],
            [q.ea1_t0 - q.ea0_t0, q.ea1_t1 - q.ea0_t1],
            [q.eb0_t0 - q.eb1_t0, q.eb0_t1 - q.eb1_t1],
            Weight::Plain,
            &q.points(),
            shared,
        )
    }

    fn new(
        p: [DVec3; 2],
        a: [DVec3; 2],
        b: [DVec3; 2],
        weight: Weight,
        pts: &[DVec3; 8],
        shared_at_start: bool,
    ) -> Self {
        // Differences must stay far enough from overflow that every intermediate value (at most
        // a few times larger) and its error bound stay finite: the input range.
        let largest = p.iter().chain(&a).chain(&b).fold(0.0, |m, x| raise_abs(m, *x));
        let finite = pts.iter().all(|x| x.is_finite()) && within_range(largest);
        // Far from 1, the differences are brought near it (exactly) so that neither their
        // cubes overflow nor the error bounds' underflow allowance swamps them.
        let scale = if finite { normalizing_scale(largest) } else { 1.0 };
        let (p, a, b) = if scale == 1.0 {
            (p, a, b)
        } else {
            (p.map(|x| x * scale), a.map(|x| x * scale), b.map(|x| x * scale))
        };
        Self {
            p,
            a,
            b,
            weight,
            finite,
            scale,
            shared_at_start,
        }
    }
}

/// With at least this many iterations allowed, a problem whose features share a point at t=0
/// is answered at once: a contact at 0, resolved (see the module documentation).
pub const SHARED_POINT_ITERATIONS: u32 = 1 << 16;

/// A box of the parameter domain. Intervals are `[lo, hi]`.
#[derive(Clone, Copy, Debug)]
struct Cell {
    t: [f64; 2],
    u: [f64; 2],
    v: [f64; 2],
}

/// `P`, `A` and `B` at the two ends of a box's time interval, computed once per box: the
/// coplanarity test, the corners, the normals and the crossing prediction all start from them.
struct Ends {
    p: [DVec3; 2],
    a: [DVec3; 2],
    b: [DVec3; 2],
    /// The normals `A x B`.
    n: [DVec3; 2],
}

/// Constants of one search, derived from the problem and the options.
struct Search<'a> {
    problem: &'a Problem,
    dp: DVec3,
    da: DVec3,
    db: DVec3,
    /// Error bound of a corner coordinate.
    eps: f64,
    /// Largest coordinate of the six difference vectors.
    m: f64,
    sep: f64,
    tol: f64,
    /// How much `F` changes, per unit width, along t, u, v, at most over the whole domain.
    rate: [f64; 3],
    /// Largest coordinate of `A` and of `B` over the step.
    size_a: f64,
    size_b: f64,
}

/// How the corner values' error bounds are known.
#[derive(Clone, Copy)]
enum Errors<'a> {
    /// The static bound `eps` for every coordinate of every corner; `largest` is the largest
    /// absolute corner coordinate.
    Static { largest: f64 },
    /// A running bound per corner coordinate.
    Running(&'a [DVec3; 8]),
}

/// Whether a box is separated from the origin.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Separation {
    /// Proved, with the error bounds.
    Yes,
    /// Not proved, but the computed values alone would separate: a tighter bound may prove it.
    Ambiguous,
    /// The computed values themselves do not separate: no tighter bound can help.
    No,
}

/// Result of examining one box.
enum Verdict {
    Excluded,
    Contact,
    Split(usize),
    /// Split in t around a predicted contact time: `[t0, lo]`, `[lo, hi]`, `[hi, t1]`.
    Bracket(f64, f64),
}

/// Runs the search of the module documentation. Returns the outcome and the number of boxes
/// examined.
pub fn solve_counted(problem: &Problem, options: &NarrowOptions) -> (Outcome, u32) {
    solve_counted_from(problem, options, 0.0)
}

/// [`solve_counted`] over `[t_start, tmax]` only, for a caller that has proved the features
/// apart by more than `min_distance` during `[0, t_start]` (the prefilter's pieces): the
/// search starts from the box `[t_start, tmax] x [0, 1]^2`, and the answer is the same kind
/// (never later than the first contact, which is not before `t_start`; separated when
/// `t_start > 0` reaches `tmax`).
pub(crate) fn solve_counted_from(
    problem: &Problem,
    options: &NarrowOptions,
    t_start: f64,
) -> (Outcome, u32) {
    if !problem.finite {
        let outcome = Outcome::Contact {
            toi: 0.0,
            certainty: Certainty::InvalidInput,
        };
        return (outcome, 0);
    }
    let (search, tmax) = Search::new(problem, options);
    if t_start > 0.0 && t_start >= tmax {
        // Apart during the whole interval.
        return (Outcome::Separated, 0);
    }
    if problem.shared_at_start && t_start <= 0.0 && options.max_iterations >= SHARED_POINT_ITERATIONS
    {
        // The features touch at t=0 (a shared point, exactly): the first contact is 0.
        let outcome = Outcome::Contact {
            toi: 0.0,
            certainty: Certainty::Resolved,
        };
        return (outcome, 0);
    }
    let max_iterations = options.max_iterations.max(1);
    // Depth-first branch and bound: `best` is the earliest start of a contact box found so far;
    // every later box is clipped to end there, or dropped if it starts there or later.
    STACK.with_borrow_mut(|stack| {
        stack.clear();
        search.run(stack, [t_start.clamp(0.0, tmax), tmax], max_iterations)
    })
}

impl<'a> Search<'a> {
    /// The search's constants for a problem with finite input, and the end of its interval.
    fn new(problem: &'a Problem, options: &NarrowOptions) -> (Self, f64) {
        let tmax = if options.tmax.is_nan() {
            1.0
        } else {
            options.tmax.clamp(0.0, 1.0)
        };
        let tol = if options.tolerance > 0.0 {
            options.tolerance.min(1.0)
        } else {
            NarrowOptions::default().tolerance
        };
        let sep = if options.min_distance > 0.0 && options.min_distance.is_finite() {
            // Scaled with the differences; beyond 1e300 the features touch anyway (their
            // distance is at most a few times the largest scaled difference, below 4).
            (options.min_distance * problem.scale).min(MAX_DIFFERENCE)
        } else {
            0.0
        };

        let [p0, p1] = problem.p;
        let [a0, a1] = problem.a;
        let [b0, b1] = problem.b;
        let m = [p0, p1, a0, a1, b0, b1]
            .iter()
            .fold(0.0, |m, x| raise_abs(m, *x));
        let eps = CORNER_ERROR * UNIT_ROUNDOFF * m + UNDERFLOW_ERROR;
        let (dp, da, db) = (p1 - p0, a1 - a0, b1 - b0);
        let size_a = max_abs(a0).max(max_abs(a1));
        let size_b = max_abs(b0).max(max_abs(b1));
        let rate_t = max_abs(dp) + max_abs(da) + max_abs(db);
        let rate = match problem.weight {
            Weight::Product => [rate_t, size_a + size_b, size_b],
            Weight::Plain => [rate_t, size_a, size_b],
        };
        let search = Self {
            problem,
            dp,
            da,
            db,
            eps,
            m,
            sep,
            tol,
            rate,
            size_a,
            size_b,
        };
        (search, tmax)
    }
}

thread_local! {
    /// The search's stack of boxes, kept per thread so a query allocates nothing.
    static STACK: std::cell::RefCell<Vec<Cell>> = const { std::cell::RefCell::new(Vec::new()) };
}

impl Search<'_> {
    /// The depth-first branch and bound of the module documentation, from the box
    /// `t x [0, 1]^2`. Returns the outcome and the number of boxes examined.
    fn run(&self, stack: &mut Vec<Cell>, t: [f64; 2], max_iterations: u32) -> (Outcome, u32) {
        let search = self;
        stack.push(Cell {
            t,
            u: [0.0, 1.0],
            v: [0.0, 1.0],
        });
        let mut best: Option<f64> = None;
        let mut iterations = 0u32;
        while let Some(mut cell) = stack.pop() {
            if let Some(b) = best {
                if cell.t[0] >= b {
                    continue;
                }
                cell.t[1] = cell.t[1].min(b);
            }
            if iterations >= max_iterations {
                // Give up: the earliest time not yet ruled out is the answer.
                let open = stack.iter().map(|c| c.t[0]).fold(cell.t[0], f64::min);
                let toi = best.map_or(open, |b| b.min(open));
                let outcome = Outcome::Contact {
                    toi,
                    certainty: Certainty::IterationLimit,
                };
                return (outcome, iterations);
            }
            iterations += 1;
            match search.examine(&cell) {
                Verdict::Excluded => {}
                Verdict::Contact => best = Some(cell.t[0]),
                Verdict::Split(dim) => {
                    let (lo, hi) = split(&cell, dim);
                    // The earlier half (or the lower half in u, v) is examined first.
                    stack.push(hi);
                    stack.push(lo);
                }
                Verdict::Bracket(lo, hi) => {
                    // Three boxes covering the cell, the earliest examined first.
                    for t in [[hi, cell.t[1]], [lo, hi], [cell.t[0], lo]] {
                        if t[0] < t[1] {
                            stack.push(Cell { t, ..cell });
                        }
                    }
                }
            }
        }
        let outcome = match best {
            Some(toi) => Outcome::Contact {
                toi,
                certainty: Certainty::Resolved,
            },
            None => Outcome::Separated,
        };
        (outcome, iterations)
    }
}

/// Runs the search of the module documentation.
pub fn solve(problem: &Problem, options: &NarrowOptions) -> Outcome {
    solve_counted(problem, options).0
}

fn split(cell: &Cell, dim: usize) -> (Cell, Cell) {
    let mut lo = *cell;
    let mut hi = *cell;
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
        // A box spanning the whole feature domain (u, v in [0, 1]) has, at each time, the exact
        // image of the features: the triangle seen from the vertex, or the parallelogram of edge
        // differences. Its best separating direction is the vector between the closest points
        // of the features at the box's mid time.
        let whole = cell.u == [0.0, 1.0] && cell.v == [0.0, 1.0];
        let ends = self.ends(cell.t);
        // Contact needs the four points coplanar: where the coplanarity cubic keeps one sign over
        // the box's time interval, there is none (for min_distance = 0). This excludes about
        // half the boxes on a cloth step, so it runs before the closest points are computed.
        // Its end coefficients are the cubic's values at the ends, which the crossing
        // prediction below reuses.
        let mut g_ends = None;
        if whole && self.sep == 0.0 {
            let g = coplanarity_ends(ends.p, ends.n);
            if self.never_coplanar(&ends, g) {
                return Verdict::Excluded;
            }
            g_ends = Some(g);
        }
        let closest = if whole {
            self.closest_direction(0.5 * (cell.t[0] + cell.t[1]))
        } else {
            None
        };
        // Fast path: one static error bound for every corner. Only where it was ambiguous (the
        // computed values separate, their static bound does not), the running bound.
        let corners = self.corners(cell, &ends);
        let largest = corners.iter().fold(0.0, |m, c| raise_abs(m, *c));
        match self.separated(&corners, Errors::Static { largest }, cell, &ends, closest) {
            Separation::Yes => return Verdict::Excluded,
            Separation::Ambiguous => {
                let (corners, errors) = self.corners_with_errors(cell);
                if self.separated(&corners, Errors::Running(&errors), cell, &ends, closest)
                    == Separation::Yes
                {
                    return Verdict::Excluded;
                }
            }
            Separation::No => {}
        }
        if let Some(d) = closest {
            // Only time needs resolving: see "False positives" in the module documentation.
            if cell.t[1] - cell.t[0] <= self.tol {
                // Unless the features come as close as the promise of the module
                // documentation says, `d` is not their closest vector (nearly parallel edges,
                // a vertex near a face edge: its direction is off by more than their gap
                // allows), and the directions across the edges may exclude the box.
                if !self.within_bound(cell, d) && self.separated_across_edges(cell, d) {
                    return Verdict::Excluded;
                }
                return Verdict::Contact;
            }
            return match self.predict_crossing(cell, g_ends) {
                Some((lo, hi)) => Verdict::Bracket(lo, hi),
                None => Verdict::Split(0),
            };
        }
        // Degenerate features (no closest points): split every dimension. A dimension is
        // resolved when the box's extent along it (how much F can change across the box in that
        // dimension) is at most `tolerance` times the largest such extent over the whole domain;
        // for t this is a width of at most `tolerance`. Measuring extents rather than parameter
        // widths matters where the parametrisation degenerates (near u = 0 the vertex-face `v`
        // moves the point by only `u |B|`).
        let extents = self.extents(cell);
        let mut best: Option<(usize, f64)> = None;
        for (dim, &extent) in extents.iter().enumerate() {
            let resolved = extent <= self.tol * self.rate[dim];
            if !resolved && best.is_none_or(|(_, e)| extent > e) {
                best = Some((dim, extent));
            }
        }
        match best {
            None => Verdict::Contact,
            Some((dim, _)) => Verdict::Split(dim),
        }
    }

    /// Whether a contact box spanning the whole feature domain, not separated along `d`
    /// (`F` at the features' closest points at its mid time, as computed), keeps the promise of
    /// the module documentation: the features come within `min_distance` plus the box's
    /// blur `sqrt(3) w S_t / 2` plus rounding of each other at its mid time, `|d|` being at
    /// least their distance (up to its rounding). False when the closest points were computed
    /// badly: then `|d|` overstates how close the features come.
    fn within_bound(&self, cell: &Cell, d: DVec3) -> bool {
        let w = cell.t[1] - cell.t[0];
        let blur = 0.5 * w * self.rate[0] * 3f64.sqrt();
        // `d`'s own rounding: a few static corner bounds per coordinate.
        let rounding = 4.0 * self.eps * 3f64.sqrt();
        d.length() <= (self.sep + blur + rounding) * (1.0 + 8.0 * UNIT_ROUNDOFF)
    }

    /// Whether the corners of a box spanning the whole feature domain are separated along
    /// `d` with its component along each edge of the features removed (at the box's mid
    /// time): the gap between nearly parallel edges, or between a vertex and a face edge, where
    /// sliding along the edge does not blur the separation, and where the closest points'
    /// direction is too imprecise to show it.
    fn separated_across_edges(&self, cell: &Cell, d: DVec3) -> bool {
        let pr = self.problem;
        let t_mid = 0.5 * (cell.t[0] + cell.t[1]);
        let a = pr.a[0] + self.da * t_mid;
        let b = pr.b[0] + self.db * t_mid;
        let edges = match pr.weight {
            Weight::Product => [a, b, a + b],
            Weight::Plain => [a, b, DVec3::ZERO],
        };
        let ends = self.ends(cell.t);
        let corners = self.corners(cell, &ends);
        let (running, errors) = self.corners_with_errors(cell);
        edges.into_iter().any(|e| {
            let ee = e.length_squared();
            if ee == 0.0 || !ee.is_finite() {
                return false;
            }
            let n = d - e * (d.dot(e) / ee);
            let largest = corners.iter().fold(0.0, |m, c| raise_abs(m, *c));
            match self.separated_along(&corners, Errors::Static { largest }, n, false) {
                Separation::Yes => true,
                Separation::Ambiguous => {
                    self.separated_along(&running, Errors::Running(&errors), n, false)
                        == Separation::Yes
                }
                Separation::No => false,
            }
        })
    }

    /// `P`, `A` and `B` at the ends of the time interval `t`.
    fn ends(&self, t: [f64; 2]) -> Ends {
        let pr = self.problem;
        let a = t.map(|t| pr.a[0] + self.da * t);
        let b = t.map(|t| pr.b[0] + self.db * t);
        Ends {
            p: t.map(|t| pr.p[0] + self.dp * t),
            a,
            b,
            n: [a[0].cross(b[0]), a[1].cross(b[1])],
        }
    }

    /// Whether the coplanarity cubic `g(t) = P . (A x B)` (zero exactly when the four points are
    /// coplanar, which every contact needs) provably keeps one sign on the interval whose ends
    /// are `ends`: its four Bernstein coefficients on the interval
    /// ([`coplanarity`](super::bernstein::coplanarity)), from the blossom of the trilinear
    /// determinant, all exceed their rounding error bound in magnitude, with one sign. `g` are
    /// the first and last coefficients, the cubic's values at the ends (computed as
    /// `P . (A x B)` from the same vectors, so bit for bit those of
    /// [`Search::predict_crossing`]); the two middle ones are computed only when both ends pass.
    ///
    /// Error bound: each vector at an end of the interval is computed with an error of at most
    /// `e = 16 u M` per coordinate (the lerp of the static analysis, doubled); a determinant of
    /// vectors of magnitude `m` perturbed by `e` moves by at most `6 e (mA mB + mP mB + mP mA)`,
    /// and its own rounding is at most `6 u . 6 mP mA mB` (`gamma_5` of six 3-products, rounded
    /// up); the averages add less than `2 u` of their size. The bound used doubles the sum.
    fn never_coplanar(&self, ends: &Ends, g: [f64; 2]) -> bool {
        let ([p0, p1], [a0, a1], [b0, b1]) = (ends.p, ends.a, ends.b);
        let e = 16.0 * UNIT_ROUNDOFF * self.m;
        // (The vectors are finite: see `Problem::new`.)
        let mp = raise_abs(raise_abs(0.0, p0), p1) + e;
        let ma = raise_abs(raise_abs(0.0, a0), a1) + e;
        let mb = raise_abs(raise_abs(0.0, b0), b1) + e;
        let bound = 2.0
            * (6.0 * e * (ma * mb + mp * mb + mp * ma) + 40.0 * UNIT_ROUNDOFF * mp * ma * mb)
            + UNDERFLOW_ERROR;
        if !bound.is_finite() {
            return false;
        }
        let above = g[0] > bound && g[1] > bound;
        let below = g[0] < -bound && g[1] < -bound;
        if !(above || below) {
            return false;
        }
        let inner = coplanarity_inner(ends.p, ends.a, ends.b, ends.n);
        if above {
            inner.iter().all(|&c| c > bound)
        } else {
            inner.iter().all(|&c| c < -bound)
        }
    }

    /// The coplanarity function `g(t) = P . (A x B)` at `t`, as the crossing prediction
    /// computes it.
    fn coplanarity_at(&self, t: f64) -> f64 {
        let pr = self.problem;
        let p = pr.p[0] + self.dp * t;
        let a = pr.a[0] + self.da * t;
        let b = pr.b[0] + self.db * t;
        p.dot(a.cross(b))
    }

    /// Where the coplanarity function `g(t) = P . (A x B)` (the signed volume of the four points,
    /// a cubic in t) changes sign across the box, a slab of width `tolerance` around its
    /// crossing, found by at most [`CROSSING_STEPS`] steps of the Illinois method: `(lo, hi)`
    /// strictly inside the box. Only a guess to split at: the three boxes it makes cover the
    /// cell, whatever it is worth.
    ///
    /// `g_ends`, when known, are the values of `g` at the box's ends, as `g` computes them.
    fn predict_crossing(&self, cell: &Cell, g_ends: Option<[f64; 2]>) -> Option<(f64, f64)> {
        let g = |t: f64| self.coplanarity_at(t);
        let (mut t0, mut t1) = (cell.t[0], cell.t[1]);
        let [mut g0, mut g1] = g_ends.unwrap_or_else(|| [g(t0), g(t1)]);
        let product = g0 * g1;
        if product.is_nan() || product >= 0.0 {
            return None; // no certain sign change (or not finite)
        }
        // The Illinois variant of regula falsi: the end that stays put twice in a row has its
        // value halved, so the bracket closes from both sides (plain regula falsi keeps one end
        // and can creep towards the root from the other for ever). It stops once the bracket is
        // at most half as wide as the slab it predicts.
        let mut guess = t0;
        let mut kept = 0i8; // +1: the later end stayed last time; -1: the earlier one
        for _ in 0..CROSSING_STEPS {
            guess = t0 + (t1 - t0) * (g0 / (g0 - g1));
            if !guess.is_finite() {
                return None;
            }
            let gm = g(guess);
            if gm * g0 > 0.0 {
                (t0, g0) = (guess, gm);
                if kept == 1 {
                    g1 *= 0.5;
                }
                kept = 1;
            } else if gm * g1 > 0.0 {
                (t1, g1) = (guess, gm);
                if kept == -1 {
                    g0 *= 0.5;
                }
                kept = -1;
            } else {
                break; // g(guess) is 0 (or not finite): as good as it gets
            }
            // The slab centred on the last guess, one of the bracket's ends, then covers it.
            if t1 - t0 <= 0.5 * self.tol {
                break;
            }
        }
        let h = 0.5 * self.tol;
        let (lo, hi) = (guess - h, guess + h);
        (lo > cell.t[0] && hi < cell.t[1]).then_some((lo, hi))
    }

    /// `F` at the closest points of the two features at time `t`: the point of the features'
    /// image `{F(t, u, v)}` nearest the origin. `None` for degenerate or overflowing features.
    fn closest_direction(&self, t: f64) -> Option<DVec3> {
        let pr = self.problem;
        let p = pr.p[0] + self.dp * t;
        let a = pr.a[0] + self.da * t;
        let b = pr.b[0] + self.db * t;
        match pr.weight {
            // The image is the triangle P, P + A, P + A + B.
            Weight::Product => closest::point_triangle(DVec3::ZERO, p, p + a, p + a + b),
            // The image is {P + u A} - {-v B}: the difference of two segments.
            Weight::Plain => {
                closest::segment_segment(p, p + a, DVec3::ZERO, -b).map(|(x, y)| x - y)
            }
        }
    }

    /// Upper bounds of how much `F` changes across the box along t, u and v.
    fn extents(&self, cell: &Cell) -> [f64; 3] {
        let w = [
            cell.t[1] - cell.t[0],
            cell.u[1] - cell.u[0],
            cell.v[1] - cell.v[0],
        ];
        match self.problem.weight {
            Weight::Product => [
                w[0] * self.rate[0],
                w[1] * (self.size_a + cell.v[1] * self.size_b),
                w[2] * cell.u[1] * self.size_b,
            ],
            Weight::Plain => [w[0] * self.rate[0], w[1] * self.size_a, w[2] * self.size_b],
        }
    }

    /// Values of `F` at the eight corners, `t` slowest, then `u`, then `v`; `ends` are those of
    /// the cell's time interval.
    fn corners(&self, cell: &Cell, ends: &Ends) -> [DVec3; 8] {
        let pr = self.problem;
        let mut out = [DVec3::ZERO; 8];
        let mut k = 0;
        for end in 0..2 {
            let (p, a, b) = (ends.p[end], ends.a[end], ends.b[end]);
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

    /// The corner values of [`Search::corners`], computed the same way, with a rigorous bound
    /// of the rounding error of each coordinate by running error analysis: every operation
    /// `z = x op y` adds `u |z|` to the propagated bounds of its operands.
    fn corners_with_errors(&self, cell: &Cell) -> ([DVec3; 8], [DVec3; 8]) {
        let pr = self.problem;
        let r = UNIT_ROUNDOFF;
        // Each stored difference is one rounded subtraction of input coordinates.
        let input = |x: DVec3| x.abs() * r;
        let diff = |x0: DVec3, x1: DVec3, d: DVec3| input(x0) + input(x1) + d.abs() * r;
        let ends = [
            (
                pr.p[0],
                input(pr.p[0]),
                self.dp,
                diff(pr.p[0], pr.p[1], self.dp),
            ),
            (
                pr.a[0],
                input(pr.a[0]),
                self.da,
                diff(pr.a[0], pr.a[1], self.da),
            ),
            (
                pr.b[0],
                input(pr.b[0]),
                self.db,
                diff(pr.b[0], pr.b[1], self.db),
            ),
        ];
        // x0 + t d, with its error bound.
        let lerp = |(x0, e0, d, ed): (DVec3, DVec3, DVec3, DVec3), t: f64| {
            let td = d * t;
            let x = x0 + td;
            (x, e0 + ed * t + td.abs() * r + x.abs() * r)
        };
        let mut values = [DVec3::ZERO; 8];
        let mut errors = [DVec3::ZERO; 8];
        let mut k = 0;
        for &t in &cell.t {
            let (p, ep) = lerp(ends[0], t);
            let (a, ea) = lerp(ends[1], t);
            let (b, eb) = lerp(ends[2], t);
            for &u in &cell.u {
                let ua = a * u;
                let pu = p + ua;
                let epu = ep + ea * u + ua.abs() * r + pu.abs() * r;
                for &v in &cell.v {
                    // The weight w and the bound of its own rounding (u v is one product).
                    let (w, ew) = match pr.weight {
                        Weight::Product => {
                            let w = u * v;
                            (w, w * r)
                        }
                        Weight::Plain => (v, 0.0),
                    };
                    let wb = b * w;
                    let ewb = eb * w + (b.abs() + eb) * ew + wb.abs() * r;
                    let f = pu + wb;
                    values[k] = f;
                    // Twice the bound, for the rounding of the bound itself; plus underflow.
                    errors[k] = (epu + ewb + f.abs() * r) * 2.0 + DVec3::splat(UNDERFLOW_ERROR);
                    k += 1;
                }
            }
        }
        (values, errors)
    }

    /// Whether a direction separates the corner images, each known to within its error bound,
    /// from the ball of radius `min_distance` around the origin.
    fn separated(
        &self,
        corners: &[DVec3; 8],
        errors: Errors<'_>,
        cell: &Cell,
        ends: &Ends,
        closest: Option<DVec3>,
    ) -> Separation {
        let mut verdict = Separation::No;
        // Coordinate axes.
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for c in corners {
            lo = lower3(lo, *c);
            hi = raise3(hi, *c);
        }
        let (lo_e, hi_e) = match errors {
            // Rounding is monotonic, so with one finite bound for every (finite) corner the
            // extreme of the shifted values is the shifted extreme, bit for bit.
            Errors::Static { .. } => (lo - DVec3::splat(self.eps), hi + DVec3::splat(self.eps)),
            Errors::Running(errors) => {
                let (mut lo_e, mut hi_e) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
                for (c, e) in corners.iter().zip(errors) {
                    lo_e = lower3(lo_e, *c - *e);
                    hi_e = raise3(hi_e, *c + *e);
                }
                (lo_e, hi_e)
            }
        };
        let (sep, neg_sep) = (DVec3::splat(self.sep), DVec3::splat(-self.sep));
        if lo_e.cmpgt(sep).any() || hi_e.cmplt(neg_sep).any() {
            return Separation::Yes;
        }
        if lo.cmpgt(sep).any() || hi.cmplt(neg_sep).any() {
            verdict = Separation::Ambiguous;
        }
        let mut along = |n: DVec3, both_sides: bool| {
            let s = self.separated_along(corners, errors, n, both_sides);
            if s == Separation::Ambiguous {
                verdict = Separation::Ambiguous;
            }
            s == Separation::Yes
        };
        // The closest points' direction, when the box spans the whole feature domain.
        if let Some(d) = closest {
            if along(d, false) {
                return Separation::Yes;
            }
        }
        // Face normal (vertex-face) or common normal of the edges (edge-edge), at both ends.
        for n in ends.n {
            if along(n, true) {
                return Separation::Yes;
            }
        }
        // For boxes not spanning the feature domain (degenerate features only): the direction
        // of F at the centre of the box, and the centre direction with its component along an
        // edge removed (the gap between nearly parallel edges, or between a vertex and a face
        // edge in the face's plane, where sliding along the edge does not blur the separation).
        if closest.is_none() {
            let centre = corners.iter().fold(DVec3::ZERO, |s, c| s + *c);
            if along(centre, false) {
                return Separation::Yes;
            }
            let pr = self.problem;
            let t_mid = 0.5 * (cell.t[0] + cell.t[1]);
            let a = pr.a[0] + self.da * t_mid;
            let b = pr.b[0] + self.db * t_mid;
            let edges = match pr.weight {
                Weight::Product => [a, b, a + b],
                Weight::Plain => [a, b, DVec3::ZERO],
            };
            for e in edges {
                let ee = e.length_squared();
                if ee > 0.0 && along(centre - e * (centre.dot(e) / ee), false) {
                    return Separation::Yes;
                }
            }
        }
        verdict
    }

    /// Whether all corner projections on `n`, less their error bounds, exceed
    /// `min_distance |n|` (on the positive side, or on either side if `both_sides`);
    /// [`Separation::Ambiguous`] if only the computed values, without their error bounds, do.
    fn separated_along(
        &self,
        corners: &[DVec3; 8],
        errors: Errors<'_>,
        n: DVec3,
        both_sides: bool,
    ) -> Separation {
        let n_abs = n.abs();
        let n1 = n_abs.x + n_abs.y + n_abs.z;
        if n1 == 0.0 || !n1.is_finite() {
            return Separation::No;
        }
        // |n|_2 rounded up generously; the margin must not shrink below min_distance |n|_2.
        // (Without a separation it is 0, as the product would be, for any `n` whose length
        // cannot overflow.)
        let margin = if self.sep == 0.0 && n1 < 1e150 {
            0.0
        } else {
            self.sep * n.length() * (1.0 + 8.0 * UNIT_ROUNDOFF)
        };
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut lo_e, mut hi_e) = (f64::INFINITY, f64::NEG_INFINITY);
        // Error of a projection: the propagated error `e . |n|` plus the rounding of a 3-term
        // dot product (gamma_3 < 4u), doubled. Statically, `|c| . |n| <= largest |n|_1`.
        let static_err = match errors {
            Errors::Static { largest } => {
                (self.eps + 4.0 * UNIT_ROUNDOFF * largest) * n1 * 2.0 + UNDERFLOW_ERROR
            }
            Errors::Running(_) => 0.0,
        };
        for (k, c) in corners.iter().enumerate() {
            let s = c.dot(n);
            let err = match errors {
                Errors::Static { .. } => static_err,
                Errors::Running(errors) => {
                    (errors[k].dot(n_abs) + 4.0 * UNIT_ROUNDOFF * c.abs().dot(n_abs)) * 2.0
                        + UNDERFLOW_ERROR
                }
            };
            lo = lower(lo, s);
            hi = raise(hi, s);
            lo_e = lower(lo_e, s - err);
            hi_e = raise(hi_e, s + err);
            // Half way, when corners already lie within the margin on each side that counts
            // (with their error bounds and without), the answer is `No`: the minima can only
            // fall and the maxima only rise. Most directions of the boxes that end up split
            // are settled here.
            if k == 3
                && lo_e <= margin
                && lo <= margin
                && (!both_sides || (hi_e >= -margin && hi >= -margin))
            {
                return Separation::No;
            }
        }
        if lo_e > margin || (both_sides && hi_e < -margin) {
            Separation::Yes
        } else if lo > margin || (both_sides && hi < -margin) {
            Separation::Ambiguous
        } else {
            Separation::No
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// On random vertex-face problems whose coplanarity function `g` changes sign over the
    /// step, the predicted slab holds a crossing of `g` as the search computes it: `g` at the
    /// slab's ends has opposite signs (or is zero at one). A cubic has at most three roots,
    /// so a slab a millionth wide that misses them shows the bracketing did not converge.
    #[test]
    fn predicted_slabs_hold_the_crossing() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut point = || DVec3::from_array([0; 3].map(|_| rng.random_range(-1.0..1.0)));
        let options = NarrowOptions::default();
        let (mut crossing, mut predicted) = (0, 0);
        for _ in 0..20_000 {
            let q = VertexFace {
                v_t0: point(),
                f0_t0: point(),
                f1_t0: point(),
                f2_t0: point(),
                v_t1: point(),
                f0_t1: point(),
                f1_t1: point(),
                f2_t1: point(),
            };
            let problem = Problem::vertex_face(&q);
            let (search, _) = Search::new(&problem, &options);
            let g = |t: f64| search.coplanarity_at(t);
            if g(0.0) * g(1.0) >= 0.0 {
                continue;
            }
            crossing += 1;
            let cell = Cell {
                t: [0.0, 1.0],
                u: [0.0, 1.0],
                v: [0.0, 1.0],
            };
            // `None` only when the slab would reach outside the box (a crossing within half
            // the tolerance of an end).
            let Some((lo, hi)) = search.predict_crossing(&cell, None) else {
                let near_end = [0.0, 1.0].iter().any(|&e: &f64| {
                    let h = options.tolerance;
                    g((e - h).max(0.0)) * g((e + h).min(1.0)) <= 0.0
                });
                assert!(near_end, "no slab predicted for {q:?}");
                continue;
            };
            predicted += 1;
            assert!((hi - lo - options.tolerance).abs() <= 1e-15, "{lo} {hi}");
            assert!(g(lo) * g(hi) <= 0.0, "slab [{lo}, {hi}] misses the crossing of {q:?}");
        }
        assert!(crossing > 5_000 && 100 * predicted > 99 * crossing, "{crossing} {predicted}");
    }
}
