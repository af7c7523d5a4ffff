//! Projection of a small symmetric matrix (a collision's local Hessian, up to 12 x 12) onto the
//! positive semi-definite cone: eigenvalues by cyclic Jacobi rotations, then negative ones
//! clamped to zero or replaced by their absolute values.

/// How the local Hessians are projected (ipctk's `PSDProjectionMethod`: 0, 1, 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Psd {
    None,
    Clamp,
    Abs,
}

impl Psd {
    pub fn from_code(code: u8) -> Option<Self> {
        match code {
            0 => Some(Psd::None),
            1 => Some(Psd::Clamp),
            2 => Some(Psd::Abs),
            _ => None,
        }
    }
}

/// Eigenvalues and eigenvectors (columns of `v`) of the symmetric `a` (row-major `n x n`).
fn jacobi(a: &mut [f64], v: &mut [f64], n: usize) {
    for i in 0..n {
        for j in 0..n {
            v[i * n + j] = if i == j { 1.0 } else { 0.0 };
        }
    }
    for _sweep in 0..100 {
        let mut off = 0.0;
        let mut diag = 0.0;
        for i in 0..n {
            diag += a[i * n + i] * a[i * n + i];
            for j in i + 1..n {
                off += a[i * n + j] * a[i * n + j];
            }
        }
        if off <= 1e-34 * diag || off == 0.0 {
            return;
        }
        for p in 0..n {
            for q in p + 1..n {
                let apq = a[p * n + q];
                if apq == 0.0 {
                    continue;
                }
                let app = a[p * n + p];
                let aqq = a[q * n + q];
                let theta = (aqq - app) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let akp = a[k * n + p];
                    let akq = a[k * n + q];
                    a[k * n + p] = c * akp - s * akq;
                    a[k * n + q] = s * akp + c * akq;
                }
                for k in 0..n {
                    let apk = a[p * n + k];
                    let aqk = a[q * n + k];
                    a[p * n + k] = c * apk - s * aqk;
                    a[q * n + k] = s * apk + c * aqk;
                }
                for k in 0..n {
                    let vkp = v[k * n + p];
                    let vkq = v[k * n + q];
                    v[k * n + p] = c * vkp - s * vkq;
                    v[k * n + q] = s * vkp + c * vkq;
                }
            }
        }
    }
}

/// Projects the symmetric `h` (row-major `n x n`) in place.
pub fn project(h: &mut [f64], n: usize, method: Psd) {
    if method == Psd::None || n == 0 {
        return;
    }
    let mut a = h.to_vec();
    let mut v = vec![0.0; n * n];
    jacobi(&mut a, &mut v, n);
    let lambda: Vec<f64> = (0..n).map(|i| a[i * n + i]).collect();
    if lambda.iter().all(|&l| l >= 0.0) {
        return;
    }
    let fixed: Vec<f64> = lambda
        .iter()
        .map(|&l| match (l < 0.0, method) {
            (true, Psd::Clamp) => 0.0,
            (true, _) => -l,
            (false, _) => l,
        })
        .collect();
    for i in 0..n {
        for j in 0..n {
            let mut s = 0.0;
            for k in 0..n {
                s += v[i * n + k] * fixed[k] * v[j * n + k];
            }
            h[i * n + j] = s;
        }
    }
}
