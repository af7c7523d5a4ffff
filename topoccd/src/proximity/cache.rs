//! The candidates kept across a solver's iterations. A solver asks for proximity at
//! positions that move a little from one iteration to the next (a line search's fraction of
//! a step). When a `Ccd` has seen such a move, its next traversal inflates the boxes by a
//! margin (twice the last move, at most half the threshold) and keeps every feature pair
//! past the boxes. A later query whose positions lie within the margin of the ones listed at
//! (every vertex, every axis, net of any growth of the boxes' own inflation) evaluates those
//! pairs again instead of traversing: every pair the traversal would evaluate is among them,
//! each is evaluated by the same per-pair test and distance, so the report is the same.
//!
//! Why the pairs are all there: the traversal evaluates a pair only when its features'
//! boxes at the new positions `x`, inflated by `h`, overlap. Every vertex lies within `D`
//! (largest coordinate difference) of where it was at the listing positions `x_ref`, so
//! each feature's box at `x` lies inside its box at `x_ref` grown by `D`; two boxes that
//! overlap at `x` with inflation `h` overlap at `x_ref` with inflation `h + D`, hence with
//! the listing's inflation `h_ref + margin` whenever `h + D <= h_ref + margin`.

use crate::math::{DVec3, UNIT_ROUNDOFF};

use super::pairs::{Cands, Found, Test};

/// The largest margin, as a fraction of the threshold.
const MAX_MARGIN: f64 = 0.5;

/// The candidates of the last listing and where they were listed.
#[derive(Clone, Debug, Default)]
pub(crate) struct Cache {
    /// The positions of the last query (whatever it did), for the next margin.
    prev: Vec<DVec3>,
    /// The listing: its positions, threshold, inflation (with the margin), and pairs.
    listed: Option<Listed>,
}

#[derive(Clone, Debug)]
struct Listed {
    x: Vec<DVec3>,
    r: f64,
    inflation: f64,
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
        self.listed = None;
    }

    /// The listed candidates, if they cover a query at `x` with threshold `r` and
    /// inflation `h` (see the module).
    pub fn covering(&self, x: &[DVec3], r: f64, h: f64) -> Option<&Cands> {
        let l = self.listed.as_ref()?;
        if l.r != r || l.x.len() != x.len() {
            return None;
        }
        let d = displacement(x, &l.x);
        ((h + d) * (1.0 + 1e-12) <= l.inflation).then_some(&l.cands)
    }

    /// The margin of the next traversal at `x` with threshold `r`: twice the move since the
    /// last query, at most [`MAX_MARGIN`] `r`; 0 without a last query.
    pub fn margin(&self, x: &[DVec3], r: f64) -> f64 {
        if self.prev.len() != x.len() {
            return 0.0;
        }
        (2.0 * displacement(x, &self.prev)).min(MAX_MARGIN * r)
    }

    /// Remembers the positions of this query.
    pub fn seen(&mut self, x: &[DVec3]) {
        self.prev.clear();
        self.prev.extend_from_slice(x);
    }

    /// Keeps the candidates of a traversal at `x` with threshold `r`, inflation `inflation`.
    pub fn keep(&mut self, x: &[DVec3], r: f64, inflation: f64, cands: Cands) {
        self.listed = Some(Listed {
            x: x.to_vec(),
            r,
            inflation,
            cands,
        });
    }

    /// Forgets the listing (a traversal without one).
    pub fn drop_listing(&mut self) {
        self.listed = None;
    }
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
