"""topoccd.rerun: recordings for the Rerun viewer, read back with Rerun's own reader
(``rerun rrd verify`` and rerun-sdk's ``RrdReader``, through topoccd-cli/tests/rrd_dump.py),
checked against the reports of the same steps; and the same layout as ``topoccd run --rerun``.

Needs rerun-sdk (``pip install topoccd[rerun]``): skipped without it, except under CI.
"""

import importlib.util
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import topoccd
from conftest import REPO, _missing

DUMP = REPO / "topoccd-cli" / "tests" / "rrd_dump.py"


@pytest.fixture(scope="module")
def rr():
    if importlib.util.find_spec("rerun") is None:
        _missing("rerun-sdk is not installed (pip install 'topoccd[rerun]')")
    import rerun

    return rerun


@pytest.fixture(scope="module")
def tools(rr, tmp_path_factory):
    """The ``rerun`` command, and an environment whose config home is a temporary folder
    where Rerun's analytics are disabled first."""
    exe = shutil.which("rerun") or os.path.join(os.path.dirname(sys.executable), "rerun")
    if not os.path.isfile(exe):
        _missing("rerun-sdk's `rerun` command is not found")
    home = tmp_path_factory.mktemp("rerun-home")
    env = dict(os.environ, HOME=str(home), XDG_CONFIG_HOME=str(home / "config"),
               XDG_DATA_HOME=str(home / "data"))
    subprocess.run([exe, "analytics", "disable"], env=env, check=True, capture_output=True)
    return exe, env


def read(tools, rrd):
    """``rerun rrd verify``, then the entities step by step (rrd_dump.py's JSON)."""
    exe, env = tools
    verify = subprocess.run([exe, "rrd", "verify", str(rrd)], env=env, capture_output=True,
                            text=True)
    assert verify.returncode == 0, verify.stderr
    out = subprocess.run([sys.executable, str(DUMP), str(rrd)], env=env, capture_output=True,
                         text=True)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def count(rec, path, k):
    return rec["entities"].get(path, {}).get(str(k), {}).get("count", 0)


def steps_of(rec, path):
    return sorted(int(k) for k in rec["entities"][path])


ENTITIES = [
    "/topoccd/mesh",
    "/topoccd/contacts/faces",
    "/topoccd/contacts/vertices",
    "/topoccd/contacts/edges",
    "/topoccd/contacts/points",
    "/topoccd/contacts/normals",
    "/topoccd/earliest",
    "/topoccd/cracks/edges",
    "/topoccd/cracks/vertices",
    "/topoccd/stats/seconds/total",
    "/topoccd/stats/candidates/vf",
    "/topoccd/stats/candidates/ee",
    "/topoccd/stats/bv_tests",
    "/topoccd/stats/contacts",
    "/topoccd/stats/triangles",
    "/topoccd/notes",
]


def reports(sequence):
    """Each step's arrays and report, as ``python -m topoccd.rerun`` makes them."""
    ccd = topoccd.Ccd()
    out = []
    for x0, x1, tris, parents in topoccd.read_sequence(sequence):
        out.append((x0, x1, tris, parents, ccd.query(x0, x1, tris, parents=parents, geometry=True)))
    return out


def check_against(rec, steps):
    for e in ENTITIES:
        assert e in rec["entities"], e
        assert steps_of(rec, e) == list(range(len(steps))), e
    for k, (x0, x1, tris, parents, report) in enumerate(steps):
        contacts = len(report.vf) + len(report.ee)
        assert count(rec, "/topoccd/mesh", k) == len(tris)
        assert count(rec, "/topoccd/contacts/points", k) == contacts
        assert count(rec, "/topoccd/contacts/normals", k) == contacts
        assert count(rec, "/topoccd/contacts/faces", k) == len(report.vf)
        assert count(rec, "/topoccd/contacts/edges", k) == 2 * len(report.ee)
        assert rec["entities"]["/topoccd/stats/contacts"][str(k)]["values"] == [float(contacts)]
        assert count(rec, "/topoccd/earliest", k) == (1 if contacts else 0)
        n_new = 0 if parents is None else len(parents)
        assert count(rec, "/topoccd/cracks/vertices", k) == n_new
        assert (count(rec, "/topoccd/cracks/edges", k) > 0) == (n_new > 0)


def test_importing_topoccd_does_not_import_rerun():
    code = "import sys, topoccd; assert 'rerun' not in sys.modules, 'rerun imported'"
    subprocess.run([sys.executable, "-c", code], check=True)


def test_the_module_records_a_sequence(tools, sequence, tmp_path):
    rrd = tmp_path / "seq.rrd"
    done = subprocess.run([sys.executable, "-m", "topoccd.rerun", str(sequence), "-o", str(rrd)],
                          capture_output=True, text=True, env=tools[1])
    assert done.returncode == 0, done.stderr
    steps = reports(sequence)
    assert any(s[3] is not None and len(s[3]) for s in steps), "the sequence has no cut"
    assert sum(len(s[4].vf) + len(s[4].ee) for s in steps) > 0
    rec = read(tools, rrd)
    assert rec["application_id"] == "topoccd"
    check_against(rec, steps)


def test_log_step_in_a_users_loop(rr, tools, sequence, tmp_path):
    import topoccd.rerun as tr

    rrd = tmp_path / "loop.rrd"
    rec = rr.RecordingStream("my-simulator")
    rec.save(str(rrd))
    steps = reports(sequence)
    for k, (x0, x1, tris, parents, report) in enumerate(steps):
        assert tr.log_step(k, x0, x1, tris, report, parents=parents, recording=rec) == []
    rec.flush()
    rec.disconnect()
    got = read(tools, rrd)
    assert got["application_id"] == "my-simulator"
    check_against(got, steps)


def test_log_report_without_geometry_and_the_cap(rr, tools, sequence, tmp_path):
    import topoccd.rerun as tr

    rrd = tmp_path / "cap.rrd"
    rec = rr.RecordingStream("capped")
    rec.save(str(rrd))
    ccd = topoccd.Ccd()
    seq = topoccd.read_sequence(sequence)
    x0, x1, tris, parents = seq[0]
    report = ccd.query(x0, x1, tris, parents=parents)
    assert report.vf_point is None
    contacts = len(report.vf) + len(report.ee)
    assert contacts > 2
    rec.set_time("step", sequence=0)
    notes = tr.log_report(x0, x1, tris, report, parents=parents, recording=rec, max_primitives=2)
    assert len(notes) == 1 and f"2 of the step's {contacts} contacts" in notes[0]
    notes = tr.log_step(1, x0, x1, tris, report, parents=parents, recording=rec,
                        max_primitives=len(tris) + 1)
    assert any("cap of" in n for n in notes)
    rec.flush()
    rec.disconnect()
    got = read(tools, rrd)
    assert count(got, "/topoccd/contacts/points", 0) == 2
    assert count(got, "/topoccd/mesh", 1) == len(tris)
    assert count(got, "/topoccd/contacts/points", 1) == 1
    # The earliest kept, wherever the cap falls: the report's earliest time.
    assert got["entities"]["/topoccd/stats/contacts"]["1"]["values"] == [float(contacts)]
    warnings = [v for v in got["entities"]["/topoccd/notes"]["1"]["values"] if "cap of" in v]
    assert warnings and f"cap of {len(tris) + 1} primitives" in warnings[0]


def test_the_command_writes_the_same_layout(cli, tools, sequence, tmp_path):
    """``topoccd run --rerun`` (a CLI built with the feature ``rerun``) and the module agree."""
    rrd_cli, rrd_py = tmp_path / "cli.rrd", tmp_path / "py.rrd"
    done = subprocess.run([cli, "run", str(sequence), "--rerun", str(rrd_cli)],
                          capture_output=True, text=True)
    if done.returncode != 0 and "--features rerun" in done.stderr:
        _missing("the topoccd CLI was built without the feature `rerun`")
    assert done.returncode == 0, done.stderr
    subprocess.run([sys.executable, "-m", "topoccd.rerun", str(sequence), "-o", str(rrd_py)],
                   check=True, capture_output=True, env=tools[1])
    a, b = read(tools, rrd_cli), read(tools, rrd_py)
    assert sorted(a["entities"]) == sorted(b["entities"])
    for path in ENTITIES:
        if path.startswith("/topoccd/stats/seconds") or path == "/topoccd/notes":
            continue
        counts_a = {k: v["count"] for k, v in a["entities"][path].items()}
        counts_b = {k: v["count"] for k, v in b["entities"][path].items()}
        assert counts_a == counts_b, path


def test_bad_output_and_no_viewer_are_clear(tools, sequence, tmp_path):
    env = dict(tools[1])
    for out, message in [("/no/such/folder/x.rrd", "cannot write"), ("x.png", "ending in .rrd")]:
        done = subprocess.run([sys.executable, "-m", "topoccd.rerun", str(sequence), "-o", out],
                              capture_output=True, text=True, env=env)
        assert done.returncode == 2 and message in done.stderr, done.stderr
    env["PATH"] = str(tmp_path)
    done = subprocess.run([sys.executable, "-m", "topoccd.rerun", str(sequence)],
                          capture_output=True, text=True, env=env)
    assert done.returncode == 2 and "pip install rerun-sdk==0.36.3" in done.stderr, done.stderr
