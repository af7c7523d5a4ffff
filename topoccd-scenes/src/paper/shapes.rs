//! Building blocks of the paper scenes' meshes: smooth noise, the cube-sphere and star-shaped
//! blobs with lobes, tori and sewn sheets.
//!
//! Every surface here is embedded by construction: a blob is `centre + r(d) d` over the unit
//! directions `d` of a cube-sphere with `r > 0`, so it cannot cross itself whatever `r` is.

use std::collections::HashMap;

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use glam::DVec3;

/// A triangle mesh under construction: positions and triangles.
#[derive(Clone, Debug, Default)]
pub(crate) struct Part {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Triangles, outward-oriented for closed surfaces.
    pub triangles: Vec<[u32; 3]>,
}

pub(crate) use crate::random_unit as unit;

/// A smooth random scalar field on space: a sum of plane waves `a sin(w . p + phase)` with
/// wave vectors up to `max_freq` radians per unit and amplitudes summing to about 1.
#[derive(Clone, Debug)]
pub(crate) struct Noise {
    waves: Vec<(DVec3, f64, f64)>,
}

impl Noise {
    /// `count` waves of frequency `min_freq..max_freq` (radians per unit length).
    pub fn new(rng: &mut ChaCha8Rng, count: usize, min_freq: f64, max_freq: f64) -> Self {
        let count = count.max(1);
        let waves = (0..count)
            .map(|_| {
                let w = unit(rng) * rng.random_range(min_freq..=max_freq);
                let phase = rng.random_range(0.0..std::f64::consts::TAU);
                let amp = rng.random_range(0.5..1.0) / count as f64 * 1.5;
                (w, phase, amp)
            })
            .collect();
        Self { waves }
    }

    /// The field at `p`, in about `[-1, 1]`.
    pub fn at(&self, p: DVec3) -> f64 {
        self.waves
            .iter()
            .map(|&(w, ph, a)| a * (w.dot(p) + ph).sin())
            .sum()
    }
}

/// The cube-sphere of resolution `n >= 1`: each face of a cube split into `n * n` cells of two
/// triangles (`12 n^2` triangles, `6 n^2 + 2` vertices), projected onto the unit sphere with the
/// tangent warp that evens out the cell sizes. Returns unit directions and outward triangles.
pub(crate) fn cube_sphere(n: usize) -> Part {
    let n = n.max(1);
    let ni = n as i64;
    let mut index: HashMap<(i64, i64, i64), u32> = HashMap::with_capacity(6 * n * n + 2);
    let mut part = Part::default();
    let warp = |i: i64| (std::f64::consts::FRAC_PI_4 * (2.0 * i as f64 / n as f64 - 1.0)).tan();
    let mut vertex = |key: (i64, i64, i64), part: &mut Part| -> u32 {
        *index.entry(key).or_insert_with(|| {
            let p = DVec3::new(warp(key.0), warp(key.1), warp(key.2));
            part.positions.push(p.normalize());
            (part.positions.len() - 1) as u32
        })
    };
    // Faces: a fixed axis at 0 or n, the two others running over the grid.
    for axis in 0..3 {
        for side in [0, ni] {
            for i in 0..ni {
                for j in 0..ni {
                    let key = |a: i64, b: i64| match axis {
                        0 => (side, a, b),
                        1 => (a, side, b),
                        _ => (a, b, side),
                    };
                    let v00 = vertex(key(i, j), &mut part);
                    let v10 = vertex(key(i + 1, j), &mut part);
                    let v11 = vertex(key(i + 1, j + 1), &mut part);
                    let v01 = vertex(key(i, j + 1), &mut part);
                    let (t1, t2) = if (i + j) % 2 == 0 {
                        ([v00, v10, v11], [v00, v11, v01])
                    } else {
                        ([v00, v10, v01], [v10, v11, v01])
                    };
                    for t in [t1, t2] {
                        part.triangles.push(outward(&part.positions, t));
                    }
                }
            }
        }
    }
    part
}

/// The triangle `t` wound so that its normal points away from the origin.
fn outward(positions: &[DVec3], t: [u32; 3]) -> [u32; 3] {
    let [a, b, c] = t.map(|i| positions[i as usize]);
    if (b - a).cross(c - a).dot(a + b + c) < 0.0 {
        [t[0], t[2], t[1]]
    } else {
        t
    }
}

/// The cube-sphere resolution whose triangle count `12 n^2` is nearest `triangles`.
pub(crate) fn cube_sphere_resolution(triangles: f64) -> usize {
    ((triangles / 12.0).max(1.0).sqrt().round() as usize).max(2)
}

/// A protrusion of a blob: a smooth bump of the radius around direction `dir`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lobe {
    /// Unit direction of the lobe's axis.
    pub dir: DVec3,
    /// How far it reaches beyond the base radius, in units of the base radius.
    pub height: f64,
    /// Angular width: the bump is `exp(-(1 - cos angle) / width)`.
    pub width: f64,
}

impl Lobe {
    /// The lobe's weight in direction `d` (unit), in `[0, 1]`.
    pub fn weight(&self, d: DVec3) -> f64 {
        (-(1.0 - d.dot(self.dir)) / self.width).exp()
    }
}

/// A star-shaped blob: `centre + r(d) d` with `r(d) = base (1 + sum of lobes + noise_amp *
/// noise(d))`, anisotropically stretched by `stretch` afterwards (still embedded: a linear map
/// of an embedded surface).
pub(crate) struct Blob<'a> {
    /// Base radius.
    pub base: f64,
    /// The protrusions.
    pub lobes: &'a [Lobe],
    /// Relative amplitude of the noise.
    pub noise_amp: f64,
    /// The noise, evaluated on the unit direction.
    pub noise: &'a Noise,
    /// Per-axis stretch.
    pub stretch: DVec3,
    /// Centre.
    pub centre: DVec3,
}

impl Blob<'_> {
    /// The radius factor in direction `d` (at least 0.2).
    pub fn radius(&self, d: DVec3) -> f64 {
        let lobes: f64 = self.lobes.iter().map(|l| l.height * l.weight(d)).sum();
        (1.0 + lobes + self.noise_amp * self.noise.at(d)).max(0.2)
    }

    /// Meshes the blob on a cube-sphere of about `triangles` triangles.
    pub fn mesh(&self, triangles: f64) -> Part {
        let mut part = cube_sphere(cube_sphere_resolution(triangles));
        for p in &mut part.positions {
            let d = *p;
            *p = self.centre + self.stretch * (self.base * self.radius(d) * d);
        }
        part
    }
}

/// A torus around axis `axis` (unit) through `centre`: major radius `major`, tube radius
/// `minor`, `nu` segments around the axis and `nv` around the tube (`2 nu nv` triangles).
pub(crate) fn torus(
    centre: DVec3,
    axis: DVec3,
    major: f64,
    minor: f64,
    nu: usize,
    nv: usize,
) -> Part {
    let (nu, nv) = (nu.max(3), nv.max(3));
    let axis = axis.normalize();
    let e1 = axis.any_orthonormal_vector();
    let e2 = axis.cross(e1);
    let tau = std::f64::consts::TAU;
    let mut part = Part::default();
    for i in 0..nu {
        let a = tau * i as f64 / nu as f64;
        let radial = e1 * a.cos() + e2 * a.sin();
        for j in 0..nv {
            let b = tau * j as f64 / nv as f64;
            part.positions
                .push(centre + radial * (major + minor * b.cos()) + axis * (minor * b.sin()));
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + (j % nv)) as u32;
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            part.triangles.push([a, b, c]);
            part.triangles.push([a, c, d]);
        }
    }
    // Orient outward from the tube's core circle.
    let core = |p: DVec3| {
        let q = p - centre;
        let planar = q - axis * q.dot(axis);
        centre + planar.normalize_or_zero() * major
    };
    for t in &mut part.triangles {
        let [a, b, c] = t.map(|i| part.positions[i as usize]);
        let mid = (a + b + c) / 3.0;
        if (b - a).cross(c - a).dot(mid - core(mid)) < 0.0 {
            t.swap(1, 2);
        }
    }
    part
}

/// A flat rectangular grid of `nx * ny` vertices spanning `origin + [0, 1] u + [0, 1] v`
/// (`2 (nx-1)(ny-1)` triangles).
pub(crate) fn grid(origin: DVec3, u: DVec3, v: DVec3, nx: usize, ny: usize) -> Part {
    let (nx, ny) = (nx.max(2), ny.max(2));
    let mut part = Part::default();
    for i in 0..nx {
        for j in 0..ny {
            let (s, t) = (i as f64 / (nx - 1) as f64, j as f64 / (ny - 1) as f64);
            part.positions.push(origin + u * s + v * t);
        }
    }
    crate::grid_triangles(nx, ny, 0, &mut part.triangles);
    part
}

/// Evenly spread unit directions (a Fibonacci spiral), rotated at random and jittered.
pub(crate) fn spread_directions(rng: &mut ChaCha8Rng, count: usize, jitter: f64) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let turn = glam::DQuat::from_axis_angle(unit(rng), rng.random_range(0.0..3.0));
    (0..count)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / count as f64;
            let r = (1.0 - z * z).sqrt();
            let a = golden * i as f64;
            let d = turn * DVec3::new(r * a.cos(), r * a.sin(), z);
            (d + jitter * unit(rng)).normalize()
        })
        .collect()
}
