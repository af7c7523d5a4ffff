#!/usr/bin/env python3
"""Run the IPC toolkit's Tight-Inclusion CCD on the same query files as `topoccd queries`.

Usage:  pip install ipctk numpy
        python3 topoccd-benches/scripts/ipctk_queries.py ../shared/data/queries [--tolerance 1e-6]

Prints, per kind, the same columns as `topoccd queries --json` (one JSON object per line), so the
two can be compared side by side:
        ./target/release/topoccd queries ../shared/data/queries --json
"""
import argparse
import json
import pathlib
import time
from fractions import Fraction

import numpy as np
import ipctk


def read_queries(path):
    rows = [r.strip() for r in path.read_text().splitlines() if r.strip()]
    if len(rows) % 8:
        raise SystemExit(f"{path}: {len(rows)} rows is not a multiple of 8")
    for i in range(0, len(rows), 8):
        pts, gt = [], None
        for row in rows[i:i + 8]:
            f = [int(x) for x in row.split(",")]
            pts.append([float(Fraction(f[2 * k], f[2 * k + 1])) for k in range(3)])
            gt = f[6] == 1
        yield np.array(pts), gt


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir", type=pathlib.Path)
    ap.add_argument("--tolerance", type=float, default=1e-6)
    ap.add_argument("--max-iterations", type=int, default=10_000_000)
    args = ap.parse_args()
    ccd = ipctk.TightInclusionCCD(tolerance=args.tolerance, max_iterations=args.max_iterations)
    for kind, folder in (("vf", "vertex-face"), ("ee", "edge-edge")):
        files = sorted(args.dir.glob(f"**/{folder}/*.csv"))
        queries = [q for f in files for q in read_queries(f)]
        n = pos = fn = fp = 0
        start = time.perf_counter()
        for p, gt in queries:
            if kind == "vf":
                hit, _toi = ccd.point_triangle_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7])
            else:
                hit, _toi = ccd.edge_edge_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7])
            n += 1
            pos += hit
            fn += gt and not hit
            fp += hit and not gt
        seconds = time.perf_counter() - start
        print(json.dumps({"kind": kind, "queries": n, "positives": pos, "false_negatives": fn,
                          "false_positives": fp, "seconds": seconds}))


if __name__ == "__main__":
    main()
