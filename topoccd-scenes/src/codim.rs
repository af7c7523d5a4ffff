//! Scenes with codimensional geometry: free edges (rods, hair) and free points (particles),
//! as frame sequences of [`Mesh`]es whose [`Mesh::edges`] hold the free edges. Seeded: the
//! same arguments give the same frames, bit for bit.
//!
//! - [`CodimScene::HairBundle`]: a bundle of hair strands (polylines of free edges) hanging in
//!   a ring, twisting about the bundle's axis, so that strands cross each other (edge-edge
//!   pairs of free edges), over a still floor of two triangles that their tips sweep through;
//! - [`CodimScene::FunnelParticles`]: particles (free points) poured into a funnel (a cone of
//!   triangles): they fall under gravity from random places above it, through its wall
//!   (vertex-face pairs) and past each other;
//! - [`CodimScene::RodRain`]: particles rained onto a grid of waving rods, with pendulum rods
//!   swinging through the grid and a floor below: particles fall through rods (vertex-edge
//!   contacts), overtake the particle below them on the same vertical line (vertex-vertex
//!   contacts) and pass the floor (vertex-face), and the pendulums cross the grid's rods
//!   (edge-edge).
//!
//! ```
//! use topoccd_scenes::codim::{codim_frames, CodimScene};
//! let frames = codim_frames(CodimScene::HairBundle, 4, 1);
//! assert_eq!(frames.len(), 4);
//! assert!(!frames[0].edges.is_empty());
//! let step = topoccd::Step::new(&frames[0].positions, &frames[1].positions, &frames[0].triangles)?
//!     .with_edges(&frames[0].edges)?;
//! let report = topoccd::query(&step, topoccd::Method::Bvh, &Default::default())?;
//! # let _ = report;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::TAU;
use topoccd::io::Mesh;

/// The codimensional scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CodimScene {
    /// Hair strands twisting in a bundle over a floor.
    HairBundle,
    /// Particles poured into a funnel.
    FunnelParticles,
    /// Particles rained onto a grid of rods, with pendulum rods swinging through it.
    RodRain,
}

impl CodimScene {
    /// All scenes.
    pub const ALL: [CodimScene; 3] = [
        CodimScene::HairBundle,
        CodimScene::FunnelParticles,
        CodimScene::RodRain,
    ];

    /// The scene's name: `hair`, `funnel-particles` or `rod-rain`.
    pub fn name(self) -> &'static str {
        match self {
            CodimScene::HairBundle => "hair",
            CodimScene::FunnelParticles => "funnel-particles",
            CodimScene::RodRain => "rod-rain",
        }
    }

    /// The scene of a name of [`CodimScene::name`].
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }
}

/// The `frames` frames (at least 2) of `scene` with random numbers from `seed`. Every frame
/// has the same triangles and edges; the positions move.
pub fn codim_frames(scene: CodimScene, frames: usize, seed: u64) -> Vec<Mesh> {
    codim_frames_scaled(scene, frames, seed, 1.0)
}

/// [`codim_frames`] with the count of moving primitives scaled by `scale` (finite, > 0; 1 is
/// [`codim_frames`]'s scene): `round(24 scale)` hair strands, `round(400 scale)` particles;
/// for [`CodimScene::RodRain`] `round(12 scale)` rods, `round(6 scale)` pendulums,
/// `round(160 scale)` falling particles and `round(40 scale)` pairs of particles on one
/// vertical line; at least 2 of each. The floor and the funnel stay as they are.
///
/// ```
/// use topoccd_scenes::codim::{codim_frames, codim_frames_scaled, CodimScene};
/// let small = codim_frames_scaled(CodimScene::FunnelParticles, 2, 1, 0.2);
/// let large = codim_frames_scaled(CodimScene::FunnelParticles, 2, 1, 0.5);
/// assert!(small[0].positions.len() < large[0].positions.len());
/// assert_eq!(codim_frames_scaled(CodimScene::HairBundle, 3, 1, 1.0), codim_frames(CodimScene::HairBundle, 3, 1));
/// ```
pub fn codim_frames_scaled(scene: CodimScene, frames: usize, seed: u64, scale: f64) -> Vec<Mesh> {
    let frames = frames.max(2);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let count = |n: usize| ((n as f64 * scale).round() as usize).max(2);
    match scene {
        CodimScene::HairBundle => hair_bundle(frames, count(STRANDS), &mut rng),
        CodimScene::FunnelParticles => funnel_particles(frames, count(PARTICLES), &mut rng),
        CodimScene::RodRain => {
            let counts = RainCounts {
                rods: count(RAIN_RODS),
                pendulums: count(RAIN_PENDULUMS),
                drops: count(RAIN_DROPS),
                pairs: count(RAIN_PAIRS),
            };
            rod_rain(frames, counts, &mut rng)
        }
    }
}

/// Strands of this many vertices.
const STRAND_VERTICES: usize = 12;
/// Strands in the bundle (at scale 1).
const STRANDS: usize = 24;

fn hair_bundle(frames: usize, strands: usize, rng: &mut ChaCha8Rng) -> Vec<Mesh> {
    // Roots on a ring of radius 0.2 at z = 1, with a little jitter; strands 1 long.
    let roots: Vec<(f64, f64)> = (0..strands)
        .map(|s| {
            let angle = TAU * s as f64 / strands as f64 + rng.random_range(-0.05..0.05);
            (angle, 0.2 + rng.random_range(-0.03..0.03))
        })
        .collect();
    let floor = [
        [-1.0, -1.0, 0.1],
        [1.0, -1.0, 0.1],
        [1.0, 1.0, 0.1],
        [-1.0, 1.0, 0.1],
    ];
    let mut edges = Vec::new();
    for s in 0..strands {
        for k in 0..STRAND_VERTICES - 1 {
            let v = (4 + s * STRAND_VERTICES + k) as u32;
            edges.push([v, v + 1]);
        }
    }
    (0..frames)
        .map(|f| {
            let t = f as f64 / (frames - 1) as f64;
            let mut positions = floor.to_vec();
            for &(angle, radius) in &roots {
                for k in 0..STRAND_VERTICES {
                    let h = k as f64 / (STRAND_VERTICES - 1) as f64;
                    // The twist grows down the strand and with time: lower parts turn further,
                    // and the strands' radii shrink, so neighbours cross.
                    let turn = angle + 2.5 * t * h * h;
                    let r = radius * (1.0 - 0.6 * t * h);
                    let sag = 1.0 - 1.05 * h + 0.2 * t * h * h;
                    positions.push([r * turn.cos(), r * turn.sin(), sag]);
                }
            }
            Mesh {
                positions,
                triangles: vec![[0, 1, 2], [0, 2, 3]],
                edges: edges.clone(),
                ..Mesh::default()
            }
        })
        .collect()
}

/// Particles poured.
const PARTICLES: usize = 400;
/// Segments around the funnel.
const FUNNEL_SEGMENTS: usize = 32;

fn funnel_particles(frames: usize, particles: usize, rng: &mut ChaCha8Rng) -> Vec<Mesh> {
    // A cone from radius 1 at z = 1 down to radius 0.15 at z = 0, in three rings.
    let rings = [(1.0, 1.0), (0.55, 0.5), (0.15, 0.0)];
    let mut funnel = Vec::new();
    for &(r, z) in &rings {
        for k in 0..FUNNEL_SEGMENTS {
            let a = TAU * k as f64 / FUNNEL_SEGMENTS as f64;
            funnel.push([r * a.cos(), r * a.sin(), z]);
        }
    }
    let id = |ring: usize, k: usize| (ring * FUNNEL_SEGMENTS + k % FUNNEL_SEGMENTS) as u32;
    let mut triangles = Vec::new();
    for ring in 0..rings.len() - 1 {
        for k in 0..FUNNEL_SEGMENTS {
            triangles.push([id(ring, k), id(ring + 1, k), id(ring + 1, k + 1)]);
            triangles.push([id(ring, k), id(ring + 1, k + 1), id(ring, k + 1)]);
        }
    }
    // Each particle: a start above the funnel, a sideways velocity, and a delay.
    let particles: Vec<([f64; 3], [f64; 2], f64)> = (0..particles)
        .map(|_| {
            let a = rng.random_range(0.0..TAU);
            let r = 0.9 * rng.random_range(0.0f64..1.0).sqrt();
            let start = [r * a.cos(), r * a.sin(), 1.2 + rng.random_range(0.0..0.6)];
            let drift = [rng.random_range(-0.4..0.4), rng.random_range(-0.4..0.4)];
            (start, drift, rng.random_range(0.0..0.3))
        })
        .collect();
    (0..frames)
        .map(|f| {
            let t = f as f64 / (frames - 1) as f64;
            let mut positions = funnel.clone();
            for &([x, y, z], [dx, dy], delay) in &particles {
                let s = (t - delay).max(0.0);
                positions.push([x + dx * s, y + dy * s, z - 0.5 * 4.0 * s * s]);
            }
            Mesh {
                positions,
                triangles: triangles.clone(),
                edges: Vec::new(),
                ..Mesh::default()
            }
        })
        .collect()
}

/// Rods in the grid (at scale 1).
const RAIN_RODS: usize = 12;
/// Pendulum rods (at scale 1).
const RAIN_PENDULUMS: usize = 6;
/// Falling particles (at scale 1).
const RAIN_DROPS: usize = 160;
/// Pairs of particles on one vertical line (at scale 1).
const RAIN_PAIRS: usize = 40;
/// Vertices of a grid rod.
const ROD_VERTICES: usize = 9;
/// The fall of a particle after its delay `s`: `G s^2`.
const G: f64 = 2.0;

/// The counts of [`rod_rain`]'s moving primitives.
struct RainCounts {
    rods: usize,
    pendulums: usize,
    drops: usize,
    pairs: usize,
}

/// Rod `j`'s plane `y = y_j`: the rods 1/11 apart, centred on y = 0 (at scale 1 they span
/// y in [-0.5, 0.5]; fewer rods stay as close, so that the pendulums still reach them).
fn rod_y(j: usize, rods: usize) -> f64 {
    (j as f64 - 0.5 * (rods - 1) as f64) / 11.0
}

fn rod_rain(frames: usize, n: RainCounts, rng: &mut ChaCha8Rng) -> Vec<Mesh> {
    // Every moving primitive keeps to a plane or a line, so that its contacts are generic
    // crossings there, not chance alignments in space: grid rod j stays in the plane y = y_j
    // (it waves in z); a falling particle on rod j's plane drifts in x and falls in z, so it
    // crosses the rod's polyline in that plane (vertex-edge); the two particles of a pair share
    // one vertical line, the upper one falls first and overtakes the lower one (vertex-vertex);
    // a pendulum swings in the plane x = x_k between two rods and its body sweeps past the
    // points where the rods cross that plane (edge-edge). The floor at z = -0.6 takes the
    // particles that fall far enough (vertex-face).
    let floor = [
        [-0.8, -0.8, -0.6],
        [0.8, -0.8, -0.6],
        [0.8, 0.8, -0.6],
        [-0.8, 0.8, -0.6],
    ];
    let waves: Vec<(f64, f64)> = (0..n.rods)
        .map(|_| (rng.random_range(0.0..TAU), rng.random_range(0.02..0.06)))
        .collect();
    // Pendulum k: its plane x = x_k, between rods j and j + 1, its amplitude and phase.
    let pendulums: Vec<(f64, f64, f64, f64)> = (0..n.pendulums)
        .map(|_| {
            let j = rng.random_range(0..n.rods - 1);
            let y = 0.5 * (rod_y(j, n.rods) + rod_y(j + 1, n.rods));
            let x = rng.random_range(-0.5..0.5);
            (x, y, rng.random_range(0.4..0.7), rng.random_range(0.0..TAU))
        })
        .collect();
    // A falling particle: its rod plane, start, drift in x, delay.
    let drops: Vec<(f64, [f64; 2], f64, f64)> = (0..n.drops)
        .map(|_| {
            let y = rod_y(rng.random_range(0..n.rods), n.rods);
            let start = [rng.random_range(-0.5..0.5), rng.random_range(0.2..0.9)];
            (
                y,
                start,
                rng.random_range(-0.2..0.2),
                rng.random_range(0.0..0.2),
            )
        })
        .collect();
    // A pair: its line (x, y; on a rod's plane every other pair), the lower particle's height,
    // the upper one's height above it, the upper one's delay and the lower one's extra delay.
    // The upper one overtakes the lower one (G (t - d)^2 - G (t - d - e)^2 = gap) at
    // t - d = (gap / G + e^2) / (2 e), in (0.16, 0.55) for these ranges.
    let pairs: Vec<([f64; 2], f64, f64, f64, f64)> = (0..n.pairs)
        .map(|p| {
            let x = rng.random_range(-0.5..0.5);
            let y = if p % 2 == 0 {
                rod_y(rng.random_range(0..n.rods), n.rods)
            } else {
                rng.random_range(-0.5..0.5)
            };
            (
                [x, y],
                rng.random_range(0.15..0.6),
                rng.random_range(0.1..0.3),
                rng.random_range(0.0..0.2),
                rng.random_range(0.25..0.35),
            )
        })
        .collect();
    let mut edges = Vec::new();
    let mut v = floor.len() as u32;
    for _ in 0..n.rods {
        for _ in 0..ROD_VERTICES - 1 {
            edges.push([v, v + 1]);
            v += 1;
        }
        v += 1;
    }
    for _ in 0..n.pendulums {
        edges.push([v, v + 1]);
        edges.push([v + 1, v + 2]);
        v += 3;
    }
    let fall = |t: f64, delay: f64| G * (t - delay).max(0.0).powi(2);
    (0..frames)
        .map(|f| {
            let t = f as f64 / (frames - 1) as f64;
            let mut positions = floor.to_vec();
            for (j, &(phase, amplitude)) in waves.iter().enumerate() {
                let y = rod_y(j, n.rods);
                for k in 0..ROD_VERTICES {
                    let u = k as f64 / (ROD_VERTICES - 1) as f64;
                    let z = amplitude * (std::f64::consts::PI * u).sin() * (5.0 * t + phase).sin();
                    positions.push([-0.6 + 1.2 * u, y, z]);
                }
            }
            for &(x, y, amplitude, phase) in &pendulums {
                // Pivot at z = 0.3, two segments 0.25 long, swinging in y.
                let angle = amplitude * (7.0 * t + phase).sin();
                for k in 0..3 {
                    let r = 0.25 * k as f64;
                    positions.push([x, y + r * angle.sin(), 0.3 - r * angle.cos()]);
                }
            }
            for &(y, [x, z], drift, delay) in &drops {
                let s = (t - delay).max(0.0);
                positions.push([x + drift * s, y, z - fall(t, delay)]);
            }
            for &([x, y], low, gap, delay, extra) in &pairs {
                positions.push([x, y, low + gap - fall(t, delay)]);
                positions.push([x, y, low - fall(t, delay + extra)]);
            }
            Mesh {
                positions,
                triangles: vec![[0, 1, 2], [0, 2, 3]],
                edges: edges.clone(),
                ..Mesh::default()
            }
        })
        .collect()
}
