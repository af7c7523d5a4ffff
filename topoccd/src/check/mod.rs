//! Static intersection check: which triangles of one configuration intersect.
//!
//! The CCD query assumes that nothing touches at t=0; after a cut, a bad step or an imported
//! frame, that may not hold. [`intersections`] lists the pairs of triangles that share no
//! vertex and intersect (touching counts: closed triangles), decided exactly with the
//! orientation predicates of the `robust` crate (Shewchuk's adaptive exact arithmetic), over a
//! bounding-box tree. [`step_intersections`] checks one end of a [`Step`], with its topology
//! change: a new vertex and its parent count as one vertex there, as for the CCD's crack
//! filter, so the two sides of a fresh crack are not reported.
//!
//! ```
//! use topoccd::check::intersections;
//! // Triangle 1 pierces triangle 0; triangle 2 lies far away.
//! let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
//!          [0.2, 0.2, -1.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0],
//!          [5.0, 5.0, 5.0], [6.0, 5.0, 5.0], [5.0, 6.0, 5.0]];
//! let triangles = [[0u32, 1, 2], [3, 4, 5], [6, 7, 8]];
//! assert_eq!(intersections(&x, &triangles)?, vec![[0, 1]]);
//! # Ok::<(), topoccd::StepError>(())
//! ```
//!
//! Pairs that share a vertex are not checked: they touch there by construction, so a fold
//! between two neighbours is not reported. The predicates are exact at every uniform scale of
//! the input range ([`range`](crate::range)): a pair's coordinates far from 1 are first
//! multiplied by a power of two, as the CCD's solver does. They stay exact unless an
//! intermediate product underflows: coordinate differences below about `1e-100` times the
//! pair's largest coordinate.

mod exact;
mod limits;
mod tree;

pub use limits::{CheckError, CheckLimits};

use std::sync::atomic::{AtomicUsize, Ordering};

use crate::alloc::try_collect;
use crate::contact::limits::Limits;
use crate::mesh::{Frame, Positions, Step, StepError, Triangles};
use crate::query::StopReason;

/// The pairs `[a, b]` (`a < b`, sorted) of triangles of one configuration that share no vertex
/// and intersect or touch. The input is checked as [`Step::new`] checks it (indices in range,
/// finite coordinates, no repeated vertex in a triangle).
///
/// ```
/// use topoccd::check::intersections;
/// // Two triangles meet at one point (corner 3 on triangle 0's face), one stays apart.
/// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
///          [0.25, 0.25, 0.0], [0.25, 0.25, 1.0], [0.5, 0.25, 1.0],
///          [0.0, 0.0, 0.5], [1.0, 0.0, 0.5], [0.0, 1.0, 0.5]];
/// let triangles = [[0u32, 1, 2], [3, 4, 5]];
/// assert_eq!(intersections(&x, &triangles)?, vec![[0, 1]]);
/// let apart = [[0u32, 1, 2], [6, 7, 8]]; // a parallel copy, 0.5 above
/// assert!(intersections(&x, &apart)?.is_empty());
/// # Ok::<(), topoccd::StepError>(())
/// ```
pub fn intersections<'a>(
    positions: impl Into<Positions<'a>>,
    triangles: impl Into<Triangles<'a>>,
) -> Result<Vec<[u32; 2]>, StepError> {
    let positions = positions.into();
    let step = Step::new(positions.clone(), positions, triangles)?;
    Ok(step_intersections(&step, Frame::Start))
}

/// [`intersections`] of a frame that ends a topology change: `parents` (`[child, parent]`
/// rows, as in a sequence's parents files) join each new vertex to its parent, so the two
/// sides of a fresh crack, which touch, are not reported. The vertices before the first child
/// are the step's old ones; the rows are checked as [`Step::with_parents`] checks them.
///
/// ```
/// use topoccd::check::frame_intersections;
/// // A square cut along its diagonal 1-2 (vertices 4 and 5 copy 1 and 2), one half lifted at
/// // its far corner: the halves still touch along the cut.
/// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 1.0],
///          [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let triangles = [[0u32, 1, 2], [4, 3, 5]];
/// assert_eq!(frame_intersections(&x, &triangles, &[])?, vec![[0, 1]]);
/// assert!(frame_intersections(&x, &triangles, &[[4, 1], [5, 2]])?.is_empty());
/// # Ok::<(), topoccd::StepError>(())
/// ```
pub fn frame_intersections<'a>(
    positions: impl Into<Positions<'a>>,
    triangles: impl Into<Triangles<'a>>,
    parents: &[[u32; 2]],
) -> Result<Vec<[u32; 2]>, StepError> {
    let unbounded = CheckLimits {
        max_contacts: None,
        ..CheckLimits::default()
    };
    frame_intersections_within(positions, triangles, parents, &unbounded).map_err(|e| match e {
        CheckError::Step(e) => e,
        CheckError::OutOfMemory { what, bytes } => StepError::OutOfMemory { what, bytes },
        _ => unreachable!("no cap, no deadline, no cancel token"),
    })
}

/// [`frame_intersections`] within `limits`: a cap on the pairs and a deadline (see
/// [`CheckLimits`]; by default at most [`DEFAULT_MAX_CONTACTS`](crate::DEFAULT_MAX_CONTACTS)
/// pairs). The Python and C front ends call this one.
///
/// ```
/// use topoccd::check::{frame_intersections_within, CheckError, CheckLimits};
/// // Two triangles pierce each other.
/// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
///          [0.2, 0.2, -1.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]];
/// let triangles = [[0u32, 1, 2], [3, 4, 5]];
/// let limits = CheckLimits::default();
/// assert_eq!(frame_intersections_within(&x, &triangles, &[], &limits)?, vec![[0, 1]]);
/// let none = CheckLimits { max_contacts: Some(0), ..CheckLimits::default() };
/// let err = frame_intersections_within(&x, &triangles, &[], &none).unwrap_err();
/// assert!(matches!(err, CheckError::MaxContacts { max_contacts: 0 }));
/// # Ok::<(), CheckError>(())
/// ```
pub fn frame_intersections_within<'a>(
    positions: impl Into<Positions<'a>>,
    triangles: impl Into<Triangles<'a>>,
    parents: &[[u32; 2]],
    limits: &CheckLimits,
) -> Result<Vec<[u32; 2]>, CheckError> {
    let positions = positions.into();
    let frame = Step::new(positions.clone(), positions, triangles)?;
    let x: &[f64] = bytemuck::cast_slice(frame.x1());
    let n = frame.vertex_count();
    let old = parents
        .iter()
        .map(|&[child, _]| child as usize)
        .min()
        .unwrap_or(n)
        .min(n);
    let step = Step::with_parents(&x[..3 * old], x, frame.triangles(), parents)?;
    step_intersections_within(&step, Frame::End, limits)
}

/// The pairs `[a, b]` (`a < b`, sorted) of the step's triangles that intersect or touch at one
/// end of the step (`frame`), skipping pairs that share a vertex, where a new vertex of the
/// step's topology change ([`Step::with_parents`]) and its parent, and two children of one
/// parent, count as one vertex.
///
/// ```
/// use topoccd::check::step_intersections;
/// use topoccd::{Frame, Step};
/// // A square cut along its diagonal 1-2: vertices 4 and 5 are the copies of 1 and 2.
/// let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
/// let x1 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 1.0],
///           [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]];
/// let triangles = [[0u32, 1, 2], [4, 3, 5]];
/// let step = Step::with_parents(&x0, &x1, &triangles, &[[4, 1], [5, 2]])?;
/// // At t=0 the two halves touch along the cut, but a child and its parent are one vertex.
/// assert!(step_intersections(&step, Frame::Start).is_empty());
/// # Ok::<(), topoccd::StepError>(())
/// ```
///
/// An allocation failure aborts, as a `Vec`'s does: [`step_intersections_within`] returns it
/// as [`CheckError::OutOfMemory`] instead.
pub fn step_intersections(step: &Step<'_>, frame: Frame) -> Vec<[u32; 2]> {
    let unbounded = CheckLimits {
        max_contacts: None,
        ..CheckLimits::default()
    };
    match step_intersections_within(step, frame, &unbounded) {
        Ok(pairs) => pairs,
        Err(CheckError::OutOfMemory { bytes, .. }) => {
            let layout = std::alloc::Layout::from_size_align(bytes, 8);
            std::alloc::handle_alloc_error(layout.unwrap_or(std::alloc::Layout::new::<u64>()))
        }
        Err(_) => unreachable!("no cap, no deadline, no cancel token"),
    }
}

/// [`step_intersections`] within `limits` (see [`CheckLimits`]): past the cap, the deadline
/// or a cancellation it stops within about a millisecond of work per thread and answers a
/// [`CheckError`], never part of the pairs.
///
/// ```
/// use std::time::Instant;
/// use topoccd::check::{step_intersections_within, CheckError, CheckLimits};
/// use topoccd::{Frame, Step, StopReason};
/// let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let step = Step::new(&x, &x, &[[0u32, 1, 2]])?;
/// let late = CheckLimits { deadline: Some(Instant::now()), ..CheckLimits::default() };
/// let err = step_intersections_within(&step, Frame::Start, &late).unwrap_err();
/// assert_eq!(err, CheckError::Stopped(StopReason::Deadline));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn step_intersections_within(
    step: &Step<'_>,
    frame: Frame,
    limits: &CheckLimits,
) -> Result<Vec<[u32; 2]>, CheckError> {
    let stop = Limits::new(limits.max_contacts, limits.deadline, limits.cancel.clone());
    if stop.poll(true) {
        return Err(stopped(&stop, limits));
    }
    let found = AtomicUsize::new(0);
    let x = match frame {
        Frame::Start => step.x0(),
        Frame::End => step.x1(),
    };
    let tris = step.triangles();
    let one = joined_vertices(step.vertex_count(), step.parents());
    let corners = |t: usize| tris[t].map(|v| x[v as usize]);
    let boxes: Vec<tree::Aabb> = try_collect(
        (0..tris.len()).map(|t| tree::Aabb::of(&corners(t))),
        "triangle boxes",
    )?;
    let tree = tree::Tree::build(&boxes);
    let visit = |a: u32, b: u32| {
        let (ta, tb) = (tris[a as usize], tris[b as usize]);
        let shared = ta
            .iter()
            .any(|&u| tb.iter().any(|&v| one[u as usize] == one[v as usize]));
        let hit = !shared && exact::triangles(corners(a as usize), corners(b as usize));
        if hit && stop.capped() && found.fetch_add(1, Ordering::Relaxed) >= stop.max_contacts {
            stop.stop(StopReason::MaxContacts);
        }
        hit.then(|| [a.min(b), a.max(b)])
    };
    let mut pairs = tree.self_pairs_until(&boxes, &visit, &|| stop.poll(false))?;
    if stop.stopped().is_some() {
        return Err(stopped(&stop, limits));
    }
    pairs.sort_unstable();
    Ok(pairs)
}

/// The error of a check that `stop` stopped.
fn stopped(stop: &Limits, limits: &CheckLimits) -> CheckError {
    match stop.stopped() {
        Some(StopReason::MaxContacts) => CheckError::MaxContacts {
            max_contacts: limits.max_contacts.unwrap_or(usize::MAX),
        },
        Some(reason) => CheckError::Stopped(reason),
        None => unreachable!("called once stopped"),
    }
}

/// For each vertex, a representative: a child of a topology change, its parent and the
/// parent's other children share one.
fn joined_vertices(n: usize, parents: &[[u32; 2]]) -> Vec<u32> {
    let mut root: Vec<u32> = (0..n as u32).collect();
    fn find(root: &mut [u32], mut v: u32) -> u32 {
        while root[v as usize] != v {
            let up = root[root[v as usize] as usize];
            root[v as usize] = up;
            v = up;
        }
        v
    }
    for &[child, parent] in parents {
        let (a, b) = (find(&mut root, child), find(&mut root, parent));
        root[a.max(b) as usize] = a.min(b);
    }
    (0..n as u32).map(|v| find(&mut root, v)).collect()
}

#[cfg(test)]
mod tests {
    use super::exact::{segment_triangle, segments, triangles};

    const T: [[f64; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

    fn moved(t: [[f64; 3]; 3], d: [f64; 3]) -> [[f64; 3]; 3] {
        t.map(|p| [p[0] + d[0], p[1] + d[1], p[2] + d[2]])
    }

    #[test]
    fn crossing_touching_and_apart() {
        // Pierced through the interior.
        let pierce = [[0.2, 0.2, -1.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]];
        assert!(triangles(T, pierce));
        // A corner exactly on the face (a vertex on a face).
        let corner = [[0.25, 0.25, 0.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]];
        assert!(triangles(T, corner));
        // The same corner lifted by the smallest step: apart.
        let lifted = [[0.25, 0.25, 1e-100], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]];
        assert!(!triangles(T, lifted));
        // Parallel planes.
        assert!(!triangles(T, moved(T, [0.0, 0.0, 1e-30])));
        // Coplanar, overlapping; coplanar, touching at a corner; coplanar, apart.
        assert!(triangles(T, moved(T, [0.25, 0.25, 0.0])));
        assert!(triangles(T, moved(T, [1.0, 0.0, 0.0])));
        assert!(!triangles(T, moved(T, [1.0 + 1e-15, 0.0, 0.0])));
        // Coplanar, one inside the other.
        let small = [[0.1, 0.1, 0.0], [0.2, 0.1, 0.0], [0.1, 0.2, 0.0]];
        assert!(triangles(T, small) && triangles(small, T));
        // Crossing edges: edge (0,0,0)-(1,0,0) against a triangle standing across it.
        let across = [[0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [0.5, 0.0, 1.0]];
        assert!(triangles(T, across));
        // Edge against edge in space, touching at one point, and just apart.
        let edge_touch = [[0.5, 0.0, 0.0], [0.5, -1.0, 1.0], [0.5, -1.0, -1.0]];
        assert!(triangles(T, edge_touch));
        let edge_apart = [[0.5, -1e-12, 0.0], [0.5, -1.0, 1.0], [0.5, -1.0, -1.0]];
        assert!(!triangles(T, edge_apart));
    }

    /// The cases of `crossing_touching_and_apart` at every uniform scale of the input range
    /// (issue 43): the answers do not depend on the scale, down to subnormal coordinates. (At
    /// 1e110 the determinants' products overflowed, at 1e-110 they underflowed.)
    #[test]
    fn every_scale_of_the_range_gives_the_same_answers() {
        let scale = |t: [[f64; 3]; 3], s: f64| t.map(|p| p.map(|x| x * s));
        let cases: [([[f64; 3]; 3], bool); 6] = [
            (
                [[0.25, -0.25, -1.0], [0.5, 0.25, 1.0], [0.25, 0.5, 1.0]],
                true,
            ),
            (
                [[0.25, 0.25, 0.0], [0.5, 0.25, 1.0], [0.25, 0.5, 1.0]],
                true,
            ),
            (
                [
                    [0.25, 0.25, 2f64.powi(-40)],
                    [0.5, 0.25, 1.0],
                    [0.25, 0.5, 1.0],
                ],
                false,
            ),
            (moved(T, [1.0, 0.0, 0.0]), true),
            (moved(T, [1.0 + 2f64.powi(-40), 0.0, 0.0]), false),
            (
                [
                    [0.5, -2f64.powi(-40), 0.0],
                    [0.5, -1.0, 1.0],
                    [0.5, -1.0, -1.0],
                ],
                false,
            ),
        ];
        for e in (-1000..=1000).step_by(25) {
            // Powers of two: scaling by them is exact, so the answers are the unscaled ones.
            let s = 2f64.powi(e);
            for (k, (u, expected)) in cases.iter().enumerate() {
                assert_eq!(
                    triangles(scale(T, s), scale(*u, s)),
                    *expected,
                    "2^{e}, case {k}"
                );
            }
        }
    }

    #[test]
    fn degenerate_triangles_and_segments() {
        // A triangle flattened to a segment, crossing T's interior.
        let flat = [[0.2, 0.2, -1.0], [0.2, 0.2, 0.0], [0.2, 0.2, 1.0]];
        assert!(triangles(T, flat) && triangles(flat, T));
        // A segment crossing a flattened triangle.
        assert!(segment_triangle(
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 2.0],
            flat.map(|p| [p[0] - 0.2, p[1] - 0.2, p[2]])
        ));
        // Collinear segments: overlapping, touching end to end, apart.
        assert!(segments([0.0; 3], [2.0, 2.0, 2.0], [1.0; 3], [3.0; 3]));
        assert!(segments([0.0; 3], [1.0; 3], [1.0; 3], [3.0; 3]));
        assert!(!segments([0.0; 3], [1.0; 3], [1.5; 3], [3.0; 3]));
        // Skew segments.
        assert!(!segments(
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, -1.0, 1.0],
            [0.5, 1.0, 1.0]
        ));
        // A triangle collapsed to a point, on T and off it.
        assert!(triangles(T, [[0.3, 0.3, 0.0]; 3]));
        assert!(!triangles(T, [[0.6, 0.6, 0.0]; 3]));
    }
}
