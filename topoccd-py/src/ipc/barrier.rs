//! The barrier's parameters and the normal force magnitude (for friction), CSR assembly,
//! and the adaptive-stiffness helpers. The barrier potential itself is the library's
//! (`topoccd::ipc::BarrierPotential`).

/// `b(x) = -(x - y)^2 ln(x / y)` for `0 < x < y` (`x` a squared distance, `y = dhat^2`), 0
/// from `y` on, infinite at and below 0; with its first two derivatives.
pub fn clamped_log(x: f64, y: f64) -> (f64, f64, f64) {
    if x >= y {
        return (0.0, 0.0, 0.0);
    }
    if x <= 0.0 {
        return (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
    }
    let l = (x / y).ln();
    let r = x - y;
    (
        -r * r * l,
        -2.0 * r * l - r * r / x,
        -2.0 * l - 4.0 * r / x + r * r / (x * x),
    )
}

/// The potential's parameters.
#[derive(Clone, Copy, Debug)]
pub struct Barrier {
    pub dhat: f64,
    pub stiffness: f64,
    pub physical: bool,
}

impl Barrier {
    /// `(x, y, scale)`: the barrier's arguments' offsets for `dmin` and the factor in front.
    fn args(&self, dmin: f64) -> (f64, f64) {
        let y = (2.0 * dmin + self.dhat) * self.dhat;
        let scale = if self.physical {
            self.stiffness * self.dhat / y
        } else {
            self.stiffness
        };
        (y, scale)
    }

    /// The normal force magnitude of a unit-weight collision at `d2`, as ipctk's
    /// `barrier_force_magnitude`: `-2 kappa b'(d^2 - dmin^2) sqrt(d^2)`, times the physical
    /// barrier's factor `dhat / y^2` when it is on.
    pub fn force_magnitude(&self, d2: f64, dmin: f64) -> f64 {
        let (y, scale) = self.args(dmin);
        let (_, db, _) = clamped_log(d2 - dmin * dmin, y);
        -scale * db * 2.0 * d2.sqrt()
    }
}

/// A sparse symmetric matrix in CSR: `indptr` (n + 1), `indices` and `data` (nnz).
pub struct Csr {
    pub indptr: Vec<i32>,
    pub indices: Vec<i32>,
    pub data: Vec<f64>,
}

/// Assembles local `m x m` blocks (`dofs` their global indices) into CSR, summing repeats.
pub struct Assembler {
    n: usize,
    rows: Vec<Vec<(u32, f64)>>,
}

impl Assembler {
    pub fn new(n: usize) -> Self {
        Self {
            n,
            rows: vec![Vec::new(); n],
        }
    }

    pub fn add(&mut self, dofs: &[usize], h: &[f64]) {
        let m = dofs.len();
        for i in 0..m {
            let row = &mut self.rows[dofs[i]];
            for j in 0..m {
                let v = h[i * m + j];
                if v != 0.0 {
                    row.push((dofs[j] as u32, v));
                }
            }
        }
    }

    pub fn finish(mut self) -> Csr {
        let mut indptr = Vec::with_capacity(self.n + 1);
        let mut indices = Vec::new();
        let mut data = Vec::new();
        indptr.push(0i32);
        for row in &mut self.rows {
            row.sort_unstable_by_key(|e| e.0);
            let mut last = u32::MAX;
            for &(j, v) in row.iter() {
                if j == last {
                    *data.last_mut().expect("an entry before") += v;
                } else {
                    indices.push(j as i32);
                    data.push(v);
                    last = j;
                }
            }
            indptr.push(indices.len() as i32);
        }
        Csr {
            indptr,
            indices,
            data,
        }
    }
}

/// ipctk's `initial_barrier_stiffness`: `(kappa, max_kappa)`.
pub fn initial_stiffness(
    diag: f64,
    dhat: f64,
    average_mass: f64,
    grad_energy: &[f64],
    grad_barrier: &[f64],
    scale: f64,
    dmin: f64,
) -> (f64, f64) {
    let y = 2.0 * dmin * dhat + dhat * dhat;
    let mut d0 = 1e-8 * diag + dmin;
    d0 *= d0;
    if d0 - dmin * dmin >= y {
        d0 = dmin * dhat + 0.5 * dhat * dhat;
    }
    let (_, _, b2) = clamped_log(d0 - dmin * dmin, y);
    let kmin = scale * average_mass / (4.0 * d0 * b2);
    let kmax = 100.0 * kmin;
    let gg: f64 = grad_barrier.iter().map(|v| v * v).sum();
    let mut kappa = 1.0;
    if gg > 0.0 {
        let ge: f64 = grad_barrier
            .iter()
            .zip(grad_energy)
            .map(|(a, b)| a * b)
            .sum();
        kappa = -ge / gg;
    }
    (
        if kappa < kmin {
            kmin
        } else if kmax < kappa {
            kmax
        } else {
            kappa
        },
        kmax,
    )
}

/// ipctk's `update_barrier_stiffness` (distances squared, as the collisions give them).
pub fn update_stiffness(
    prev: f64,
    cur: f64,
    kmax: f64,
    kappa: f64,
    diag: f64,
    eps_scale: f64,
    dmin: f64,
) -> f64 {
    let mut eps = eps_scale * (diag + dmin);
    eps *= eps;
    if prev < eps && cur < eps && cur < prev {
        return kmax.min(2.0 * kappa);
    }
    kappa
}
