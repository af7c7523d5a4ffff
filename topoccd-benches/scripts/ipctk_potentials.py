#!/usr/bin/env python3
"""Conformance and speed of topoccd.ipc against the IPC toolkit 1.6.1, side by side in one run.

Usage:  pip install ipctk==1.6.1 numpy scipy ./topoccd-py
        python3 topoccd-benches/scripts/ipctk_potentials.py [--data ../shared/data] [--reps 5]

Scenes: cloth-funnel 227 and cloth-ball 92 (the shared data's first frames), a hair bundle
(free edges only) and particles over a floor (free points and triangles), both generated here
from a seed. For each scene, rest = the frame itself, then the frame shifted by a small seeded
random field; dhat = 1e-3 x the bounding-box diagonal; ipctk's defaults, then area weighting.

Prints, kind by kind, whether the collision sets are equal; the relative differences of the
barrier energy, gradient (norm of the difference over the norm) and Hessian, plain and
PSD-projected (Frobenius); the same for friction (mu = 0.5, the same lagged normal forces, a
seeded displacement); the minimum distance and both stiffness helpers; then the CPU time
(one thread, ``time.process_time``, min of --reps) of energy + gradient + PSD Hessian over the
collision set for each library, with the ratio.
"""

import os

# One thread for both libraries, before they start their pools.
os.environ.setdefault("RAYON_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import ipctk  # noqa: E402
import topoccd  # noqa: E402
import topoccd.ipc as tipc  # noqa: E402

ipctk.set_num_threads(1)


def hair(seed=1, strands=40, per=60):
    """Strands as polylines (free edges) twisting around each other, a few near-touching."""
    rng = np.random.default_rng(seed)
    x, E = [], []
    for s in range(strands):
        r, phase = 0.02 + 0.03 * rng.random(), 2 * np.pi * rng.random()
        t = np.linspace(0, 1, per)
        pts = np.column_stack([
            r * np.cos(phase + 6 * t) + 0.002 * rng.normal(size=per),
            r * np.sin(phase + 6 * t) + 0.002 * rng.normal(size=per),
            t,
        ])
        base = len(x) * 0 + s * per
        x.append(pts)
        E += [[base + i, base + i + 1] for i in range(per - 1)]
    return np.vstack(x), np.array(E, np.int32), np.zeros((0, 3), np.int32)


def particles(seed=2, n=3000, grid=30):
    """Free points in a slab over a triangulated floor, some within dhat of it and of each
    other."""
    rng = np.random.default_rng(seed)
    s = np.linspace(0, 1, grid)
    X, Y = np.meshgrid(s, s, indexing="ij")
    floor = np.column_stack([X.ravel(), Y.ravel(), 0.002 * rng.normal(size=grid * grid)])
    F = []
    for i in range(grid - 1):
        for j in range(grid - 1):
            a, b, c, d = i * grid + j, (i + 1) * grid + j, (i + 1) * grid + j + 1, i * grid + j + 1
            F += [[a, b, c], [a, c, d]]
    pts = np.column_stack([rng.random(n), rng.random(n), 0.003 + 0.02 * rng.random(n)])
    F = np.array(F, np.int32)
    return np.vstack([floor, pts]), ipctk.edges(F), F


def frame(data, name):
    folder = Path(data) / "scenes" / name / "frames"
    first = sorted(p for p in folder.iterdir() if p.suffix == ".ply")[0]
    x, F = topoccd.read_mesh(first)
    F = F.astype(np.int32)
    return x, ipctk.edges(F), F


def sets(C):
    return {
        # vertex-vertex and edge-edge pairs unordered (ipctk keeps its broad phase's order)
        "vv": sorted(tuple(sorted((c.vertex0_id, c.vertex1_id))) for c in C.vv_collisions),
        "ev": sorted((c.edge_id, c.vertex_id) for c in C.ev_collisions),
        "ee": sorted(tuple(sorted((c.edge0_id, c.edge1_id))) for c in C.ee_collisions),
        "fv": sorted((c.face_id, c.vertex_id) for c in C.fv_collisions),
    }


def rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    n = np.linalg.norm(b)
    return np.linalg.norm(a - b) / n if n > 0 else np.linalg.norm(a - b)


def fro(A, B):
    d = (A - B).tocoo().data
    n = np.sqrt((B.tocoo().data ** 2).sum())
    return np.sqrt((d**2).sum()) / n if n > 0 else np.sqrt((d**2).sum())


def evaluate(mod, rest, x, E, F, dhat, area, U, ge):
    mesh = mod.CollisionMesh(np.asfortranarray(rest) if mod is ipctk else rest, E, F)
    C = mod.NormalCollisions()
    C.use_area_weighting = area
    C.build(mesh, x, dhat)
    B = mod.BarrierPotential(dhat, 1.0)
    T = mod.TangentialCollisions()
    T.build(mesh, x, C, B, 0.5)
    D = mod.FrictionPotential(1e-3 * dhat)
    psd = mod.PSDProjectionMethod.CLAMP
    diag = float(np.linalg.norm(x.max(axis=0) - x.min(axis=0)))
    gb = B.gradient(C, mesh, x)
    mind = C.compute_minimum_distance(mesh, x)
    kappa, kmax = mod.initial_barrier_stiffness(diag, B.barrier, dhat, 1.0, ge, gb)
    return dict(
        mesh=mesh, C=C, B=B, sets=sets(C), e=B(C, mesh, x), g=gb, H=B.hessian(C, mesh, x),
        Hp=B.hessian(C, mesh, x, project_hessian_to_psd=psd), mind=mind, kappa=(kappa, kmax),
        update=(mod.update_barrier_stiffness(mind * 2, mind, kmax, kappa, diag, dhat_epsilon_scale=1.0),
                mod.update_barrier_stiffness(mind, mind * 2, kmax, kappa, diag, dhat_epsilon_scale=1.0)),
        De=D(T, mesh, U), Dg=D.gradient(T, mesh, U), DH=D.hessian(T, mesh, U),
        DHp=D.hessian(T, mesh, U, project_hessian_to_psd=psd), nT=len(T),
    )


#: An edge-edge type's name with the two edges swapped.
SWAPPED = {"EA0_EB1": "EA1_EB0", "EA1_EB0": "EA0_EB1", "EA_EB0": "EA0_EB", "EA0_EB": "EA_EB0",
           "EA_EB1": "EA1_EB", "EA1_EB": "EA_EB1"}


def merge_ipctk_ee(C):
    """Merges ipctk's edge-edge collisions by their features, in place. ipctk merges them by
    edge ids in its broad phase's order and type number, so the same features named in the
    other order (a collision and its improved-max-approximation correction) stay two entries
    whose barriers cancel but whose PSD projections, one collision at a time, do not.
    topoccd merges them; ipctk then evaluates the merged set."""
    keep = {}
    for c in C.ee_collisions:
        a, b, t = c.edge0_id, c.edge1_id, c.dtype.name
        if a > b:
            a, b, t = b, a, SWAPPED.get(t, t)
        if (a, b, t) in keep:
            keep[(a, b, t)].weight += c.weight
        else:
            keep[(a, b, t)] = c
    before = len(C.ee_collisions)
    C.ee_collisions = [c for c in keep.values() if c.weight != 0]
    return before - len(C.ee_collisions)


def weighted(C):
    """Each collision as (kind, ids, weight), sorted (vv and ee ids unordered)."""
    out = []
    for kind, items, key in (
        ("vv", C.vv_collisions, lambda c: tuple(sorted((c.vertex0_id, c.vertex1_id)))),
        ("ev", C.ev_collisions, lambda c: (c.edge_id, c.vertex_id)),
        ("ee", C.ee_collisions, lambda c: tuple(sorted((c.edge0_id, c.edge1_id)))),
        ("fv", C.fv_collisions, lambda c: (c.face_id, c.vertex_id)),
    ):
        out += [(kind, key(c), c.weight) for c in items]
    return sorted(out)


def improved_max_approx(makers):
    """Conformance of the IMPROVED_MAX_APPROX collision set (area weighting off and on, as
    ipctk warns without it): the same collisions with the same weights, negative corrections
    included, and the barrier and friction figures (friction with mu_s = 0.5, mu_k = 0.3)."""
    print("\n## IMPROVED_MAX_APPROX collision set")
    worst = {}
    for name, make in makers.items():
        x, E, F = make()
        diag = float(np.linalg.norm(x.max(axis=0) - x.min(axis=0)))
        dhat = 1e-3 * diag
        U = np.random.default_rng(11).normal(scale=1e-2 * dhat, size=x.shape)
        for rest_name, rest in (("frame", x), ("shifted", x + np.random.default_rng(3).normal(scale=0.1 * dhat, size=x.shape))):
            for area in (False, True):
                r = {}
                for mod in (tipc, ipctk):
                    mesh = mod.CollisionMesh(np.asfortranarray(rest) if mod is ipctk else rest, E, F)
                    C = mod.NormalCollisions()
                    C.use_area_weighting = area
                    C.collision_set_type = mod.NormalCollisions.CollisionSetType.IMPROVED_MAX_APPROX
                    C.build(mesh, x, dhat)
                    merged = merge_ipctk_ee(C) if mod is ipctk else 0
                    B = mod.BarrierPotential(dhat, 1.0)
                    T = mod.TangentialCollisions()
                    T.build(mesh, x, C, B, 0.5, 0.3)
                    D = mod.FrictionPotential(1e-3 * dhat)
                    psd = mod.PSDProjectionMethod.CLAMP
                    r[mod] = dict(w=weighted(C), merged=merged, e=B(C, mesh, x), g=B.gradient(C, mesh, x), H=B.hessian(C, mesh, x),
                                  Hp=B.hessian(C, mesh, x, project_hessian_to_psd=psd), De=D(T, mesh, U),
                                  Dg=D.gradient(T, mesh, U), DH=D.hessian(T, mesh, U, project_hessian_to_psd=psd))
                a, b = r[tipc], r[ipctk]
                same = [c[:2] for c in a["w"]] == [c[:2] for c in b["w"]]
                negative = sum(c[2] < 0 for c in b["w"])
                figures = {
                    "weights": (max(abs(p[2] - q[2]) / max(abs(q[2]), 1e-300) for p, q in zip(a["w"], b["w"]))
                                if same and b["w"] else float(not same)),
                    "energy": abs(a["e"] - b["e"]) / abs(b["e"]) if b["e"] else abs(a["e"]),
                    "gradient": rel(a["g"], b["g"]),
                    "hessian": fro(a["H"], b["H"]),
                    "hessian_psd": fro(a["Hp"], b["Hp"]),
                    "friction_energy": abs(a["De"] - b["De"]) / abs(b["De"]) if b["De"] else abs(a["De"]),
                    "friction_gradient": rel(a["Dg"], b["Dg"]),
                    "friction_hessian_psd": fro(a["DH"], b["DH"]),
                }
                for k, v in figures.items():
                    worst[k] = max(worst.get(k, 0.0), v)
                print(f"- {name} rest={rest_name} area_weighting={area}: sets equal {same} "
                      f"({len(b['w'])} collisions, {negative} negative; {b['merged']} of ipctk's edge-edge "
                      f"entries merged into others by their features)")
                print("  " + ", ".join(f"{k} {v:.1e}" for k, v in figures.items()))
    print("- worst: " + ", ".join(f"{k} {v:.2e}" for k, v in worst.items()))


def cpu_time(f, reps):
    best = np.inf
    for _ in range(reps):
        t = time.process_time()
        f()
        best = min(best, time.process_time() - t)
    return best


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=str(Path(__file__).resolve().parents[2] / ".." / "shared" / "data"))
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--scenes", default="cloth-funnel,cloth-ball,hair,particles")
    ap.add_argument("--improved-only", action="store_true", help="only the IMPROVED_MAX_APPROX rows")
    args = ap.parse_args()
    makers = {
        "cloth-funnel": lambda: frame(args.data, "cloth-funnel"),
        "cloth-ball": lambda: frame(args.data, "cloth-ball"),
        "hair": hair,
        "particles": particles,
    }
    if args.improved_only:
        return improved_max_approx({k: makers[k] for k in args.scenes.split(",")})
    worst = {}
    speed = []
    for name in args.scenes.split(","):
        x, E, F = makers[name]()
        diag = float(np.linalg.norm(x.max(axis=0) - x.min(axis=0)))
        dhat = 1e-3 * diag
        rng = np.random.default_rng(11)
        U = rng.normal(scale=1e-2 * dhat, size=x.shape)
        ge = rng.normal(size=x.size)
        print(f"\n## {name}: {len(x)} vertices, {len(E)} edges, {len(F)} faces, dhat = {dhat:.4g}")
        for rest_name, rest in (("frame", x), ("shifted", x + np.random.default_rng(3).normal(scale=0.1 * dhat, size=x.shape))):
            for area in (False, True):
                a = evaluate(tipc, rest, x, E, F, dhat, area, U, ge)
                b = evaluate(ipctk, rest, x, E, F, dhat, area, U, ge)
                same = {k: a["sets"][k] == b["sets"][k] for k in ("vv", "ev", "ee", "fv")}
                counts = " ".join(f"{k}={len(b['sets'][k])}{'' if same[k] else '(DIFFER: ours ' + str(len(a['sets'][k])) + ')'}" for k in same)
                figures = {
                    "energy": abs(a["e"] - b["e"]) / abs(b["e"]) if b["e"] else abs(a["e"]),
                    "gradient": rel(a["g"], b["g"]),
                    "hessian": fro(a["H"], b["H"]),
                    "hessian_psd": fro(a["Hp"], b["Hp"]),
                    "friction_energy": abs(a["De"] - b["De"]) / abs(b["De"]) if b["De"] else abs(a["De"]),
                    "friction_gradient": rel(a["Dg"], b["Dg"]),
                    "friction_hessian": fro(a["DH"], b["DH"]),
                    "friction_hessian_psd": fro(a["DHp"], b["DHp"]),
                    "min_distance": abs(a["mind"] - b["mind"]) / b["mind"] if np.isfinite(b["mind"]) and b["mind"] else float(a["mind"] != b["mind"]),
                    "initial_stiffness": max(abs(p - q) / abs(q) for p, q in zip(a["kappa"], b["kappa"])),
                    "update_stiffness": max(abs(p - q) / abs(q) for p, q in zip(a["update"], b["update"])),
                }
                for k, v in figures.items():
                    worst[k] = max(worst.get(k, 0.0), v)
                print(f"- rest={rest_name} area_weighting={area}: sets equal {all(same.values())} ({counts})")
                print("  " + ", ".join(f"{k} {v:.1e}" for k, v in figures.items()))
                if rest_name == "frame" and not area:
                    psd_ours, psd_theirs = tipc.PSDProjectionMethod.CLAMP, ipctk.PSDProjectionMethod.CLAMP

                    def work(r, psd):
                        def run():
                            r["B"](r["C"], r["mesh"], x)
                            r["B"].gradient(r["C"], r["mesh"], x)
                            r["B"].hessian(r["C"], r["mesh"], x, project_hessian_to_psd=psd)
                        return run

                    t_ours = cpu_time(work(a, psd_ours), args.reps)
                    t_theirs = cpu_time(work(b, psd_theirs), args.reps)
                    speed.append((name, len(b["C"]), t_theirs, t_ours))
    print("\n## Worst relative difference over all cases")
    for k, v in worst.items():
        print(f"- {k}: {v:.2e}")
    print("\n## energy + gradient + PSD Hessian, one thread, CPU seconds (min of %d)" % args.reps)
    print("| scene | collisions | ipctk 1.6.1 | topoccd.ipc | ratio |")
    print("|---|---:|---:|---:|---:|")
    for name, n, t_theirs, t_ours in speed:
        print(f"| {name} | {n} | {t_theirs * 1e3:.2f} ms | {t_ours * 1e3:.2f} ms | {t_theirs / t_ours:.1f}x |")
    improved_max_approx({k: makers[k] for k in args.scenes.split(",")})


if __name__ == "__main__":
    main()
