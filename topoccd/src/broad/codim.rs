//! The codimensional pass: the candidate pairs of a step's free edges and free points (see
//! `mesh::codim` for which pairs, and why they are all), found by sort and sweep over their
//! boxes swept over `[0, tmax]`, and solved by the narrow phase's driver after the method's
//! own (triangle) work.
//!
//! Every method runs this same pass, after its triangle work: the triangle pairs go through
//! the method as they always did (a step without free edges and points costs nothing more),
//! and the pairs involving a free primitive are the same for every method, so every method
//! reports the same contacts. The pass is the oracle's sort and sweep, made bipartite where
//! one side is the mesh (free vertices against faces, free edges against triangle edges): its
//! cost grows with the number of mesh features along x within reach of a free one, not with
//! all mesh pairs.
//!
//! Vertex-edge and vertex-vertex pairs are edge-edge pairs of the driver in which a point is an
//! edge of length zero `[p, p]` (the elementary test is the same, see
//! [`narrow::vertex_edge`](crate::narrow::vertex_edge)): the driver indexes the *combined* edge
//! list ([`combined_edges`]): the step's triangle edges, then the free edges, then the points.

use std::time::Instant;

use super::tasks::Totals;
use super::{BroadInput, BroadStats, Candidates, Sink};
use crate::alloc::{grow, try_collect, AllocError};
use crate::contact::driver::{lower, Context, Found, Keeper};
use crate::mesh::codim::Codim;
use crate::mesh::features::SweptBox;

/// The step's edges for the driver when it has free primitives: `mesh` (the triangles' edges,
/// sorted), then the free edges, then each point `p` as `[p, p]`, into `out`.
pub(crate) fn combined_edges(
    mesh: &[[u32; 2]],
    codim: &Codim,
    out: &mut Vec<[u32; 2]>,
) -> Result<(), AllocError> {
    out.clear();
    let len = mesh.len() + codim.edges.len() + codim.points.len();
    grow(out, len, "edges")?;
    out.extend_from_slice(mesh);
    out.extend_from_slice(&codim.edges);
    out.extend(codim.points.iter().map(|&p| [p, p]));
    Ok(())
}

/// One box of a sweep: its lower x (the sort key) and an index.
#[derive(Clone, Copy, Debug)]
struct Item {
    lo_x: f64,
    index: u32,
}

/// Items of `boxes` at `indices`, sorted by lower x, then by index (deterministic).
fn sorted(
    boxes: &[SweptBox],
    indices: impl Iterator<Item = u32>,
) -> Result<Vec<Item>, AllocError> {
    let items = indices.map(|i| Item {
        lo_x: boxes[i as usize].lo.x,
        index: i,
    });
    let mut items = try_collect(items, "sweep items")?;
    items.sort_unstable_by(|a, b| a.lo_x.total_cmp(&b.lo_x).then(a.index.cmp(&b.index)));
    Ok(items)
}

/// Calls `pair(a, b)` for every `a` of `left` and `b` of `right` whose boxes overlap along x
/// within `sep`, each pair once, in a fixed order; stops when `pair` returns `false`.
fn bipartite(
    (left, left_boxes): (&[Item], &[SweptBox]),
    (right, right_boxes): (&[Item], &[SweptBox]),
    sep: f64,
    mut pair: impl FnMut(u32, u32) -> bool,
) {
    // Pairs whose right box starts at or after the left one's start, then the others.
    for a in left {
        let reach = left_boxes[a.index as usize].hi.x + sep;
        let from = right.partition_point(|b| b.lo_x < a.lo_x);
        for b in right[from..].iter().take_while(|b| b.lo_x <= reach) {
            if !pair(a.index, b.index) {
                return;
            }
        }
    }
    for b in right {
        let reach = right_boxes[b.index as usize].hi.x + sep;
        let from = left.partition_point(|a| a.lo_x <= b.lo_x);
        for a in left[from..].iter().take_while(|a| a.lo_x <= reach) {
            if !pair(a.index, b.index) {
                return;
            }
        }
    }
}

/// Calls `pair(a, b)` for every two items of `items` whose boxes overlap along x within
/// `sep`, each pair once, in a fixed order; stops when `pair` returns `false`.
fn within(items: &[Item], boxes: &[SweptBox], sep: f64, mut pair: impl FnMut(u32, u32) -> bool) {
    for (i, a) in items.iter().enumerate() {
        let reach = boxes[a.index as usize].hi.x + sep;
        for b in items[i + 1..].iter().take_while(|b| b.lo_x <= reach) {
            if !pair(a.index, b.index) {
                return;
            }
        }
    }
}

/// Appends the candidate pairs of the free primitives to `out`: `[vertex, face]` for free
/// vertices, and `[e, f]` into `edges` (the [`combined_edges`], `mesh` of them the
/// triangles'), `edges[e] < edges[f]`, for a free edge against any edge, a point against a
/// free edge and two points; each pair sharing no vertex, passing the pair filter (rules 1 to
/// 4: rules 5 and 6 need owner triangles) and with swept boxes within the separation. An
/// error if the sweep's boxes cannot be allocated.
pub(crate) fn candidates(
    input: &BroadInput<'_, '_>,
    codim: &Codim,
    (edges, mesh): (&[[u32; 2]], usize),
    out: &mut Sink<'_>,
) -> Result<BroadStats, AllocError> {
    let start = Instant::now();
    let (step, filter) = (input.step, input.filter);
    let (sep, tmax) = (filter.sep, filter.tmax());
    let (x0, x1, tris) = (step.pos0(), step.pos1(), step.triangles());
    let what = "swept boxes";
    let vertex: Vec<SweptBox> = try_collect(
        (x0.iter().zip(x1)).map(|(&a, &b)| SweptBox::vertex_until(a, b, tmax)),
        what,
    )?;
    let face: Vec<SweptBox> = try_collect(
        (tris.iter()).map(|t| t.iter().fold(SweptBox::EMPTY, |b, &v| b.merge(&vertex[v as usize]))),
        what,
    )?;
    let edge: Vec<SweptBox> = try_collect(
        (edges.iter()).map(|&[i, j]| vertex[i as usize].merge(&vertex[j as usize])),
        what,
    )?;
    let free_vertices = sorted(&vertex, codim.free_vertices.iter().copied())?;
    let faces = sorted(&face, 0..tris.len() as u32)?;
    let mesh_edges = sorted(&edge, 0..mesh as u32)?;
    let free_edges = sorted(&edge, mesh as u32..(mesh + codim.edges.len()) as u32)?;
    let free = sorted(&edge, mesh as u32..edges.len() as u32)?;
    let build = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let mut tests = 0u64;

    // Free vertices against faces.
    bipartite((&free_vertices, &vertex), (&faces, &face), sep, |v, f| {
        if out.stopped() {
            return false;
        }
        let tri = tris[f as usize];
        if tri.contains(&v) {
            return true;
        }
        tests += 1;
        if vertex[v as usize].near(&face[f as usize], sep) && filter.vertex_face(v, tri) {
            out.buf.vf.push([v, f]);
            out.check();
        }
        true
    });
    // An edge pair, if it shares no vertex, passes the filter and its boxes are near.
    let mut edge_pair = |e: u32, f: u32, out: &mut Sink<'_>| {
        if out.stopped() {
            return false;
        }
        let (a, b) = (edges[e as usize], edges[f as usize]);
        if a.iter().any(|v| b.contains(v)) {
            return true;
        }
        tests += 1;
        if edge[e as usize].near(&edge[f as usize], sep) && filter.edge_edge(a, b) {
            out.buf.ee.push(if a < b { [e, f] } else { [f, e] });
            out.check();
        }
        true
    };
    // Free edges against the triangles' edges, then every pair among the free edges and
    // points (the points against the triangles' edges are vertex-face pairs, above).
    bipartite((&free_edges, &edge), (&mesh_edges, &edge), sep, |e, f| {
        edge_pair(e, f, out)
    });
    within(&free, &edge, sep, |e, f| edge_pair(e, f, out));
    Ok(BroadStats {
        bv_tests: tests,
        build,
        traverse: start.elapsed().as_secs_f64(),
        ..BroadStats::default()
    })
}

/// Runs the codimensional pass after a method's triangle work: its candidates, in buffers of
/// `chunk`, solved by `ctx` (whose edges are the [`combined_edges`], and which has no first
/// pass to mirror) into `found`, after what it holds, with the same cap, modes and streaming.
/// Adds to `totals`; returns the pass's times.
pub(crate) fn run(
    input: &BroadInput<'_, '_>,
    codim: &Codim,
    (ctx, mesh): (&Context<'_, '_>, usize),
    chunk: usize,
    found: &mut Found,
    totals: &mut Totals,
) -> BroadStats {
    let mut best = None;
    lower(&mut best, found.vf.iter().map(|c| c.toi));
    lower(&mut best, found.ee.iter().map(|c| c.toi));
    lower(&mut best, found.streamed.iter().map(|c| c.toi()));
    let mut keeper = Keeper::default();
    let mut narrow = 0.0;
    let mut flush = |c: &Candidates| {
        let t = Instant::now();
        let budget = keeper.budget(ctx, found);
        let mut part = Found::with_budget(ctx, budget, ctx.limit(best));
        ctx.solve_parallel(c, &mut best, &mut part);
        part.deliver(ctx);
        let kept = keeper.take(ctx, found, &mut part);
        narrow += t.elapsed().as_secs_f64();
        kept
    };
    let stop = || ctx.limits.poll(true);
    let mut sink = Sink::new(chunk, &mut flush, &stop);
    let mut stats = candidates(input, codim, (ctx.edges, mesh), &mut sink).unwrap_or_else(|e| {
        ctx.limits.fail(e);
        BroadStats::default()
    });
    let t = Instant::now();
    sink.flush_now();
    stats.traverse += t.elapsed().as_secs_f64();
    totals.vf_tests += sink.vf_total;
    totals.ee_tests += sink.ee_total;
    totals.peak = totals.peak.max(sink.peak);
    drop(sink);
    totals.tasks += keeper.tasks;
    stats.traverse = (stats.traverse - narrow).max(0.0);
    stats.narrow = narrow;
    stats
}
