//! Conformance of the public per-pair tests (`topoccd::pair`) on the Sample-Queries data
//! (`../shared/data/queries`, exact ground truth): no false negative, every time of impact in
//! `[0, t_max]`, and the false positives held to Tight-Inclusion's count on the same files.

use std::path::PathBuf;

use topoccd::io::queries::{find_query_files, read_query_file, QueryKind};
use topoccd::pair::{edge_edge, vertex_face, EdgeEdge, Outcome, VertexFace};
use topoccd::NarrowOptions;

fn data_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("TOPOCCD_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"))
        .join("queries");
    if dir.is_dir() {
        return Some(dir);
    }
    assert!(
        std::env::var_os("TOPOCCD_REQUIRE_DATA").is_none(),
        "TOPOCCD_REQUIRE_DATA is set but the shared data is absent: {}",
        dir.display()
    );
    eprintln!(
        "SKIPPED, NOT TESTED: the shared query data is not at {}",
        dir.display()
    );
    None
}

/// Queries, touching ones, false negatives (file:line) and false positives of one kind.
fn run(
    dir: &PathBuf,
    kind: QueryKind,
    options: &NarrowOptions,
) -> (usize, usize, Vec<String>, usize) {
    let (mut queries, mut touching, mut missed, mut false_pos) = (0, 0, vec![], 0);
    for (k, path) in find_query_files(dir).expect("query folder readable") {
        if k != kind {
            continue;
        }
        for q in read_query_file(&path).expect("query file well formed") {
            let points = q.points.map(|p| p.to_array());
            let outcome = match kind {
                QueryKind::VertexFace => vertex_face(&VertexFace::from_points(points), options),
                QueryKind::EdgeEdge => edge_edge(&EdgeEdge::from_points(points), options),
            }
            .expect("valid options");
            if let Outcome::Contact { toi, .. } = outcome {
                assert!(
                    (0.0..=options.t_max).contains(&toi),
                    "toi {toi} out of range"
                );
            }
            queries += 1;
            touching += usize::from(q.touching);
            if q.touching && !outcome.is_contact() {
                missed.push(format!("{}:{}", path.display(), q.line));
            }
            false_pos += usize::from(!q.touching && outcome.is_contact());
        }
    }
    (queries, touching, missed, false_pos)
}

#[test]
fn public_pair_tests_miss_no_touching_query() {
    let Some(dir) = data_dir() else { return };
    // Tight-Inclusion's false positives on these files (IPC toolkit, tolerance 1e-6).
    for (kind, count, bar) in [
        (QueryKind::VertexFace, 1835, 56),
        (QueryKind::EdgeEdge, 3049, 69),
    ] {
        let (queries, touching, missed, false_pos) = run(&dir, kind, &NarrowOptions::default());
        eprintln!("{kind:?}: {queries} queries, {touching} touching, {false_pos} false positives");
        assert_eq!(queries, count, "{kind:?}: the data set changed");
        assert!(missed.is_empty(), "{kind:?} false negatives: {missed:?}");
        assert!(
            false_pos <= bar,
            "{kind:?}: {false_pos} false positives > {bar}"
        );
    }
    // Coarse and fine tolerances, and a budget of a few boxes, stay conservative.
    for options in [
        NarrowOptions {
            tolerance: 1e-3,
            ..NarrowOptions::default()
        },
        NarrowOptions {
            tolerance: 1e-9,
            ..NarrowOptions::default()
        },
        NarrowOptions {
            max_iterations: 3,
            ..NarrowOptions::default()
        },
    ] {
        for kind in [QueryKind::VertexFace, QueryKind::EdgeEdge] {
            let (_, _, missed, _) = run(&dir, kind, &options);
            assert!(
                missed.is_empty(),
                "{kind:?} with {options:?}: missed {missed:?}"
            );
        }
    }
}

#[test]
fn invalid_options_are_refused() {
    let q = VertexFace::default();
    let bad = NarrowOptions {
        t_max: 0.0,
        ..NarrowOptions::default()
    };
    assert_eq!(
        vertex_face(&q, &bad).unwrap_err().to_string(),
        "t_max must be in (0, 1], got 0"
    );
    let bad = NarrowOptions {
        max_iterations: 0,
        ..NarrowOptions::default()
    };
    assert!(edge_edge(&EdgeEdge::default(), &bad).is_err());
}
