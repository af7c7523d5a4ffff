//! `airbag`: a flat sewn bag, Z-folded in three layers, inflating and unfolding into a wheel.
//!
//! Mesh: two rectangular sheets (3 x 1) sharing their rim vertices (sewn), about 83% of the
//! 9,076 x scale triangles, and a torus (a tyre, axis across the bag) for the rest.
//!
//! Motion (soft bag, static wheel): the bag's mid-surface follows a planar curve whose
//! curvature turns it by pi at a third and by -pi at two thirds of its length (a Z-fold with
//! fold radius `r`); the sheets sit at `+-h` along its normal, `h = H(t) p(u, v)` with a
//! profile `p` vanishing at the seam, and `H` growing from `0.2 r` to `2.2 r` (inflation), so
//! the layers of the fold press together; `h` stays below `0.7 r` inside the folds. The
//! second fold opens (its angle shrinks to 55% of pi), swinging the top layer up into the
//! wheel, which stands where the layer's free end arrives at story time 0.8. Touching vertices
//! stop; the run starts halfway to the first contact.

use std::f64::consts::PI;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::driver::{preroll, run as run_world, Script, Sink};
use super::shapes::{torus, Part};
use super::world::{Motion, World};
use super::{GenSummary, PaperScene};
use glam::DVec3;
use topoccd::Ccd;

/// Length and width of the bag.
const LENGTH: f64 = 3.0;
const WIDTH: f64 = 1.0;
/// Cells of one sheet at scale 1 (two sheets: 7,500 triangles).
const SHEET_CELLS: f64 = 1875.0;
/// Torus segments at scale 1 (1,536 triangles).
const TORUS: (f64, f64) = (48.0, 16.0);
/// Story time covered by the run (after the pre-roll).
const SPAN: f64 = 0.6;
/// Story time at which the free end reaches the wheel.
const HIT: f64 = 0.8;
/// Samples of the mid-surface curve.
const SAMPLES: usize = 2048;

/// Grid and torus resolution at `scale`.
fn resolution(scale: f64) -> (usize, usize, usize, usize) {
    let cells = SHEET_CELLS * scale;
    let nu = ((3.0 * cells).sqrt().round() as usize).max(6) + 1;
    let nv = ((cells / 3.0).sqrt().round() as usize).max(2) + 1;
    let s = scale.sqrt();
    let tu = ((TORUS.0 * s).round() as usize).max(8);
    let tv = ((TORUS.1 * s).round() as usize).max(4);
    (nu, nv, tu, tv)
}

/// First-frame triangle count at `scale`.
pub(super) fn triangles(scale: f64) -> usize {
    let (nu, nv, tu, tv) = resolution(scale);
    4 * (nu - 1) * (nv - 1) + 2 * tu * tv
}

/// The folding and inflation of the bag.
struct Bag {
    /// Per bag vertex: `(u, v, side)`, side `+1` top sheet, `-1` bottom, `0` seam.
    params: Vec<(f64, f64, f64)>,
    /// Half-length of each fold zone along the bag and the fold radius.
    fold_half: f64,
    radius: f64,
    /// Fold positions along the bag.
    folds: [f64; 2],
    /// Random phase of the inflation profile.
    wobble: f64,
    t0: f64,
    dt: f64,
}

impl Bag {
    /// The turn angle of fold `f` at story time `t`.
    fn fold_angle(&self, f: usize, t: f64) -> f64 {
        if f == 0 {
            PI
        } else {
            -PI * (1.0 - 0.45 * t.clamp(0.0, 1.2))
        }
    }

    /// Tangent angle of the mid-surface at arc length `u`.
    fn angle(&self, u: f64, t: f64) -> f64 {
        let a = self.fold_half;
        (0..2)
            .map(|f| {
                let s = ((u - (self.folds[f] - a)) / (2.0 * a)).clamp(0.0, 1.0);
                self.fold_angle(f, t) * s * s * (3.0 - 2.0 * s)
            })
            .sum()
    }

    /// The mid-surface curve at time `t`: `SAMPLES + 1` points and angles, `u` evenly spaced.
    fn curve(&self, t: f64) -> Vec<(f64, f64, f64)> {
        let du = LENGTH / SAMPLES as f64;
        let mut out = Vec::with_capacity(SAMPLES + 1);
        let (mut x, mut z) = (0.0, 0.0);
        let mut prev = self.angle(0.0, t);
        out.push((x, z, prev));
        for i in 1..=SAMPLES {
            let alpha = self.angle(i as f64 * du, t);
            let mid = 0.5 * (prev + alpha);
            x += du * mid.cos();
            z += du * mid.sin();
            out.push((x, z, alpha));
            prev = alpha;
        }
        out
    }

    /// Half-thickness of the bag at `(u, v)` and time `t`.
    fn half_thickness(&self, u: f64, v: f64, t: f64) -> f64 {
        let inflation = self.radius * (0.2 + 2.0 * t.clamp(0.0, 1.2));
        let pu = (PI * u / LENGTH).sin().max(0.0).sqrt();
        let pv = (PI * v / WIDTH).sin().max(0.0).sqrt();
        let ripple = 1.0 + 0.1 * (2.0 * PI * (u / LENGTH * 3.0 + v) + self.wobble).sin();
        let h = inflation * pu * pv * ripple;
        // Inside a fold zone the inner sheet must keep a positive radius.
        let fold = self
            .folds
            .iter()
            .map(|&f| (1.0 - ((u - f) / (1.5 * self.fold_half)).abs()).clamp(0.0, 1.0))
            .fold(0.0, f64::max);
        let capped = h.min(0.7 * self.radius);
        h + (capped - h) * fold.min(1.0)
    }

    /// Positions of the bag's vertices at time `t`.
    fn positions(&self, t: f64) -> Vec<DVec3> {
        let curve = self.curve(t);
        self.params
            .iter()
            .map(|&(u, v, side)| {
                let s = (u / LENGTH * SAMPLES as f64).clamp(0.0, SAMPLES as f64);
                let i = (s.floor() as usize).min(SAMPLES - 1);
                let f = s - i as f64;
                let (x0, z0, a0) = curve[i];
                let (x1, z1, a1) = curve[i + 1];
                let (x, z, a) = (x0 + (x1 - x0) * f, z0 + (z1 - z0) * f, a0 + (a1 - a0) * f);
                let h = side * self.half_thickness(u, v, t);
                DVec3::new(x - h * a.sin(), v, z + h * a.cos())
            })
            .collect()
    }
}

impl Script for Bag {
    fn before_step(&mut self, _k: usize, _world: &mut World, _parents: &mut Vec<(u32, u32)>) {}

    fn soft_displacement(&mut self, k: usize, _world: &World, out: &mut [DVec3]) {
        let (ta, tb) = (
            self.t0 + k as f64 * self.dt,
            self.t0 + (k + 1) as f64 * self.dt,
        );
        let (a, b) = (self.positions(ta), self.positions(tb));
        for ((o, pa), pb) in out.iter_mut().zip(&a).zip(&b) {
            *o = *pb - *pa;
        }
    }
}

/// Builds and runs the scene.
pub(super) fn run<E>(
    scale: f64,
    frames: usize,
    seed: u64,
    sink: &mut Sink<'_, E>,
) -> Result<GenSummary, E> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (nu, nv, tu, tv) = resolution(scale);
    let du = LENGTH / (nu - 1) as f64;
    let fold_half = (0.06f64).max(1.5 * du) * rng.random_range(0.9..1.1);
    let steps = frames - 1;
    let mut bag = Bag {
        params: Vec::new(),
        fold_half,
        radius: 2.0 * fold_half / PI,
        folds: [LENGTH / 3.0, 2.0 * LENGTH / 3.0],
        wobble: rng.random_range(0.0..2.0 * PI),
        t0: 0.0,
        dt: SPAN / steps as f64,
    };
    // Two sheets sharing the seam: top sheet ids first, then the bottom's interior.
    let mut sheets = Part::default();
    let mut bottom_id = vec![0u32; nu * nv];
    let seam = |i: usize, j: usize| i == 0 || j == 0 || i == nu - 1 || j == nv - 1;
    for i in 0..nu {
        for j in 0..nv {
            let (u, v) = (i as f64 * du, j as f64 * WIDTH / (nv - 1) as f64);
            bag.params.push((u, v, if seam(i, j) { 0.0 } else { 1.0 }));
            bottom_id[i * nv + j] = (i * nv + j) as u32;
        }
    }
    for i in 0..nu {
        for j in 0..nv {
            if !seam(i, j) {
                let (u, v, _) = bag.params[i * nv + j];
                bottom_id[i * nv + j] = bag.params.len() as u32;
                bag.params.push((u, v, -1.0));
            }
        }
    }
    crate::grid_triangles(nu, nv, 0, &mut sheets.triangles);
    let top_count = sheets.triangles.len();
    for k in 0..top_count {
        let [a, b, c] = sheets.triangles[k].map(|i| bottom_id[i as usize]);
        sheets.triangles.push([a, c, b]);
    }
    sheets.positions = bag.positions(0.0);
    // The wheel: where the free end heads at story time HIT.
    let end = |t: f64| {
        let c = bag.curve(t);
        let (x, z, _) = c[SAMPLES];
        DVec3::new(x, WIDTH / 2.0, z)
    };
    let heading = (end(HIT + 0.01) - end(HIT - 0.01)).normalize_or(DVec3::Z);
    let (major, minor) = (0.5, 0.18);
    let wheel = torus(
        end(HIT) + heading * (major + minor),
        DVec3::Y,
        major,
        minor,
        tu,
        tv,
    );
    let mut world = World::default();
    world.add_part(&sheets, Motion::Soft, false);
    world.add_part(&wheel, Motion::Static, false);
    let bag_vertices = bag.params.len();
    let mut ccd = Ccd::new();
    let start = preroll(
        &mut ccd,
        &world.mesh.triangles,
        |t| {
            let mut x = bag.positions(t);
            x.extend_from_slice(&wheel.positions);
            x
        },
        bag.dt,
        (2.0 / bag.dt).ceil() as usize,
    );
    if let Some((t0, x)) = start {
        bag.t0 = t0;
        world.mesh.positions = x.iter().map(DVec3::to_array).collect();
    }
    debug_assert_eq!(
        world.mesh.positions.len(),
        bag_vertices + wheel.positions.len()
    );
    run_world(PaperScene::Airbag, &mut world, &mut bag, frames, sink)
}
