//! `lion` and `bunny-dragon`: breakable bodies shattering into rigid fragments.
//!
//! Meshes: star-shaped blobs with lobes (legs, head, tail, ears, spikes) and smooth noise on
//! cube-spheres, stretched along their length. A body is partitioned into fragments of about
//! 1,000 (lion) or 60 (dragon) triangles by geodesic breadth-first growth from random seeds.
//!
//! `lion` (1.6M x scale triangles): the body is static and breakable. An explosion at a point
//! inside breaks fragments off in order of distance from it (jittered), evenly over the steps
//! (85% of them by the end); each flies off radially at 0.03 to 0.08 per step with a random
//! spin, under gravity. Fragments that hit the body faster than the break speed break the
//! fragment they hit; slower hits bounce. Fragments bounce off each other.
//!
//! `bunny-dragon` (0.25M x scale: a 0.2M dragon and a 0.05M bunny): the bunny, a heavy rigid
//! body, flies sideways into the static, breakable dragon (starting halfway to the first
//! contact). Each fragment it hits breaks off faster than the bunny, and a shock front from the
//! first impact, growing by 0.25 per step, breaks off every fragment it passes, pushed
//! outwards; the dragon ends in thousands of pieces.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::driver::{preroll, run as run_world, Script, Sink};
use super::fracture::partition;
use super::response::{Break, Hit};
use super::shapes::{cube_sphere_resolution, unit, Blob, Lobe, Noise};
use super::world::{Motion, World};
use super::{GenSummary, PaperScene};
use glam::DVec3;
use topoccd::Ccd;

/// Paper triangle counts.
const LION: f64 = 1_600_000.0;
const DRAGON: f64 = 200_000.0;
const BUNNY: f64 = 50_000.0;

/// First-frame triangle count of `lion` at `scale`.
pub(super) fn lion_triangles(scale: f64) -> usize {
    let n = cube_sphere_resolution(LION * scale);
    12 * n * n
}

/// First-frame triangle count of `bunny-dragon` at `scale`.
pub(super) fn bunny_dragon_triangles(scale: f64) -> usize {
    let (d, b) = (
        cube_sphere_resolution(DRAGON * scale),
        cube_sphere_resolution(BUNNY * scale),
    );
    12 * (d * d + b * b)
}

/// A lobe from a direction (normalised here), height and width.
fn lobe(dir: [f64; 3], height: f64, width: f64) -> Lobe {
    Lobe {
        dir: DVec3::from_array(dir).normalize(),
        height,
        width,
    }
}

/// A shock front breaking every fragment it passes.
struct Shock {
    centre: DVec3,
    /// Step of the first impact.
    from: usize,
    /// Growth of the radius per step.
    speed: f64,
    /// Velocity of the impactor.
    push: DVec3,
}

/// The breaking of a body.
struct Shatter {
    rng: ChaCha8Rng,
    /// Fragments to break off at each step, with their velocity (the lion's explosion).
    schedule: Vec<Vec<(u32, DVec3)>>,
    /// Fragments hit in the last step, to break off at the next.
    pending: Vec<(u32, DVec3)>,
    /// Rest centroid of each fragment.
    centroids: Vec<DVec3>,
    /// Largest spin given to a fragment, radians per step.
    spin: f64,
    /// Speed factor of a fragment hit by an impactor, relative to the impactor.
    kick: f64,
    /// The shock front, if the scene has one (started by the first impact).
    shock: Option<Shock>,
    shock_speed: Option<f64>,
}

impl Script for Shatter {
    fn before_step(&mut self, k: usize, world: &mut World, parents: &mut Vec<(u32, u32)>) {
        let previous = world.vertex_count();
        let mut breaking = std::mem::take(&mut self.pending);
        if let Some(list) = self.schedule.get(k) {
            breaking.extend_from_slice(list);
        }
        if let Some(shock) = &self.shock {
            let radius = shock.speed * (k - shock.from) as f64;
            for (f, &c) in self.centroids.iter().enumerate() {
                let d = c - shock.centre;
                if !world.detached[f] && d.length() < radius {
                    let out = d.normalize_or_zero() * 0.05 + shock.push * 0.4;
                    breaking.push((f as u32, out + unit(&mut self.rng) * 0.01));
                }
            }
        }
        breaking.sort_by_key(|&(f, _)| f);
        breaking.dedup_by_key(|&mut (f, _)| f);
        for (f, velocity) in breaking {
            let f = f as usize;
            if world.detached[f] {
                continue;
            }
            let spin = unit(&mut self.rng) * self.rng.random_range(0.0..self.spin);
            let piece = world.detach(f, Motion::Static, previous, parents);
            let vertices = world.fragment_vertices(f);
            let motion = world.rigid_for(&vertices, world.fragments[f].len(), velocity, spin);
            world.pieces[piece as usize].motion = motion;
        }
    }

    fn after_step(&mut self, k: usize, _world: &mut World, _hits: &[Hit], breaks: &[Break]) {
        for b in breaks {
            let jitter = unit(&mut self.rng) * (0.2 * b.velocity.length());
            let factor = self.kick * self.rng.random_range(1.0..1.3);
            self.pending
                .push((b.fragment, b.velocity * factor + jitter));
        }
        if let (None, Some(speed), Some(first)) = (&self.shock, self.shock_speed, breaks.first()) {
            self.shock = Some(Shock {
                centre: first.point,
                from: k,
                speed,
                push: first.velocity,
            });
        }
    }
}

/// Rest centroids of the fragments.
fn centroids(world: &World) -> Vec<DVec3> {
    world
        .fragments
        .iter()
        .map(|tris| {
            let sum: DVec3 = tris
                .iter()
                .flat_map(|&t| world.mesh.triangles[t as usize])
                .map(|v| world.rest[v as usize])
                .sum();
            sum / (3 * tris.len().max(1)) as f64
        })
        .collect()
}

/// Builds and runs `lion`.
pub(super) fn run_lion<E>(
    scale: f64,
    frames: usize,
    seed: u64,
    sink: &mut Sink<'_, E>,
) -> Result<GenSummary, E> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut lobes = vec![
        lobe([0.55, 0.45, -0.75], 1.1, 0.018),
        lobe([0.55, -0.45, -0.75], 1.1, 0.018),
        lobe([-0.55, 0.45, -0.75], 1.1, 0.018),
        lobe([-0.55, -0.45, -0.75], 1.1, 0.018),
        lobe([0.8, 0.0, 0.55], 0.8, 0.07),
        lobe([-0.93, 0.0, 0.35], 1.3, 0.006),
    ];
    // The mane: small bumps around the head.
    for _ in 0..24 {
        let d = (DVec3::new(0.8, 0.0, 0.55) + unit(&mut rng) * 0.45).normalize();
        lobes.push(Lobe {
            dir: d,
            height: rng.random_range(0.1..0.25),
            width: rng.random_range(0.004..0.01),
        });
    }
    let noise = Noise::new(&mut rng, 16, 4.0, 12.0);
    let blob = Blob {
        base: 1.0,
        lobes: &lobes,
        noise_amp: 0.05,
        noise: &noise,
        stretch: DVec3::new(1.5, 0.75, 0.85),
        centre: DVec3::ZERO,
    };
    let part = blob.mesh(LION * scale);
    let mut world = World::default();
    world.gravity = DVec3::new(0.0, 0.0, -0.004);
    world.break_speed = 0.05;
    world.add_part(&part, Motion::Static, true);
    let count = (part.triangles.len() / 1000).max(8);
    let fragments = partition(
        &world.mesh.triangles,
        0..part.triangles.len(),
        count,
        &mut rng,
    );
    world.set_fragments(fragments);
    let centroids = centroids(&world);
    // The explosion: fragments nearest the centre go first, evenly over the steps.
    let centre = DVec3::new(0.3, 0.0, 0.1);
    let mut order: Vec<(f64, u32)> = centroids
        .iter()
        .enumerate()
        .map(|(f, c)| {
            (
                (*c - centre).length() + rng.random_range(0.0..0.4),
                f as u32,
            )
        })
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let steps = frames - 1;
    let explode = ((order.len() as f64 * 0.85).ceil() as usize).max(steps.min(order.len()));
    let mut schedule = vec![Vec::new(); steps];
    for (i, &(_, f)) in order.iter().take(explode).enumerate() {
        let k = i * steps / explode;
        let dir = (centroids[f as usize] - centre).normalize_or(DVec3::Z);
        let speed = rng.random_range(0.03..0.08);
        schedule[k].push((f, dir * speed + unit(&mut rng) * 0.01));
    }
    let mut script = Shatter {
        rng,
        schedule,
        pending: Vec::new(),
        centroids,
        spin: 0.06,
        kick: 1.2,
        shock: None,
        shock_speed: None,
    };
    run_world(PaperScene::Lion, &mut world, &mut script, frames, sink)
}

/// Builds and runs `bunny-dragon`.
pub(super) fn run_bunny_dragon<E>(
    scale: f64,
    frames: usize,
    seed: u64,
    sink: &mut Sink<'_, E>,
) -> Result<GenSummary, E> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut dragon_lobes = vec![
        lobe([0.9, 0.0, 0.45], 1.2, 0.03),
        lobe([-1.0, 0.0, 0.1], 1.6, 0.01),
        lobe([0.5, 0.6, -0.65], 0.9, 0.02),
        lobe([0.5, -0.6, -0.65], 0.9, 0.02),
        lobe([-0.5, 0.6, -0.65], 0.9, 0.02),
        lobe([-0.5, -0.6, -0.65], 0.9, 0.02),
    ];
    for i in 0..7 {
        let x = -0.6 + 0.2 * i as f64;
        dragon_lobes.push(lobe([x, 0.0, 1.0], 0.35, 0.004));
    }
    let dragon_noise = Noise::new(&mut rng, 16, 4.0, 10.0);
    let dragon = Blob {
        base: 0.7,
        lobes: &dragon_lobes,
        noise_amp: 0.06,
        noise: &dragon_noise,
        stretch: DVec3::new(1.8, 0.7, 0.9),
        centre: DVec3::ZERO,
    }
    .mesh(DRAGON * scale);
    let bunny_lobes = [
        lobe([0.25, 0.2, 1.0], 1.4, 0.006),
        lobe([-0.25, 0.2, 1.0], 1.4, 0.006),
        lobe([0.0, -1.0, 0.1], 0.25, 0.02),
        lobe([0.0, 0.9, 0.5], 0.4, 0.05),
    ];
    let bunny_noise = Noise::new(&mut rng, 8, 3.0, 8.0);
    let bunny_start = DVec3::new(rng.random_range(-0.3..0.3), -2.2, 0.25);
    let bunny = Blob {
        base: 0.35,
        lobes: &bunny_lobes,
        noise_amp: 0.05,
        noise: &bunny_noise,
        stretch: DVec3::ONE,
        centre: bunny_start,
    }
    .mesh(BUNNY * scale);
    let velocity = DVec3::new(0.0, 0.3, -0.02);
    let mut world = World::default();
    world.gravity = DVec3::new(0.0, 0.0, -0.003);
    world.break_speed = 0.05;
    world.add_part(&dragon, Motion::Static, true);
    let bunny_piece = world.add_part(&bunny, Motion::Static, false);
    let dragon_tris = dragon.triangles.len();
    let count = (dragon_tris / 60).max(8);
    let fragments = partition(&world.mesh.triangles, 0..dragon_tris, count, &mut rng);
    world.set_fragments(fragments);
    let centroids = centroids(&world);
    // Fly the bunny in until it nearly touches.
    let offset = dragon.positions.len();
    let mut ccd = Ccd::new();
    let start = preroll(
        &mut ccd,
        &world.mesh.triangles,
        |t| {
            let mut x = dragon.positions.clone();
            x.extend(bunny.positions.iter().map(|&p| p + velocity * t));
            x
        },
        1.0,
        40,
    );
    if let Some((_, x)) = start {
        world.mesh.positions = x.iter().map(DVec3::to_array).collect();
    }
    let bunny_ids: Vec<u32> = (offset as u32..world.vertex_count() as u32).collect();
    let mut motion = world.rigid_for(&bunny_ids, bunny.triangles.len(), velocity, DVec3::ZERO);
    if let Motion::Rigid {
        inv_mass,
        inv_inertia,
        ..
    } = &mut motion
    {
        // Much heavier than its triangle count: it ploughs through.
        *inv_mass *= 0.05;
        *inv_inertia *= 0.05;
    }
    world.pieces[bunny_piece as usize].motion = motion;
    let mut script = Shatter {
        rng,
        schedule: Vec::new(),
        pending: Vec::new(),
        centroids,
        spin: 0.1,
        kick: 1.3,
        shock: None,
        shock_speed: Some(0.25),
    };
    run_world(
        PaperScene::BunnyDragon,
        &mut world,
        &mut script,
        frames,
        sink,
    )
}
