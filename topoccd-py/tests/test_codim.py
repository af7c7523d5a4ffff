"""Codimensional geometry from Python: free edges (``edges=``) and free points in a query,
with the report's ``ve`` and ``vv`` arrays, and the per-pair ``point_edge_ccd`` and
``point_point_ccd`` on analytic cases with known times."""

import numpy as np
import pytest

import topoccd


def test_point_edge_and_point_point_known_times():
    e = [[-1.0, 0, 0], [1.0, 0, 0]]
    hit, toi = topoccd.point_edge_ccd([0.3, 0, 1], *e, [0.3, 0, -1], *e)
    assert hit and 0.5 - 1e-6 <= toi <= 0.5
    hit, toi = topoccd.point_edge_ccd([1.2, 0, 1], *e, [1.2, 0, -1], *e)
    assert not hit and toi == np.inf
    hit, toi = topoccd.point_point_ccd([-1, 0, 0], [1, 0, 0], [3, 0, 0], [-3, 0, 0])
    assert hit and 0.25 - 1e-6 <= toi <= 0.25
    # With min_distance d the head-on pair touches at (2 - d) / 8.
    hit, toi = topoccd.point_point_ccd([-1, 0, 0], [1, 0, 0], [3, 0, 0], [-3, 0, 0], min_distance=0.4)
    assert hit and 0.2 - 1e-6 <= toi <= 0.2


def test_batches_match_single_pairs():
    rng = np.random.default_rng(3)
    x_t0 = rng.uniform(-1, 1, (64, 3, 3))
    x_t1 = rng.uniform(-1, 1, (64, 3, 3))
    hit, toi = topoccd.point_edge_ccd(x_t0, x_t1, min_distance=0.2)
    for i in range(64):
        h, t = topoccd.point_edge_ccd(*x_t0[i], *x_t1[i], min_distance=0.2)
        assert (h, t) == (hit[i], toi[i])
    pp_hit, pp_toi = topoccd.point_point_ccd(x_t0[:, :2], x_t1[:, :2], min_distance=0.3)
    assert pp_hit.shape == (64,)
    with pytest.raises(topoccd.InputError):
        topoccd.point_point_ccd(x_t0, x_t1)  # (N, 3, 3) is not (N, 2, 3)


def test_query_with_free_edges_and_points():
    # A rod (free edge 0-1) and two particles: 2 falls onto the rod at t=0.25, 3 at t=0.75;
    # the particles meet each other at t = 4.75 / (17 / 3).
    x0 = np.array([[-1, 0, 0], [1, 0, 0], [0.5, 0, 0.25], [0.5, 0, 5.0]])
    x1 = np.array([[-1, 0, 0], [1, 0, 0], [0.5, 0, -0.75], [0.5, 0, -5 / 3]])
    triangles = np.zeros((0, 3), dtype=np.int64)
    r = topoccd.query(x0, x1, triangles, edges=[[0, 1]])
    assert r.ve.tolist() == [[2, 0, 1], [3, 0, 1]]
    assert r.ve_toi[0] <= 0.25 and r.ve_toi[0] > 0.25 - 1e-6
    assert r.vv.tolist() == [[2, 3]]
    assert r.vv_toi[0] <= 4.75 / (17 / 3)
    assert r.earliest[0] == "ve"
    # Without edges= the free vertices are ignored, as before.
    r = topoccd.query(x0, x1, triangles)
    assert len(r.ve) == 0 and len(r.vv) == 0 and r.earliest is None
    with pytest.raises(topoccd.InputError, match="edge 0"):
        topoccd.query(x0, x1, triangles, edges=[[0, 9]])


def test_line_search_helpers_see_free_edges():
    # The rod and particles above: the earliest contact is particle 2 on the rod at t=0.25.
    x0 = np.array([[-1, 0, 0], [1, 0, 0], [0.5, 0, 0.25], [0.5, 0, 5.0]])
    x1 = np.array([[-1, 0, 0], [1, 0, 0], [0.5, 0, -0.75], [0.5, 0, -5 / 3]])
    triangles = np.zeros((0, 3), dtype=np.int64)
    alpha, earliest = topoccd.collision_free_stepsize(
        x0, x1, triangles, edges=[[0, 1]], conservative_rescaling=1.0, return_earliest=True
    )
    assert 0.25 - 1e-6 < alpha <= 0.25
    assert (earliest.kind, earliest.indices, earliest.certainty) == ("ve", (2, 0, 1), 0)
    assert topoccd.collision_free_stepsize(x0, x1, triangles, edges=[[0, 1]]) <= 0.8 * 0.25
    assert not topoccd.is_step_collision_free(x0, x1, triangles, edges=[[0, 1]])
    assert topoccd.is_step_collision_free(x0, x1, triangles, edges=[[0, 1]], tmax=0.24)
    # Two particles alone: they meet at 4.75 / (17 / 3); a vv earliest contact.
    alpha, earliest = topoccd.collision_free_stepsize(
        x0[2:], x1[2:], triangles, conservative_rescaling=1.0, return_earliest=True, edges=[]
    )
    assert earliest.kind == "vv" and earliest.indices == (0, 1)
    assert 4.75 / (17 / 3) - 1e-6 < alpha <= 4.75 / (17 / 3)
    # Without edges= the free vertices are not seen: the whole step.
    assert topoccd.collision_free_stepsize(x0, x1, triangles) == 1.0


def test_docstring_examples():
    import doctest

    for obj in (topoccd.point_edge_ccd, topoccd.point_point_ccd):
        runner = doctest.DocTestRunner()
        for test in doctest.DocTestFinder(recurse=False).find(obj, globs={}):
            runner.run(test)
        assert runner.failures == 0 and runner.tries > 0, obj
    assert "edges" in topoccd.Ccd.query.__doc__


def test_write_pairs_has_the_ve_and_vv_lines(tmp_path):
    # A rod (0-1); particle 2 falls across it at t=0.5, particle 3 onto particle 4 at t=0.25.
    x0 = np.array([[0, 0, 0], [1, 0, 0], [0.5, 0, 1], [3, 0, 0.5], [3, 0, 0]], dtype=float)
    x1 = np.array([[0, 0, 0], [1, 0, 0], [0.5, 0, -1], [3, 0, -1.5], [3, 0, 0]], dtype=float)
    r = topoccd.query(x0, x1, np.zeros((0, 3), dtype=np.int64), edges=[[0, 1]])
    path = tmp_path / "pairs.csv"
    r.write_pairs(path)
    lines = path.read_text().splitlines()
    assert [line.rsplit(",", 1)[0] for line in lines] == ["ve,2,0,1", "vv,3,4"]
    assert [float(line.rsplit(",", 1)[1]) for line in lines] == [r.ve_toi[0], r.vv_toi[0]]
