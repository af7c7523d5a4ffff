"""Every step of a long frame sequence, spread over Ray tasks (or a local process pool).

The steps of a sequence are independent once the frames are on disk, so a run of consecutive
steps is one task: :func:`process_steps` reads each step's two frames (and the parents file of
the second), runs the query with one :class:`topoccd.Ccd` kept across the run (so each step
benefits from the last, as in ``topoccd run``: the tree refitted while the triangles stay the
same, the last step's clusters offered again), writes each step's pairs file
``OUT_DIR/NNNN.csv`` (the format of ``topoccd run --pairs-dir``) and returns the steps' JSON
lines (the keys of ``topoccd run --json``). It is a plain function of plain arguments, so any
engine can call it: :func:`run_sequence` maps it over Ray tasks (``engine="ray"``) or a
``concurrent.futures`` process pool (``engine="process"``), gathers the lines in step order
with a progress bar, and writes ``OUT_DIR/steps.jsonl``. The answers are those of
``topoccd run``, whatever the runs' length.

On a cluster (``address="ray://head:10001"`` or ``"auto"``) every node needs ``topoccd``
installed, and the frame folder and ``out_dir`` must be on a file system all nodes see under
the same path (NFS, Lustre, a mounted bucket): a task reads two frames and writes one small
file, and only the JSON line travels back to the driver.

Example::

    from topoccd.batch import run_sequence
    result = run_sequence("frames/", "pairs/", workers=8, method="cluster")
    print(result.summary)          # steps, contacts, earliest toi, seconds
    for line in result.failed:     # steps that could not be processed, with their frames
        print(line["step"], line["frames"], line["error"])

Tasks of ``steps_per_task`` consecutive steps (default: the steps spread evenly over the
workers, at most 16 a task) keep the everyday step's gains; shorter runs balance the load
better, and a crashed worker loses only its run.
"""

import json
import os
import sys
import time
import traceback
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, Iterable, List, Optional

from ._topoccd import DEFAULT_MAX_CONTACTS, Ccd, read_sequence

__all__ = ["process_step", "process_steps", "run_sequence", "BatchResult", "QUERY_OPTIONS"]

#: The longest run of steps that :func:`run_sequence` gives one task by default.
MAX_STEPS_PER_TASK = 16

#: The keyword options of :meth:`topoccd.Ccd.query` that :func:`run_sequence` passes on.
QUERY_OPTIONS = (
    "method",
    "mode",
    "tolerance",
    "min_distance",
    "tmax",
    "max_iterations",
    "k",
    "growth",
    "crack_filter",
    "threads",
    "max_contacts",
    "timeout",
)


def pairs_path(out_dir: str, k: int) -> str:
    """The pairs file of step ``k``: ``OUT_DIR/NNNN.csv`` (NNNN: the step's first frame)."""
    return os.path.join(out_dir, f"{k:04d}.csv")


def _step_line(ccd: Ccd, folder: str, k: int, out_dir: str, options: Dict[str, Any]) -> dict:
    """Step ``k`` with ``ccd``: reads its frames, queries, writes its pairs, returns its line."""
    started = time.perf_counter()
    sequence = read_sequence(folder)
    x0, x1, triangles, parents = sequence[k]
    read_seconds = time.perf_counter() - started
    report = ccd.query(x0, x1, triangles, parents=parents, **options)
    path = pairs_path(out_dir, k)
    report.write_pairs(path)
    line = {
        "step": k,
        "vertices": int(report.stats["vertices"]),
        "triangles": int(report.stats["triangles"]),
        "method": options.get("method", "auto"),
        "mode": options.get("mode", "all"),
        "vf": int(len(report.vf)),
        "ee": int(len(report.ee)),
        "unresolved": report.unresolved,
        "earliest_toi": report.earliest_toi,
        "earliest": None if report.earliest is None else list(report.earliest),
        "seconds": dict(report.seconds),
        "stats": {key: report.stats[key] for key in ("bv_tests", "vf_tests", "ee_tests")},
    }
    if "cluster" in report.stats:
        line["clusters"] = dict(report.stats["cluster"])
    line["pairs"] = path
    line["read_seconds"] = read_seconds
    return line


def process_steps(
    folder: str, first: int, count: int, out_dir: str, options: Optional[Dict[str, Any]] = None
) -> List[dict]:
    """Processes steps ``first`` to ``first + count - 1`` of the sequence in ``folder`` with
    one :class:`topoccd.Ccd` kept across them: one task of :func:`run_sequence`.

    For each step ``k``: reads frames ``k`` and ``k + 1`` (and frame ``k + 1``'s parents file),
    runs :meth:`topoccd.Ccd.query` with ``options``, writes the pairs to ``OUT_DIR/NNNN.csv``
    in the format of ``topoccd run --pairs-dir``, and makes the step's JSON line, with the keys
    of ``topoccd run --json``: ``step``, ``vertices``, ``triangles``, ``method``, ``mode``,
    ``vf``, ``ee``, ``unresolved``, ``earliest_toi``, ``earliest`` (``["vf", vertex, face,
    toi]`` or ``["ee", a0, a1, b0, b1, toi]``), ``seconds``, ``stats`` (and ``clusters`` with
    ``method="cluster"``), plus ``pairs`` (the file written) and ``read_seconds``.

    A step that fails (an unreadable frame, an invalid step) gives a line with ``error``,
    ``frames`` and ``traceback`` instead, and the run goes on with the next step.

    Engine-agnostic: plain arguments, a list of plain ``dict`` back, no global state; call it
    from Ray, Dask, a process pool or a loop.

    Returns:
        list of dict: the steps' lines, in step order.
    """
    options = dict(options or {})
    ccd = Ccd()
    lines = []
    for k in range(first, first + count):
        try:
            lines.append(_step_line(ccd, folder, k, out_dir, options))
        except Exception as err:  # noqa: BLE001 - any failure of one step is reported, not raised
            lines.append(_failure(folder, k, err, traceback.format_exc(limit=3)))
    return lines


def process_step(folder: str, k: int, out_dir: str, options: Optional[Dict[str, Any]] = None) -> dict:
    """Processes step ``k`` alone with a fresh :class:`topoccd.Ccd`: :func:`process_steps`
    with a run of one step, except that a failure raises (what :func:`topoccd.read_sequence`
    and :meth:`topoccd.Ccd.query` raise) instead of returning an error line."""
    return _step_line(Ccd(), folder, k, out_dir, dict(options or {}))


def _failure(folder: str, k: int, err: BaseException, trace: str = "") -> dict:
    try:
        frames = read_sequence(folder).frames[k : k + 2]
    except Exception:  # noqa: BLE001 - the folder itself may be the problem
        frames = [os.path.join(folder, f"{k:04d}.*"), os.path.join(folder, f"{k + 1:04d}.*")]
    return {
        "step": k,
        "error": f"{type(err).__name__}: {err}",
        "frames": frames,
        "traceback": trace,
    }


@dataclass
class BatchResult:
    """What :func:`run_sequence` returns.

    Attributes:
        lines: one dict per step, in step order (a failed step's dict has ``error`` and
            ``frames`` instead of the counts).
        failed: the failed steps' dicts.
        summary: ``steps``, ``steps_with_contacts``, ``vf``, ``ee``, ``earliest_toi``,
            ``query_seconds`` (sum over the steps), ``wall_seconds``, ``failed``, ``engine``,
            ``workers``, ``steps_per_task``.
        jsonl: the path of ``steps.jsonl``.
    """

    lines: List[dict]
    failed: List[dict] = field(default_factory=list)
    summary: Dict[str, Any] = field(default_factory=dict)
    jsonl: str = ""


class _Progress:
    """tqdm when installed, else a counter on stderr."""

    def __init__(self, total: int, enabled: bool) -> None:
        self.total, self.done, self.enabled, self.bar = total, 0, enabled, None
        if enabled:
            try:
                from tqdm import tqdm

                self.bar = tqdm(total=total, desc="steps", unit="step", file=sys.stderr)
            except ImportError:
                self.bar = None

    def update(self) -> None:
        self.done += 1
        if self.bar is not None:
            self.bar.update(1)
        elif self.enabled:
            end = "\n" if self.done == self.total else ""
            print(f"\rsteps {self.done}/{self.total}", end=end, file=sys.stderr, flush=True)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _check_options(options: Dict[str, Any]) -> None:
    """Raises OptionsError (or TypeError) now rather than in every task."""
    import numpy as np

    unknown = set(options) - set(QUERY_OPTIONS)
    if unknown:
        raise TypeError(f"run_sequence() got unknown query options {sorted(unknown)}")
    empty = np.zeros((0, 3))
    Ccd().query(empty, empty, np.zeros((0, 3), dtype=np.int64), **options)


def _runs(steps: int, per_task: int) -> List[range]:
    """The steps cut into runs of ``per_task`` consecutive steps (the last may be shorter)."""
    return [range(k, min(k + per_task, steps)) for k in range(0, steps, per_task)]


def _run_ray(
    folder: str,
    out_dir: str,
    runs: List[range],
    options: Dict[str, Any],
    address: Optional[str],
    workers: Optional[int],
    cpus_per_task: float,
    on_done: Callable[[range, List[dict]], None],
) -> None:
    try:
        import ray
    except ImportError as err:
        raise ImportError(
            "engine='ray' needs Ray: pip install 'topoccd[ray]' (or use engine='process')"
        ) from err
    if not ray.is_initialized():
        if address is None:
            ray.init(num_cpus=workers, include_dashboard=False, logging_level="warning")
        else:
            ray.init(address=address, logging_level="warning")
    task = ray.remote(num_cpus=cpus_per_task, max_retries=0)(process_steps)
    pending = {
        task.remote(folder, run.start, len(run), out_dir, options): run for run in runs
    }
    try:
        while pending:
            done, _ = ray.wait(list(pending), num_returns=1)
            for ref in done:
                run = pending.pop(ref)
                try:
                    lines = ray.get(ref)
                except Exception as err:  # noqa: BLE001 - a crashed worker loses only its run
                    lines = [_failure(folder, k, err) for k in run]
                on_done(run, lines)
    except KeyboardInterrupt:
        # Ctrl-C: the tasks still running or queued are cancelled, not waited for.
        for ref in pending:
            ray.cancel(ref, force=True)
        raise


_MAIN_GUARD = (
    "engine='process' starts its workers by importing the script that calls run_sequence, "
    "which then runs again in every worker: put the call under "
    "`if __name__ == \"__main__\":` (see the multiprocessing guide, 'Safe importing of main "
    "module'), or use engine='ray'"
)


def _guards_main(test: "Any") -> bool:
    """Whether an ``if`` test reads ``__name__ == "__main__"`` (either way round)."""
    import ast

    if not (isinstance(test, ast.Compare) and len(test.ops) == 1):
        return False
    if not isinstance(test.ops[0], ast.Eq):
        return False
    sides = [test.left, test.comparators[0]]
    names = [s.id for s in sides if isinstance(s, ast.Name)]
    texts = [s.value for s in sides if isinstance(s, ast.Constant)]
    return names == ["__name__"] and texts == ["__main__"]


def _unguarded_call() -> Optional[str]:
    """Where the script run as ``__main__`` calls into this module at its top level outside an
    ``if __name__ == "__main__":`` block (``"script.py:12"``), or ``None``: a spawned worker
    would import the script and call again. Scripts only (an interactive session or ``-c`` is
    not re-run)."""
    import ast
    import inspect

    frame = inspect.currentframe()
    top = None
    while frame is not None:
        if frame.f_code.co_name == "<module>" and frame.f_globals.get("__name__") in (
            "__main__",
            "__mp_main__",
        ):
            top = frame
        frame = frame.f_back
    if top is None:
        return None
    path = top.f_globals.get("__file__")
    line = top.f_lineno
    if not path or not os.path.isfile(path):
        return None
    try:
        with open(path, encoding="utf-8") as source:
            tree = ast.parse(source.read(), path)
    except (OSError, SyntaxError, ValueError):
        return None
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and _guards_main(node.test):
            end = getattr(node, "end_lineno", None) or line
            if node.lineno <= line <= end:
                return None
    return f"{path}:{line}"


def _require_main_guard() -> None:
    """Raises a clear error where ``engine="process"`` would re-run the calling script in
    every worker: called from a script's top level outside ``if __name__ == "__main__":``, or
    from a worker importing such a script."""
    import multiprocessing

    main = getattr(sys.modules.get("__main__"), "__name__", "")
    if multiprocessing.parent_process() is not None and main == "__mp_main__":
        # A worker importing the script: starting a pool here would recurse.
        raise RuntimeError(f"run_sequence was called while a worker process started: {_MAIN_GUARD}")
    where = _unguarded_call()
    if where is not None:
        raise RuntimeError(
            f"{where}: run_sequence(engine='process') outside a main guard: {_MAIN_GUARD}"
        )


def _run_processes(
    folder: str,
    out_dir: str,
    runs: List[range],
    options: Dict[str, Any],
    workers: Optional[int],
    on_done: Callable[[range, List[dict]], None],
) -> None:
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    # spawn, not fork: a forked child would inherit a thread pool without its threads.
    context = multiprocessing.get_context("spawn")
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=context)
    try:
        _collect_processes(pool, folder, out_dir, runs, options, on_done)
    except KeyboardInterrupt:
        # Ctrl-C: queued runs are dropped and the workers ended, not waited for (a step
        # without a timeout could run for long).
        workers_alive = list(getattr(pool, "_processes", {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for process in workers_alive:
            process.kill()
        for process in workers_alive:
            process.join(1.0)
        raise
    except BaseException:
        pool.shutdown(wait=True)
        raise
    pool.shutdown(wait=True)


def _collect_processes(
    pool: "Any",
    folder: str,
    out_dir: str,
    runs: List[range],
    options: Dict[str, Any],
    on_done: Callable[[range, List[dict]], None],
) -> None:
    """Submits the runs to the process pool and hands each one's lines to ``on_done``."""
    from concurrent.futures import as_completed
    from concurrent.futures.process import BrokenProcessPool

    futures = {
        pool.submit(process_steps, folder, run.start, len(run), out_dir, options): run
        for run in runs
    }
    for future in as_completed(futures):
        run = futures[future]
        try:
            lines = future.result()
        except BrokenProcessPool as err:
            raise RuntimeError(
                f"the worker processes of engine='process' died ({err}); if the calling "
                f"script has no main guard: {_MAIN_GUARD}"
            ) from err
        except Exception as err:  # noqa: BLE001 - a crashed worker loses only its run
            lines = [_failure(folder, k, err) for k in run]
        on_done(run, lines)


def run_sequence(
    folder: "str | os.PathLike[str]",
    out_dir: "str | os.PathLike[str]",
    *,
    engine: str = "ray",
    address: Optional[str] = None,
    workers: Optional[int] = None,
    cpus_per_task: int = 1,
    steps_per_task: Optional[int] = None,
    progress: bool = True,
    method: str = "auto",
    mode: str = "all",
    tolerance: float = 1e-6,
    min_distance: float = 0.0,
    tmax: float = 1.0,
    max_iterations: int = 1_000_000,
    k: int = 18,
    growth: Optional[str] = None,
    crack_filter: bool = True,
    max_contacts: Optional[int] = DEFAULT_MAX_CONTACTS,
    timeout: Optional[float] = None,
) -> BatchResult:
    """Processes every step of a frame sequence in parallel; writes one pairs file per step
    and ``OUT_DIR/steps.jsonl``.

    Args:
        folder: the sequence (``0000.ply``, ``0001.ply``, ... and ``NNNN.parents`` files); on a
            cluster, a path every node can read.
        out_dir: where ``NNNN.csv`` (the pairs of step NNNN, as ``topoccd run --pairs-dir``)
            and ``steps.jsonl`` go; created if missing; on a cluster, writable by every node.
        engine: ``"ray"`` (Ray tasks) or ``"process"`` (a local process pool, no Ray).
        address: Ray only: ``None`` starts a local Ray instance (unless one is already
            initialised, which is then used as it is); ``"auto"`` or ``"ray://HOST:10001"``
            joins a cluster.
        workers: parallel tasks: the CPUs of a local Ray instance, or the process pool's size
            (default: the core count). Ignored when joining a cluster (its size decides).
        cpus_per_task: CPUs reserved by each Ray task, and the threads each query uses.
        steps_per_task: consecutive steps per task, each task keeping one
            :class:`topoccd.Ccd` across its steps (so each step benefits from the last, as in
            ``topoccd run``). Default: the steps spread evenly over ``workers`` (or the core
            count), at most ``MAX_STEPS_PER_TASK`` (16) a task. The results do not depend
            on it.
        progress: show a progress bar (tqdm if installed, else a counter on stderr).
        method, mode, tolerance, min_distance, tmax, max_iterations, k, growth,
            crack_filter, max_contacts, timeout: as in :meth:`topoccd.Ccd.query`, for each
            step (``max_contacts`` defaults to one million per step, ``None`` for no cap;
            ``timeout`` is per step, and a step that times out is a failed step).

    Returns:
        BatchResult: the steps' lines in step order, the failed steps and a summary. A step
        that fails (unreadable frame, invalid step, crashed worker) is reported with its two
        frames and its error, in ``failed`` and in ``steps.jsonl``; the other steps are kept.

    Raises:
        OptionsError: an invalid option (checked once, before any task starts).
        OSError, FormatError: the folder cannot be listed or is not a sequence.
        RuntimeError: ``engine="process"`` called from a script's top level without
            ``if __name__ == "__main__":`` (every worker would run the script again), or its
            workers could not start.
    """
    options: Dict[str, Any] = {
        "method": method,
        "mode": mode,
        "tolerance": tolerance,
        "min_distance": min_distance,
        "tmax": tmax,
        "max_iterations": max_iterations,
        "k": k,
        "growth": growth,
        "crack_filter": crack_filter,
        "threads": int(cpus_per_task),
        "max_contacts": max_contacts,
        "timeout": timeout,
    }
    _check_options(options)
    if engine == "process":
        _require_main_guard()
    folder = os.path.abspath(os.fspath(folder))
    out_dir = os.path.abspath(os.fspath(out_dir))
    steps = len(read_sequence(folder))
    if steps_per_task is None:
        slots = workers or os.cpu_count() or 1
        steps_per_task = max(1, min(MAX_STEPS_PER_TASK, -(-steps // slots)))
    elif not (isinstance(steps_per_task, int) and steps_per_task >= 1):
        raise ValueError(f"steps_per_task must be an integer >= 1, got {steps_per_task!r}")
    runs = _runs(steps, steps_per_task)
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise NotADirectoryError(f"{out_dir}: exists and is not a folder")
    os.makedirs(out_dir, exist_ok=True)

    started = time.perf_counter()
    lines: List[Optional[dict]] = [None] * steps
    bar = _Progress(steps, progress)

    def on_done(run: range, run_lines: List[dict]) -> None:
        for k, line in zip(run, run_lines):
            lines[k] = line
            if "error" in line:
                print(
                    f"topoccd.batch: step {k} failed ({' -> '.join(map(str, line['frames']))}): "
                    f"{line['error']}",
                    file=sys.stderr,
                )
            bar.update()

    try:
        if engine == "ray":
            _run_ray(folder, out_dir, runs, options, address, workers, cpus_per_task, on_done)
        elif engine == "process":
            _run_processes(folder, out_dir, runs, options, workers, on_done)
        else:
            raise ValueError(f"engine must be 'ray' or 'process', got {engine!r}")
    finally:
        bar.close()
    wall = time.perf_counter() - started

    done = [line for line in lines if line is not None]
    failed = [line for line in done if "error" in line]
    good = [line for line in done if "error" not in line]
    tois = [line["earliest_toi"] for line in good if line["earliest_toi"] is not None]
    summary = {
        "steps": steps,
        "steps_with_contacts": sum(1 for line in good if line["vf"] + line["ee"] > 0),
        "vf": sum(line["vf"] for line in good),
        "ee": sum(line["ee"] for line in good),
        "earliest_toi": min(tois) if tois else None,
        "query_seconds": sum(line["seconds"]["total"] for line in good),
        "wall_seconds": wall,
        "failed": len(failed),
        "engine": engine,
        "workers": workers,
        "steps_per_task": steps_per_task,
    }
    jsonl = os.path.join(out_dir, "steps.jsonl")
    _write_jsonl(jsonl, done, summary)
    return BatchResult(lines=done, failed=failed, summary=summary, jsonl=jsonl)


def _write_jsonl(path: str, lines: Iterable[dict], summary: dict) -> None:
    with open(path, "w", encoding="utf-8") as out:
        for line in lines:
            out.write(json.dumps({key: v for key, v in line.items() if key != "traceback"}))
            out.write("\n")
        out.write(json.dumps({"summary": summary}))
        out.write("\n")
