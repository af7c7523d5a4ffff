//! The line-search helpers on the real cloth-funnel step (`../shared/data/scenes`), whose
//! earliest time of impact is known exactly (0.0452322, a vertex-face pair): the step size
//! stops short of it, and a whole-step query of the shortened step finds no contact.

use std::path::PathBuf;

use topoccd::io::sequence::Sequence;
use topoccd::line_search::{LineSearchOptions, StepStatus};
use topoccd::{Ccd, Certainty, Method, QueryOptions, Step};

/// The exact earliest root of cloth-funnel's step (the data's `toi/227vf_toi.txt`).
const FUNNEL_EARLIEST: f64 = 0.0452322;

/// A step's positions at t=0 and t=1 and its triangles.
type Frames = (Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<[u32; 3]>);

fn funnel() -> Option<Frames> {
    let dir = std::env::var_os("TOPOCCD_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"))
        .join("scenes/cloth-funnel");
    if !dir.is_dir() {
        assert!(
            std::env::var_os("TOPOCCD_REQUIRE_DATA").is_none(),
            "TOPOCCD_REQUIRE_DATA is set but the shared data is absent: {}",
            dir.display()
        );
        eprintln!(
            "SKIPPED, NOT TESTED: the shared scenes are not at {}",
            dir.display()
        );
        return None;
    }
    let steps = Sequence::open(&dir).expect("cloth-funnel opens");
    let frames = steps.load(0).expect("cloth-funnel's step reads");
    Some((frames.x0, frames.x1, frames.triangles))
}

/// `x0 + alpha (x1 - x0)`.
fn along(x0: &[[f64; 3]], x1: &[[f64; 3]], alpha: f64) -> Vec<[f64; 3]> {
    x0.iter()
        .zip(x1)
        .map(|(a, b)| std::array::from_fn(|k| a[k] + alpha * (b[k] - a[k])))
        .collect()
}

#[test]
fn the_step_size_gives_a_step_without_contact_on_cloth_funnel() {
    let Some((x0, x1, triangles)) = funnel() else {
        return;
    };
    let step = Step::new(&x0, &x1, &triangles).expect("valid step");
    let mut ccd = Ccd::new();
    for min_distance in [0.0, 1e-8] {
        let mut options = LineSearchOptions::default();
        options.query.narrow.min_distance = min_distance;
        let size = ccd
            .collision_free_stepsize(&step, &options)
            .expect("valid options");
        let earliest = size.earliest.expect("the step has contacts");
        assert_eq!(earliest.certainty(), Certainty::Resolved);
        // The reported time is no later than the exact first contact, and within the
        // tolerance of it without a separation (rounding aside: the data gives 7 digits).
        assert!(earliest.toi() <= FUNNEL_EARLIEST + 1e-7, "{earliest:?}");
        if min_distance == 0.0 {
            assert!(
                earliest.toi() >= FUNNEL_EARLIEST - 1e-6 - 1e-7,
                "{earliest:?}"
            );
        }
        assert_eq!(size.alpha, 0.8 * earliest.toi());
        assert!(
            size.alpha > 0.0,
            "features within {min_distance} at the start"
        );

        // The whole step collides; the shortened step does not, in either helper or a query.
        let whole = ccd
            .is_step_collision_free(&step, &options)
            .expect("valid options");
        assert!(
            matches!(whole, StepStatus::Collides(c) if c == earliest),
            "{whole:?}"
        );
        let x_alpha = along(&x0, &x1, size.alpha);
        let short = Step::new(&x0, &x_alpha, &triangles).expect("valid step");
        let status = ccd
            .is_step_collision_free(&short, &options)
            .expect("valid options");
        assert_eq!(
            status,
            StepStatus::CollisionFree,
            "min_distance {min_distance}"
        );
        let all = QueryOptions {
            narrow: options.query.narrow,
            ..QueryOptions::default()
        };
        for method in [Method::Bvh, Method::Brute] {
            let report = ccd.query(&short, method, &all).expect("valid options");
            assert_eq!(report.contact_count(), 0, "{method:?}, {min_distance}");
        }
    }
}

#[test]
fn a_step_without_contact_may_be_taken_whole() {
    let Some((x0, _, triangles)) = funnel() else {
        return;
    };
    // Half a funnel step's worth of motion, all of it rigid: nothing changes distance.
    let x1: Vec<[f64; 3]> = x0.iter().map(|p| [p[0] + 0.01, p[1], p[2]]).collect();
    let step = Step::new(&x0, &x1, &triangles).expect("valid step");
    let options = LineSearchOptions::default();
    let size = Ccd::new()
        .collision_free_stepsize(&step, &options)
        .expect("valid options");
    assert_eq!((size.alpha, size.earliest), (1.0, None));
    let tmax = LineSearchOptions {
        query: QueryOptions {
            narrow: topoccd::NarrowOptions {
                tmax: 0.5,
                ..Default::default()
            },
            ..QueryOptions::default()
        },
        ..options
    };
    let size = Ccd::new()
        .collision_free_stepsize(&step, &tmax)
        .expect("valid");
    assert_eq!(size.alpha, 0.5, "only [0, tmax] was searched");
}

#[test]
fn bad_rescaling_and_bad_input_are_refused() {
    use topoccd::line_search::{collision_free_stepsize, LineSearchError};
    let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let zero = LineSearchOptions {
        conservative_rescaling: 0.0,
        ..LineSearchOptions::default()
    };
    assert!(matches!(
        collision_free_stepsize(&x, &x, &[[0u32, 1, 2]], &zero),
        Err(LineSearchError::ConservativeRescaling(_))
    ));
    let err = collision_free_stepsize(&x, &x, &[[0u32, 1, 5]], &LineSearchOptions::default())
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "triangle 0 names vertex 5, but there are only 3 vertices"
    );
}

/// Triangle 1 pierces triangle 0 at t=0 and does not move: no contact starts in the step, so
/// the helpers take it whole unless `check_start` looks at the start.
#[test]
fn check_start_refuses_a_start_that_intersects() {
    use topoccd::line_search::{collision_free_stepsize, is_step_collision_free, LineSearchError};
    let x = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.2, 0.2, -1.0],
        [0.3, 0.2, 1.0],
        [0.2, 0.3, 1.0],
        [5.0, 5.0, 5.0],
        [6.0, 5.0, 5.0],
        [5.0, 6.0, 5.0],
    ];
    let triangles = [[0u32, 1, 2], [3, 4, 5], [6, 7, 8]];
    let unchecked = LineSearchOptions::default();
    let size = collision_free_stepsize(&x, &x, &triangles, &unchecked).expect("valid");
    assert_eq!(size.alpha, 1.0, "the premise is not checked by default");
    let checked = LineSearchOptions {
        check_start: true,
        ..LineSearchOptions::default()
    };
    let err = collision_free_stepsize(&x, &x, &triangles, &checked).unwrap_err();
    assert_eq!(
        err,
        LineSearchError::StartIntersects {
            triangles: [0, 1],
            count: 1
        }
    );
    assert!(err
        .to_string()
        .starts_with("triangles 0 and 1 intersect at t=0"));
    let err = is_step_collision_free(&x, &x, &triangles, &checked).unwrap_err();
    assert!(matches!(err, LineSearchError::StartIntersects { .. }));
    // Apart at t=0 (triangle 1 lifted above triangle 0), the check passes and the query runs.
    let mut apart = x;
    for p in &mut apart[3..6] {
        p[2] += 2.0;
    }
    let size = collision_free_stepsize(&apart, &apart, &triangles, &checked).expect("apart");
    assert_eq!(size.alpha, 1.0);
}
