#!/usr/bin/env bash
# The tests, Python included: the Rust workspace in release mode, then the Python package built
# in a fresh virtual environment (target/test-venv) with its pytest suite and Ray.
# Needs the Rust toolchain, python3 with venv, and crates.io / PyPI.
# The data tests read ../shared/data (the public Sample-Queries and Sample-Scalable-CCD-Data
# sets; see the README). Without it they check nothing and say so below; with
# TOPOCCD_REQUIRE_DATA=1 (as .ci/run sets it) its absence is an error.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"

data="${TOPOCCD_DATA:-../shared/data}"
missing=""
if [ ! -f "$data/queries/LICENSE" ] || [ ! -d "$data/scenes/cloth-ball" ]; then
    if [ -n "${TOPOCCD_REQUIRE_DATA:-}" ]; then
        echo "error: the shared data is not at $data (TOPOCCD_REQUIRE_DATA is set)" >&2
        exit 1
    fi
    missing="WARNING: the shared data is not at $data: the data tests checked NOTHING (see the README)"
    echo "$missing" >&2
fi

echo "== Rust tests (release)"
cargo test --workspace --release

echo "== Python package: a fresh virtual environment, then its pytest suite"
# The suite compares with the CLI (target/release/topoccd) and reads the shared data; with
# CI=true it fails rather than skips where either is absent.
cargo build --release --quiet -p topoccd-cli
PYTHON_BIN="${PYTHON:-python3}"
VENV=target/test-venv
rm -rf "$VENV"
"$PYTHON_BIN" -m venv "$VENV"
"$VENV/bin/python" -m pip install --quiet --upgrade pip
"$VENV/bin/python" -m pip install --quiet maturin pytest hypothesis numpy ray tqdm
"$VENV/bin/python" -m pip install --quiet "./topoccd-py[ray,test]"
"$VENV/bin/python" -c "import topoccd; print('topoccd', topoccd.__version__, 'imported')"
set +e
"$VENV/bin/python" -m pytest topoccd-py/tests -q -rs
status=$?
set -e
if [ "$status" -eq 5 ]; then
    echo "error: pytest collected no tests" >&2
    exit 1
fi
if [ -n "$missing" ]; then
    echo "$missing" >&2
fi
exit "$status"
