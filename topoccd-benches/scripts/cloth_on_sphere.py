#!/usr/bin/env python3
"""A minimal cloth-on-sphere simulator in numpy that uses topoccd's earliest time of impact for
its line search; with ipctk installed, the same step's collision-free step size side by side.

Usage:  pip install ./topoccd-py            (and optionally: pip install ipctk)
        python3 topoccd-benches/scripts/cloth_on_sphere.py [--steps 80] [--cloth 40]

Each step:
 1. proposes new positions with position-based dynamics: gravity, a few Jacobi passes over the
    cloth's edge lengths, and the analytic sphere pushing vertices out to radius r + margin;
 2. asks topoccd for the earliest time of impact of the whole mesh (cloth and sphere) moving
    linearly from the current to the proposed positions: ``Ccd.query(..., mode="earliest")``;
 3. moves by the line-search fraction alpha = 1, or 0.8 * toi when a contact exists, so that no
    triangle ever passes through another (the cloth through itself, or a sphere vertex poking
    through a cloth triangle between its vertices);
 4. sets the velocities from the positions reached.

Columns: the step, alpha, the earliest toi and its pair (or -), the query's wall time; with
ipctk, its ``compute_collision_free_stepsize`` on the same two position arrays and its time.
The two numbers differ by design: topoccd returns the time of impact (never later than the
contact, at most its tolerance earlier), ipctk a step size it already considers safe
(Tight-Inclusion's conservative rescaling); both are 1 when nothing collides.
"""

import argparse
import time

import numpy as np

import topoccd

try:
    import ipctk
except ImportError:  # the comparison is optional
    ipctk = None


def grid(n: int, size: float, height: float):
    """An n x n cloth of squares (two triangles each), centred above the origin."""
    u = np.linspace(-size / 2, size / 2, n + 1)
    xx, yy = np.meshgrid(u, u, indexing="ij")
    points = np.stack([xx.ravel(), yy.ravel(), np.full(xx.size, height)], axis=1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    tris = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(-1, 3)
    return points, tris


def icosphere(level: int, radius: float):
    """A sphere of 20 * 4**level triangles, vertices on the radius."""
    t = (1 + 5**0.5) / 2
    v = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
         [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
         [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
         [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    faces = f
    for _ in range(level):
        cache, new = {}, []

        def mid(i, j):
            key = (min(i, j), max(i, j))
            if key not in cache:
                m = verts[i] + verts[j]
                verts.append(m / np.linalg.norm(m))
                cache[key] = len(verts) - 1
            return cache[key]

        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        faces = new
    return np.array(verts) * radius, np.array(faces)


def unique_edges(tris: np.ndarray) -> np.ndarray:
    e = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    return np.unique(np.sort(e, axis=1), axis=0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=80)
    ap.add_argument("--cloth", type=int, default=40, help="cloth resolution (squares per side)")
    ap.add_argument("--dt", type=float, default=0.01)
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--method", default="bvh", choices=["bvh", "cluster", "brute"])
    args = ap.parse_args()

    radius, margin = 0.5, 0.0
    cloth, cloth_tris = grid(args.cloth, 1.6, 0.62)
    sphere, sphere_tris = icosphere(2, radius)
    n_cloth = len(cloth)
    x = np.vstack([cloth, sphere])                      # (n, 3) float64, C order: no copy
    tris = np.vstack([cloth_tris, sphere_tris + n_cloth])
    edges = unique_edges(cloth_tris)
    rest = np.linalg.norm(cloth[edges[:, 0]] - cloth[edges[:, 1]], axis=1)
    v = np.zeros_like(x)
    gravity = np.array([0.0, 0.0, -9.81])

    ccd = topoccd.Ccd()                                 # buffers kept across steps
    ipc_mesh = None
    if ipctk is not None:
        ipc_mesh = ipctk.CollisionMesh(x, ipctk.edges(tris), tris)
    print(f"cloth {n_cloth} vertices, {len(cloth_tris)} triangles; sphere {len(sphere)} vertices, "
          f"{len(sphere_tris)} triangles; {'ipctk ' + ipctk.__version__ if ipctk else 'no ipctk'}")
    header = f"{'step':>4} {'toi':>9} {'earliest pair':>22} {'ours ms':>8}"
    if ipctk is not None:
        header += f" {'ipctk step':>10} {'ipctk ms':>8}"
    print(header + f" {'frozen':>6} {'alpha':>7}")

    totals = {"topoccd": 0.0, "ipctk": 0.0}
    for step in range(args.steps):
        # 1. Proposal: position-based dynamics on the cloth; the sphere does not move.
        p = x.copy()
        p[:n_cloth] += args.dt * v[:n_cloth] + args.dt**2 * gravity
        for _ in range(12):
            d = p[edges[:, 1]] - p[edges[:, 0]]
            length = np.linalg.norm(d, axis=1)
            corr = 0.5 * ((length - rest) / np.maximum(length, 1e-12))[:, None] * d
            delta = np.zeros_like(p)
            count = np.zeros(len(p))
            np.add.at(delta, edges[:, 0], corr)
            np.add.at(delta, edges[:, 1], -corr)
            np.add.at(count, edges.ravel(), 1)
            p[:n_cloth] += (delta / np.maximum(count, 1)[:, None])[:n_cloth] * 0.9
            r = np.linalg.norm(p[:n_cloth], axis=1)
            inside = r < radius + margin
            p[:n_cloth][inside] *= ((radius + margin) / r[inside])[:, None]

        # 2. The earliest time of impact of the linear motion x -> p (what a line search
        #    needs), and ipctk's collision-free step size on the same two arrays.
        started = time.perf_counter()
        first = ccd.query(x, p, tris, mode="earliest", method=args.method, threads=args.threads)
        ours = time.perf_counter() - started
        totals["topoccd"] += ours
        line = f"{step:4d} "
        if first.earliest is None:
            line += f"{'-':>9} {'-':>22}"
        else:
            kind, *ids, toi = first.earliest
            line += f"{toi:9.6f} {kind + ' ' + ','.join(map(str, ids)):>22}"
        line += f" {ours * 1e3:8.2f}"
        if ipc_mesh is not None:
            started = time.perf_counter()
            ipc_step = ipctk.compute_collision_free_stepsize(
                ipc_mesh, np.asfortranarray(x), np.asfortranarray(p))
            theirs = time.perf_counter() - started
            totals["ipctk"] += theirs
            line += f" {ipc_step:10.6f} {theirs * 1e3:8.2f}"

        # 3. Contact response, crude but enough to avoid locking: cloth vertices of every
        #    colliding pair (mode="all") keep their position this step and lose their velocity
        #    (inelastic, sticky); repeat while the frozen vertices make new contacts.
        frozen = np.zeros(n_cloth, dtype=bool)
        report = first
        if first.earliest is not None:
            for _ in range(4):
                report = ccd.query(x, p, tris, method=args.method, threads=args.threads)
                if len(report) == 0:
                    break
                ids = np.concatenate([report.vf[:, 0], tris[report.vf[:, 1]].ravel(), report.ee.ravel()])
                ids = ids[ids < n_cloth]
                p[ids], v[ids], frozen[ids] = x[ids], 0.0, True

        # 4. Line search: the whole step, or 0.8 of the way to the first remaining contact.
        alpha = 1.0 if report.earliest_toi is None else 0.8 * report.earliest_toi
        print(line + f" {int(frozen.sum()):6d} {alpha:7.4f}", flush=True)

        # 5. Move and update the velocities (slightly damped).
        new_x = x + alpha * (p - x)
        v = 0.995 * (new_x - x) / args.dt
        x = new_x

    r = np.linalg.norm(x[:n_cloth], axis=1)
    print(f"done: lowest cloth vertex z = {x[:n_cloth, 2].min():.3f}, "
          f"closest to the sphere centre {r.min():.4f} (radius {radius}); "
          f"query time topoccd {totals['topoccd']:.3f} s"
          + (f", ipctk {totals['ipctk']:.3f} s" if ipctk is not None else ""))


if __name__ == "__main__":
    main()
