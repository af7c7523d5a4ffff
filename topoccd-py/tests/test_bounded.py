"""Every entry point bounded (issue 43): each public Python call that can run long, run with
its defaults on the integer-cast cloth-funnel step (every vertex on one of ten points) and on
coordinates near f64's end, in a subprocess under a 3 GB address-space limit, returns or raises
a documented error: none aborts, none is killed, none runs away. Time and memory figures are
measured by ``topoccd-benches/scripts/hostile.py`` (the guide's reliability page), not asserted
here but for a generous bound on each subprocess.
"""

import json
import subprocess
import sys
import textwrap

import pytest
import topoccd

#: The address-space limit of each subprocess (the issue's failures: an out-of-memory kill at
#: 23.5 GB, and an abort on a failed allocation under 3 GB).
LIMIT = 3 * 1024**3

CHILD = textwrap.dedent(
    """
    import json, resource, sys, warnings
    resource.setrlimit(resource.RLIMIT_AS, ({limit}, {limit}))
    import numpy as np, topoccd
    warnings.simplefilter("ignore", topoccd.InputWarning)
    frames, case = sys.argv[1], sys.argv[2]
    if case.startswith("huge"):
        x0 = np.array([[1e308, 1e308, 0], [1.000000005e308, 1e308, 0], [1e308, 1.000000005e308, 0],
                       [1.000000001e308, 1.000000001e308, 1e299],
                       [1.000000002e308, 1.000000001e308, 1e299],
                       [1.000000001e308, 1.000000002e308, 1e299]])
        x1 = x0.copy()
        x1[3:, 2] = -1e299
        tris = np.array([[0, 1, 2], [3, 4, 5]])
    else:
        x0, _ = topoccd.read_mesh(frames + "/227.ply")
        x1, tris = topoccd.read_mesh(frames + "/228.ply")
        x0, x1 = x0.astype(np.int32), x1.astype(np.int32)
    kind = case.split("-", 1)[1]
    out = {{"case": case}}
    try:
        if kind == "all":
            r = topoccd.query(x0, x1, tris, threads=1)
            out.update(n=len(r), earliest=r.earliest_toi, truncated=r.truncated,
                       complete=r.earliest_complete)
        elif kind == "earliest":
            r = topoccd.Ccd().query(x0, x1, tris, mode="earliest", threads=1)
            out.update(n=len(r), earliest=r.earliest_toi, truncated=r.truncated,
                       complete=r.earliest_complete)
        elif kind == "stepsize":
            out["alpha"] = topoccd.collision_free_stepsize(x0, x1, tris, threads=1)
        elif kind == "free":
            out["free"] = topoccd.is_step_collision_free(x0, x1, tris, threads=1)
        elif kind == "check":
            out["pairs"] = len(topoccd.intersecting_triangles(x0, tris))
        elif kind == "timeout":
            topoccd.query(x0, x1, tris, threads=1, max_contacts=None, timeout=1.0)
    except Exception as e:
        out["error"] = type(e).__name__
        out["message"] = str(e)
    print(json.dumps(out))
    """
).format(limit=LIMIT)


def run(frames, case):
    """Runs `case` in a subprocess under the limit; its JSON line (the process must exit 0)."""
    proc = subprocess.run(
        [sys.executable, "-c", CHILD, str(frames), case],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, f"{case}: exit {proc.returncode}, {proc.stderr[-2000:]}"
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def frames(scenes_dir):
    return scenes_dir / "cloth-funnel" / "frames"


def test_collapsed_step_answers_with_the_defaults(frames):
    # Everything touches at t=0: the step size is 0, the step is not free, the earliest
    # time is 0 exactly; every report is capped by default, and says it is not complete.
    assert run(frames, "collapsed-stepsize") == {"case": "collapsed-stepsize", "alpha": 0.0}
    assert run(frames, "collapsed-free") == {"case": "collapsed-free", "free": False}
    for mode in ["earliest", "all"]:
        out = run(frames, f"collapsed-{mode}")
        assert "error" not in out, out
        assert out["earliest"] == 0.0, out
        assert out["n"] == topoccd.DEFAULT_MAX_CONTACTS, out
        assert out["truncated"]["reason"] == "max_contacts", out
        assert out["complete"] is False, out


def test_collapsed_static_check_stops_at_its_cap(frames):
    out = run(frames, "collapsed-check")
    assert out.get("error") == "RuntimeError", out
    assert f"more than {topoccd.DEFAULT_MAX_CONTACTS} pairs" in out["message"], out


def test_collapsed_step_without_a_cap_ends_on_its_timeout(frames):
    out = run(frames, "collapsed-timeout")
    assert out.get("error") == "TimeoutError", out


def test_coordinates_near_the_end_of_f64_give_their_contacts(frames):
    # Triangle 1 falls flat through triangle 0 at t = 1/2 (the case): never an empty
    # report, a step size within the first contact, a step that is not free.
    out = run(frames, "huge-all")
    assert "error" not in out, out
    assert out["n"] >= 3 and out["earliest"] <= 0.5 and out["complete"], out
    out = run(frames, "huge-earliest")
    assert out["earliest"] <= 0.5, out
    assert run(frames, "huge-free")["free"] is False
    assert run(frames, "huge-stepsize")["alpha"] <= 0.8 * 0.5
    assert run(frames, "huge-check")["pairs"] == 0  # apart at t=0
