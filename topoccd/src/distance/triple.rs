//! The kernel shared by the point-plane and line-line distances: the squared length of the
//! projection of `r` on the normal `n = u x v`,
//! `f(r, u, v) = s^2 / m` with `s = r . n` (the triple product) and `m = |n|^2`.
//!
//! The derivatives of the pieces:
//!
//! - `ds/dr = n`, `ds/du = v x r`, `ds/dv = r x u`; the second derivatives of `s` are the
//!   blocks `d2s/dr du = -[v]x`, `d2s/dr dv = [u]x`, `d2s/du dv = -[r]x` (`[a]x b = a x b`),
//!   zero on the diagonal;
//! - `m = |u|^2 |v|^2 - (u.v)^2`: `dm/du = 2 v x n`, `dm/dv = 2 n x u`,
//!   `d2m/du2 = 2 (|v|^2 I - v v^T)`, `d2m/dv2 = 2 (|u|^2 I - u u^T)`,
//!   `d2m/du dv = 2 (2 u v^T - v u^T - (u.v) I)`.
//!
//! With `k = s / m`, `grad f = 2 k grad s - k^2 grad m`, which is
//! `(2 k n, 2 k v x w, 2 k w x u)` with `w = r - k n` (the part of `r` in the plane of `u`
//! and `v`), and
//! `hess f = (2 / m) h h^T + 2 k hess s - k^2 hess m` with `h = grad s - k grad m =
//! (n, v x q, q x u)`, `q = r - 2 k n`.
//!
//! The kernel needs `m > 0`; its callers handle `m == 0` (see [`super::point_plane`] and
//! [`super::line_line`]).

use super::linear_map::{add_block, diag_outer, scaled, skew, symmetrize};
use crate::math::DVec3;

/// `f(r, u, v)`; needs `|u x v| > 0`.
#[inline]
pub(crate) fn value(r: DVec3, u: DVec3, v: DVec3) -> f64 {
    let n = u.cross(v);
    let s = r.dot(n);
    s * s / n.length_squared()
}

/// The gradient of `f` in `(r, u, v)`; needs `|u x v| > 0`.
#[inline]
pub(crate) fn gradient(r: DVec3, u: DVec3, v: DVec3) -> [f64; 9] {
    let n = u.cross(v);
    let k = r.dot(n) / n.length_squared();
    let w = r - n * k;
    let (gr, gu, gv) = (
        n * (2.0 * k),
        v.cross(w) * (2.0 * k),
        w.cross(u) * (2.0 * k),
    );
    [gr.x, gr.y, gr.z, gu.x, gu.y, gu.z, gv.x, gv.y, gv.z]
}

/// The Hessian of `f` in `(r, u, v)`; needs `|u x v| > 0`.
#[inline]
pub(crate) fn hessian(r: DVec3, u: DVec3, v: DVec3) -> [[f64; 9]; 9] {
    let n = u.cross(v);
    let m = n.length_squared();
    let k = r.dot(n) / m;
    let q = r - n * (2.0 * k);
    let hv = [n, v.cross(q), q.cross(u)];
    let mut h = [[0.0; 9]; 9];
    // (2 / m) h h^T, upper triangle of blocks.
    for a in 0..3 {
        for b in a..3 {
            add_block(&mut h, a, b, diag_outer(0.0, 2.0 / m, hv[a], hv[b]));
        }
    }
    // 2 k hess s.
    let two_k = 2.0 * k;
    add_block(&mut h, 0, 1, scaled(-two_k, skew(v)));
    add_block(&mut h, 0, 2, scaled(two_k, skew(u)));
    add_block(&mut h, 1, 2, scaled(-two_k, skew(r)));
    // -k^2 hess m.
    let kk2 = -2.0 * k * k;
    let (uu, uv, vv) = (u.dot(u), u.dot(v), v.dot(v));
    add_block(&mut h, 1, 1, diag_outer(kk2 * vv, -kk2, v, v));
    add_block(&mut h, 2, 2, diag_outer(kk2 * uu, -kk2, u, u));
    let mut b = diag_outer(-kk2 * uv, 2.0 * kk2, u, v);
    let vu = diag_outer(0.0, -kk2, v, u);
    for i in 0..3 {
        for j in 0..3 {
            b[i][j] += vu[i][j];
        }
    }
    add_block(&mut h, 1, 2, b);
    symmetrize(&mut h);
    h
}
