#!/usr/bin/env python3
"""The IPC toolkit's earliest-contact query on whole steps, beside topoccd's, in one run.

Usage:  pip install ipctk numpy ./topoccd-py
        python3 topoccd-benches/scripts/ipctk_step.py [--threads 1,2] [--reps 3] STEP...

STEP is what `compare.py` takes: a real step (DIR with frames/, its first two frames), a
generated sequence (DIR with 0000.ply, its first step with 0001.parents), or T0.ply,T1.ply.

For each step and thread count, alternating the two libraries on every repetition, prints the
median wall seconds of
- ipctk: `compute_collision_free_stepsize` (LBVH broad phase, Tight-Inclusion CCD, tolerance
  1e-6), the IPC toolkit's whole-step query, which returns a step size rather than contacts;
- topoccd: `Ccd.query(..., mode="earliest")` (its default method), the earliest time of impact;
then a markdown table. Each library is given the thread count (`ipctk.set_num_threads`,
`threads=` of the query). A step that adds vertices (a cut) gives ipctk each new vertex's
parent's position at t=0, the start topoccd gives it; ipctk has no crack filter, so such a
step's step size may be 0 (the two sides of a fresh crack touch at t=0).
"""

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

import ipctk
import topoccd


def load(spec):
    """(name, x0, x1, triangles, parents) of one step."""
    if "," in spec:
        t0, t1 = (Path(p) for p in spec.split(",", 1))
        x0, _ = topoccd.read_mesh(t0)
        x1, tris = topoccd.read_mesh(t1)
        return f"{t0.stem}->{t1.stem}", x0, x1, tris, np.zeros((0, 2), np.int64)
    d = Path(spec)
    if (d / "frames").is_dir():
        frames = sorted(p for p in (d / "frames").iterdir() if p.suffix in (".ply", ".obj"))
        if len(frames) < 2:
            raise SystemExit(f"{d}: fewer than two frames")
        x0, _ = topoccd.read_mesh(frames[0])
        x1, tris = topoccd.read_mesh(frames[1])
        return d.name, x0, x1, tris, np.zeros((0, 2), np.int64)
    if (d / "0000.ply").is_file():
        x0, x1, tris, parents = topoccd.read_sequence(d)[0]
        return d.name, x0, x1, tris, parents
    raise SystemExit(f"{spec}: not a step (DIR/frames, a sequence DIR/0000.ply, or T0,T1)")


def full_start(x0, x1, parents):
    """x0 with a row for every vertex of x1: a new vertex starts at its parent's position."""
    if len(x0) == len(x1):
        return x0
    out = np.empty_like(x1)
    out[: len(x0)] = x0
    for child, parent in parents:
        out[child] = out[parent]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("steps", nargs="+")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--reps", type=int, default=3)
    args = ap.parse_args()
    threads = [int(t) for t in args.threads.split(",")]
    rows = []
    for spec in args.steps:
        name, x0, x1, tris, parents = load(spec)
        start = np.asfortranarray(full_start(x0, x1, parents))
        end = np.asfortranarray(x1)
        faces = np.asfortranarray(tris.astype(np.int32))
        mesh = ipctk.CollisionMesh(start, np.asfortranarray(ipctk.edges(faces)), faces)
        ccd = ipctk.TightInclusionCCD(tolerance=1e-6, max_iterations=10_000_000)
        for n in threads:
            ipctk.set_num_threads(n)
            ipc_s, ours_s = [], []
            for _ in range(args.reps):
                t = time.perf_counter()
                alpha = ipctk.compute_collision_free_stepsize(
                    mesh, start, end, broad_phase=ipctk.LBVH(), narrow_phase_ccd=ccd
                )
                ipc_s.append(time.perf_counter() - t)
                t = time.perf_counter()
                # A fresh Ccd each time, as a one-shot query (the CLI's case).
                query = topoccd.Ccd()
                report = query.query(x0, x1, tris, parents=parents, mode="earliest", threads=n)
                ours_s.append(time.perf_counter() - t)
            toi = report.earliest_toi
            row = (name, len(tris), n, statistics.median(ipc_s), alpha, statistics.median(ours_s), toi)
            rows.append(row)
            print(f"{name} {n}t: ipctk {row[3]:.3f} s (step size {alpha:.6g}), "
                  f"topoccd {row[5]:.3f} s (earliest toi {toi})", flush=True)
    print()
    print("| step | tris | thr | ipctk s | ipctk step size | topoccd earliest s | topoccd toi | ipctk / topoccd |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, m, n, ipc, alpha, ours, toi in rows:
        print(f"| {name} | {m:,} | {n} | {ipc:.3f} | {alpha:.6g} | {ours:.3f} | {toi} | {ipc / ours:.1f} |")


if __name__ == "__main__":
    main()
