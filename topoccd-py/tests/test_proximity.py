"""The proximity query from Python: analytic pairs with their types, the numpy layout, the same
pairs for one and two threads and across a refit, limits and errors named. The conformance with
ipctk lives in topoccd-benches/scripts/ipc_loop.py (CI has no ipctk); the Rust tests compare the
hierarchy with the brute-force oracle on every generated scene."""

import numpy as np
import pytest
import topoccd


def scene():
    # Triangle 0 1 2; particle 3 above its interior; rod 4-5 over it, crossing edges (0, 1)
    # and (1, 2); two particles 6 and 7 far away, 0.4e-3 apart.
    x = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, 0.5e-3],
                  [0.5, -0.5, 0.2e-3], [0.6, 0.5, 0.2e-3], [3, 3, 3], [3, 3, 3.0004]])
    return x, np.array([[0, 1, 2]]), np.array([[5, 4]])


def test_every_kind_with_distance_and_type():
    x, tris, rods = scene()
    p = topoccd.proximity(x, tris, 1e-3, edges=rods)
    assert p.vf.tolist() == [[3, 0]] and p.vf.dtype == np.int64
    assert topoccd.POINT_TRIANGLE_TYPES[p.vf_type[0]] == "P_T"
    assert p.vf_distance[0] == pytest.approx(0.5e-3, abs=1e-15)
    assert p.ee.tolist() == [[0, 1, 4, 5], [1, 2, 4, 5]]
    assert [topoccd.EDGE_EDGE_TYPES[t] for t in p.ee_type] == ["EA_EB", "EA_EB"]
    assert np.allclose(p.ee_distance, 0.2e-3, atol=1e-15)
    assert p.vv.tolist() == [[6, 7]] and p.vv_distance[0] == pytest.approx(0.4e-3, abs=1e-12)
    assert p.ve.shape == (0, 3) and p.ve_distance.shape == (0,)
    assert len(p) == 4 and p.truncated is None


def test_point_edge_and_dmin():
    # A free point 0.3e-3 beyond the end of a rod: P_E1; 1.5e-3 above it needs dmin.
    x = np.array([[0, 0, 0], [1, 0, 0], [1.0003, 0, 0], [0.5, 0, 1.5e-3]])
    p = topoccd.proximity(x, np.zeros((0, 3), dtype=int), 1e-3, edges=[[0, 1]])
    assert p.ve.tolist() == [[2, 0, 1]]
    assert topoccd.POINT_EDGE_TYPES[p.ve_type[0]] == "P_E1"
    assert p.ve_distance[0] == pytest.approx(0.3e-3, rel=1e-9)
    q = topoccd.proximity(x, np.zeros((0, 3), dtype=int), 1e-3, edges=[[0, 1]], dmin=1e-3)
    assert q.ve.tolist() == [[2, 0, 1], [3, 0, 1]]
    assert topoccd.POINT_EDGE_TYPES[q.ve_type[1]] == "P_E"


def cloth(n=30, seed=3):
    """A crumpled grid: many pairs within a small dhat."""
    rng = np.random.default_rng(seed)
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    x = np.column_stack([i.ravel() / n, j.ravel() / n, 0.02 * rng.normal(size=n * n)])
    x[:, 2] += 0.3 * np.sin(8 * x[:, 0])
    x[:, 0] = np.abs(x[:, 0] - 0.5)  # folded onto itself
    t = []
    for a in range(n - 1):
        for b in range(n - 1):
            v = a * n + b
            t += [[v, v + n, v + n + 1], [v, v + n + 1, v + 1]]
    return x, np.array(t)


def test_threads_refit_and_ccd_reuse():
    x, tris = cloth()
    ccd = topoccd.Ccd()
    one = ccd.proximity(x, tris, 0.02, threads=1)
    assert not one.refitted and len(one) > 100
    two = ccd.proximity(x, tris, 0.02, threads=2)
    assert two.refitted
    for kind in ("vf", "ee", "ve", "vv"):
        assert np.array_equal(getattr(one, kind), getattr(two, kind))
        assert np.array_equal(getattr(one, kind + "_distance"), getattr(two, kind + "_distance"))
        assert np.array_equal(getattr(one, kind + "_type"), getattr(two, kind + "_type"))
    assert np.all(one.vf_distance < 0.02) and np.all(one.ee_distance < 0.02)
    # ee rows as the CCD report writes them.
    ee = one.ee
    assert np.all(ee[:, 0] < ee[:, 1]) and np.all(ee[:, 2] < ee[:, 3])
    assert np.all((ee[:, 0] < ee[:, 2]) | ((ee[:, 0] == ee[:, 2]) & (ee[:, 1] < ee[:, 3])))
    # The same Ccd answers CCD queries between its proximity queries: a triangle falls
    # through a fixed one, first contact at t = 0.5, so the step is 0.8 of it.
    fixed = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    falling = np.array([[0.2, 0.2, 1], [0.3, 0.2, 1], [0.2, 0.3, 1]])
    x0, x1 = np.vstack([fixed, falling]), np.vstack([fixed, falling - [0, 0, 2]])
    alpha = topoccd.collision_free_stepsize(x0, x1, [[0, 1, 2], [3, 4, 5]], ccd=ccd)
    assert alpha == pytest.approx(0.4, abs=1e-6)
    again = ccd.proximity(x, tris, 0.02, threads=1)
    assert again.refitted and np.array_equal(again.ee, one.ee)


def test_groups_limits_and_errors():
    x, tris = cloth()
    all_pairs = topoccd.proximity(x, tris, 0.02)
    capped = topoccd.proximity(x, tris, 0.02, max_contacts=7)
    assert len(capped) == 7 and capped.truncated == "max_contacts"
    one_group = topoccd.proximity(x, tris, 0.02, groups=np.zeros(len(x), dtype=int))
    assert len(one_group) == 0 < len(all_pairs)
    with pytest.raises(topoccd.OptionsError, match="dhat"):
        topoccd.proximity(x, tris, 0.0)
    with pytest.raises(topoccd.OptionsError, match="dmin"):
        topoccd.proximity(x, tris, 1e-3, dmin=-1.0)
    with pytest.raises(topoccd.InputError, match="edge 1 names vertex 9999"):
        topoccd.proximity(x, tris, 1e-3, edges=[[0, 1], [2, 9999]])
    with pytest.raises(topoccd.InputError, match="edge 0 uses vertex 2 twice"):
        topoccd.proximity(x, tris, 1e-3, edges=[[2, 2]])
    bad = x.copy()
    bad[5, 1] = np.nan
    with pytest.raises(topoccd.InputError, match="vertex 5"):
        topoccd.proximity(bad, tris, 1e-3)
    with pytest.raises(TimeoutError):
        topoccd.proximity(x, tris, 0.02, timeout=0.0)
