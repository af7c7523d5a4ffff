"""topoccd.batch: the steps of a sequence over a process pool and over Ray give exactly the
pairs of `topoccd run`; a failed step is reported with its frames and loses no other step."""

import json
import shutil

import pytest
import topoccd
from conftest import sigint_default
from topoccd.batch import process_step, process_steps, run_sequence


def assert_same_pairs(out_dir, cli_pairs_dir, steps):
    for k in range(steps):
        name = f"{k:04d}.csv"
        assert (out_dir / name).read_text() == (cli_pairs_dir / name).read_text(), name


def assert_same_lines(result, cli_lines):
    for line, cli_line in zip(result.lines, cli_lines):
        assert "error" not in line, line
        for key in ("step", "vertices", "triangles", "vf", "ee", "earliest_toi", "method", "mode", "unresolved"):
            if key in cli_line:
                assert line[key] == cli_line[key], (key, line, cli_line)


def test_process_step_is_a_plain_function(sequence, cli_run, tmp_path):
    pairs_dir, cli_lines = cli_run
    line = process_step(str(sequence), 1, str(tmp_path), {"threads": 1})
    assert json.loads(json.dumps(line)) == line  # plain JSON data
    assert (tmp_path / "0001.csv").read_text() == (pairs_dir / "0001.csv").read_text()
    for key in ("step", "vertices", "triangles", "vf", "ee", "earliest_toi"):
        assert line[key] == cli_lines[1][key]
    assert set(line["seconds"]) >= {"build", "traverse", "narrow", "total"}


def test_process_engine_matches_topoccd_run(sequence, cli_run, tmp_path):
    pairs_dir, cli_lines = cli_run
    out = tmp_path / "out"
    result = run_sequence(sequence, out, engine="process", workers=2, progress=False)
    assert [line["step"] for line in result.lines] == [0, 1, 2]
    assert not result.failed
    assert_same_pairs(out, pairs_dir, 3)
    assert_same_lines(result, cli_lines)
    jsonl = [json.loads(x) for x in (out / "steps.jsonl").read_text().splitlines()]
    assert [x["step"] for x in jsonl[:-1]] == [0, 1, 2]
    cli_summary = cli_lines[-1]["summary"]
    for key in ("steps", "steps_with_contacts", "vf", "ee", "earliest_toi"):
        assert jsonl[-1]["summary"][key] == cli_summary[key], key


def test_a_failed_step_is_reported_and_the_others_kept(copy_sequence, cli_run, tmp_path, capsys):
    pairs_dir, _ = cli_run
    folder = copy_sequence()
    broken = folder / "0002.ply"
    broken.write_bytes(broken.read_bytes()[:300])  # truncated: steps 1 and 2 need it
    out = tmp_path / "out"
    result = run_sequence(folder, out, engine="process", workers=2, progress=True)
    assert [line["step"] for line in result.lines] == [0, 1, 2]
    assert [line["step"] for line in result.failed] == [1, 2]
    for line in result.failed:
        assert "0002.ply" in line["error"] and str(broken) in line["frames"]
    assert_same_pairs(out, pairs_dir, 1)
    assert result.summary["failed"] == 2
    err = capsys.readouterr().err
    assert "step 1 failed" in err and "0002.ply" in err
    jsonl = (out / "steps.jsonl").read_text().splitlines()
    assert len(jsonl) == 4 and "error" in json.loads(jsonl[2])


def test_invalid_options_fail_before_any_task(sequence, tmp_path):
    with pytest.raises(topoccd.OptionsError):
        run_sequence(sequence, tmp_path / "o", engine="process", tolerance=2.0)
    with pytest.raises(ValueError, match="engine"):
        run_sequence(sequence, tmp_path / "o", engine="spark")


def test_ray_matches_topoccd_run(sequence, cli_run, tmp_path):
    ray = pytest.importorskip(
        "ray", reason="SKIPPED, NOT TESTED: Ray is not installed (pip install 'topoccd[ray]')"
    )
    pairs_dir, cli_lines = cli_run
    out = tmp_path / "ray-out"
    started_here = not ray.is_initialized()
    try:
        result = run_sequence(sequence, out, engine="ray", workers=2, progress=False)
        assert not result.failed, result.failed
        assert [line["step"] for line in result.lines] == [0, 1, 2]
        assert_same_pairs(out, pairs_dir, 3)
        assert_same_lines(result, cli_lines)
        assert (out / "steps.jsonl").exists()
        # An initialised Ray is used as it is (no second ray.init).
        again = run_sequence(sequence, tmp_path / "again", engine="ray", progress=False)
        assert_same_pairs(tmp_path / "again", pairs_dir, 3)
        assert again.summary["vf"] == result.summary["vf"]
    finally:
        if started_here and ray.is_initialized():
            ray.shutdown()
        shutil.rmtree(out, ignore_errors=True)


@pytest.mark.parametrize("per_task", [1, 2, 3])
def test_runs_of_steps_match_topoccd_run(sequence, cli_run, tmp_path, per_task):
    pairs_dir, cli_lines = cli_run
    out = tmp_path / f"runs-{per_task}"
    result = run_sequence(
        sequence, out, engine="process", workers=2, steps_per_task=per_task, progress=False
    )
    assert not result.failed and result.summary["steps_per_task"] == per_task
    assert [line["step"] for line in result.lines] == [0, 1, 2]
    assert_same_pairs(out, pairs_dir, 3)
    assert_same_lines(result, cli_lines)


@pytest.fixture(scope="module")
def uncut_sequence(cli, tmp_path_factory):
    """A generated sequence whose triangles stay the same (nidus, 4 frames)."""
    from conftest import run_cli

    folder = tmp_path_factory.mktemp("uncut") / "nidus"
    run_cli(cli, "gen", "nidus", str(folder), "--scale", "0.1", "--frames", "4")
    return folder


def test_a_task_keeps_its_ccd_across_its_steps(uncut_sequence, cli, tmp_path):
    """In a run of steps, the cluster method offers a step the last step's leaves
    (reused_leaves > 0 on step 1, and on every step as many as `topoccd run` reuses); steps
    run alone start afresh. Same pairs either way."""
    import subprocess

    options = {"method": "cluster", "threads": 1}
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    together = process_steps(str(uncut_sequence), 0, 3, str(tmp_path / "a"), options)
    assert not [line for line in together if "error" in line], together
    alone = [process_step(str(uncut_sequence), k, str(tmp_path / "b"), options) for k in range(3)]
    assert [line["clusters"]["reused_leaves"] for line in alone] == [0, 0, 0]
    assert together[0]["clusters"]["reused_leaves"] == 0
    assert together[1]["clusters"]["reused_leaves"] > 0, together
    for k in range(3):
        name = f"{k:04d}.csv"
        assert (tmp_path / "a" / name).read_text() == (tmp_path / "b" / name).read_text()
    cli_out = subprocess.run(
        [cli, "--threads", "1", "run", str(uncut_sequence), "--method", "cluster", "--json"],
        capture_output=True, text=True, check=True,
    ).stdout.splitlines()
    cli_lines = [json.loads(line) for line in cli_out[:-1]]
    for line, cli_line in zip(together, cli_lines):
        assert line["clusters"]["reused_leaves"] == cli_line["stats"]["cluster"]["reused_leaves"]
        assert (line["vf"], line["ee"]) == (cli_line["vf"], cli_line["ee"])


def test_a_failed_step_in_a_run_loses_no_other_step(copy_sequence, cli_run, tmp_path):
    pairs_dir, _ = cli_run
    folder = copy_sequence()
    (folder / "0001.ply").write_bytes((folder / "0001.ply").read_bytes()[:300])
    lines = process_steps(str(folder), 0, 3, str(tmp_path), {"threads": 1})
    assert [line["step"] for line in lines] == [0, 1, 2]
    assert ["error" in line for line in lines] == [True, True, False]
    assert (tmp_path / "0002.csv").read_text() == (pairs_dir / "0002.csv").read_text()
    with pytest.raises(ValueError, match="steps_per_task"):
        run_sequence(folder, tmp_path / "o", engine="process", steps_per_task=0)


_INTERRUPTED = """
import math, os, sys
from topoccd.batch import run_sequence

def collapsed_obj(n):
    rows = []
    for j in range(n + 1):
        for i in range(n + 1):
            u, v = i / n, j / n
            p = (2.5 * u - 1.25 + 0.3 * math.sin(7 * v), 2.5 * v - 1.25,
                 -1 + 0.9 * math.cos(5 * u) * math.sin(3 * v))
            rows.append("v %d %d %d" % tuple(int(c) for c in p))
    idx = lambda i, j: j * (n + 1) + i + 1
    for j in range(n):
        for i in range(n):
            rows.append("f %d %d %d" % (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)))
            rows.append("f %d %d %d" % (idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)))
    return "\\n".join(rows) + "\\n"

if __name__ == "__main__":
    folder, out = sys.argv[1], sys.argv[2]
    os.makedirs(folder)
    text = collapsed_obj(120)
    for k in range(40):
        with open(os.path.join(folder, "%04d.obj" % k), "w") as f:
            f.write(text)
    print("ready", flush=True)
    run_sequence(folder, out, engine="process", workers=1, progress=False)
    print("finished", flush=True)
"""


def test_ctrl_c_ends_run_sequence(tmp_path):
    """Ctrl-C (SIGINT to the process group, as a terminal sends it) ends ``run_sequence``
    promptly: 39 collapsed steps of about a second each are not waited for."""
    import os
    import signal
    import subprocess
    import sys
    import time

    script = tmp_path / "interrupted.py"
    script.write_text(_INTERRUPTED)
    child = subprocess.Popen(
        [sys.executable, str(script), str(tmp_path / "seq"), str(tmp_path / "out")],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        preexec_fn=sigint_default,
    )
    try:
        assert child.stdout.readline().strip() == "ready"
        time.sleep(4.0)  # the worker starts (spawn) and is inside a step
        os.killpg(child.pid, signal.SIGINT)
        sent = time.perf_counter()
        out, err = child.communicate(timeout=30)
        waited = time.perf_counter() - sent
    finally:
        if child.poll() is None:
            os.killpg(child.pid, signal.SIGKILL)
    assert "finished" not in out, "the run was not interrupted"
    assert child.returncode != 0
    assert "KeyboardInterrupt" in err, err[-2000:]
    assert waited < 2.0, waited  # 0.14 s here
