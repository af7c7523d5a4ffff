"""The per-pair tests (point_triangle_ccd, edge_edge_ccd) on every query of the shared
Sample-Queries set: no false negative against its exact ground truth, single and batched calls
identical, and every outcome identical to the Rust library's (`topoccd queries --outcomes`)."""

import math
from pathlib import Path

import numpy as np
import pytest
import topoccd

from conftest import _missing, run_cli, shared_data, sigint_default


def read_queries(path: Path):
    """The queries of one Sample-Queries file: (points (N, 8, 3), touching (N,), lines (N,))."""
    rows = [line.split(",") for line in path.read_text().splitlines() if line.strip()]
    assert len(rows) % 8 == 0, path
    points, touching, lines = [], [], []
    for q in range(len(rows) // 8):
        block = rows[8 * q : 8 * q + 8]
        # Every value is num/den with a power-of-two den: the float division is exact.
        points.append([[int(r[2 * k]) / int(r[2 * k + 1]) for k in range(3)] for r in block])
        touching.append(block[0][6].strip() == "1")
        lines.append(8 * q + 1)
    return np.array(points, dtype=np.float64), np.array(touching), np.array(lines)


@pytest.fixture(scope="module")
def queries():
    root = shared_data() / "queries"
    if not root.is_dir():
        _missing(f"the shared query data is absent: {root} (set TOPOCCD_SHARED_DATA)")
    out = {"vf": [], "ee": []}
    for kind, folder in (("vf", "vertex-face"), ("ee", "edge-edge")):
        for path in sorted(root.glob(f"*/{folder}/*.csv")):
            out[kind].append((path, *read_queries(path)))
    assert out["vf"] and out["ee"], root
    return out


FUNCTIONS = {"vf": topoccd.point_triangle_ccd, "ee": topoccd.edge_edge_ccd}


@pytest.mark.parametrize("kind", ["vf", "ee"])
def test_no_false_negative_single_and_batched_agree(queries, kind):
    ccd = FUNCTIONS[kind]
    total = positives = false_positives = 0
    for path, points, touching, lines in queries[kind]:
        hit, toi, certainty = ccd(points[:, :4], points[:, 4:], certainty=True)
        assert hit.shape == toi.shape == certainty.shape == (len(points),)
        missed = [int(line) for line, t, h in zip(lines, touching, hit) if t and not h]
        assert not missed, f"{path}: false negatives at lines {missed}"
        assert np.all(np.isinf(toi[~hit])) and np.all((toi[hit] >= 0) & (toi[hit] <= 1))
        for q in range(len(points)):
            one = ccd(*points[q], certainty=True)
            assert one == (bool(hit[q]), float(toi[q]), int(certainty[q])), (path, lines[q])
        total += len(points)
        positives += int(touching.sum())
        false_positives += int((hit & ~touching).sum())
    assert total == {"vf": 1835, "ee": 3049}[kind]
    # The bar of the Rust conformance test (Tight-Inclusion's false positives on these files).
    assert false_positives <= {"vf": 56, "ee": 69}[kind], false_positives


def test_outcomes_match_the_rust_library(queries, cli, tmp_path):
    """Every hit, time of impact and certainty equals the CLI's (the Rust `narrow` tests)."""
    out = tmp_path / "outcomes.csv"
    run_cli(cli, "queries", str(shared_data() / "queries"), "--outcomes", str(out))
    rust = {}
    for line in out.read_text().splitlines():
        kind, path, row, _touching, hit, toi, certainty = line.split(",")
        rust[(kind, Path(path).resolve(), int(row))] = (
            hit == "true",
            float(toi) if toi else math.inf,
            {"resolved": 0, "iteration_limit": 1, "invalid_input": 2}[certainty],
        )
    compared = 0
    for kind in ("vf", "ee"):
        for path, points, _touching, lines in queries[kind]:
            hit, toi, certainty = FUNCTIONS[kind](points[:, :4], points[:, 4:], certainty=True)
            for q, row in enumerate(lines):
                got = (bool(hit[q]), float(toi[q]), int(certainty[q]))
                assert got == rust[(kind, path.resolve(), int(row))], (path, row)
                compared += 1
    assert compared == len(rust) == 4884


def test_keywords_follow_ipctk():
    tri = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    # The point stays 1 above the triangle: no hit, unless min_distance reaches it.
    p_t0, p_t1 = [0.2, 0.2, 1.0], [0.3, 0.2, 1.0]
    assert topoccd.point_triangle_ccd(p_t0, *tri, p_t1, *tri) == (False, math.inf)
    hit, toi = topoccd.point_triangle_ccd(p_t0, *tri, p_t1, *tri, min_distance=1.0)
    assert hit and toi == 0.0
    # Falling through at t=0.5: found over [0, 1], not over [0, 0.4].
    down = [0.2, 0.2, -1.0]
    hit, toi = topoccd.point_triangle_ccd(p_t0, *tri, down, *tri, tolerance=1e-3)
    assert hit and 0.5 - 1e-3 <= toi <= 0.5
    assert topoccd.point_triangle_ccd(p_t0, *tri, down, *tri, tmax=0.4)[0] is False
    hit, toi, code = topoccd.point_triangle_ccd(p_t0, *tri, down, *tri, max_iterations=1, certainty=True)
    assert hit and code in (topoccd.RESOLVED, topoccd.ITERATION_LIMIT) and toi <= 0.5
    # A non-finite coordinate is a conservative hit at 0, marked invalid input.
    nan = [math.nan, 0.2, 1.0]
    assert topoccd.point_triangle_ccd(nan, *tri, down, *tri, certainty=True) == (True, 0.0, 2)


def test_batches_of_any_dtype_and_empty_batches():
    x_t0 = np.array([[[-1, 0, 0], [1, 0, 0], [0, -1, 1], [0, 1, 1]]] * 3, dtype=np.int32)
    x_t1 = x_t0.copy()
    x_t1[:, 2:, 2] = -1
    x_t1[1, 2:, 2] = 1  # stays above edge a
    hit, toi = topoccd.edge_edge_ccd(x_t0, np.asfortranarray(x_t1))
    assert hit.tolist() == [True, False, True]
    assert not hit.flags.writeable and toi.dtype == np.float64
    empty = np.zeros((0, 4, 3))
    hit, toi, code = topoccd.point_triangle_ccd(empty, empty, certainty=True)
    assert hit.shape == toi.shape == code.shape == (0,)


def test_bad_input_is_named():
    tri = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    with pytest.raises(topoccd.InputError, match=r"t1_t0 must have shape \(3,\), got \(2,\)"):
        topoccd.point_triangle_ccd([0, 0, 1], tri[0], [1, 0], tri[2], [0, 0, 1], *tri)
    with pytest.raises(topoccd.InputError, match=r"x_t1 must have shape \(N, 4, 3\)"):
        topoccd.edge_edge_ccd(np.zeros((2, 4, 3)), np.zeros((2, 3, 3)))
    with pytest.raises(topoccd.InputError, match="same shape"):
        topoccd.edge_edge_ccd(np.zeros((2, 4, 3)), np.zeros((3, 4, 3)))
    with pytest.raises(topoccd.InputError, match="real numbers"):
        topoccd.edge_edge_ccd(np.full((1, 4, 3), "a"), np.zeros((1, 4, 3)))
    with pytest.raises(TypeError, match="eight points"):
        topoccd.edge_edge_ccd(np.zeros((1, 4, 3)))
    with pytest.raises(topoccd.OptionsError, match="tolerance"):
        topoccd.point_triangle_ccd(*([[0, 0, 0]] * 8), tolerance=0)
    with pytest.raises(topoccd.OptionsError, match="min_distance"):
        topoccd.point_triangle_ccd(*([[0, 0, 0]] * 8), min_distance=-1)
    with pytest.raises(topoccd.OptionsError, match="tmax"):
        topoccd.point_triangle_ccd(*([[0, 0, 0]] * 8), tmax=2)
    with pytest.raises(topoccd.OptionsError, match="max_iterations"):
        topoccd.point_triangle_ccd(*([[0, 0, 0]] * 8), max_iterations=0)


def test_the_gil_is_released_during_a_batch():
    """A second Python thread keeps running while a batch is tested."""
    import threading
    import time

    from test_gil_and_copies import counting_rate

    rng = np.random.default_rng(3)
    rate = counting_rate()
    count, running = [0], [True]

    def counter():
        while running[0]:
            count[0] += 1

    thread = threading.Thread(target=counter)
    thread.start()
    try:
        time.sleep(0.05)
        # A batch long enough to tell (its time depends on the machine and its load): twice
        # as many pairs until the call takes 0.2 s.
        n = 100_000
        while True:
            x_t0 = rng.normal(size=(n, 4, 3))
            x_t1 = x_t0 + rng.normal(scale=0.5, size=x_t0.shape)
            before = count[0]
            started = time.perf_counter()
            hit, _ = topoccd.point_triangle_ccd(x_t0, x_t1)
            seconds = time.perf_counter() - started
            during = count[0] - before
            if seconds > 0.2 or n >= 6_400_000:
                break
            n *= 2
    finally:
        running[0] = False
        thread.join()
    assert seconds > 0.05, f"{n} pairs took only {seconds:.3f} s: too short to tell"
    assert hit.any()
    # Held, the GIL would let the counter run only around the call (a few 5 ms intervals).
    share = during / (rate * seconds)
    assert share > 0.25, f"counting thread ran at {share:.1%} of its rate during the batch"


def random_batch(n, seed=5):
    rng = np.random.default_rng(seed)
    x_t0 = rng.normal(size=(n, 4, 3))
    return x_t0, x_t0 + rng.normal(scale=0.5, size=x_t0.shape)


@pytest.mark.parametrize("function", [topoccd.point_triangle_ccd, topoccd.edge_edge_ccd])
def test_threads_give_the_same_outcomes(function):
    x_t0, x_t1 = random_batch(20_000)
    want = function(x_t0, x_t1, certainty=True)
    assert want[0].any() and not want[0].all()
    for threads in (1, 2, 3, 1):  # 1 twice: the pool kept for its size is reused
        got = function(x_t0, x_t1, certainty=True, threads=threads, timeout=60)
        for w, g in zip(want, got):
            assert np.array_equal(w, g), threads
    for bad in (0, -1, 5000):
        with pytest.raises(topoccd.OptionsError, match="threads must be None or in"):
            function(x_t0[:1], x_t1[:1], threads=bad)
    with pytest.raises(topoccd.OptionsError, match="timeout must be None or seconds"):
        function(x_t0[:1], x_t1[:1], timeout=0)


def test_a_batch_stops_at_its_timeout_within_100_ms():
    import time

    # A batch of random pairs on one thread, timed whole, then given a quarter of that time.
    n = 500_000
    x_t0, x_t1 = random_batch(n)
    started = time.perf_counter()
    full = topoccd.point_triangle_ccd(x_t0, x_t1, threads=1)
    whole = time.perf_counter() - started
    timeout = whole / 4
    assert timeout > 0.01, f"the batch took {whole:.3f} s: too short to tell"
    started = time.perf_counter()
    with pytest.raises(TimeoutError, match=r"point_triangle_ccd\(\) did not finish within timeout=.*tested \d+ of 500000"):
        topoccd.point_triangle_ccd(x_t0, x_t1, threads=1, timeout=timeout)
    late = time.perf_counter() - started - timeout
    assert late < 0.1, f"stopped {late:.3f} s after the timeout"
    assert full[0].any()


CHILD_BATCH = """
import sys, time
import numpy as np, topoccd
rng = np.random.default_rng(5)
x_t0 = rng.normal(size=(2_000_000, 4, 3))
x_t1 = x_t0 + rng.normal(scale=0.5, size=x_t0.shape)
print("testing", flush=True)
try:
    for _ in range(1000):  # minutes of work
        topoccd.edge_edge_ccd(x_t0, x_t1, threads=1)
except KeyboardInterrupt:
    print("interrupted", time.monotonic(), flush=True)
    sys.exit(130)
print("finished", flush=True)
"""


def test_ctrl_c_stops_a_batch(tmp_path):
    import signal
    import subprocess
    import sys
    import time

    script = tmp_path / "child.py"
    script.write_text(CHILD_BATCH)
    child = subprocess.Popen(
        [sys.executable, str(script)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=sigint_default,
    )
    try:
        assert child.stdout.readline().strip() == "testing"
        time.sleep(1.0)
        assert child.poll() is None, "the batch ended by itself"
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=30)
    finally:
        if child.poll() is None:
            child.kill()
    assert child.returncode == 130, err
    stopped = float(out.splitlines()[0].split()[1])
    # Chunks of about 20 ms: generous on a shared machine.
    assert stopped - sent < 1.0, stopped - sent
