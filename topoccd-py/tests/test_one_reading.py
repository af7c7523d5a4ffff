"""One reading of every file: the frames ``topoccd gen`` writes for the scenes with free edges
and free points give Python's ``read_mesh`` and ``read_primitives`` the primitives that the
CLI's ``step``, ``run``, ``proximity`` and ``check`` report, under both rules for loose
vertices; and a query on what Python read finds the pairs ``topoccd run`` writes, every kind.
"""

import json

import numpy as np
import pytest
import topoccd
from conftest import run_cli

# The scenes with free edges or free points (rod-rain has all four contact kinds).
CODIM_SCENES = ["hair", "funnel-particles", "rod-rain"]


@pytest.fixture(scope="module", params=CODIM_SCENES)
def frames(request, cli, tmp_path_factory):
    scene = request.param
    folder = tmp_path_factory.mktemp(scene) / "frames"
    run_cli(cli, "gen", scene, str(folder), "--scale", "0.2", "--frames", "4", "--seed", "1")
    return scene, folder


def cli_primitives(cli, frame0, frame1, folder, loose):
    """``(vertices, triangles, free_edges, free_points)`` of frame 1 as each command reports
    them, by command."""
    flag = ["--loose-vertices", loose]
    step = json.loads(run_cli(cli, "step", str(frame0), str(frame1), "--json", *flag))
    run = [
        json.loads(line)
        for line in run_cli(cli, "run", str(folder), "--json", "--no-check", *flag).splitlines()
    ]
    prox = json.loads(run_cli(cli, "proximity", str(frame1), "--dhat", "1e-3", "--json", *flag))
    # check exits non-zero when it warns; its JSON is still on stdout.
    import subprocess

    done = subprocess.run(
        [cli, "check", str(frame1), "--json", *flag], capture_output=True, text=True
    )
    check = json.loads(done.stdout)
    counts = lambda v: (v["free_edges"], v["free_points"])  # noqa: E731
    return {
        "step": counts(step),
        "run": counts(run[0]),
        "proximity": counts(prox),
        "check": counts(check),
    }, (step["vertices"], step["triangles"])


@pytest.mark.parametrize("loose", ["points", "ignore"])
def test_python_reads_the_primitives_every_command_reads(frames, cli, loose):
    scene, folder = frames
    frame0, frame1 = folder / "0000.ply", folder / "0001.ply"
    by_command, (vertices, triangle_count) = cli_primitives(cli, frame0, frame1, folder, loose)
    x, triangles = topoccd.read_mesh(frame1)
    assert x.shape == (vertices, 3) and triangles.shape == (triangle_count, 3), scene
    edges, points = topoccd.read_primitives(frame1, loose_vertices=loose)
    for command, counts in by_command.items():
        assert counts == (len(edges), len(points)), f"{scene} {loose}: {command}"
    # The rule itself, from the arrays: free edges are in no triangle, free points in no
    # triangle and no edge, and under "points" every vertex is one of the three.
    in_triangles = set(triangles.ravel().tolist())
    in_edges = set(edges.ravel().tolist())
    sides = {tuple(sorted((t[k], t[(k + 1) % 3]))) for t in triangles.tolist() for k in range(3)}
    assert not any(tuple(sorted(e)) in sides for e in edges.tolist()), scene
    assert not (set(points.tolist()) & (in_triangles | in_edges)), scene
    if loose == "points":
        assert in_triangles | in_edges | set(points.tolist()) == set(range(len(x))), scene
    else:
        assert len(points) == 0, scene


def test_a_query_on_what_python_read_finds_the_pairs_of_run(frames, cli, tmp_path):
    scene, folder = frames
    pairs_dir = tmp_path / "pairs"
    lines = [
        json.loads(line)
        for line in run_cli(
            cli, "--threads", "1", "run", str(folder), "--json", "--no-check",
            "--pairs-dir", str(pairs_dir),
        ).splitlines()
    ]
    ccd = topoccd.Ccd()
    kinds = np.zeros(4, dtype=int)
    for k in range(len(lines) - 1):
        x0, _ = topoccd.read_mesh(folder / f"{k:04d}.ply")
        x1, triangles = topoccd.read_mesh(folder / f"{k + 1:04d}.ply")
        # The file's edges as read_primitives gives them (an empty array still turns the
        # free points on): the step run queries.
        edges, _ = topoccd.read_primitives(folder / f"{k + 1:04d}.ply")
        report = ccd.query(x0, x1, triangles, edges=edges, threads=1)
        counts = [len(report.vf), len(report.ee), len(report.ve), len(report.vv)]
        line = lines[k]
        assert counts == [line[kind] for kind in ("vf", "ee", "ve", "vv")], f"{scene} step {k}"
        mine = tmp_path / f"{k:04d}.csv"
        report.write_pairs(mine)
        assert mine.read_text() == (pairs_dir / f"{k:04d}.csv").read_text(), f"{scene} step {k}"
        kinds += counts
    if scene == "rod-rain":
        assert (kinds > 0).all(), f"rod-rain has every kind: {kinds}"
