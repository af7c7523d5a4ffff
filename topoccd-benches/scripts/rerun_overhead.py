#!/usr/bin/env python3
"""What recording costs: `topoccd run SEQ` against `topoccd run SEQ --rerun OUT.rrd`, on the
generated nidus sequence, alternating the two, several times each; the median wall time of
each and the overhead of recording in percent (the issue's bound: at most 20 %), in wall time
and in CPU time (user + system of the process: steadier than wall time on a busy machine).

Usage:  cargo build --release -p topoccd-cli --features rerun
        python3 topoccd-benches/scripts/rerun_overhead.py [--frames 8] [--scale 1] [--repeats 5]
        [--threads N] [--cli target/release/topoccd]

The wall time is the command's own (`wall_seconds` of its JSON summary: the sequence read, the
queries, the recording and its flush to disk), not the process start. The sequence is
generated once into a temporary folder (`topoccd gen nidus DIR --frames F --scale S`) and the
recording is written to the same folder.
"""

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def wall(cli, seq, threads, extra):
    args = [cli]
    if threads:
        args += ["--threads", str(threads)]
    args += ["run", str(seq), "--json", "--no-check", *extra]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run(args, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        sys.exit(f"{' '.join(args)} failed: {done.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    last = json.loads(done.stdout.strip().splitlines()[-1])
    return last["summary"]["wall_seconds"], cpu, last["summary"]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cli", default=str(REPO / "target" / "release" / "topoccd"))
    p.add_argument("--frames", type=int, default=8)
    p.add_argument("--scale", type=float, default=1.0)
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--threads", type=int, default=None)
    args = p.parse_args()
    with tempfile.TemporaryDirectory(prefix="topoccd-rerun-bench-") as tmp:
        seq = Path(tmp) / "nidus"
        subprocess.run([args.cli, "gen", "nidus", str(seq), "--frames", str(args.frames),
                        "--scale", str(args.scale)], check=True, capture_output=True)
        rrd = Path(tmp) / "out.rrd"
        plain, recorded, plain_cpu, recorded_cpu = [], [], [], []
        for r in range(args.repeats):
            # Alternate which goes first, so that neither always runs on a warm cache.
            order = [False, True] if r % 2 == 0 else [True, False]
            for rec in order:
                extra = ["--rerun", str(rrd)] if rec else []
                t, cpu, summary = wall(args.cli, seq, args.threads, extra)
                (recorded if rec else plain).append(t)
                (recorded_cpu if rec else plain_cpu).append(cpu)
        size = os.path.getsize(rrd)
        a, b = statistics.median(plain), statistics.median(recorded)
        print(f"nidus, {args.frames} frames, scale {args.scale}: {summary['steps']} steps, "
              f"{summary['vf'] + summary['ee']} contacts")
        print(f"run:          median {a:.3f} s over {args.repeats} ({', '.join(f'{x:.3f}' for x in plain)})")
        print(f"run --rerun:  median {b:.3f} s over {args.repeats} ({', '.join(f'{x:.3f}' for x in recorded)})")
        print(f"recording costs {100 * (b - a) / a:+.1f} % of run's wall time; the .rrd is {size / 2**20:.1f} MiB")
        c, d = statistics.median(plain_cpu), statistics.median(recorded_cpu)
        print(f"CPU time (user + system): run {c:.3f} s, run --rerun {d:.3f} s (medians): "
              f"recording costs {100 * (d - c) / c:+.1f} % of run's CPU time")


if __name__ == "__main__":
    main()
