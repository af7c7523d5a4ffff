#!/usr/bin/env bash
# Prints the crates that the README's demo build (`cargo run --release -p topoccd-cli`) and the
# test build of scripts/test.sh (`cargo test --workspace`) would compile with different
# features; each such crate compiles twice. No output: one build serves both.
set -euo pipefail
cd "$(dirname "$0")/.."
tree() { cargo tree "$@" -f '{p} {f}' --prefix none | sed 's/ (\*)//; s/ (\/[^)]*)//' | sort -u; }
cli=$(tree -p topoccd-cli -e normal,build)
ws=$(tree --workspace)
# A crate of the demo's build whose feature set the test build never has.
comm -23 <(printf '%s\n' "$cli") <(printf '%s\n' "$ws")
