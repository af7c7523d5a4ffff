//! Validation of a step's input, and degenerate meshes.

use topoccd::math::DVec3;
use topoccd::{query, Ccd, Frame, Method, Mode, QueryOptions, Step, StepError};

fn three() -> Vec<DVec3> {
    vec![DVec3::ZERO, DVec3::X, DVec3::Y]
}

#[test]
fn length_mismatch_is_refused() {
    let mut x1 = three();
    x1.push(DVec3::Z);
    let err = Step::new(three(), x1, vec![[0, 1, 2]]).unwrap_err();
    assert_eq!(err, StepError::LengthMismatch { start: 3, end: 4 });
    assert_eq!(
        err.to_string(),
        "the step has 3 vertices at t=0 but 4 at t=1"
    );
}

#[test]
fn index_out_of_range_is_refused() {
    let err = Step::new(three(), three(), vec![[0, 1, 2], [2, 1, 7]]).unwrap_err();
    let expected = StepError::IndexOutOfRange {
        triangle: 1,
        index: 7,
        vertices: 3,
    };
    assert_eq!(err, expected);
}

#[test]
fn non_finite_coordinates_are_refused() {
    let mut x0 = three();
    x0[1].y = f64::NAN;
    let err = Step::new(x0, three(), vec![[0, 1, 2]]).unwrap_err();
    assert!(matches!(
        err,
        StepError::NonFinite { vertex: 1, frame: Frame::Start, position } if position[1].is_nan()
    ));
    let mut x1 = three();
    x1[2].z = f64::NEG_INFINITY;
    let err = Step::new(three(), x1, vec![[0, 1, 2]]).unwrap_err();
    assert_eq!(
        err,
        StepError::NonFinite {
            vertex: 2,
            frame: Frame::End,
            position: [0.0, 1.0, f64::NEG_INFINITY],
        }
    );
}

#[test]
fn repeated_vertices_are_refused() {
    for (tri, vertex) in [([0, 0, 1], 0), ([2, 1, 2], 2), ([0, 1, 1], 1)] {
        let err = Step::new(three(), three(), vec![[0, 1, 2], tri]).unwrap_err();
        assert_eq!(
            err,
            StepError::RepeatedVertex {
                triangle: 1,
                vertex
            }
        );
    }
}

#[test]
fn empty_and_single_triangle_meshes_have_no_contacts() {
    let mut ccd = Ccd::new();
    let none: [[f64; 3]; 0] = [];
    let empty = Step::new(&none, &none, &[] as &[[u32; 3]]).unwrap();
    let lonely = Step::new(
        three(),
        three()
            .iter()
            .map(|p| *p + DVec3::Z)
            .collect::<Vec<DVec3>>(),
        vec![[0, 1, 2]],
    )
    .unwrap();
    // Unreferenced vertices are allowed and ignored, even crossing the triangle.
    let mut x0 = three();
    let mut x1: Vec<DVec3> = three();
    x0.push(DVec3::new(0.2, 0.2, 1.0));
    x1.push(DVec3::new(0.2, 0.2, -1.0));
    let unreferenced = Step::new(x0, x1, vec![[0, 1, 2]]).unwrap();
    for step in [&empty, &lonely, &unreferenced] {
        for method in [Method::Brute, Method::Bvh, Method::Cluster] {
            for mode in [Mode::All, Mode::Earliest] {
                let options = QueryOptions {
                    mode,
                    ..QueryOptions::default()
                };
                let report = ccd.query(step, method, &options).unwrap();
                assert_eq!(ccd.validate_tree(step), Ok(()));
                assert_eq!(report.contact_count(), 0);
                assert_eq!(report.earliest, None);
                assert_eq!((report.stats.vf_tests, report.stats.ee_tests), (0, 0));
            }
        }
    }
    assert_eq!(
        query(&empty, Method::Bvh, &QueryOptions::default())
            .unwrap()
            .stats
            .bv_tests,
        0
    );
}
