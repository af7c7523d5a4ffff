//! Deforming meshes shared by the clustering and cluster-query tests: parametric grids, spheres
//! and helicoid ribbons, and adversarial steps built to break the paper's clustering criterion
//! (a helicoid whose upper turn sinks through the one below, a tight fold, crumpled sheets,
//! torn pieces pressed together, a partial tear).
#![allow(dead_code)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{PI, TAU};
use topoccd::math::DVec3;
use topoccd::{Report, Step};

/// A grid of `nu x nv` quads, two triangles each, mapped by `f0` at t=0 and `f1` at t=1 from
/// `(u, v)` in `[0, 1]^2`. Triangles face `+(d/du x d/dv)`.
pub fn grid(
    nu: u32,
    nv: u32,
    f0: impl Fn(f64, f64) -> DVec3,
    f1: impl Fn(f64, f64) -> DVec3,
) -> Step<'static> {
    let (mut x0, mut x1) = (Vec::new(), Vec::new());
    for j in 0..=nv {
        for i in 0..=nu {
            let (u, v) = (i as f64 / nu as f64, j as f64 / nv as f64);
            x0.push(f0(u, v));
            x1.push(f1(u, v));
        }
    }
    let mut tris = Vec::new();
    let id = |i: u32, j: u32| j * (nu + 1) + i;
    for j in 0..nv {
        for i in 0..nu {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Step::new(x0, x1, tris).expect("valid grid")
}

/// Closed UV sphere: `rings` latitude bands, `segments` longitudes, outward normals; each vertex
/// `p` of the unit sphere goes to `f0(p)` and `f1(p)`.
pub fn sphere(
    rings: u32,
    segments: u32,
    f0: impl Fn(DVec3) -> DVec3,
    f1: impl Fn(DVec3) -> DVec3,
) -> Step<'static> {
    let mut unit = vec![DVec3::Z];
    for r in 1..rings {
        let th = PI * r as f64 / rings as f64;
        for s in 0..segments {
            let ph = TAU * s as f64 / segments as f64;
            unit.push(DVec3::new(
                th.sin() * ph.cos(),
                th.sin() * ph.sin(),
                th.cos(),
            ));
        }
    }
    unit.push(-DVec3::Z);
    let south = unit.len() as u32 - 1;
    let at = |r: u32, s: u32| 1 + (r - 1) * segments + s % segments;
    let mut tris = Vec::new();
    for s in 0..segments {
        tris.push([0, at(1, s), at(1, s + 1)]);
        for r in 1..rings - 1 {
            tris.push([at(r, s), at(r + 1, s), at(r + 1, s + 1)]);
            tris.push([at(r, s), at(r + 1, s + 1), at(r, s + 1)]);
        }
        tris.push([at(rings - 1, s), south, at(rings - 1, s + 1)]);
    }
    let x0: Vec<DVec3> = unit.iter().map(|&p| f0(p)).collect();
    let x1: Vec<DVec3> = unit.iter().map(|&p| f1(p)).collect();
    Step::new(x0, x1, tris).expect("valid sphere")
}

/// Helicoid ribbon: angle `theta` in `[0, turns 2 pi]`, radius in `[1, 1.5]`, height `z0` at
/// t=0 and `z1` at t=1 (functions of the angle). Triangles face up.
pub fn ribbon(
    n_theta: u32,
    n_r: u32,
    turns: f64,
    z0: impl Fn(f64) -> f64,
    z1: impl Fn(f64) -> f64,
) -> Step<'static> {
    let at = |z: &dyn Fn(f64) -> f64, u: f64, v: f64| {
        let th = u * turns * TAU;
        let r = 1.0 + 0.5 * v;
        DVec3::new(r * th.cos(), r * th.sin(), z(th))
    };
    // In (u = radius, v = angle) order so that d/du x d/dv points up.
    grid(n_r, n_theta, |v, u| at(&z0, u, v), |v, u| at(&z1, u, v))
}

/// Two turns of a helicoid, pitch 0.4; during the step the upper turn (angle > 2 pi + 1) sinks
/// by 0.6 through the turn below.
pub fn sinking_helicoid() -> Step<'static> {
    sinking_helicoid_with(160)
}

/// [`sinking_helicoid`] with `n_theta` segments along the two turns. With an even count, every
/// vertex of the upper turn sinks exactly (up to rounding) through a vertex of the lower one: a
/// degenerate near-miss at distance ~1e-15 that the narrow phase reports conservatively, slowly.
pub fn sinking_helicoid_with(n_theta: u32) -> Step<'static> {
    let pitch = 0.4;
    ribbon(
        n_theta,
        4,
        2.0,
        |th| pitch * th / TAU,
        |th| pitch * th / TAU - 0.6 * ((th - TAU - 1.0) / 1.0).clamp(0.0, 1.0),
    )
}

/// A ribbon built so that every triangle faces away from the seed's centroid during the whole
/// step (flat landing, a rising turn), whose end dives through the landing at t=1: the paper's
/// criterion alone puts touching features in one cluster.
pub fn phi_adversarial_helicoid() -> Step<'static> {
    let landing = 1.2 * PI;
    let peak = TAU + 0.05;
    let h = 0.15;
    let height = h * (peak - landing);
    let z0 = move |th: f64| h * (th - landing).max(0.0);
    let z1 = move |th: f64| {
        if th <= peak {
            z0(th)
        } else {
            height - 1.3 * height * (th - peak)
        }
    };
    ribbon(220, 3, (peak + 1.0) / TAU, z0, z1)
}

/// Flat at t=0; at t=1 the part x > 0 wraps over a hinge of radius 0.05 and dives back through
/// the part x < 0.
pub fn tight_fold() -> Step<'static> {
    let rho = 0.05;
    let fold = move |u: f64, v: f64| {
        let x = 2.0 * u - 1.0;
        let y = v;
        if x <= 0.0 {
            DVec3::new(x, y, 0.0)
        } else if x <= PI * rho {
            let a = x / rho;
            DVec3::new(rho * a.sin(), y, rho * (1.0 - a.cos()))
        } else {
            let s = x - PI * rho;
            DVec3::new(-s, y, 2.0 * rho - 0.3 * s)
        }
    };
    grid(40, 12, |u, v| DVec3::new(2.0 * u - 1.0, v, 0.0), fold)
}

/// A flat `n x n` sheet crumpled at t=1 by per-vertex noise of the order of the cell size on
/// top of a smooth wave (seeded).
pub fn crumpled(n: usize, seed: u64) -> Step<'static> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let noise: Vec<DVec3> = (0..(n + 1) * (n + 1))
        .map(|_| {
            DVec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
        })
        .collect();
    let idx = move |u: f64, v: f64| {
        ((v * n as f64).round() as usize) * (n + 1) + (u * n as f64).round() as usize
    };
    let h = 1.0 / n as f64;
    grid(
        n as u32,
        n as u32,
        |u, v| DVec3::new(u, v, 0.0),
        |u, v| {
            let e = noise[idx(u, v)];
            DVec3::new(
                u + 0.8 * h * e.x,
                v + 0.8 * h * e.y,
                1.5 * h * e.z + 0.3 * (6.0 * u).sin() * v,
            )
        },
    )
}

/// Two pieces of a sheet cut along x = 0 (vertices duplicated): during the step the right piece
/// slides left over the cut and tilts down through the left piece.
pub fn torn_pieces() -> Step<'static> {
    let left = grid(
        12,
        16,
        |u, v| DVec3::new(u - 1.0, v, 0.0),
        |u, v| DVec3::new(u - 1.0, v, 0.0),
    );
    let right = grid(
        12,
        16,
        |u, v| DVec3::new(u, v, 0.0),
        |u, v| DVec3::new(u - 0.4, v, 0.12 * (u - 0.2)),
    );
    let off = left.vertex_count() as u32;
    let x0 = [left.pos0(), right.pos0()].concat();
    let x1 = [left.pos1(), right.pos1()].concat();
    let tris: Vec<[u32; 3]> = left
        .triangles()
        .iter()
        .copied()
        .chain(right.triangles().iter().map(|t| t.map(|i| i + off)))
        .collect();
    Step::new(x0, x1, tris).expect("valid")
}

/// A 24 x 16 sheet torn along x = 1/2 from the bottom up to 5/8 of its height: the column of
/// vertices on the tear is duplicated, the right flap uses the copies. During the step the right
/// flap swings left over the tear and down through the left flap.
pub fn partial_tear() -> Step<'static> {
    let (nu, nv) = (24u32, 16u32);
    let tear_top = 10u32;
    let sheet = grid(
        nu,
        nv,
        |u, v| DVec3::new(u, v, 0.0),
        |u, v| DVec3::new(u, v, 0.0),
    );
    let mut x0 = sheet.pos0().to_vec();
    let mut x1 = sheet.pos1().to_vec();
    let id = |i: u32, j: u32| j * (nu + 1) + i;
    let mut copy = std::collections::HashMap::new();
    for j in 0..tear_top {
        copy.insert(id(nu / 2, j), x0.len() as u32);
        x0.push(x0[id(nu / 2, j) as usize]);
        x1.push(x1[id(nu / 2, j) as usize]);
    }
    let tris: Vec<[u32; 3]> = sheet
        .triangles()
        .iter()
        .map(|t| {
            let right = t.iter().any(|&v| v % (nu + 1) > nu / 2);
            t.map(|v| {
                if right {
                    *copy.get(&v).unwrap_or(&v)
                } else {
                    v
                }
            })
        })
        .collect();
    // Deform the right flap: below the tear top, move left and down, more so further down.
    for (v, p) in x1.iter_mut().enumerate() {
        let is_right = (v < sheet.vertex_count() && (v as u32 % (nu + 1)) > nu / 2)
            || v >= sheet.vertex_count();
        let h = p.y / (tear_top as f64 / nv as f64);
        if is_right && h < 1.0 {
            let w = 1.0 - h;
            p.x -= 0.3 * w;
            p.z += 0.2 * w * (p.x - 0.45);
        }
    }
    Step::new(x0, x1, tris).expect("valid")
}

/// A sheet or blob under a random smooth deformation large enough to fold it through itself
/// (seeded): a sphere when `seed % 3 == 2`, else a grid.
pub fn random_smooth(seed: u64) -> Step<'static> {
    let mut rng = ChaCha8Rng::seed_from_u64(1000 + seed);
    let amp: [f64; 3] = [0.0, 1.0, 2.0].map(|_| rng.random_range(0.05..0.6));
    let freq: [f64; 3] = [0.0, 1.0, 2.0].map(|_| rng.random_range(2.0..9.0));
    let phase: [f64; 3] = [0.0, 1.0, 2.0].map(|_| rng.random_range(0.0..TAU));
    let warp = move |p: DVec3| {
        p + DVec3::new(
            amp[0] * (freq[0] * p.y + phase[0]).sin(),
            amp[1] * (freq[1] * p.z + phase[1]).sin(),
            amp[2] * (freq[2] * p.x + phase[2]).sin(),
        )
    };
    if seed % 3 == 2 {
        sphere(10, 16, |p| p, warp)
    } else {
        grid(
            14,
            10,
            |u, v| DVec3::new(u, v, 0.1 * (3.0 * u).sin()),
            move |u, v| warp(DVec3::new(u, v, 0.1 * (3.0 * u).sin())),
        )
    }
}

/// Frame `k` of `frames` of a sheet (or, for odd `seed`, a sphere) deformed ever more by a
/// random smooth warp: mild at first, folding through itself by the end.
pub fn warped_frame(seed: u64, k: usize, frames: usize) -> impl Fn(DVec3) -> DVec3 {
    let mut rng = ChaCha8Rng::seed_from_u64(2000 + seed);
    let amp: [f64; 3] = [0; 3].map(|_| rng.random_range(0.2..0.7));
    let freq: [f64; 3] = [0; 3].map(|_| rng.random_range(2.0..9.0));
    let phase: [f64; 3] = [0; 3].map(|_| rng.random_range(0.0..TAU));
    let s = k as f64 / (frames - 1) as f64;
    move |p: DVec3| {
        p + s * DVec3::new(
            amp[0] * (freq[0] * p.y + phase[0]).sin(),
            amp[1] * (freq[1] * p.z + phase[1]).sin(),
            amp[2] * (freq[2] * p.x + phase[2]).sin(),
        )
    }
}

/// Step `k` (frame `k` to `k + 1`) of the sequence of [`warped_frame`].
pub fn warped_step(seed: u64, k: usize, frames: usize) -> Step<'static> {
    let (a, b) = (
        warped_frame(seed, k, frames),
        warped_frame(seed, k + 1, frames),
    );
    if seed % 2 == 1 {
        sphere(10, 16, a, b)
    } else {
        let sheet = |u: f64, v: f64| DVec3::new(u, v, 0.1 * (3.0 * u).sin());
        grid(
            14,
            10,
            move |u, v| a(sheet(u, v)),
            move |u, v| b(sheet(u, v)),
        )
    }
}

/// `Mode::Earliest` reports exactly the pairs of `Mode::All` whose time of impact is within the
/// tolerance of the earliest, with the same times.
pub fn assert_earliest_pairs(all: &Report, earliest: &Report, tolerance: f64, what: &str) {
    let cut = all
        .earliest_toi()
        .map_or(f64::NEG_INFINITY, |t| t + tolerance);
    let vf: Vec<_> = all.vf.iter().filter(|c| c.toi <= cut).copied().collect();
    let ee: Vec<_> = all.ee.iter().filter(|c| c.toi <= cut).copied().collect();
    assert_eq!(earliest.vf, vf, "{what}: the earliest vertex-face pairs");
    assert_eq!(earliest.ee, ee, "{what}: the earliest edge-edge pairs");
    assert_eq!(
        earliest.contact_count() > 0,
        all.earliest.is_some(),
        "{what}"
    );
}
