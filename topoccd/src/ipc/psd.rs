//! Projection of a symmetric matrix onto the positive semi-definite cone, by its
//! eigen-decomposition.
//!
//! A collision's Hessian is translation invariant: moving all its points by one vector
//! changes nothing, so the three translations are in its kernel. Its eigenvectors of
//! nonzero eigenvalue lie in the orthonormal complement `Q` of the translations, and
//! `H = Q (Q^T H Q) Q^T` exactly. [`project_translation_free`] decomposes the reduced
//! matrix `Q^T H Q` (3 (P - 1) square for P points: 9 for 12, 6 for 9, 3 for 6) and
//! subtracts the negative part, `H+ = H - Q (sum_{l < 0} l v v^T) Q^T` for the clamp (twice
//! that for the absolute values): the same matrix as the projection of the full `H`, at a
//! fraction of the cost. Before any decomposition a Cholesky factorisation tests whether the
//! reduced matrix is positive definite; if so it is left as is.
//!
//! The decomposition is Householder tridiagonalisation followed by the implicit QL
//! iteration with Wilkinson-like shifts (the classical `tred2` / `tql2` pair of EISPACK), on
//! stack arrays of the fixed size.

// Index loops over small fixed-size arrays read as the formulas do.
#![allow(clippy::needless_range_loop)]

use nalgebra::DMatrix;

/// How a collision's Hessian is made positive semi-definite before assembly (ipctk's
/// `PSDProjectionMethod`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PsdProjection {
    /// No projection (ipctk's `NONE`, the default of its `hessian`).
    #[default]
    None,
    /// Negative eigenvalues set to 0 (`CLAMP`).
    Clamp,
    /// Negative eigenvalues replaced by their absolute values (`ABS`).
    Abs,
}

impl PsdProjection {
    /// The factor of the negative part removed: `H+ = H - f sum_{l < 0} l v v^T`.
    #[inline]
    fn factor(self) -> f64 {
        match self {
            PsdProjection::None => 0.0,
            PsdProjection::Clamp => 1.0,
            PsdProjection::Abs => 2.0,
        }
    }
}

/// Projects the symmetric `n x n` matrix `h` (row-major, `h.len() == n * n`) in place: when
/// its smallest eigenvalue is negative, `h = V f(D) V^T` with `f` the method's map of the
/// eigenvalues; a matrix already PSD is left as is (as ipctk does).
///
/// ```
/// use topoccd::ipc::{project_to_psd, PsdProjection};
/// let mut h = [1.0, 2.0, 2.0, 1.0]; // eigenvalues 3 and -1
/// project_to_psd(&mut h, 2, PsdProjection::Clamp);
/// for (a, b) in h.iter().zip([1.5, 1.5, 1.5, 1.5]) { assert!((a - b).abs() < 1e-14); }
/// let mut h = [1.0, 2.0, 2.0, 1.0];
/// project_to_psd(&mut h, 2, PsdProjection::Abs); // eigenvalues 3 and 1
/// for (a, b) in h.iter().zip([2.0, 1.0, 1.0, 2.0]) { assert!((a - b).abs() < 1e-14); }
/// ```
pub fn project_to_psd(h: &mut [f64], n: usize, method: PsdProjection) {
    assert_eq!(h.len(), n * n, "project_to_psd: h must hold n * n entries");
    if method == PsdProjection::None || n == 0 {
        return;
    }
    match n {
        2 => fixed::<2>(h, method),
        3 => fixed::<3>(h, method),
        6 => fixed::<6>(h, method),
        9 => fixed::<9>(h, method),
        12 => fixed::<12>(h, method),
        _ => dynamic(h, n, method),
    }
}

/// The full decomposition on a stack matrix of size `N`.
fn fixed<const N: usize>(h: &mut [f64], method: PsdProjection) {
    let mut a = [[0.0; N]; N];
    for i in 0..N {
        a[i].copy_from_slice(&h[i * N..(i + 1) * N]);
    }
    if is_positive_definite(&a) {
        return;
    }
    let (d, v) = symmetric_eigen(a);
    let f = method.factor();
    for k in 0..N {
        if d[k] < 0.0 {
            let s = f * d[k];
            for i in 0..N {
                let si = s * v[k][i];
                for j in 0..N {
                    h[i * N + j] -= si * v[k][j];
                }
            }
        }
    }
}

/// Any other size, on the heap (nalgebra's decomposition).
fn dynamic(h: &mut [f64], n: usize, method: PsdProjection) {
    let m = DMatrix::<f64>::from_row_slice(n, n, h);
    let e = m.symmetric_eigen();
    if e.eigenvalues.min() >= 0.0 {
        return;
    }
    let f = method.factor();
    for k in 0..n {
        let l = e.eigenvalues[k];
        if l < 0.0 {
            for i in 0..n {
                for j in 0..n {
                    h[i * n + j] -= f * l * e.eigenvectors[(i, k)] * e.eigenvectors[(j, k)];
                }
            }
        }
    }
}

/// The orthonormal complement of the translations of `P` points, point by point: row `i`
/// is point `i`'s weights on the `P - 1` basis vectors (each basis vector of `R^(3P)` is
/// one of these columns times a unit coordinate vector).
pub(crate) trait Complement<const P: usize, const K: usize> {
    /// The `P x K` weights; the columns are orthonormal and orthogonal to `(1, ..., 1)`.
    const Q: [[f64; K]; P];
}

/// The translation complements of 2, 3 and 4 points.
pub(crate) struct Translations;

const S2: f64 = std::f64::consts::FRAC_1_SQRT_2;
// 1 / sqrt(6)
const S6: f64 = 0.408_248_290_463_863_f64;

impl Complement<2, 1> for Translations {
    const Q: [[f64; 1]; 2] = [[S2], [-S2]];
}
impl Complement<3, 2> for Translations {
    const Q: [[f64; 2]; 3] = [[S2, S6], [-S2, S6], [0.0, -2.0 * S6]];
}
impl Complement<4, 3> for Translations {
    // The rows of a 4 x 4 Hadamard matrix but the first, over 2.
    const Q: [[f64; 3]; 4] = [
        [0.5, 0.5, 0.5],
        [0.5, -0.5, -0.5],
        [-0.5, 0.5, -0.5],
        [-0.5, -0.5, 0.5],
    ];
}

/// Projects a translation-invariant symmetric `N x N` Hessian of `P` points (`N = 3 P`,
/// `R = 3 K = 3 (P - 1)`) in place, through its reduced `R x R` matrix (see the module's
/// documentation). The result equals [`project_to_psd`] of the full matrix up to rounding;
/// only the translation-free part of `h` is kept (its translation part is zero for an exact
/// Hessian of a translation-invariant function, to rounding).
#[inline]
pub(crate) fn project_translation_free<
    const P: usize,
    const K: usize,
    const N: usize,
    const R: usize,
>(
    h: &mut [[f64; N]; N],
    method: PsdProjection,
) where
    Translations: Complement<P, K>,
{
    debug_assert!(N == 3 * P && R == 3 * K && K + 1 == P);
    if method == PsdProjection::None {
        return;
    }
    let q = <Translations as Complement<P, K>>::Q;
    // t = Q^T H (R x N), then m = t Q (R x R); Q acts on the point index only.
    let mut t = [[0.0; N]; R];
    for a in 0..K {
        for i in 0..P {
            let w = q[i][a];
            if w == 0.0 {
                continue;
            }
            for r in 0..3 {
                let (src, dst) = (&h[3 * i + r], &mut t[3 * a + r]);
                for c in 0..N {
                    dst[c] += w * src[c];
                }
            }
        }
    }
    let mut m = [[0.0; R]; R];
    for row in 0..R {
        for b in 0..K {
            for j in 0..P {
                let w = q[j][b];
                if w == 0.0 {
                    continue;
                }
                for c in 0..3 {
                    m[row][3 * b + c] += w * t[row][3 * j + c];
                }
            }
        }
    }
    if is_positive_definite(&m) {
        return;
    }
    let (d, v) = symmetric_eigen(m);
    let f = method.factor();
    for k in 0..R {
        if d[k] >= 0.0 {
            continue;
        }
        // u = Q v_k, in the full coordinates.
        let mut u = [0.0; N];
        for i in 0..P {
            for a in 0..K {
                for c in 0..3 {
                    u[3 * i + c] += q[i][a] * v[k][3 * a + c];
                }
            }
        }
        let s = f * d[k];
        for i in 0..N {
            let si = s * u[i];
            for j in 0..N {
                h[i][j] -= si * u[j];
            }
        }
    }
}

/// Whether the symmetric matrix `a` is positive definite: its Cholesky factorisation runs
/// with every pivot positive (a pivot within rounding of zero counts as not definite, so the
/// caller decomposes).
#[inline]
pub(crate) fn is_positive_definite<const N: usize>(a: &[[f64; N]; N]) -> bool {
    let mut l = [[0.0; N]; N];
    let mut diag_max = 0.0f64;
    for i in 0..N {
        diag_max = diag_max.max(a[i][i].abs());
    }
    let tol = 64.0 * f64::EPSILON * diag_max;
    for j in 0..N {
        let mut s = a[j][j];
        for k in 0..j {
            s -= l[j][k] * l[j][k];
        }
        // Not greater, NaN included.
        if s.partial_cmp(&tol) != Some(std::cmp::Ordering::Greater) {
            return false;
        }
        let d = s.sqrt();
        l[j][j] = d;
        let inv = 1.0 / d;
        for i in j + 1..N {
            let mut s = a[i][j];
            for k in 0..j {
                s -= l[i][k] * l[j][k];
            }
            l[i][j] = s * inv;
        }
    }
    true
}

/// The eigenvalues `d` and eigenvectors of the symmetric matrix `a` (the vector of `d[k]`
/// is the row `v[k]`), unordered: Householder tridiagonalisation, then the implicit QL
/// iteration (EISPACK's `tred2` and `tql2`).
pub(crate) fn symmetric_eigen<const N: usize>(a: [[f64; N]; N]) -> ([f64; N], [[f64; N]; N]) {
    if N == 0 {
        return ([0.0; N], a);
    }
    // z: the accumulated transformations, eigenvectors in its columns at the end.
    let mut z = a;
    let mut d = [0.0; N];
    let mut e = [0.0; N];
    tridiagonalize(&mut z, &mut d, &mut e);
    ql_implicit(&mut z, &mut d, &mut e);
    let mut v = [[0.0; N]; N];
    for i in 0..N {
        for k in 0..N {
            v[k][i] = z[i][k];
        }
    }
    (d, v)
}

/// Householder reduction of the symmetric `z` to tridiagonal form: diagonal `d`,
/// subdiagonal `e[1..]` (`e[0] = 0`); `z` becomes the orthogonal transformation.
fn tridiagonalize<const N: usize>(z: &mut [[f64; N]; N], d: &mut [f64; N], e: &mut [f64; N]) {
    let n = N;
    d[..n].copy_from_slice(&z[n - 1][..n]);
    for i in (1..n).rev() {
        let mut scale = 0.0;
        let mut h = 0.0;
        for k in 0..i {
            scale += d[k].abs();
        }
        if scale == 0.0 {
            e[i] = d[i - 1];
            for j in 0..i {
                d[j] = z[i - 1][j];
                z[i][j] = 0.0;
                z[j][i] = 0.0;
            }
        } else {
            for k in 0..i {
                d[k] /= scale;
                h += d[k] * d[k];
            }
            let mut f = d[i - 1];
            let mut g = h.sqrt();
            if f > 0.0 {
                g = -g;
            }
            e[i] = scale * g;
            h -= f * g;
            d[i - 1] = f - g;
            for j in 0..i {
                e[j] = 0.0;
            }
            for j in 0..i {
                f = d[j];
                z[j][i] = f;
                g = e[j] + z[j][j] * f;
                for k in j + 1..i {
                    g += z[k][j] * d[k];
                    e[k] += z[k][j] * f;
                }
                e[j] = g;
            }
            f = 0.0;
            for j in 0..i {
                e[j] /= h;
                f += e[j] * d[j];
            }
            let hh = f / (h + h);
            for j in 0..i {
                e[j] -= hh * d[j];
            }
            for j in 0..i {
                f = d[j];
                g = e[j];
                for k in j..i {
                    z[k][j] -= f * e[k] + g * d[k];
                }
                d[j] = z[i - 1][j];
                z[i][j] = 0.0;
            }
        }
        d[i] = h;
    }
    // Accumulate the transformations.
    for i in 0..n - 1 {
        z[n - 1][i] = z[i][i];
        z[i][i] = 1.0;
        let h = d[i + 1];
        if h != 0.0 {
            for k in 0..=i {
                d[k] = z[k][i + 1] / h;
            }
            for j in 0..=i {
                let mut g = 0.0;
                for k in 0..=i {
                    g += z[k][i + 1] * z[k][j];
                }
                for k in 0..=i {
                    z[k][j] -= g * d[k];
                }
            }
        }
        for k in 0..=i {
            z[k][i + 1] = 0.0;
        }
    }
    for j in 0..n {
        d[j] = z[n - 1][j];
        z[n - 1][j] = 0.0;
    }
    z[n - 1][n - 1] = 1.0;
    e[0] = 0.0;
}

/// The implicit QL iteration on the tridiagonal `(d, e)`, rotating the columns of `z`:
/// `d` becomes the eigenvalues, `z`'s columns the eigenvectors.
fn ql_implicit<const N: usize>(z: &mut [[f64; N]; N], d: &mut [f64; N], e: &mut [f64; N]) {
    let n = N;
    for i in 1..n {
        e[i - 1] = e[i];
    }
    e[n - 1] = 0.0;
    let mut f = 0.0;
    let mut tst1 = 0.0f64;
    let eps = f64::EPSILON;
    for l in 0..n {
        tst1 = tst1.max(d[l].abs() + e[l].abs());
        let mut m = l;
        while m < n - 1 && e[m].abs() > eps * tst1 {
            m += 1;
        }
        if m > l {
            // At most a few dozen sweeps in practice; the bound keeps a NaN from looping.
            for _ in 0..64 {
                let mut g = d[l];
                let mut p = (d[l + 1] - g) / (2.0 * e[l]);
                let mut r = (p * p + 1.0).sqrt();
                if p < 0.0 {
                    r = -r;
                }
                d[l] = e[l] / (p + r);
                d[l + 1] = e[l] * (p + r);
                let dl1 = d[l + 1];
                let mut h = g - d[l];
                for i in l + 2..n {
                    d[i] -= h;
                }
                f += h;
                p = d[m];
                let (mut c, mut c2, mut c3) = (1.0, 1.0, 1.0);
                let el1 = e[l + 1];
                let (mut s, mut s2) = (0.0, 0.0);
                for i in (l..m).rev() {
                    c3 = c2;
                    c2 = c;
                    s2 = s;
                    g = c * e[i];
                    h = c * p;
                    r = (p * p + e[i] * e[i]).sqrt();
                    e[i + 1] = s * r;
                    s = e[i] / r;
                    c = p / r;
                    p = c * d[i] - s * g;
                    d[i + 1] = h + s * (c * g + s * d[i]);
                    for row in z.iter_mut() {
                        let h = row[i + 1];
                        row[i + 1] = s * row[i] + c * h;
                        row[i] = c * row[i] - s * h;
                    }
                }
                p = -s * s2 * c3 * el1 * e[l] / dl1;
                e[l] = s * p;
                d[l] = c * p;
                if e[l].abs() <= eps * tst1 {
                    break;
                }
            }
        }
        d[l] += f;
        e[l] = 0.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The plain projection with nalgebra's decomposition of the full matrix: the reference.
    pub(crate) fn reference<const N: usize>(
        h: &[[f64; N]; N],
        method: PsdProjection,
    ) -> [[f64; N]; N] {
        let m = DMatrix::<f64>::from_fn(N, N, |i, j| h[i][j]);
        let e = m.symmetric_eigen();
        if e.eigenvalues.min() >= 0.0 {
            return *h;
        }
        let d = e.eigenvalues.map(|l| match method {
            PsdProjection::Clamp => l.max(0.0),
            PsdProjection::Abs => l.abs(),
            PsdProjection::None => l,
        });
        let r = &e.eigenvectors * DMatrix::from_diagonal(&d) * e.eigenvectors.transpose();
        std::array::from_fn(|i| std::array::from_fn(|j| r[(i, j)]))
    }

    fn frobenius<const N: usize>(a: &[[f64; N]; N]) -> f64 {
        a.iter().flatten().map(|v| v * v).sum::<f64>().sqrt()
    }

    pub(crate) fn rel_diff<const N: usize>(a: &[[f64; N]; N], b: &[[f64; N]; N]) -> f64 {
        let mut d = [[0.0; N]; N];
        for i in 0..N {
            for j in 0..N {
                d[i][j] = a[i][j] - b[i][j];
            }
        }
        frobenius(&d) / frobenius(b).max(f64::MIN_POSITIVE)
    }

    fn random_symmetric<const N: usize>(rng: &mut ChaCha8Rng) -> [[f64; N]; N] {
        let mut a = [[0.0; N]; N];
        for i in 0..N {
            for j in 0..=i {
                let v = rng.random::<f64>() * 2.0 - 1.0;
                a[i][j] = v;
                a[j][i] = v;
            }
        }
        a
    }

    fn check_eigen<const N: usize>(a: [[f64; N]; N]) {
        let (d, v) = symmetric_eigen(a);
        let scale = frobenius(&a).max(f64::MIN_POSITIVE);
        for k in 0..N {
            // A v = d v and |v| = 1.
            for i in 0..N {
                let av: f64 = (0..N).map(|j| a[i][j] * v[k][j]).sum();
                assert!((av - d[k] * v[k][i]).abs() < 1e-13 * scale, "A v != d v");
            }
            for l in 0..N {
                let dot: f64 = (0..N).map(|i| v[k][i] * v[l][i]).sum();
                let want = if k == l { 1.0 } else { 0.0 };
                assert!((dot - want).abs() < 1e-13, "not orthonormal");
            }
        }
        // The eigenvalues are nalgebra's.
        let m = DMatrix::<f64>::from_fn(N, N, |i, j| a[i][j]);
        let mut ours = d.to_vec();
        let mut theirs: Vec<f64> = m.symmetric_eigen().eigenvalues.iter().copied().collect();
        ours.sort_by(f64::total_cmp);
        theirs.sort_by(f64::total_cmp);
        for (x, y) in ours.iter().zip(&theirs) {
            assert!((x - y).abs() < 1e-13 * scale, "{x} vs {y}");
        }
    }

    #[test]
    fn eigen_matches_nalgebra_on_random_and_degenerate_matrices() {
        let mut rng = ChaCha8Rng::seed_from_u64(41);
        for _ in 0..500 {
            check_eigen(random_symmetric::<3>(&mut rng));
            check_eigen(random_symmetric::<6>(&mut rng));
            check_eigen(random_symmetric::<9>(&mut rng));
            check_eigen(random_symmetric::<12>(&mut rng));
        }
        // Degenerate: zero, identity, repeated eigenvalues, rank one, already diagonal.
        check_eigen([[0.0; 9]; 9]);
        check_eigen(std::array::from_fn::<_, 9, _>(|i| {
            std::array::from_fn(|j| if i == j { 1.0 } else { 0.0 })
        }));
        let u: [f64; 9] = std::array::from_fn(|i| (i as f64 + 1.0).sin());
        check_eigen(std::array::from_fn::<_, 9, _>(|i| {
            std::array::from_fn(|j| u[i] * u[j])
        }));
        check_eigen(std::array::from_fn::<_, 6, _>(|i| {
            std::array::from_fn(|j| {
                if i == j {
                    [3.0, -1.0, 3.0, 0.0, -1.0, 2.0][i]
                } else {
                    0.0
                }
            })
        }));
    }

    /// A random translation-invariant Hessian of `P` points: `T^T S T` with `T` the map to
    /// the differences from point 0 and `S` random symmetric (indefinite).
    fn translation_invariant<const P: usize, const N: usize>(
        rng: &mut ChaCha8Rng,
        rank: usize,
    ) -> [[f64; N]; N] {
        let s = random_symmetric::<N>(rng);
        let mut h = [[0.0; N]; N];
        // Differences y_i = x_i - x_0 for i >= 1 (coordinates 3..N), low rank when asked.
        let keep = |i: usize| i >= 3 && i < 3 + rank;
        let mut t = [[0.0; N]; N];
        for i in 3..N {
            if keep(i) {
                t[i][i] = 1.0;
                t[i][i % 3] = -1.0;
            }
        }
        for i in 0..N {
            for j in 0..N {
                for k in 0..N {
                    for l in 0..N {
                        h[i][j] += t[k][i] * s[k][l] * t[l][j];
                    }
                }
            }
        }
        h
    }

    /// `|a - b| / |h|` in the Frobenius norm: the projection's rounding scales with its input
    /// `h`, not with its result, which is near zero when `h` is negative semi-definite.
    fn diff_over_input<const N: usize>(
        a: &[[f64; N]; N],
        b: &[[f64; N]; N],
        h: &[[f64; N]; N],
    ) -> f64 {
        rel_diff(a, b) * frobenius(b).max(f64::MIN_POSITIVE) / frobenius(h).max(f64::MIN_POSITIVE)
    }

    fn check_reduced<const P: usize, const K: usize, const N: usize, const R: usize>(
        h: [[f64; N]; N],
    ) where
        Translations: Complement<P, K>,
    {
        for method in [PsdProjection::Clamp, PsdProjection::Abs] {
            let want = reference(&h, method);
            let mut got = h;
            project_translation_free::<P, K, N, R>(&mut got, method);
            let d = diff_over_input(&got, &want, &h);
            assert!(d < 1e-12, "reduced projection differs by {d:e}");
            let mut flat: Vec<f64> = h.iter().flatten().copied().collect();
            project_to_psd(&mut flat, N, method);
            let full: [[f64; N]; N] =
                std::array::from_fn(|i| std::array::from_fn(|j| flat[i * N + j]));
            let d = diff_over_input(&full, &want, &h);
            assert!(d < 1e-12, "full projection differs by {d:e}");
        }
    }

    #[test]
    fn complements_are_orthonormal_and_free_of_translations() {
        fn check<const P: usize, const K: usize>()
        where
            Translations: Complement<P, K>,
        {
            let q = <Translations as Complement<P, K>>::Q;
            for a in 0..K {
                assert!((0..P).map(|i| q[i][a]).sum::<f64>().abs() < 1e-15);
                for b in 0..K {
                    let dot: f64 = (0..P).map(|i| q[i][a] * q[i][b]).sum();
                    assert!((dot - if a == b { 1.0 } else { 0.0 }).abs() < 1e-15);
                }
            }
        }
        check::<2, 1>();
        check::<3, 2>();
        check::<4, 3>();
    }

    #[test]
    fn reduced_projection_equals_the_full_one() {
        let mut rng = ChaCha8Rng::seed_from_u64(42);
        for _ in 0..300 {
            for rank in [3, 6, 9] {
                check_reduced::<4, 3, 12, 9>(translation_invariant::<4, 12>(&mut rng, rank));
            }
            for rank in [3, 6] {
                check_reduced::<3, 2, 9, 6>(translation_invariant::<3, 9>(&mut rng, rank));
            }
            check_reduced::<2, 1, 6, 3>(translation_invariant::<2, 6>(&mut rng, 3));
        }
        // Degenerate: zero, and already PSD.
        check_reduced::<4, 3, 12, 9>([[0.0; 12]; 12]);
        let mut h = translation_invariant::<4, 12>(&mut rng, 9);
        h = reference(&h, PsdProjection::Abs);
        check_reduced::<4, 3, 12, 9>(h);
    }

    #[test]
    fn positive_definite_test_agrees_with_the_eigenvalues() {
        let mut rng = ChaCha8Rng::seed_from_u64(43);
        for _ in 0..1000 {
            let mut a = random_symmetric::<6>(&mut rng);
            let shift = rng.random::<f64>() * 3.0;
            for i in 0..6 {
                a[i][i] += shift;
            }
            let m = DMatrix::<f64>::from_fn(6, 6, |i, j| a[i][j]);
            let min = m.symmetric_eigen().eigenvalues.min();
            if is_positive_definite(&a) {
                assert!(min > 0.0, "called definite with eigenvalue {min}");
            } else {
                assert!(min < 1e-12, "not called definite with eigenvalue {min}");
            }
        }
    }
}
