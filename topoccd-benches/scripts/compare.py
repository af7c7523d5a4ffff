#!/usr/bin/env python3
"""Compare two builds of the `topoccd` command-line tool on the same steps, in one run.

For every input, method, mode (all pairs, `--earliest`) and thread count, runs
`topoccd --threads N step T0 T1 --method M [--earliest] --json` (or `topoccd run` on a one-step
copy of a generated sequence, whose topology may change), alternating base and new on every
repetition so that both see the same machine load, and prints a markdown table of the per-phase
seconds (median over the repetitions), the candidates (vf_tests + ee_tests), the contacts, the
peak memory (`/usr/bin/time -f %M`, else the child's rusage) and the new/base ratio of the total.

Fields that one build does not print are shown as "–", so builds from different commits can be
compared. Python 3 standard library only.

Inputs (any number):
  DIR with frames/          a real step, as in the shared data (the two frames in frames/)
  DIR with 0000.ply         a generated sequence: its first step (0000 -> 0001, with parents),
                            or with --step K its step K after the K - 1 before it
  T0.ply,T1.ply             an explicit step
With no input, the two real steps of the shared data ($TOPOCCD_DATA, else ../shared/data
from the repository's root) and every sequence under --scenes DIR.

Example (BASE_BIN and SCENES are placeholders, made as said below it):
  python3 topoccd-benches/scripts/compare.py --base BASE_BIN \\
      --new target/release/topoccd --scenes SCENES --reps 3
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
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PHASES = ["build", "traverse", "narrow", "clustering", "total"]
DASH = "–"


def frame_number(path):
    m = re.search(r"(\d+)$", path.stem)
    return int(m.group(1)) if m else None


def ply_faces(path):
    """The face count in a PLY header, or None."""
    try:
        with open(path, "rb") as f:
            head = f.read(4096)
    except OSError:
        return None
    m = re.search(rb"element face (\d+)", head)
    return int(m.group(1)) if m else None


class Input:
    """One step: a name, how to run it, and its triangle count."""

    def __init__(self, name, args, triangles, tmp=None):
        self.name, self.args, self.triangles, self.tmp = name, args, triangles, tmp


def make_input(spec, tmproot, step=1):
    if "," in spec:
        t0, t1 = (Path(p) for p in spec.split(",", 1))
        return Input(f"{t0.stem}->{t1.stem}", ["step", str(t0), str(t1)], ply_faces(t1))
    d = Path(spec)
    if (d / "frames").is_dir():
        frames = sorted(
            (p for p in (d / "frames").iterdir() if p.suffix in (".ply", ".obj")),
            key=lambda p: (frame_number(p) is None, frame_number(p), p.name),
        )
        if len(frames) < 2:
            raise SystemExit(f"{d}: fewer than two frames")
        t0, t1 = frames[0], frames[1]
        return Input(d.name, ["step", str(t0), str(t1)], ply_faces(t1))
    if (d / "0000.ply").is_file() and (d / "0001.ply").is_file():
        # Frames 0 to `step` (fewer if the sequence is shorter): `run` takes the steps in
        # turn in one process, as a simulator's loop does, and the last one is measured.
        last = 1
        while last < step and (d / f"{last + 1:04}.ply").is_file():
            last += 1
        one = Path(tmproot) / d.name
        one.mkdir()
        for k in range(last + 1):
            for f in [f"{k:04}.ply", f"{k:04}.parents"]:
                if (d / f).exists():
                    os.symlink((d / f).resolve(), one / f)
        name = d.name if last == 1 else f"{d.name} (step {last})"
        return Input(name, ["run", str(one)], ply_faces(d / f"{last:04}.ply"))
    raise SystemExit(f"{spec}: not a step (DIR/frames, a sequence DIR/0000.ply, or T0,T1)")


def default_inputs(scenes):
    data = os.environ.get("TOPOCCD_DATA")
    root = Path(__file__).resolve().parents[2]
    data = Path(data) if data else root.parent / "shared" / "data"
    out = [str(data / "scenes" / n) for n in ["cloth-funnel", "cloth-ball"]]
    out = [p for p in out if Path(p, "frames").is_dir()]
    if scenes:
        for d in sorted(Path(scenes).iterdir()):
            if (d / "0000.ply").is_file() and (d / "0001.ply").is_file():
                out.append(str(d))
    return out


def run_once(binary, inp, method, earliest, threads, timeout):
    """Runs one query; returns (record dict or None, peak KB or None, wall seconds, error)."""
    # "default": no --method, so each build runs its own default method.
    chosen = [] if method == "default" else ["--method", method]
    cmd = [binary, "--threads", str(threads)] + inp.args + chosen + ["--json"]
    if earliest:
        cmd.append("--earliest")
    timer = shutil.which("time") and os.path.exists("/usr/bin/time")
    fd, memfile = tempfile.mkstemp(prefix="compare-mem-")
    os.close(fd)
    if timer:
        cmd = ["/usr/bin/time", "-f", "%M", "-o", memfile] + cmd
    start = time.perf_counter()
    try:
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            out, err = p.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            p.kill()
            p.communicate()
            return None, None, time.perf_counter() - start, "timeout"
        wall = time.perf_counter() - start
        peak = None
        if timer:
            try:
                peak = int(open(memfile).read().strip().splitlines()[-1])
            except (OSError, ValueError, IndexError):
                peak = None
    finally:
        os.unlink(memfile)
    record = None
    for line in out.splitlines():
        line = line.strip()
        if not line.startswith("{"):
            continue
        try:
            obj = json.loads(line)
        except json.JSONDecodeError:
            continue
        if isinstance(obj, dict) and "seconds" in obj and "error" not in obj:
            # The last step's (a `run` prints one line per step, then its summary).
            record = obj
    if p.returncode != 0 or record is None:
        msg = (err.strip().splitlines() or [f"exit {p.returncode}"])[-1][:80]
        return None, peak, wall, msg
    return record, peak, wall, None


def field(rec, *path):
    cur = rec
    for k in path:
        if not isinstance(cur, dict) or k not in cur:
            return None
        cur = cur[k]
    return cur


def summarize(runs):
    """Median per phase over the successful repetitions, and the other figures of the last."""
    ok = [r for r in runs if r[0] is not None]
    if not ok:
        return {"error": runs[-1][3] if runs else "not run"}
    s = {}
    for ph in PHASES:
        vals = [field(r[0], "seconds", ph) for r in ok]
        vals = [v for v in vals if isinstance(v, (int, float))]
        s[ph] = statistics.median(vals) if vals else None
    rec = ok[-1][0]
    vf, ee = field(rec, "stats", "vf_tests"), field(rec, "stats", "ee_tests")
    s["candidates"] = vf + ee if isinstance(vf, int) and isinstance(ee, int) else None
    cvf, cee = rec.get("vf"), rec.get("ee")
    s["contacts"] = (
        cvf + cee if isinstance(cvf, int) and isinstance(cee, int) else None
    )
    s["earliest"] = rec.get("earliest_toi")
    # The method that ran (builds that report it): what "default" or "auto" chose.
    s["ran"] = field(rec, "stats", "method") or rec.get("method")
    peaks = [r[1] for r in ok if r[1] is not None]
    s["peak_mb"] = max(peaks) / 1024 if peaks else None
    s["wall"] = statistics.median(r[2] for r in ok)
    return s


def ms(v):
    return DASH if v is None else f"{1e3 * v:.1f}"


def num(v):
    return DASH if v is None else f"{v:,}"


def pair(b, n, fmt):
    return f"{fmt(b)} / {fmt(n)}"


def ratio(b, n):
    if b is None or n is None or b <= 0:
        return DASH
    return f"{n / b:.2f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("inputs", nargs="*", help="steps (see above)")
    ap.add_argument("--new", required=True, help="the new topoccd binary")
    ap.add_argument("--base", required=True, help="the base topoccd binary to compare with")
    ap.add_argument("--scenes", help="with no inputs: also every generated sequence in this folder")
    ap.add_argument("--methods", default="bvh,cluster,brute",
                    help="comma-separated (default: bvh,cluster,brute); 'default' runs each build's "
                         "default method (no --method), 'auto' needs a build that knows it")
    ap.add_argument("--threads", default="1,2", help="comma-separated thread counts (default 1,2)")
    ap.add_argument("--modes", default="all,earliest",
                    help="comma-separated: all, earliest (default: all,earliest; 'both' is both)")
    ap.add_argument("--reps", type=int, default=3, help="repetitions of each pair of runs (default 3)")
    ap.add_argument("--brute-max-triangles", type=int, default=40000,
                    help="run brute only on steps with at most this many triangles (default 40000)")
    ap.add_argument("--timeout", type=float, default=900, help="seconds per run (default 900)")
    ap.add_argument("--step", type=int, default=1,
                    help="for a generated sequence: measure its step K (frames K-1 -> K), the "
                         "steps before it run first in the same process, as in a simulator's "
                         "loop (default 1: the first step, in a fresh process)")
    ap.add_argument("--json-out", help="also write every raw result to this JSON file")
    args = ap.parse_args()

    builds = {"base": args.base, "new": args.new}
    for name, b in builds.items():
        if not (os.path.isfile(b) and os.access(b, os.X_OK)):
            raise SystemExit(f"--{name} {b}: not an executable file")
    tmproot = tempfile.mkdtemp(prefix="topoccd-compare-")
    try:
        specs = args.inputs or default_inputs(args.scenes)
        if not specs:
            raise SystemExit("no input (give steps, or --scenes DIR, or set TOPOCCD_DATA)")
        if args.step < 1:
            ap.error("--step must be at least 1")
        inputs = [make_input(s, tmproot, args.step) for s in specs]
        methods = [m for m in args.methods.split(",") if m]
        threads = [int(t) for t in args.threads.split(",") if t]
        modes = [m for m in args.modes.replace("both", "all,earliest").split(",") if m]
        for m in modes:
            if m not in ("all", "earliest"):
                ap.error(f"unknown mode {m!r} (all, earliest or both)")
        rows, raw = [], []
        for inp in inputs:
            for method in methods:
                if method == "brute" and (inp.triangles or 0) > args.brute_max_triangles:
                    continue
                for mode in modes:
                    for th in threads:
                        runs = {"base": [], "new": []}
                        for rep in range(args.reps):
                            order = ["base", "new"] if rep % 2 == 0 else ["new", "base"]
                            for b in order:
                                runs[b].append(run_once(builds[b], inp, method, mode == "earliest", th, args.timeout))
                        sb, sn = summarize(runs["base"]), summarize(runs["new"])
                        print(f"{inp.name} {method} {mode} {th}t: total {ms(sb.get('total'))} -> {ms(sn.get('total'))} ms",
                              file=sys.stderr, flush=True)
                        rows.append((inp, method, mode, th, sb, sn))
                        raw.append({"input": inp.name, "method": method, "mode": mode, "threads": th,
                                    "base": runs["base"], "new": runs["new"]})
    finally:
        shutil.rmtree(tmproot, ignore_errors=True)

    print(f"base: `{args.base}`, new: `{args.new}`; median of {args.reps} alternating runs; "
          "times in ms as base / new; ratio = new / base of the total (below 1: new is faster).\n")
    print("| step | tris | method | mode | thr | build | traverse | narrow | clustering | total | "
          "new/base | candidates | contacts | peak MB |")
    print("|---|---:|---|---|---:|---|---|---|---|---|---:|---|---|---|")
    for inp, method, mode, th, sb, sn in rows:
        if "error" in sb or "error" in sn:
            note = f"base: {sb.get('error', 'ok')}; new: {sn.get('error', 'ok')}"
            print(f"| {inp.name} | {num(inp.triangles)} | {method} | {mode} | {th} | {note} |||||||||")
            continue
        cells = [pair(sb[ph], sn[ph], ms) for ph in PHASES]
        shown = method
        if method in ("default", "auto"):
            shown = f"{method} ({sb.get('ran') or DASH} / {sn.get('ran') or DASH})"
        print("| " + " | ".join([
            inp.name, num(inp.triangles), shown, mode, str(th), *cells,
            ratio(sb["total"], sn["total"]),
            pair(sb["candidates"], sn["candidates"], num),
            pair(sb["contacts"], sn["contacts"], num) if mode == "all"
            else pair(sb["earliest"], sn["earliest"], lambda v: DASH if v is None else f"t={v:.6g}"),
            pair(sb["peak_mb"], sn["peak_mb"], lambda v: DASH if v is None else f"{v:.0f}"),
        ]) + " |")
    if args.json_out:
        with open(args.json_out, "w") as f:
            json.dump(raw, f, indent=1)


if __name__ == "__main__":
    main()
