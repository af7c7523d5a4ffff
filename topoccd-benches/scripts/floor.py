#!/usr/bin/env python3
"""Where a one-step query's time goes: the bounding-volume layer alone against the rest.

For every input, in rounds (inputs and programs alternating, so all see the same machine load),
measures with the release binaries of this repository:

- query cold:   `topoccd --threads 1 step|run ... --method bvh --json`, a fresh process (what
                `compare.py` measures), the query's total;
- BV cold:      `BVH_PROBE_IN_PLACE=1 bvh_probe INPUT`, its first repetition: the swept
                18-DOPs, the tree's build and the self-traversal that enumerates the
                overlapping triangle pairs, nothing else, in a fresh process;
- query warm:   `step_probe INPUT bvh all`, the best repetition after the first (the tree
                refitted, memory reused), and its traversal (pairs, pair filter, narrow phase);
- BV warm:      the bounding-volume self-traversal of `bvh_probe`, best after the first;
- rest warm:    query warm's traversal minus BV warm: the triangle pairs' features, the pair
                filter, the star certificates and the elementary tests;
- neighbours:   of the overlapping triangle pairs the BV layer enumerates, the share whose two
                triangles share a vertex (mesh neighbours, whose volumes always overlap; the
                pair filter drops most of them after the hierarchy has found them).

With `--base OLD/topoccd --factor F`, also measures the old build's query cold and prints the
budget a new query has to meet to be F times faster (old median / F). Medians over the rounds.
Python 3 standard library only.

Inputs: a scene folder with frames/ (its first two frames) or a generated sequence folder (its
first step, parents included), as `step_probe` and `bvh_probe` take them.

Example:
  cargo build --release -p topoccd-cli -p topoccd-benches
  python3 topoccd-benches/scripts/floor.py --base BASE_BIN --factor 3 \\
      ../shared/data/scenes/cloth-funnel SCENES/airbag
  BASE_BIN is the `topoccd` command of the revision compared against, built in a worktree of
  its own: `git worktree add ../base REV && (cd ../base && cargo build --release -p
  topoccd-cli)`, then BASE_BIN=../base/target/release/topoccd. SCENES holds generated
  sequences: `target/release/topoccd gen SCENE SCENES/SCENE --frames 8 --seed 1` for each scene
  (`simloop.py --gen SCENES` makes the set the README's figures use).
"""

import argparse
import json
import os
import re
import statistics
import subprocess
import tempfile
from pathlib import Path


def json_lines(cmd, env=None):
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, check=True).stdout
    return [json.loads(line) for line in out.splitlines() if line.startswith("{")]


def cli_args(path, tmp):
    """The command-line tool's arguments for the input's first step."""
    d = Path(path)
    if (d / "frames").is_dir():
        # In the order of their numbers, as the probes' sequence reader takes them.
        number = lambda p: int(re.search(r"(\d+)$", p.stem).group(1))
        frames = sorted(
            (p for p in (d / "frames").iterdir() if p.suffix in (".ply", ".obj")), key=number
        )
        return ["step", str(frames[0]), str(frames[1])]
    one = Path(tempfile.mkdtemp(dir=tmp))
    for name in ["0000.ply", "0001.ply", "0001.parents"]:
        if (d / name).exists():
            os.symlink((d / name).resolve(), one / name)
    return ["run", str(one)]


def query_cold(binary, args):
    """The query's total in a fresh process, in ms (the last step's record of a `run`)."""
    records = json_lines([binary, "--threads", "1", *args, "--method", "bvh", "--json"])
    totals = [r["seconds"]["total"] for r in records if "seconds" in r]
    return 1e3 * totals[-1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("inputs", nargs="+")
    ap.add_argument("--bin-dir", default=str(Path(__file__).resolve().parents[2] / "target/release"))
    ap.add_argument("--base", help="an older build's topoccd, for the budget")
    ap.add_argument("--factor", type=float, default=3.0)
    ap.add_argument("--rounds", type=int, default=5)
    a = ap.parse_args()
    bins = Path(a.bin_dir)
    topoccd, bvh_probe, step_probe = (str(bins / n) for n in ["topoccd", "bvh_probe", "step_probe"])
    env = dict(os.environ, BVH_PROBE_IN_PLACE="1")
    keys = ["base", "q_cold", "bv_cold", "q_warm", "q_trav", "bv_trav", "neighbours"]
    res = {p: {k: [] for k in keys} for p in a.inputs}
    with tempfile.TemporaryDirectory() as tmp:
        args = {p: cli_args(p, tmp) for p in a.inputs}
        for _ in range(a.rounds):
            for p in a.inputs:
                r = res[p]
                if a.base:
                    r["base"].append(query_cold(a.base, args[p]))
                r["q_cold"].append(query_cold(topoccd, args[p]))
                b = json_lines([bvh_probe, p, "4"], env)
                r["bv_cold"].append(1e3 * (b[0]["build"] + b[0]["traverse"]))
                r["bv_trav"].append(1e3 * min(x["traverse"] for x in b[1:]))
                if "neighbours" in b[0]:
                    r["neighbours"].append(b[0]["neighbours"] / max(b[0]["pairs"], 1))
                q = json_lines([step_probe, p, "bvh", "all", "4", "1"])
                r["q_warm"].append(1e3 * min(x["build"] + x["traverse"] for x in q[1:]))
                r["q_trav"].append(1e3 * min(x["traverse"] for x in q[1:]))
    budget = f" | budget (base / {a.factor:g})" if a.base else ""
    print(
        f"| input{budget} | query cold | BV cold | query warm | its traversal | BV warm | rest warm"
        " | neighbours |"
    )
    print("|---" * (9 if a.base else 8) + "|")
    for p in a.inputs:
        m = {k: statistics.median(v) if v else None for k, v in res[p].items()}
        cells = [Path(p).name]
        if a.base:
            cells.append(f"{m['base'] / a.factor:.1f} ({m['base']:.1f} / {a.factor:g})")
        cells += [f"{m[k]:.1f}" for k in ["q_cold", "bv_cold", "q_warm", "q_trav", "bv_trav"]]
        cells.append(f"{m['q_trav'] - m['bv_trav']:.1f}")
        cells.append("–" if m["neighbours"] is None else f"{100 * m['neighbours']:.0f}%")
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
