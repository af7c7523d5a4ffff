"""A 1,000-step sequence in one process: the resident memory stays flat. Small deforming
meshes (two rippled sheets passing through each other, with a cut every 50 steps), one
``Ccd`` kept across the steps as a simulator keeps it, and along the way every path that could
leak: fresh ``Ccd`` objects, ``max_contacts`` truncation, a timeout, errors, warnings,
geometry."""

import sys
import warnings

import numpy as np
import pytest
import topoccd
from scenes import crossing_sheets


def resident_bytes() -> int:
    """The process's resident set size now (Linux: /proc/self/statm)."""
    import os

    with open("/proc/self/statm") as f:
        pages = int(f.read().split()[1])
    return pages * os.sysconf("SC_PAGE_SIZE")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc/self/statm")
def test_a_thousand_steps_keep_memory_flat():
    x0, x1, tris = crossing_sheets(8)
    n = len(x0)
    ccd = topoccd.Ccd()
    rng = np.random.default_rng(38)
    samples = {}
    contacts = 0
    for step in range(1000):
        # The sheets breathe: the contacts change every step.
        phase = 0.02 * np.sin(0.1 * step)
        a = x0 + [0, 0, phase]
        b = x1 + rng.normal(0, 0.003, x1.shape)
        kind = step % 10
        if step % 50 == 49:
            # A cut: vertex n is split from vertex 0 and moves with it.
            b2 = np.vstack([b, b[0]])
            t2 = tris.copy()
            t2[0] = [n, t2[0][1], t2[0][2]] if t2[0][0] == 0 else t2[0]
            r = ccd.query(a, b2, t2, parents=[[n, 0]])
        elif kind == 1:
            r = topoccd.query(a, b, tris, mode="earliest")
        elif kind == 2:
            r = ccd.query(a, b, tris, max_contacts=3)
            assert r.truncated is None or len(r) == 3
        elif kind == 3:
            try:
                ccd.query(a, b, tris, timeout=1e-9)
            except TimeoutError:
                pass
            r = ccd.query(a, b, tris, geometry=True, threads=1 + step % 2)
        elif kind == 4:
            try:
                ccd.query(a, b[:-1], tris)
            except topoccd.InputError:
                pass
            with warnings.catch_warnings(record=True):
                warnings.simplefilter("always")
                # Coincident vertices: warned about.
                c = a.copy()
                c[1] = c[0]
                r = ccd.query(c, b, tris, method="brute")
        else:
            r = ccd.query(a, b, tris, method=("bvh", "cluster", "auto")[step % 3])
        contacts += len(r)
        if step + 1 in (200, 600, 1000):
            samples[step + 1] = resident_bytes()
    assert contacts > 1000, contacts
    grown = samples[1000] - samples[200]
    # Flat: what the 800 later steps added is noise (allocator slack), not a leak of the few
    # kilobytes each step allocates (800 steps x a few KB, or x the report's arrays, would be
    # tens of MB).
    assert grown < 8 << 20, {k: v >> 20 for k, v in samples.items()}
    assert samples[1000] - samples[600] < 4 << 20, {k: v >> 20 for k, v in samples.items()}
