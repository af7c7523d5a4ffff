//! The README's Rust quick start, pasted as a user would: its block, as it stands, becomes the
//! `src/main.rs` of a fresh crate that depends on this repository's `topoccd` by path, and
//! `cargo run` must build it and print what the README says. (The doctests of `src/lib.rs`
//! run the block too, but rustdoc forgives what a `main.rs` does not: hidden `#` lines, a
//! missing `fn main`.)
//!
//! The scratch crate builds offline, pinned by the workspace's `Cargo.lock`, in a target folder
//! of its own under the workspace's (`target/readme-rust`: the workspace's own is locked by the
//! `cargo test` that runs this).

use std::path::Path;
use std::process::Command;

/// The README's Rust code blocks: (first line, code).
fn rust_blocks(readme: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut lines = readme.lines().enumerate();
    while let Some((n, line)) = lines.next() {
        if line.trim_end() == "```rust" {
            let code: Vec<&str> = lines
                .by_ref()
                .map(|(_, l)| l)
                .take_while(|l| l.trim_end() != "```")
                .collect();
            out.push((n + 2, code.join("\n") + "\n"));
        }
    }
    out
}

#[test]
fn the_readme_rust_quick_start_runs_as_a_main_rs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let blocks = rust_blocks(&readme);
    assert!(!blocks.is_empty(), "the README has no Rust block");
    for (line, code) in &blocks {
        // What rustdoc hides but a main.rs would keep.
        for l in code.lines() {
            assert!(
                !(l.trim_start() == "#" || l.trim_start().starts_with("# ")),
                "README.md:{line}: a rustdoc-hidden line in a block meant for pasting: {l}"
            );
        }
        assert!(
            code.contains("fn main()"),
            "README.md:{line}: no fn main: it cannot be pasted into a main.rs"
        );
    }
    let scratch = root.join("target").join("readme-rust");
    let krate = scratch.join("crate");
    std::fs::create_dir_all(krate.join("src")).unwrap();
    std::fs::write(
        krate.join("Cargo.toml"),
        format!(
            "[package]\nname = \"readme-quick-start\"\nversion = \"0.0.0\"\nedition = \"2021\"\n\
             publish = false\n\n[dependencies]\ntopoccd = {{ path = {:?} }}\n\n[workspace]\n",
            root.join("topoccd")
        ),
    )
    .unwrap();
    std::fs::copy(root.join("Cargo.lock"), krate.join("Cargo.lock")).unwrap();
    for (line, code) in &blocks {
        std::fs::write(krate.join("src/main.rs"), code).unwrap();
        let out = Command::new(env!("CARGO"))
            // The dev profile: the quick start is tiny, and unoptimised dependencies build
            // in a third of the release profile's time.
            .args(["run", "--offline", "--quiet"])
            .current_dir(&krate)
            .env("CARGO_TARGET_DIR", scratch.join("target"))
            .env_remove("RUSTFLAGS")
            .output()
            .expect("cargo runs");
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "README.md:{line}: the block as a main.rs fails:\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
        // The README says what it prints, right after the block.
        let after = &readme[readme.find(code.as_str()).unwrap() + code.len()..];
        let said = after
            .split("it prints `")
            .nth(1)
            .and_then(|s| s.split('`').next())
            .expect("the README says what the quick start prints");
        assert_eq!(
            stdout.trim(),
            said,
            "README.md:{line}: not what the README says"
        );
    }
}
