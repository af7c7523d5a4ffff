//! Tests of the collision set and the potential: derivatives against central finite
//! differences, the PSD projection against eigenvalues, an analytic case, and the set
//! against a brute-force oracle written plainly (every primitive pair, ipctk's rules).

// Index loops over small fixed-size arrays read as the formulas do.
#![allow(clippy::needless_range_loop)]

use std::collections::BTreeMap;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;
use crate::distance::EdgeEdgeType;
use crate::math::DVec3;
use crate::{Ccd, Configuration};

/// The distances' derivatives the potential uses, from `crate::distance`, in the shape the
/// checks below take.
mod deriv {
    use crate::distance::*;
    use crate::math::DVec3;

    pub(super) struct Local<const N: usize> {
        pub d2: f64,
        pub g: [f64; N],
        pub h: [[f64; N]; N],
    }

    pub(super) fn vv(p: [DVec3; 2], _hess: bool) -> Local<6> {
        Local {
            d2: point_point_distance(p[0], p[1]),
            g: point_point_distance_gradient(p[0], p[1]),
            h: point_point_distance_hessian(p[0], p[1]),
        }
    }

    pub(super) fn ev(p: [DVec3; 3], _hess: bool) -> Local<9> {
        Local {
            d2: point_line_distance(p[0], p[1], p[2]),
            g: point_line_distance_gradient(p[0], p[1], p[2]),
            h: point_line_distance_hessian(p[0], p[1], p[2]),
        }
    }

    pub(super) fn fv(p: [DVec3; 4], _hess: bool) -> Local<12> {
        Local {
            d2: point_plane_distance(p[0], p[1], p[2], p[3]),
            g: point_plane_distance_gradient(p[0], p[1], p[2], p[3]),
            h: point_plane_distance_hessian(p[0], p[1], p[2], p[3]),
        }
    }

    pub(super) fn ee(p: [DVec3; 4], t: EdgeEdgeType, _hess: bool) -> Local<12> {
        Local {
            d2: edge_edge_distance_of_type(p[0], p[1], p[2], p[3], t),
            g: edge_edge_distance_gradient(p[0], p[1], p[2], p[3], t),
            h: edge_edge_distance_hessian(p[0], p[1], p[2], p[3], t),
        }
    }

    pub(super) fn mollifier(
        p: [DVec3; 4],
        eps: f64,
        _hess: bool,
    ) -> (f64, [f64; 12], [[f64; 12]; 12]) {
        (
            edge_edge_mollifier(p[0], p[1], p[2], p[3], eps),
            edge_edge_mollifier_gradient(p[0], p[1], p[2], p[3], eps),
            edge_edge_mollifier_hessian(p[0], p[1], p[2], p[3], eps),
        )
    }
}

fn rand_points<const P: usize>(rng: &mut ChaCha8Rng) -> [DVec3; P] {
    std::array::from_fn(|_| DVec3::new(rng.random(), rng.random(), rng.random()))
}

/// Checks a local gradient and Hessian against central differences of the value and the
/// gradient.
fn check_local<const P: usize, const N: usize>(
    p: [DVec3; P],
    f: impl Fn([DVec3; P]) -> deriv::Local<N>,
    tol: f64,
) {
    let l = f(p);
    let h = 1e-6;
    for i in 0..N {
        let mut a = p;
        let mut b = p;
        a[i / 3][i % 3] += h;
        b[i / 3][i % 3] -= h;
        let (la, lb) = (f(a), f(b));
        let fd = (la.d2 - lb.d2) / (2.0 * h);
        let scale = 1.0 + l.g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(
            (fd - l.g[i]).abs() < tol * scale,
            "gradient {i}: {fd} vs {}",
            l.g[i]
        );
        for j in 0..N {
            let fd = (la.g[j] - lb.g[j]) / (2.0 * h);
            let hs = 1.0 + l.h.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(
                (fd - l.h[i][j]).abs() < tol * hs,
                "hessian {i} {j}: {fd} vs {}",
                l.h[i][j]
            );
            assert!(
                (l.h[i][j] - l.h[j][i]).abs() < 1e-10 * hs,
                "symmetry {i} {j}"
            );
        }
    }
}

#[test]
fn distance_derivatives_match_finite_differences() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..200 {
        check_local(rand_points::<2>(&mut rng), |p| deriv::vv(p, true), 1e-6);
        check_local(rand_points::<3>(&mut rng), |p| deriv::ev(p, true), 1e-5);
        check_local(rand_points::<4>(&mut rng), |p| deriv::fv(p, true), 1e-4);
        let p = rand_points::<4>(&mut rng);
        for k in 0..9u8 {
            let t: EdgeEdgeType = unsafe_type(k);
            check_local(p, |q| deriv::ee(q, t, true), 1e-4);
        }
    }
}

fn unsafe_type(k: u8) -> EdgeEdgeType {
    use EdgeEdgeType::*;
    [
        Ea0Eb0, Ea0Eb1, Ea1Eb0, Ea1Eb1, EaEb0, EaEb1, Ea0Eb, Ea1Eb, EaEb,
    ][k as usize]
}

#[test]
fn distance_values_match_the_robust_kernels() {
    // The squared distances of the true types equal the robust kernels' distances.
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for _ in 0..1000 {
        let p = rand_points::<4>(&mut rng);
        let (d, ty) = crate::distance::point_triangle_distance(p[0], p[1], p[2], p[3]);
        if ty == crate::distance::PointTriangleType::Interior {
            assert!((deriv::fv(p, false).d2 - d).abs() < 1e-12);
        }
        let (d, ty) = crate::distance::edge_edge_distance(p[0], p[1], p[2], p[3]);
        assert!((deriv::ee(p, ty, false).d2 - d).abs() < 1e-12);
    }
}

#[test]
fn mollifier_derivatives_match_finite_differences() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..200 {
        let mut p = rand_points::<4>(&mut rng);
        // Nearly parallel edges, inside the mollifier's range.
        p[3] = p[2]
            + (p[1] - p[0]) * 0.7
            + DVec3::new(0.5, -0.6, 0.7) * (0.01 * (p[1] - p[0]).length());
        let eps = 1e-3 * (p[1] - p[0]).length_squared() * (p[3] - p[2]).length_squared();
        let (m, g, hm) = deriv::mollifier(p, eps, true);
        assert!(m > 0.0 && m < 1.0);
        let h = 1e-7;
        for i in 0..12 {
            let (mut a, mut b) = (p, p);
            a[i / 3][i % 3] += h;
            b[i / 3][i % 3] -= h;
            let (ma, ga, _) = deriv::mollifier(a, eps, true);
            let (mb, gb, _) = deriv::mollifier(b, eps, true);
            let gs = 1.0 + g.iter().fold(0.0f64, |x, v| x.max(v.abs()));
            assert!(((ma - mb) / (2.0 * h) - g[i]).abs() < 1e-5 * gs);
            for j in 0..12 {
                let hs = 1.0 + hm.iter().flatten().fold(0.0f64, |x, v| x.max(v.abs()));
                assert!(((ga[j] - gb[j]) / (2.0 * h) - hm[i][j]).abs() < 1e-5 * hs);
            }
        }
    }
}

/// A random scene: small triangles (pairs sharing an edge), free edges and free points,
/// in a box of size 1, with `dhat` 0.1.
type Scene = (Vec<[f64; 3]>, Vec<[u32; 3]>, Vec<[u32; 2]>);

fn scene(seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut x = Vec::new();
    let mut f = Vec::new();
    let r = |rng: &mut ChaCha8Rng, s: f64| -> [f64; 3] {
        std::array::from_fn(|_| s * (rng.random::<f64>() - 0.5))
    };
    for _ in 0..12 {
        let c = r(&mut rng, 1.0);
        let base = x.len() as u32;
        for _ in 0..4 {
            let d = r(&mut rng, 0.3);
            x.push([c[0] + d[0], c[1] + d[1], c[2] + d[2]]);
        }
        f.push([base, base + 1, base + 2]);
        f.push([base + 1, base, base + 3]);
    }
    let mut e = Vec::new();
    for _ in 0..6 {
        let c = r(&mut rng, 1.0);
        let d = r(&mut rng, 0.3);
        let i = x.len() as u32;
        x.push(c);
        x.push([c[0] + d[0], c[1] + d[1], c[2] + d[2]]);
        e.push([i, i + 1]);
    }
    for _ in 0..6 {
        x.push(r(&mut rng, 1.0));
    }
    (x, f, e)
}

/// The oracle: every primitive pair of the configuration (vertex-face, edge-edge, free
/// point-free edge, free point-free point), each reduced by ipctk's rules and merged.
/// Keys by vertex ids; the value is the summed weight.
fn oracle(
    x: &[[f64; 3]],
    f: &[[u32; 3]],
    free: &[[u32; 2]],
    options: &CollisionOptions,
) -> [BTreeMap<Vec<u32>, f64>; 4] {
    use super::types::*;
    let p = |v: u32| DVec3::from(x[v as usize]);
    let n = x.len();
    let mut edges: Vec<[u32; 2]> = Vec::new();
    for t in f {
        for k in 0..3 {
            let (a, b) = (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]));
            if !edges.contains(&[a, b]) {
                edges.push([a, b]);
            }
        }
    }
    for &[a, b] in free {
        if !edges.contains(&[a.min(b), a.max(b)]) {
            edges.push([a.min(b), a.max(b)]);
        }
    }
    let in_face = |v: u32| f.iter().any(|t| t.contains(&v));
    let in_edge = |v: u32| edges.iter().any(|e| e.contains(&v));
    let tri_area = |t: &[u32; 3]| 0.5 * (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length();
    let varea = |v: u32| -> f64 {
        if in_face(v) {
            f.iter()
                .filter(|t| t.contains(&v))
                .map(|t| tri_area(t) / 3.0)
                .sum()
        } else if in_edge(v) {
            edges
                .iter()
                .filter(|e| e.contains(&v))
                .map(|e| 0.5 * (p(e[0]) - p(e[1])).length())
                .sum()
        } else {
            1.0
        }
    };
    let earea = |e: [u32; 2]| -> f64 {
        let fs: Vec<_> = f
            .iter()
            .filter(|t| t.contains(&e[0]) && t.contains(&e[1]))
            .collect();
        if fs.is_empty() {
            (p(e[0]) - p(e[1])).length()
        } else {
            fs.iter().map(|t| tri_area(t) / 3.0).sum()
        }
    };
    let aw = options.use_area_weighting;
    let r = options.dhat + options.dmin;
    let mut out: [BTreeMap<Vec<u32>, f64>; 4] = Default::default();
    let mut add = |k: usize, mut key: Vec<u32>, w: f64| {
        if k == 0 {
            key.sort();
        }
        if k == 1 {
            key[..2].sort();
        }
        *out[k].entry(key).or_insert(0.0) += w;
    };
    // Vertex-face.
    for v in 0..n as u32 {
        for t in f {
            if t.contains(&v) {
                continue;
            }
            let [a, b, c] = t.map(p);
            let ty = point_triangle_type(p(v), a, b, c);
            if point_triangle_sq(p(v), a, b, c, ty) >= r * r {
                continue;
            }
            let w = if aw { 0.25 * varea(v) } else { 1.0 };
            use crate::distance::PointTriangleType::*;
            match ty {
                T0 => add(0, vec![v, t[0]], w),
                T1 => add(0, vec![v, t[1]], w),
                T2 => add(0, vec![v, t[2]], w),
                E0 => add(1, vec![t[0], t[1], v], w),
                E1 => add(1, vec![t[1], t[2], v], w),
                E2 => add(1, vec![t[2], t[0], v], w),
                Interior => add(3, vec![t[0], t[1], t[2], v], w),
            }
        }
    }
    // Edge-edge.
    for (i, ea) in edges.iter().enumerate() {
        for eb in &edges[i + 1..] {
            if ea.iter().any(|v| eb.contains(v)) {
                continue;
            }
            let (ea, eb) = if ea < eb { (*ea, *eb) } else { (*eb, *ea) };
            let q = [ea[0], ea[1], eb[0], eb[1]].map(p);
            let ty = edge_edge_type(q[0], q[1], q[2], q[3]);
            if edge_edge_sq(q[0], q[1], q[2], q[3], ty) >= r * r {
                continue;
            }
            let w = if aw {
                0.25 * (earea(ea) + earea(eb))
            } else {
                1.0
            };
            let eps = 1e-3 * (q[1] - q[0]).length_squared() * (q[3] - q[2]).length_squared();
            if (q[1] - q[0]).cross(q[3] - q[2]).length_squared() < eps {
                add(2, vec![ea[0], ea[1], eb[0], eb[1], ty as u32], w);
                continue;
            }
            use EdgeEdgeType::*;
            match ty {
                Ea0Eb0 => add(0, vec![ea[0], eb[0]], w),
                Ea0Eb1 => add(0, vec![ea[0], eb[1]], w),
                Ea1Eb0 => add(0, vec![ea[1], eb[0]], w),
                Ea1Eb1 => add(0, vec![ea[1], eb[1]], w),
                EaEb0 => add(1, vec![ea[0], ea[1], eb[0]], w),
                EaEb1 => add(1, vec![ea[0], ea[1], eb[1]], w),
                Ea0Eb => add(1, vec![eb[0], eb[1], ea[0]], w),
                Ea1Eb => add(1, vec![eb[0], eb[1], ea[1]], w),
                EaEb => add(2, vec![ea[0], ea[1], eb[0], eb[1], ty as u32], w),
            }
        }
    }
    // Free points against free edges and free points.
    let free_pt = |v: u32| !in_face(v) && !in_edge(v);
    for v in (0..n as u32).filter(|&v| free_pt(v)) {
        for e in edges
            .iter()
            .filter(|e| !f.iter().any(|t| t.contains(&e[0]) && t.contains(&e[1])))
        {
            let ty = point_edge_type(p(v), p(e[0]), p(e[1]));
            if point_edge_sq(p(v), p(e[0]), p(e[1]), ty) >= r * r {
                continue;
            }
            let w = if aw { 0.5 * varea(v) } else { 1.0 };
            match ty {
                crate::distance::PointEdgeType::E0 => add(0, vec![v, e[0]], w),
                crate::distance::PointEdgeType::E1 => add(0, vec![v, e[1]], w),
                crate::distance::PointEdgeType::Interior => add(1, vec![e[0], e[1], v], w),
            }
        }
        for u in (v + 1..n as u32).filter(|&u| free_pt(u)) {
            if (p(u) - p(v)).length_squared() < r * r {
                let w = if aw { 0.5 * (varea(u) + varea(v)) } else { 1.0 };
                add(0, vec![v, u], w);
            }
        }
    }
    out
}

fn ours(c: &NormalCollisions) -> [BTreeMap<Vec<u32>, f64>; 4] {
    let mut out: [BTreeMap<Vec<u32>, f64>; 4] = Default::default();
    for v in &c.vv {
        out[0].insert(v.vertices.to_vec(), v.weight);
    }
    for v in &c.ev {
        let mut k = vec![v.edge[0], v.edge[1], v.vertex];
        k[..2].sort();
        out[1].insert(k, v.weight);
    }
    for v in &c.ee {
        out[2].insert(
            vec![v.a[0], v.a[1], v.b[0], v.b[1], v.kind as u32],
            v.weight,
        );
    }
    for v in &c.fv {
        out[3].insert(
            vec![v.triangle[0], v.triangle[1], v.triangle[2], v.vertex],
            v.weight,
        );
    }
    out
}

#[test]
fn collision_set_matches_the_brute_force_oracle() {
    let mut total = [0usize; 4];
    for seed in 0..20 {
        let (x, f, e) = scene(seed);
        let config = Configuration::new(&x, &f, &e).unwrap();
        for aw in [false, true] {
            let options = CollisionOptions {
                dhat: 0.1,
                use_area_weighting: aw,
                ..Default::default()
            };
            let c = NormalCollisions::build(&mut Ccd::new(), &config, &x, &options).unwrap();
            let (a, b) = (ours(&c), oracle(&x, &f, &e, &options));
            for k in 0..4 {
                assert_eq!(
                    a[k].keys().collect::<Vec<_>>(),
                    b[k].keys().collect::<Vec<_>>(),
                    "seed {seed} kind {k}"
                );
                for (key, w) in &a[k] {
                    assert!(
                        (w - b[k][key]).abs() < 1e-12 * w.abs().max(1.0),
                        "weight {key:?}"
                    );
                }
                total[k] += a[k].len();
            }
        }
    }
    // The scenes exercise every kind.
    assert!(total.iter().all(|&t| t > 0), "{total:?}");
}

/// A vertex near an edge shared by two faces: one edge-vertex collision of weight 2
/// (both faces report it), and the energy is twice that of one.
#[test]
fn shared_edge_merges_with_multiplicity() {
    let x = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, 1.0, 0.0],
        [0.5, -1.0, 0.0],
        [0.5, 0.0, 1e-3],
    ];
    let f = [[0u32, 1, 2], [1, 0, 3]];
    let config = Configuration::new(&x, &f, &[]).unwrap();
    let options = CollisionOptions {
        dhat: 1e-2,
        ..Default::default()
    };
    let c = NormalCollisions::build(&mut Ccd::new(), &config, &x, &options).unwrap();
    assert_eq!(
        (c.vv.len(), c.ev.len(), c.ee.len(), c.fv.len()),
        (0, 1, 0, 0)
    );
    assert_eq!(c.ev[0].weight, 2.0);
    let b = BarrierPotential::new(1e-2, 3.0);
    let expected = 2.0 * 3.0 * Barrier::ClampedLog.value(1e-6, 1e-4);
    assert!((b.energy(&c, &x) - expected).abs() < 1e-12 * expected);
}

#[test]
fn point_over_triangle_energy_is_kappa_b() {
    for z in [1e-4, 3e-4, 9e-4] {
        let x = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.25, 0.25, z],
        ];
        let config = Configuration::new(&x, &[[0u32, 1, 2]], &[]).unwrap();
        let options = CollisionOptions {
            dhat: 1e-3,
            ..Default::default()
        };
        let c = NormalCollisions::build(&mut Ccd::new(), &config, &x, &options).unwrap();
        assert_eq!(c.fv.len(), 1);
        for barrier in [
            Barrier::ClampedLog,
            Barrier::NormalizedClampedLog,
            Barrier::ClampedLogSq,
            Barrier::Cubic,
        ] {
            let b = BarrierPotential {
                barrier,
                ..BarrierPotential::new(1e-3, 7.0)
            };
            let e = 7.0 * barrier.value(z * z, 1e-6);
            assert!((b.energy(&c, &x) - e).abs() <= 1e-12 * e.abs());
            // The gradient on z is 2 z kappa b'(z^2); the triangle gets the opposite.
            let g = b.gradient(&c, &x);
            let gz = 2.0 * z * 7.0 * barrier.first_derivative(z * z, 1e-6);
            assert!((g[11] - gz).abs() <= 1e-9 * gz.abs());
            assert!((g[2] + g[5] + g[8] + gz).abs() <= 1e-9 * gz.abs());
        }
        assert!((c.minimum_distance(&x) - z).abs() < 1e-15);
        assert!((c.compute_minimum_distance(&x) - z * z).abs() < 1e-18);
    }
}

#[test]
fn barrier_derivatives_match_finite_differences() {
    for barrier in [
        Barrier::ClampedLog,
        Barrier::NormalizedClampedLog,
        Barrier::ClampedLogSq,
        Barrier::Cubic,
    ] {
        for d in [0.01, 0.1, 0.3, 0.7, 0.95] {
            let h = 1e-7;
            let fd1 = (barrier.value(d + h, 1.0) - barrier.value(d - h, 1.0)) / (2.0 * h);
            let fd2 = (barrier.first_derivative(d + h, 1.0) - barrier.first_derivative(d - h, 1.0))
                / (2.0 * h);
            let (d1, d2) = (
                barrier.first_derivative(d, 1.0),
                barrier.second_derivative(d, 1.0),
            );
            assert!(
                (fd1 - d1).abs() < 1e-5 * (1.0 + d1.abs()),
                "{barrier:?} {d}"
            );
            assert!(
                (fd2 - d2).abs() < 1e-5 * (1.0 + d2.abs()),
                "{barrier:?} {d}"
            );
        }
    }
}

/// The potential over a whole random scene: gradient against central differences of the
/// energy, Hessian against differences of the gradient, PSD projections without negative
/// eigenvalues.
#[test]
fn potential_derivatives_and_psd() {
    for seed in 0..4 {
        let (x, f, e) = scene(100 + seed);
        let config = Configuration::new(&x, &f, &e).unwrap();
        let options = CollisionOptions {
            dhat: 0.1,
            use_area_weighting: seed % 2 == 1,
            ..Default::default()
        };
        let c = NormalCollisions::build(&mut Ccd::new(), &config, &x, &options).unwrap();
        assert!(!c.is_empty());
        let b = BarrierPotential::new(0.1, 1.0);
        let g = b.gradient(&c, &x);
        let hm = b.hessian(&c, &x, PsdProjection::None);
        let h = 1e-7;
        let gnorm = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let hnorm = hm.triplets().fold(0.0f64, |m, t| m.max(t.2.abs()));
        for i in 0..3 * x.len() {
            let (mut a, mut bb) = (x.clone(), x.clone());
            a[i / 3][i % 3] += h;
            bb[i / 3][i % 3] -= h;
            let fd = (b.energy(&c, &a) - b.energy(&c, &bb)) / (2.0 * h);
            assert!(
                (fd - g[i]).abs() < 1e-5 * gnorm,
                "seed {seed} grad {i}: {fd} vs {}",
                g[i]
            );
            let (ga, gb) = (b.gradient(&c, &a), b.gradient(&c, &bb));
            for j in 0..3 * x.len() {
                let fd = (ga[j] - gb[j]) / (2.0 * h);
                assert!(
                    (fd - hm.get(i, j)).abs() < 1e-5 * hnorm,
                    "seed {seed} hess {i} {j}"
                );
            }
        }
        for m in [PsdProjection::Clamp, PsdProjection::Abs] {
            let hp = b.hessian(&c, &x, m);
            let n = hp.size();
            let dense = nalgebra::DMatrix::from_fn(n, n, |i, j| hp.get(i, j));
            let min = dense.symmetric_eigen().eigenvalues.min();
            assert!(min >= -1e-9 * hnorm, "{m:?}: {min}");
        }
    }
}

#[test]
fn stiffness_helpers_follow_their_formulas() {
    // kappa = -gb.ge / |gb|^2 inside the clamp.
    let k = initial_barrier_stiffness(
        1.0,
        Barrier::ClampedLog,
        1e-3,
        1e-6,
        &[2.0, 0.0],
        &[-1.0, 0.0],
        1e-11,
        0.0,
    );
    let d0 = 1e-16f64;
    let kmin = 1e-11 * 1e-6 / (4.0 * d0 * Barrier::ClampedLog.second_derivative(d0, 1e-6));
    assert!((k.max_stiffness - 100.0 * kmin).abs() < 1e-12 * k.max_stiffness);
    let want = 2.0f64.clamp(kmin, 100.0 * kmin);
    assert!((k.stiffness - want).abs() <= 1e-12 * want);
    assert_eq!(
        update_barrier_stiffness(1e-19, 1e-20, 10.0, 8.0, 1.0, 1e-9, 0.0),
        10.0
    );
    assert_eq!(
        update_barrier_stiffness(1e-20, 1e-19, 10.0, 8.0, 1.0, 1e-9, 0.0),
        8.0
    );
}

#[test]
fn bad_input_is_refused() {
    let x = [[0.0; 3]; 3];
    let config = Configuration::new(&x, &[[0u32, 1, 2]], &[]).unwrap();
    let mut ccd = Ccd::new();
    let bad = |o: CollisionOptions| {
        NormalCollisions::build(&mut Ccd::new(), &config, &x, &o).unwrap_err()
    };
    assert_eq!(
        bad(CollisionOptions {
            dhat: 0.0,
            ..Default::default()
        }),
        IpcError::Dhat(0.0)
    );
    assert_eq!(
        bad(CollisionOptions {
            enable_shape_derivatives: true,
            ..Default::default()
        }),
        IpcError::ShapeDerivatives
    );
    let err = NormalCollisions::build(&mut ccd, &config, &x[..2], &CollisionOptions::default());
    assert!(matches!(
        err,
        Err(IpcError::RestPositions {
            got: 2,
            vertices: 3
        })
    ));
}

#[test]
fn sparse_assembly_matches_triplets() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let ids = [0u32, 3, 1, 3, 2];
    let offsets = [0usize, 3, 5];
    let vals: Vec<f64> = (0..81 + 36).map(|_| rng.random::<f64>()).collect();
    let m = SparseMatrix::from_vertex_blocks(4, &ids, &offsets, &vals);
    let mut trip = Vec::new();
    let mut off = 0;
    for w in offsets.windows(2) {
        let s = &ids[w[0]..w[1]];
        let k = 3 * s.len();
        for i in 0..k {
            for j in 0..k {
                trip.push((
                    3 * s[i / 3] as usize + i % 3,
                    3 * s[j / 3] as usize + j % 3,
                    vals[off + i * k + j],
                ));
            }
        }
        off += k * k;
    }
    let t = SparseMatrix::from_triplets(12, trip);
    assert_eq!(m.nnz(), t.nnz());
    for ((a, b, v), (c, d, w)) in m.triplets().zip(t.triplets()) {
        assert_eq!((a, b), (c, d));
        assert!((v - w).abs() < 1e-14);
    }
}
