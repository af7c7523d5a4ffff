//! ipctk's clamped log barrier and the barrier potential over a collision set: energy,
//! gradient (flat, `3 #V`) and Hessian (CSR, optionally projected per collision to PSD), and
//! the adaptive-stiffness helpers.

use super::collisions::{Collision, Collisions};
use super::distance::{hd_cross2, hd_line, hd_line_line, hd_plane, hd_pp, stencil_distance2};
use super::hd::{points, Hd};
use super::psd::{project, Psd};

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

/// The edge-edge mollifier `m(c) = (2 - c/eps) c/eps` below `eps`, else 1, with derivatives.
pub fn mollifier(c: f64, eps: f64) -> (f64, f64, f64) {
    if c < eps {
        let t = c / eps;
        ((2.0 - t) * t, 2.0 / eps * (1.0 - t), -2.0 / (eps * eps))
    } else {
        (1.0, 0.0, 0.0)
    }
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
    /// `barrier_force_magnitude`: `-kappa b'(d^2 - dmin^2) 2 (d + dmin) / dhat`... in ipctk's
    /// form `-2 kappa b' sqrt(d^2)`, with the physical factor.
    pub fn force_magnitude(&self, d2: f64, dmin: f64) -> f64 {
        let (y, scale) = self.args(dmin);
        let (_, db, _) = clamped_log(d2 - dmin * dmin, y);
        -scale * db * 2.0 * d2.sqrt()
    }
}

fn gather(c: &Collision, x: &[f64], out: &mut [f64; 12]) -> usize {
    let n = c.nverts();
    for (k, &v) in c.verts[..n].iter().enumerate() {
        out[3 * k..3 * k + 3].copy_from_slice(&x[3 * v as usize..3 * v as usize + 3]);
    }
    n
}

fn local<const N: usize>(c: &Collision, xs: &[f64], b: &Barrier, dmin: f64) -> Hd<N> {
    let p = points::<N>(xs);
    let d2 = match c.kind {
        0 => hd_pp(&p[0], &p[1]),
        1 => hd_line(&p[0], &p[1], &p[2]),
        3 => hd_plane(&p[0], &p[1], &p[2], &p[3]),
        _ => match c.dtype {
            0 => hd_pp(&p[0], &p[2]),
            1 => hd_pp(&p[0], &p[3]),
            2 => hd_pp(&p[1], &p[2]),
            3 => hd_pp(&p[1], &p[3]),
            4 => hd_line(&p[2], &p[0], &p[1]),
            5 => hd_line(&p[3], &p[0], &p[1]),
            6 => hd_line(&p[0], &p[2], &p[3]),
            7 => hd_line(&p[1], &p[2], &p[3]),
            _ => hd_line_line(&p[0], &p[1], &p[2], &p[3]),
        },
    };
    let (y, scale) = b.args(dmin);
    let (f, df, d2f) = clamped_log(d2.v - dmin * dmin, y);
    let mut e = d2.chain(f, df, d2f);
    if c.kind == 2 {
        let cr = hd_cross2(&p[0], &p[1], &p[2], &p[3]);
        let (m, dm, d2m) = mollifier(cr.v, c.eps_x);
        if m != 1.0 || dm != 0.0 {
            e = cr.chain(m, dm, d2m) * e;
        }
    }
    e.scale(scale * c.weight)
}

/// Local gradient and Hessian (row-major) of one collision, `3 nverts` long.
fn local_derivatives(
    c: &Collision,
    xs: &[f64],
    b: &Barrier,
    dmin: f64,
    g: &mut [f64],
    h: &mut [f64],
) {
    macro_rules! go {
        ($n:expr) => {{
            let e = local::<$n>(c, xs, b, dmin);
            g[..$n].copy_from_slice(&e.g);
            for i in 0..$n {
                h[i * $n..(i + 1) * $n].copy_from_slice(&e.h[i]);
            }
        }};
    }
    match c.nverts() {
        2 => go!(6),
        3 => go!(9),
        _ => go!(12),
    }
}

/// The energy: a sum over the collisions.
pub fn energy(set: &Collisions, x: &[f64], b: &Barrier) -> f64 {
    let (y, scale) = b.args(set.dmin);
    let mut xs = [0.0; 12];
    let mut total = 0.0;
    for c in &set.items {
        let n = gather(c, x, &mut xs);
        let d2 = stencil_distance2(c.kind, c.dtype, &xs[..3 * n]);
        let mut e = clamped_log(d2 - set.dmin * set.dmin, y).0;
        if c.kind == 2 {
            let q = |k: usize| [xs[3 * k], xs[3 * k + 1], xs[3 * k + 2]];
            let cr = cross2(q(0), q(1), q(2), q(3));
            e *= mollifier(cr, c.eps_x).0;
        }
        total += scale * c.weight * e;
    }
    total
}

fn cross2(a0: [f64; 3], a1: [f64; 3], b0: [f64; 3], b1: [f64; 3]) -> f64 {
    let u = [a1[0] - a0[0], a1[1] - a0[1], a1[2] - a0[2]];
    let v = [b1[0] - b0[0], b1[1] - b0[1], b1[2] - b0[2]];
    let c = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    c[0] * c[0] + c[1] * c[1] + c[2] * c[2]
}

/// The gradient, `3 #V` long.
pub fn gradient(set: &Collisions, x: &[f64], b: &Barrier) -> Vec<f64> {
    let mut out = vec![0.0; x.len()];
    let mut xs = [0.0; 12];
    let (mut g, mut h) = ([0.0; 12], [0.0; 144]);
    for c in &set.items {
        let n = gather(c, x, &mut xs);
        local_derivatives(c, &xs[..3 * n], b, set.dmin, &mut g, &mut h);
        for (k, &v) in c.verts[..n].iter().enumerate() {
            for j in 0..3 {
                out[3 * v as usize + j] += g[3 * k + j];
            }
        }
    }
    out
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

/// The Hessian, each collision's block projected by `psd` before it is summed.
pub fn hessian(set: &Collisions, x: &[f64], b: &Barrier, psd: Psd) -> Csr {
    let mut asm = Assembler::new(x.len());
    let mut xs = [0.0; 12];
    let (mut g, mut h) = ([0.0; 12], [0.0; 144]);
    let mut dofs = [0usize; 12];
    for c in &set.items {
        let n = gather(c, x, &mut xs);
        let m = 3 * n;
        local_derivatives(c, &xs[..m], b, set.dmin, &mut g, &mut h);
        project(&mut h[..m * m], m, psd);
        for (k, &v) in c.verts[..n].iter().enumerate() {
            for j in 0..3 {
                dofs[3 * k + j] = 3 * v as usize + j;
            }
        }
        asm.add(&dofs[..m], &h[..m * m]);
    }
    asm.finish()
}

/// The smallest squared distance over the collisions (infinite for none), as ipctk's.
pub fn minimum_distance(set: &Collisions, x: &[f64]) -> f64 {
    let mut xs = [0.0; 12];
    (set.items.iter())
        .map(|c| {
            let n = gather(c, x, &mut xs);
            stencil_distance2(c.kind, c.dtype, &xs[..3 * n])
        })
        .fold(f64::INFINITY, f64::min)
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
