//! `nidus` and `nidus-cut`: a lumpy vascular blob whose lobes bend into each other, and the
//! same blob while a cut advances through it.
//!
//! Mesh: a star-shaped blob (core radius 0.6) with 12 tube-like lobes reaching 1.5 to 2.4 core
//! radii out, with smooth noise, on a cube-sphere of about 32,798 x scale triangles.
//!
//! Motion (soft): the lobes are paired with their nearest neighbour and each bends towards its
//! partner: a point of lobe `i` turns about the axis `d_i x d_j` through the centre by
//! `0.6 t angle(d_i, d_j) w_i`, its weight `w_i` in the lobe (0 at the core, 1 along the
//! lobe), for story time `t`. Lobes meet tip first, then press together along their length;
//! touching vertices stop (see `response.rs`). The run starts halfway to the first contact.
//!
//! Cut: a plane through the centre; the cut front advances across it, from one side of the
//! blob to the other over the run. Each step, the vertices behind the front that join
//! triangles on both sides of the plane are split (the copy takes the far side's triangles,
//! parented to the original), and the two sides open by a smooth displacement away from the
//! plane, fading out towards the front.

use glam::DQuat;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::driver::{preroll, run as run_world, Script, Sink};
use super::shapes::{cube_sphere_resolution, spread_directions, unit, Blob, Lobe, Noise};
use super::world::{Motion, World};
use super::{GenSummary, PaperScene};
use glam::DVec3;
use topoccd::{mesh::Topology, Ccd};

/// The paper's triangle count.
const PAPER: f64 = 32_798.0;
/// Core radius of the blob.
const CORE: f64 = 0.6;
/// Number of lobes.
const LOBES: usize = 12;
/// Story time covered by the run (after the pre-roll).
const SPAN: f64 = 0.6;
/// Opening speed of the cut, per step, at the plane.
const OPEN: f64 = 0.02;

/// First-frame triangle count at `scale`.
pub(super) fn triangles(scale: f64) -> usize {
    let n = cube_sphere_resolution(PAPER * scale);
    12 * n * n
}

/// The bending field and the cut.
struct Nidus {
    lobes: Vec<Lobe>,
    /// Per lobe: rotation axis and angle per unit of story time.
    bends: Vec<(DVec3, f64)>,
    /// Story time of frame 0 and per step.
    t0: f64,
    dt: f64,
    cut: Option<Cut>,
}

/// A cut advancing across a plane.
struct Cut {
    /// Plane normal (the plane goes through the centre).
    normal: DVec3,
    /// Direction in the plane along which the front advances.
    along: DVec3,
    /// Front position (along `along`) at the start and at the end of the run.
    from: f64,
    to: f64,
    /// Steps in the run.
    steps: usize,
    /// Vertices already split (or made by a split).
    done: Vec<bool>,
    /// Which side each vertex opens towards: +1, -1, or 0 (not separated yet).
    side: Vec<f64>,
}

impl Nidus {
    /// Position of rest point `x` at story time `t` under the bending field.
    fn bent(&self, t: f64, x: DVec3) -> DVec3 {
        let r = x.length();
        if r <= 0.0 {
            return x;
        }
        let d = x / r;
        let s = ((r / CORE - 1.0) / 1.0).clamp(0.0, 1.0);
        let ramp = s * s * (3.0 - 2.0 * s);
        let mut out = x;
        for (lobe, &(axis, rate)) in self.lobes.iter().zip(&self.bends) {
            let w = lobe.weight(d) * ramp;
            if w > 1e-6 {
                out += DQuat::from_axis_angle(axis, rate * t * w) * x - x;
            }
        }
        out
    }

    /// The front position of the cut during step `k`.
    fn front(cut: &Cut, k: usize) -> f64 {
        cut.from + (cut.to - cut.from) * (k + 1) as f64 / cut.steps.max(1) as f64
    }
}

impl Script for Nidus {
    fn before_step(&mut self, k: usize, world: &mut World, parents: &mut Vec<(u32, u32)>) {
        let Some(cut) = &mut self.cut else { return };
        let front = Self::front(cut, k);
        let previous = world.vertex_count();
        let tris = &world.mesh.triangles;
        // Side of each triangle: by its rest centroid.
        let above: Vec<bool> = tris
            .iter()
            .map(|t| {
                t.iter()
                    .map(|&v| world.rest[v as usize])
                    .sum::<DVec3>()
                    .dot(cut.normal)
                    > 0.0
            })
            .collect();
        // Vertex -> triangles (a snapshot: splitting below changes the triangles).
        let topo = Topology::new(tris, previous);
        cut.done.resize(previous, false);
        cut.side.resize(previous, 0.0);
        for v in 0..previous {
            if cut.done[v] || world.rest[v].dot(cut.along) > front {
                continue;
            }
            let around = topo.triangles_of(v as u32);
            let below: Vec<u32> = around
                .iter()
                .copied()
                .filter(|&t| !above[t as usize])
                .collect();
            if below.is_empty() || below.len() == around.len() {
                continue;
            }
            let copy = world.split_vertex(v as u32, &below, previous, parents);
            cut.done[v] = true;
            cut.side[v] = 1.0;
            cut.done.push(true);
            cut.side.push(-1.0);
            debug_assert_eq!(copy as usize + 1, cut.done.len());
        }
    }

    fn soft_displacement(&mut self, k: usize, world: &World, out: &mut [DVec3]) {
        let (ta, tb) = (
            self.t0 + k as f64 * self.dt,
            self.t0 + (k + 1) as f64 * self.dt,
        );
        for (v, o) in out.iter_mut().enumerate() {
            let x = world.rest[v];
            *o = self.bent(tb, x) - self.bent(ta, x);
        }
        let Some(cut) = &self.cut else { return };
        let front = Self::front(cut, k);
        for (v, o) in out.iter_mut().enumerate() {
            let x = world.rest[v];
            let h = x.dot(cut.normal);
            let side = match cut.side.get(v) {
                Some(&s) if s != 0.0 => s,
                _ => h.signum(),
            };
            let behind = ((front - x.dot(cut.along)) / (4.0 * CORE)).clamp(0.0, 1.0);
            let near = (-(h * h) / (0.3 * CORE * CORE)).exp();
            *o += cut.normal * (OPEN * side * near * behind);
        }
    }
}

/// Builds and runs the scene.
pub(super) fn run<E>(
    cut: bool,
    scale: f64,
    frames: usize,
    seed: u64,
    sink: &mut Sink<'_, E>,
) -> Result<GenSummary, E> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let dirs = spread_directions(&mut rng, LOBES, 0.15);
    let lobes: Vec<Lobe> = dirs
        .iter()
        .map(|&dir| Lobe {
            dir,
            height: rng.random_range(1.5..2.4),
            width: rng.random_range(0.02..0.035),
        })
        .collect();
    let noise = Noise::new(&mut rng, 12, 3.0, 7.0);
    let blob = Blob {
        base: CORE,
        lobes: &lobes,
        noise_amp: 0.12,
        noise: &noise,
        stretch: DVec3::ONE,
        centre: DVec3::ZERO,
    };
    let part = blob.mesh(PAPER * scale);
    // Pair each lobe with its nearest free neighbour, closest pairs first.
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for i in 0..LOBES {
        for j in i + 1..LOBES {
            pairs.push((dirs[i].dot(dirs[j]).clamp(-1.0, 1.0).acos(), i, j));
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut partner = [usize::MAX; LOBES];
    for &(_, i, j) in &pairs {
        if partner[i] == usize::MAX && partner[j] == usize::MAX {
            partner[i] = j;
            partner[j] = i;
        }
    }
    let bends = (0..LOBES)
        .map(|i| {
            let j = if partner[i] == usize::MAX {
                // Odd one out: towards its nearest lobe.
                (0..LOBES)
                    .filter(|&j| j != i)
                    .max_by(|&a, &b| dirs[i].dot(dirs[a]).total_cmp(&dirs[i].dot(dirs[b])))
                    .unwrap_or(i)
            } else {
                partner[i]
            };
            let axis = dirs[i]
                .cross(dirs[j])
                .try_normalize()
                .unwrap_or_else(|| unit(&mut rng));
            (axis, 0.6 * dirs[i].dot(dirs[j]).clamp(-1.0, 1.0).acos())
        })
        .collect();
    let steps = frames - 1;
    let dt = SPAN / steps as f64;
    let mut world = World::default();
    world.add_part(&part, Motion::Soft, false);
    let mut nidus = Nidus {
        lobes,
        bends,
        t0: 0.0,
        dt,
        cut: None,
    };
    let mut ccd = Ccd::new();
    let rest = world.rest.clone();
    let start = preroll(
        &mut ccd,
        &world.mesh.triangles,
        |t| rest.iter().map(|&x| nidus.bent(t, x)).collect(),
        dt,
        (2.0 / dt).ceil() as usize,
    );
    if let Some((t0, x)) = start {
        nidus.t0 = t0;
        world.mesh.positions = x.iter().map(DVec3::to_array).collect();
    }
    if cut {
        let normal = unit(&mut rng);
        let along = normal.any_orthonormal_vector();
        let extent = world.rest.iter().map(|x| x.dot(along));
        let (lo, hi) = extent.fold((f64::MAX, f64::MIN), |(lo, hi), s| (lo.min(s), hi.max(s)));
        nidus.cut = Some(Cut {
            normal,
            along,
            from: lo + 0.05 * (hi - lo),
            to: hi,
            steps,
            done: Vec::new(),
            side: Vec::new(),
        });
    }
    let scene = if cut {
        PaperScene::NidusCut
    } else {
        PaperScene::Nidus
    };
    run_world(scene, &mut world, &mut nidus, frames, sink)
}
