//! The narrow phase shared by every method: the elementary tests over a buffer of candidate
//! feature pairs, in either mode, in parallel, with the same output for any thread count.

use rayon::prelude::*;

use super::geometry;
use super::report::{Contact, EeContact, VfContact};
use super::{Mode, QueryOptions};
use crate::broad::Candidates;
use crate::mesh::Step;
use crate::narrow::prefilter::{ee_separated, vf_separated};
use crate::narrow::{edge_edge, vertex_face, Certainty, EdgeEdge, NarrowOptions, Outcome, VertexFace};

/// Pairs solved between two updates of the best time in [`Mode::Earliest`]. Fixed, so that
/// what is pruned does not depend on the thread count.
const EARLIEST_CHUNK: usize = 4096;

/// What the narrow phase found.
#[derive(Debug, Default)]
pub(crate) struct Found {
    pub vf: Vec<VfContact>,
    pub ee: Vec<EeContact>,
}

fn vf_query(step: &Step, [v, f]: [u32; 2]) -> VertexFace {
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

fn ee_query(step: &Step, [a0, a1]: [u32; 2], [b0, b1]: [u32; 2]) -> EdgeEdge {
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

/// One candidate's elementary test, its prefilter first: `limit` is the end of the interval
/// that can still matter (see [`pruned`]).
fn vf_contact(
    step: &Step,
    pair: [u32; 2],
    options: &QueryOptions,
    limit: f64,
) -> Option<VfContact> {
    let q = vf_query(step, pair);
    if vf_separated(&q, options.narrow.min_separation) {
        return None;
    }
    let (toi, certainty) = pruned(&options.narrow, limit, |o| vertex_face(&q, o))?;
    Some(VfContact {
        vertex: pair[0],
        face: pair[1],
        toi,
        certainty,
        geometry: options.geometry.then(|| geometry::vertex_face(&q, toi)),
    })
}

fn ee_contact(
    step: &Step,
    edges: &[[u32; 2]],
    [e, f]: [u32; 2],
    options: &QueryOptions,
    limit: f64,
) -> Option<EeContact> {
    let (a, b) = (edges[e as usize], edges[f as usize]);
    debug_assert!(a < b);
    let q = ee_query(step, a, b);
    if ee_separated(&q, options.narrow.min_separation) {
        return None;
    }
    let (toi, certainty) = pruned(&options.narrow, limit, |o| edge_edge(&q, o))?;
    Some(EeContact {
        a,
        b,
        toi,
        certainty,
        geometry: options.geometry.then(|| geometry::edge_edge(&q, toi)),
    })
}

/// Runs the elementary tests on `candidates` (pairs of indices into `edges`, the step's edges
/// sorted lexicographically, for edge-edge) and appends the contacts to `found`.
///
/// In [`Mode::All`] every candidate is solved over `[0, t_max]`. In [`Mode::Earliest`]
/// candidates go in fixed chunks; a candidate is first solved over `[0, min(t_max, best + 2
/// tolerance)]`, where `best` is the earliest time found in the chunks before: a contact there
/// is then solved again over `[0, t_max]` exactly as in [`Mode::All`], so the times compared
/// are the same numbers in both modes. A pair skipped this way has no contact before
/// `best + 2 tolerance` (the solver is conservative on its interval), so the earliest time is
/// still no later than the first contact, and every pair whose first contact lies within the
/// tolerance of it is found. `best` is updated by the caller between calls through `best`.
pub(crate) fn run(
    step: &Step,
    edges: &[[u32; 2]],
    candidates: &Candidates,
    options: &QueryOptions,
    best: &mut Option<f64>,
    found: &mut Found,
) {
    match options.mode {
        Mode::All => {
            let limit = f64::INFINITY;
            found.vf.par_extend(
                candidates
                    .vf
                    .par_iter()
                    .with_min_len(256)
                    .filter_map(|&pair| vf_contact(step, pair, options, limit)),
            );
            found.ee.par_extend(
                candidates
                    .ee
                    .par_iter()
                    .with_min_len(256)
                    .filter_map(|&pair| ee_contact(step, edges, pair, options, limit)),
            );
        }
        Mode::Earliest => {
            let tol2 = 2.0 * options.narrow.tolerance;
            for chunk in candidates.vf.chunks(EARLIEST_CHUNK) {
                let limit = best.map_or(f64::INFINITY, |b| b + tol2);
                let start = found.vf.len();
                found.vf.par_extend(
                    chunk
                        .par_iter()
                        .with_min_len(64)
                        .filter_map(|&pair| vf_contact(step, pair, options, limit)),
                );
                lower(best, found.vf[start..].iter().map(|c| c.toi));
            }
            for chunk in candidates.ee.chunks(EARLIEST_CHUNK) {
                let limit = best.map_or(f64::INFINITY, |b| b + tol2);
                let start = found.ee.len();
                found.ee.par_extend(
                    chunk
                        .par_iter()
                        .with_min_len(64)
                        .filter_map(|&pair| ee_contact(step, edges, pair, options, limit)),
                );
                lower(best, found.ee[start..].iter().map(|c| c.toi));
            }
        }
    }
}

/// Lowers `best` to the smallest of `tois`.
fn lower(best: &mut Option<f64>, tois: impl Iterator<Item = f64>) {
    for t in tois {
        if best.is_none_or(|b| t < b) {
            *best = Some(t);
        }
    }
}

/// Sorts what was found, keeps in [`Mode::Earliest`] only the contacts within the tolerance of
/// the earliest, and returns the earliest contact.
pub(crate) fn finish(found: &mut Found, options: &QueryOptions) -> Option<Contact> {
    found.vf.sort_unstable_by_key(|c| (c.vertex, c.face));
    found.ee.sort_unstable_by_key(|c| (c.a, c.b));
    let earliest = found
        .vf
        .iter()
        .map(|&c| Contact::Vf(c))
        .chain(found.ee.iter().map(|&c| Contact::Ee(c)))
        .min_by(Contact::earliest_order);
    if options.mode == Mode::Earliest {
        let cut = earliest.map_or(f64::NEG_INFINITY, |c| c.toi() + options.narrow.tolerance);
        found.vf.retain(|c| c.toi <= cut);
        found.ee.retain(|c| c.toi <= cut);
    }
    earliest
}

/// The time of impact and certainty over `[0, full.t_max]`, or `None` when the pair is
/// separated or has no contact before `limit`: solved first over the shorter interval up to
/// `limit`, and again over the full interval only if that finds a contact.
#[inline]
fn pruned(
    full: &NarrowOptions,
    limit: f64,
    solve: impl Fn(&NarrowOptions) -> Outcome,
) -> Option<(f64, Certainty)> {
    let contact = |o: Outcome| match o {
        Outcome::Separated => None,
        Outcome::Contact { toi, certainty } => Some((toi, certainty)),
    };
    if limit >= full.t_max {
        return contact(solve(full));
    }
    let short = NarrowOptions {
        t_max: limit,
        ..*full
    };
    contact(solve(&short))?;
    contact(solve(full))
}
