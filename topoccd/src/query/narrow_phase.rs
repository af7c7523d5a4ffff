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
    let t_end = limit.min(options.narrow.t_max);
    if vf_separated(&q, options.narrow.min_separation, t_end) {
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
    let t_end = limit.min(options.narrow.t_max);
    if ee_separated(&q, options.narrow.min_separation, t_end) {
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

/// What the narrow phase reads besides the candidates.
pub(crate) struct Context<'a, 's> {
    pub step: &'a Step<'s>,
    /// The step's edges, sorted lexicographically (edge-edge candidates index them).
    pub edges: &'a [[u32; 2]],
    pub options: &'a QueryOptions,
}

impl Context<'_, '_> {
    /// The end of the interval that still matters once a contact at `best` is known: in
    /// [`Mode::Earliest`], `best + 2 tolerance` (a pair skipped with it has no contact before
    /// that, the solver being conservative on its interval, so every pair whose time is within
    /// the tolerance of the earliest is still found); unbounded in [`Mode::All`].
    pub fn limit(&self, best: Option<f64>) -> f64 {
        match (self.options.mode, best) {
            (Mode::Earliest, Some(b)) => b + 2.0 * self.options.narrow.tolerance,
            _ => f64::INFINITY,
        }
    }

    /// Solves the candidates in order on this thread, appending the contacts to `found`.
    /// `limit` (see [`Context::limit`]) is lowered as contacts are found.
    pub fn solve(&self, candidates: &Candidates, limit: &mut f64, found: &mut Found) {
        let earliest = self.options.mode == Mode::Earliest;
        for &pair in &candidates.vf {
            if let Some(c) = vf_contact(self.step, pair, self.options, *limit) {
                if earliest {
                    *limit = limit.min(self.limit(Some(c.toi)));
                }
                found.vf.push(c);
            }
        }
        for &pair in &candidates.ee {
            if let Some(c) = ee_contact(self.step, self.edges, pair, self.options, *limit) {
                if earliest {
                    *limit = limit.min(self.limit(Some(c.toi)));
                }
                found.ee.push(c);
            }
        }
    }

    /// Solves a buffer of candidates on the current rayon pool, appending the contacts to
    /// `found`. In [`Mode::Earliest`] the buffer goes in fixed chunks, each pruned with the
    /// best time of the chunks before (`best`, updated), so what is pruned does not depend on
    /// the thread count.
    pub fn solve_parallel(&self, candidates: &Candidates, best: &mut Option<f64>, found: &mut Found) {
        let step = self.step;
        let options = self.options;
        let edges = self.edges;
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
                for chunk in candidates.vf.chunks(EARLIEST_CHUNK) {
                    let limit = self.limit(*best);
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
                    let limit = self.limit(*best);
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
}

/// Lowers `best` to the smallest of `tois`.
pub(crate) fn lower(best: &mut Option<f64>, tois: impl Iterator<Item = f64>) {
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
