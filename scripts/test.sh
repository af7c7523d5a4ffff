#!/usr/bin/env bash
# The tests, Python included: the Rust workspace in release mode (and the library's doctests),
# then the Python package as PyPI would get it: an sdist, a manylinux abi3 wheel built from it
# (maturin with zig from PyPI's ziglang, checked by auditwheel), installed in a fresh virtual
# environment (target/test-venv) without a Rust toolchain on its PATH, and the pytest suite
# (with Ray) run there.
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
# The library's doctests are off in its manifest (the published crate's plain `cargo test`
# cannot build the internals' ones); here the dev-dependency turns the internals on.
echo "== the library's doctests (release)"
cargo test --release -p topoccd --doc

scripts/test-c.sh  # the C API and the C++ wrapper: examples, tests under ASan, doc blocks

echo "== Python package: sdist, manylinux abi3 wheel, fresh venv without Rust, pytest"
# The suite compares with the CLI (target/release/topoccd) and reads the shared data; with
# CI=true it fails rather than skips where either is absent.
# With the feature `rerun` (--rerun recordings), which test_rerun.py and the CLI's own
# recording test below check.
cargo build --release --quiet -p topoccd-cli --features rerun
PYTHON_BIN="${PYTHON:-python3}"
# The build tools live in a venv of their own, kept between runs.
BUILD_VENV=target/wheel-build-venv
[ -x "$BUILD_VENV/bin/python" ] || "$PYTHON_BIN" -m venv "$BUILD_VENV"
"$BUILD_VENV/bin/python" -m pip install --quiet --upgrade pip
"$BUILD_VENV/bin/python" -m pip install --quiet "maturin>=1.9,<2" ziglang auditwheel
DIST=target/dist
rm -rf "$DIST"
"$BUILD_VENV/bin/maturin" sdist --manifest-path topoccd-py/Cargo.toml --out "$DIST"
sdist=$(ls "$DIST"/topoccd-*.tar.gz)
# The wheel is built from the sdist (so the sdist builds): zig links against glibc 2.17.
PATH="$PWD/$BUILD_VENV/bin:$PATH" MATURIN_PEP517_ARGS="--zig --compatibility manylinux2014" \
    CARGO_TARGET_DIR="$PWD/target/wheel" "$BUILD_VENV/bin/python" -m pip wheel --quiet --no-build-isolation --no-deps -w "$DIST" "$sdist"
wheel=$(ls "$DIST"/topoccd-*.whl)
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

# A fresh venv whose PATH has no Rust toolchain: pip can only install the wheel as built.
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
no_rust python -m pip install --quiet --only-binary topoccd "$wheel[ray,test,rerun]" tqdm
no_rust python -c "import topoccd; print('topoccd', topoccd.__version__, 'imported from', topoccd.__file__)"
set +e
no_rust python -m pytest topoccd-py/tests -q -rs
status=$?
set -e
if [ "$status" -eq 5 ]; then
    echo "error: pytest collected no tests" >&2
    exit 1
fi
# The CLI's recordings (feature `rerun`), read back with the venv's rerun-sdk (its `rerun`
# command and Python first on the PATH).
echo "== topoccd --rerun recordings (feature rerun)"
if ! PATH="$PWD/$VENV/bin:$PATH" cargo test --release --quiet -p topoccd-cli --features rerun --test rerun; then
    status=1
fi
if [ -n "$missing" ]; then
    echo "$missing" >&2
fi
exit "$status"
