//! The brute-force oracle: every feature pair of the configuration, no hierarchy and no
//! ownership, with the same distance test. `O(n^2)`; for tests and small inputs.

use rayon::prelude::*;

use super::pairs::{Found, Test};
use super::primitives::Primitives;
use super::run::Stop;

/// Every vertex against every triangle not containing it, every edge against every edge
/// sharing no vertex, every free point against every free edge and every other free point. Rows
/// (a vertex, an edge, a free point) run in parallel; a stop is checked once per row.
pub(crate) fn brute(prims: &Primitives, tris: &[[u32; 3]], test: &Test<'_>, stop: &Stop) -> Found {
    let n = test.x.len() as u32;
    let edges = &prims.edges;
    let vf = (0..n).into_par_iter().map(|v| {
        let mut out = Found::default();
        if stop.check() {
            return out;
        }
        for (f, tri) in tris.iter().enumerate() {
            if !tri.contains(&v) {
                test.vf(v, f as u32, *tri, &mut out);
            }
        }
        out
    });
    let ee = (0..edges.len()).into_par_iter().map(|i| {
        let mut out = Found::default();
        if stop.check() {
            return out;
        }
        let a = edges[i];
        for &b in &edges[i + 1..] {
            if !(a.contains(&b[0]) || a.contains(&b[1])) {
                test.ee(a, b, &mut out);
            }
        }
        out
    });
    let points = &prims.points;
    let pv = (0..points.len()).into_par_iter().map(|i| {
        let mut out = Found::default();
        if stop.check() {
            return out;
        }
        let p = points[i];
        for &e in &edges[prims.mesh_edges..] {
            test.ve(p, e, &mut out);
        }
        for &q in &points[i + 1..] {
            test.vv(p, q, &mut out);
        }
        out
    });
    let mut all: Vec<Found> = vf.collect();
    all.par_extend(ee);
    all.par_extend(pv);
    let mut found = Found::default();
    for mut f in all {
        // A failure is kept in `found.failure`, which the query returns.
        if found.append(&mut f).is_err() {
            break;
        }
    }
    found
}
