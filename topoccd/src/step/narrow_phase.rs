//! The narrow phase shared by every method: the elementary tests over a buffer of candidate
//! feature pairs, in either mode.

use rayon::prelude::*;

use super::prefilter::{ee_separated, vf_separated};
use super::report::{Contact, EeContact, VfContact};
use super::{Mode, QueryOptions, Step};
use crate::narrow::{edge_edge, vertex_face, EdgeEdge, NarrowOptions, VertexFace};

/// What the narrow phase found.
#[derive(Debug, Default)]
pub(crate) struct Found {
    pub vf: Vec<VfContact>,
    pub ee: Vec<EeContact>,
    pub earliest: Option<Contact>,
}

fn vf_query(step: &Step, [v, f]: [u32; 2]) -> VertexFace {
    let (x0, x1) = (step.x0(), step.x1());
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
    let (x0, x1) = (step.x0(), step.x1());
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

/// Runs the elementary tests on the candidates, each first through the conservative
/// [`prefilter`](super::prefilter): `vf` holds `(vertex, face)`, `ee` holds pairs of
/// indices into `edges`, the step's edges sorted lexicographically (so a smaller index is the
/// lexicographically smaller edge).
///
/// In [`Mode::All`] every candidate is solved over `[0, t_max]`. In [`Mode::Earliest`] a
/// candidate is first solved over `[0, min(t_max, best + 2 tolerance)]`, where `best` is the
/// earliest time found so far: a contact there is then solved again over `[0, t_max]` exactly
/// as in [`Mode::All`], so the times compared are the same numbers in both modes, and a pair
/// skipped this way has no contact before `best` (the solver is conservative on its
/// interval), so the result is still no later than the first contact.
pub(crate) fn run(
    step: &Step,
    edges: &[[u32; 2]],
    vf: &[[u32; 2]],
    ee: &[[u32; 2]],
    options: &QueryOptions,
) -> Found {
    let full = options.narrow;
    let sep = if full.min_separation > 0.0 && full.min_separation.is_finite() {
        full.min_separation
    } else {
        0.0
    };
    let mut found = Found::default();
    match options.mode {
        Mode::All => {
            // Every candidate is independent: run them on the current rayon pool (one thread
            // or many); the results are sorted below, so the output does not depend on it.
            found.vf = vf
                .par_iter()
                .with_min_len(256)
                .filter_map(|&pair| {
                    let q = vf_query(step, pair);
                    if vf_separated(&q, sep) {
                        return None;
                    }
                    let toi = vertex_face(&q, &full).toi()?;
                    Some(VfContact {
                        vertex: pair[0],
                        face: pair[1],
                        toi,
                    })
                })
                .collect();
            found.ee = ee
                .par_iter()
                .with_min_len(256)
                .filter_map(|&[e, f]| {
                    let (a, b) = (edges[e as usize], edges[f as usize]);
                    debug_assert!(a < b);
                    let q = ee_query(step, a, b);
                    if ee_separated(&q, sep) {
                        return None;
                    }
                    let toi = edge_edge(&q, &full).toi()?;
                    Some(EeContact { a, b, toi })
                })
                .collect();
            found.vf.sort_unstable_by_key(|c| (c.vertex, c.face));
            found.ee.sort_unstable_by_key(|c| (c.a, c.b));
            found.earliest = found
                .vf
                .iter()
                .map(|&c| Contact::Vf(c))
                .chain(found.ee.iter().map(|&c| Contact::Ee(c)))
                .min_by(Contact::earliest_order);
        }
        Mode::Earliest => {
            let mut best: Option<Contact> = None;
            for &pair in vf {
                let q = vf_query(step, pair);
                if vf_separated(&q, sep) {
                    continue;
                }
                let toi = pruned(&full, best, |o| vertex_face(&q, o).toi());
                if let Some(toi) = toi {
                    let c = VfContact {
                        vertex: pair[0],
                        face: pair[1],
                        toi,
                    };
                    offer(Contact::Vf(c), &mut best);
                }
            }
            for &[e, f] in ee {
                let (a, b) = (edges[e as usize], edges[f as usize]);
                let q = ee_query(step, a, b);
                if ee_separated(&q, sep) {
                    continue;
                }
                if let Some(toi) = pruned(&full, best, |o| edge_edge(&q, o).toi()) {
                    offer(Contact::Ee(EeContact { a, b, toi }), &mut best);
                }
            }
            found.earliest = best;
        }
    }
    found
}

/// Keeps the earlier of `c` and `best` in [`Contact::earliest_order`].
fn offer(c: Contact, best: &mut Option<Contact>) {
    if best.is_none_or(|b| c.earliest_order(&b).is_lt()) {
        *best = Some(c);
    }
}

/// The time of impact over `[0, full.t_max]`, or `None` when the pair is separated or cannot
/// beat `best`: solved first over the shorter interval up to `best` (plus two tolerances), and
/// again over the full interval only if that finds a contact.
#[inline]
fn pruned(
    full: &NarrowOptions,
    best: Option<Contact>,
    solve: impl Fn(&NarrowOptions) -> Option<f64>,
) -> Option<f64> {
    let limit = match best {
        Some(b) => b.toi() + 2.0 * full.tolerance,
        None => f64::INFINITY,
    };
    if limit >= full.t_max {
        return solve(full);
    }
    let short = NarrowOptions {
        t_max: limit,
        ..*full
    };
    solve(&short)?;
    solve(full)
}
