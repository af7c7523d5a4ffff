#!/usr/bin/env python3
"""Compare two builds of the `topoccd` command-line tool over whole frame sequences, in one run.

Where `compare.py` times single steps, this times a simulator's loop: `topoccd run SEQ --json`
keeps one query object for the whole sequence, so what one step leaves for the next (the cluster
method's leaf clusters) counts. For every sequence, method and thread count it runs base and
new alternately, `--reps` times each, and prints the median over the repetitions of the summed
step totals over steps 1.. (step 0 starts from nothing), of the summed leaf-growth seconds and
leaf clusters (cluster method), and the new/base ratio. Python 3 standard library only.

`--substeps N` also times, for every sequence, a copy of its first step cut into N steps of
equal duration (the positions interpolated linearly; the parents file, if any, dropped, so use
it on sequences that do not change topology): the small motion per step of a simulator that
takes several substeps per frame.

Example:
  python3 topoccd-benches/scripts/sequence.py --base /work/head/target/release/topoccd \\
      --new target/release/topoccd --methods cluster,bvh --threads 1,2 --substeps 8 \\
      /work/scenes/seq-airbag /work/scenes/seq-nidus
"""

import argparse
import json
import statistics
import struct
import subprocess
import sys
import tempfile
from pathlib import Path


def read_ply(path):
    """(header bytes, positions, rest) of a binary little-endian PLY with double x, y, z."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end]
    if b"format binary_little_endian" not in header or b"property double z" not in header:
        raise SystemExit(f"{path}: --substeps needs binary little-endian PLY with double x, y, z")
    n = int(header.split(b"element vertex ")[1].split()[0])
    positions = struct.unpack_from(f"<{3 * n}d", data, end)
    return header, positions, data[end + 24 * n:]


def substepped(seq, n, root):
    """A sequence of n steps from the first step of `seq`, written under `root`."""
    h0, p0, faces0 = read_ply(seq / "0000.ply")
    _, p1, faces1 = read_ply(seq / "0001.ply")
    if faces0 != faces1 or len(p0) != len(p1):
        raise SystemExit(f"{seq}: its first step changes topology; --substeps needs one that does not")
    out = Path(root) / f"{seq.name}-sub{n}"
    out.mkdir()
    for k in range(n + 1):
        t = k / n
        p = [a + (b - a) * t for a, b in zip(p0, p1)]
        (out / f"{k:04d}.ply").write_bytes(h0 + struct.pack(f"<{len(p)}d", *p) + faces0)
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
        seqs = [Path(s) for s in args.sequences]
        if args.substeps > 1:
            seqs += [substepped(s, args.substeps, tmp) for s in list(seqs)]
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
