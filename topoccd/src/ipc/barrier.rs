//! Barrier functions `b(d, dhat)` with their first and second derivatives in `d` (ipctk's
//! `Barrier` classes). The potential evaluates them on squared distances: `d = dist^2 -
//! dmin^2` and `dhat' = (2 dmin + dhat) dhat` (see [`BarrierPotential`](super::BarrierPotential)).

/// A barrier function (ipctk 1.6.1's `ClampedLogBarrier`, `NormalizedClampedLogBarrier`,
/// `ClampedLogSqBarrier`, `CubicBarrier`).
///
/// ```
/// use topoccd::ipc::Barrier;
/// let b = Barrier::ClampedLog;
/// // -(d - dhat)^2 ln(d / dhat)
/// let (d, dhat) = (0.25f64, 1.0);
/// assert!((b.value(d, dhat) + (d - dhat).powi(2) * (d / dhat).ln()).abs() < 1e-15);
/// assert_eq!(b.value(2.0, 1.0), 0.0);
/// assert_eq!(b.value(0.0, 1.0), f64::INFINITY);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Barrier {
    /// `-(d - dhat)^2 ln(d / dhat)` for `0 < d < dhat` [Li et al. 2020]; ipctk's default.
    #[default]
    ClampedLog,
    /// The clamped log barrier of `d / dhat` with `dhat = 1`, dimensionless [Li et al. 2023].
    NormalizedClampedLog,
    /// `(d - dhat)^2 ln(d / dhat)^2` [Huang et al. 2024].
    ClampedLogSq,
    /// `-2/(3 dhat) (d - dhat)^3` for `d < dhat` [Ando 2024].
    Cubic,
}

impl Barrier {
    /// The barrier's value: `+inf` at `d <= 0` (except the cubic), 0 at `d >= dhat`.
    #[inline]
    pub fn value(self, d: f64, dhat: f64) -> f64 {
        match self {
            Barrier::ClampedLog => clamped_log(d, dhat),
            Barrier::NormalizedClampedLog => clamped_log(d / dhat, 1.0),
            Barrier::ClampedLogSq => {
                if d <= 0.0 {
                    return f64::INFINITY;
                }
                if d >= dhat {
                    return 0.0;
                }
                let (s, l) = (d - dhat, (d / dhat).ln());
                s * s * l * l
            }
            Barrier::Cubic => {
                if d < dhat {
                    let s = d - dhat;
                    -2.0 / 3.0 / dhat * s * s * s
                } else {
                    0.0
                }
            }
        }
    }

    /// The first derivative in `d` (0 outside `(0, dhat)`).
    #[inline]
    pub fn first_derivative(self, d: f64, dhat: f64) -> f64 {
        match self {
            Barrier::ClampedLog => clamped_log_first(d, dhat),
            Barrier::NormalizedClampedLog => clamped_log_first(d / dhat, 1.0) / dhat,
            Barrier::ClampedLogSq => {
                if d <= 0.0 || d >= dhat {
                    return 0.0;
                }
                let (s, l) = (d - dhat, (d / dhat).ln());
                2.0 * s * l * (l + s / d)
            }
            Barrier::Cubic => {
                if d < dhat {
                    let s = d - dhat;
                    -2.0 / dhat * s * s
                } else {
                    0.0
                }
            }
        }
    }

    /// The second derivative in `d` (0 outside `(0, dhat)`).
    #[inline]
    pub fn second_derivative(self, d: f64, dhat: f64) -> f64 {
        match self {
            Barrier::ClampedLog => clamped_log_second(d, dhat),
            Barrier::NormalizedClampedLog => clamped_log_second(d / dhat, 1.0) / (dhat * dhat),
            Barrier::ClampedLogSq => {
                if d <= 0.0 || d >= dhat {
                    return 0.0;
                }
                let (t0, t1) = (dhat - d, (d / dhat).ln());
                let t2 = t0 * t0 / (d * d);
                2.0 * (t1 * t1 - (t1 - 1.0) * t2 - 4.0 * t1 * t0 / d)
            }
            Barrier::Cubic => {
                if d < dhat {
                    4.0 * (1.0 - d / dhat)
                } else {
                    0.0
                }
            }
        }
    }

    /// The barrier's units for the physical barrier (ipctk's `units(dhat)`): `dhat^2`, or 1
    /// for the normalized barrier.
    #[inline]
    pub fn units(self, dhat: f64) -> f64 {
        match self {
            Barrier::NormalizedClampedLog => 1.0,
            _ => dhat * dhat,
        }
    }
}

#[inline]
fn clamped_log(d: f64, dhat: f64) -> f64 {
    if d <= 0.0 {
        return f64::INFINITY;
    }
    if d >= dhat {
        return 0.0;
    }
    let s = d - dhat;
    -s * s * (d / dhat).ln()
}

#[inline]
fn clamped_log_first(d: f64, dhat: f64) -> f64 {
    if d <= 0.0 || d >= dhat {
        return 0.0;
    }
    (dhat - d) * (2.0 * (d / dhat).ln() - dhat / d + 1.0)
}

#[inline]
fn clamped_log_second(d: f64, dhat: f64) -> f64 {
    if d <= 0.0 || d >= dhat {
        return 0.0;
    }
    let r = dhat / d;
    (r + 2.0) * r - 2.0 * (d / dhat).ln() - 3.0
}
