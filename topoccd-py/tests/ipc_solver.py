"""A small implicit-Euler Newton solver written against the IPC toolkit's Python API: a
mass-spring cloth falling onto a fixed bumpy floor, with the barrier, lagged friction, a sparse
solve and a line search bounded by ``compute_collision_free_stepsize``.

``simulate(ipctk)`` runs it on whichever module is passed: the IPC toolkit itself
(``import ipctk``) or topoccd's mirror of it (``import topoccd.ipc as ipctk``). Only the module
object differs, so the two trajectories can be compared.
"""

import numpy as np
import scipy.sparse
import scipy.sparse.linalg


def scene(n: int = 6):
    """A cloth of ``n x n`` vertices 2 mm above a fixed floor of 3 x 3 quads with a raised
    centre, so that vertex-face, edge-vertex and edge-edge collisions all occur."""
    s = np.linspace(-0.5, 0.5, n)
    X, Y = np.meshgrid(s, s, indexing="ij")
    cloth = np.column_stack([X.ravel(), Y.ravel(), np.full(n * n, 0.032)]) + [0.013, 0.007, 0]
    g = np.linspace(-0.8, 0.8, 4)
    GX, GY = np.meshgrid(g, g, indexing="ij")
    floor = np.column_stack([GX.ravel(), GY.ravel(), np.zeros(16)])
    floor[[5, 6, 9, 10], 2] = 0.03  # the raised centre
    def grid(m, off):
        f = []
        for i in range(m - 1):
            for j in range(m - 1):
                a, b, c, d = off + i * m + j, off + (i + 1) * m + j, off + (i + 1) * m + j + 1, off + i * m + j + 1
                f += [[a, b, c], [a, c, d]]
        return f
    F = np.array(grid(n, 0) + grid(4, n * n), np.int32)
    x = np.vstack([cloth, floor])
    fixed = np.arange(n * n, n * n + 16)
    return x, F, fixed


def simulate(ipctk, iterations: int = 10, dt: float = 0.005, mu: float = 0.5, speed: float = 0.05):
    """Newton iterations of implicit Euler steps (5 per step); returns the positions after
    each iteration."""
    x, F, fixed = scene()
    E = ipctk.edges(F)
    mesh = ipctk.CollisionMesh(x, E, F)
    n = len(x)
    free = np.ones(3 * n, bool)
    free[(3 * fixed[:, None] + np.arange(3)).ravel()] = False
    rest_len = np.linalg.norm(x[E[:, 1]] - x[E[:, 0]], axis=1)
    cloth_edge = ~np.isin(E, fixed).any(axis=1)
    ks, mass, g = 2e2, 1e-2, np.array([0.0, 0.0, -9.81])
    M = mass * np.ones(3 * n)
    diag = float(np.linalg.norm(x.max(axis=0) - x.min(axis=0)))
    dhat = 1e-2
    eps_v = 1e-3

    def elastic(y):
        d = y[E[:, 1]] - y[E[:, 0]]
        L = np.linalg.norm(d, axis=1)
        s = np.where(cloth_edge, ks, 0.0)
        e = 0.5 * np.sum(s * (L - rest_len) ** 2)
        f = (s * (L - rest_len) / L)[:, None] * d
        grad = np.zeros((n, 3))
        np.add.at(grad, E[:, 1], f)
        np.add.at(grad, E[:, 0], -f)
        u = d / L[:, None]
        r = np.clip(1 - rest_len / L, 0, None)  # PSD: drop the negative transverse part
        K = s[:, None, None] * (u[:, :, None] * u[:, None, :] + r[:, None, None] * (np.eye(3) - u[:, :, None] * u[:, None, :]))
        rows, cols, vals = [], [], []
        for a, b, sign in ((0, 0, 1), (1, 1, 1), (0, 1, -1), (1, 0, -1)):
            for i in range(3):
                for j in range(3):
                    rows.append(3 * E[:, a] + i)
                    cols.append(3 * E[:, b] + j)
                    vals.append(sign * K[:, i, j])
        H = scipy.sparse.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(3 * n, 3 * n))
        return e, grad.ravel(), H

    v = np.zeros((n, 3))
    v[~np.isin(np.arange(n), fixed)] = [0.0, 0.0, -speed]
    C = ipctk.NormalCollisions()
    C.build(mesh, x, dhat)
    B1 = ipctk.BarrierPotential(dhat, 1.0)
    _, ge, _ = elastic(x)
    kappa, kappa_max = ipctk.initial_barrier_stiffness(diag, B1.barrier, dhat, mass, ge, B1.gradient(C, mesh, x))
    prev_min = C.compute_minimum_distance(mesh, x)
    traj = []
    x_n = x.copy()
    while len(traj) < iterations:
        x_tilde = x_n + dt * v + dt * dt * np.where(free.reshape(n, 3), g, 0.0)
        B = ipctk.BarrierPotential(dhat, kappa)
        C.build(mesh, x_n, dhat)
        T = ipctk.TangentialCollisions()
        T.build(mesh, x_n, C, B, mu)
        D = ipctk.FrictionPotential(eps_v * dt)

        def total(y, C=C, B=B, T=T, D=D):
            e, _, _ = elastic(y)
            dx = (y - x_tilde).ravel()
            return 0.5 * dx @ (M * dx) + dt * dt * (e + B(C, mesh, y) + D(T, mesh, y - x_n))

        y = x_n.copy()
        for _ in range(5):
            C.build(mesh, y, dhat)
            e, ge, He = elastic(y)
            grad = M * (y - x_tilde).ravel() + dt * dt * (ge + B.gradient(C, mesh, y) + D.gradient(T, mesh, y - x_n))
            H = scipy.sparse.diags(M) + dt * dt * (
                He
                + B.hessian(C, mesh, y, project_hessian_to_psd=ipctk.PSDProjectionMethod.CLAMP)
                + D.hessian(T, mesh, y - x_n, project_hessian_to_psd=ipctk.PSDProjectionMethod.CLAMP)
            )
            H = H.tocsc()[free][:, free]
            p = np.zeros(3 * n)
            p[free] = scipy.sparse.linalg.spsolve(H.tocsc(), -grad[free])
            p = p.reshape(n, 3)
            alpha = min(1.0, ipctk.compute_collision_free_stepsize(mesh, y, y + p))
            e0 = total(y)
            while total(y + alpha * p) > e0 and alpha > 1e-10:
                alpha *= 0.5
            y = y + alpha * p
            C.build(mesh, y, dhat)
            min_d = C.compute_minimum_distance(mesh, y)
            kappa = ipctk.update_barrier_stiffness(prev_min, min_d, kappa_max, kappa, diag)
            prev_min = min_d
            traj.append(y.copy())
            if len(traj) == iterations:
                break
        v = (y - x_n) / dt
        x_n = y
    return traj, C


if __name__ == "__main__":
    import ipctk

    traj, C = simulate(ipctk)
    print(len(C), len(C.vv_collisions), len(C.ev_collisions), len(C.ee_collisions), len(C.fv_collisions))
    print(traj[-1][:36, 2].min())
