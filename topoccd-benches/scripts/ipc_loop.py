#!/usr/bin/env python3
"""Issue 42's measurements: topoccd's proximity query beside the IPC toolkit's (ipctk 1.6.1).

Run it in a venv outside the repository that has ipctk 1.6.1, numpy and this build of topoccd
(`maturin develop --release` from topoccd-py with that venv active), as
../shared/peers/README.md says:

  python3 -m venv /work/venvs/ipctk
  /work/venvs/ipctk/bin/pip install ipctk==1.6.1 numpy maturin
  (cd topoccd-py && VIRTUAL_ENV=/work/venvs/ipctk PATH=/work/venvs/ipctk/bin:$PATH \\
      maturin develop --release)
  /work/venvs/ipctk/bin/python topoccd-benches/scripts/ipc_loop.py --reps 3

Inputs: the shared real steps cloth-funnel 227->228 and cloth-ball 92->93 ($TOPOCCD_DATA, else
../shared/data beside the repository, or --data), and a generated codimensional scene (rods
and particles over a sheet, seeded). dhat = 1e-3 x the bounding-box diagonal of the first
frame. Both tools run on one thread (`ipctk.set_num_threads(1)`, topoccd `threads=1`).

(a) Conformance at the primitive-pair level, at the first frame: ipctk's `Candidates` built
    with inflation dhat/2, kept where the squared distance is below dhat^2, against topoccd's
    pairs (vf and ee; free points' ve and vv for the codimensional scene). Every difference is
    listed with its distance; a difference is allowed only within 1e-9 dhat of the threshold
    (the script exits with status 1 otherwise).
Times are wall time, or with --clock cpu the process's CPU time (on a machine shared with
other work, where wall time measures the load as much as the tools).
(b) Speed, alternating the tools rep by rep: topoccd's proximity (a fresh Ccd: build; the same
    Ccd again: refit) against `NormalCollisions.build(mesh, x, dhat)`. As a lower bound of any
    method that enumerates pairs, ipctk's `Candidates.build` alone is timed too.
(c) The inner loop of a solver: from x = x0 of the step towards x1, five iterations of
    proximity at x, the collision-free step size alpha from x to x1, x <- x + alpha (x1 - x);
    per phase and in all, with the ratio ipctk / topoccd. ipctk's step size uses its LBVH
    broad phase and Tight-Inclusion CCD (tolerance 1e-6), as ipctk_step.py does; topoccd's
    `collision_free_stepsize` its defaults; both with conservative rescaling 0.8.
(e) Issue 49's loop: the inner loop of (c) with the contact potentials, written once against
    ipctk's Python API and run on ipctk and on topoccd.ipc (the module is the only
    difference): per iteration NormalCollisions.build, the barrier's energy, gradient and
    PSD-projected Hessian, the friction potential's (tangential collisions lagged at x0,
    mu_s = 0.5, mu_k = 0.3, on x - x0), and compute_collision_free_stepsize with its defaults;
    CPU time (time.process_time), one thread, the two alternating rep by rep; prints the
    ratio ipctk / topoccd.ipc, the phases, and the energies of both (they must agree).
(d) topoccd's inner loop in detail: per iteration, proximity as Python times it and as the
    library reports it (the difference: converting the input and the output), the step size,
    and the fixed cost of a call on a one-triangle mesh.
"""

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

try:
    import ipctk
except ImportError:  # pragma: no cover
    sys.exit("ipctk is not installed in this Python (see the docstring)")
import topoccd

sys.dont_write_bytecode = True

STEPS = {
    "cloth-funnel": ("cloth-funnel/frames/227.ply", "cloth-funnel/frames/228.ply"),
    "cloth-ball": ("cloth-ball/frames/cloth_ball92.ply", "cloth-ball/frames/cloth_ball93.ply"),
}


def data_dir(arg):
    if arg:
        return Path(arg)
    if os.environ.get("TOPOCCD_DATA"):
        return Path(os.environ["TOPOCCD_DATA"])
    repo = Path(__file__).resolve().parents[2]
    # ../shared/data beside the repository (or beside the folder of worktrees).
    for base in (repo.parent, repo.parent.parent):
        if (base / "shared" / "data").is_dir():
            return base / "shared" / "data"
    sys.exit("no shared data: give --data or $TOPOCCD_DATA")


def codim_scene(seed=1, n=40, rods=60, rod_len=20, particles=600):
    """A sheet (n x n) with rods (polylines) and particles just above it, and a step that
    pushes everything down by a little more than the gap: x0, x1, triangles, free edges."""
    rng = np.random.default_rng(seed)
    h = 1.0 / (n - 1)
    g = np.stack(np.meshgrid(np.arange(n) * h, np.arange(n) * h, indexing="ij"), -1).reshape(-1, 2)
    sheet = np.column_stack([g, 0.002 * np.sin(7 * g[:, 0]) * np.cos(5 * g[:, 1])])
    tris = []
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1
            tris += [[a, b, c], [a, c, d]]
    pts = [sheet]
    edges = []
    base = len(sheet)
    for _ in range(rods):
        start = rng.uniform(0.1, 0.9, 2)
        direction = rng.normal(size=2)
        direction /= np.linalg.norm(direction)
        s = np.arange(rod_len) * (0.6 / rod_len)
        xy = start + np.outer(s, direction) + 0.01 * rng.normal(size=(rod_len, 2))
        z = 0.004 + 0.003 * rng.uniform(size=rod_len)
        pts.append(np.column_stack([xy, z]))
        edges += [[base + k, base + k + 1] for k in range(rod_len - 1)]
        base += rod_len
    p = np.column_stack([rng.uniform(0.05, 0.95, (particles, 2)), rng.uniform(0.002, 0.01, particles)])
    pts.append(p)
    x0 = np.vstack(pts)
    x1 = x0.copy()
    x1[len(sheet):, 2] -= 0.012
    return x0, x1, np.array(tris, dtype=np.int64), np.array(edges, dtype=np.int64)


def load(name, data):
    if name == "codim":
        return codim_scene()
    t0, t1 = STEPS[name]
    x0, tris = topoccd.read_mesh(str(data / "scenes" / t0))
    x1, _ = topoccd.read_mesh(str(data / "scenes" / t1))
    return x0, x1, tris, np.zeros((0, 2), dtype=np.int64)


def ipc_mesh(x, tris, free_edges):
    faces = np.asfortranarray(tris.astype(np.int32))
    edges = ipctk.edges(faces) if len(tris) else np.zeros((0, 2), dtype=np.int32)
    if len(free_edges):
        edges = np.vstack([edges, free_edges.astype(np.int32)])
    return ipctk.CollisionMesh(np.asfortranarray(x), np.asfortranarray(edges), faces)


def ipc_pairs(mesh, x, dhat):
    """ipctk's primitive pairs within dhat: {kind: {key: squared distance}}."""
    cand = ipctk.Candidates()
    cand.build(mesh, x, dhat / 2)
    E, F = mesh.edges, mesh.faces
    out = {"vf": {}, "ee": {}, "ve": {}, "vv": {}}
    for c in cand.fv_candidates:
        d2 = c.compute_distance(x, E, F)
        out["vf"][(c.vertex_id, c.face_id)] = d2
    for c in cand.ee_candidates:
        a = tuple(sorted(E[c.edge0_id]))
        b = tuple(sorted(E[c.edge1_id]))
        a, b = min(a, b), max(a, b)
        out["ee"][a + b] = c.compute_distance(x, E, F)
    for c in cand.ev_candidates:
        e = tuple(sorted(E[c.edge_id]))
        out["ve"][(c.vertex_id,) + e] = c.compute_distance(x, E, F)
    for c in cand.vv_candidates:
        a, b = sorted((c.vertex0_id, c.vertex1_id))
        out["vv"][(a, b)] = c.compute_distance(x, E, F)
    return out


def ours_pairs(p):
    out = {}
    for kind in ("vf", "ee", "ve", "vv"):
        rows = getattr(p, kind)
        dist = getattr(p, kind + "_distance")
        out[kind] = {tuple(int(v) for v in r): float(d) for r, d in zip(rows, dist)}
    return out


def conformance(name, x, tris, free_edges, dhat, mesh):
    theirs = ipc_pairs(mesh, np.asfortranarray(x), dhat)
    ours = ours_pairs(topoccd.proximity(x, tris, dhat, edges=free_edges, threads=1))
    ok = True
    free_points = None
    print(f"\n(a) conformance, {name}: dhat = {dhat:.6g}")
    for kind in ("vf", "ee", "ve", "vv"):
        t = {k: d2 for k, d2 in theirs[kind].items() if d2 < dhat * dhat}
        if kind in ("ve", "vv"):
            # Ours: free points only (a mesh vertex's point-edge pairs are its edges' and
            # faces' pairs already). Keep ipctk's pairs whose vertices are free points.
            if free_points is None:
                used = set(np.asarray(tris).ravel().tolist()) | set(np.asarray(free_edges).ravel().tolist())
                free_points = set(range(len(x))) - used
            t = {k: d2 for k, d2 in t.items() if k[0] in free_points and (kind == "ve" or k[1] in free_points)}
        o = ours[kind]
        only_ipc = sorted(set(t) - set(o))
        only_ours = sorted(set(o) - set(t))
        print(f"  {kind}: ipctk {len(t)}, topoccd {len(o)}, only ipctk {len(only_ipc)}, only topoccd {len(only_ours)}")
        for k in only_ipc + only_ours:
            d = np.sqrt(t[k]) if k in t else o[k]
            rel = (d - dhat) / dhat
            allowed = abs(rel) <= 1e-9
            ok &= allowed
            print(f"    {'ipctk' if k in t else 'topoccd'} only {k}: distance = dhat (1 {rel:+.3e}) {'(allowed)' if allowed else 'NOT ALLOWED'}")
        # Distances of the common pairs agree.
        common = set(t) & set(o)
        if common:
            worst = max(abs(np.sqrt(t[k]) - o[k]) for k in common) / dhat
            print(f"    largest |distance difference| on common pairs: {worst:.3e} dhat")
    return ok


def timed(f):
    """Runs f: (seconds, out), seconds as --clock says (wall or this process's CPU time)."""
    clock = time.process_time if CLOCK == "cpu" else time.perf_counter
    t = clock()
    out = f()
    return clock() - t, out


#: "wall" (time.perf_counter) or "cpu" (time.process_time: the CPU time of all the process's
#: threads, for a machine shared with other work; both tools run on one thread).
CLOCK = "wall"


def speed(name, x, tris, free_edges, dhat, mesh, reps):
    xf = np.asfortranarray(x)
    ipc_s, cand_s, fresh_s, kept_s, refit_s = [], [], [], [], []
    # A cap never takes the pairs a kept Ccd keeps across iterations: the refit and traversal.
    no_reuse = 2**62
    kept = topoccd.Ccd()
    kept.proximity(x, tris, dhat, edges=free_edges, threads=1)
    counts = None
    for _ in range(reps):
        s, c = timed(lambda: _build(mesh, xf, dhat))
        ipc_s.append(s)
        s, _ = timed(lambda: ipctk.Candidates().build(mesh, xf, dhat / 2))
        cand_s.append(s)
        s, p = timed(lambda: topoccd.Ccd().proximity(x, tris, dhat, edges=free_edges, threads=1))
        fresh_s.append(s)
        s, q = timed(lambda: kept.proximity(x, tris, dhat, edges=free_edges, threads=1))
        kept_s.append(s)
        s, _ = timed(lambda: kept.proximity(x, tris, dhat, edges=free_edges, threads=1, max_contacts=no_reuse))
        refit_s.append(s)
        counts = (len(c), len(p), q.refitted, q.reused)
    m = statistics.median
    print(f"\n(b) speed, {name}, one thread, median of {reps}:")
    print(f"  ipctk NormalCollisions.build: {m(ipc_s) * 1e3:9.2f} ms ({counts[0]} collisions)")
    print(f"  ipctk Candidates.build only:  {m(cand_s) * 1e3:9.2f} ms (lower bound of pair enumeration)")
    print(f"  topoccd proximity, fresh Ccd: {m(fresh_s) * 1e3:9.2f} ms ({counts[1]} pairs)  ratio {m(ipc_s) / m(fresh_s):.1f}x")
    print(f"  topoccd proximity, kept Ccd, refit and traversal: {m(refit_s) * 1e3:9.2f} ms  ratio {m(ipc_s) / m(refit_s):.1f}x")
    print(f"  topoccd proximity, kept Ccd, same x again: {m(kept_s) * 1e3:9.2f} ms (reused its kept pairs: {counts[3]})  ratio {m(ipc_s) / m(kept_s):.1f}x")
    return m(ipc_s), m(fresh_s), m(kept_s)


def _build(mesh, x, dhat):
    c = ipctk.NormalCollisions()
    c.build(mesh, x, dhat)
    return c


def loop_ipctk(mesh, x0, x1, dhat, iters):
    x = np.asfortranarray(x0.copy())
    x1f = np.asfortranarray(x1)
    ccd = ipctk.TightInclusionCCD(tolerance=1e-6, max_iterations=10_000_000)
    prox = step = 0.0
    alphas = []
    for _ in range(iters):
        s, _ = timed(lambda: _build(mesh, x, dhat))
        prox += s
        s, alpha = timed(lambda: ipctk.compute_collision_free_stepsize(
            mesh, x, x1f, broad_phase=ipctk.LBVH(), narrow_phase_ccd=ccd))
        step += s
        alphas.append(alpha)
        x = np.asfortranarray(x + alpha * (x1f - x))
    return prox, step, alphas


def loop_topoccd(x0, x1, tris, free_edges, dhat, iters):
    x = x0.copy()
    ccd = topoccd.Ccd()
    prox = step = 0.0
    alphas = []
    for _ in range(iters):
        s, _ = timed(lambda: ccd.proximity(x, tris, dhat, edges=free_edges, threads=1))
        prox += s
        s, alpha = timed(lambda: topoccd.collision_free_stepsize(
            x, x1, tris, edges=free_edges, ccd=ccd, threads=1, conservative_rescaling=0.8))
        step += s
        alphas.append(alpha)
        x = x + alpha * (x1 - x)
    return prox, step, alphas


def detail(name, x0, x1, tris, free_edges, dhat, iters, reps):
    """(d) Where topoccd's inner-loop time goes, per iteration (the loop of (c) run reps
    times with a fresh Ccd, median per iteration, --clock): proximity as Python sees it and
    as the library reports it (its own wall clock: the difference is the call's conversion of
    the input and the output), whether it refitted the tree or evaluated the candidates kept
    from the iteration before, the step size, and a call on a one-triangle mesh (the fixed
    cost of a call)."""
    tiny = (np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, 1e-4]]), np.array([[0, 1, 2]]))
    m = statistics.median
    rows = [[] for _ in range(iters)]
    for _ in range(reps):
        x = x0.copy()
        ccd = topoccd.Ccd()
        for it in range(iters):
            sp, p = timed(lambda: ccd.proximity(x, tris, dhat, edges=free_edges, threads=1))
            ss, alpha = timed(lambda: topoccd.collision_free_stepsize(
                x, x1, tris, edges=free_edges, ccd=ccd, threads=1, conservative_rescaling=0.8))
            rows[it].append((sp, p.seconds, len(p.vf) + len(p.ee), p.refitted, getattr(p, "reused", None), ss, alpha))
            x = x + alpha * (x1 - x)
    print(f"\n(d) inner loop of topoccd in detail, {name}: per iteration, median of {reps} (ms)")
    print(f"  {'iter':>4} {'prox (py)':>10} {'prox (lib)':>11} {'pairs':>7} {'refit':>6} {'reused':>7} {'step':>8} {'alpha':>9}")
    for it, r in enumerate(rows):
        print(f"  {it:>4} {m(q[0] for q in r) * 1e3:10.3f} {m(q[1] for q in r) * 1e3:11.3f} {r[0][2]:7d} "
              f"{str(r[0][3]):>6} {str(r[0][4]):>7} {m(q[5] for q in r) * 1e3:8.3f} {r[0][6]:9.6f}")
    small = topoccd.Ccd()
    calls = [timed(lambda: small.proximity(tiny[0], tiny[1], 1e-3, threads=1))[0] for _ in range(50)]
    steps = [timed(lambda: topoccd.collision_free_stepsize(
        tiny[0], tiny[0] + [0, 0, 0.1], tiny[1], ccd=small, threads=1))[0] for _ in range(50)]
    print(f"  fixed cost of a call (one triangle): proximity {m(calls) * 1e3:.3f} ms, step size {m(steps) * 1e3:.3f} ms")


def inner_loop(name, x0, x1, tris, free_edges, dhat, mesh, reps, iters):
    ipc, ours = [], []
    for _ in range(reps):
        ipc.append(loop_ipctk(mesh, x0, x1, dhat, iters))
        ours.append(loop_topoccd(x0, x1, tris, free_edges, dhat, iters))
    m = statistics.median
    ip, isz = m(r[0] for r in ipc), m(r[1] for r in ipc)
    op, osz = m(r[0] for r in ours), m(r[1] for r in ours)
    print(f"\n(c) inner loop, {name}: {iters} iterations, one thread, median of {reps} (seconds):")
    print(f"  {'phase':<12} {'ipctk':>10} {'topoccd':>10} {'ratio':>8}")
    print(f"  {'proximity':<12} {ip:10.4f} {op:10.4f} {ip / op:8.1f}")
    print(f"  {'step size':<12} {isz:10.4f} {osz:10.4f} {isz / osz:8.1f}")
    print(f"  {'total':<12} {ip + isz:10.4f} {op + osz:10.4f} {(ip + isz) / (op + osz):8.1f}")
    print(f"  step sizes ipctk   {[round(a, 6) for a in ipc[0][2]]}")
    print(f"  step sizes topoccd {[round(a, 6) for a in ours[0][2]]}")
    return (ip + isz) / (op + osz)


def potential_loop(mod, x0, x1, tris, free_edges, dhat, iters):
    """(e) The inner loop written against ipctk's API, for `mod` = ipctk or topoccd.ipc:
    CPU seconds per phase, the step sizes and the energies."""
    faces = tris.astype(np.int32)
    edges = mod.edges(faces) if len(tris) else np.zeros((0, 2), np.int32)
    if len(free_edges):
        edges = np.vstack([edges, free_edges.astype(np.int32)])
    # Each library's own layout (ipctk's Eigen matrices are column-major; topoccd's rows), so
    # neither pays a copy per call.
    layout = np.asfortranarray if mod is ipctk else np.ascontiguousarray
    x0f, x1f = layout(x0), layout(x1)
    clock = time.process_time
    t = {"build": 0.0, "barrier": 0.0, "friction": 0.0, "step": 0.0}
    t0 = clock()
    mesh = mod.CollisionMesh(x0f, layout(edges), layout(faces))
    B = mod.BarrierPotential(dhat, 1.0)
    C = mod.NormalCollisions()
    C.build(mesh, x0f, dhat)
    T = mod.TangentialCollisions()
    T.build(mesh, x0f, C, B, 0.5, 0.3)
    D = mod.FrictionPotential(1e-3 * dhat)
    t["build"] += clock() - t0
    psd = mod.PSDProjectionMethod.CLAMP
    x = layout(x0f.copy())
    alphas, energies = [], []
    for _ in range(iters):
        s = clock()
        C.build(mesh, x, dhat)
        t["build"] += clock() - s
        s = clock()
        e = B(C, mesh, x)
        g = B.gradient(C, mesh, x)
        H = B.hessian(C, mesh, x, project_hessian_to_psd=psd)
        t["barrier"] += clock() - s
        s = clock()
        u = layout(x - x0f)
        f = D(T, mesh, u)
        fg = D.gradient(T, mesh, u)
        fH = D.hessian(T, mesh, u, project_hessian_to_psd=psd)
        t["friction"] += clock() - s
        s = clock()
        alpha = mod.compute_collision_free_stepsize(mesh, x, x1f)
        t["step"] += clock() - s
        energies.append((e, float(np.linalg.norm(g)), H.nnz, f, float(np.linalg.norm(fg)), fH.nnz, len(C)))
        alphas.append(alpha)
        x = layout(x + alpha * (x1f - x))
    return t, alphas, energies


def potentials_loop(name, x0, x1, tris, free_edges, dhat, reps, iters):
    import topoccd.ipc as tipc

    runs = {ipctk: [], tipc: []}
    for _ in range(reps):
        for mod in (ipctk, tipc):
            runs[mod].append(potential_loop(mod, x0, x1, tris, free_edges, dhat, iters))
    m = statistics.median
    print(f"\n(e) inner loop with the potentials, {name}: {iters} iterations, one thread, CPU seconds, "
          f"median of {reps}, alternating:")
    print(f"  {'phase':<10} {'ipctk':>10} {'topoccd.ipc':>12} {'ratio':>8}")
    totals = {}
    for phase in ("build", "barrier", "friction", "step"):
        a, b = m(r[0][phase] for r in runs[ipctk]), m(r[0][phase] for r in runs[tipc])
        print(f"  {phase:<10} {a:10.4f} {b:12.4f} {a / b if b else float('inf'):8.1f}")
    for mod in (ipctk, tipc):
        totals[mod] = m(sum(r[0].values()) for r in runs[mod])
    ratio = totals[ipctk] / totals[tipc]
    print(f"  {'total':<10} {totals[ipctk]:10.4f} {totals[tipc]:12.4f} {ratio:8.1f}")
    print(f"  step sizes ipctk       {[round(a, 6) for a in runs[ipctk][0][1]]}")
    print(f"  step sizes topoccd.ipc {[round(a, 6) for a in runs[tipc][0][1]]}")
    for it, (a, b) in enumerate(zip(runs[ipctk][0][2], runs[tipc][0][2])):
        rel = lambda p, q: abs(p - q) / abs(q) if q else abs(p)  # noqa: E731
        print(f"  iteration {it}: collisions {a[6]} / {b[6]}, barrier energy rel. diff {rel(b[0], a[0]):.1e}, "
              f"|grad| {rel(b[1], a[1]):.1e}; friction energy {rel(b[3], a[3]):.1e}, |grad| {rel(b[4], a[4]):.1e}")
    print(f"  ratio ipctk / topoccd.ipc: {ratio:.1f}x")
    return ratio


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", help="the shared data folder (default $TOPOCCD_DATA or ../shared/data)")
    ap.add_argument("--scenes", default="cloth-funnel,cloth-ball,codim")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--iters", type=int, default=5)
    ap.add_argument("--skip", default="", help="parts to skip: a, b, c, d, e (comma separated)")
    ap.add_argument("--clock", choices=["wall", "cpu"], default="wall",
                    help="wall time, or the process's CPU time (on a loaded machine)")
    args = ap.parse_args()
    global CLOCK
    CLOCK = args.clock
    print(f"clock: {CLOCK}")
    ipctk.set_num_threads(1)
    data = data_dir(args.data)
    skip = set(args.skip.split(","))
    ok = True
    for name in args.scenes.split(","):
        x0, x1, tris, free_edges = load(name, data)
        x0 = np.ascontiguousarray(x0, dtype=np.float64)
        x1 = np.ascontiguousarray(x1, dtype=np.float64)
        dhat = 1e-3 * float(np.linalg.norm(x0.max(0) - x0.min(0)))
        mesh = ipc_mesh(x0, tris, free_edges)
        print(f"\n== {name}: {len(x0)} vertices, {len(tris)} triangles, {len(free_edges)} free edges, dhat {dhat:.6g}")
        if "a" not in skip:
            ok &= conformance(name, x0, tris, free_edges, dhat, mesh)
        if "b" not in skip:
            speed(name, x0, tris, free_edges, dhat, mesh, args.reps)
        if "c" not in skip:
            inner_loop(name, x0, x1, tris, free_edges, dhat, mesh, args.reps, args.iters)
        if "d" not in skip:
            detail(name, x0, x1, tris, free_edges, dhat, args.iters, args.reps)
        if "e" not in skip:
            potentials_loop(name, x0, x1, tris, free_edges, dhat, args.reps, args.iters)
    if not ok:
        print("\nconformance: differences beyond 1e-9 dhat of the threshold (see above)")
        sys.exit(1)


if __name__ == "__main__":
    main()
