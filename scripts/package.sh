#!/usr/bin/env bash
# The library as a registry takes it: `cargo package -p topoccd` (which builds the packaged
# sources on their own), then, outside the workspace, the packaged crate's own tests, and a
# scratch crate that depends on the packaged crate and runs a step.
# Needs the Rust toolchain and crates.io (the packaged crate resolves its dependencies there,
# pinned to the workspace's Cargo.lock). Run from anywhere; CI runs it (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"
# One target folder for everything, so the dependencies are built once.
export CARGO_TARGET_DIR="$PWD/target"
# The packaged crate is a workspace of its own, without the workspace's `[profile.test]`
# (opt-level 2): its tests unoptimised took 2 minutes. The scratch crates below build with
# the same level, so the dependencies are built once.
export CARGO_PROFILE_DEV_OPT_LEVEL=2

version=$(cargo metadata --format-version 1 --no-deps \
    | python3 -c 'import json,sys; print(next(p["version"] for p in json.load(sys.stdin)["packages"] if p["name"]=="topoccd"))')
echo "== [${SECONDS} s] cargo package -p topoccd ($version): the packaged sources build on their own"
# --allow-dirty: a local run may have uncommitted changes; CI runs on a clean clone.
cargo package -p topoccd --allow-dirty --quiet
crate="target/package/topoccd-$version.crate"
listing=$(tar -tzf "$crate")
for f in Cargo.toml README.md LICENSE-MIT LICENSE-APACHE src/lib.rs; do
    grep -qx "topoccd-$version/$f" <<<"$listing" || { echo "error: $crate lacks $f" >&2; exit 1; }
done
echo "$crate: $(wc -l <<<"$listing") files, $(du -k "$crate" | cut -f1) kB"

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
tar -xzf "$crate" -C "$scratch"
unpacked="$scratch/topoccd-$version"
# The workspace's lock file pins the dependencies (cargo trims what the crate does not use).
cp Cargo.lock "$unpacked/Cargo.lock"

# The data tests of the packaged crate read the shared data where the workspace's do.
data="${TOPOCCD_DATA:-../shared/data}"
if [ -d "$data" ]; then
    export TOPOCCD_DATA="$(cd "$data" && pwd)"
fi
echo "== [${SECONDS} s] the packaged crate's tests, outside the workspace (no generators, no internals)"
(cd "$unpacked" && cargo test --quiet)
# Its doctests are the workspace's (`cargo test -p topoccd --doc`, run by scripts/test.sh) on the
# same sources; in the packaged crate they need `--features internals` (see its Cargo.toml).

echo "== [${SECONDS} s] a scratch crate that depends on the packaged crate"
mkdir -p "$scratch/user/src"
cat > "$scratch/user/Cargo.toml" <<TOML
[package]
name = "topoccd-user"
version = "0.0.0"
edition = "2021"
publish = false

[dependencies]
topoccd = { path = "$unpacked" }

[workspace]
TOML
cp Cargo.lock "$scratch/user/Cargo.lock"
cat > "$scratch/user/src/main.rs" <<'RS'
use topoccd::{Ccd, Method, QueryOptions, Step};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let x0 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.2, 1.0], [0.3, 0.2, 1.0], [0.2, 0.3, 1.0]];
    let x1 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.2, -1.0], [0.3, 0.2, -1.0], [0.2, 0.3, -1.0]];
    let step = Step::new(&x0, &x1, &[[0u32, 1, 2], [3, 4, 5]])?;
    let report = Ccd::new().query(&step, Method::Auto, &QueryOptions::default())?;
    assert_eq!(report.vf.len(), 3);
    println!("topoccd from the packaged crate: {} contacts, earliest at {:?}", report.contact_count(), report.earliest_toi());
    Ok(())
}
RS
(cd "$scratch/user" && cargo run --quiet)
echo "package check: passed"
