#!/usr/bin/env bash
# Builds the Python package's wheel on its own, the way scripts/test.sh tests it: an sdist,
# then a manylinux2014 abi3 wheel built from it (maturin with zig from PyPI's ziglang), both
# in target/dist. The last line of output is the wheel's path; install it with
#
#     pip install "$(scripts/wheel.sh | tail -1)"
#
# into any Python >= 3.9 on Linux x86_64 (no Rust needed there). Needs the Rust toolchain,
# python3 with venv, and PyPI (for maturin, ziglang); the build tools live in
# target/wheel-build-venv, kept between runs. The first run took 6 minutes on a shared 2-core
# machine, downloads included.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"
PYTHON_BIN="${PYTHON:-python3}"
BUILD_VENV=target/wheel-build-venv
[ -x "$BUILD_VENV/bin/python" ] || "$PYTHON_BIN" -m venv "$BUILD_VENV" >&2
"$BUILD_VENV/bin/python" -m pip install --quiet --upgrade pip >&2
"$BUILD_VENV/bin/python" -m pip install --quiet "maturin>=1.9,<2" ziglang auditwheel >&2
DIST=target/dist
rm -rf "$DIST"
"$BUILD_VENV/bin/maturin" sdist --manifest-path topoccd-py/Cargo.toml --out "$DIST" >&2
sdist=$(ls "$DIST"/topoccd-*.tar.gz)
# The sdist's files carry a fixed old date (reproducible archives), so cargo would take the
# previous run's build of this project for up to date: drop it (the dependencies stay built).
cargo clean --quiet --manifest-path topoccd-py/Cargo.toml --target-dir "$PWD/target/wheel" \
    --target x86_64-unknown-linux-gnu --release -p topoccd -p topoccd-py >&2
# The wheel is built from the sdist (so the sdist builds): zig links against glibc 2.17.
PATH="$PWD/$BUILD_VENV/bin:$PATH" MATURIN_PEP517_ARGS="--zig --compatibility manylinux2014" \
    CARGO_TARGET_DIR="$PWD/target/wheel" "$BUILD_VENV/bin/python" -m pip wheel --quiet \
    --no-build-isolation --no-deps -w "$DIST" "$sdist" >&2
wheel=$(ls "$DIST"/topoccd-*.whl)
echo "$PWD/$wheel"
