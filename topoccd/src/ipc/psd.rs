//! Projection of a symmetric matrix onto the positive semi-definite cone, by its
//! eigen-decomposition (nalgebra's `SymmetricEigen`).

// Index loops over small fixed-size arrays read as the formulas do.
#![allow(clippy::needless_range_loop)]

use nalgebra::{DMatrix, SMatrix};

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
        6 => fixed::<6>(h, method),
        9 => fixed::<9>(h, method),
        12 => fixed::<12>(h, method),
        _ => dynamic(h, n, method),
    }
}

/// The eigenvalue map of the method.
#[inline]
fn map(l: f64, method: PsdProjection) -> f64 {
    match method {
        PsdProjection::Clamp => l.max(0.0),
        PsdProjection::Abs => l.abs(),
        PsdProjection::None => l,
    }
}

macro_rules! fixed_impl {
    ($($n:literal),*) => {
        /// The decomposition on a stack matrix of size `N` (6, 9 or 12).
        #[inline]
        fn fixed<const N: usize>(h: &mut [f64], method: PsdProjection) {
            match N {
                $($n => {
                    let m = SMatrix::<f64, $n, $n>::from_row_slice(h);
                    let e = m.symmetric_eigen();
                    if e.eigenvalues.min() >= 0.0 {
                        return;
                    }
                    let d = e.eigenvalues.map(|l| map(l, method));
                    let v = &e.eigenvectors;
                    let r = v * SMatrix::<f64, $n, $n>::from_diagonal(&d) * v.transpose();
                    for i in 0..$n {
                        for j in 0..$n {
                            h[i * $n + j] = r[(i, j)];
                        }
                    }
                })*
                _ => dynamic(h, N, method),
            }
        }
    };
}
fixed_impl!(6, 9, 12);

/// Any other size, on the heap.
fn dynamic(h: &mut [f64], n: usize, method: PsdProjection) {
    let m = DMatrix::<f64>::from_row_slice(n, n, h);
    let e = m.symmetric_eigen();
    if e.eigenvalues.min() >= 0.0 {
        return;
    }
    let d = e.eigenvalues.map(|l| map(l, method));
    let r = &e.eigenvectors * DMatrix::from_diagonal(&d) * e.eigenvectors.transpose();
    for i in 0..n {
        for j in 0..n {
            h[i * n + j] = r[(i, j)];
        }
    }
}
