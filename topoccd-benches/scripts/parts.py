#!/usr/bin/env python3
"""Where the everyday step's time goes, by part of the pipeline: a sampling profile of a
simulator's loop, mapped to milliseconds per step.

Runs `seq_probe SEQ METHOD MODE REPS 1` (a whole frame sequence in memory, one `Ccd` kept
across the steps, every repetition starting from a new one) twice: once plainly, for the
mean wall time per step over steps 1.. (median over the repetitions), and once under
`perf record -e cpu-clock`, whose samples are grouped by function into the parts below. The
samples of step 0's own work (building the tree and its front afresh) and of reading the
frames are left out; each remaining part's share of the samples, times the per-step time,
gives its milliseconds per step. Needs `perf` (Debian's linux-perf) and a build with symbols:
`cargo build --profile profiling -p topoccd-benches --bin seq_probe`.

Example:
  python3 topoccd-benches/scripts/parts.py --bin target/profiling/seq_probe \\
      SCENES/nidus SCENES/airbag
  SCENES holds generated sequences: `target/release/topoccd gen SCENE SCENES/SCENE --frames 8
  --seed 1` for each scene (`simloop.py --gen SCENES` makes the set the README's figures use).
"""

import argparse
import json
import re
import statistics
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

# Parts, in pipeline order: (name, regex on the symbol). The first match wins.
PARTS = [
    ("reading frames (left out)", r"ply_rs|io::|parser|read_binary|from_utf8|Sequence"),
    ("tree built afresh (step 0, left out)", r"front_of_pair|front_of_self|front_blocks|bvh::build|sort::|partition|rebuild"),
    ("star certificates", r"mesh::star::"),
    ("swept volumes and refit", r"triangle_volume|corner_volume|swept_point|swept_triangle|kdop::volume|kdop::compact|sweep_leaves|bvh::refit|Bvh<V>>::refit"),
    ("features' boxes, topology", r"FeatureBoxes|Features::update|topology::|same_topology|memcmp|bcmp"),
    ("neighbour list and star marks", r"mark_stars|neighbours"),
    ("front traversal (bounding volumes)", r"front_pairs|traverse::run|traverse::step|par_self_pairs|TaskPairs>::pairs"),
    ("triangle pairs (filter, features)", r"triangle_pair|filter::|triangles_separated|vertices_face"),
    ("narrow phase (prefilter, solver)", r"prefilter|solver|narrow_phase|narrow::|bernstein|closest|Search::"),
]
OTHER = "other (tasks, memory, threads)"
LEFT_OUT = {PARTS[0][0], PARTS[1][0]}


def per_step(bin_, seq, method, mode, reps):
    out = subprocess.run([bin_, str(seq), method, mode, str(reps), "1"], capture_output=True,
                         text=True, check=True).stdout
    by = defaultdict(list)
    for line in out.splitlines():
        d = json.loads(line)
        by[d["step"]].append(d["wall"])
    later = [s for s in by if s >= 1]
    return statistics.mean(statistics.median(by[s]) for s in later)


def profile(bin_, seq, method, mode, reps):
    with tempfile.TemporaryDirectory() as tmp:
        data = Path(tmp) / "perf.data"
        subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-F", "4000", "-o", str(data),
                        bin_, str(seq), method, mode, str(reps), "1"],
                       capture_output=True, check=True)
        report = subprocess.run(["perf", "report", "-i", str(data), "--no-children", "--sort",
                                 "symbol", "--stdio", "--percent-limit", "0"],
                                capture_output=True, text=True, check=True).stdout
    shares = defaultdict(float)
    for line in report.splitlines():
        m = re.match(r"\s*([0-9.]+)%\s+\[\.\]\s+(.*)$", line)
        if not m:
            continue
        share, symbol = float(m.group(1)), m.group(2)
        part = next((name for name, rx in PARTS if re.search(rx, symbol)), OTHER)
        shares[part] += share
    return shares


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="target/profiling/seq_probe")
    ap.add_argument("--method", default="bvh")
    ap.add_argument("--mode", default="all")
    ap.add_argument("--reps", type=int, default=10)
    ap.add_argument("sequences", nargs="+")
    args = ap.parse_args()
    names = [n for n, _ in PARTS if n not in LEFT_OUT] + [OTHER]
    rows = []
    for seq in args.sequences:
        wall = per_step(args.bin, seq, args.method, args.mode, args.reps)
        shares = profile(args.bin, seq, args.method, args.mode, args.reps)
        kept = sum(v for k, v in shares.items() if k not in LEFT_OUT)
        rows.append((Path(seq).name, wall, {n: wall * shares.get(n, 0.0) / kept for n in names}))
    print(f"{args.method}, {args.mode}, one thread; ms per step (steps 1.., median of {args.reps})\n")
    print("| part | " + " | ".join(r[0] for r in rows) + " |")
    print("|---|" + "---|" * len(rows))
    for n in names:
        print(f"| {n} | " + " | ".join(f"{r[2][n] * 1e3:.2f}" for r in rows) + " |")
    print("| **step** | " + " | ".join(f"**{r[1] * 1e3:.2f}**" for r in rows) + " |")


if __name__ == "__main__":
    sys.exit(main())
