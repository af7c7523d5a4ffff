#!/usr/bin/env python3
"""Compare two builds of the `topoccd` command-line tool over whole frame sequences, in one run.

Where `compare.py` times single steps, this times a simulator's loop: `topoccd run SEQ --json`
keeps one query object for the whole sequence, so what one step leaves for the next (the cluster
method's leaf clusters) counts. For every sequence, method and thread count it runs base and
new alternately, `--reps` times each, and prints the median over the repetitions of the summed
step totals over steps 1.. (step 0 starts from nothing), of the summed leaf-growth seconds and
leaf clusters (cluster method), and the new/base ratio. Python 3 standard library only.
For issue 35's per-step table in a simulator's loop beside Self-CCD, see its successor
`simloop.py`.

`--substeps N` also times, for every sequence (or scene folder with `frames/`, such as the shared
real steps, which is then timed this way only), a copy of its first step cut into N steps of
equal duration (the positions interpolated linearly; the parents file, if any, dropped, so use
it on sequences that do not change topology): the small motion per step of a simulator that
takes several substeps per frame.

Example:
  python3 topoccd-benches/scripts/sequence.py --base BASE_BIN \\
      --new target/release/topoccd --methods cluster,bvh --threads 1,2 --substeps 8 \\
      SCENES/airbag SCENES/nidus
  BASE_BIN is the `topoccd` command of the revision compared against, built in a worktree of
  its own: `git worktree add ../base REV && (cd ../base && cargo build --release -p
  topoccd-cli)`, then BASE_BIN=../base/target/release/topoccd. SCENES holds generated
  sequences: `target/release/topoccd gen SCENE SCENES/SCENE --frames 8 --seed 1` for each scene
  (`simloop.py --gen SCENES` makes the set the README's figures use).
"""

import argparse
import json
import re
import statistics
import struct
import subprocess
import sys
import tempfile
from pathlib import Path


def read_ply(path):
    """(header bytes, positions, rest, struct code) of a binary PLY whose vertices are x, y, z
    only (float or double, either byte order)."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii", "replace")
    order = "<" if "binary_little_endian" in header else ">" if "binary_big_endian" in header else None
    lines = header.splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("element vertex"))
    props = []
    for l in lines[start + 1:]:
        if not l.startswith("property"):
            break
        props.append(l.split())
    kinds = {p[1] for p in props}
    if order is None or [p[-1] for p in props] != ["x", "y", "z"] or len(kinds) != 1 or kinds - {"float", "double"}:
        raise SystemExit(f"{path}: --substeps needs binary PLY vertices of x, y, z (float or double)")
    code = "d" if "double" in kinds else "f"
    n = int(lines[start].split()[2])
    positions = struct.unpack_from(f"{order}{3 * n}{code}", data, end)
    return data[:end], positions, data[end + struct.calcsize(f"{order}{3 * n}{code}"):], order + code


def first_frames(seq):
    """The first two frames of a frame folder (or of a scene folder's `frames/`), by number."""
    folder = seq / "frames" if (seq / "frames").is_dir() else seq
    frames = [p for p in folder.iterdir() if p.suffix == ".ply" and re.search(r"\d+$", p.stem)]
    frames.sort(key=lambda p: int(re.search(r"(\d+)$", p.stem).group(1)))
    if len(frames) < 2:
        raise SystemExit(f"{seq}: fewer than two numbered PLY frames")
    return frames[0], frames[1]


def substepped(seq, n, root):
    """A sequence of n steps from the first step of `seq`, written under `root`."""
    f0, f1 = first_frames(seq)
    h0, p0, faces0, code = read_ply(f0)
    _, p1, faces1, _ = read_ply(f1)
    if faces0 != faces1 or len(p0) != len(p1):
        raise SystemExit(f"{seq}: its first step changes topology; --substeps needs one that does not")
    out = Path(root) / f"{seq.name}-sub{n}"
    out.mkdir()
    for k in range(n + 1):
        t = k / n
        p = [a + (b - a) * t for a, b in zip(p0, p1)]
        (out / f"{k:04d}.ply").write_bytes(h0 + struct.pack(f"{code[0]}{len(p)}{code[1]}", *p) + faces0)
    return out


def run(binary, seq, method, threads):
    """Sums over steps 1.. of one `run --json`: (total s, clustering s, leaves), or an error."""
    cmd = [binary, "--threads", str(threads), "run", str(seq), "--method", method, "--json"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        return None, (p.stderr.strip().splitlines() or [f"exit {p.returncode}"])[-1][:80]
    steps = [json.loads(l) for l in p.stdout.splitlines() if l.startswith('{"step"')]
    later = steps[1:]
    if not later:
        return None, "fewer than two steps"
    total = sum(s["seconds"]["total"] for s in later)
    clustering = sum(s["seconds"].get("clustering") or 0.0 for s in later)
    leaves = sum((s["stats"].get("cluster") or {}).get("leaf", 0) for s in later)
    return (total, clustering, leaves), None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--base", required=True, help="the earlier build's topoccd binary")
    ap.add_argument("--new", required=True, help="the build to compare with it")
    ap.add_argument("--methods", default="cluster", help="comma-separated: cluster, bvh, brute, auto")
    ap.add_argument("--threads", default="1", help="comma-separated thread counts")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--substeps", type=int, default=0, help="also time the first step cut in N")
    ap.add_argument("sequences", nargs="+", help="frame folders (0000.ply, 0001.ply, ...)")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="topoccd-seq-") as tmp:
        given = [Path(s) for s in args.sequences]
        # A scene folder with only a pair of frames (frames/) is timed by its substeps alone.
        seqs = [s for s in given if not (s / "frames").is_dir()]
        if args.substeps > 1:
            seqs += [substepped(s, args.substeps, tmp) for s in given]
        print("steps 1.. of each sequence, medians; ms as base / new; ratio = base / new "
              "(above 1: new is faster)\n")
        print("| sequence | method | thr | total base | total new | ratio | growth base | growth new | leaves base | leaves new |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for seq in seqs:
            for method in args.methods.split(","):
                for threads in args.threads.split(","):
                    got = {"base": [], "new": []}
                    error = None
                    for _ in range(args.reps):
                        for name in ("base", "new"):
                            r, err = run(getattr(args, name), seq, method, threads)
                            if r is None:
                                error = f"{name}: {err}"
                            else:
                                got[name].append(r)
                    if error or not got["base"] or not got["new"]:
                        print(f"| {seq.name} | {method} | {threads} | {error} |")
                        continue
                    med = {k: [statistics.median(x[i] for x in v) for i in range(3)] for k, v in got.items()}
                    b, n = med["base"], med["new"]
                    print(f"| {seq.name} | {method} | {threads} | {b[0] * 1e3:.1f} | {n[0] * 1e3:.1f} | "
                          f"{b[0] / n[0]:.3f} | {b[1] * 1e3:.1f} | {n[1] * 1e3:.1f} | {b[2]:.0f} | {n[2]:.0f} |")
                    sys.stdout.flush()


if __name__ == "__main__":
    main()
