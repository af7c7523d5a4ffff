#!/usr/bin/env bash
# The tests, Python included: the Rust workspace in release mode (and the library's doctests),
# then the Python package as PyPI would get it: an sdist, a manylinux abi3 wheel built from it
# (maturin with zig from PyPI's ziglang, checked by auditwheel), installed in a fresh virtual
# environment (target/test-venv) without a Rust toolchain on its PATH, and the pytest suite
# (with Ray) run there.
# Needs the Rust toolchain, python3 with venv, cmake, g++, pkg-config and Eigen 3 (checked
# first: the script stops at once with the apt-get line to run), and crates.io / PyPI.
# 80 minutes measured on 2 shared, loaded cores after the demo build (the Rust tests 44 of them;
# see the README); CI prints each phase's seconds.
# The data tests read ../shared/data (the public Sample-Queries and Sample-Scalable-CCD-Data
# sets; see the README). Without it they check nothing and say so below; with
# TOPOCCD_REQUIRE_DATA=1 (as .ci/run sets it) its absence is an error.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"
PYTHON_BIN="${PYTHON:-python3}"

# The prerequisites, checked first (within a second), never installed from here: a test script
# must not change the system, and a user is not root. What is missing is named with the line
# that installs it on Debian or Ubuntu.
absent=()
command -v cargo >/dev/null || { echo "error: cargo not found: install Rust first (https://rustup.rs)" >&2; exit 1; }
command -v "$PYTHON_BIN" >/dev/null || absent+=(python3)
# ensurepip is what python3-venv adds; `python3 -m venv` fails without it.
"$PYTHON_BIN" -c 'import ensurepip, venv' 2>/dev/null || absent+=(python3-venv)
command -v cmake >/dev/null || absent+=(cmake)
command -v g++ >/dev/null || absent+=(g++)
command -v pkg-config >/dev/null || absent+=(pkg-config)
if ! { command -v pkg-config >/dev/null && pkg-config --exists eigen3; }; then
    absent+=(libeigen3-dev)
fi
if [ "${#absent[@]}" -gt 0 ]; then
    echo "error: scripts/test.sh needs ${absent[*]}, which this machine lacks. Run:" >&2
    echo "    sudo apt-get install -y ${absent[*]}" >&2
    echo "(the C and C++ tests need cmake, g++, pkg-config and Eigen; the Python tests a venv)" >&2
    exit 1
fi

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

# The test venv first: a fresh one whose PATH has no Rust toolchain (pip can only install the
# wheel as built, below). It gets rerun-sdk now, for the CLI's recording test among the Rust
# tests (its `rerun rrd verify` and Python reader), and the wheel after them.
NO_RUST_PATH=$(printf '%s' "$PATH" | tr ':' '\n' | grep -v -e cargo -e rustup | paste -sd: -)
if env PATH="$NO_RUST_PATH" sh -c 'command -v cargo || command -v rustc' >/dev/null; then
    echo "error: cannot hide the Rust toolchain from the test venv's PATH" >&2
    exit 1
fi
VENV=target/test-venv
rm -rf "$VENV"
"$PYTHON_BIN" -m venv "$VENV"
no_rust() { env PATH="$PWD/$VENV/bin:$NO_RUST_PATH" CARGO_HOME=/nonexistent RUSTUP_HOME=/nonexistent "$@"; }
no_rust python -m pip install --quiet --upgrade pip
no_rust python -m pip install --quiet "rerun-sdk==0.36.3"

# Every cargo command below selects the whole workspace with the same features, so cargo
# resolves the dependencies' features one way and builds each crate once. The CLI has the
# feature `rerun` by default (its recording test reads back what it writes with the venv's
# rerun-sdk), and its manifest gives the crates it shares with the tests the workspace's
# features, so the README's demo build and this one are the same CLI. The C tests and the
# Python suite below use this binary (target/release/topoccd).
FEATURES=(--workspace)
echo "== [${SECONDS} s] Rust tests (release, the CLI with the feature rerun)"
TOPOCCD_RERUN_BIN="$PWD/$VENV/bin/rerun" TOPOCCD_RERUN_PYTHON="$PWD/$VENV/bin/python" \
    cargo test --release "${FEATURES[@]}" --lib --bins --tests --examples
# The library's doctests are off in its manifest (the published crate's plain `cargo test`
# cannot build the internals' ones); `--doc` runs them, with the internals that the
# workspace's dev-dependency turns on (and the other members' doctests).
echo "== [${SECONDS} s] the doctests (release)"
cargo test --release "${FEATURES[@]}" --doc

# The C API and the C++ wrapper: examples, tests under ASan, doc blocks. They compare with the
# CLI built above.
TOPOCCD_CLI="$PWD/target/release/topoccd" scripts/test-c.sh

echo "== [${SECONDS} s] Python package: sdist, manylinux abi3 wheel, fresh venv without Rust, pytest"
# The suite compares with the CLI (target/release/topoccd, built above with the feature
# `rerun`) and reads the shared data; with CI=true it fails rather than skips where either is
# absent.
# The wheel as scripts/wheel.sh builds it (its build tools live in a venv kept between runs).
BUILD_VENV=target/wheel-build-venv
DIST=target/dist
wheel=$(scripts/wheel.sh | tail -1)
sdist=$(ls "$DIST"/topoccd-*.tar.gz)
size=$(stat -c %s "$wheel")
echo "$(basename "$sdist"), $(basename "$wheel"): $((size / 1024)) kB"
case "$(basename "$wheel")" in
    *-abi3-*manylinux*) ;;
    *) echo "error: $wheel is not a manylinux abi3 wheel" >&2; exit 1 ;;
esac
if [ "$size" -ge $((10 * 1024 * 1024)) ]; then
    echo "error: $wheel is $size bytes, over 10 MB" >&2
    exit 1
fi
"$BUILD_VENV/bin/auditwheel" show "$wheel" | tr '\n' ' ' | grep -q 'consistent with the following platform tag: "manylinux_2_17_x86_64"' \
    || { "$BUILD_VENV/bin/auditwheel" show "$wheel"; echo "error: auditwheel does not find $wheel manylinux_2_17" >&2; exit 1; }

# Into the fresh venv (made above, no Rust on its PATH): pip can only install the wheel as built.
# ipctk 1.6.1 (and scipy, the extra `ipc`) for topoccd.ipc's conformance and solver tests.
no_rust python -m pip install --quiet --only-binary topoccd "$wheel[ray,test,rerun,ipc]" tqdm "ipctk==1.6.1" scipy
no_rust python -c "import topoccd; print('topoccd', topoccd.__version__, 'imported from', topoccd.__file__)"
set +e
no_rust python -m pytest topoccd-py/tests -q -rs
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
