//! Sheet scenes: crumpled, folded, torn into strips.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{assemble, grid_triangles};
use glam::DVec3;
use topoccd::Step;

/// A smooth random scalar field on the unit square: a sum of a few plane waves with
/// frequencies up to `max_freq` (cycles per unit), normalised to amplitude about 1.
struct Field {
    waves: Vec<(f64, f64, f64, f64)>,
}

impl Field {
    fn new(rng: &mut ChaCha8Rng, max_freq: f64) -> Self {
        let waves = (0..4)
            .map(|_| {
                let fx = rng.random_range(-max_freq..=max_freq);
                let fy = rng.random_range(-max_freq..=max_freq);
                let phase = rng.random_range(0.0..std::f64::consts::TAU);
                let amp = rng.random_range(0.5..1.0) / 2.0;
                (fx, fy, phase, amp)
            })
            .collect();
        Self { waves }
    }

    fn at(&self, u: f64, v: f64) -> f64 {
        let tau = std::f64::consts::TAU;
        self.waves
            .iter()
            .map(|&(fx, fy, ph, a)| a * (tau * (fx * u + fy * v) + ph).sin())
            .sum()
    }
}

/// Grid coordinate `i` of `n` in `[0, 1]`.
fn coord(i: usize, n: usize) -> f64 {
    i as f64 / (n - 1) as f64
}

/// A square sheet of `n * n` vertices (`n >= 2`; `2 (n-1)^2` triangles) on the unit square,
/// gently rippled at t=0; during the step it is squeezed to 40% of its width while a smooth
/// random displacement (amplitude about 0.15 in the plane, 0.4 out of it) folds it onto itself
/// like an accordion, so distant parts of the sheet cross each other.
///
/// ```
/// let step = topoccd_scenes::crumpled_sheet(10, 3);
/// assert_eq!(step.triangles().len(), 2 * 9 * 9);
/// ```
pub fn crumpled_sheet(n: usize, seed: u64) -> Step<'static> {
    let n = n.max(2);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let ripple = Field::new(&mut rng, 2.0);
    let [dx, dy, dz] = [0; 3].map(|_| Field::new(&mut rng, 2.5));
    let (mut x0, mut x1) = (Vec::with_capacity(n * n), Vec::with_capacity(n * n));
    for i in 0..n {
        for j in 0..n {
            let (u, v) = (coord(i, n), coord(j, n));
            x0.push(DVec3::new(u, v, 0.03 * ripple.at(u, v)));
            x1.push(DVec3::new(
                0.5 + 0.4 * (u - 0.5) + 0.15 * dx.at(u, v),
                v + 0.1 * dy.at(u, v),
                0.4 * dz.at(u, v),
            ));
        }
    }
    let mut tris = Vec::with_capacity(2 * (n - 1) * (n - 1));
    grid_triangles(n, n, 0, &mut tris);
    assemble(x0, x1, tris)
}

/// A square sheet of `n * n` vertices (`n >= 3`) whose right half (`x > 0.5`) turns about the
/// fold line `x = 0.5`: at t=0 it stands 20° to 40° above the left half, at t=1 it has turned
/// 3° to 8° past it, so the flap sweeps through the left half. Both halves carry small random
/// bumps (amplitude 0.01), so nothing is exactly coplanar.
///
/// ```
/// let step = topoccd_scenes::folded_sheet(9, 2);
/// assert_eq!(step.vertex_count(), 81);
/// ```
pub fn folded_sheet(n: usize, seed: u64) -> Step<'static> {
    let n = n.max(3);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let bumps0 = Field::new(&mut rng, 3.0);
    let bumps1 = Field::new(&mut rng, 3.0);
    let deg = std::f64::consts::PI / 180.0;
    let a0 = (180.0 - rng.random_range(20.0..40.0)) * deg;
    let a1 = (180.0 + rng.random_range(3.0..8.0)) * deg;
    let place = |u: f64, v: f64, angle: f64, bump: f64| {
        if u <= 0.5 {
            DVec3::new(u, v, bump)
        } else {
            // Distance from the fold line, then turned by `angle` about it; the bump acts
            // along the flap's normal.
            let r = u - 0.5;
            let (s, c) = angle.sin_cos();
            DVec3::new(0.5 + r * c - bump * s, v, r * s + bump * c)
        }
    };
    let (mut x0, mut x1) = (Vec::with_capacity(n * n), Vec::with_capacity(n * n));
    for i in 0..n {
        for j in 0..n {
            let (u, v) = (coord(i, n), coord(j, n));
            x0.push(place(u, v, a0, 0.01 * bumps0.at(u, v)));
            x1.push(place(u, v, a1, 0.01 * bumps1.at(u, v)));
        }
    }
    let mut tris = Vec::with_capacity(2 * (n - 1) * (n - 1));
    grid_triangles(n, n, 0, &mut tris);
    assemble(x0, x1, tris)
}

/// A square sheet of about `n * n` vertices (`n >= 4`) torn along lines `x = const` into
/// strips about 4 cells wide: the vertices on a cut are duplicated, so the strips share none
/// and touch along the cuts at t=0. During the step alternate strips slide left and right by
/// about 60% of a strip's width while waving up and down in opposite phase, so neighbouring
/// strips pass across and through each other.
///
/// ```
/// let step = topoccd_scenes::torn_sheet(13, 5);
/// assert_eq!(step.triangles().len(), 2 * 12 * 12);
/// assert!(step.vertex_count() > 13 * 13); // duplicated along the cuts
/// ```
pub fn torn_sheet(n: usize, seed: u64) -> Step<'static> {
    let n = n.max(4);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let cells = n - 1;
    let strip_cells = 4.min(cells / 2).max(1);
    let wave = Field::new(&mut rng, 1.5);
    let (mut x0, mut x1, mut tris) = (Vec::new(), Vec::new(), Vec::new());
    let mut first = 0;
    let mut strip = 0;
    while first < cells {
        let last = (first + strip_cells).min(cells);
        let cols = last - first + 1;
        let offset = x0.len() as u32;
        let width = (last - first) as f64 / cells as f64;
        let side = if strip % 2 == 0 { 1.0 } else { -1.0 };
        let slide = side * width * rng.random_range(0.5..0.7);
        let lift = rng.random_range(0.05..0.1);
        for i in first..=last {
            for j in 0..n {
                let (u, v) = (coord(i, n), coord(j, n));
                x0.push(DVec3::new(u, v, 0.0));
                let dz = side * lift * (1.0 + wave.at(u, v));
                x1.push(DVec3::new(u + slide, v + 0.02 * wave.at(v, u), dz));
            }
        }
        grid_triangles(cols, n, offset, &mut tris);
        first = last;
        strip += 1;
    }
    assemble(x0, x1, tris)
}
