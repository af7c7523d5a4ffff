//! Edge against edge: the driver's per-kind part for edge-edge candidates (the query of a pair, its
//! prefilter, its elementary test, the first pass's rules, the contact).

use super::driver::{pruned, Context};
use super::geometry;
use super::report::EeContact;
use crate::mesh::Step;
use crate::narrow::prefilter::ee_unresolved;
use crate::narrow::{edge_edge_from, NarrowOptions, EdgeEdge};

pub(super) fn ee_query(step: &Step, edges: &[[u32; 2]], [e, f]: [u32; 2]) -> EdgeEdge {
    let ([a0, a1], [b0, b1]) = (edges[e as usize], edges[f as usize]);
    debug_assert!([a0, a1] < [b0, b1]);
    let (x0, x1) = (step.pos0(), step.pos1());
    let [a0, a1, b0, b1] = [a0, a1, b0, b1].map(|i| i as usize);
    EdgeEdge {
        ea0_t0: x0[a0],
        ea1_t0: x0[a1],
        eb0_t0: x0[b0],
        eb1_t0: x0[b1],
        ea0_t1: x1[a0],
        ea1_t1: x1[a1],
        eb0_t1: x1[b0],
        eb1_t1: x1[b1],
    }
}

/// [`vf_contact`](super::vertex_face::vf_contact) for an edge-edge pair (indices into [`Context::edges`]).
pub(super) fn ee_contact(ctx: &Context, pair: [u32; 2], limit: f64) -> Option<EeContact> {
    let options = ctx.options;
    let q = ee_query(ctx.step, ctx.edges, pair);
    let t_end = limit.min(options.narrow.tmax);
    let start = ee_unresolved(&q, options.narrow.min_distance, t_end, ctx.coord)?;
    ee_solved(ctx, &q, pair, (limit, start))
}

/// [`vf_solved`](super::vertex_face::vf_solved) for an edge-edge pair.
pub(super) fn ee_solved(
    ctx: &Context,
    q: &EdgeEdge,
    [e, f]: [u32; 2],
    (limit, start): (f64, f64),
) -> Option<EeContact> {
    let (options, coord, edges) = (ctx.options, ctx.coord, ctx.edges);
    let apart = std::cell::OnceCell::new();
    let raise = |s: f64| match &ctx.first {
        Some(fp) => fp.raise(s, || *apart.get_or_init(|| fp.ee_apart([e, f]))),
        None => s,
    };
    let whole = || ee_unresolved(q, options.narrow.min_distance, options.narrow.tmax, coord);
    let whole = || whole().map(raise);
    let solve = |o: &NarrowOptions, start| edge_edge_from(q, o, start);
    let (toi, certainty) = pruned(&options.narrow, limit, raise(start), whole, solve)?;
    if ctx.whole.is_some_and(|w| !w.ee_candidate([e, f])) {
        return None;
    }
    Some(EeContact {
        a: edges[e as usize],
        b: edges[f as usize],
        toi,
        certainty,
        geometry: options.geometry.then(|| geometry::edge_edge(q, toi)),
    })
}
