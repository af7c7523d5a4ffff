"""Small steps built in numpy for the tests."""

import numpy as np

FIXED = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float64)
FALLING = np.array([[0.2, 0.2, 1], [0.3, 0.2, 1.5], [0.2, 0.3, 1.5]], dtype=np.float64)
TRIANGLES = np.array([[0, 1, 2], [3, 4, 5]])


def falling_triangle():
    """A triangle falls through a fixed one: vf (3, 0) at 0.5, (4, 0) and (5, 0) at 0.75."""
    x0 = np.vstack([FIXED, FALLING])
    x1 = np.vstack([FIXED, FALLING - [0, 0, 2]])
    return x0, x1, TRIANGLES.copy()


def sheet(n: int, z: float, shift=(0.0, 0.0)):
    """An n x n grid of squares, two triangles each, in the plane z, over [0, 1]^2 + shift."""
    u = np.linspace(0, 1, n + 1)
    xx, yy = np.meshgrid(u + shift[0], u + shift[1], indexing="ij")
    points = np.stack([xx.ravel(), yy.ravel(), np.full(xx.size, z)], axis=1)
    idx = np.arange((n + 1) * (n + 1)).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    tris = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(-1, 3)
    return points, tris


def crossing_sheets(n: int, seed: int = 1):
    """Two rippled sheets that pass through each other: many contacts."""
    rng = np.random.default_rng(seed)
    p, t = sheet(n, 0.1, (0.013, 0.007))
    q, s = sheet(n, -0.1)
    x0 = np.vstack([p, q])
    x1 = np.vstack([p - [0, 0, 0.2], q + [0, 0, 0.2]])
    x1[:, 2] += rng.normal(0, 0.01, len(x1))
    tris = np.vstack([t, s + len(p)])
    return x0, x1, tris
