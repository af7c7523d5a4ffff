//! Conformance of the public per-pair tests (`topoccd::pair`) on the Sample-Queries data
//! (`../shared/data/queries`, exact ground truth): no false negative, every time of impact in
//! `[0, tmax]`, and the false positives held to Tight-Inclusion's count on the same files.

use std::path::{Path, PathBuf};

use topoccd::pair::{edge_edge, vertex_face, EdgeEdge, Outcome, VertexFace};
use topoccd::NarrowOptions;

#[derive(Clone, Copy, Debug, PartialEq)]
enum QueryKind {
    VertexFace,
    EdgeEdge,
}

/// One query of a file: its eight points, its ground truth and its first line.
struct Query {
    points: [[f64; 3]; 8],
    touching: bool,
    line: usize,
}

/// Reads a Sample-Queries file: 8 rows `xnum,xden,ynum,yden,znum,znum,gt` per query, each
/// coordinate an exact rational with a power-of-two denominator (so the division is exact).
fn read_queries(path: &Path) -> Vec<Query> {
    let text = std::fs::read_to_string(path).expect("query file readable");
    let rows: Vec<Vec<i128>> = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split(',')
                .map(|v| v.trim().parse().expect("an integer"))
                .collect()
        })
        .collect();
    assert_eq!(
        rows.len() % 8,
        0,
        "{}: not 8 rows per query",
        path.display()
    );
    rows.chunks(8)
        .enumerate()
        .map(|(q, block)| Query {
            points: std::array::from_fn(|i| {
                std::array::from_fn(|k| block[i][2 * k] as f64 / block[i][2 * k + 1] as f64)
            }),
            touching: block[0][6] == 1,
            line: 8 * q + 1,
        })
        .collect()
}

/// The query files below `dir`: `*/vertex-face/*.csv` and `*/edge-edge/*.csv`, sorted.
fn find_query_files(dir: &Path) -> Vec<(QueryKind, PathBuf)> {
    let mut out = Vec::new();
    for scene in std::fs::read_dir(dir).expect("query folder readable") {
        let scene = scene.expect("entry").path();
        for (kind, sub) in [
            (QueryKind::VertexFace, "vertex-face"),
            (QueryKind::EdgeEdge, "edge-edge"),
        ] {
            let Ok(files) = std::fs::read_dir(scene.join(sub)) else {
                continue;
            };
            for f in files {
                let f = f.expect("entry").path();
                if f.extension().is_some_and(|e| e == "csv") {
                    out.push((kind, f));
                }
            }
        }
    }
    out.sort_by(|a, b| a.1.cmp(&b.1));
    out
}

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
fn run(dir: &Path, kind: QueryKind, options: &NarrowOptions) -> (usize, usize, Vec<String>, usize) {
    let (mut queries, mut touching, mut missed, mut false_pos) = (0, 0, vec![], 0);
    for (k, path) in find_query_files(dir) {
        if k != kind {
            continue;
        }
        for q in read_queries(&path) {
            let points = q.points;
            let outcome = match kind {
                QueryKind::VertexFace => vertex_face(&VertexFace::from_points(points), options),
                QueryKind::EdgeEdge => edge_edge(&EdgeEdge::from_points(points), options),
            }
            .expect("valid options");
            if let Outcome::Contact { toi, .. } = outcome {
                assert!(
                    (0.0..=options.tmax).contains(&toi),
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
        tmax: 0.0,
        ..NarrowOptions::default()
    };
    assert_eq!(
        vertex_face(&q, &bad).unwrap_err().to_string(),
        "tmax must be in (0, 1], got 0"
    );
    let bad = NarrowOptions {
        max_iterations: 0,
        ..NarrowOptions::default()
    };
    assert!(edge_edge(&EdgeEdge::default(), &bad).is_err());
}
