#!/usr/bin/env python3
"""The figures of issue 38 (hostile input): the cloth-funnel step with its positions cast to
int32, which collapses 9,450 vertices onto 10 points, queried from Python as a user who made
that mistake would.

Every case runs in a fresh process (so that its peak resident memory is its own), on 1 and 2
threads, and prints one line; then a markdown table. Measured per case:

- the query's wall time (time.perf_counter around the call), or the time from the signal to
  the KeyboardInterrupt for the Ctrl-C case, or to the TimeoutError for the timeout case;
- the process's peak resident memory (resource.getrusage ru_maxrss), which includes Python,
  numpy, the read meshes and the report's arrays;
- what the query returned (contacts, earliest time, truncation).

Cases:
  all-1M        mode="all", max_contacts=1_000_000
  earliest-1M   mode="earliest", max_contacts=1_000_000
  earliest-10   mode="earliest", max_contacts=10 (a line search wanting the time only)
  timeout-1s    no cap, timeout=1.0 (TimeoutError expected)
  ctrl-c        no cap, SIGINT sent 2 s into the query (KeyboardInterrupt expected)
  warning       the delay from the call to the coincident-vertices warning (before the query)

Issue 43's cases (every entry point with its defaults, and each timeout):
  default-all       topoccd.query with the defaults (max_contacts=DEFAULT_MAX_CONTACTS)
  default-earliest  mode="earliest" with the defaults
  line-search       Ccd.query(mode="earliest", max_contacts=1): what the Rust line-search
                    helpers run (the Python helpers after issue 43's merge note)
  stepsize          topoccd.collision_free_stepsize with its defaults
  free              topoccd.is_step_collision_free with its defaults
  check             topoccd.intersecting_triangles(x0, tris) with its defaults (RuntimeError)
  earliest-timeout  mode="earliest", max_contacts=None, timeout=1.0 (TimeoutError)
  check-timeout     intersecting_triangles(max_contacts=None, timeout=1.0) (TimeoutError)

Needs the topoccd Python package (pip install ./topoccd-py) and numpy.

Example:
  python3 topoccd-benches/scripts/hostile.py ../shared/data/scenes/cloth-funnel --reps 3
"""

import argparse
import json
import os
import signal
import statistics
import subprocess
import sys
import time

CHILD = r"""
import json, resource, signal, sys, time, warnings
import numpy as np, topoccd
frames, case, threads = sys.argv[1], sys.argv[2], int(sys.argv[3])
x0, _ = topoccd.read_mesh(frames + "/227.ply")
x1, tris = topoccd.read_mesh(frames + "/228.ply")
x0, x1 = x0.astype(np.int32), x1.astype(np.int32)
out = {"case": case, "threads": threads}
def rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
if case == "warning":
    seen = []
    def show(message, category, filename, lineno, file=None, line=None):
        seen.append(time.perf_counter())
    warnings.showwarning = show
    start = time.perf_counter()
    topoccd.query(x0, x1, tris, max_contacts=1, threads=threads)
    out["seconds"] = seen[0] - start
    out["result"] = f"{len(seen)} warnings"
else:
    warnings.simplefilter("ignore")
    kwargs = {
        "all-1M": dict(max_contacts=1_000_000),
        "earliest-1M": dict(mode="earliest", max_contacts=1_000_000),
        "earliest-10": dict(mode="earliest", max_contacts=10),
        "timeout-1s": dict(max_contacts=None, timeout=1.0),
        "ctrl-c": dict(max_contacts=None),
        "default-all": dict(),
        "default-earliest": dict(mode="earliest"),
        "line-search": dict(mode="earliest", max_contacts=1),
        "earliest-timeout": dict(mode="earliest", max_contacts=None, timeout=1.0),
    }.get(case, {})
    print("ready", flush=True)
    start = time.perf_counter()
    try:
        if case == "stepsize":
            a = topoccd.collision_free_stepsize(x0, x1, tris, threads=threads)
            out["result"] = f"alpha {a}"
        elif case == "free":
            out["result"] = f"free {topoccd.is_step_collision_free(x0, x1, tris, threads=threads)}"
        elif case in ("check", "check-timeout"):
            kw = dict(max_contacts=None, timeout=1.0) if case == "check-timeout" else {}
            out["result"] = f"{len(topoccd.intersecting_triangles(x0, tris, **kw))} pairs"
        else:
            r = topoccd.query(x0, x1, tris, threads=threads, **kwargs)
            out["result"] = (
                f"{len(r)} contacts, earliest {r.earliest_toi}, truncated {r.truncated}, "
                f"complete {r.earliest_complete}"
            )
        out["seconds"] = time.perf_counter() - start
    except (TimeoutError, RuntimeError) as e:
        out["seconds"] = time.perf_counter() - start
        out["result"] = type(e).__name__
    except KeyboardInterrupt:
        out["interrupted_at"] = time.monotonic()
        out["result"] = "KeyboardInterrupt"
out["peak_mb"] = rss_mb()
print(json.dumps(out), flush=True)
"""


def run_case(frames: str, case: str, threads: int) -> dict:
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, frames, case, str(threads)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    if case == "ctrl-c":
        assert child.stdout.readline().strip() == "ready"
        time.sleep(2.0)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=60)
        line = json.loads(out.strip().splitlines()[-1])
        line["seconds"] = line["interrupted_at"] - sent
        return line
    out, err = child.communicate(timeout=600)
    if child.returncode != 0:
        raise RuntimeError(f"{case}: {err}")
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", help="the cloth-funnel scene folder (with frames/)")
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--threads", default="1,2")
    parser.add_argument(
        "--cases", default="all-1M,earliest-1M,earliest-10,timeout-1s,ctrl-c,warning"
    )
    args = parser.parse_args()
    frames = os.path.join(args.scene, "frames")
    rows = []
    for case in args.cases.split(","):
        for threads in map(int, args.threads.split(",")):
            runs = [run_case(frames, case, threads) for _ in range(args.reps)]
            for r in runs:
                print(json.dumps(r), flush=True)
            rows.append(
                (
                    case,
                    threads,
                    statistics.median(r["seconds"] for r in runs),
                    max(r["seconds"] for r in runs),
                    max(r["peak_mb"] for r in runs),
                    runs[-1]["result"],
                )
            )
    print()
    print("| case | threads | seconds (median) | seconds (max) | peak RSS (MB, max) | result |")
    print("|---|---|---|---|---|---|")
    for case, threads, med, worst, rss, result in rows:
        print(f"| {case} | {threads} | {med:.3f} | {worst:.3f} | {rss:.0f} | {result} |")


if __name__ == "__main__":
    main()
