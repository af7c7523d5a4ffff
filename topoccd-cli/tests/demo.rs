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
}
