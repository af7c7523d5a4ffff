//! Elementary tests against analytic answers: near-degenerate grids around +-epsilon, the time
//! of impact, and degenerate input (zero-length edges, zero-area triangles, coplanar motion,
//! touching at t=0, repeated points, non-finite input).

use topoccd::math::DVec3;
use topoccd::narrow::{
    edge_edge, vertex_face, Certainty, EdgeEdge, NarrowOptions, Outcome, VertexFace,
};

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// A static triangle in the plane z=0 and a vertex moving from `p0` to `p1`.
fn vf_static(p0: DVec3, p1: DVec3) -> VertexFace {
    let (f0, f1, f2) = (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0));
    VertexFace {
        v_t0: p0,
        f0_t0: f0,
        f1_t0: f1,
        f2_t0: f2,
        v_t1: p1,
        f0_t1: f0,
        f1_t1: f1,
        f2_t1: f2,
    }
}

/// Whether a reported time of impact is no later than `exact` and within tolerance of it.
fn near(toi: f64, exact: f64) -> bool {
    (exact - 2e-6..=exact).contains(&toi)
}

fn assert_finite(o: Outcome) {
    if let Outcome::Contact { toi, .. } = o {
        assert!(
            toi.is_finite() && (0.0..=1.0).contains(&toi),
            "bad toi {toi}"
        );
    }
}

/// The false-positive distance documented in `narrow::solver` for unit-sized, unit-speed
/// features at the default tolerance, with a wide margin: farther than this must be separated.
const FP_DISTANCE: f64 = 1e-4;

#[test]
fn vertex_over_triangle_grid_stopping_at_plus_minus_epsilon() {
    let opts = NarrowOptions::default();
    // Barycentric-like grid over the triangle, its edges and corners, and just outside them.
    let coords = [-1e-3, 0.0, 0.25, 0.5, 1.0 - 1e-3, 1.0];
    for &x in &coords {
        for &y in &coords {
            let inside = x >= 0.0 && y >= 0.0 && x + y <= 1.0;
            for eps in [1e-2, 1e-3, FP_DISTANCE, 1e-8, 1e-12, 0.0] {
                for sign in [-1.0, 1.0] {
                    let end = sign * eps;
                    let q = vf_static(v(x, y, 1.0), v(x, y, end));
                    let o = vertex_face(&q, &opts);
                    assert_finite(o);
                    let touches = inside && end <= 0.0;
                    if touches {
                        let exact = 1.0 / (1.0 - end); // z(t) = 1 + t (end - 1) = 0
                        let toi = o.toi().unwrap_or_else(|| panic!("missed ({x},{y},{end})"));
                        assert!(near(toi, exact), "toi {toi} vs {exact}");
                    } else {
                        // Closest approach: the vertical gap `end` (above) or the horizontal
                        // distance outside the triangle (at least 1e-3 / sqrt 2 here).
                        let gap = if inside { end } else { 1e-3 / 2f64.sqrt() };
                        if gap >= FP_DISTANCE {
                            assert!(!o.is_contact(), "false positive at ({x},{y},{end}): {o:?}");
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn crossing_edges_offset_by_plus_minus_epsilon() {
    let opts = NarrowOptions::default();
    for eps in [1e-2, FP_DISTANCE, 1e-9, 0.0] {
        for sign in [-1.0, 1.0] {
            // Edge b along y at z=0 spans y in [-1, 1], or [sign eps, 2 + sign eps]: its lower end
            // then overshoots the x-axis (edge a's path) by eps or stops short of it by eps.
            for (shift, crosses) in [(0.0, true), (1.0 + sign * eps, sign * eps <= 0.0)] {
                let b0 = v(0.0, -1.0 + shift, 0.0);
                let b1 = v(0.0, 1.0 + shift, 0.0);
                let q = EdgeEdge {
                    ea0_t0: v(-1.0, 0.0, 1.0),
                    ea1_t0: v(1.0, 0.0, 1.0),
                    eb0_t0: b0,
                    eb1_t0: b1,
                    ea0_t1: v(-1.0, 0.0, -1.0),
                    ea1_t1: v(1.0, 0.0, -1.0),
                    eb0_t1: b0,
                    eb1_t1: b1,
                };
                for query in [q, q.swapped()] {
                    let o = edge_edge(&query, &opts);
                    assert_finite(o);
                    if crosses {
                        let toi = o.toi().expect("crossing edges missed");
                        assert!(near(toi, 0.5), "toi {toi}");
                    } else if eps >= FP_DISTANCE {
                        assert!(!o.is_contact(), "false positive at eps {eps}: {o:?}");
                    }
                }
            }
        }
    }
}

#[test]
fn min_separation_reports_near_approach() {
    // The vertex stops 0.01 above the plane: separated at 0, a contact with min_distance 0.02
    // at the time it comes within 0.02 (z(t) = 1 - 0.99 t = 0.02 -> t = 0.98 / 0.99).
    let q = vf_static(v(0.2, 0.2, 1.0), v(0.2, 0.2, 0.01));
    assert_eq!(
        vertex_face(&q, &NarrowOptions::default()),
        Outcome::Separated
    );
    let opts = NarrowOptions {
        min_distance: 0.02,
        ..NarrowOptions::default()
    };
    let toi = vertex_face(&q, &opts).toi().expect("within min_distance");
    let exact = 0.98 / 0.99;
    assert!(near(toi, exact), "toi {toi} vs {exact}");
}

#[test]
fn t_max_limits_the_search() {
    let q = vf_static(v(0.2, 0.2, 1.0), v(0.2, 0.2, -1.0)); // contact at 0.5
    let early = NarrowOptions {
        tmax: 0.4,
        ..NarrowOptions::default()
    };
    assert_eq!(vertex_face(&q, &early), Outcome::Separated);
    let late = NarrowOptions {
        tmax: 0.6,
        ..NarrowOptions::default()
    };
    assert!(vertex_face(&q, &late).toi().is_some_and(|t| t <= 0.5));
}

#[test]
fn degenerate_inputs_are_conservative_and_finite() {
    let opts = NarrowOptions::default();
    let o = v(0.0, 0.0, 0.0);
    // Zero-area triangle (all corners equal) with the vertex passing exactly through it.
    let q = VertexFace {
        v_t0: v(0.0, 0.0, 1.0),
        f0_t0: o,
        f1_t0: o,
        f2_t0: o,
        v_t1: v(0.0, 0.0, -1.0),
        f0_t1: o,
        f1_t1: o,
        f2_t1: o,
    };
    assert!(vertex_face(&q, &opts).toi().is_some_and(|t| near(t, 0.5)));
    // Collinear triangle, vertex passing beside it: separated.
    let q2 = VertexFace {
        f1_t0: v(1.0, 0.0, 0.0),
        f2_t0: v(2.0, 0.0, 0.0),
        f1_t1: v(1.0, 0.0, 0.0),
        f2_t1: v(2.0, 0.0, 0.0),
        v_t0: v(0.5, 1.0, 1.0),
        v_t1: v(0.5, 1.0, -1.0),
        ..q
    };
    assert_eq!(vertex_face(&q2, &opts), Outcome::Separated);
    // Zero-length edges meeting at one moving point.
    let e = EdgeEdge {
        ea0_t0: v(0.0, 0.0, 1.0),
        ea1_t0: v(0.0, 0.0, 1.0),
        eb0_t0: o,
        eb1_t0: o,
        ea0_t1: v(0.0, 0.0, -1.0),
        ea1_t1: v(0.0, 0.0, -1.0),
        eb0_t1: o,
        eb1_t1: o,
    };
    assert!(edge_edge(&e, &opts).toi().is_some_and(|t| near(t, 0.5)));
    // Parallel, coplanar edges sliding along each other, overlapping from t=0.
    let p = EdgeEdge {
        ea0_t0: v(0.0, 0.0, 0.0),
        ea1_t0: v(1.0, 0.0, 0.0),
        eb0_t0: v(0.5, 0.0, 0.0),
        eb1_t0: v(1.5, 0.0, 0.0),
        ea0_t1: v(1.0, 0.0, 0.0),
        ea1_t1: v(2.0, 0.0, 0.0),
        eb0_t1: v(0.5, 0.0, 0.0),
        eb1_t1: v(1.5, 0.0, 0.0),
    };
    assert_eq!(edge_edge(&p, &opts).toi(), Some(0.0));
    // The same edges side by side at distance 0.1: separated.
    let shifted = |x: DVec3| x + v(0.0, 0.1, 0.0);
    let p2 = EdgeEdge {
        eb0_t0: shifted(p.eb0_t0),
        eb1_t0: shifted(p.eb1_t0),
        eb0_t1: shifted(p.eb0_t1),
        eb1_t1: shifted(p.eb1_t1),
        ..p
    };
    assert_eq!(edge_edge(&p2, &opts), Outcome::Separated);
    // Vertex resting in the triangle's plane, inside it, all step long: contact at t=0.
    let q3 = vf_static(v(0.2, 0.2, 0.0), v(0.3, 0.3, 0.0));
    assert_eq!(vertex_face(&q3, &opts).toi(), Some(0.0));
    // Coplanar motion outside the triangle: separated.
    let q4 = vf_static(v(1.0, 1.0, 0.0), v(2.0, 0.5, 0.0));
    assert_eq!(vertex_face(&q4, &opts), Outcome::Separated);
    // Every point the same: touching throughout.
    let all = VertexFace::from_points([o; 8]);
    assert_eq!(vertex_face(&all, &opts).toi(), Some(0.0));
}

#[test]
fn non_finite_input_is_an_undecided_contact_at_zero() {
    let opts = NarrowOptions::default();
    for bad in [f64::NAN, f64::INFINITY, -f64::INFINITY] {
        let q = vf_static(v(0.2, bad, 1.0), v(0.2, 0.2, -1.0));
        assert_eq!(
            vertex_face(&q, &opts),
            Outcome::Contact {
                toi: 0.0,
                certainty: Certainty::InvalidInput
            }
        );
    }
    // Finite but huge coordinates whose differences overflow.
    let q = vf_static(v(1e308, 0.0, 0.0), v(-1e308, 0.0, 0.0));
    assert!(vertex_face(&q, &opts).is_contact());
}

#[test]
fn options_out_of_range_are_clamped_not_panicking() {
    let q = vf_static(v(0.2, 0.2, 1.0), v(0.2, 0.2, -1.0));
    for opts in [
        NarrowOptions {
            tolerance: 0.0,
            ..NarrowOptions::default()
        },
        NarrowOptions {
            tolerance: f64::NAN,
            tmax: f64::NAN,
            min_distance: f64::NAN,
            max_iterations: 0,
        },
        NarrowOptions {
            tmax: 7.0,
            tolerance: 5.0,
            ..NarrowOptions::default()
        },
    ] {
        assert!(vertex_face(&q, &opts).toi().is_some_and(|t| t <= 0.5));
    }
}
