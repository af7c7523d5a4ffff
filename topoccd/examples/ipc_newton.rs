//! A cloth falls onto a fixed sphere, with implicit Euler steps solved by Newton's method
//! on topoccd's contact potential: inertia and gravity, mass-spring cloth, the barrier
//! ([`BarrierPotential`] over [`NormalCollisions`], PSD-projected Hessian), lagged friction
//! ([`topoccd::ipc::friction`]), a sparse Cholesky solve (nalgebra-sparse), the line search from the
//! collision-free step size, and the adaptive barrier stiffness.
//!
//! `cargo run --release -p topoccd --example ipc_newton [-- STEPS] [sphere|box]` prints, per step, the
//! Newton iterations, the incremental potential at the solution and the minimum distance,
//! and exits non-zero if a gap closes or Newton does not converge. Its tests
//! (`cargo test --release -p topoccd --example ipc_newton`) check the assembled gradient and
//! Hessian against finite differences, the free fall against implicit Euler's closed form,
//! and Coulomb's law on a cloth sliding over a box.
//!
//! Each step minimises, over the cloth's positions `x` (the obstacle is fixed),
//!
//! ```text
//! E(x) = m/(2 h^2) |x - x_tilde|^2 + springs(x) + kappa B(x) + h D((x - x_t) / h)
//! ```
//!
//! with `x_tilde = x_t + h v + h^2 g`, `B` the barrier over the collisions at `x` and `D`
//! the friction of the velocities over the tangential collisions lagged at the step's start
//! `x_t` (their normal forces, tangent bases and closest points). The gradient of `h D` in
//! `x` is `grad D`, its Hessian `hess D / h`.

use std::error::Error;
use std::fmt;

use nalgebra::DMatrix;
use nalgebra_sparse::factorization::CscCholesky;
use nalgebra_sparse::{CooMatrix, CscMatrix};
use topoccd::ipc::friction::{FrictionCoefficients, FrictionPotential, TangentialCollisions};
use topoccd::ipc::{
    initial_barrier_stiffness, update_barrier_stiffness, Barrier, BarrierPotential,
    CollisionOptions, NormalCollisions, PsdProjection,
};
use topoccd::line_search::LineSearchOptions;
use topoccd::{Ccd, Configuration, Step};

/// A sparse matrix as (row, column, value) triplets; repeats add up.
type Triplets = Vec<(usize, usize, f64)>;

/// The fixed obstacle under the cloth.
#[derive(Clone, Copy, Debug)]
enum Obstacle {
    /// An icosphere of this radius, centred at the origin (its top at `z = radius`).
    Sphere { radius: f64, subdivisions: u32 },
    /// A box `[-half, half]^2 x [-depth, 0]` moved by `(dx, dy)` (its top at `z = 0`).
    Box {
        half: f64,
        depth: f64,
        dx: f64,
        dy: f64,
    },
}

/// The scene and the solver's parameters.
#[derive(Clone, Debug)]
struct Params {
    obstacle: Obstacle,
    /// Vertices per side of the square cloth.
    cloth_n: usize,
    /// Its side length (m).
    cloth_size: f64,
    /// The cloth's initial height above the obstacle's top (m).
    drop: f64,
    /// The cloth's initial velocity (m/s).
    velocity: [f64; 3],
    /// Time step (s), cloth mass (kg), spring stiffness (N/m).
    h: f64,
    mass: f64,
    k: f64,
    /// Barrier activation distance (m), friction coefficient, friction threshold (m/s).
    dhat: f64,
    mu: f64,
    eps_v: f64,
    gravity: f64,
    steps: usize,
    /// Newton stops when `max |p| / h` (a speed) falls below this times the bounding box's
    /// diagonal per second (the IPC paper's `eps_d`, 1e-2).
    newton_tol: f64,
    max_newton: usize,
    /// Print one line per step.
    verbose: bool,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            obstacle: Obstacle::Sphere {
                radius: 0.25,
                subdivisions: 2,
            },
            cloth_n: 16,
            cloth_size: 0.8,
            drop: 0.01,
            velocity: [0.0; 3],
            h: 0.01,
            mass: 0.1,
            k: 100.0,
            dhat: 2e-3,
            mu: 0.5,
            eps_v: 1e-3,
            gravity: 9.81,
            steps: 25,
            newton_tol: 1e-2,
            max_newton: 100,
            verbose: true,
        }
    }
}

/// Why a run stopped.
#[derive(Debug)]
enum SimError {
    /// Newton did not reach the tolerance within `max_newton` iterations.
    NoConvergence { step: usize, residual: f64 },
    /// The line search could not decrease the energy along a descent direction.
    LineSearch { step: usize, iteration: usize },
    /// The minimum distance reached zero (or the positions stopped being finite).
    GapClosed { step: usize, distance: f64 },
    /// The sparse Cholesky factorisation failed (the Hessian is not positive definite).
    Factorisation(String),
    /// An error of topoccd.
    Topoccd(Box<dyn Error>),
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoConvergence { step, residual } => {
                write!(
                    f,
                    "step {step}: Newton did not converge (|p|/h = {residual:e})"
                )
            }
            Self::LineSearch { step, iteration } => {
                write!(
                    f,
                    "step {step}, iteration {iteration}: the line search failed"
                )
            }
            Self::GapClosed { step, distance } => {
                write!(
                    f,
                    "step {step}: a gap closed (minimum distance {distance:e})"
                )
            }
            Self::Factorisation(e) => write!(f, "the sparse Cholesky failed: {e}"),
            Self::Topoccd(e) => write!(f, "{e}"),
        }
    }
}

impl Error for SimError {}

fn topo<E: Error + 'static>(e: E) -> SimError {
    SimError::Topoccd(Box::new(e))
}

/// The mesh: the cloth's vertices first (`0..nc`), then the obstacle's.
struct Scene {
    x0: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    /// The cloth's springs and their rest lengths.
    springs: Vec<([usize; 2], f64)>,
    /// Number of cloth vertices: their `3 nc` coordinates are the unknowns.
    nc: usize,
}

fn icosphere(radius: f64, subdivisions: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<[f64; 3]> = vec![
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, v: &mut Vec<[f64; 3]>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (v[a as usize], v[b as usize]);
                v.push([0, 1, 2].map(|i| 0.5 * (p[i] + q[i])));
                (v.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(4 * f.len());
        for &[a, b, c] in &f {
            let (ab, bc, ca) = (
                midpoint(a, b, &mut v),
                midpoint(b, c, &mut v),
                midpoint(c, a, &mut v),
            );
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    for p in &mut v {
        let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        *p = p.map(|c| radius * c / l);
    }
    (v, f)
}

fn block(half: f64, depth: f64, dx: f64, dy: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let v = (0..8)
        .map(|i| {
            [
                dx + if i & 1 == 0 { -half } else { half },
                dy + if i & 2 == 0 { -half } else { half },
                if i & 4 == 0 { -depth } else { 0.0 },
            ]
        })
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let f = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    (v, f)
}

impl Scene {
    fn new(p: &Params) -> Self {
        let (obstacle_x, obstacle_f, top) = match p.obstacle {
            Obstacle::Sphere {
                radius,
                subdivisions,
            } => {
                let (v, f) = icosphere(radius, subdivisions);
                (v, f, radius)
            }
            Obstacle::Box {
                half,
                depth,
                dx,
                dy,
            } => {
                let (v, f) = block(half, depth, dx, dy);
                (v, f, 0.0)
            }
        };
        let n = p.cloth_n;
        let nc = n * n;
        let dx = p.cloth_size / (n - 1) as f64;
        // The cloth, slightly rotated about z so that no cloth edge is parallel to an
        // obstacle's edge.
        let (s, c) = 0.1f64.sin_cos();
        let mut x0 = Vec::with_capacity(nc + obstacle_x.len());
        for j in 0..n {
            for i in 0..n {
                let (u, v) = (
                    i as f64 * dx - 0.5 * p.cloth_size,
                    j as f64 * dx - 0.5 * p.cloth_size,
                );
                x0.push([c * u - s * v, s * u + c * v, top + p.drop]);
            }
        }
        x0.extend(obstacle_x);
        let id = |i: usize, j: usize| (j * n + i) as u32;
        let mut triangles = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                triangles.extend([[a, b, c], [a, c, d]]);
            }
        }
        triangles.extend(obstacle_f.iter().map(|t| t.map(|v| v + nc as u32)));
        // Springs on the cloth's edges and, against shearing, nothing more: a mass-spring
        // cloth keeps its area through the diagonals of the triangulation.
        let mut springs: Vec<[usize; 2]> = triangles[..2 * (n - 1) * (n - 1)]
            .iter()
            .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
            .map(|[a, b]| [a.min(b) as usize, a.max(b) as usize])
            .collect();
        springs.sort_unstable();
        springs.dedup();
        let springs = springs
            .into_iter()
            .map(|[a, b]| ([a, b], dist(x0[a], x0[b])))
            .collect();
        Scene {
            x0,
            triangles,
            springs,
            nc,
        }
    }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The smooth part of the energy (inertia, gravity through `x_tilde`, springs), its
/// gradient over all `3 #V` coordinates and its Hessian's triplets (springs projected to
/// PSD by clamping their stretch factor at zero).
struct Elastic<'a> {
    scene: &'a Scene,
    m: f64,
    h: f64,
    k: f64,
    /// Clamp the springs' Hessians to PSD (off: the exact Hessian, for the tests).
    project: bool,
}

impl Elastic<'_> {
    fn energy(&self, x: &[[f64; 3]], x_tilde: &[f64]) -> f64 {
        let inertia: f64 = (0..3 * self.scene.nc)
            .map(|i| (x[i / 3][i % 3] - x_tilde[i]).powi(2))
            .sum();
        let springs: f64 = self
            .scene
            .springs
            .iter()
            .map(|&([a, b], l0)| (dist(x[a], x[b]) - l0).powi(2))
            .sum();
        0.5 * self.m / (self.h * self.h) * inertia + 0.5 * self.k * springs
    }

    fn gradient(&self, x: &[[f64; 3]], x_tilde: &[f64]) -> Vec<f64> {
        let mut g = vec![0.0; 3 * x.len()];
        for (i, gi) in g.iter_mut().enumerate().take(3 * self.scene.nc) {
            *gi = self.m / (self.h * self.h) * (x[i / 3][i % 3] - x_tilde[i]);
        }
        for &([a, b], l0) in &self.scene.springs {
            let l = dist(x[a], x[b]);
            for c in 0..3 {
                let f = self.k * (l - l0) / l * (x[a][c] - x[b][c]);
                g[3 * a + c] += f;
                g[3 * b + c] -= f;
            }
        }
        g
    }

    fn hessian(&self, x: &[[f64; 3]], out: &mut Vec<(usize, usize, f64)>) {
        let diag = self.m / (self.h * self.h);
        out.extend((0..3 * self.scene.nc).map(|i| (i, i, diag)));
        for &([a, b], l0) in &self.scene.springs {
            let l = dist(x[a], x[b]);
            let u = [0, 1, 2].map(|c| (x[a][c] - x[b][c]) / l);
            let r = if self.project {
                (1.0 - l0 / l).max(0.0)
            } else {
                1.0 - l0 / l
            };
            for i in 0..3 {
                for j in 0..3 {
                    let kij = self.k * (if i == j { r } else { 0.0 } + (1.0 - r) * u[i] * u[j]);
                    out.extend([
                        (3 * a + i, 3 * a + j, kij),
                        (3 * b + i, 3 * b + j, kij),
                        (3 * a + i, 3 * b + j, -kij),
                        (3 * b + i, 3 * a + j, -kij),
                    ]);
                }
            }
        }
    }
}

/// One implicit Euler step's incremental potential, with what it needs at hand.
struct Potential<'a> {
    elastic: Elastic<'a>,
    scene: &'a Scene,
    options: CollisionOptions,
    barrier: BarrierPotential,
    friction: FrictionPotential,
    x_t: Vec<[f64; 3]>,
    x_tilde: Vec<f64>,
    tangential: TangentialCollisions,
    h: f64,
}

impl<'a> Potential<'a> {
    /// The potential of the step from `x_t` at velocity `v`, with stiffness `kappa`: the
    /// tangential collisions are built from `c_t`, the collisions at `x_t`.
    #[allow(clippy::too_many_arguments)]
    fn new(
        p: &Params,
        scene: &'a Scene,
        x_t: &[[f64; 3]],
        v: &[[f64; 3]],
        kappa: f64,
        c_t: &NormalCollisions,
    ) -> Result<Self, SimError> {
        let nc = scene.nc;
        let x_tilde = (0..3 * nc)
            .map(|i| {
                let g = if i % 3 == 2 { -p.gravity } else { 0.0 };
                x_t[i / 3][i % 3] + p.h * v[i / 3][i % 3] + p.h * p.h * g
            })
            .collect();
        let barrier = BarrierPotential::new(p.dhat, kappa);
        // Friction, lagged: the normal forces and bases of the collisions at x_t.
        let tangential =
            TangentialCollisions::build(x_t, c_t, &barrier, FrictionCoefficients::uniform(p.mu))
                .map_err(topo)?;
        Ok(Self {
            elastic: Elastic {
                scene,
                m: p.mass / nc as f64,
                h: p.h,
                k: p.k,
                project: true,
            },
            scene,
            options: CollisionOptions {
                dhat: p.dhat,
                ..Default::default()
            },
            barrier,
            friction: FrictionPotential::new(p.eps_v).map_err(topo)?,
            x_t: x_t.to_vec(),
            x_tilde,
            tangential,
            h: p.h,
        })
    }
}

impl Potential<'_> {
    fn collisions(&self, ccd: &mut Ccd, x: &[[f64; 3]]) -> Result<NormalCollisions, SimError> {
        let config = Configuration::new(x, &self.scene.triangles, &[]).map_err(topo)?;
        NormalCollisions::build(ccd, &config, &self.scene.x0, &self.options).map_err(topo)
    }

    fn velocities(&self, x: &[[f64; 3]]) -> Vec<[f64; 3]> {
        x.iter()
            .zip(&self.x_t)
            .map(|(a, b)| [0, 1, 2].map(|c| (a[c] - b[c]) / self.h))
            .collect()
    }

    /// `E(x)`, and the collisions at `x` (`E` is `+inf` if the barrier is).
    fn energy(&self, ccd: &mut Ccd, x: &[[f64; 3]]) -> Result<(f64, NormalCollisions), SimError> {
        let c = self.collisions(ccd, x)?;
        let d = self
            .friction
            .energy(&self.tangential, &self.velocities(x))
            .map_err(topo)?;
        let e = self.elastic.energy(x, &self.x_tilde) + self.barrier.energy(&c, x) + self.h * d;
        Ok((e, c))
    }

    /// The gradient over all coordinates and the Hessian's triplets.
    fn derivatives(
        &self,
        c: &NormalCollisions,
        x: &[[f64; 3]],
    ) -> Result<(Vec<f64>, Triplets), SimError> {
        let v = self.velocities(x);
        let mut g = self.elastic.gradient(x, &self.x_tilde);
        let gb = self.barrier.gradient(c, x);
        let gd = self.friction.gradient(&self.tangential, &v).map_err(topo)?;
        for ((gi, b), d) in g.iter_mut().zip(&gb).zip(&gd) {
            *gi += b + d;
        }
        let mut t = Vec::new();
        self.elastic.hessian(x, &mut t);
        let project = if self.elastic.project {
            PsdProjection::Clamp
        } else {
            PsdProjection::None
        };
        t.extend(self.barrier.hessian(c, x, project).triplets());
        let hd = self
            .friction
            .hessian(&self.tangential, &v, project)
            .map_err(topo)?;
        t.extend(hd.triplets().map(|(i, j, w)| (i, j, w / self.h)));
        Ok((g, t))
    }
}

/// Solves `H p = -g` on the free coordinates `0..nf` (the cloth's) with a sparse Cholesky
/// factorisation (nalgebra-sparse's; faer's and sprs-ldl's read the same triplets).
fn newton_direction(
    nf: usize,
    g: &[f64],
    triplets: &[(usize, usize, f64)],
) -> Result<Vec<f64>, SimError> {
    let mut coo = CooMatrix::new(nf, nf);
    for &(i, j, v) in triplets {
        if i < nf && j < nf {
            coo.push(i, j, v); // repeated entries are summed
        }
    }
    let llt = CscCholesky::factor(&CscMatrix::from(&coo))
        .map_err(|e| SimError::Factorisation(e.to_string()))?;
    let p = llt.solve(&DMatrix::from_iterator(nf, 1, g[..nf].iter().map(|v| -v)));
    Ok(p.iter().copied().collect())
}

/// What one step did.
#[derive(Clone, Debug)]
struct StepLog {
    iterations: usize,
    energy: f64,
    /// The smallest distance between the mesh's primitives within `dhat` (`+inf`: none).
    min_distance: f64,
    collisions: usize,
    tangential: usize,
    kappa: f64,
}

/// The run's result: the positions after each step and the steps' logs.
struct Run {
    positions: Vec<Vec<[f64; 3]>>,
    logs: Vec<StepLog>,
}

fn bbox_diagonal(x: &[[f64; 3]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in x {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    dist(lo, hi)
}

fn simulate(p: &Params) -> Result<Run, SimError> {
    let scene = Scene::new(p);
    let nc = scene.nc;
    let nf = 3 * nc;
    let m = p.mass / nc as f64;
    let bbox = bbox_diagonal(&scene.x0);
    let options = CollisionOptions {
        dhat: p.dhat,
        ..Default::default()
    };
    let line_search_options = LineSearchOptions::default();
    // Kept between calls: their hierarchies are refitted, not rebuilt.
    let (mut ccd, mut line_search) = (Ccd::new(), Ccd::new());
    let mut x = scene.x0.clone();
    let mut v: Vec<[f64; 3]> = (0..x.len())
        .map(|i| if i < nc { p.velocity } else { [0.0; 3] })
        .collect();
    let mut kappa: Option<(f64, f64)> = None;
    let mut run = Run {
        positions: Vec::new(),
        logs: Vec::new(),
    };
    for step in 0..p.steps {
        let x_t = x.clone();
        let config = Configuration::new(&x_t, &scene.triangles, &[]).map_err(topo)?;
        let c_t = NormalCollisions::build(&mut ccd, &config, &scene.x0, &options).map_err(topo)?;
        let (mut k, k_max) = match kappa {
            Some(k) => k,
            None => {
                // ipctk's initial stiffness: the barrier's gradient balanced against the
                // rest of the energy's.
                let pot = Potential::new(p, &scene, &x_t, &v, 1.0, &c_t)?;
                let s = initial_barrier_stiffness(
                    bbox,
                    Barrier::ClampedLog,
                    p.dhat,
                    m,
                    &pot.elastic.gradient(&x_t, &pot.x_tilde),
                    &pot.barrier.gradient(&c_t, &x_t),
                    1e11,
                    0.0,
                );
                (s.stiffness, s.max_stiffness)
            }
        };
        let mut pot = Potential::new(p, &scene, &x_t, &v, k, &c_t)?;
        let mut prev_min_d = c_t.compute_minimum_distance(&x);
        let (mut e, mut c) = pot.energy(&mut ccd, &x)?;
        let mut iterations = 0;
        loop {
            let (g, t) = pot.derivatives(&c, &x)?;
            let dir = newton_direction(nf, &g, &t)?;
            let residual = dir.iter().fold(0.0f64, |a, d| a.max(d.abs())) / p.h;
            if residual < p.newton_tol * bbox {
                break;
            }
            if iterations == p.max_newton {
                return Err(SimError::NoConvergence { step, residual });
            }
            iterations += 1;
            let moved = |alpha: f64| {
                let mut y = x.clone();
                for (i, d) in dir.iter().enumerate() {
                    y[i / 3][i % 3] += alpha * d;
                }
                y
            };
            let full = moved(1.0);
            let s = Step::new(&x, &full, &scene.triangles).map_err(topo)?;
            let mut alpha = line_search
                .collision_free_stepsize(&s, &line_search_options)
                .map_err(topo)?
                .alpha;
            // Backtracking from the collision-free step size until the energy falls.
            let (e_new, c_new, y) = loop {
                let y = moved(alpha);
                let (e_new, c_new) = pot.energy(&mut ccd, &y)?;
                if e_new <= e {
                    break (e_new, c_new, y);
                }
                alpha *= 0.5;
                if alpha < 1e-12 {
                    return Err(SimError::LineSearch {
                        step,
                        iteration: iterations,
                    });
                }
            };
            (x, e, c) = (y, e_new, c_new);
            // ipctk's adaptive stiffness: doubled while the gaps keep shrinking below
            // 1e-9 of the bounding box's diagonal.
            let min_d = c.compute_minimum_distance(&x);
            let k_next = update_barrier_stiffness(prev_min_d, min_d, k_max, k, bbox, 1e-9, 0.0);
            prev_min_d = min_d;
            if k_next != k {
                k = k_next;
                pot.barrier = BarrierPotential::new(p.dhat, k);
                e = pot.energy(&mut ccd, &x)?.0;
            }
        }
        kappa = Some((k, k_max));
        let min_distance = c.minimum_distance(&x);
        if min_distance.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
            || x.iter().flatten().any(|c| !c.is_finite())
        {
            return Err(SimError::GapClosed {
                step,
                distance: min_distance,
            });
        }
        v = x
            .iter()
            .zip(&x_t)
            .map(|(a, b)| [0, 1, 2].map(|i| (a[i] - b[i]) / p.h))
            .collect();
        let log = StepLog {
            iterations,
            energy: e,
            min_distance,
            collisions: c.len(),
            tangential: pot.tangential.len(),
            kappa: k,
        };
        if p.verbose {
            println!(
                "step {step:3}: {:3} Newton iterations, energy {:+.6e}, min distance {:.3e}, \
                 {} collisions, {} tangential, kappa {:.3e}",
                log.iterations,
                log.energy,
                log.min_distance,
                log.collisions,
                log.tangential,
                log.kappa
            );
        }
        run.logs.push(log);
        run.positions.push(x.clone());
    }
    Ok(run)
}

fn main() {
    let mut p = Params::default();
    for arg in std::env::args().skip(1) {
        match (arg.as_str(), arg.parse()) {
            (_, Ok(steps)) => p.steps = steps,
            ("sphere", _) => {}
            // A wider box than the cloth, its top 1 cm under it, the cloth sliding along x.
            ("box", _) => {
                p.obstacle = Obstacle::Box {
                    half: 0.6,
                    depth: 0.2,
                    dx: 0.0,
                    dy: 0.0,
                };
                p.velocity = [0.5, 0.0, 0.0];
            }
            _ => {
                eprintln!("usage: ipc_newton [STEPS] [sphere|box]");
                std::process::exit(2);
            }
        }
    }
    match simulate(&p) {
        Ok(run) => {
            let total: usize = run.logs.iter().map(|l| l.iterations).sum();
            let min = run
                .logs
                .iter()
                .map(|l| l.min_distance)
                .fold(f64::INFINITY, f64::min);
            println!(
                "{} steps, {total} Newton iterations, smallest distance {min:.3e} (dhat {:e})",
                run.logs.len(),
                p.dhat
            );
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small cloth over a wide box, `drop` above it, moving at `velocity`, inside one of
    /// the top's two triangles (an edge or vertex of the top within `dhat` of the cloth
    /// would push it sideways: there the barrier's normals are not vertical).
    fn on_box(drop: f64, velocity: [f64; 3], mu: f64, steps: usize) -> Params {
        Params {
            obstacle: Obstacle::Box {
                half: 1.0,
                depth: 0.2,
                dx: 0.5,
                dy: -0.5,
            },
            cloth_n: 6,
            cloth_size: 0.3,
            drop,
            velocity,
            mu,
            steps,
            newton_tol: 1e-6,
            verbose: false,
            ..Params::default()
        }
    }

    /// The gradient against central differences of the energy, and the exact (unprojected)
    /// Hessian against central differences of the gradient, on a cloth sliding within
    /// `dhat` of a box: inertia, springs, barrier and friction together.
    #[test]
    fn derivatives_match_finite_differences() {
        let p = on_box(0.5e-3, [0.3, 0.1, 0.0], 0.5, 0);
        let scene = Scene::new(&p);
        let nc = scene.nc;
        let x_t = scene.x0.clone();
        let v: Vec<[f64; 3]> = (0..x_t.len())
            .map(|i| if i < nc { p.velocity } else { [0.0; 3] })
            .collect();
        let mut ccd = Ccd::new();
        let config = Configuration::new(&x_t, &scene.triangles, &[]).unwrap();
        let opts = CollisionOptions {
            dhat: p.dhat,
            ..Default::default()
        };
        let c_t = NormalCollisions::build(&mut ccd, &config, &scene.x0, &opts).unwrap();
        assert_eq!(c_t.fv.len(), nc, "every cloth vertex over the box's top");
        let mut pot = Potential::new(&p, &scene, &x_t, &v, 1e3, &c_t).unwrap();
        assert_eq!(pot.tangential.len(), nc);
        assert_eq!(c_t.len(), nc, "the cloth is away from the box top's edges");
        pot.elastic.project = false;
        // A state inside the step: moved along the velocity (sliding, |u| > eps_v for most
        // vertices), stretched a little, still within dhat, each vertex by its own amount.
        let x: Vec<[f64; 3]> = x_t
            .iter()
            .enumerate()
            .map(|(i, q)| {
                if i >= nc {
                    return *q;
                }
                let s = (i as f64 * 0.37).sin();
                [
                    1.05 * q[0] + p.h * p.velocity[0] * (1.0 + 0.3 * s),
                    q[1] + p.h * 1e-4 * s,
                    q[2] + 2e-4 * s,
                ]
            })
            .collect();
        let (_, c) = pot.energy(&mut ccd, &x).unwrap();
        let (g, t) = pot.derivatives(&c, &x).unwrap();
        let n = 3 * x.len();
        let mut hess = vec![0.0; n * n];
        for (i, j, w) in t {
            hess[i * n + j] += w;
        }
        let delta = 1e-7;
        let shifted = |i: usize, s: f64| {
            let mut y = x.clone();
            y[i / 3][i % 3] += s;
            y
        };
        let (mut worst_g, mut worst_h) = (0.0f64, 0.0f64);
        let gscale = g.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        let hscale = hess.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        for i in 0..3 * nc {
            let (yp, ym) = (shifted(i, delta), shifted(i, -delta));
            let (ep, cp) = pot.energy(&mut ccd, &yp).unwrap();
            let (em, cm) = pot.energy(&mut ccd, &ym).unwrap();
            worst_g = worst_g.max(((ep - em) / (2.0 * delta) - g[i]).abs() / gscale);
            let (gp, gm) = (
                pot.derivatives(&cp, &yp).unwrap().0,
                pot.derivatives(&cm, &ym).unwrap().0,
            );
            for j in 0..3 * nc {
                let fd = (gp[j] - gm[j]) / (2.0 * delta);
                worst_h = worst_h.max((fd - hess[j * n + i]).abs() / hscale);
            }
        }
        eprintln!("gradient vs FD {worst_g:.1e}, Hessian vs FD {worst_h:.1e}");
        assert!(
            worst_g < 1e-6,
            "gradient vs finite differences: {worst_g:e}"
        );
        assert!(worst_h < 1e-5, "Hessian vs finite differences: {worst_h:e}");
    }

    /// Far from the sphere, the cloth falls as one body: implicit Euler gives
    /// `z_n = z_0 - g h^2 n (n + 1) / 2`, each step one Newton iteration (the energy is
    /// quadratic along a rigid translation and the springs stay at rest).
    #[test]
    fn free_fall_is_implicit_euler() {
        let p = Params {
            drop: 0.1,
            steps: 6,
            newton_tol: 1e-6,
            verbose: false,
            ..Params::default()
        };
        let run = simulate(&p).unwrap();
        let x0 = Scene::new(&p).x0;
        let nc = p.cloth_n * p.cloth_n;
        for (n, (x, log)) in run.positions.iter().zip(&run.logs).enumerate() {
            let steps = (n + 1) as f64;
            let fall = p.gravity * p.h * p.h * steps * (steps + 1.0) / 2.0;
            for i in 0..nc {
                assert!(
                    (x[i][2] - (x0[i][2] - fall)).abs() < 1e-10,
                    "step {n}, vertex {i}"
                );
                assert!((x[i][0] - x0[i][0]).abs() < 1e-12);
            }
            assert_eq!(log.iterations, 1, "step {n}");
            assert_eq!(log.collisions, 0);
        }
    }

    /// A cloth sliding on a box: once landed, Coulomb's law takes `mu g h` off its speed
    /// each step; without friction the speed stays.
    #[test]
    fn sliding_on_a_box_follows_coulomb() {
        let (h, g, mu) = (0.01, 9.81, 0.5);
        let mean_vx = |run: &Run, n: usize| {
            let nc = 36;
            let (a, b) = (&run.positions[n], &run.positions[n - 1]);
            (0..nc).map(|i| (a[i][0] - b[i][0]) / h).sum::<f64>() / nc as f64
        };
        let run = simulate(&on_box(1e-3, [0.5, 0.0, 0.0], mu, 8)).unwrap();
        for n in 4..8 {
            let dv = mean_vx(&run, n - 1) - mean_vx(&run, n);
            assert!(
                (dv - mu * g * h).abs() < 0.03 * mu * g * h,
                "step {n}: the speed fell by {dv}, Coulomb says {}",
                mu * g * h
            );
        }
        let run = simulate(&on_box(1e-3, [0.5, 0.0, 0.0], 0.0, 8)).unwrap();
        for n in 4..8 {
            let dv = mean_vx(&run, n - 1) - mean_vx(&run, n);
            assert!(
                dv.abs() < 1e-4,
                "step {n}: without friction the speed fell by {dv}"
            );
        }
        assert!(run
            .logs
            .iter()
            .all(|l| l.min_distance > 0.0 && l.collisions > 0));
    }

    /// The example's own run, shortened: the cloth lands on the sphere and rests on it
    /// within `dhat`, Newton converges at every step and no gap closes.
    #[test]
    fn cloth_lands_on_the_sphere() {
        let p = Params {
            cloth_n: 11,
            steps: 12,
            verbose: false,
            ..Params::default()
        };
        let run = simulate(&p).unwrap();
        let last = run.logs.last().unwrap();
        assert!(last.collisions > 0 && last.tangential > 0);
        assert!(last.min_distance > 0.0 && last.min_distance < p.dhat);
        // The centre vertex has stopped falling.
        let c = 5 * 11 + 5;
        let (a, b) = (&run.positions[11], &run.positions[10]);
        assert!(((a[c][2] - b[c][2]) / p.h).abs() < 0.05);
    }
}
