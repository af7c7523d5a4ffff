"""The GIL is released during a query; a contiguous float64 input is not copied."""

import threading
import time

import numpy as np
import pytest
import topoccd
from scenes import crossing_sheets, falling_triangle


def long_step(scenes_dir_or_none):
    """cloth-ball if the shared data is there, else a large generated step."""
    if scenes_dir_or_none is not None:
        from truth import Scene

        scene = Scene(scenes_dir_or_none / "cloth-ball")
        x0, _ = topoccd.read_mesh(scene.start)
        x1, triangles = topoccd.read_mesh(scene.end)
        return x0, x1, triangles
    return crossing_sheets(200)


def counting_rate(seconds: float = 0.2) -> float:
    """Increments per second of the counting loop with nothing else running."""
    n, end = 0, time.perf_counter() + seconds
    while time.perf_counter() < end:
        n += 1
    return n / seconds


def test_a_second_thread_runs_during_a_query(scenes_dir):
    x0, x1, triangles = long_step(scenes_dir)
    rate = counting_rate()
    count, running = [0], [True]

    def counter():
        while running[0]:
            count[0] += 1

    thread = threading.Thread(target=counter)
    thread.start()
    try:
        time.sleep(0.05)
        before = count[0]
        started = time.perf_counter()
        report = topoccd.Ccd().query(x0, x1, triangles, threads=1)
        seconds = time.perf_counter() - started
        during = count[0] - before
    finally:
        running[0] = False
        thread.join()
    assert seconds > 0.3, f"the query took only {seconds:.3f} s: too short to tell"
    assert len(report) > 0
    # With the GIL held the counter would only run in the query's Python prologue and
    # epilogue (a few switch intervals of 5 ms). Released, it runs all along.
    share = during / (rate * seconds)
    print(f"query {seconds:.2f} s; the counting thread ran at {share:.0%} of its solo rate")
    assert share > 0.25, f"counting thread ran at {share:.1%} of its rate during the query"


def test_contiguous_float64_positions_are_not_copied():
    x0, x1, tris = falling_triangle()
    assert x0.flags.c_contiguous and x0.dtype == np.float64
    r = topoccd.query(x0, x1, tris)
    # The library read the caller's own memory: the address of the positions it used is the
    # array's data pointer.
    assert r._borrowed == (True, True)
    assert r._x0_address == x0.ctypes.data
    assert r._x1_address == x1.ctypes.data


@pytest.mark.parametrize(
    "convert",
    [
        lambda a: a.astype(np.float32),
        np.asfortranarray,
        lambda a: np.repeat(a, 2, axis=0)[::2],  # strided view
        lambda a: a.tolist(),
    ],
    ids=["float32", "fortran", "strided", "list"],
)
def test_other_inputs_are_converted_once(convert):
    x0, x1, tris = falling_triangle()
    r = topoccd.query(convert(x0), x1, tris)
    assert r._borrowed == (False, True)
    assert r._x1_address == x1.ctypes.data
    assert r.vf.tolist() == [[3, 0], [4, 0], [5, 0]]


def test_inputs_are_not_modified():
    x0, x1, tris = crossing_sheets(8)
    copies = [a.copy() for a in (x0, x1, tris)]
    topoccd.query(x0, x1, tris, geometry=True)
    for a, b in zip((x0, x1, tris), copies):
        np.testing.assert_array_equal(a, b)


def test_one_ccd_used_by_two_threads_at_once_raises_instead_of_crashing():
    x0, x1, tris = crossing_sheets(120)
    ccd = topoccd.Ccd()
    outcomes = []

    def run():
        try:
            outcomes.append(len(ccd.query(x0, x1, tris, threads=1)))
        except RuntimeError as err:
            outcomes.append(err)

    first = threading.Thread(target=run)
    first.start()
    time.sleep(0.1)
    run()  # while the first query runs (its GIL released): the object is busy
    first.join()
    errors = [o for o in outcomes if isinstance(o, RuntimeError)]
    counts = [o for o in outcomes if not isinstance(o, RuntimeError)]
    assert len(outcomes) == 2 and counts and counts[0] > 0
    assert len(errors) <= 1
    for err in errors:
        assert "use one Ccd per thread" in str(err)
