#!/usr/bin/env python3
"""Issue 50's proximity figures: topoccd's query against ipctk 1.6.1's `NormalCollisions.build`
(its default LBVH broad phase), one thread, CPU time, min of N, the two alternating rep by rep
so that a loaded machine slows both alike.

Usage (a venv with ipctk 1.6.1 and numpy, outside the repository):

  cargo build --release -p topoccd-benches --bin prox_probe
  /work/ipctk-venv/bin/python topoccd-benches/scripts/proximity_vs_ipctk.py [--reps 5]
      [--data ../shared/data] [--probe target/release/prox_probe] [--method wide|triangles]

ipctk runs in this process (`ipctk.set_num_threads(1)`, `time.process_time`). topoccd runs in
`prox_probe` (one thread), which times its own queries by the process's CPU clock and prints
them; one repetition per call, alternating with ipctk's. Cases, per frame (cloth-funnel 227,
cloth-ball 92; dhat = 1e-3 x the bounding-box diagonal, as both tools take it):

- fresh: a new `Ccd` (build and query);
- kept, dhat move: a `Ccd` asked at the frame, then at positions moved by a seeded uniform
  amount in [-dhat, dhat] per coordinate (its kept pairs cannot be reused);
- kept, real move: the same after the move to the next frame (228, 93), and half way;
  the fresh query at the moved positions is printed beside it.

ipctk is timed at the frame's positions (its build keeps nothing across calls).
"""

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

try:
    import ipctk
except ImportError:  # pragma: no cover
    sys.exit("ipctk is not installed in this Python (see the docstring)")

FRAMES = {
    "cloth-funnel 227": ("cloth-funnel/frames/227.ply", "cloth-funnel/frames/228.ply"),
    "cloth-ball 92": ("cloth-ball/frames/cloth_ball92.ply", "cloth-ball/frames/cloth_ball93.ply"),
}


def read_ply(path):
    data = Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    head = data[:end].decode().splitlines()
    nv = nf = 0
    for line in head:
        if line.startswith("element vertex"):
            nv = int(line.split()[2])
        if line.startswith("element face"):
            nf = int(line.split()[2])
    e = "<" if "binary_little_endian" in head[1] else ">"
    t = "f8" if sum(line.startswith("property double") for line in head) == 3 else "f4"
    x = np.frombuffer(data, dtype=e + t, count=3 * nv, offset=end).reshape(nv, 3).astype(np.float64)
    rec = np.dtype([("n", "u1"), ("i", e + "i4", 3)])
    f = np.frombuffer(data, dtype=rec, count=nf, offset=end + 3 * int(t[1]) * nv)
    if not (f["n"] == 3).all():
        sys.exit(f"{path}: not a triangle mesh")
    return x, f["i"].astype(np.int32)


def ipctk_build(path):
    x, F = read_ply(path)
    dhat = 1e-3 * float(np.linalg.norm(x.max(0) - x.min(0)))
    F = np.asfortranarray(F)
    xf = np.asfortranarray(x)
    mesh = ipctk.CollisionMesh(xf, np.asfortranarray(ipctk.edges(F)), F)

    def once():
        t = time.process_time()
        c = ipctk.NormalCollisions()
        c.build(mesh, xf, dhat)
        return time.process_time() - t, len(c)

    return once


def probe(args, env, *rest):
    """Runs prox_probe with one repetition; returns its JSON lines and its last line."""
    out = subprocess.run([args.probe, *map(str, rest)], env=env, check=True,
                         capture_output=True, text=True).stdout.splitlines()
    return [json.loads(line) for line in out if line.startswith("{")], out[-1]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--data", default=os.environ.get("TOPOCCD_DATA", "../shared/data"))
    ap.add_argument("--probe", default="target/release/prox_probe")
    ap.add_argument("--method", default="wide", choices=["wide", "triangles"])
    ap.add_argument("--frames", default=",".join(FRAMES))
    args = ap.parse_args()
    ipctk.set_num_threads(1)
    env = dict(os.environ, PROX_METHOD=args.method)
    scenes = Path(args.data) / "scenes"
    for name in args.frames.split(","):
        a, b = (str(scenes / p) for p in FRAMES[name])
        ipc = ipctk_build(a)
        best = {}

        def keep(key, t):
            best[key] = min(best.get(key, float("inf")), t)

        for _ in range(args.reps):
            t, n_ipc = ipc()
            keep("ipctk", t)
            rows, _ = probe(args, env, a, 1, "fresh")
            keep("fresh", rows[0]["cpu"])
            n_ours = rows[0]["pairs"]
            for key, target, frac in [("dhat", "dhat", 1.0), ("real", b, 1.0), ("half", b, 0.5)]:
                rows, _ = probe(args, env, a, 1, "moved", target, frac)
                keep(f"{key} kept", rows[0]["kept"])
                keep(f"{key} fresh", rows[0]["fresh"])
                if rows[0]["kept_reused"]:
                    sys.exit("a kept Ccd reused its pairs after a move: not the case measured")
        ms = {k: v * 1e3 for k, v in best.items()}
        print(f"{name} ({args.method}; min of {args.reps}, ms CPU, one thread; "
              f"ipctk {n_ipc} collisions, topoccd {n_ours} pairs)")
        print(f"  ipctk NormalCollisions.build        {ms['ipctk']:9.2f}")
        print(f"  topoccd fresh Ccd                   {ms['fresh']:9.2f}  {ms['ipctk'] / ms['fresh']:5.2f}x")
        print(f"  topoccd kept, moved by dhat         {ms['dhat kept']:9.2f}  {ms['ipctk'] / ms['dhat kept']:5.2f}x"
              f"  (fresh there {ms['dhat fresh']:.2f})")
        print(f"  topoccd kept, real move             {ms['real kept']:9.2f}  (fresh there {ms['real fresh']:.2f})")
        print(f"  topoccd kept, half the real move    {ms['half kept']:9.2f}  (fresh there {ms['half fresh']:.2f})")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
