#!/usr/bin/env python3
"""The Python package's overhead per query against the Rust CLI, on the shared real steps.

Usage:  pip install ./topoccd-py
        cargo build --release -p topoccd-cli
        python3 topoccd-benches/scripts/python_overhead.py [../shared/data/scenes] [--runs 1]

For each scene (cloth-funnel, cloth-ball), one thread on both sides:
  - cli: `topoccd --threads 1 step T0 T1 --json`, its seconds.total (the query alone, as timed
    inside the library);
  - py: the wall time of `Ccd.query(x0, x1, triangles, threads=1)` around the call in Python
    (input checks, building the step, the query, the numpy output arrays), and the library's
    own seconds.total inside that call.
Prints one JSON object per scene; `ratio` is py wall / cli total, `overhead_ms` is py wall less
the library's time inside the same call.
"""

import argparse
import json
import pathlib
import re
import subprocess
import time

import topoccd

REPO = pathlib.Path(__file__).resolve().parents[2]


def frames(scene: pathlib.Path):
    found = sorted((scene / "frames").glob("*.ply"), key=lambda p: int(re.findall(r"\d+", p.stem)[-1]))
    return found[0], found[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="?", type=pathlib.Path, default=REPO.parent / "shared" / "data" / "scenes")
    ap.add_argument("--cli", type=pathlib.Path, default=REPO / "target" / "release" / "topoccd")
    ap.add_argument("--runs", type=int, default=1, help="runs of each side; the minimum is kept")
    ap.add_argument("--method", default="bvh")
    args = ap.parse_args()
    for name in ("cloth-funnel", "cloth-ball"):
        t0, t1 = frames(args.scenes / name)
        cli = []
        for _ in range(args.runs):
            out = subprocess.run(
                [str(args.cli), "--threads", "1", "step", str(t0), str(t1), "--method", args.method, "--json"],
                capture_output=True, text=True, check=True)
            cli.append(json.loads(out.stdout)["seconds"]["total"])
        x0, _ = topoccd.read_mesh(t0)
        x1, triangles = topoccd.read_mesh(t1)
        ccd = topoccd.Ccd()
        ccd.query(x0[:3], x1[:3], triangles[:0], threads=1)  # builds the one-thread pool
        walls, inside = [], []
        for _ in range(args.runs):
            started = time.perf_counter()
            report = ccd.query(x0, x1, triangles, threads=1, method=args.method)
            walls.append(time.perf_counter() - started)
            inside.append(report.seconds["total"])
        wall, lib, cli_total = min(walls), min(inside), min(cli)
        overhead = min(w - i for w, i in zip(walls, inside))  # per run, then the least
        print(json.dumps({
            "scene": name, "method": args.method, "vf": len(report.vf), "ee": len(report.ee),
            "cli_total_s": round(cli_total, 4), "py_wall_s": round(wall, 4),
            "py_library_total_s": round(lib, 4), "overhead_ms": round(overhead * 1e3, 2),
            "ratio": round(wall / cli_total, 3),
        }), flush=True)


if __name__ == "__main__":
    main()
