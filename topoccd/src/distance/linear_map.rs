//! The constant linear maps between a distance's own variables and the coordinates of the
//! pair's points, for gradients and Hessians.
//!
//! A distance written in `K` difference vectors `d_k = sum_j c[k][j] x_j` of the `P` points
//! `x_j` has gradient `g = A^T g_d` and Hessian `H = A^T H_d A` in the points' coordinates,
//! where `A = c ⊗ I3`. [`pull_back_gradient`] and [`pull_back_hessian`] apply that map block
//! by block without forming `A`. [`scatter_gradient`] and [`scatter_hessian`] place the
//! derivatives of a sub-distance over some of the points into the arrays over all of them.

use crate::math::DVec3;

/// A 3x3 block, row-major.
pub(crate) type Block = [[f64; 3]; 3];

/// The matrix of the cross product by `a`: `skew(a) b = a x b`.
#[inline]
pub(crate) fn skew(a: DVec3) -> Block {
    [[0.0, -a.z, a.y], [a.z, 0.0, -a.x], [-a.y, a.x, 0.0]]
}

/// `alpha I + beta a b^T`.
#[inline]
pub(crate) fn diag_outer(alpha: f64, beta: f64, a: DVec3, b: DVec3) -> Block {
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = beta * a[i] * b[j];
        }
        row[i] += alpha;
    }
    m
}

/// `s m`.
#[inline]
pub(crate) fn scaled(s: f64, m: Block) -> Block {
    m.map(|row| row.map(|x| s * x))
}

/// Adds `m` at block `(a, b)` of `h` and, when `a != b`, `m^T` at block `(b, a)`.
#[inline]
pub(crate) fn add_block<const M: usize>(h: &mut [[f64; M]; M], a: usize, b: usize, m: Block) {
    for i in 0..3 {
        for j in 0..3 {
            h[3 * a + i][3 * b + j] += m[i][j];
            if a != b {
                h[3 * b + j][3 * a + i] += m[i][j];
            }
        }
    }
}

/// The gradient over the `P` points (`N = 3P` entries) of a function whose gradient over its
/// `K` difference vectors (`M = 3K` entries) is `g`; row `k` of `c` gives difference `k`'s
/// coefficients on the points.
#[inline(always)]
pub(crate) fn pull_back_gradient<const K: usize, const M: usize, const P: usize, const N: usize>(
    c: &[[f64; P]; K],
    g: &[f64; M],
) -> [f64; N] {
    debug_assert!(M == 3 * K && N == 3 * P);
    let mut out = [0.0; N];
    for j in 0..P {
        for (k, ck) in c.iter().enumerate() {
            if ck[j] != 0.0 {
                for i in 0..3 {
                    out[3 * j + i] += ck[j] * g[3 * k + i];
                }
            }
        }
    }
    out
}

/// The Hessian over the points of a function whose Hessian over its difference vectors is
/// `h` (see [`pull_back_gradient`]); the result is made exactly symmetric.
#[inline(always)]
pub(crate) fn pull_back_hessian<const K: usize, const M: usize, const P: usize, const N: usize>(
    c: &[[f64; P]; K],
    h: &[[f64; M]; M],
) -> [[f64; N]; N] {
    debug_assert!(M == 3 * K && N == 3 * P);
    // First T = H A (M x N), then A^T T.
    let mut t = [[0.0; N]; M];
    for (row, hrow) in t.iter_mut().zip(h) {
        for l in 0..P {
            for (k, ck) in c.iter().enumerate() {
                if ck[l] != 0.0 {
                    for i in 0..3 {
                        row[3 * l + i] += ck[l] * hrow[3 * k + i];
                    }
                }
            }
        }
    }
    let mut out = [[0.0; N]; N];
    for j in 0..P {
        for (k, ck) in c.iter().enumerate() {
            if ck[j] != 0.0 {
                for i in 0..3 {
                    for (o, x) in out[3 * j + i].iter_mut().zip(&t[3 * k + i]) {
                        *o += ck[j] * x;
                    }
                }
            }
        }
    }
    symmetrize(&mut out);
    out
}

/// Copies the upper triangle of `h` onto the lower one.
#[inline]
#[allow(clippy::needless_range_loop)] // `h[i][j] = h[j][i]` reads across rows
pub(crate) fn symmetrize<const N: usize>(h: &mut [[f64; N]; N]) {
    for i in 0..N {
        for j in 0..i {
            h[i][j] = h[j][i];
        }
    }
}

/// The gradient over `N / 3` points of a sub-distance whose gradient `g` is over the points
/// `idx` (in its own argument order); the other entries are 0.
#[inline(always)]
pub(crate) fn scatter_gradient<const L: usize, const N: usize>(
    g: &[f64; L],
    idx: &[usize],
) -> [f64; N] {
    debug_assert!(L == 3 * idx.len());
    let mut out = [0.0; N];
    for (a, &ia) in idx.iter().enumerate() {
        out[3 * ia..3 * ia + 3].copy_from_slice(&g[3 * a..3 * a + 3]);
    }
    out
}

/// The Hessian over `N / 3` points of a sub-distance whose Hessian `h` is over the points
/// `idx` (see [`scatter_gradient`]).
#[inline(always)]
pub(crate) fn scatter_hessian<const L: usize, const N: usize>(
    h: &[[f64; L]; L],
    idx: &[usize],
) -> [[f64; N]; N] {
    debug_assert!(L == 3 * idx.len());
    let mut out = [[0.0; N]; N];
    for (a, &ia) in idx.iter().enumerate() {
        for i in 0..3 {
            let row = &mut out[3 * ia + i];
            for (b, &ib) in idx.iter().enumerate() {
                row[3 * ib..3 * ib + 3].copy_from_slice(&h[3 * a + i][3 * b..3 * b + 3]);
            }
        }
    }
    out
}
