//! The brute-force oracle: every feature pair whose swept boxes come within `min_distance`,
//! found by sort and sweep along x, then kept if the swept k-DOPs of the pair's owner
//! triangles overlap (the test every other method makes on its way down; see the
//! [broad phases](super)).

use std::time::Instant;

use super::tasks::{Out, Passes, Totals};
use super::{triangle_volumes, BroadInput, BroadPhase, BroadStats, Candidates, Sink};
use crate::alloc::{grow, try_collect, AllocError};
use crate::bvh::BvhWorkspace;
use crate::kdop::{DopKind, Kdop};
use crate::mesh::features::SweptBox;
use crate::contact::driver::{Found, Keeper};

/// The oracle as a broad phase: a sequential sweep whose buffer of candidates is solved in
/// parallel whenever it is full. It keeps nothing from one step to the next.
pub(crate) struct Brute;

impl BroadPhase for Brute {
    fn run(&mut self, passes: &Passes<'_, '_, '_>, _: &mut BvhWorkspace, out: Out<'_>) -> BroadStats {
        let Passes {
            input,
            ctx,
            limits,
            record,
            chunk,
            ..
        } = *passes;
        let Out {
            found,
            totals,
            recorded,
        } = out;
        // Each buffer is one unit of the order a cap keeps (see `Keeper`).
        let mut best = None;
        let mut keeper = Keeper::default();
        let mut narrow = 0.0;
        let mut flush = |c: &Candidates| {
            let t = Instant::now();
            let budget = keeper.budget(ctx, found);
            let mut part = Found::with_budget(ctx, budget, ctx.limit(best));
            ctx.solve_parallel(c, &mut best, &mut part);
            part.deliver(ctx);
            let kept = keeper.take(ctx, found, &mut part);
            if record && limits.check(recorded.grow_for(c)) {
                recorded.vf.extend_from_slice(&c.vf);
                recorded.ee.extend_from_slice(&c.ee);
            }
            narrow += t.elapsed().as_secs_f64();
            kept
        };
        let stop = || limits.poll(true);
        let mut sink = Sink::new(chunk, &mut flush, &stop);
        let mut stats = {
            let sink = &mut sink;
            match ctx.options.kdop {
                DopKind::K6 => candidates::<3>(input, &mut Vec::new(), sink),
                DopKind::K14 => candidates::<7>(input, &mut Vec::new(), sink),
                DopKind::K18 => candidates::<9>(input, &mut Vec::new(), sink),
                DopKind::K26 => candidates::<13>(input, &mut Vec::new(), sink),
            }
        }
        .unwrap_or_else(|e| {
            limits.fail(e);
            BroadStats::default()
        });
        let t = Instant::now();
        sink.flush_now();
        stats.traverse += t.elapsed().as_secs_f64();
        *totals = Totals {
            vf_tests: sink.vf_total,
            ee_tests: sink.ee_total,
            peak: sink.peak,
            tasks: 0,
        };
        drop(sink);
        totals.tasks = keeper.tasks;
        // The narrow phase ran inside the traversal: take it out of the traversal time.
        stats.traverse = (stats.traverse - narrow).max(0.0);
        stats.narrow = narrow;
        stats
    }
}

/// One box of the sweep: its lower x (the sort key), a kind and an index.
#[derive(Clone, Copy, Debug)]
struct Item {
    lo_x: f64,
    /// 0 for a vertex, 1 for a face (vertex-face sweep); 0 for an edge (edge-edge sweep).
    kind: u32,
    index: u32,
}

/// Sorts the items by lower x, breaking ties by kind and index (deterministic).
fn sort(items: &mut [Item]) {
    items.sort_unstable_by(|a, b| {
        a.lo_x
            .total_cmp(&b.lo_x)
            .then(a.kind.cmp(&b.kind))
            .then(a.index.cmp(&b.index))
    });
}

/// Appends every candidate pair of the step to `out`: `(vertex, face)`, the vertex not in the
/// face, and edge indices, smaller first, the edges sharing no vertex, that pass the pair
/// filter (its rules 5 and 6 on the owner triangles included), whose swept boxes come within
/// the separation, and whose owner triangles' swept k-DOPs (`volumes`, scratch) overlap. An
/// error if the sweep's volumes and boxes cannot be allocated.
pub(crate) fn candidates<const H: usize>(
    input: &BroadInput<'_, '_>,
    volumes: &mut Vec<Kdop<H>>,
    out: &mut Sink<'_>,
) -> Result<BroadStats, AllocError> {
    let start = Instant::now();
    let (features, filter, sep) = (input.features, input.filter, input.filter.sep);
    let tris = input.step.triangles();
    // Room first, fallibly: the volumes then fill it in place.
    volumes.clear();
    grow(volumes, tris.len(), "triangle volumes")?;
    triangle_volumes(input.step, (filter.tmax(), sep), volumes);
    // Owner triangles: the incident triangle of lowest index (as in the ownership scheme).
    let topo = &features.topo;
    let owner_of_vertex = |v: u32| topo.triangles_of(v)[0];
    let edge_owner = &topo.edge_owner;
    // The test on the owner triangles of a pair: their k-DOPs overlap, and the filter's rules
    // 5 and 6 do not drop them.
    let owners_may_meet = |s: u32, t: u32| {
        let (s, t) = (s as usize, t as usize);
        volumes[s].overlaps(&volumes[t]) && !filter.owners_dropped(tris[s], tris[t])
    };
    // The edges' swept boxes: the unions of their vertices'.
    let boxes = &features.boxes;
    let edge_boxes: Vec<SweptBox> =
        try_collect(topo.edges.iter().map(|&e| boxes.edge(e)), "swept boxes")?;
    let build = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let mut tests = 0u64;
    let item = |b: &SweptBox, kind, index: usize| Item {
        lo_x: b.lo.x,
        kind,
        index: index as u32,
    };

    // Vertex-face: the referenced vertices and the faces in one sweep.
    let mut referenced = try_collect(
        std::iter::repeat_n(false, features.boxes.vertex.len()),
        "sweep items",
    )?;
    for t in tris {
        for &v in t {
            referenced[v as usize] = true;
        }
    }
    let vertices = features.boxes.vertex.iter().enumerate();
    let mut items: Vec<Item> = try_collect(
        vertices
            .filter(|&(v, _)| referenced[v])
            .map(|(v, b)| item(b, 0, v))
            .chain(boxes.face.iter().enumerate().map(|(f, b)| item(b, 1, f))),
        "sweep items",
    )?;
    sort(&mut items);
    let bx = |it: &Item| match it.kind {
        0 => &features.boxes.vertex[it.index as usize],
        _ => &boxes.face[it.index as usize],
    };
    'sweep: for (i, a) in items.iter().enumerate() {
        let a_box = bx(a);
        let reach = a_box.hi.x + sep;
        for b in items[i + 1..].iter().take_while(|b| b.lo_x <= reach) {
            if out.stopped() {
                break 'sweep;
            }
            if a.kind == b.kind {
                continue;
            }
            let (v, f) = if a.kind == 0 {
                (a.index, b.index)
            } else {
                (b.index, a.index)
            };
            if tris[f as usize].contains(&v) {
                continue;
            }
            tests += 1;
            if a_box.near(bx(b), sep)
                && filter.vertex_face(v, tris[f as usize])
                && owners_may_meet(owner_of_vertex(v), f)
            {
                out.buf.vf.push([v, f]);
                out.check();
            }
        }
    }

    // Edge-edge: all edges in one sweep.
    let edges = &features.topo.edges;
    items.clear();
    grow(&mut items, edge_boxes.len(), "sweep items")?;
    items.extend(
        edge_boxes
            .iter()
            .enumerate()
            .map(|(e, b)| item(b, 0, e)),
    );
    sort(&mut items);
    'edges: for (i, a) in items.iter().enumerate() {
        let a_box = &edge_boxes[a.index as usize];
        let reach = a_box.hi.x + sep;
        let [a0, a1] = edges[a.index as usize];
        for b in items[i + 1..].iter().take_while(|b| b.lo_x <= reach) {
            if out.stopped() {
                break 'edges;
            }
            let [b0, b1] = edges[b.index as usize];
            if a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1 {
                continue;
            }
            tests += 1;
            if a_box.near(&edge_boxes[b.index as usize], sep)
                && filter.edge_edge([a0, a1], [b0, b1])
                && owners_may_meet(edge_owner[a.index as usize], edge_owner[b.index as usize])
            {
                out.buf.ee.push([a.index.min(b.index), a.index.max(b.index)]);
                out.check();
            }
        }
    }
    Ok(BroadStats {
        bv_tests: tests,
        build,
        traverse: start.elapsed().as_secs_f64(),
        ..BroadStats::default()
    })
}
