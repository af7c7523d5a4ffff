#!/usr/bin/env python3
"""A simulator's loop over whole frame sequences: topoccd step by step, beside Self-CCD.

The successor of `sequence.py` for issue 35's measurements (`sequence.py` stays for its
base/new comparison of methods and thread counts; its frame reader and `--substeps` code are
reused here). One process per sequence and run, one query object kept across the steps, as a
simulator calls the library: `topoccd --threads T run SEQ --json [--earliest] [--method M]`.

For every sequence, every repetition runs in turn (so all see the same machine load):
  1 thread      topoccd, 1 thread, all pairs (the default method unless --method)
  Self-CCD      with --selfccd BIN: its driver `BIN SEQ --scale S`, one OpenMP thread
  2 threads     topoccd, 2 threads, all pairs
  Earliest      topoccd, 1 thread, --earliest
and with --base OLD_BIN the same topoccd runs of the older build, each right after the new
build's. It prints, per sequence and step, the median over the repetitions of: the seconds of
each phase (the `seconds` object of the JSON line: build, traverse, narrow, total, and the
cluster method's clustering and merging when present), the bounding-volume tests, the
candidates (stats.vf_tests + stats.ee_tests), the contacts (vf + ee), the totals of the other
runs and Self-CCD's step time and contacts. Then one summary row per sequence:

- times: the MEAN over steps 1.. of the per-step medians (step 0 starts from nothing), in ms
  per step, and the ratios Self-CCD / topoccd (above 1: topoccd is faster), 1 / 2 threads,
  All / Earliest and new / base (below 1: the new build is faster);
- contacts: the SUM over ALL steps (step 0 included, as issue 35's table counts them) of
  Self-CCD's distinct pairs and of topoccd's (1 thread, all pairs), and in how many steps the
  two counts are equal.

Self-CCD's `step_s` is its CCD work for the step (a rebuild included where the triangles
change); topoccd's is the query's `seconds.total`. Neither includes reading the frames.

A run that fails, times out (--timeout) or prints no step is reported in the tables and does
not stop the others. Python 3 standard library only.

Sequences: frame folders (0000.ply, 0001.ply, ... with optional .parents files). A scene
folder with frames/ (such as the shared real steps) is replaced by its first step cut into
--substeps N linear substeps (default 8), written to a temporary folder. `--scenes DIR` adds
the six sequences of issue 35 found under DIR; `--gen DIR` first writes them there (those
missing only; nothing existing is overwritten), with the binary given:
  topoccd gen SCENE DIR/SCENE --frames 8 --seed 1 --scale 1   for nidus, airbag, nidus-cut,
                                                               bunny-dragon
  the shared real steps cloth-funnel and cloth-ball cut into 8 substeps (DIR/NAME-sub8;
  from $TOPOCCD_DATA/scenes, else ../shared/data/scenes beside the repository, or --data)

Example (issue 35's table; SELFCCD_BIN and SCENES are placeholders, made as said below it):
  cargo build --release -p topoccd-cli
  nice -n 5 python3 topoccd-benches/scripts/simloop.py --bin target/release/topoccd \\
      --selfccd SELFCCD_BIN --reps 3 --scenes SCENES --out simloop.md
  SELFCCD_BIN is Self-CCD's sequence runner, built as ../shared/peers/README.md says. SCENES is a
  folder of the sequences above: `--gen SCENES` instead of `--scenes SCENES` writes them first
  (`topoccd gen SCENE SCENES/SCENE --frames 8 --seed 1` for each generated scene).
"""

import argparse
import json
import os
import platform
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.dont_write_bytecode = True  # no __pycache__ beside the scripts
from sequence import substepped  # noqa: E402  (the frame reader and substeps of sequence.py)

# Issue 35's sequences, in the order of its table.
SIX = ["airbag", "nidus", "cloth-funnel-sub8", "cloth-ball-sub8", "nidus-cut", "bunny-dragon"]
GENERATED = ["nidus", "airbag", "nidus-cut", "bunny-dragon"]
REAL = ["cloth-funnel", "cloth-ball"]
GEN_SUBSTEPS = 8
DASH = "–"

# The topoccd runs: name -> (threads, earliest).
RUNS = {"1": (1, False), "2": (2, False), "earliest": (1, True)}
RUN_LABEL = {"1": "1 thread", "2": "2 threads", "earliest": "Earliest"}


def last_line(text, code):
    lines = [l for l in text.strip().splitlines() if l.strip()]
    return (lines[-1] if lines else f"exit status {code}")[:160]


def call(cmd, timeout, env=None):
    """(stdout, None) or (None, why it failed): never raises for a failing child."""
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return None, f"timed out after {timeout:g} s"
    except OSError as e:
        return None, f"cannot run {cmd[0]}: {e}"
    if p.returncode != 0:
        return None, f"exit {p.returncode}: {last_line(p.stderr, p.returncode)}"
    return p.stdout, None


def json_lines(text):
    out = []
    for line in text.splitlines():
        line = line.strip()
        if line.startswith("{"):
            try:
                out.append(json.loads(line))
            except ValueError:
                pass
    return out


def run_topoccd(binary, seq, threads, earliest, method, timeout):
    """The steps of one `topoccd run --json`, or an error."""
    cmd = [binary, "--threads", str(threads), "run", str(seq), "--json"]
    if earliest:
        cmd.append("--earliest")
    if method:
        cmd += ["--method", method]
    text, err = call(cmd, timeout)
    if err:
        return None, err
    steps = []
    try:
        for o in json_lines(text):
            if "step" not in o:
                continue
            stats = o["stats"]
            seconds = {k: v for k, v in o["seconds"].items() if v is not None}
            steps.append({
                "step": o["step"],
                "triangles": o["triangles"],
                "method": stats.get("method"),
                "seconds": seconds,
                "bv_tests": stats["bv_tests"],
                "candidates": stats["vf_tests"] + stats["ee_tests"],
                "contacts": o["vf"] + o["ee"],
            })
    except (KeyError, TypeError) as e:
        return None, f"unexpected JSON line (missing {e})"
    if not steps:
        return None, "no step printed"
    return steps, None


def run_selfccd(binary, seq, scale, timeout):
    """The steps of one Self-CCD driver run (one OpenMP thread), or an error."""
    env = dict(os.environ, OMP_NUM_THREADS="1")
    text, err = call([binary, str(seq), "--scale", repr(scale)], timeout, env)
    if err:
        return None, err
    lines = json_lines(text)
    try:
        steps = [{
            "step": o["step"],
            "triangles": o["triangles"],
            "seconds": {"total": o["step_s"], "rebuild": o["rebuild_s"]},
            "rebuilt": o["rebuilt"],
            "contacts": o["vf"] + o["ee"],
        } for o in lines if "step" in o]
    except (KeyError, TypeError) as e:
        return None, f"unexpected JSON line (missing {e})"
    if not any("summary" in o for o in lines):
        return None, "no summary line (the run did not finish)"
    if not steps:
        return None, "no step printed"
    return steps, None


def median_steps(reps):
    """Per step (by position), the median over the repetitions of every number; None if the
    repetitions disagree on the number of steps."""
    if not reps or len({len(r) for r in reps}) != 1:
        return None
    out = []
    for i in range(len(reps[0])):
        at = [r[i] for r in reps]
        step = dict(at[0])
        step["seconds"] = {k: statistics.median(s["seconds"][k] for s in at)
                           for k in at[0]["seconds"] if all(k in s["seconds"] for s in at)}
        for key in ("bv_tests", "candidates", "contacts"):
            if key in step:
                step[key] = statistics.median_low(s[key] for s in at)
        out.append(step)
    return out


def later_mean(steps, key="total"):
    """Mean over steps 1.. of a phase's per-step medians (None if there is no step 1)."""
    xs = [s["seconds"].get(key) for s in steps[1:]]
    if not xs or any(x is None for x in xs):
        return None
    return statistics.fmean(xs)


def ms(x):
    return DASH if x is None else f"{x * 1e3:,.1f}" if x < 10 else f"{x * 1e3:,.0f}"


def ratio(a, b):
    return DASH if a is None or b is None or b == 0 else f"{a / b:.2f}"


def count(x):
    return DASH if x is None else f"{x:,.0f}"


class Sequence:
    def __init__(self, name, path, origin=None):
        self.name, self.path = name, path
        self.origin = origin or str(path)  # what the user gave, and how it was cut
        self.reps = {}     # run name -> [steps of each repetition]
        self.errors = {}   # run name -> [messages]
        self.medians = {}  # run name -> per-step medians

    def add(self, run, steps, err):
        if err:
            self.errors.setdefault(run, []).append(err)
        else:
            self.reps.setdefault(run, []).append(steps)

    def finish(self):
        for run, reps in self.reps.items():
            m = median_steps(reps)
            if m is None:
                self.errors.setdefault(run, []).append(
                    "repetitions with different step counts: "
                    + ", ".join(str(len(r)) for r in reps))
            else:
                self.medians[run] = m


def detail_table(seq, runs, base):
    """Markdown lines: per step, the 1-thread run's phases and counters, the other runs'
    totals."""
    lines = [f"### {seq.name}", "", f"`{seq.origin}`", ""]
    for run, errs in seq.errors.items():
        for e in sorted(set(errs)):
            lines.append(f"- **{label(run)} failed** ({errs.count(e)} of the repetitions): {e}")
    if seq.errors:
        lines.append("")
    main = seq.medians.get("1")
    ref = main or next(iter(seq.medians.values()), None)
    if ref is None:
        lines += ["(no run succeeded)", ""]
        return lines
    phases = []
    if main:
        for s in main:
            for k in s["seconds"]:
                if k != "total" and k not in phases:
                    phases.append(k)
    head = ["step", "triangles"]
    if main:
        head += [f"{p} ms" for p in phases] + ["total ms", "method", "BV tests", "candidates",
                                                 "contacts"]
    others = [r for r in ["2", "earliest"] if r in runs]
    head += [f"{RUN_LABEL[r]} ms" for r in others]
    if "self" in runs:
        head += ["Self-CCD ms", "Self-CCD contacts", "rebuilt"]
    if base:
        head += [f"base {RUN_LABEL[r]} ms" for r in runs if r in RUNS]
    lines += ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]

    def at(run, i):
        m = seq.medians.get(run)
        return m[i] if m and i < len(m) else None

    for i, s in enumerate(ref):
        row = [str(s["step"]), count(s["triangles"])]
        if main:
            m = main[i]
            row += [ms(m["seconds"].get(p)) for p in phases]
            row += [ms(m["seconds"].get("total")), str(m.get("method")), count(m["bv_tests"]),
                    count(m["candidates"]), count(m["contacts"])]
        for r in others:
            o = at(r, i)
            row.append(ms(o["seconds"]["total"]) if o else DASH)
        if "self" in runs:
            o = at("self", i)
            row += [ms(o["seconds"]["total"]), count(o["contacts"]),
                    "yes" if o["rebuilt"] else "no"] if o else [DASH] * 3
        if base:
            for r in runs:
                if r in RUNS:
                    o = at("base-" + r, i)
                    row.append(ms(o["seconds"]["total"]) if o else DASH)
        lines.append("| " + " | ".join(row) + " |")
    if len(ref) > 1:
        # The mean over steps 1.. of every column above that is a time or a count.
        def mean(run, f):
            m = seq.medians.get(run)
            if not m or len(m) != len(ref):
                return None
            xs = [f(x) for x in m[1:]]
            return None if any(x is None for x in xs) else statistics.fmean(xs)

        row = ["mean 1..", DASH]
        if main:
            row += [ms(mean("1", lambda x, p=p: x["seconds"].get(p))) for p in phases]
            row += [ms(mean("1", lambda x: x["seconds"].get("total"))), DASH]
            row += [count(mean("1", lambda x, k=k: x[k])) for k in ("bv_tests", "candidates",
                                                                      "contacts")]
        row += [ms(mean(r, lambda x: x["seconds"]["total"])) for r in others]
        if "self" in runs:
            row += [ms(mean("self", lambda x: x["seconds"]["total"])),
                    count(mean("self", lambda x: x["contacts"])), DASH]
        if base:
            row += [ms(mean("base-" + r, lambda x: x["seconds"]["total"]))
                    for r in runs if r in RUNS]
        lines.append("| " + " | ".join(f"**{c}**" if c != DASH else c for c in row) + " |")
    lines.append("")
    return lines


def label(run):
    if run == "self":
        return "Self-CCD"
    if run.startswith("base-"):
        return "base " + RUN_LABEL.get(run[5:], run[5:])
    return RUN_LABEL.get(run, run)


def summarize(seq):
    """The per-sequence figures of the summary table (None where a run failed)."""
    m = seq.medians
    mean = {r: later_mean(steps) for r, steps in m.items()}
    out = {"sequence": seq.name, "steps": None, "triangles": None, "mean_ms": {},
           "contacts_selfccd": None, "contacts_topoccd": None, "contacts_equal_steps": None}
    ref = m.get("1") or next(iter(m.values()), None)
    if ref:
        out["steps"] = len(ref)
        out["triangles"] = ref[0]["triangles"]
    for r, x in mean.items():
        out["mean_ms"][r] = None if x is None else x * 1e3
    if "1" in m and "self" in m:
        a, b = m["self"], m["1"]
        out["contacts_selfccd"] = sum(s["contacts"] for s in a)
        out["contacts_topoccd"] = sum(s["contacts"] for s in b)
        if len(a) == len(b):
            out["contacts_equal_steps"] = sum(x["contacts"] == y["contacts"] for x, y in zip(a, b))
    return out


def summary_table(sums, runs, base):
    head = ["sequence", "triangles", "steps"]
    head += [f"topoccd {RUN_LABEL[r]}" for r in runs if r in RUNS]
    if "self" in runs:
        head += ["Self-CCD refit loop", "Self-CCD / topoccd", "contacts Self-CCD / topoccd",
                 "steps with equal counts"]
    if "2" in runs and "1" in runs:
        head.append("1 / 2 threads")
    if "earliest" in runs and "1" in runs:
        head.append("All / Earliest")
    if base:
        for r in runs:
            if r in RUNS:
                head += [f"base {RUN_LABEL[r]}", f"new / base {RUN_LABEL[r]}"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for s in sums:
        t = s["mean_ms"]
        f = lambda r: DASH if t.get(r) is None else f"{t[r]:,.1f} ms"  # noqa: E731
        q = lambda a, b: ratio(t.get(a), t.get(b))  # noqa: E731
        row = [s["sequence"], count(s["triangles"]), DASH if s["steps"] is None else str(s["steps"])]
        for r in runs:
            if r not in RUNS:
                continue
            cell = f(r)
            if r == "1" and "self" in runs and t.get("self") and t.get("1"):
                cell += f" ({q('self', '1')}×)"
            row.append(cell)
        if "self" in runs:
            row += [f("self"), q("self", "1")]
            cs, ct = s["contacts_selfccd"], s["contacts_topoccd"]
            row.append(DASH if cs is None else f"{count(cs)} / {count(ct)}")
            eq = s["contacts_equal_steps"]
            row.append(DASH if eq is None else f"{eq} of {s['steps']}")
        if "2" in runs and "1" in runs:
            row.append(q("1", "2"))
        if "earliest" in runs and "1" in runs:
            row.append(q("1", "earliest"))
        if base:
            for r in runs:
                if r in RUNS:
                    row += [f("base-" + r), q(r, "base-" + r)]
        lines.append("| " + " | ".join(row) + " |")
    return lines


def phase_table(seqs):
    """Where topoccd's 1-thread time goes: the mean over steps 1.. of each phase and counter."""
    phases = []
    for s in seqs:
        for step in s.medians.get("1", []):
            for k in step["seconds"]:
                if k not in phases:
                    phases.append(k)
    phases.sort(key=lambda k: k == "total")
    head = ["sequence"] + [f"{p} ms" for p in phases] + ["BV tests", "candidates", "contacts",
                                                          "ns per BV test (traverse)"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for s in seqs:
        m = s.medians.get("1")
        if not m or len(m) < 2:
            lines.append(f"| {s.name} |" + f" {DASH} |" * (len(head) - 1))
            continue
        later = m[1:]
        mean = lambda f: statistics.fmean(f(x) for x in later)  # noqa: E731
        row = [s.name]
        for p in phases:
            xs = [x["seconds"].get(p) for x in later]
            row.append(DASH if any(x is None for x in xs) else ms(statistics.fmean(xs)))
        bv = mean(lambda x: x["bv_tests"])
        row += [count(bv), count(mean(lambda x: x["candidates"])),
                count(mean(lambda x: x["contacts"]))]
        trav = [x["seconds"].get("traverse") for x in later]
        row.append(DASH if not bv or any(t is None for t in trav)
                   else f"{statistics.fmean(trav) / bv * 1e9:.0f}")
        lines.append("| " + " | ".join(row) + " |")
    return lines


def data_scenes(arg):
    if arg:
        return Path(arg)
    if os.environ.get("TOPOCCD_DATA"):
        return Path(os.environ["TOPOCCD_DATA"]) / "scenes"
    return Path(__file__).resolve().parents[2].parent / "shared" / "data" / "scenes"


def generate(binary, out, data, timeout):
    """Writes issue 35's six sequences under `out`, skipping those already there. Returns the
    messages of what failed."""
    failed = []
    out.mkdir(parents=True, exist_ok=True)
    for scene in GENERATED:
        d = out / scene
        if d.is_dir() and any(d.iterdir()):
            print(f"gen: keeping {d} (not empty)", file=sys.stderr)
            continue
        cmd = [binary, "gen", scene, str(d), "--frames", "8", "--seed", "1", "--scale", "1"]
        print("gen: " + shlex.join(cmd), file=sys.stderr)
        _, err = call(cmd, timeout)
        if err:
            failed.append(f"gen {scene}: {err}")
    for real in REAL:
        d = out / f"{real}-sub{GEN_SUBSTEPS}"
        if d.exists():
            if d.is_dir() and not any(d.iterdir()):
                d.rmdir()
            else:
                print(f"gen: keeping {d} (exists)", file=sys.stderr)
                continue
        print(f"gen: {data / real} cut into {GEN_SUBSTEPS} substeps -> {d}", file=sys.stderr)
        try:
            substepped(data / real, GEN_SUBSTEPS, out)
        except (SystemExit, OSError, ValueError) as e:
            failed.append(f"substeps of {data / real}: {e}")
    return failed


def machine():
    load = os.getloadavg() if hasattr(os, "getloadavg") else None
    return {"host": platform.node(), "cpus": os.cpu_count(), "python": platform.python_version(),
            "load_at_start": load, "date": time.strftime("%Y-%m-%d %H:%M:%S %z")}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="target/release/topoccd", help="the topoccd binary to time")
    ap.add_argument("--base", help="an earlier build's topoccd binary, timed alternately")
    ap.add_argument("--selfccd", help="Self-CCD's sequence driver (selfccd_seq), timed alternately")
    ap.add_argument("--selfccd-scale", type=float, default=1.0, help="its --scale (default 1)")
    ap.add_argument("--method", help="topoccd's --method (default: the CLI's default, auto)")
    ap.add_argument("--runs", default="1,2,earliest",
                    help="topoccd runs, comma-separated: 1 (1 thread), 2 (2 threads), "
                         "earliest (1 thread, --earliest); default all three")
    ap.add_argument("--reps", type=int, default=3, help="repetitions (median), default 3")
    ap.add_argument("--substeps", type=int, default=8,
                    help="a scene folder with frames/ is cut into N substeps (default 8)")
    ap.add_argument("--timeout", type=float, default=1800, help="seconds per run (default 1800)")
    ap.add_argument("--scenes", help="a folder holding issue 35's six sequences")
    ap.add_argument("--gen", metavar="DIR", help="write the six sequences into DIR first "
                    "(missing ones only), then time them unless sequences are given")
    ap.add_argument("--data", help="the shared scenes folder (cloth-funnel/, cloth-ball/) for --gen")
    ap.add_argument("--out", help="also write the tables to this markdown file (new file)")
    ap.add_argument("--json", help="also write the raw numbers to this JSON file (new file)")
    ap.add_argument("sequences", nargs="*", help="frame folders, or scene folders with frames/")
    args = ap.parse_args()

    runs = [r.strip() for r in args.runs.split(",") if r.strip()]
    bad = [r for r in runs if r not in RUNS]
    if bad or not runs:
        ap.error(f"--runs: unknown {bad}; choose among {', '.join(RUNS)}")
    if args.reps < 1 or args.substeps < 2:
        ap.error("--reps must be at least 1 and --substeps at least 2")
    for f in (args.out, args.json):
        if f and Path(f).exists():
            ap.error(f"{f} exists; refusing to overwrite it (give a new file)")
    for b in [args.bin, args.base, args.selfccd]:
        if b and not (Path(b).is_file() and os.access(b, os.X_OK)):
            ap.error(f"{b}: not an executable file")
    order = []  # the runs of one repetition, in turn
    for r in runs:
        order.append(r)
        if args.base:
            order.append("base-" + r)
        if r == runs[0] and args.selfccd:
            order.append("self")
    shown = runs + (["self"] if args.selfccd else [])

    problems = []
    if args.gen:
        problems += generate(args.bin, Path(args.gen), data_scenes(args.data), args.timeout)
    given = [Path(s) for s in args.sequences]
    for folder in [args.scenes] + ([args.gen] if args.gen and not given else []):
        if folder:
            for name in SIX:
                p = Path(folder) / name
                if p.is_dir():
                    given.append(p)
                else:
                    problems.append(f"{p}: missing")
    if not given:
        ap.error("no sequence: give frame folders, --scenes DIR or --gen DIR")

    command = shlex.join([sys.executable] + sys.argv)
    info = machine()
    md = [f"# simloop: {len(given)} sequences, {args.reps} repetitions", "",
          f"`{command}`", "",
          f"{info['date']}, {info['host']}, {info['cpus']} CPUs, load average at start "
          f"{info['load_at_start']}. topoccd: `{args.bin}`"
          + (f"; base: `{args.base}`" if args.base else "")
          + (f"; Self-CCD: `{args.selfccd}` (OMP_NUM_THREADS=1, scale {args.selfccd_scale:g})"
             if args.selfccd else "") + ".", ""]
    for p in problems:
        md.append(f"- **problem**: {p}")
    print("\n".join(md), flush=True)

    seqs = []
    with tempfile.TemporaryDirectory(prefix="topoccd-simloop-") as tmp:
        for path in given:
            name = path.name
            if (path / "frames").is_dir():
                origin = f"{path}, its first step cut into {args.substeps} substeps"
                try:
                    path = substepped(path, args.substeps, tmp)
                    name = path.name
                except (SystemExit, OSError, ValueError) as e:
                    seq = Sequence(name, path, origin)
                    seq.errors["all"] = [f"cannot cut into substeps: {e}"]
                    seqs.append(seq)
                    continue
            else:
                origin = None
            seq = Sequence(name, path, origin)
            started = time.monotonic()
            for rep in range(args.reps):
                for run in order:
                    if run == "self":
                        steps, err = run_selfccd(args.selfccd, path, args.selfccd_scale, args.timeout)
                    else:
                        binary = args.base if run.startswith("base-") else args.bin
                        threads, earliest = RUNS[run.removeprefix("base-")]
                        steps, err = run_topoccd(binary, path, threads, earliest, args.method,
                                                 args.timeout)
                    seq.add(run, steps, err)
                    if err:
                        print(f"{name}: {label(run)}, repetition {rep + 1}: {err}",
                              file=sys.stderr, flush=True)
            seq.finish()
            seqs.append(seq)
            detail = detail_table(seq, shown, bool(args.base))
            detail.insert(1, f"({time.monotonic() - started:.0f} s for {args.reps} repetitions)")
            print("\n".join(detail), flush=True)
            md += detail

    sums = [summarize(s) for s in seqs]
    head = ["## Summary", "",
            "Times: the mean over steps 1.. of each step's median over the repetitions, per "
            "step. (×) and Self-CCD / topoccd: Self-CCD's time over topoccd's 1-thread time "
            "(above 1: topoccd is faster). Contacts: summed over all steps, step 0 included; "
            "topoccd's are its 1-thread all-pairs run's."
            + (" new / base: below 1, the new build is faster." if args.base else ""), ""]
    table = summary_table(sums, shown, bool(args.base))
    if "1" in runs:
        table += ["", "Where topoccd's time goes, 1 thread, all pairs: the mean over steps 1.. "
                  "of each step's median (the traversal includes the elementary tests run "
                  "inside it).", ""] + phase_table(seqs)
    print("\n".join(head + table), flush=True)
    md += head + table + [""]
    failures = [(s.name, r, e) for s in seqs for r, es in s.errors.items() for e in es]
    if args.out:
        Path(args.out).write_text("\n".join(md) + "\n")
    if args.json:
        raw = {"command": command, "machine": info, "reps": args.reps, "problems": problems,
               "sequences": [{"name": s.name, "path": str(s.path), "runs": s.reps,
                              "errors": s.errors, "medians": s.medians, "summary": x}
                             for s, x in zip(seqs, sums)]}
        Path(args.json).write_text(json.dumps(raw, indent=1) + "\n")
    if failures or problems:
        print(f"\n{len(failures)} failed runs, {len(problems)} problems (see above)", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
