//! The closed-form derivatives of the squared distances against second-order dual numbers
//! (num-dual) of an independent generic implementation, on 10,000 seeded random pairs per
//! type (degenerate and boundary cases included), and against central finite differences.
//!
//! The reference is written here from the definitions, not from the library: the distance
//! from a point to a line as the norm of the rejection from the line, to a plane and between
//! lines as the projection on the normal `u x v`, the mollifier from its polynomial, each
//! generic over the dual number type.
// The reference is generic over the dual type, whose values it clones; the Hessian loops
// index two arrays at once.
#![allow(clippy::clone_on_copy, clippy::needless_range_loop)]

use nalgebra::SVector;
use num_dual::{hessian, Dual2SVec64, DualNum};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use topoccd::distance::*;
use topoccd::math::DVec3;

// ---------------------------------------------------------------------------------------
// The independent reference, generic over the number type.

type V<T> = [T; 3];

fn sub<T: DualNum<f64>>(a: &V<T>, b: &V<T>) -> V<T> {
    [
        a[0].clone() - &b[0],
        a[1].clone() - &b[1],
        a[2].clone() - &b[2],
    ]
}

fn dot<T: DualNum<f64>>(a: &V<T>, b: &V<T>) -> T {
    a[0].clone() * &b[0] + a[1].clone() * &b[1] + a[2].clone() * &b[2]
}

fn cross<T: DualNum<f64>>(a: &V<T>, b: &V<T>) -> V<T> {
    [
        a[1].clone() * &b[2] - a[2].clone() * &b[1],
        a[2].clone() * &b[0] - a[0].clone() * &b[2],
        a[0].clone() * &b[1] - a[1].clone() * &b[0],
    ]
}

fn ref_point_point<T: DualNum<f64>>(p: &V<T>, q: &V<T>) -> T {
    let d = sub(p, q);
    dot(&d, &d)
}

/// The squared norm of the rejection of `p - e0` from the line's direction.
fn ref_point_line<T: DualNum<f64>>(p: &V<T>, e0: &V<T>, e1: &V<T>) -> T {
    let (r, u) = (sub(p, e0), sub(e1, e0));
    let t = dot(&r, &u) / dot(&u, &u);
    let w = [
        r[0].clone() - u[0].clone() * &t,
        r[1].clone() - u[1].clone() * &t,
        r[2].clone() - u[2].clone() * &t,
    ];
    dot(&w, &w)
}

/// The squared projection of `r` on the normal of `u` and `v`.
fn ref_projection<T: DualNum<f64>>(r: &V<T>, u: &V<T>, v: &V<T>) -> T {
    let n = cross(u, v);
    let s = dot(r, &n);
    s.clone() * s / dot(&n, &n)
}

/// The sub-distance of a type, from ipctk's tables: `Pp(i, j)` point-point, `Pl(i, a, b)`
/// point `i` to the line `a b`, `Plane` point 0 to plane 1 2 3, `Lines` line 0 1 to line 2 3.
#[derive(Clone, Copy, Debug)]
enum Sub {
    Pp(usize, usize),
    Pl(usize, usize, usize),
    Plane,
    Lines,
}

fn ref_sub<T: DualNum<f64>>(x: &[V<T>], sub_: Sub) -> T {
    match sub_ {
        Sub::Pp(i, j) => ref_point_point(&x[i], &x[j]),
        Sub::Pl(i, a, b) => ref_point_line(&x[i], &x[a], &x[b]),
        Sub::Plane => ref_projection(&sub(&x[0], &x[1]), &sub(&x[2], &x[1]), &sub(&x[3], &x[1])),
        Sub::Lines => ref_projection(&sub(&x[2], &x[0]), &sub(&x[1], &x[0]), &sub(&x[3], &x[2])),
    }
}

const PE_TYPES: [(PointEdgeType, Sub); 3] = [
    (PointEdgeType::E0, Sub::Pp(0, 1)),
    (PointEdgeType::E1, Sub::Pp(0, 2)),
    (PointEdgeType::Interior, Sub::Pl(0, 1, 2)),
];

const PT_TYPES: [(PointTriangleType, Sub); 7] = [
    (PointTriangleType::T0, Sub::Pp(0, 1)),
    (PointTriangleType::T1, Sub::Pp(0, 2)),
    (PointTriangleType::T2, Sub::Pp(0, 3)),
    (PointTriangleType::E0, Sub::Pl(0, 1, 2)),
    (PointTriangleType::E1, Sub::Pl(0, 2, 3)),
    (PointTriangleType::E2, Sub::Pl(0, 3, 1)),
    (PointTriangleType::Interior, Sub::Plane),
];

const EE_TYPES: [(EdgeEdgeType, Sub); 9] = [
    (EdgeEdgeType::Ea0Eb0, Sub::Pp(0, 2)),
    (EdgeEdgeType::Ea0Eb1, Sub::Pp(0, 3)),
    (EdgeEdgeType::Ea1Eb0, Sub::Pp(1, 2)),
    (EdgeEdgeType::Ea1Eb1, Sub::Pp(1, 3)),
    (EdgeEdgeType::EaEb0, Sub::Pl(2, 0, 1)),
    (EdgeEdgeType::EaEb1, Sub::Pl(3, 0, 1)),
    (EdgeEdgeType::Ea0Eb, Sub::Pl(0, 2, 3)),
    (EdgeEdgeType::Ea1Eb, Sub::Pl(1, 2, 3)),
    (EdgeEdgeType::EaEb, Sub::Lines),
];

/// Value, gradient and Hessian of `f` over the `P` points `x` (`N = 3 P` coordinates), by
/// dual numbers.
fn dual<const N: usize>(
    x: &[DVec3],
    f: impl Fn(&[V<Dual2SVec64<N>>]) -> Dual2SVec64<N>,
) -> (f64, [f64; N], [[f64; N]; N]) {
    let flat: SVector<f64, N> = SVector::from_iterator(x.iter().flat_map(|p| p.to_array()));
    let (v, g, h) = hessian(
        |c: SVector<Dual2SVec64<N>, N>| {
            let pts: Vec<V<Dual2SVec64<N>>> = (0..N / 3)
                .map(|j| [c[3 * j].clone(), c[3 * j + 1].clone(), c[3 * j + 2].clone()])
                .collect();
            f(&pts)
        },
        &flat,
    );
    let mut ga = [0.0; N];
    let mut ha = [[0.0; N]; N];
    for i in 0..N {
        ga[i] = g[i];
        for j in 0..N {
            ha[i][j] = h[(i, j)];
        }
    }
    (v, ga, ha)
}

// ---------------------------------------------------------------------------------------
// Comparison.

/// The largest discrepancy of a value, gradient and Hessian, each relative to the
/// reference's magnitude with a floor in the pair's units (`l^2`, `l`, 1 for a squared
/// distance of a pair of extent `l`; pass `l = 1` for dimensionless functions).
#[derive(Clone, Copy, Debug, Default)]
struct Err {
    value: f64,
    gradient: f64,
    hessian: f64,
}

impl Err {
    fn max(self, o: Err) -> Err {
        Err {
            value: self.value.max(o.value),
            gradient: self.gradient.max(o.gradient),
            hessian: self.hessian.max(o.hessian),
        }
    }
    fn worst(self) -> f64 {
        self.value.max(self.gradient).max(self.hessian)
    }
}

fn rel_err<const N: usize>(
    ours: (f64, &[f64; N], &[[f64; N]; N]),
    reference: (f64, &[f64; N], &[[f64; N]; N]),
    floors: [f64; 3],
) -> Err {
    let maxabs = |it: &mut dyn Iterator<Item = f64>| it.fold(0.0f64, |m, x| m.max(x.abs()));
    let gmag = maxabs(&mut reference.1.iter().copied()).max(floors[1]);
    let hmag = maxabs(&mut reference.2.iter().flatten().copied()).max(floors[2]);
    let gerr = maxabs(&mut ours.1.iter().zip(reference.1).map(|(a, b)| a - b));
    let herr = maxabs(
        &mut ours
            .2
            .iter()
            .flatten()
            .zip(reference.2.iter().flatten())
            .map(|(a, b)| a - b),
    );
    Err {
        value: (ours.0 - reference.0).abs() / reference.0.abs().max(floors[0]),
        gradient: gerr / gmag,
        hessian: herr / hmag,
    }
}

fn assert_finite_symmetric<const N: usize>(g: &[f64; N], h: &[[f64; N]; N], what: &str) {
    assert!(g.iter().all(|x| x.is_finite()), "{what}: gradient {g:?}");
    for i in 0..N {
        for j in 0..N {
            assert!(h[i][j].is_finite(), "{what}: Hessian not finite");
            assert_eq!(
                h[i][j], h[j][i],
                "{what}: Hessian not symmetric at ({i}, {j})"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------
// Random pairs: generic, scaled, offset, near type boundaries, near degenerate.

const PAIRS: usize = 10_000;

/// The kinds of random pairs, cycled through.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Generic,
    Tiny,
    Huge,
    Offset,
    Boundary,
    Degenerate,
}

const KINDS: [Kind; 6] = [
    Kind::Generic,
    Kind::Tiny,
    Kind::Huge,
    Kind::Offset,
    Kind::Boundary,
    Kind::Degenerate,
];

fn unit(rng: &mut ChaCha8Rng) -> DVec3 {
    DVec3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    )
}

/// A unit vector at squared sine `s2` of angle from `a` (unit).
fn at_angle(rng: &mut ChaCha8Rng, a: DVec3, s2: f64) -> DVec3 {
    let perp = a.cross(unit(rng)).normalize();
    a * (1.0 - s2).sqrt() + perp * s2.sqrt()
}

/// `10^-e` with `e` uniform in `[lo, hi]`.
fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    10f64.powf(-rng.random_range(lo..hi))
}

/// Scales and shifts a pair by its kind.
fn place<const P: usize>(mut x: [DVec3; P], kind: Kind, rng: &mut ChaCha8Rng) -> [DVec3; P] {
    let (scale, shift) = match kind {
        Kind::Tiny => (1e-6, DVec3::ZERO),
        Kind::Huge => (1e6, DVec3::ZERO),
        Kind::Offset => (1.0, DVec3::splat(1e3) + unit(rng)),
        _ => (1.0, DVec3::ZERO),
    };
    for p in &mut x {
        *p = *p * scale + shift;
    }
    x
}

fn point_edge_pair(rng: &mut ChaCha8Rng, kind: Kind) -> [DVec3; 3] {
    let (e0, e1) = (unit(rng), unit(rng));
    let p = match kind {
        // The projection at an end, within 1e-8.
        Kind::Boundary => {
            let t = if rng.random_bool(0.5) { 0.0 } else { 1.0 } + rng.random_range(-1e-8..1e-8);
            let n = (e1 - e0).cross(unit(rng)).normalize();
            e0 + (e1 - e0) * t + n * rng.random_range(1e-3..1.0)
        }
        // Very short edges, or the point almost on the line.
        Kind::Degenerate => {
            if rng.random_bool(0.5) {
                return [unit(rng), e0, e0 + unit(rng) * log_uniform(rng, 4.0, 6.0)];
            }
            let n = (e1 - e0).cross(unit(rng)).normalize();
            e0 + (e1 - e0) * rng.random_range(0.0..1.0) + n * log_uniform(rng, 4.0, 7.0)
        }
        _ => unit(rng),
    };
    place([p, e0, e1], kind, rng)
}

fn point_triangle_pair(rng: &mut ChaCha8Rng, kind: Kind) -> [DVec3; 4] {
    let (t0, t1) = (unit(rng), unit(rng));
    let mut t2 = unit(rng);
    let bary = |rng: &mut ChaCha8Rng| {
        let (mut a, mut b) = (rng.random_range(0.0..1.0), rng.random_range(0.0..1.0));
        if a + b > 1.0 {
            (a, b) = (1.0 - a, 1.0 - b);
        }
        (a, b)
    };
    let p = match kind {
        // The projection on an edge or at a corner, within 1e-8.
        Kind::Boundary => {
            let (mut a, mut b) = bary(rng);
            let j = 1e-8;
            match rng.random_range(0..4) {
                0 => a = rng.random_range(-j..j),
                1 => b = rng.random_range(-j..j),
                2 => b = 1.0 - a + rng.random_range(-j..j),
                _ => (a, b) = (rng.random_range(-j..j), rng.random_range(-j..j)),
            }
            let n = (t1 - t0).cross(t2 - t0).normalize();
            t0 + (t1 - t0) * a + (t2 - t0) * b + n * rng.random_range(-1.0..1.0)
        }
        // Nearly collinear corners (squared sine of the angle at t0 down to 1e-12).
        Kind::Degenerate => {
            let u = (t1 - t0).normalize();
            let s2 = log_uniform(rng, 2.0, 12.0);
            let len = rng.random_range(0.1..1.0);
            t2 = t0 + at_angle(rng, u, s2) * len;
            unit(rng)
        }
        _ => unit(rng),
    };
    place([p, t0, t1, t2], kind, rng)
}

fn edge_edge_pair(rng: &mut ChaCha8Rng, kind: Kind) -> [DVec3; 4] {
    let (ea0, ea1, eb0) = (unit(rng), unit(rng), unit(rng));
    let eb1 = match kind {
        // Nearly parallel (squared sine down to 1e-12).
        Kind::Degenerate => {
            let u = (ea1 - ea0).normalize();
            let s2 = log_uniform(rng, 2.0, 12.0);
            let len = rng.random_range(0.1..1.5);
            eb0 + at_angle(rng, u, s2) * len
        }
        // The lines' closest points near an end of edge b.
        Kind::Boundary => {
            let eb1 = unit(rng);
            let (u, v, w) = (ea1 - ea0, eb1 - eb0, ea0 - eb0);
            let (a, b, c, d, e) = (u.dot(u), u.dot(v), v.dot(v), u.dot(w), v.dot(w));
            let t = (a * e - b * d) / (a * c - b * b);
            // Move eb0 to the line b point at t, within 1e-8: then t is near 0.
            let shift = v * (t + rng.random_range(-1e-8..1e-8));
            return place([ea0, ea1, eb0 + shift, eb1 + shift], kind, rng);
        }
        _ => unit(rng),
    };
    place([ea0, ea1, eb0, eb1], kind, rng)
}

/// The pair's extent: its largest coordinate difference.
fn extent(x: &[DVec3]) -> f64 {
    x.iter()
        .fold(0.0f64, |m, p| m.max((*p - x[0]).abs().max_element()))
}

/// The squared sine of the angle between two vectors.
fn sin2(u: DVec3, v: DVec3) -> f64 {
    u.cross(v).length_squared() / (u.length_squared() * v.length_squared())
}

/// The allowed discrepancy: 1e-9, widened for ill-conditioned formulas to `1e3 u` times
/// their condition number. Both sides compute the same exact function in floating point;
/// their rounding errors are each bounded by a small multiple of `u` times the condition
/// number, which for the normal-projection formulas (point-plane, line-line) grows as one
/// over the squared sine of the angle between `u` and `v`, and for point-line as the
/// squared ratio of the pair's extent to the edge length.
fn tolerance(cond: f64) -> f64 {
    1e-9f64.max(1e3 * f64::EPSILON * cond)
}

/// Condition number of the point-line formula of the points `x[i]`, `x[a]`, `x[b]`.
fn cond_line(x: &[DVec3], sub_: Sub, l: f64) -> f64 {
    match sub_ {
        Sub::Pl(_, a, b) => (l * l / (x[b] - x[a]).length_squared()).max(1.0),
        Sub::Plane => 1.0 / sin2(x[2] - x[1], x[3] - x[1]),
        Sub::Lines => 1.0 / sin2(x[1] - x[0], x[3] - x[2]),
        Sub::Pp(..) => 1.0,
    }
}

/// Runs the check for one kind of pair over its types; returns the worst error per type
/// (scaled by that pair's tolerance) and the worst raw error per type.
fn check_kind<const P: usize, const N: usize, Ty: Copy + std::fmt::Debug>(
    name: &str,
    types: &[(Ty, Sub)],
    gen: impl Fn(&mut ChaCha8Rng, Kind) -> [DVec3; P],
    ours: impl Fn(&[DVec3; P], Ty) -> (f64, [f64; N], [[f64; N]; N]),
    seed: u64,
) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut worst = vec![Err::default(); types.len()];
    let mut worst_well = vec![Err::default(); types.len()];
    for i in 0..PAIRS {
        let kind = KINDS[i % KINDS.len()];
        let x = gen(&mut rng, kind);
        let l = extent(&x);
        for (k, &(ty, sub_)) in types.iter().enumerate() {
            let (v, g, h) = ours(&x, ty);
            assert_finite_symmetric(&g, &h, name);
            let (rv, rg, rh) = dual::<N>(&x, |c| ref_sub(c, sub_));
            let e = rel_err((v, &g, &h), (rv, &rg, &rh), [l * l, l, 1.0]);
            let cond = cond_line(&x, sub_, l);
            let tol = tolerance(cond);
            assert!(
                e.worst() <= tol,
                "{name} {ty:?} pair {i} ({kind:?}, condition {cond:.1e}): {e:?} > {tol:.1e}\n{x:?}"
            );
            worst[k] = worst[k].max(e);
            if cond < 1e3 {
                worst_well[k] = worst_well[k].max(e);
            }
        }
    }
    for (k, (ty, _)) in types.iter().enumerate() {
        eprintln!(
            "{name} {ty:?}: max rel err all {:.1e} / {:.1e} / {:.1e}, condition < 1e3 {:.1e} / {:.1e} / {:.1e}",
            worst[k].value,
            worst[k].gradient,
            worst[k].hessian,
            worst_well[k].value,
            worst_well[k].gradient,
            worst_well[k].hessian
        );
    }
}

#[test]
fn point_edge_against_dual_numbers() {
    check_kind(
        "point-edge",
        &PE_TYPES,
        point_edge_pair,
        |x: &[DVec3; 3], ty| {
            (
                point_edge_distance_of_type(x[0], x[1], x[2], ty),
                point_edge_distance_gradient(x[0], x[1], x[2], ty),
                point_edge_distance_hessian(x[0], x[1], x[2], ty),
            )
        },
        1,
    );
}

#[test]
fn point_triangle_against_dual_numbers() {
    check_kind(
        "point-triangle",
        &PT_TYPES,
        point_triangle_pair,
        |x: &[DVec3; 4], ty| {
            (
                point_triangle_distance_of_type(x[0], x[1], x[2], x[3], ty),
                point_triangle_distance_gradient(x[0], x[1], x[2], x[3], ty),
                point_triangle_distance_hessian(x[0], x[1], x[2], x[3], ty),
            )
        },
        2,
    );
}

#[test]
fn edge_edge_against_dual_numbers() {
    check_kind(
        "edge-edge",
        &EE_TYPES,
        edge_edge_pair,
        |x: &[DVec3; 4], ty| {
            (
                edge_edge_distance_of_type(x[0], x[1], x[2], x[3], ty),
                edge_edge_distance_gradient(x[0], x[1], x[2], x[3], ty),
                edge_edge_distance_hessian(x[0], x[1], x[2], x[3], ty),
            )
        },
        3,
    );
}

#[test]
fn point_point_against_dual_numbers() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut worst = Err::default();
    for i in 0..PAIRS {
        let kind = KINDS[i % KINDS.len()];
        let mut x = [unit(&mut rng), unit(&mut rng)];
        if kind == Kind::Degenerate {
            x[1] = x[0] + unit(&mut rng) * log_uniform(&mut rng, 6.0, 12.0);
        }
        let x = place(x, kind, &mut rng);
        let l = extent(&x);
        let g = point_point_distance_gradient(x[0], x[1]);
        let h = point_point_distance_hessian(x[0], x[1]);
        let (rv, rg, rh) = dual::<6>(&x, |c| ref_point_point(&c[0], &c[1]));
        let e = rel_err(
            (point_point_distance(x[0], x[1]), &g, &h),
            (rv, &rg, &rh),
            [l * l, l, 1.0],
        );
        assert!(e.worst() <= 1e-12, "point-point pair {i}: {e:?}");
        worst = worst.max(e);
    }
    eprintln!("point-point: {worst:?}");
}

/// The mollifier as a function of the four points, with the threshold of the rest
/// positions, against dual numbers of its polynomial of the cross product.
#[test]
fn mollifier_against_dual_numbers() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut worst = Err::default();
    let mut active = 0;
    for i in 0..PAIRS {
        let kind = KINDS[i % KINDS.len()];
        let x = edge_edge_pair(
            &mut rng,
            if kind == Kind::Boundary {
                Kind::Degenerate
            } else {
                kind
            },
        );
        let l = extent(&x);
        // Rest positions: the same pair, or a perturbed one.
        let rest = x.map(|p| p + unit(&mut rng) * 0.01 * l * rng.random_range(0.0..1.0));
        let eps_x = edge_edge_mollifier_threshold(rest[0], rest[1], rest[2], rest[3]);
        let ex = (rest[1] - rest[0]).length_squared() * (rest[3] - rest[2]).length_squared();
        assert!(
            (eps_x - 1e-3 * ex).abs() <= 1e-15 * eps_x,
            "threshold {eps_x} {ex}"
        );
        let xv = edge_edge_cross_squarednorm(x[0], x[1], x[2], x[3]);
        let m = edge_edge_mollifier(x[0], x[1], x[2], x[3], eps_x);
        let g = edge_edge_mollifier_gradient(x[0], x[1], x[2], x[3], eps_x);
        let h = edge_edge_mollifier_hessian(x[0], x[1], x[2], x[3], eps_x);
        assert_finite_symmetric(&g, &h, "mollifier");
        let (rv, rg, rh) = dual::<12>(&x, |c| {
            let n = cross(&sub(&c[1], &c[0]), &sub(&c[3], &c[2]));
            let xx = dot(&n, &n);
            if xx.re < eps_x {
                let r = xx / eps_x;
                (r.clone() * -1.0 + 2.0) * r
            } else {
                xx * 0.0 + 1.0
            }
        });
        if xv < eps_x {
            active += 1;
        }
        // Scales: the mollifier is dimensionless; its gradient scales as 1 / l and its
        // Hessian as 1 / l^2.
        let e = rel_err((m, &g, &h), (rv, &rg, &rh), [1.0, 1.0 / l, 1.0 / (l * l)]);
        assert!(e.worst() <= 1e-9, "mollifier pair {i}: {e:?}");
        worst = worst.max(e);
        // The cross product's squared norm itself.
        let gx = edge_edge_cross_squarednorm_gradient(x[0], x[1], x[2], x[3]);
        let hx = edge_edge_cross_squarednorm_hessian(x[0], x[1], x[2], x[3]);
        let (rv, rg, rh) = dual::<12>(&x, |c| {
            let n = cross(&sub(&c[1], &c[0]), &sub(&c[3], &c[2]));
            dot(&n, &n)
        });
        let l4 = l.powi(4);
        let e = rel_err((xv, &gx, &hx), (rv, &rg, &rh), [l4, l4 / l, l4 / (l * l)]);
        assert!(e.worst() <= 1e-12, "cross squared norm pair {i}: {e:?}");
    }
    assert!(
        active > PAIRS / 10,
        "too few pairs below the threshold: {active}"
    );
    eprintln!("mollifier ({active} pairs below eps_x): {worst:?}");
}

#[test]
fn mollifier_scalar_against_dual_numbers() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    for _ in 0..PAIRS {
        let eps_x = log_uniform(&mut rng, -3.0, 12.0);
        let x = eps_x * rng.random_range(0.0..1.5);
        let (v, d1, d2) = num_dual::second_derivative(
            |y: num_dual::Dual2_64| {
                if y.re < eps_x {
                    let r = y / eps_x;
                    (r * -1.0 + 2.0) * r
                } else {
                    y * 0.0 + 1.0
                }
            },
            x,
        );
        let close = |a: f64, b: f64, s: f64| (a - b).abs() <= 1e-13 * s;
        assert!(close(edge_edge_mollifier_scalar(x, eps_x), v, 1.0));
        assert!(close(
            edge_edge_mollifier_derivative(x, eps_x),
            d1,
            1.0 / eps_x
        ));
        assert!(close(
            edge_edge_mollifier_second_derivative(x, eps_x),
            d2,
            1.0 / (eps_x * eps_x)
        ));
    }
}

// ---------------------------------------------------------------------------------------
// Central finite differences, a second independent check.

/// Central differences of `f` (gradient) and of `grad` (Hessian) at `x`, step `h`.
fn central<const P: usize, const N: usize>(
    x: &[DVec3; P],
    h: f64,
    f: impl Fn(&[DVec3; P]) -> f64,
    grad: impl Fn(&[DVec3; P]) -> [f64; N],
) -> ([f64; N], [[f64; N]; N]) {
    let mut g = [0.0; N];
    let mut hh = [[0.0; N]; N];
    for k in 0..N {
        let (mut xp, mut xm) = (*x, *x);
        xp[k / 3][k % 3] += h;
        xm[k / 3][k % 3] -= h;
        g[k] = (f(&xp) - f(&xm)) / (2.0 * h);
        let (gp, gm) = (grad(&xp), grad(&xm));
        for j in 0..N {
            hh[k][j] = (gp[j] - gm[j]) / (2.0 * h);
        }
    }
    (g, hh)
}

fn fd_kind<const P: usize, const N: usize, Ty: Copy + std::fmt::Debug>(
    name: &str,
    types: &[(Ty, Sub)],
    gen: impl Fn(&mut ChaCha8Rng, Kind) -> [DVec3; P],
    f: impl Fn(&[DVec3; P], Ty) -> f64,
    grad: impl Fn(&[DVec3; P], Ty) -> [f64; N],
    hess: impl Fn(&[DVec3; P], Ty) -> [[f64; N]; N],
    seed: u64,
) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut worst = 0.0f64;
    let mut done = 0;
    while done < 300 {
        let x = gen(&mut rng, Kind::Generic);
        let l = extent(&x);
        // Well-conditioned pairs only: differences lose the rest to cancellation.
        if types.iter().any(|&(_, s)| cond_line(&x, s, l) > 1e2) {
            continue;
        }
        done += 1;
        for &(ty, _) in types {
            let (fg, fh) = central(&x, 1e-6 * l, |y| f(y, ty), |y| grad(y, ty));
            let (g, h) = (grad(&x, ty), hess(&x, ty));
            let e = rel_err((0.0, &g, &h), (0.0, &fg, &fh), [1.0, l, 1.0]);
            assert!(
                e.worst() <= 1e-6,
                "{name} {ty:?}: finite differences {e:?}\n{x:?}"
            );
            worst = worst.max(e.worst());
        }
    }
    eprintln!("{name}: max rel err against central differences {worst:.1e}");
}

#[test]
fn all_types_against_finite_differences() {
    fd_kind(
        "point-edge",
        &PE_TYPES,
        point_edge_pair,
        |x, t| point_edge_distance_of_type(x[0], x[1], x[2], t),
        |x, t| point_edge_distance_gradient(x[0], x[1], x[2], t),
        |x, t| point_edge_distance_hessian(x[0], x[1], x[2], t),
        11,
    );
    fd_kind(
        "point-triangle",
        &PT_TYPES,
        point_triangle_pair,
        |x, t| point_triangle_distance_of_type(x[0], x[1], x[2], x[3], t),
        |x, t| point_triangle_distance_gradient(x[0], x[1], x[2], x[3], t),
        |x, t| point_triangle_distance_hessian(x[0], x[1], x[2], x[3], t),
        12,
    );
    fd_kind(
        "edge-edge",
        &EE_TYPES,
        edge_edge_pair,
        |x, t| edge_edge_distance_of_type(x[0], x[1], x[2], x[3], t),
        |x, t| edge_edge_distance_gradient(x[0], x[1], x[2], x[3], t),
        |x, t| edge_edge_distance_hessian(x[0], x[1], x[2], x[3], t),
        13,
    );
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    for _ in 0..300 {
        let x = edge_edge_pair(&mut rng, Kind::Degenerate);
        let l = extent(&x);
        let eps_x = 1e-3 * (x[1] - x[0]).length_squared() * (x[3] - x[2]).length_squared() * 2.0;
        let xv = edge_edge_cross_squarednorm(x[0], x[1], x[2], x[3]);
        // Away from the threshold, where the mollifier's second derivative jumps.
        if (xv - eps_x).abs() < 1e-3 * eps_x {
            continue;
        }
        let (fg, fh) = central(
            &x,
            1e-7 * l,
            |y| edge_edge_mollifier(y[0], y[1], y[2], y[3], eps_x),
            |y| edge_edge_mollifier_gradient(y[0], y[1], y[2], y[3], eps_x),
        );
        let g = edge_edge_mollifier_gradient(x[0], x[1], x[2], x[3], eps_x);
        let h = edge_edge_mollifier_hessian(x[0], x[1], x[2], x[3], eps_x);
        let e = rel_err(
            (0.0, &g, &h),
            (0.0, &fg, &fh),
            [1.0, 1.0 / l, 1.0 / (l * l)],
        );
        assert!(e.worst() <= 1e-5, "mollifier: finite differences {e:?}");
    }
}

// ---------------------------------------------------------------------------------------
// Type boundaries, degenerate input, batches.

/// At a type boundary the two sides' sub-distances agree in value and gradient: a point
/// whose projection is exactly a triangle's corner, on an edge's line at the corner.
#[test]
fn type_boundaries_agree_to_first_order() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    for _ in 0..1000 {
        let [_, t0, t1, t2] = point_triangle_pair(&mut rng, Kind::Generic);
        let n = (t1 - t0).cross(t2 - t0).normalize();
        // The point over the edge t0 t1 at parameter s, height z: P_E0 and P_T agree.
        let s = rng.random_range(0.0..1.0);
        let p = t0 + (t1 - t0) * s + n * rng.random_range(-1.0..1.0);
        let e = point_triangle_distance_of_type(p, t0, t1, t2, PointTriangleType::E0);
        let f = point_triangle_distance_of_type(p, t0, t1, t2, PointTriangleType::Interior);
        assert!((e - f).abs() <= 1e-12 * (1.0 + f));
        // The gradients agree in the point's coordinates (the corners' differ: the plane
        // turns with t2, the line does not).
        let ge = point_triangle_distance_gradient(p, t0, t1, t2, PointTriangleType::E0);
        let gf = point_triangle_distance_gradient(p, t0, t1, t2, PointTriangleType::Interior);
        for k in 0..3 {
            assert!((ge[k] - gf[k]).abs() <= 1e-10, "{ge:?} {gf:?}");
        }
        // At the corner: P_T0, P_E0 and P_E2 agree in value and in the point's gradient.
        let p = t0 + n * rng.random_range(-1.0..1.0) + (t1 - t0).cross(n) * 0.0;
        let a = point_triangle_distance_gradient(p, t0, t1, t2, PointTriangleType::T0);
        for ty in [
            PointTriangleType::E0,
            PointTriangleType::E2,
            PointTriangleType::Interior,
        ] {
            let b = point_triangle_distance_gradient(p, t0, t1, t2, ty);
            for k in 0..3 {
                assert!((a[k] - b[k]).abs() <= 1e-10, "{ty:?}: {a:?} {b:?}");
            }
        }
    }
}

/// Exactly degenerate input: finite values, the documented fallbacks.
#[test]
fn degenerate_input_is_finite_with_the_documented_fallbacks() {
    let p = DVec3::new(0.3, 2.0, -1.0);
    let (a, b) = (DVec3::new(1.0, 0.0, 0.0), DVec3::new(3.0, 0.0, 0.0));
    // A zero-length edge is its point.
    assert_eq!(point_line_distance(p, a, a), (p - a).length_squared());
    let g = point_line_distance_gradient(p, a, a);
    assert_eq!(&g[..6], &point_point_distance_gradient(p, a)[..]);
    assert_eq!(&g[6..], &[0.0; 3]);
    // A collinear triangle is its line; coincident corners their point.
    let c = DVec3::new(2.0, 0.0, 0.0);
    assert_eq!(
        point_plane_distance(p, a, c, b),
        point_line_distance(p, a, b)
    );
    assert_eq!(point_plane_distance(p, a, a, a), (p - a).length_squared());
    let g = point_plane_distance_gradient(p, a, c, b);
    let gl = point_line_distance_gradient(p, a, b);
    assert_eq!([g[0], g[3], g[9]], [gl[0], gl[3], gl[6]]);
    assert_eq!(&g[6..9], &[0.0; 3]);
    // Parallel lines: their distance.
    let off = DVec3::new(0.0, 1.0, 1.0);
    assert_eq!(line_line_distance(a, b, a + off, b + off), 2.0);
    assert_eq!(line_line_distance(a, b, a + off, a + off), 2.0);
    assert_eq!(
        line_line_distance(a, a, b + off, b + off),
        (b + off - a).length_squared()
    );
    for h in [
        point_plane_distance_hessian(p, a, c, b),
        point_plane_distance_hessian(p, a, a, a),
        line_line_distance_hessian(a, b, a + off, b + off),
        line_line_distance_hessian(a, a, b, b),
    ] {
        assert_finite_symmetric(&[0.0; 12], &h, "degenerate");
    }
    // Through the types: a zero-length edge's interior.
    let g = edge_edge_distance_gradient(a, a, p, b, EdgeEdgeType::EaEb0);
    assert!(g.iter().all(|x| x.is_finite()));
}

#[test]
fn batches_match_the_per_pair_calls() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let n = 500;
    let pt: Vec<[DVec3; 4]> = (0..n)
        .map(|i| point_triangle_pair(&mut rng, KINDS[i % 6]))
        .collect();
    let pt_ty: Vec<PointTriangleType> = pt
        .iter()
        .map(|x| point_triangle_distance(x[0], x[1], x[2], x[3]).1)
        .collect();
    let (mut d, mut g, mut h) = (vec![0.0; n], vec![[0.0; 12]; n], vec![[[0.0; 12]; 12]; n]);
    point_triangle_distance_batch(
        &pt,
        &pt_ty,
        BatchOutput {
            distances: &mut d,
            gradients: Some(&mut g),
            hessians: Some(&mut h),
        },
    )
    .unwrap();
    for i in 0..n {
        let [p, t0, t1, t2] = pt[i];
        assert_eq!(
            d[i],
            point_triangle_distance_of_type(p, t0, t1, t2, pt_ty[i])
        );
        assert_eq!(
            g[i],
            point_triangle_distance_gradient(p, t0, t1, t2, pt_ty[i])
        );
        assert_eq!(
            h[i],
            point_triangle_distance_hessian(p, t0, t1, t2, pt_ty[i])
        );
        // The type's distance is the pair's distance (the classifier's minimum), up to
        // rounding: the sub-distances are the right ones.
        let dd = point_triangle_distance(p, t0, t1, t2).0;
        let l = extent(&pt[i]);
        assert!((d[i] - dd).abs() <= 1e-9 * l * l, "{i}: {} {dd}", d[i]);
    }
    let ee: Vec<[DVec3; 4]> = (0..n)
        .map(|i| edge_edge_pair(&mut rng, KINDS[i % 6]))
        .collect();
    let ee_ty: Vec<EdgeEdgeType> = ee
        .iter()
        .map(|x| edge_edge_distance(x[0], x[1], x[2], x[3]).1)
        .collect();
    edge_edge_distance_batch(
        &ee,
        &ee_ty,
        BatchOutput {
            distances: &mut d,
            gradients: Some(&mut g),
            hessians: None,
        },
    )
    .unwrap();
    for i in 0..n {
        let [a0, a1, b0, b1] = ee[i];
        assert_eq!(d[i], edge_edge_distance_of_type(a0, a1, b0, b1, ee_ty[i]));
        assert_eq!(g[i], edge_edge_distance_gradient(a0, a1, b0, b1, ee_ty[i]));
        let dd = edge_edge_distance(a0, a1, b0, b1).0;
        let l = extent(&ee[i]);
        // Nearly parallel interiors lose accuracy as one over the sine (see rounding_bound).
        let s2 = sin2(a1 - a0, b1 - b0);
        let tol = 1e-9 * l * l + 4.0 * l * l * (1e-15 / s2).min(1.0);
        assert!(
            (d[i] - dd).abs() <= tol,
            "{i} {:?}: {} {dd}",
            ee_ty[i],
            d[i]
        );
    }
    let pe: Vec<[DVec3; 3]> = (0..n)
        .map(|i| point_edge_pair(&mut rng, KINDS[i % 6]))
        .collect();
    let pe_ty: Vec<PointEdgeType> = pe
        .iter()
        .map(|x| point_edge_distance(x[0], x[1], x[2]).1)
        .collect();
    let (mut g9, mut h9) = (vec![[0.0; 9]; n], vec![[[0.0; 9]; 9]; n]);
    point_edge_distance_batch(
        &pe,
        &pe_ty,
        BatchOutput {
            distances: &mut d,
            gradients: Some(&mut g9),
            hessians: Some(&mut h9),
        },
    )
    .unwrap();
    for i in 0..n {
        let [p, e0, e1] = pe[i];
        assert_eq!(g9[i], point_edge_distance_gradient(p, e0, e1, pe_ty[i]));
        assert_eq!(h9[i], point_edge_distance_hessian(p, e0, e1, pe_ty[i]));
        let dd = point_edge_distance(p, e0, e1).0;
        let l = extent(&pe[i]);
        assert!((d[i] - dd).abs() <= 1e-9 * l * l);
    }
    let pp: Vec<[DVec3; 2]> = (0..n).map(|_| [unit(&mut rng), unit(&mut rng)]).collect();
    let mut g6 = vec![[0.0; 6]; n];
    point_point_distance_batch(
        &pp,
        BatchOutput {
            distances: &mut d,
            gradients: Some(&mut g6),
            hessians: None,
        },
    )
    .unwrap();
    for i in 0..n {
        assert_eq!(d[i], point_point_distance(pp[i][0], pp[i][1]));
        assert_eq!(g6[i], point_point_distance_gradient(pp[i][0], pp[i][1]));
    }
    // Wrong lengths: an error naming the buffer.
    let err = point_point_distance_batch(
        &pp,
        BatchOutput {
            distances: &mut d[..3],
            gradients: None,
            hessians: None,
        },
    )
    .unwrap_err();
    assert_eq!((err.what, err.expected, err.found), ("distances", n, 3));
    let err = edge_edge_distance_batch(
        &ee,
        &ee_ty[..1],
        BatchOutput {
            distances: &mut d,
            gradients: None,
            hessians: None,
        },
    )
    .unwrap_err();
    assert_eq!(err.what, "types");
}
