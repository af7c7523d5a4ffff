//! The pairs kept across a solver's iterations. A solver asks for proximity at positions
//! that move a little from one iteration to the next (a line search's fraction of a step).
//! Once a `Ccd` has seen a move `D` (the largest coordinate difference of a vertex), a query
//! may list (when it pays, see below), beside its report, every pair closer than a listing
//! threshold `r_list = r + 2 sqrt(3) A + slack`, for an allowance `A` (the last move, at
//! most a quarter of the threshold). A later query whose vertices all lie within `A` of the
//! listing's positions (same threshold, no groups, no predicate, no cap, no deadline)
//! evaluates the listed pairs with the same per-pair test and distance instead of
//! traversing: the same report.
//!
//! Why every pair the query keeps is listed: a pair kept at the new positions has a
//! computed distance below `r + eps`, so an exact distance below `r + 2 eps` (`eps` the
//! rounding bound, `distance::rounding_bound`). Every point of the two features moved by at
//! most `sqrt(3) A` (Euclidean), so their exact distance at the listing was below
//! `r + 2 eps + 2 sqrt(3) A`, and its computed distance below that plus `eps`. `slack`
//! covers `3 eps` at any extent such a pair may have. And the listing traversal misses no pair
//! closer than `r_list`: its boxes and per-pair reject are those of a query at `r_list`.
//!
//! **Only while it pays.** A listing costs a wider traversal (more candidates, at `r_list`)
//! and pays only if a later query falls within its allowance. So a query lists only when a
//! listing made at the last query would have covered it: when this move is at most the last
//! move (and the cap). That check is exact and free (the last move is a number kept), so a
//! kept `Ccd` lists while the motion shrinks or holds (a line search's backtracking, the
//! same positions asked again) and traverses with unwidened boxes otherwise: after a first
//! move, after a move past the margin, after a growing one. Then it does the work of a
//! fresh query on a refitted tree.

use crate::math::{DVec3, UNIT_ROUNDOFF};

use crate::distance::rounding_bound;

use super::pairs::{Cands, Found, Test, PARALLEL_EXTRA};

/// The largest allowance, as a fraction of the threshold.
const MAX_ALLOWANCE: f64 = 0.25;

/// The candidates of the last listing and where they were listed.
#[derive(Clone, Debug, Default)]
pub(crate) struct Cache {
    /// The positions of the last query (whatever it did), for the next allowance.
    prev: Vec<DVec3>,
    /// The move of the last query from the one before it ([`displacement`]), if both were
    /// seen.
    last_move: Option<f64>,
    /// The listing: its positions, threshold, allowance, and pairs.
    listed: Option<Listed>,
}

#[derive(Clone, Debug)]
struct Listed {
    x: Vec<DVec3>,
    r: f64,
    allowance: f64,
    cands: Cands,
}

/// The largest coordinate difference between `a` and `b` (same length), rounded up by the
/// rounding of the subtractions.
fn displacement(a: &[DVec3], b: &[DVec3]) -> f64 {
    let (mut d, mut m) = (0.0f64, 0.0f64);
    for (p, q) in a.iter().zip(b) {
        d = d.max((*p - *q).abs().max_element());
        m = m.max(p.abs().max_element().max(q.abs().max_element()));
    }
    d * (1.0 + 4.0 * UNIT_ROUNDOFF) + 4.0 * UNIT_ROUNDOFF * m
}

impl Cache {
    /// Forgets everything (the primitives changed).
    pub fn clear(&mut self) {
        self.prev.clear();
        self.last_move = None;
        self.listed = None;
    }

    /// The listed pairs, if they cover a query at `x` with threshold `r` (see the module).
    pub fn covering(&self, x: &[DVec3], r: f64) -> Option<&Cands> {
        let l = self.listed.as_ref()?;
        if l.r != r || l.x.len() != x.len() {
            return None;
        }
        (displacement(x, &l.x) <= l.allowance).then_some(&l.cands)
    }

    /// The move of positions `x` since the last query: `None` without one.
    pub fn moved(&self, x: &[DVec3]) -> Option<f64> {
        (self.prev.len() == x.len()).then(|| displacement(x, &self.prev))
    }

    /// The allowance of a listing at this query, `moved` its move since the last query (see
    /// [`Cache::moved`]), for threshold `r`: the move, at most [`MAX_ALLOWANCE`] `r`, when a
    /// listing at the last query with its own allowance would have covered this query (see
    /// the module); else 0 (no listing: it would not pay).
    pub fn allowance(&self, moved: Option<f64>, r: f64) -> f64 {
        let cap = MAX_ALLOWANCE * r;
        match (moved, self.last_move) {
            (Some(d), Some(last)) if d <= last.min(cap) => d,
            _ => 0.0,
        }
    }

    /// Remembers the positions of this query and its move since the last one.
    pub fn seen(&mut self, x: &[DVec3], moved: Option<f64>) {
        self.last_move = moved;
        self.prev.clear();
        self.prev.extend_from_slice(x);
    }

    /// Keeps the pairs listed at `x` for threshold `r` and allowance `allowance`.
    pub fn keep(&mut self, x: &[DVec3], r: f64, allowance: f64, cands: Cands) {
        self.listed = Some(Listed {
            x: x.to_vec(),
            r,
            allowance,
            cands,
        });
    }

    /// Forgets the listing (a traversal without one).
    pub fn drop_listing(&mut self) {
        self.listed = None;
    }
}

/// The listing threshold for threshold `r`, allowance `allowance` (> 0), and `big` the
/// largest side of a triangle or free edge at the listing positions (see the module). A
/// pair's extent, at the listing or within the allowance of it, is below
/// `e = 2 (big + 2 A) + 2 r_list`, and `r_list < r + 4 A` (the slack is far below `A`...
/// or counted in the `4 r` below): `e` is taken as `(2 big + 4 r + 8 A) (1 + 1e-6)`.
pub(crate) fn list_threshold(r: f64, allowance: f64, big: f64) -> f64 {
    let e = (2.0 * big + 4.0 * r + 8.0 * allowance) * (1.0 + 1e-6);
    let slack = 4.0 * (rounding_bound(e, 1.0) + PARALLEL_EXTRA * e);
    (r + 2.0 * 3f64.sqrt() * allowance) * (1.0 + 1e-9) + slack
}

/// Evaluates the candidates `c` with `test` (the triangles `tris` for the faces').
pub(crate) fn evaluate(c: &Cands, tris: &[[u32; 3]], test: &Test<'_>) -> Found {
    let mut out = Found::default();
    for &(v, f) in &c.vf {
        test.vf(v, f, tris[f as usize], &mut out);
    }
    for &(a, b) in &c.ee {
        test.ee(a, b, &mut out);
    }
    for &(v, e) in &c.ve {
        test.ve(v, e, &mut out);
    }
    for &(a, b) in &c.vv {
        test.vv(a, b, &mut out);
    }
    out
}
