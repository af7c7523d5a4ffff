//! The squared distances of the collisions' types with their gradients and Hessians, and
//! the edge-edge mollifier, in closed form.
//!
//! Each distance is a function `F(y)` of a few difference vectors `y_k = sum_i A[k][i]
//! x_i` of the stencil's points (point-line: `w = p - e0`, `e = e1 - e0`; point-plane and
//! line-line: `w`, `a`, `b` with `F = (w . (a x b))^2 / |a x b|^2`); the derivatives in `x`
//! are `A^T grad F` and `A^T hess F A`, block by block.

// Index loops over small fixed-size arrays read as the formulas do.
#![allow(clippy::needless_range_loop)]

use crate::distance::EdgeEdgeType;
use crate::math::DVec3;

/// Value, gradient and Hessian (row-major) of a squared distance over `N` coordinates.
pub(crate) struct Local<const N: usize> {
    pub d2: f64,
    pub g: [f64; N],
    pub h: [[f64; N]; N],
}

type M3 = [[f64; 3]; 3];

#[inline]
fn outer(a: DVec3, b: DVec3) -> M3 {
    let (a, b) = (a.to_array(), b.to_array());
    let mut m = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] = a[i] * b[j];
        }
    }
    m
}

#[inline]
fn skew(a: DVec3) -> M3 {
    // [a]_x v = a x v
    [[0.0, -a.z, a.y], [a.z, 0.0, -a.x], [-a.y, a.x, 0.0]]
}

#[inline]
fn eye(s: f64) -> M3 {
    [[s, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]]
}

#[inline]
fn lin(terms: &[(f64, M3)]) -> M3 {
    let mut m = [[0.0; 3]; 3];
    for &(c, t) in terms {
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += c * t[i][j];
            }
        }
    }
    m
}

/// Maps a function of `K` difference vectors (gradient `gy`, Hessian blocks `hy`) to the
/// `P` points through `y_k = sum_i a[k][i] x_i`.
#[inline]
fn map<const K: usize, const P: usize, const N: usize>(
    d2: f64,
    a: &[[f64; P]; K],
    gy: &[DVec3; K],
    hy: &[[M3; K]; K],
    hess: bool,
) -> Local<N> {
    debug_assert_eq!(N, 3 * P);
    let mut g = [0.0; N];
    let mut h = [[0.0; N]; N];
    for i in 0..P {
        let mut v = DVec3::ZERO;
        for k in 0..K {
            v += gy[k] * a[k][i];
        }
        g[3 * i..3 * i + 3].copy_from_slice(&v.to_array());
    }
    if hess {
        for i in 0..P {
            for j in 0..P {
                let mut b = [[0.0; 3]; 3];
                for k in 0..K {
                    if a[k][i] == 0.0 {
                        continue;
                    }
                    for l in 0..K {
                        let c = a[k][i] * a[l][j];
                        if c == 0.0 {
                            continue;
                        }
                        for r in 0..3 {
                            for s in 0..3 {
                                b[r][s] += c * hy[k][l][r][s];
                            }
                        }
                    }
                }
                for r in 0..3 {
                    h[3 * i + r][3 * j..3 * j + 3].copy_from_slice(&b[r]);
                }
            }
        }
    }
    Local { d2, g, h }
}

/// `|w|^2 - (w.e)^2 / |e|^2` in `(w, e)`.
#[inline]
fn point_line_y(w: DVec3, e: DVec3) -> (f64, [DVec3; 2], [[M3; 2]; 2]) {
    let (al, be) = (w.dot(e), e.dot(e));
    let f = w.dot(w) - al * al / be;
    let gw = 2.0 * w - (2.0 * al / be) * e;
    let ge = (-2.0 * al / be) * w + (2.0 * al * al / (be * be)) * e;
    let hww = lin(&[(2.0, eye(1.0)), (-2.0 / be, outer(e, e))]);
    let hwe = lin(&[
        (-2.0 / be, outer(e, w)),
        (-2.0 * al / be, eye(1.0)),
        (4.0 * al / (be * be), outer(e, e)),
    ]);
    let hee = lin(&[
        (-2.0 / be, outer(w, w)),
        (4.0 * al / (be * be), outer(w, e)),
        (4.0 * al / (be * be), outer(e, w)),
        (2.0 * al * al / (be * be), eye(1.0)),
        (-8.0 * al * al / (be * be * be), outer(e, e)),
    ]);
    (f, [gw, ge], [[hww, hwe], [transpose(hwe), hee]])
}

#[inline]
fn transpose(m: M3) -> M3 {
    let mut t = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            t[i][j] = m[j][i];
        }
    }
    t
}

/// `(w . n)^2 / |n|^2` with `n = a x b`, in `(w, a, b)`.
#[inline]
fn plane_y(w: DVec3, a: DVec3, b: DVec3) -> (f64, [DVec3; 3], [[M3; 3]; 3]) {
    let n = a.cross(b);
    let s = w.dot(n);
    let nn = n.dot(n);
    let f = s * s / nn;
    let gs = [n, b.cross(w), w.cross(a)];
    let gn = [DVec3::ZERO, 2.0 * b.cross(n), 2.0 * n.cross(a)];
    let z = [[0.0; 3]; 3];
    // Hessian of s: ww = aa = bb = 0, wa = -[b]x, wb = [a]x, ab = -[w]x.
    let neg = |m: M3| lin(&[(-1.0, m)]);
    let swa = neg(skew(b));
    let swb = skew(a);
    let sab = neg(skew(w));
    let hs = [
        [z, swa, swb],
        [transpose(swa), z, sab],
        [transpose(swb), transpose(sab), z],
    ];
    // Hessian of N = |n|^2: aa = 2(|b|^2 I - b b^T), bb = 2(|a|^2 I - a a^T),
    // ab = 2(a b^T - (a.b) I) - 2[n]x.
    let naa = lin(&[(2.0 * b.dot(b), eye(1.0)), (-2.0, outer(b, b))]);
    let nbb = lin(&[(2.0 * a.dot(a), eye(1.0)), (-2.0, outer(a, a))]);
    let nab = lin(&[
        (2.0, outer(a, b)),
        (-2.0 * a.dot(b), eye(1.0)),
        (-2.0, skew(n)),
    ]);
    let hn = [[z, z, z], [z, naa, nab], [z, transpose(nab), nbb]];
    let mut g = [DVec3::ZERO; 3];
    for k in 0..3 {
        g[k] = (2.0 * s / nn) * gs[k] - (s * s / (nn * nn)) * gn[k];
    }
    let mut h = [[z; 3]; 3];
    let (c1, c2, c3, c4, c5) = (
        2.0 / nn,
        2.0 * s / nn,
        -2.0 * s / (nn * nn),
        2.0 * s * s / (nn * nn * nn),
        -s * s / (nn * nn),
    );
    for k in 0..3 {
        for l in 0..3 {
            h[k][l] = lin(&[
                (c1, outer(gs[k], gs[l])),
                (c2, hs[k][l]),
                (c3, outer(gs[k], gn[l])),
                (c3, outer(gn[k], gs[l])),
                (c4, outer(gn[k], gn[l])),
                (c5, hn[k][l]),
            ]);
        }
    }
    (f, g, h)
}

/// Point-point `|p - q|^2` over `(p, q)`.
#[inline]
pub(crate) fn vv(p: [DVec3; 2], hess: bool) -> Local<6> {
    let w = p[0] - p[1];
    let h2 = eye(2.0);
    map(
        w.length_squared(),
        &[[1.0, -1.0]],
        &[2.0 * w],
        &[[h2]],
        hess,
    )
}

/// Point-line over `(p, e0, e1)`.
#[inline]
pub(crate) fn ev(p: [DVec3; 3], hess: bool) -> Local<9> {
    let (f, g, h) = point_line_y(p[0] - p[1], p[2] - p[1]);
    map(f, &[[1.0, -1.0, 0.0], [0.0, -1.0, 1.0]], &g, &h, hess)
}

/// Point-plane over `(p, t0, t1, t2)`.
#[inline]
pub(crate) fn fv(p: [DVec3; 4], hess: bool) -> Local<12> {
    let (f, g, h) = plane_y(p[0] - p[1], p[2] - p[1], p[3] - p[1]);
    let a = [
        [1.0, -1.0, 0.0, 0.0],
        [0.0, -1.0, 1.0, 0.0],
        [0.0, -1.0, 0.0, 1.0],
    ];
    map(f, &a, &g, &h, hess)
}

/// Edge-edge of the type over `(ea0, ea1, eb0, eb1)`.
pub(crate) fn ee(p: [DVec3; 4], t: EdgeEdgeType, hess: bool) -> Local<12> {
    use EdgeEdgeType::*;
    // A point-point or point-line sub-case: which points, in the stencil's slots.
    let pp = |i: usize, j: usize| {
        let w = p[i] - p[j];
        let mut a = [[0.0; 4]];
        a[0][i] = 1.0;
        a[0][j] = -1.0;
        map(w.length_squared(), &a, &[2.0 * w], &[[eye(2.0)]], hess)
    };
    let pl = |q: usize, e0: usize, e1: usize| {
        let (f, g, h) = point_line_y(p[q] - p[e0], p[e1] - p[e0]);
        let mut a = [[0.0; 4]; 2];
        a[0][q] = 1.0;
        a[0][e0] = -1.0;
        a[1][e1] = 1.0;
        a[1][e0] = -1.0;
        map(f, &a, &g, &h, hess)
    };
    match t {
        Ea0Eb0 => pp(0, 2),
        Ea0Eb1 => pp(0, 3),
        Ea1Eb0 => pp(1, 2),
        Ea1Eb1 => pp(1, 3),
        EaEb0 => pl(2, 0, 1),
        EaEb1 => pl(3, 0, 1),
        Ea0Eb => pl(0, 2, 3),
        Ea1Eb => pl(1, 2, 3),
        EaEb => {
            let (f, g, h) = plane_y(p[2] - p[0], p[1] - p[0], p[3] - p[2]);
            let a = [
                [-1.0, 0.0, 1.0, 0.0],
                [-1.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, -1.0, 1.0],
            ];
            map(f, &a, &g, &h, hess)
        }
    }
}

/// The mollifier `m(x) = (2 - x/eps) x/eps` for `x < eps`, else 1, of `x = |(ea1 - ea0) x
/// (eb1 - eb0)|^2`, with its gradient and (when asked) Hessian over the 12 coordinates.
pub(crate) fn mollifier(p: [DVec3; 4], eps: f64, hess: bool) -> (f64, [f64; 12], [[f64; 12]; 12]) {
    let (u, v) = (p[1] - p[0], p[3] - p[2]);
    let x = u.cross(v).length_squared();
    let mut g = [0.0; 12];
    let mut h = [[0.0; 12]; 12];
    if x >= eps {
        return (1.0, g, h);
    }
    let r = x / eps;
    let m = (2.0 - r) * r;
    let m1 = 2.0 / eps * (1.0 - r);
    let m2 = -2.0 / (eps * eps);
    let (uu, vv, uv) = (u.dot(u), v.dot(v), u.dot(v));
    // dx/du = 2|v|^2 u - 2(u.v) v, dx/dv = 2|u|^2 v - 2(u.v) u.
    let gu = u * (2.0 * vv) - v * (2.0 * uv);
    let gv = v * (2.0 * uu) - u * (2.0 * uv);
    // The chain rule: u = ea1 - ea0, v = eb1 - eb0.
    let sign = [-1.0, 1.0, -1.0, 1.0];
    let gx = [gu, gu, gv, gv];
    for k in 0..4 {
        for c in 0..3 {
            g[3 * k + c] = m1 * sign[k] * gx[k][c];
        }
    }
    if hess {
        let (ua, va) = (u.to_array(), v.to_array());
        // Blocks of the Hessian of x: uu = 2|v|^2 I - 2 v v^T, vv = 2|u|^2 I - 2 u u^T,
        // uv = 4 u v^T - 2 v u^T - 2 (u.v) I, vu its transpose.
        let block = |bu: bool, bv: bool, i: usize, j: usize| -> f64 {
            let id = if i == j { 1.0 } else { 0.0 };
            match (bu, bv) {
                (true, true) => 2.0 * vv * id - 2.0 * va[i] * va[j],
                (false, false) => 2.0 * uu * id - 2.0 * ua[i] * ua[j],
                (true, false) => 4.0 * ua[i] * va[j] - 2.0 * va[i] * ua[j] - 2.0 * uv * id,
                (false, true) => 4.0 * va[i] * ua[j] - 2.0 * ua[i] * va[j] - 2.0 * uv * id,
            }
        };
        for k in 0..4 {
            for l in 0..4 {
                let s = sign[k] * sign[l];
                for i in 0..3 {
                    for j in 0..3 {
                        let gk = sign[k] * gx[k][i];
                        let gl = sign[l] * gx[l][j];
                        h[3 * k + i][3 * l + j] = m2 * gk * gl + m1 * s * block(k < 2, l < 2, i, j);
                    }
                }
            }
        }
    }
    (m, g, h)
}
