//! `topoccd_step`: the input of one step as borrowed C arrays, checked and turned into a
//! `topoccd::Step` without a copy.

use std::mem::{align_of, size_of};
use std::slice;

use topoccd::Step;

use crate::status::{chain, topoccd_status, Failure};

/// The input of one step, borrowed: nothing is copied, and nothing is kept after the call.
/// Vertices move linearly from their position at t=0 to their position at t=1. Zero-initialise
/// it (`topoccd_step step = {0};`) and set the arrays; a NULL array with a count of 0 is empty.
///
/// - `x0`, `x1`: positions at t=0 and t=1, `x0_count` and `x1_count` rows of 3 doubles
///   (`x y z`), finite. Without a topology change the counts are equal.
/// - `triangles`: `triangle_count` rows of 3 vertex indices, each `< x1_count`, three different
///   vertices per triangle. Their order numbers the faces of the report.
/// - `parents`: a topology change (a cut, a tear, a fracture). When `parents` is not NULL,
///   `x0_count` may be smaller than `x1_count`: vertex ids persist and the vertices from
///   `x0_count` on are new. Each of the `parent_count` rows `[child, parent]` says that `child`
///   was split from `parent` (an old vertex); a new vertex starts at its parent's position
///   (without a parent, it starts where it ends). A child and its parent, and two children of
///   one parent, count as one vertex for the step (see `crack_filter`). Pass a non-NULL pointer
///   with `parent_count` 0 for new vertices without parents.
/// - `groups`: NULL, or `group_count` = `x1_count` group ids, one per vertex: two features are
///   tested only if some vertex of one is in another group than some vertex of the other (give
///   each object its own id to turn off its self-collision).
/// - `edges`: NULL, or `edge_count` rows of 2 vertex indices (codimensional geometry). Those
///   in no triangle are free edges (rods, hair, yarn); with `edges` given, vertices in no
///   triangle and no edge are free points (particles). Contacts of a free point with a free
///   edge are reported in the report's `ve`, of two free points in `vv`. Edges of the
///   triangles may be listed too; they change nothing.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct topoccd_step {
    /// Positions at t=0: `x0_count` rows of 3 doubles.
    pub x0: *const f64,
    /// Vertices at t=0.
    pub x0_count: usize,
    /// Positions at t=1: `x1_count` rows of 3 doubles.
    pub x1: *const f64,
    /// Vertices at t=1.
    pub x1_count: usize,
    /// Triangles: `triangle_count` rows of 3 vertex indices.
    pub triangles: *const u32,
    /// Number of triangles.
    pub triangle_count: usize,
    /// NULL, or `parent_count` rows `[child, parent]` of a topology change.
    pub parents: *const u32,
    /// Number of parent rows.
    pub parent_count: usize,
    /// NULL, or one group id per vertex.
    pub groups: *const u32,
    /// Number of group ids (`x1_count` when `groups` is not NULL).
    pub group_count: usize,
    /// NULL, or `edge_count` rows of 2 vertex indices: free edges, and free points.
    pub edges: *const u32,
    /// Number of edges.
    pub edge_count: usize,
}

/// `count` rows of `N` values of `T` at `ptr`, borrowed; `what` names the array in messages.
///
/// # Safety
/// `ptr` is NULL or valid for reads of `count * N` values of `T` during `'a`.
pub(crate) unsafe fn rows<'a, T, const N: usize>(
    ptr: *const T,
    count: usize,
    what: &str,
) -> Result<&'a [[T; N]], Failure> {
    if count == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(Failure::new(
            topoccd_status::NullPointer,
            format!("{what} is NULL but {what}_count is {count}"),
        ));
    }
    if !(ptr as usize).is_multiple_of(align_of::<T>()) {
        return Err(Failure::new(
            topoccd_status::InvalidArgument,
            format!(
                "{what} is not aligned for its type ({} bytes)",
                align_of::<T>()
            ),
        ));
    }
    if count
        .checked_mul(size_of::<[T; N]>())
        .is_none_or(|bytes| bytes > isize::MAX as usize)
    {
        return Err(Failure::new(
            topoccd_status::InvalidArgument,
            format!("{what}_count is {count}, more than memory can hold"),
        ));
    }
    Ok(slice::from_raw_parts(ptr.cast::<[T; N]>(), count))
}

/// The step's input refused by the library, with the element named.
pub(crate) fn invalid_step(error: &dyn std::error::Error) -> Failure {
    Failure::new(topoccd_status::InvalidStep, chain(error))
}

/// The `topoccd::Step` of a `topoccd_step`, borrowing its arrays.
///
/// # Safety
/// The arrays of `step` are NULL or valid for reads of their counts' rows during `'a`.
pub(crate) unsafe fn borrow<'a>(step: &topoccd_step) -> Result<Step<'a>, Failure> {
    let x0 = rows::<f64, 3>(step.x0, step.x0_count, "x0")?;
    let x1 = rows::<f64, 3>(step.x1, step.x1_count, "x1")?;
    let triangles = rows::<u32, 3>(step.triangles, step.triangle_count, "triangles")?;
    let parents = if step.parents.is_null() && step.parent_count == 0 {
        None
    } else {
        Some(rows::<u32, 2>(step.parents, step.parent_count, "parents")?)
    };
    let built = match parents {
        Some(p) => Step::with_parents(x0, x1, triangles, p),
        None => Step::new(x0, x1, triangles),
    }
    .map_err(|e| invalid_step(&e))?;
    let built = if step.groups.is_null() && step.group_count == 0 {
        built
    } else {
        let groups = rows::<u32, 1>(step.groups, step.group_count, "groups")?;
        // SAFETY: `[u32; 1]` has the layout of `u32`.
        let groups = slice::from_raw_parts(groups.as_ptr().cast::<u32>(), groups.len());
        built.with_groups(groups).map_err(|e| invalid_step(&e))?
    };
    if step.edges.is_null() && step.edge_count == 0 {
        return Ok(built);
    }
    let edges = rows::<u32, 2>(step.edges, step.edge_count, "edges")?;
    built.with_edges(edges).map_err(|e| invalid_step(&e))
}
