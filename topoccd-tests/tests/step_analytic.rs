//! Tiny scenes with known answers: the exact pairs and times of impact.

use topoccd::math::DVec3;
use topoccd::{Ccd, Certainty, Contact, EeContact, Method, Mode, QueryOptions, Step, VfContact};

const TOLERANCE: f64 = 1e-6;

fn methods() -> [Method; 3] {
    [Method::Brute, Method::Bvh, Method::Cluster]
}

/// Triangle 0 fixed in z = 0; triangle 1 is a small triangle whose corner 3 falls from z = h0
/// to z = h1 above (0.2, 0.2), the others staying higher.
fn falling_vertex(h0: f64, h1: f64) -> Step<'static> {
    let fixed = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let carrier = |h: f64| {
        [
            DVec3::new(0.2, 0.2, h),
            DVec3::new(0.3, 0.2, h + 5.0),
            DVec3::new(0.2, 0.3, h + 5.0),
        ]
    };
    let x0: Vec<DVec3> = fixed.iter().chain(&carrier(h0)).copied().collect();
    let x1: Vec<DVec3> = fixed.iter().chain(&carrier(h1)).copied().collect();
    Step::new(x0, x1, vec![[0, 1, 2], [3, 4, 5]]).unwrap()
}

#[test]
fn a_vertex_falling_through_a_triangle() {
    let mut ccd = Ccd::new();
    // Crossing z = 0 at t = 0.25, 0.5, 0.75.
    for (h0, h1, toi) in [(1.0, -3.0, 0.25), (1.0, -1.0, 0.5), (3.0, -1.0, 0.75)] {
        let step = falling_vertex(h0, h1);
        for method in methods() {
            let report = ccd.query(&step, method, &QueryOptions::default()).unwrap();
            assert!(report.ee.is_empty(), "{method}: {:?}", report.ee);
            assert_eq!(report.vf.len(), 1, "{method}");
            let VfContact {
                vertex,
                face,
                toi: found,
                certainty,
                ..
            } = report.vf[0];
            assert_eq!(certainty, Certainty::Resolved);
            assert_eq!((vertex, face), (3, 0));
            assert!(
                found <= toi && found > toi - TOLERANCE,
                "{method}: {found} vs {toi}"
            );
            assert_eq!(report.earliest, Some(Contact::Vf(report.vf[0])));
        }
    }
}

#[test]
fn min_separation_brings_the_contact_forward() {
    // The vertex passes z = 0.1 at t = 0.45.
    let step = falling_vertex(1.0, -1.0);
    let mut options = QueryOptions::default();
    options.narrow.min_distance = 0.1;
    for method in methods() {
        let report = Ccd::new().query(&step, method, &options).unwrap();
        let toi = report.earliest_toi().unwrap();
        assert!(
            toi <= 0.45 && toi > 0.45 - 2.0 * TOLERANCE,
            "{method}: {toi}"
        );
    }
}

#[test]
fn a_vertex_passing_beside_the_triangle_does_not_collide() {
    let fixed = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let carrier = |h: f64| {
        [
            DVec3::new(0.6, 0.6, h), // beyond the hypotenuse x + y = 1
            DVec3::new(0.7, 0.6, h + 5.0),
            DVec3::new(0.6, 0.7, h + 5.0),
        ]
    };
    let x0: Vec<DVec3> = fixed.iter().chain(&carrier(1.0)).copied().collect();
    let x1: Vec<DVec3> = fixed.iter().chain(&carrier(-1.0)).copied().collect();
    let step = Step::new(x0, x1, vec![[0, 1, 2], [3, 4, 5]]).unwrap();
    for method in methods() {
        let report = Ccd::new()
            .query(&step, method, &QueryOptions::default())
            .unwrap();
        assert_eq!(report.contact_count(), 0, "{method}: {report:?}");
    }
}

#[test]
fn two_crossing_edges() {
    // Edge (0, 1) along x at height 1 - 2t falls across edge (3, 4) along y at z = 0: contact
    // at t = 0.5. Each edge belongs to a thin triangle pointing away from the other edge.
    let x0 = vec![
        DVec3::new(-1.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 1.0),
        DVec3::new(0.0, 0.0, 3.0),
        DVec3::new(0.0, -1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(0.0, 0.0, -2.0),
    ];
    let mut x1 = x0.clone();
    for p in &mut x1[..3] {
        p.z -= 2.0;
    }
    let step = Step::new(x0, x1, vec![[0, 1, 2], [3, 4, 5]]).unwrap();
    for method in methods() {
        for mode in [Mode::All, Mode::Earliest] {
            let options = QueryOptions {
                mode,
                ..QueryOptions::default()
            };
            let report = Ccd::new().query(&step, method, &options).unwrap();
            let Some(Contact::Ee(EeContact { a, b, toi, .. })) = report.earliest else {
                panic!("{method} {mode:?}: {report:?}");
            };
            assert_eq!((a, b), ([0, 1], [3, 4]));
            assert!(toi <= 0.5 && toi > 0.5 - TOLERANCE, "{toi}");
            if mode == Mode::All {
                assert!(report.vf.is_empty());
                assert_eq!(report.ee.len(), 1);
            }
        }
    }
}

#[test]
fn pairs_sharing_a_vertex_are_never_reported() {
    // Two triangles hinged on edge (0, 1); the second swings through the first. Only features
    // that share no vertex may be reported: vertex 3 against face 0, and edges of the second
    // triangle not touching the hinge against edges of the first.
    let x0 = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.3, 1.0, 0.0),
        DVec3::new(0.5, 0.4, 0.5),
    ];
    let mut x1 = x0.clone();
    x1[3] = DVec3::new(0.5, 0.4, -0.5);
    let step = Step::new(x0, x1, vec![[0, 1, 2], [1, 0, 3]]).unwrap();
    for method in methods() {
        let report = Ccd::new()
            .query(&step, method, &QueryOptions::default())
            .unwrap();
        let vf: Vec<(u32, u32)> = report.vf.iter().map(|c| (c.vertex, c.face)).collect();
        assert_eq!(vf, vec![(3, 0)], "{method}");
        for c in &report.ee {
            assert!(!c.a.iter().any(|v| c.b.contains(v)), "{method}: {c:?}");
        }
    }
}
