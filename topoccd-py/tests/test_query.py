"""The query API: arrays out, options, modes and methods, reuse, threads, geometry, help."""

import numpy as np
import pytest
import topoccd
from scenes import crossing_sheets, falling_triangle


def test_falling_triangle_pairs_and_times():
    x0, x1, tris = falling_triangle()
    r = topoccd.Ccd().query(x0, x1, tris)
    assert r.vf.dtype == np.int64 and r.vf.shape == (3, 2)
    assert r.vf.tolist() == [[3, 0], [4, 0], [5, 0]]
    np.testing.assert_allclose(r.vf_toi, [0.5, 0.75, 0.75], atol=2e-6)
    assert np.all(r.vf_toi <= [0.5, 0.75, 0.75])  # never later than the contact
    assert r.vf_certainty.dtype == np.uint8 and r.vf_certainty.tolist() == [0, 0, 0]
    assert r.ee.shape == (0, 4) and r.ee_toi.shape == (0,) and r.ee_certainty.shape == (0,)
    assert r.earliest[:3] == ("vf", 3, 0) and r.earliest[3] == r.earliest_toi
    assert r.earliest_toi == pytest.approx(0.5, abs=2e-6)
    assert r.unresolved == 0 and len(r) == 3
    assert r.vf_point is None and r.ee_params is None
    for key in ("bv_tests", "vf_tests", "ee_tests", "peak_candidates", "vertices", "triangles"):
        assert isinstance(r.stats[key], int)
    assert r.stats["vertices"] == 6 and r.stats["triangles"] == 2
    for key in ("build", "traverse", "narrow", "total"):
        assert r.seconds[key] >= 0.0
    assert "earliest_toi=0.5" in repr(r) or "earliest_toi=0.4999" in repr(r)


def test_no_contact():
    x0, x1, tris = falling_triangle()
    r = topoccd.query(x0, x0, tris)
    assert r.earliest is None and r.earliest_toi is None and len(r) == 0


def test_t_max_cuts_later_contacts():
    x0, x1, tris = falling_triangle()
    r = topoccd.query(x0, x1, tris, tmax=0.6)
    assert r.vf.tolist() == [[3, 0]]


def test_methods_agree_on_many_contacts():
    x0, x1, tris = crossing_sheets(20)
    reports = {m: topoccd.query(x0, x1, tris, method=m) for m in ("bvh", "cluster", "brute")}
    base = reports["bvh"]
    assert len(base.vf) > 100 and len(base.ee) > 100
    for name, r in reports.items():
        np.testing.assert_array_equal(r.vf, base.vf, err_msg=name)
        np.testing.assert_array_equal(r.ee, base.ee, err_msg=name)
        np.testing.assert_allclose(r.vf_toi, base.vf_toi, atol=2e-6, err_msg=name)
    assert "cluster" in reports["cluster"].stats
    assert "clustering" in reports["cluster"].seconds
    ee = base.ee
    assert np.all(ee[:, 0] < ee[:, 1]) and np.all(ee[:, 2] < ee[:, 3])


def test_earliest_mode_matches_all_mode():
    x0, x1, tris = crossing_sheets(16)
    a = topoccd.query(x0, x1, tris)
    e = topoccd.query(x0, x1, tris, mode="earliest")
    assert e.earliest_toi == pytest.approx(a.earliest_toi, abs=1e-6)
    assert len(e) <= len(a)


def test_reused_ccd_and_threads_give_the_same_pairs():
    x0, x1, tris = crossing_sheets(16)
    ccd = topoccd.Ccd()
    first = ccd.query(x0, x1, tris)
    for threads in (1, 2, 1, None):
        again = ccd.query(x0, x1, tris, threads=threads)
        np.testing.assert_array_equal(again.vf, first.vf)
        np.testing.assert_array_equal(again.ee, first.ee)
        np.testing.assert_array_equal(again.vf_toi, first.vf_toi)
    assert "pool of 1 threads" in repr(ccd) or repr(ccd) == "<topoccd.Ccd>"


def test_any_dtype_and_order_give_the_same_pairs():
    x0, x1, tris = crossing_sheets(12)
    base = topoccd.query(x0, x1, tris)
    variants = [
        (np.asfortranarray(x0), np.asfortranarray(x1), tris.astype(np.uint32)),
        (x0.astype(np.float32).astype(np.float64), x1, tris.astype(np.int16)),
        (x0.tolist(), x1.tolist(), tris.tolist()),
        (x0[:, ::-1][:, ::-1], x1, np.asfortranarray(tris.astype(np.uint64))),
    ]
    for a, b, t in variants:
        r = topoccd.query(a, b, t)
        if isinstance(a, list) or a.dtype == np.float64:
            np.testing.assert_array_equal(r.vf, base.vf)
            np.testing.assert_array_equal(r.ee, base.ee)
    r32 = topoccd.query(x0.astype(np.float32), x1.astype(np.float32), tris)
    assert len(r32) > 0


def test_geometry_arrays():
    x0, x1, tris = falling_triangle()
    r = topoccd.query(x0, x1, tris, geometry=True)
    for name, shape in [("vf_barycentric", (3, 3)), ("vf_point", (3, 3)), ("vf_normal", (3, 3)),
                        ("ee_params", (0, 2)), ("ee_point", (0, 3)), ("ee_normal", (0, 3))]:
        a = getattr(r, name)
        assert a is not None and a.shape == shape and a.dtype == np.float64, name


def test_geometry_values():
    """Contact of vertex 3 at t=0.5: the point (0.2, 0.2, 0), on the face's plane z=0."""
    x0, x1, tris = falling_triangle()
    r = topoccd.query(x0, x1, tris, geometry=True)
    if np.isnan(r.vf_point).all():
        pytest.skip("SKIPPED, NOT TESTED: the library returned no contact geometry")
    np.testing.assert_allclose(r.vf_point[0], [0.2, 0.2, 0.0], atol=1e-5)
    np.testing.assert_allclose(r.vf_barycentric[0].sum(), 1.0, atol=1e-9)
    np.testing.assert_allclose(np.abs(r.vf_normal[0]), [0, 0, 1], atol=1e-6)


def test_groups_filter_pairs_within_one_group():
    x0, x1, tris = crossing_sheets(10)
    n_half = len(x0) // 2
    one_group = topoccd.query(x0, x1, tris, groups=np.zeros(len(x0), dtype=np.int32))
    assert len(one_group) == 0
    two = np.repeat([0, 1], n_half)
    assert len(topoccd.query(x0, x1, tris, groups=two)) > 0


def test_parents_start_new_vertices_at_their_parent():
    """A vertex appears in the step (a cut): without its parent it would not move."""
    x0, x1, tris = falling_triangle()
    # Vertex 6 is new: a copy of vertex 3, on a new triangle (6, 4, 5).
    x1b = np.vstack([x1, x1[3]])
    trisb = np.vstack([tris, [[6, 4, 5]]])
    r = topoccd.query(x0, x1b, trisb, parents=[[6, 3]])
    assert (6, 0) in set(map(tuple, r.vf.tolist()))
    # Without a parent vertex 6 stays at its x1 position (below the plane): no contact of it.
    # (An empty parent list says so; without `parents` a shorter x0 is an error, issue 38.)
    r_still = topoccd.query(x0, x1b, trisb, parents=np.zeros((0, 2), dtype=np.int64))
    assert (6, 0) not in set(map(tuple, r_still.vf.tolist()))


def test_help_explains_the_options():
    doc = topoccd.Ccd.query.__doc__
    for word in ("x0", "triangles", "parents", "groups", "method", "tolerance", "tmax",
                 "min_distance", "threads", "geometry", "InputError"):
        assert word in doc, word
    assert "earliest_toi" in topoccd.Report.__doc__
    assert topoccd.read_mesh.__doc__ and topoccd.read_sequence.__doc__
    assert topoccd.query.__doc__ and topoccd.batch.run_sequence.__doc__


def test_docstring_examples():
    import doctest

    for obj in (topoccd.Ccd, topoccd.query):
        finder = doctest.DocTestFinder(recurse=False)
        runner = doctest.DocTestRunner()
        for test in finder.find(obj, globs={}):
            runner.run(test)
        assert runner.failures == 0 and runner.tries > 0, obj
