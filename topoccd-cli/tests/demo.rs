//! `topoccd demo` explains itself: a plain-words line says what was detected, the tables carry
//! a legend, counts take the singular when they are 1.

use std::process::Command;

#[test]
fn the_demo_says_what_it_found_in_plain_words() {
    // A small scene: 3 frames (2 steps) at scale 0.005, well under a second.
    let out = Command::new(env!("CARGO_BIN_EXE_topoccd"))
        .args(["demo", "--scale", "0.005", "--frames", "3"])
        .output()
        .expect("run topoccd demo");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let found = text
        .lines()
        .find(|l| l.starts_with("Found "))
        .unwrap_or_else(|| panic!("no 'Found ...' line:\n{text}"));
    assert!(
        found.contains(" vertex-face contact") && found.contains(" edge-edge contact"),
        "{found}"
    );
    assert!(found.contains("over 2 steps"), "{found}");
    assert!(found.contains("the earliest at t="), "{found}");
    // The triangle count reads as one count, not a range; the cut steps are explained.
    assert!(text.contains("1,272 triangles throughout"), "{text}");
    assert!(
        text.contains("1 step cuts or breaks the mesh (vertices are split"),
        "{text}"
    );
    assert!(
        !text.contains("1 steps") && !text.contains("1 pieces"),
        "{text}"
    );
    // Every column is explained; no unexplained abbreviation is left.
    for needle in [
        "contacts/step",
        "What the columns mean:",
        "BV tests: bounding-volume overlap tests",
        "elem. tests: elementary tests",
        "leaf clusters",
        "intermediate clusters",
    ] {
        assert!(text.contains(needle), "{needle:?} missing:\n{text}");
    }
    for jargon in [" LC ", " IC ", "ratio", "lazy BVHs"] {
        assert!(!text.contains(jargon), "{jargon:?} left:\n{text}");
    }
    // One line says why cluster wins or loses, from the tables' own figures: the verdict
    // follows the printed speedup, and the grouping's cost is the cluster row's clustering
    // and merging milliseconds.
    let speedup: f64 = text
        .split("Speedup of cluster over bvh: ")
        .nth(1)
        .and_then(|s| s.split('x').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no speedup:\n{text}"));
    let why = text
        .lines()
        .find(|l| l.starts_with("Why cluster"))
        .unwrap_or_else(|| panic!("no 'Why cluster ...' line:\n{text}"));
    // The printed speedup is rounded: near a threshold either side's verdict may follow it.
    let verdict = |s: f64| {
        if s > 1.05 {
            "Why cluster wins here"
        } else if s < 0.95 {
            "Why cluster loses here"
        } else {
            "Why cluster and bvh tie here"
        }
    };
    assert!(
        why.starts_with(verdict(speedup - 0.005)) || why.starts_with(verdict(speedup + 0.005)),
        "{speedup}: {why}"
    );
    assert!(why.contains(&format!("({speedup:.2}x")), "{why}");
    let row: Vec<f64> = text
        .lines()
        .find(|l| l.trim_start().starts_with("cluster "))
        .unwrap_or_else(|| panic!("no cluster row:\n{text}"))
        .split_whitespace()
        .skip(1)
        .filter_map(|w| w.parse().ok())
        .collect();
    // clustering ms, merging ms, build, traverse, narrow, total, ...
    let grouping: f64 = why
        .split("costs it ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no grouping cost: {why}"));
    assert!(
        (grouping - (row[0] + row[1])).abs() <= 0.011,
        "{why} against the row {row:?}"
    );
}
