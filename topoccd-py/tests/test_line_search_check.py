"""The line-search helpers (collision_free_stepsize, is_step_collision_free) on the real
cloth-funnel step, and the static check (intersecting_triangles) on analytic cases, against a
double loop and against the CLI's `topoccd check`."""

import doctest
import json
import subprocess

import numpy as np
import pytest
import topoccd

from conftest import run_cli

#: The exact earliest root of cloth-funnel's step (the data's toi/227vf_toi.txt).
FUNNEL_EARLIEST = 0.0452322


@pytest.fixture(scope="module")
def funnel(scenes_dir):
    x0, x1, triangles, _ = topoccd.read_sequence(scenes_dir / "cloth-funnel")[0]
    return x0, x1, triangles


@pytest.mark.parametrize("min_distance", [0.0, 1e-8])
def test_the_step_size_gives_a_step_without_contact(funnel, min_distance):
    x0, x1, triangles = funnel
    ccd = topoccd.Ccd()
    alpha = topoccd.collision_free_stepsize(x0, x1, triangles, min_distance=min_distance, ccd=ccd)
    assert 0 < alpha <= 0.8 * (FUNNEL_EARLIEST + 1e-7)
    if min_distance == 0.0:
        assert alpha >= 0.8 * (FUNNEL_EARLIEST - 1e-6 - 1e-7)
    assert not topoccd.is_step_collision_free(x0, x1, triangles, min_distance=min_distance)
    x_alpha = x0 + alpha * (x1 - x0)
    assert topoccd.is_step_collision_free(x0, x_alpha, triangles, min_distance=min_distance, ccd=ccd)
    for method in ("bvh", "brute"):
        report = ccd.query(x0, x_alpha, triangles, method=method, min_distance=min_distance)
        assert len(report) == 0, method
    # The same number as the earliest query gives, and as the CLI's Earliest step.
    earliest = topoccd.query(x0, x1, triangles, mode="earliest", min_distance=min_distance)
    assert alpha == 0.8 * earliest.earliest_toi


def test_step_size_agrees_with_the_cli(funnel, cli, scenes_dir):
    x0, x1, triangles = funnel
    frames = sorted((scenes_dir / "cloth-funnel" / "frames").glob("*.ply"))
    out = json.loads(run_cli(cli, "step", str(frames[0]), str(frames[1]), "--earliest", "--json"))
    alpha = topoccd.collision_free_stepsize(x0, x1, triangles, conservative_rescaling=0.5)
    assert alpha == 0.5 * out["earliest_toi"]


def test_a_free_step_is_taken_whole_and_bad_options_are_refused():
    x0 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.0]])
    assert topoccd.collision_free_stepsize(x0, x0 + 1, [[0, 1, 2]]) == 1.0
    assert topoccd.collision_free_stepsize(x0, x0 + 1, [[0, 1, 2]], tmax=0.5) == 0.5
    assert topoccd.is_step_collision_free(x0, x0 + 1, [[0, 1, 2]]) is True
    for bad in (0.0, 1.5):
        with pytest.raises(topoccd.OptionsError, match="conservative_rescaling"):
            topoccd.collision_free_stepsize(x0, x0, [[0, 1, 2]], conservative_rescaling=bad)
    with pytest.raises(topoccd.OptionsError, match="min_distance"):
        topoccd.is_step_collision_free(x0, x0, [[0, 1, 2]], min_distance=-1.0)
    with pytest.raises(topoccd.InputError, match="vertex 5"):
        topoccd.is_step_collision_free(x0, x0, [[0, 1, 5]])


BASE = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]


def soup(*triangles):
    x = np.array([p for t in triangles for p in t], dtype=np.float64)
    return x, np.arange(len(x)).reshape(-1, 3)


def pairs(*triangles):
    return topoccd.intersecting_triangles(*soup(*triangles)).tolist()


def test_analytic_intersections():
    up = np.nextafter(0.0, 1.0)
    # A vertex on the face, and the same vertex one ulp above it.
    assert pairs(BASE, [[0.25, 0.25, 0], [0.25, 0.25, 1], [0.5, 0.25, 1]]) == [[0, 1]]
    assert pairs(BASE, [[0.25, 0.25, up], [0.25, 0.25, 1], [0.5, 0.25, 1]]) == []
    # Crossing edges, and an edge passing one ulp above.
    assert pairs(BASE, [[0.5, -0.5, 0], [0.5, 0.5, 0], [0.5, 0, -1]]) == [[0, 1]]
    assert pairs(BASE, [[0.5, -0.5, up], [0.5, 0.5, up], [0.5, 0, 1]]) == []
    # Coplanar: overlapping, touching at a corner, and apart by one ulp.
    shifted = lambda dx: [[p[0] + dx, p[1], p[2]] for p in BASE]  # noqa: E731
    assert pairs(BASE, shifted(0.5)) == [[0, 1]]
    assert pairs(BASE, shifted(1.0)) == [[0, 1]]
    assert pairs(BASE, shifted(np.nextafter(1.0, 2.0))) == []
    # Parallel copies and a triangle beside the base.
    assert pairs(BASE, [[p[0], p[1], 1e-9] for p in BASE], [[1.5, 0, -1], [1.5, 1, 0], [1.5, 0, 1]]) == []


def test_a_fresh_cut_is_not_an_intersection_with_its_parents():
    x = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [1, 0, 0], [0, 1, 0.0]])
    triangles = [[0, 1, 2], [4, 3, 5]]
    assert topoccd.intersecting_triangles(x, triangles).tolist() == [[0, 1]]
    assert topoccd.intersecting_triangles(x, triangles, parents=[[4, 1], [5, 2]]).tolist() == []
    with pytest.raises(topoccd.InputError, match="parent row 0"):
        topoccd.intersecting_triangles(x, triangles, parents=[[4, 4]])


def test_the_tree_finds_the_pairs_of_a_double_loop():
    rng = np.random.default_rng(37)
    x = rng.integers(0, 4, size=(40, 3)).astype(np.float64)  # a grid: many touching cases
    triangles = []
    while len(triangles) < 120:
        t = rng.integers(0, 40, size=3)
        if len(set(t.tolist())) == 3:
            triangles.append(t)
    triangles = np.array(triangles)
    got = topoccd.intersecting_triangles(x, triangles).tolist()
    want = []
    for a in range(len(triangles)):
        for b in range(a + 1, len(triangles)):
            if len(set(triangles[a]) & set(triangles[b])) == 0:
                if topoccd.intersecting_triangles(x, triangles[[a, b]]).tolist() == [[0, 1]]:
                    want.append([a, b])
    assert want and got == want


def test_the_check_agrees_with_the_cli(cli, sequence):
    """On the generated sequence (its later frames intersect), with their parents files."""
    seq = topoccd.read_sequence(sequence)
    checked = 0
    for k in range(len(seq)):
        _, x1, triangles, parents = seq[k]
        frame = seq.frames[k + 1]
        done = subprocess.run([cli, "check", frame, "--json"], capture_output=True, text=True)
        assert done.returncode in (0, 1), done.stderr
        out = json.loads(done.stdout)
        got = topoccd.intersecting_triangles(x1, triangles, parents=parents).tolist()
        assert got == out["pairs"], frame
        assert done.returncode == (1 if got else 0)
        checked += len(got)
    assert checked > 0, "the generated frames should intersect somewhere"


def test_docstring_examples():
    for obj in (
        topoccd.point_triangle_ccd,
        topoccd.edge_edge_ccd,
        topoccd.intersecting_triangles,
        topoccd.collision_free_stepsize,
        topoccd.is_step_collision_free,
    ):
        runner = doctest.DocTestRunner()
        for test in doctest.DocTestFinder(recurse=False).find(obj, globs={}):
            runner.run(test)
        assert runner.failures == 0 and runner.tries > 0, obj


# Issue 45: the earliest contact with the step size, the start checked, time and size limits.

FALL_X0 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, 1], [0.3, 0.2, 1.5], [0.2, 0.3, 1.5]], float)
FALL_X1 = FALL_X0 - np.r_[np.zeros((3, 3)), np.tile([0, 0, 2], (3, 1))]
FALL_TRIS = [[0, 1, 2], [3, 4, 5]]


def test_return_earliest_names_the_pair_of_the_earliest_query(funnel):
    # Analytic: vertex 3 reaches face 0 at t=0.5, vertices 4 and 5 at 0.75.
    alpha, earliest = topoccd.collision_free_stepsize(FALL_X0, FALL_X1, FALL_TRIS, return_earliest=True)
    assert earliest.kind == "vf" and earliest.indices == (3, 0) and earliest.certainty == 0
    assert 0.5 - 1e-6 <= earliest.toi <= 0.5 and alpha == 0.8 * earliest.toi
    assert topoccd.collision_free_stepsize(FALL_X0, FALL_X0, FALL_TRIS, return_earliest=True) == (1.0, None)
    # The real step: the pair and time of an Earliest query, and a pair of its report.
    x0, x1, triangles = funnel
    alpha, earliest = topoccd.collision_free_stepsize(x0, x1, triangles, return_earliest=True)
    report = topoccd.query(x0, x1, triangles, mode="earliest")
    assert (earliest.kind, *earliest.indices, earliest.toi) == report.earliest
    assert alpha == 0.8 * report.earliest_toi
    rows = report.vf if earliest.kind == "vf" else report.ee
    assert list(earliest.indices) in rows.tolist()


def test_check_start_refuses_triangles_that_pierce_at_t0():
    # Triangle 1 pierces triangle 0 and does not move: no contact starts during the step.
    x = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, -1], [0.3, 0.2, 1], [0.2, 0.3, 1]], float)
    assert topoccd.collision_free_stepsize(x, x, FALL_TRIS) == 1.0
    assert topoccd.is_step_collision_free(x, x, FALL_TRIS) is True
    with pytest.raises(topoccd.InputError, match=r"triangles 0 and 1 intersect at t=0 \(1 intersecting pairs\)"):
        topoccd.collision_free_stepsize(x, x, FALL_TRIS, check_start=True)
    with pytest.raises(topoccd.InputError, match="intersect at t=0"):
        topoccd.is_step_collision_free(x, x, FALL_TRIS, check_start=True)
    # Apart at t=0, the check passes and the answer is the unchecked one.
    assert topoccd.collision_free_stepsize(FALL_X0, FALL_X1, FALL_TRIS, check_start=True) == (
        topoccd.collision_free_stepsize(FALL_X0, FALL_X1, FALL_TRIS)
    )


def test_check_start_joins_the_sides_of_a_cut():
    # A square cut along its diagonal 1-2 (vertices 4 and 5 are the copies of 1 and 2): at t=0
    # the halves touch along the cut, which is not an intersection (as the CCD's crack filter).
    x0 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    x1 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 1], [1, 0, 1], [0, 1, 1]], float)
    tris, parents = [[0, 1, 2], [4, 3, 5]], [[4, 1], [5, 2]]
    free = topoccd.collision_free_stepsize(x0, x1, tris, parents=parents)
    assert topoccd.collision_free_stepsize(x0, x1, tris, parents=parents, check_start=True) == free


def test_timeout_and_max_contacts_reach_the_query(funnel):
    x0, x1, triangles = funnel
    with pytest.raises(TimeoutError):
        topoccd.collision_free_stepsize(x0, x1, triangles, timeout=1e-9)
    with pytest.raises(TimeoutError):
        topoccd.is_step_collision_free(x0, x1, triangles, timeout=1e-9)
    # A cap keeps the earliest time exact: the same step size.
    assert topoccd.collision_free_stepsize(x0, x1, triangles, max_contacts=1, timeout=60) == (
        topoccd.collision_free_stepsize(x0, x1, triangles)
    )
