#!/usr/bin/env bash
# The user guide: builds docs/guide with mdBook (into target/guide) and checks every relative
# link and anchor of the README files and the guide (scripts/check_links.py).
# mdBook has no prebuilt package in the registries this project reaches (crates.io, PyPI,
# Debian, npm), so it is built from crates.io, without its server and file watcher (about two
# minutes on two cores), once per machine: into cargo's own bin folder, like any `cargo
# install`, and reused while its version stays the same.
# The code blocks of the guide are run by the tests (see docs/guide/src/testing.md).
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"
MDBOOK_VERSION=0.5.4
ROOT="${CARGO_HOME:-$HOME/.cargo}"
mdbook="$ROOT/bin/mdbook"
if ! "$mdbook" --version 2>/dev/null | grep -qx "mdbook v$MDBOOK_VERSION"; then
    echo "== installing mdbook $MDBOOK_VERSION into $ROOT/bin (once per machine)"
    cargo install mdbook --version "$MDBOOK_VERSION" --locked --no-default-features \
        --features search --root "$ROOT" --quiet
fi
echo "== mdbook build docs/guide"
rm -rf target/guide
"$mdbook" build docs/guide --dest-dir "$PWD/target/guide"
test -f target/guide/index.html
echo "== links of the README files and the guide"
python3 scripts/check_links.py
