//! Property tests of the elementary tests: invariance under scaling, translation, swapping the
//! edges and reversing the face; and recall on contacts constructed to happen at a known time.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use topoccd::math::DVec3;
use topoccd::narrow::{edge_edge, vertex_face, EdgeEdge, NarrowOptions, Outcome, VertexFace};

const TOL: f64 = 1e-6;

fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x70_cc_d0),
        failure_persistence: None,
        ..Config::default()
    }
}

fn point() -> impl Strategy<Value = DVec3> {
    prop::array::uniform3(-1.0f64..1.0).prop_map(DVec3::from_array)
}

fn points() -> impl Strategy<Value = [DVec3; 8]> {
    prop::array::uniform8(point())
}

/// Scale factors from 1e-3 to 1e3, log-uniform.
fn scale() -> impl Strategy<Value = f64> {
    (-3.0f64..3.0).prop_map(|e| 10f64.powf(e))
}

#[derive(Clone, Copy, Debug)]
enum Kind {
    VertexFace,
    EdgeEdge,
}

fn run(kind: Kind, p: [DVec3; 8], opts: &NarrowOptions) -> Outcome {
    match kind {
        Kind::VertexFace => vertex_face(&VertexFace::from_points(p), opts),
        Kind::EdgeEdge => edge_edge(&EdgeEdge::from_points(p), opts),
    }
}

/// The outcome, or `None` when the case lies within a hair of the contact boundary (separated
/// at distance 0 but not at 1e-6 times the configuration's size), where invariance is not owed.
fn robust(kind: Kind, p: [DVec3; 8]) -> Option<Outcome> {
    let base = run(kind, p, &NarrowOptions::default());
    let size = p.iter().map(|x| x.abs().max_element()).fold(0.0, f64::max);
    let shell = NarrowOptions {
        min_distance: 1e-6 * size,
        ..NarrowOptions::default()
    };
    if base == Outcome::Separated && run(kind, p, &shell).is_contact() {
        return None;
    }
    Some(base)
}

fn same(a: Outcome, b: Outcome) -> Result<(), TestCaseError> {
    match (a.toi(), b.toi()) {
        (None, None) => Ok(()),
        (Some(x), Some(y)) => {
            prop_assert!((x - y).abs() <= 2.0 * TOL, "toi {x} vs {y}");
            Ok(())
        }
        _ => Err(TestCaseError::fail(format!("{a:?} vs {b:?}"))),
    }
}

fn kind() -> impl Strategy<Value = Kind> {
    prop_oneof![Just(Kind::VertexFace), Just(Kind::EdgeEdge)]
}

proptest! {
    #![proptest_config(config(3000))]

    #[test]
    fn scaling_does_not_change_the_answer(k in kind(), p in points(), s in scale()) {
        let Some(base) = robust(k, p) else { return Ok(()) };
        let scaled = run(k, p.map(|x| x * s), &NarrowOptions::default());
        same(base, scaled)?;
    }

    #[test]
    fn translation_does_not_change_the_answer(k in kind(), p in points(),
                                             shift in prop::array::uniform3(-1e3f64..1e3)) {
        let Some(base) = robust(k, p) else { return Ok(()) };
        let d = DVec3::from_array(shift);
        let moved = run(k, p.map(|x| x + d), &NarrowOptions::default());
        same(base, moved)?;
    }

    #[test]
    fn swapping_the_edges_does_not_change_the_answer(p in points()) {
        let Some(base) = robust(Kind::EdgeEdge, p) else { return Ok(()) };
        let swapped = edge_edge(&EdgeEdge::from_points(p).swapped(), &NarrowOptions::default());
        same(base, swapped)?;
    }

    #[test]
    fn reversing_the_face_does_not_change_the_answer(p in points()) {
        let Some(base) = robust(Kind::VertexFace, p) else { return Ok(()) };
        let mut r = p;
        r.swap(2, 3);
        r.swap(6, 7);
        same(base, run(Kind::VertexFace, r, &NarrowOptions::default()))?;
    }

    /// A vertex placed on its triangle at a random time t*: a contact no later than t*.
    #[test]
    fn constructed_vertex_face_contacts_are_found(
        f in prop::array::uniform3(point()), vel in prop::array::uniform4(point()),
        bary in (0.0f64..1.0, 0.0f64..1.0), t_star in 0.0f64..=1.0, s in scale(),
    ) {
        // Barycentric point of the triangle at t*, folded into the triangle.
        let (mut a, mut b) = bary;
        if a + b > 1.0 { a = 1.0 - a; b = 1.0 - b; }
        let at_star = [f[0], f[1], f[2]];
        let v_star = at_star[0] + (at_star[1] - at_star[0]) * a + (at_star[2] - at_star[0]) * b;
        let star = [v_star, at_star[0], at_star[1], at_star[2]];
        // Each point moves with its own velocity and passes its t* position at t*.
        let mut p = [DVec3::ZERO; 8];
        for i in 0..4 {
            p[i] = (star[i] - vel[i] * t_star) * s;
            p[i + 4] = (star[i] + vel[i] * (1.0 - t_star)) * s;
        }
        let o = vertex_face(&VertexFace::from_points(p), &NarrowOptions::default());
        // The construction itself rounds: allow the toi a hair past t*.
        prop_assert!(o.toi().is_some_and(|t| t <= t_star + 1e-9), "{o:?} for t* = {t_star}");
    }

    /// Two edges crossing at a random time t*: a contact no later than t*.
    #[test]
    fn constructed_edge_edge_contacts_are_found(
        e in prop::array::uniform3(point()), vel in prop::array::uniform4(point()),
        uv in (0.0f64..=1.0, 0.0f64..=1.0), t_star in 0.0f64..=1.0, s in scale(),
    ) {
        // Edge a from e0 to e1; edge b passes through a's point at u, with direction e2.
        let (u, v) = uv;
        let x = e[0] + (e[1] - e[0]) * u;
        let star = [e[0], e[1], x - e[2] * v, x + e[2] * (1.0 - v)];
        let mut p = [DVec3::ZERO; 8];
        for i in 0..4 {
            p[i] = (star[i] - vel[i] * t_star) * s;
            p[i + 4] = (star[i] + vel[i] * (1.0 - t_star)) * s;
        }
        let o = edge_edge(&EdgeEdge::from_points(p), &NarrowOptions::default());
        prop_assert!(o.toi().is_some_and(|t| t <= t_star + 1e-9), "{o:?} for t* = {t_star}");
    }
}
