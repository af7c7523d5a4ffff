//! The adaptive barrier stiffness of IPC (ipctk's `initial_barrier_stiffness` and
//! `update_barrier_stiffness`, same arguments and defaults).

use super::barrier::Barrier;

/// The result of [`initial_barrier_stiffness`]: the stiffness and the largest one
/// [`update_barrier_stiffness`] may raise it to (ipctk returns the latter through a
/// reference).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InitialStiffness {
    /// The initial stiffness `kappa`.
    pub stiffness: f64,
    /// The cap: 100 times the smallest stiffness.
    pub max_stiffness: f64,
}

/// The initial stiffness [Li et al. 2020]: the `kappa` that balances the barrier's
/// gradient `grad_barrier` (at `kappa = 1`) against the energy's `grad_energy`
/// (`kappa = -grad_barrier . grad_energy / |grad_barrier|^2`), clamped to
/// `[kappa_min, 100 kappa_min]` with `kappa_min = min_barrier_stiffness_scale *
/// average_mass / (4 d0 b''(d0 - dmin^2))`, `d0 = (1e-8 bbox_diagonal + dmin)^2`.
/// ipctk's defaults: `min_barrier_stiffness_scale = 1e11`, `dmin = 0`.
///
/// ```
/// use topoccd::ipc::{initial_barrier_stiffness, Barrier};
/// let k = initial_barrier_stiffness(1.0, Barrier::ClampedLog, 1e-3, 1.0, &[0.0; 3], &[0.0; 3], 1e11, 0.0);
/// assert!(k.stiffness > 0.0 && k.max_stiffness == 100.0 * k.stiffness);
/// ```
#[allow(clippy::too_many_arguments)]
pub fn initial_barrier_stiffness(
    bbox_diagonal: f64,
    barrier: Barrier,
    dhat: f64,
    average_mass: f64,
    grad_energy: &[f64],
    grad_barrier: &[f64],
    min_barrier_stiffness_scale: f64,
    dmin: f64,
) -> InitialStiffness {
    let (dhat2, dmin2) = (dhat * dhat, dmin * dmin);
    let mut d0 = 1e-8 * bbox_diagonal + dmin;
    d0 *= d0;
    if d0 - dmin2 >= 2.0 * dmin * dhat + dhat2 {
        d0 = dmin * dhat + 0.5 * dhat2;
    }
    let mut kmin = 4.0 * d0 * barrier.second_derivative(d0 - dmin2, 2.0 * dmin * dhat + dhat2);
    kmin = min_barrier_stiffness_scale * average_mass / kmin;
    let kmax = 100.0 * kmin;
    let gb2: f64 = grad_barrier.iter().map(|g| g * g).sum();
    let mut kappa = 1.0;
    if gb2 > 0.0 {
        let dot: f64 = grad_barrier
            .iter()
            .zip(grad_energy)
            .map(|(a, b)| a * b)
            .sum();
        kappa = -dot / gb2;
    }
    InitialStiffness {
        stiffness: kappa.max(kmin).min(kmax),
        max_stiffness: kmax,
    }
}

/// Doubles the stiffness (up to `max_barrier_stiffness`) when the minimum distance keeps
/// falling below `(dhat_epsilon_scale (bbox_diagonal + dmin))^2`; the distances are ipctk's
/// squared ones ([`NormalCollisions::compute_minimum_distance`](super::NormalCollisions::compute_minimum_distance)).
/// ipctk's defaults: `dhat_epsilon_scale = 1e-9`, `dmin = 0`.
///
/// ```
/// use topoccd::ipc::update_barrier_stiffness;
/// assert_eq!(update_barrier_stiffness(1e-20, 1e-21, 100.0, 1.0, 1.0, 1e-9, 0.0), 2.0);
/// assert_eq!(update_barrier_stiffness(1e-2, 1e-3, 100.0, 1.0, 1.0, 1e-9, 0.0), 1.0);
/// ```
pub fn update_barrier_stiffness(
    prev_min_distance: f64,
    min_distance: f64,
    max_barrier_stiffness: f64,
    barrier_stiffness: f64,
    bbox_diagonal: f64,
    dhat_epsilon_scale: f64,
    dmin: f64,
) -> f64 {
    let mut eps = dhat_epsilon_scale * (bbox_diagonal + dmin);
    eps *= eps;
    if prev_min_distance < eps && min_distance < eps && min_distance < prev_min_distance {
        return max_barrier_stiffness.min(2.0 * barrier_stiffness);
    }
    barrier_stiffness
}
