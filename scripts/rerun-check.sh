#!/usr/bin/env bash
# The `--rerun` smoke check of the built CLI (target/release/topoccd, as the README's commands
# leave it): a tiny generated sequence recorded to a temporary .rrd, which must exist and be
# non-empty; then `rerun rrd verify` reads it back when rerun-sdk's `rerun` is at hand
# ($TOPOCCD_RERUN_BIN, else target/test-venv/bin/rerun, which scripts/test.sh makes, else the
# PATH; without one it says that it only checked the file). A CLI built without the feature
# `rerun` fails here: that is what this check is for (.ci/run runs it around scripts/test.sh).
# Builds nothing. About a second.
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${TOPOCCD_CLI:-$PWD/target/release/topoccd}"
if [ ! -x "$bin" ]; then
    echo "error: $bin is missing: run \`cargo run --release -p topoccd-cli -- demo\` first" >&2
    exit 1
fi
tmp=$(mktemp -d "${TMPDIR:-/tmp}/topoccd-rerun-check.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

"$bin" gen nidus-cut "$tmp/seq" --scale 0.05 --frames 3 >/dev/null
if ! "$bin" run "$tmp/seq" --rerun "$tmp/seq.rrd" >/dev/null 2>"$tmp/run.err"; then
    cat "$tmp/run.err" >&2
    echo "error: \`topoccd run SEQ --rerun OUT.rrd\` failed (is $bin built with the feature rerun?)" >&2
    exit 1
fi
if [ ! -s "$tmp/seq.rrd" ]; then
    echo "error: $tmp/seq.rrd is missing or empty after \`topoccd run --rerun\`" >&2
    exit 1
fi
size=$(stat -c %s "$tmp/seq.rrd")

rerun="${TOPOCCD_RERUN_BIN:-}"
if [ -z "$rerun" ] && [ -x target/test-venv/bin/rerun ]; then
    rerun="$PWD/target/test-venv/bin/rerun"
fi
if [ -z "$rerun" ]; then
    rerun=$(command -v rerun || true)
fi
if [ -z "$rerun" ]; then
    echo "rerun check: $size-byte recording written (no rerun-sdk here: not read back)"
    exit 0
fi
# Rerun's usage analytics off, in a config home of our own.
rr() { env HOME="$tmp/home" XDG_CONFIG_HOME="$tmp/home/config" XDG_DATA_HOME="$tmp/home/data" "$rerun" "$@"; }
mkdir -p "$tmp/home"
rr analytics disable >/dev/null 2>&1 || true
if ! rr rrd verify "$tmp/seq.rrd" >"$tmp/verify.out" 2>&1; then
    cat "$tmp/verify.out" >&2
    echo "error: rerun rrd verify rejects the recording" >&2
    exit 1
fi
echo "rerun check: $size-byte recording written and verified by $rerun"
