"""Every entry point with its cap lifted (issue 51, item 7): on a collapsed configuration (the
integer-cast cloth-funnel step, every vertex on one of ten points), in a subprocess under a 1 GiB address-space
limit (``resource.setrlimit``), each call raises ``MemoryError`` naming the buffer and the
bytes it asked for: the interpreter is not aborted, and the same ``Ccd`` answers a capped
CCD query afterwards. Reading a file whose vertices do not fit raises ``MemoryError`` naming
the file and what was being read.
"""

import json
import os
import subprocess
import sys
import textwrap

import pytest

#: The address-space limit of each subprocess.
LIMIT = 1024**3

CHILD = textwrap.dedent(
    """
    import json, resource, sys, warnings
    resource.setrlimit(resource.RLIMIT_AS, ({limit}, {limit}))
    import numpy as np, topoccd
    warnings.simplefilter("ignore", topoccd.InputWarning)
    frames, case = sys.argv[1], sys.argv[2]
    x0, _ = topoccd.read_mesh(frames + "/227.ply")
    x1, tris = topoccd.read_mesh(frames + "/228.ply")
    x0, x1 = x0.astype(np.int32), x1.astype(np.int32)
    ccd = topoccd.Ccd()
    out = {{"case": case}}
    try:
        if case == "all":
            ccd.query(x0, x1, tris, max_contacts=None)
        elif case == "earliest":
            ccd.query(x0, x1, tris, mode="earliest", max_contacts=None)
        elif case == "proximity":
            ccd.proximity(x0, tris, 1e-3, max_contacts=None)
    except MemoryError as e:
        out["error"] = "MemoryError"
        out["message"] = str(e)
    # The interpreter and the query object live on: a capped query answers.
    if case != "proximity":
        out["after"] = ccd.query(x0, x1, tris).truncated["reason"]
    else:
        r = ccd.proximity(x0, tris, 1e-3)
        out["after"] = r.truncated
        out["after_pairs"] = len(r.vf) + len(r.ee)
    print(json.dumps(out))
    """
).format(limit=LIMIT)


def run(frames, case):
    """Runs `case` in a subprocess under the limit; its JSON line (the process must exit 0)."""
    # One BLAS thread and two malloc arenas: each would reserve address space of its own.
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MALLOC_ARENA_MAX="2")
    proc = subprocess.run(
        [sys.executable, "-c", CHILD, str(frames), case],
        capture_output=True,
        text=True,
        timeout=600,
        env=env,
    )
    assert proc.returncode == 0, f"{case}: exit {proc.returncode}, {proc.stderr[-2000:]}"
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def frames(scenes_dir):
    return scenes_dir / "cloth-funnel" / "frames"


@pytest.mark.parametrize("case", ["all", "earliest", "proximity"])
def test_uncapped_call_raises_memory_error_under_an_address_space_limit(frames, case):
    out = run(frames, case)
    assert out.get("error") == "MemoryError", out
    assert "out of memory: could not allocate" in out["message"], out
    assert "bytes for the" in out["message"], out
    assert out["after"] == "max_contacts", out
    if case == "proximity":
        assert out["after_pairs"] == 1_000_000, out


READER = textwrap.dedent(
    """
    import json, resource, sys
    resource.setrlimit(resource.RLIMIT_AS, ({limit}, {limit}))
    import topoccd
    out = {{}}
    try:
        topoccd.read_mesh(sys.argv[1])
    except MemoryError as e:
        out["error"] = "MemoryError"
        out["message"] = str(e)
    # The interpreter lives on.
    out["after"] = len(topoccd.read_mesh(sys.argv[2])[1])
    print(json.dumps(out))
    """
).format(limit=LIMIT)


def test_a_file_larger_than_memory_raises_memory_error(tmp_path):
    """A binary PLY file as large as its header says (sparse: no disk space), whose 200
    million vertices do not fit under the limit."""
    vertices = 200_000_000
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {vertices}\n"
        "property float x\nproperty float y\nproperty float z\n"
        "element face 0\nproperty list uchar int vertex_indices\nend_header\n"
    ).encode()
    huge = tmp_path / "huge.ply"
    with open(huge, "wb") as f:
        f.write(header)
        f.truncate(len(header) + 12 * vertices)
    small = tmp_path / "small.obj"
    small.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MALLOC_ARENA_MAX="2")
    proc = subprocess.run(
        [sys.executable, "-c", READER, str(huge), str(small)],
        capture_output=True,
        text=True,
        timeout=600,
        env=env,
    )
    assert proc.returncode == 0, f"exit {proc.returncode}, {proc.stderr[-2000:]}"
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert out.get("error") == "MemoryError", out
    assert f"{huge}: out of memory reading the vertex positions" in out["message"], out
    assert out["after"] == 1, out
