//! The friction potential's derivatives against central finite differences on random
//! stencils, and the PSD projection against an independent eigensolver.
#![allow(clippy::needless_range_loop)] // the Jacobi sweeps index rows and columns together

use super::potential::project_2x2;
use super::*;
use crate::ipc::PsdProjection;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A random small "mesh": `n` vertices and stencils of every kind on distinct vertices.
fn random_set(
    rng: &mut ChaCha8Rng,
    n: usize,
    mu: FrictionCoefficients<'_>,
) -> TangentialCollisions {
    let x: Vec<[f64; 3]> = (0..n)
        .map(|_| [0; 3].map(|_| rng.random_range(-1.0..1.0)))
        .collect();
    let mut stencils = Vec::new();
    for (kind, k) in [
        (StencilKind::VertexVertex, 2),
        (StencilKind::EdgeVertex, 3),
        (StencilKind::EdgeEdge, 4),
        (StencilKind::FaceVertex, 4),
    ] {
        for _ in 0..3 {
            let mut v = [0usize; 4];
            let mut i = 0;
            while i < k {
                let c = rng.random_range(0..n);
                if !v[..i].contains(&c) {
                    v[i] = c;
                    i += 1;
                }
            }
            stencils.push(NormalStencil {
                kind,
                primitives: [0, 0],
                vertices: v,
                weight: rng.random_range(0.5..2.0),
                dmin: 0.0,
                eps_x: 0.0,
            });
        }
    }
    // A normal force that depends on the distance, as a barrier's does.
    TangentialCollisions::build_from_stencils(&x, stencils, |d2, _| 1.0 + d2, mu).unwrap()
}

fn dense(m: &crate::ipc::SparseMatrix) -> Vec<Vec<f64>> {
    let n = m.size();
    let mut d = vec![vec![0.0; n]; n];
    for (r, c, x) in m.triplets() {
        d[r][c] += x;
    }
    d
}

fn flat(v: &[[f64; 3]]) -> Vec<f64> {
    v.iter().flatten().copied().collect()
}

fn unflat(x: &[f64]) -> Vec<[f64; 3]> {
    x.chunks(3).map(|c| [c[0], c[1], c[2]]).collect()
}

/// Velocities whose slips fall below, across and above `eps_v` (scale `s`).
fn random_velocities(rng: &mut ChaCha8Rng, n: usize, s: f64) -> Vec<[f64; 3]> {
    (0..n)
        .map(|_| [0; 3].map(|_| rng.random_range(-s..s)))
        .collect()
}

#[test]
fn gradient_and_hessian_match_finite_differences() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let n = 9;
    let mu_s: Vec<f64> = (0..n).map(|_| rng.random_range(0.4..0.9)).collect();
    let mu_k: Vec<f64> = (0..n).map(|_| rng.random_range(0.1..0.4)).collect();
    let eps_v = 0.05;
    let d = FrictionPotential::new(eps_v).unwrap();
    for (trial, mu) in [
        FrictionCoefficients::uniform(0.5),
        FrictionCoefficients::Global {
            mu_s: 0.8,
            mu_k: 0.3,
        },
        FrictionCoefficients::PerVertex {
            mu_s: &mu_s,
            mu_k: &mu_k,
        },
    ]
    .into_iter()
    .enumerate()
    {
        for scale in [0.01, 0.04, 0.2, 3.0] {
            let set = random_set(&mut rng, n, mu);
            let v = random_velocities(&mut rng, n, scale * eps_v);
            let x = flat(&v);
            let g = d.gradient(&set, &v).unwrap();
            let hm = dense(&d.hessian(&set, &v, PsdProjection::None).unwrap());
            let h = 1e-7 * eps_v;
            for i in 0..x.len() {
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[i] += h;
                xm[i] -= h;
                let (vp, vm) = (unflat(&xp), unflat(&xm));
                let fd = (d.energy(&set, &vp).unwrap() - d.energy(&set, &vm).unwrap()) / (2.0 * h);
                let gs = g.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                assert!(
                    (fd - g[i]).abs() <= 1e-6 * gs.max(1.0),
                    "trial {trial} grad {i}: {fd} vs {}",
                    g[i]
                );
                let (gp, gm) = (
                    d.gradient(&set, &vp).unwrap(),
                    d.gradient(&set, &vm).unwrap(),
                );
                let hs = hm.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
                for j in 0..x.len() {
                    let fdh = (gp[j] - gm[j]) / (2.0 * h);
                    assert!(
                        (fdh - hm[j][i]).abs() <= 1e-5 * hs.max(1.0),
                        "trial {trial} scale {scale} hess ({j},{i}): {fdh} vs {}",
                        hm[j][i]
                    );
                }
            }
            // The force is minus the gradient.
            let f = d.force(&set, &v).unwrap();
            assert!(f.iter().zip(&g).all(|(a, b)| *a == -*b));
        }
    }
}

/// Eigenvalues of a symmetric matrix by cyclic Jacobi rotations.
fn jacobi_eigenvalues(mut a: Vec<Vec<f64>>) -> Vec<f64> {
    let n = a.len();
    for _ in 0..100 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .filter(|(i, j)| i != j)
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        if off < 1e-30 {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                if a[p][q].abs() < 1e-300 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let (akp, akq) = (a[k][p], a[k][q]);
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for k in 0..n {
                    let (apk, aqk) = (a[p][k], a[q][k]);
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
            }
        }
    }
    (0..n).map(|i| a[i][i]).collect()
}

#[test]
fn projected_hessian_has_no_negative_eigenvalue() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let d = FrictionPotential::new(0.05).unwrap();
    let mut negative_seen = false;
    for _ in 0..20 {
        // Static above kinetic makes the plain Hessian indefinite in the transition.
        let set = random_set(
            &mut rng,
            8,
            FrictionCoefficients::Global {
                mu_s: 1.0,
                mu_k: 0.1,
            },
        );
        let v = random_velocities(&mut rng, 8, 0.04);
        let plain = dense(&d.hessian(&set, &v, PsdProjection::None).unwrap());
        let lp = jacobi_eigenvalues(plain.clone());
        let scale = lp.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        negative_seen |= lp.iter().any(|&l| l < -1e-8 * scale);
        for method in [PsdProjection::Clamp, PsdProjection::Abs] {
            let m = dense(&d.hessian(&set, &v, method).unwrap());
            for (i, row) in m.iter().enumerate() {
                for (j, x) in row.iter().enumerate() {
                    assert!((x - m[j][i]).abs() <= 1e-12 * scale.max(1.0));
                }
            }
            let l = jacobi_eigenvalues(m);
            assert!(
                l.iter().all(|&x| x >= -1e-10 * scale.max(1.0)),
                "{method:?}: {l:?}"
            );
        }
    }
    assert!(
        negative_seen,
        "the test never exercised an indefinite Hessian"
    );
}

#[test]
fn two_by_two_projection() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for _ in 0..1000 {
        let (a, b, c) = (
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let h = [[a, b], [b, c]];
        let l = jacobi_eigenvalues(vec![vec![a, b], vec![b, c]]);
        for (method, f) in [
            (
                PsdProjection::Clamp,
                (|x: f64| x.max(0.0)) as fn(f64) -> f64,
            ),
            (PsdProjection::Abs, |x: f64| x.abs()),
        ] {
            let p = project_2x2(h, method);
            let mut want: Vec<f64> = l.iter().map(|&x| f(x)).collect();
            let mut got = jacobi_eigenvalues(vec![p[0].to_vec(), p[1].to_vec()]);
            want.sort_by(f64::total_cmp);
            got.sort_by(f64::total_cmp);
            assert!((want[0] - got[0]).abs() < 1e-12 && (want[1] - got[1]).abs() < 1e-12);
            // Same eigenvectors: the projection commutes with the original.
            let ab = [
                [
                    h[0][0] * p[0][0] + h[0][1] * p[1][0],
                    h[0][0] * p[0][1] + h[0][1] * p[1][1],
                ],
                [
                    h[1][0] * p[0][0] + h[1][1] * p[1][0],
                    h[1][0] * p[0][1] + h[1][1] * p[1][1],
                ],
            ];
            assert!((ab[0][1] - ab[1][0]).abs() < 1e-12);
            if l.iter().all(|&x| x >= 0.0) {
                assert_eq!(p, h);
            }
        }
    }
    assert_eq!(
        project_2x2([[-1.0, 0.0], [0.0, 2.0]], PsdProjection::None),
        [[-1.0, 0.0], [0.0, 2.0]]
    );
}

#[test]
fn bad_input_is_an_error() {
    assert!(matches!(
        FrictionPotential::new(0.0),
        Err(FrictionError::BadEpsV { .. })
    ));
    assert!(matches!(
        FrictionPotential::new(f64::NAN),
        Err(FrictionError::BadEpsV { .. })
    ));
    let x = [[0.0; 3], [1.0, 0.0, 0.0]];
    let vv = NormalStencil {
        kind: StencilKind::VertexVertex,
        primitives: [0, 5],
        vertices: [0, 5, 0, 0],
        weight: 1.0,
        dmin: 0.0,
        eps_x: 0.0,
    };
    let mu = FrictionCoefficients::uniform(0.5);
    let e = TangentialCollisions::build_from_stencils(&x, [vv], |_, _| 1.0, mu);
    assert_eq!(
        e,
        Err(FrictionError::VertexOutOfRange {
            vertex: 5,
            vertices: 2
        })
    );
    let same = NormalStencil {
        vertices: [0, 0, 0, 0],
        ..vv
    };
    let x1 = [[0.0; 3]];
    let e = TangentialCollisions::build_from_stencils(&x1, [same], |_, _| 1.0, mu);
    assert!(matches!(e, Err(FrictionError::DegenerateStencil { .. })));
    let ok = NormalStencil {
        vertices: [0, 1, 0, 0],
        ..vv
    };
    let set = TangentialCollisions::build_from_stencils(&x, [ok], |_, _| 1.0, mu).unwrap();
    let d = FrictionPotential::new(1.0).unwrap();
    assert!(matches!(
        d.energy(&set, &x1),
        Err(FrictionError::VertexOutOfRange { .. })
    ));
    let short = [0.5];
    let e = TangentialCollisions::build_from_stencils(
        &x,
        [ok],
        |_, _| 1.0,
        FrictionCoefficients::PerVertex {
            mu_s: &short,
            mu_k: &short,
        },
    );
    assert!(matches!(e, Err(FrictionError::CoefficientsLength { .. })));
    let e = TangentialCollisions::build_from_stencils(
        &x,
        [ok],
        |_, _| 1.0,
        FrictionCoefficients::uniform(-1.0),
    );
    assert!(matches!(e, Err(FrictionError::BadCoefficient { .. })));
}
