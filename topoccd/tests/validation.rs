//! One rule for every front end: `x0` shorter than `x1` only across a topology change, parent
//! rows checked (child new, parent old, no child twice), and the warnings on valid but likely
//! mistaken input (`io::input_warnings`) that the command line and the Python package share.

use topoccd::io::{input_warnings, InputWarning};
use topoccd::{Step, StepError};

fn tri() -> Vec<[f64; 3]> {
    vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ]
}

#[test]
fn a_shorter_x0_needs_parents() {
    let (x0, mut x1) = (tri(), tri());
    x1.push([1.0, 0.0, 0.0]);
    let t = [[0u32, 1, 2], [4, 3, 2]];
    let err = Step::new(&x0, &x1, &t).unwrap_err();
    assert_eq!(err, StepError::LengthMismatch { start: 4, end: 5 });
    assert_eq!(
        err.to_string(),
        "the step has 4 vertices at t=0 but 5 at t=1"
    );
    // With a parent list (even an empty one, for a new vertex that does not move): valid.
    let step = Step::with_parents(&x0, &x1, &t, &[[4, 1]]).unwrap();
    assert_eq!(step.x0()[4], [1.0, 0.0, 0.0]);
    assert!(Step::with_parents(&x0, &x1, &t, &[]).is_ok());
    // A topology change only adds vertices.
    let err = Step::with_parents(&x1, &x0, &[[0u32, 1, 2]], &[]).unwrap_err();
    assert_eq!(err, StepError::Shrinks { start: 5, end: 4 });
}

#[test]
fn parent_rows_are_checked_and_named() {
    let (x0, mut x1) = (tri(), tri());
    x1.extend([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let t = [[0u32, 1, 2], [4, 3, 5]];
    let reason = |rows: &[[u32; 2]]| match Step::with_parents(&x0, &x1, &t, rows) {
        Err(StepError::Parent { row, reason, .. }) => (row, reason),
        other => panic!("{rows:?}: {other:?}"),
    };
    assert_eq!(reason(&[[4, 1], [2, 1]]).0, 1);
    assert!(reason(&[[2, 1]])
        .1
        .starts_with("the child is not a new vertex"));
    assert_eq!(reason(&[[4, 5]]), (0, "the parent is not a vertex at t=0"));
    assert_eq!(
        reason(&[[4, 1], [4, 2]]),
        (1, "the child already has a parent")
    );
    assert_eq!(reason(&[[9, 1]]), (0, "the child is not a vertex at t=1"));
    let err = Step::with_parents(&x0, &x1, &t, &[[5, 2], [3, 0]]).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("parent row 1 [3, 0]: the child is not a new vertex"),
        "{err}"
    );
}

/// A `n x n` grid in the plane z = 0, its vertices scaled by `s`.
fn grid(n: u32, s: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut x = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            x.push([s * i as f64, s * j as f64, 0.0]);
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut t = Vec::new();
    for j in 0..n {
        for i in 0..n {
            t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (x, t)
}

#[test]
fn input_warnings_name_collapsed_input_and_its_cause() {
    // A grid with unit spacing, integer coordinates: nothing wrong.
    let (x, t) = grid(8, 1.0);
    assert!(input_warnings(&x, &t).is_empty());
    // Spacing 0.3, cast to integers: every vertex lands on one of a few lattice points.
    let (x, t) = grid(8, 0.3);
    let cast: Vec<[f64; 3]> = x.iter().map(|p| p.map(f64::trunc)).collect();
    let w = input_warnings(&cast, &t);
    assert_eq!(w.len(), 3, "{w:?}");
    let InputWarning::CoincidentVertices {
        duplicates,
        groups,
        largest,
        largest_size,
    } = &w[0]
    else {
        panic!("{w:?}")
    };
    // x, y in {0, 1, 2} after the cast: 9 points for 81 vertices.
    assert_eq!((*duplicates, *groups), (81 - 9, 9));
    assert_eq!(largest[..3], [0, 1, 2]);
    assert!(*largest_size >= 9);
    let text = w[0].to_string();
    assert!(
        text.starts_with("72 vertices sit exactly on another vertex (9 groups"),
        "{text}"
    );
    assert!(text.contains("spurious contacts at t=0"), "{text}");
    let InputWarning::ZeroAreaTriangles { count, first } = &w[1] else {
        panic!("{w:?}")
    };
    assert!(*count > 64 && first.len() == 6, "{count} {first:?}");
    assert!(
        w[1].to_string().contains("zero area (triangles 0, 1,"),
        "{}",
        w[1]
    );
    assert_eq!(w[2], InputWarning::IntegralCoordinates { vertices: 81 });
    assert!(w[2].to_string().contains("cast to integers"));
    // The same positions before the cast: no warning.
    assert!(input_warnings(&x, &t).is_empty());
    // A UV sphere's duplicate pole: coincident vertices only (not integral: a fraction).
    let mut x = vec![
        [0.5, 0.0, 1.0],
        [0.5, 0.0, 1.0],
        [1.0, 0.5, 0.0],
        [0.0, 0.5, 0.0],
    ];
    x.push([0.5, 1.0, 0.0]);
    let t = [[0, 2, 3], [1, 3, 4]];
    let w = input_warnings(&x, &t);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0]
        .to_string()
        .starts_with("1 vertices sit exactly on another vertex (1 groups"));
}
