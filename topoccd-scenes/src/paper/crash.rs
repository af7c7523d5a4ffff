//! `crash`: a thin-shell car-like body crushed against a wall, tearing.
//!
//! Mesh: one closed shell (a boxy superquadric, 4.4 x 1.8 x 1.5, lower over the front third
//! like a bonnet, with small dents), on a cube-sphere of about 1.1M x scale triangles, and a
//! flat wall (a grid) ahead of it. The shell is partitioned into panels of about 2,000
//! triangles (scaled).
//!
//! Motion: the shell is soft and drives at the wall, slowing from 0.12 to 0.03 per step;
//! within 0.9 of the wall its vertices also buckle sideways, a ripple along the car's length
//! growing as they approach, so the crumple zone folds onto itself. Vertices that touch the
//! wall or another part of the shell stop (see `response.rs`), so the front crushes flat and
//! its folds press together. Each step, up to a few panels holding stopped vertices tear off
//! and bounce back as rigid pieces with a random spin, hitting the wall and the shell. The
//! run starts halfway to the first contact with the wall.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::driver::{preroll, run as run_world, Script, Sink};
use super::fracture::partition;
use super::shapes::{cube_sphere, cube_sphere_resolution, grid, unit, Noise};
use super::world::{Motion, World};
use super::{GenSummary, PaperScene};
use glam::DVec3;
use topoccd::Ccd;

/// Paper triangle count.
const PAPER: f64 = 1_100_000.0;
/// Wall cells per side at scale 1.
const WALL: f64 = 30.0;
/// Half-length, half-width, half-height (cabin, bonnet) of the shell.
const SIZE: (f64, f64, f64, f64) = (2.2, 0.9, 0.75, 0.45);
/// The wall's plane, `x = WALL_X`.
const WALL_X: f64 = 2.5;
/// Initial speed, per step.
const SPEED: f64 = 0.12;
/// Depth of the crumple zone.
const CRUMPLE: f64 = 0.9;

/// Resolutions of the shell and the wall at `scale`.
fn resolution(scale: f64) -> (usize, usize) {
    let wall = ((WALL * scale.sqrt()).round() as usize).max(4);
    let shell = cube_sphere_resolution(PAPER * scale - (2 * wall * wall) as f64);
    (shell, wall)
}

/// First-frame triangle count at `scale`.
pub(super) fn triangles(scale: f64) -> usize {
    let (n, w) = resolution(scale);
    12 * n * n + 2 * w * w
}

/// The shell's surface point in direction `d` (unit).
fn shell_point(d: DVec3, dents: &Noise) -> DVec3 {
    let (a, b, c_cabin, c_bonnet) = SIZE;
    let front = ((d.x - 0.25) / 0.3).clamp(0.0, 1.0);
    let front = front * front * (3.0 - 2.0 * front);
    let c = if d.z > 0.0 {
        c_cabin + (c_bonnet - c_cabin) * front
    } else {
        c_cabin
    };
    let p = 4.0;
    let s = ((d.x / a).abs().powf(p) + (d.y / b).abs().powf(p) + (d.z / c).abs().powf(p))
        .powf(-1.0 / p);
    d * (s * (1.0 + 0.004 * dents.at(d * 3.0))) + DVec3::new(0.0, 0.0, c_cabin)
}

/// The crush and the tearing.
struct Crash {
    rng: ChaCha8Rng,
    steps: usize,
    /// Phase of the buckling ripple.
    phase: f64,
    /// Panels torn off at most per step.
    tear_max: usize,
}

impl Crash {
    /// Speed of the shell during step `k`.
    fn speed(&self, k: usize) -> f64 {
        SPEED * (1.0 - 0.75 * k as f64 / self.steps.max(1) as f64)
    }
}

impl Script for Crash {
    fn before_step(&mut self, _k: usize, world: &mut World, parents: &mut Vec<(u32, u32)>) {
        let previous = world.vertex_count();
        // Panels holding stopped vertices, in order.
        let candidates: Vec<usize> = (0..world.fragments.len())
            .filter(|&f| {
                !world.detached[f]
                    && world.fragments[f].iter().any(|&t| {
                        world.mesh.triangles[t as usize]
                            .iter()
                            .any(|&v| world.pinned[v as usize])
                    })
            })
            .collect();
        let mut torn = 0;
        for f in candidates {
            if torn >= self.tear_max || self.rng.random_range(0.0..1.0) > 0.5 {
                continue;
            }
            torn += 1;
            let back = DVec3::new(-0.3 * SPEED, 0.0, 0.0);
            let velocity = back + unit(&mut self.rng) * 0.02;
            let spin = unit(&mut self.rng) * self.rng.random_range(0.0..0.05);
            let piece = world.detach(f, Motion::Static, previous, parents);
            let vertices = world.fragment_vertices(f);
            let motion = world.rigid_for(&vertices, world.fragments[f].len(), velocity, spin);
            world.pieces[piece as usize].motion = motion;
        }
    }

    fn soft_displacement(&mut self, k: usize, world: &World, out: &mut [DVec3]) {
        let v = self.speed(k);
        let tau = std::f64::consts::TAU;
        for (i, o) in out.iter_mut().enumerate() {
            let x = DVec3::from_array(world.mesh.positions[i]);
            let rest = world.rest[i];
            let mut d = DVec3::new(v, 0.0, 0.0);
            let s = ((x.x - (WALL_X - CRUMPLE)) / CRUMPLE).clamp(0.0, 1.0);
            if s > 0.0 {
                let w = s * s * (3.0 - 2.0 * s);
                let radial = DVec3::new(0.0, rest.y, rest.z - SIZE.2).normalize_or_zero();
                d += radial * (0.6 * v * w * (tau * rest.x / 0.3 + self.phase).sin());
            }
            *o = d;
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
    let (n, w) = resolution(scale);
    let dents = Noise::new(&mut rng, 10, 3.0, 9.0);
    let mut shell = cube_sphere(n);
    for p in &mut shell.positions {
        *p = shell_point(*p, &dents);
    }
    let wall = grid(
        DVec3::new(WALL_X, -1.6, -0.4),
        DVec3::new(0.0, 3.2, 0.0),
        DVec3::new(0.0, 0.0, 2.4),
        w + 1,
        w + 1,
    );
    let mut world = World::default();
    world.add_part(&shell, Motion::Soft, false);
    world.add_part(&wall, Motion::Static, false);
    let shell_tris = shell.triangles.len();
    let panels = (shell_tris as f64 / (2000.0 * scale.max(0.01).sqrt())).round() as usize;
    let fragments = partition(
        &world.mesh.triangles,
        0..shell_tris,
        panels.max(8),
        &mut rng,
    );
    world.set_fragments(fragments);
    let mut ccd = Ccd::new();
    let start = preroll(
        &mut ccd,
        &world.mesh.triangles,
        |t| {
            let mut x: Vec<DVec3> = shell
                .positions
                .iter()
                .map(|&p| p + DVec3::X * (SPEED * t))
                .collect();
            x.extend_from_slice(&wall.positions);
            x
        },
        1.0,
        40,
    );
    if let Some((_, x)) = start {
        world.mesh.positions = x.iter().map(DVec3::to_array).collect();
    }
    let mut script = Crash {
        phase: rng.random_range(0.0..std::f64::consts::TAU),
        rng,
        steps: frames - 1,
        tear_max: (world.fragments.len() / 40).max(2),
    };
    run_world(PaperScene::Crash, &mut world, &mut script, frames, sink)
}
