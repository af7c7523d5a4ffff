//! Vertex against face: the driver's per-kind part for vertex-face candidates (the query of a pair, its
//! prefilter, its elementary test, the first pass's rules, the contact).

use super::driver::{pruned, Context};
use super::geometry;
use super::report::VfContact;
use crate::mesh::Step;
use crate::narrow::prefilter::vf_unresolved;
use crate::narrow::{vertex_face_from, NarrowOptions, VertexFace};

pub(super) fn vf_query(step: &Step, [v, f]: [u32; 2]) -> VertexFace {
    let (x0, x1) = (step.pos0(), step.pos1());
    let [f0, f1, f2] = step.triangles()[f as usize].map(|i| i as usize);
    let v = v as usize;
    VertexFace {
        v_t0: x0[v],
        f0_t0: x0[f0],
        f1_t0: x0[f1],
        f2_t0: x0[f2],
        v_t1: x1[v],
        f0_t1: x1[f0],
        f1_t1: x1[f1],
        f2_t1: x1[f2],
    }
}

/// One candidate's elementary test, its prefilter first: `limit` is the end of the interval
/// that can still matter (see [`pruned`]).
pub(super) fn vf_contact(ctx: &Context, pair: [u32; 2], limit: f64) -> Option<VfContact> {
    let options = ctx.options;
    let q = vf_query(ctx.step, pair);
    let t_end = limit.min(options.narrow.tmax);
    let start = vf_unresolved(&q, options.narrow.min_distance, t_end, ctx.coord)?;
    vf_solved(ctx, &q, pair, (limit, start))
}

/// The elementary test of a candidate that its prefilter over `[0, limit]` passed, proved
/// apart until `start`. A pair the first pass leaves out is searched from its end
/// ([`Context::first`]); in the first pass, a contact of a pair the whole step leaves out is
/// dropped ([`Context::whole`]).
pub(super) fn vf_solved(
    ctx: &Context,
    q: &VertexFace,
    pair: [u32; 2],
    (limit, start): (f64, f64),
) -> Option<VfContact> {
    let (options, coord) = (ctx.options, ctx.coord);
    let apart = std::cell::OnceCell::new();
    let raise = |s: f64| match &ctx.first {
        Some(fp) => fp.raise(s, || *apart.get_or_init(|| fp.vf_apart(pair))),
        None => s,
    };
    let whole = || vf_unresolved(q, options.narrow.min_distance, options.narrow.tmax, coord);
    let whole = || whole().map(raise);
    let solve = |o: &NarrowOptions, start| vertex_face_from(q, o, start);
    let (toi, certainty) = pruned(&options.narrow, limit, raise(start), whole, solve)?;
    if ctx.whole.is_some_and(|w| !w.vf_candidate(pair)) {
        return None;
    }
    Some(VfContact {
        vertex: pair[0],
        face: pair[1],
        toi,
        certainty,
        geometry: options.geometry.then(|| geometry::vertex_face(q, toi)),
    })
}
