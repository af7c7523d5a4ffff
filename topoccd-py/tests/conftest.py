"""Shared fixtures: the repository's paths, the shared real steps, the CLI and generated
sequences.

- The shared data is looked up at ``$TOPOCCD_SHARED_DATA``, else ``../shared/data`` from the
  repository root. Where it is absent the tests that need it are skipped with a loud reason,
  except under CI (``CI=true``), where they fail: CI must never pass without the real data.
- The CLI is ``$TOPOCCD_CLI``, else ``target/release/topoccd`` (``cargo build --release -p
  topoccd-cli``); the same rule applies.
"""

import os
import signal
import shutil
import subprocess
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parent
REPO = TESTS.parent.parent
IN_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")


def _missing(what: str) -> None:
    """Fails under CI, skips loudly elsewhere."""
    if IN_CI:
        pytest.fail(f"{what} (CI=true: this must not pass silently)", pytrace=False)
    pytest.skip(f"SKIPPED, NOT TESTED: {what}")


def shared_data() -> Path:
    return Path(os.environ.get("TOPOCCD_SHARED_DATA", REPO.parent / "shared" / "data"))


@pytest.fixture(scope="session")
def scenes_dir() -> Path:
    path = shared_data() / "scenes"
    if not path.is_dir():
        _missing(f"the shared scenes are absent: {path} (set TOPOCCD_SHARED_DATA)")
    return path


@pytest.fixture(scope="session")
def cli() -> str:
    path = Path(os.environ.get("TOPOCCD_CLI", REPO / "target" / "release" / "topoccd"))
    if not path.is_file():
        _missing(
            f"the topoccd CLI is absent: {path} (cargo build --release -p topoccd-cli, "
            "or set TOPOCCD_CLI)"
        )
    return str(path)


def run_cli(cli: str, *args: str) -> str:
    done = subprocess.run([cli, *args], capture_output=True, text=True)
    if done.returncode != 0:
        raise AssertionError(f"topoccd {' '.join(args)} failed: {done.stderr}")
    return done.stdout


@pytest.fixture(scope="session")
def sequence(cli, tmp_path_factory) -> Path:
    """A small generated sequence with topology changes (nidus-cut, 4 frames)."""
    folder = tmp_path_factory.mktemp("seq") / "nidus-cut"
    run_cli(cli, "gen", "nidus-cut", str(folder), "--scale", "0.1", "--frames", "4")
    return folder


@pytest.fixture(scope="session")
def cli_run(cli, sequence, tmp_path_factory):
    """``topoccd run SEQ --pairs-dir DIR --json`` on the sequence: (pairs dir, JSON lines)."""
    import json

    pairs = tmp_path_factory.mktemp("cli-pairs")
    out = run_cli(cli, "--threads", "1", "run", str(sequence), "--pairs-dir", str(pairs), "--json")
    lines = [json.loads(line) for line in out.splitlines() if line.strip()]
    return pairs, lines


@pytest.fixture
def copy_sequence(sequence, tmp_path):
    """A writable copy of the generated sequence."""

    def make() -> Path:
        target = tmp_path / "copy"
        shutil.copytree(sequence, target)
        return target

    return make


def sigint_default():
    """``preexec_fn`` of a child that a test interrupts: SIGINT back to its default action.
    A shell runs a background job with SIGINT ignored, and Python keeps an ignored SIGINT
    ignored: the child would never see the test's Ctrl-C."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
