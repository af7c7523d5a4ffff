"""Every code block of the README, the user guide (docs/guide/src) and the Python package's
page runs: the Python and shell blocks here, page by page, in document order, in a fresh
folder (the rule is in the guide's page testing.md); the Rust blocks are doctests of the
workspace's test crate, which must include every page that has one."""

import os
import re
import subprocess
from pathlib import Path

import pytest

from conftest import REPO, shared_data

RUN = {"python", "sh"}
#: Blocks shown and not run (console: install, build, long runs), data (text, toml), Rust
#: (doctests of topoccd-tests), and the C and C++ interface's blocks and CMake snippets (its
#: own script, scripts/test-c.sh, compiles and runs those and builds CMake consumers).
NOT_RUN_HERE = {"console", "text", "toml", "rust", "c", "cpp", "cmake"}

PAGES = [
    REPO / "README.md",
    REPO / "topoccd-py" / "README.md",
    *sorted((REPO / "docs" / "guide" / "src").glob("*.md")),
]

FENCE = re.compile(r"^(`{3,})(\S*)\s*$")


def blocks(path: Path):
    """The fenced code blocks of a markdown file: (language, code, first line)."""
    out, lines, i = [], path.read_text().splitlines(), 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        fence, info, start = m.group(1), m.group(2), i + 1
        j = start
        while j < len(lines) and lines[j].strip() != fence:
            j += 1
        assert j < len(lines), f"{path}:{start}: unclosed code block"
        lang = info.split(",")[0]
        out.append((lang, "\n".join(lines[start:j]) + "\n", start))
        i = j + 1
    return out


def page_id(path: Path) -> str:
    return str(path.relative_to(REPO))


def test_every_block_has_a_known_language_and_rust_pages_are_doctests():
    lib = (REPO / "topoccd-tests" / "src" / "lib.rs").read_text()
    for page in PAGES:
        langs = [(lang, line) for lang, _, line in blocks(page)]
        for lang, line in langs:
            assert lang in RUN | NOT_RUN_HERE, f"{page_id(page)}:{line}: block language {lang!r}"
        if any(lang == "rust" for lang, _ in langs):
            rel = os.path.relpath(page, REPO / "topoccd-tests" / "src")
            assert f'"{rel}"' in lib, f"{page_id(page)} has Rust blocks; include it in {lib}"


#: What the CLI says when `--rerun` is asked of a build without the feature.
NO_RERUN = "--rerun needs a topoccd built with the cargo feature `rerun`"

RUNNABLE = [p for p in PAGES if any(lang in RUN for lang, _, _ in blocks(p))]


@pytest.mark.parametrize("page", RUNNABLE, ids=page_id)
def test_python_and_shell_blocks_run(page, cli, tmp_path, monkeypatch):
    data = shared_data()
    env = dict(os.environ)
    env["PATH"] = f"{Path(cli).parent}{os.pathsep}{env['PATH']}"
    env["TOPOCCD_DATA"] = str(data)
    monkeypatch.setenv("PATH", env["PATH"])
    monkeypatch.setenv("TOPOCCD_DATA", str(data))
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__docs__"}
    ran = 0
    for lang, code, line in blocks(page):
        where = f"{page_id(page)}:{line}"
        if lang == "sh":
            done = subprocess.run(
                ["bash", "-euo", "pipefail", "-c", code],
                cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600,
            )
            if done.returncode != 0 and NO_RERUN in done.stderr:
                # A build without the feature (e.g. `cargo build -p topoccd-cli
                # --no-default-features`): the page's recording cannot run with it.
                pytest.skip(
                    f"{where}: {cli} was built without the cargo feature `rerun`; "
                    "`cargo build --release -p topoccd-cli` (the feature is on by default, "
                    "Rust >= 1.95) builds the CLI that runs this block"
                )
            assert done.returncode == 0, (
                f"{where}: the shell block failed ({done.returncode}):\n{code}\n"
                f"stdout:\n{done.stdout[-2000:]}\nstderr:\n{done.stderr[-2000:]}"
            )
            ran += 1
        elif lang == "python":
            exec(compile(code, where, "exec"), namespace)  # noqa: S102 - the docs' own code
            ran += 1
    assert ran > 0
