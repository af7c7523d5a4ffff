"""Record steps and their contacts for the Rerun viewer (https://rerun.io).

Needs ``rerun-sdk`` (``pip install topoccd[rerun]`` pulls in the version whose recordings the
``topoccd`` command's ``--rerun`` also writes). ``import topoccd`` does not import it; this
module does.

In a simulator's own loop::

    import rerun as rr, topoccd, topoccd.rerun

    rec = rr.RecordingStream("my-sim")
    rec.save("contacts.rrd")                  # or rec.spawn() for a live viewer
    ccd = topoccd.Ccd()
    for k, (x0, x1, tris, parents) in enumerate(steps):
        report = ccd.query(x0, x1, tris, parents=parents, geometry=True)
        topoccd.rerun.log_step(k, x0, x1, tris, report, parents=parents, recording=rec)

From the shell, a whole sequence (as ``topoccd run SEQ --rerun OUT.rrd``)::

    python -m topoccd.rerun SEQ -o OUT.rrd

The entities, on the timeline ``step``, all under ``topoccd/`` (the command's layout):

- ``mesh``: the mesh at t=0, with this step's triangles;
- ``contacts/faces``, ``contacts/vertices``, ``contacts/edges``: the colliding features at
  t=0, coloured by time of impact (red at 0, through yellow and green, to blue at 1);
- ``contacts/points``, ``contacts/normals``: each contact's point at its time of impact and
  its normal (the report's geometry, ``geometry=True``), labelled with its pair and time;
- ``earliest``: the earliest contact, marked;
- ``cracks/edges``, ``cracks/vertices``: the edges along the cracks the step opens (both ends
  are a new vertex or its parent), the vertices it adds;
- ``stats/...``: the step's figures as scalars (``seconds/<phase>``, ``candidates/vf``,
  ``candidates/ee``, ``bv_tests``, ``contacts``, ``triangles``);
- ``notes``: one line per step, and a warning when the cap left something out.

The command records the clusters' boxes (``volumes/...``) on request; these helpers do not.
"""

from __future__ import annotations

import argparse
import math
import shutil
import sys
from typing import Any, List, Optional, Sequence, Tuple

import numpy as np

try:
    import rerun as rr
except ImportError as _err:  # pragma: no cover - the message is the point
    raise ImportError(
        "topoccd.rerun needs rerun-sdk: pip install 'topoccd[rerun]' "
        "(or pip install rerun-sdk==0.36.3)"
    ) from _err

__all__ = [
    "log_step",
    "log_report",
    "blueprint",
    "toi_color",
    "RERUN_VERSION",
    "DEFAULT_MAX_PRIMITIVES",
    "main",
]

#: The rerun-sdk version whose recordings the ``topoccd`` command writes too.
RERUN_VERSION = "0.36.3"

#: At most this many primitives (mesh triangles, contacts, crack edges) per step, as the
#: command's ``--rerun-max-primitives``.
DEFAULT_MAX_PRIMITIVES = 1_000_000

_NEUTRAL = (205, 205, 200)
_CRACK = (240, 165, 20)
_EARLIEST = (230, 20, 140)


def blueprint() -> Any:
    """The viewer's layout the command sends as its default: the 3D view beside the plots of
    the figures and the notes, the side panels collapsed. ``rec.send_blueprint(topoccd.rerun.blueprint())`` in a loop of
    your own, or pass it to ``rec.save(path, default_blueprint=...)``."""
    import rerun.blueprint as rrb

    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Spatial3DView(
                name="contacts",
                origin="/topoccd",
                contents=["+ /topoccd/**", "- /topoccd/stats/**", "- /topoccd/notes"],
            ),
            rrb.Vertical(
                rrb.TimeSeriesView(name="seconds by phase", origin="/topoccd/stats/seconds"),
                rrb.TimeSeriesView(
                    name="candidates and contacts",
                    origin="/topoccd/stats",
                    contents=["+ /topoccd/stats/candidates/**", "+ /topoccd/stats/contacts"],
                ),
                rrb.TextLogView(name="notes", origin="/topoccd/notes"),
            ),
            column_shares=[2, 1],
        ),
        rrb.BlueprintPanel(state="collapsed"),
        rrb.SelectionPanel(state="collapsed"),
        rrb.TimePanel(state="collapsed", timeline="step"),
    )


def _oklch(lightness: float, chroma: float, hue_turns: float) -> Tuple[int, int, int]:
    """An OKLCh colour as sRGB bytes (Björn Ottosson's OKLab)."""
    angle = hue_turns * 2.0 * math.pi
    a, b = chroma * math.cos(angle), chroma * math.sin(angle)
    l_ = lightness + 0.3963377774 * a + 0.2158037573 * b
    m_ = lightness - 0.1055613458 * a - 0.0638541728 * b
    s_ = lightness - 0.0894841775 * a - 1.2914855480 * b
    l, m, s = l_**3, m_**3, s_**3
    rgb = (
        4.0767416621 * l - 3.3077115913 * m + 0.2309699292 * s,
        -1.2684380046 * l + 2.6097574011 * m - 0.3413193965 * s,
        -0.0041960863 * l - 0.7034186147 * m + 1.7076147010 * s,
    )

    def gamma(c: float) -> int:
        c = min(max(c, 0.0), 1.0)
        v = 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055
        return int(round(min(max(v, 0.0), 1.0) * 255))

    return (gamma(rgb[0]), gamma(rgb[1]), gamma(rgb[2]))


def toi_color(toi: float) -> Tuple[int, int, int]:
    """The colour of a time of impact: red at t=0 through yellow and green to blue at t=1."""
    t = min(max(float(toi), 0.0), 1.0) if math.isfinite(toi) else 0.0
    return _oklch(0.68, 0.16, 0.08 + 0.62 * t)


def _full_x0(x0: np.ndarray, x1: np.ndarray, parents: Optional[np.ndarray]) -> np.ndarray:
    """Positions at t=0 of every vertex of the step: a new vertex starts at its parent's."""
    n = len(x1)
    if len(x0) >= n:
        return x0[:n]
    out = np.empty((n, 3), dtype=np.float64)
    out[: len(x0)] = x0
    known = np.zeros(n, dtype=bool)
    known[: len(x0)] = True
    if parents is not None and len(parents):
        rows = np.asarray(parents, dtype=np.int64).reshape(-1, 2)
        # Chains (a copy of a copy) resolve in as many passes as they are long.
        for _ in range(len(rows)):
            progress = False
            for child, parent in rows:
                if not known[child] and known[parent]:
                    out[child] = out[parent]
                    known[child] = progress = True
            if known.all() or not progress:
                break
    # A new vertex without a parent does not move.
    out[~known] = x1[~known]
    return out


def _budget_note(kept: int, total: int, what: str, cap: int) -> str:
    return (
        f"{kept} of the step's {total} {what} recorded (the earliest), the cap of {cap} "
        "primitives per step (max_primitives) reached"
    )


def _contacts(report: Any) -> List[tuple]:
    """The report's contacts as ``(toi, kind, ids, index)``, in the report's order."""
    out = []
    for i, ((v, f), t) in enumerate(zip(np.asarray(report.vf).reshape(-1, 2), report.vf_toi)):
        out.append((float(t), 0, (int(v), int(f)), i))
    for i, (e, t) in enumerate(zip(np.asarray(report.ee).reshape(-1, 4), report.ee_toi)):
        out.append((float(t), 1, tuple(int(x) for x in e), i))
    return out


def _label(kind: int, ids: tuple, toi: float) -> str:
    if kind == 0:
        return f"vf {ids[0]}-{ids[1]} t={toi:.6f}"
    return f"ee {ids[0]}-{ids[1]}/{ids[2]}-{ids[3]} t={toi:.6f}"


def _log(recording: Any, path: str, archetype: Any) -> None:
    rr.log(path, archetype, recording=recording)


def log_report(
    x0: Any,
    x1: Any,
    triangles: Any,
    report: Any,
    *,
    parents: Any = None,
    recording: Any = None,
    max_primitives: int = DEFAULT_MAX_PRIMITIVES,
    prefix: str = "topoccd",
) -> List[str]:
    """Logs one report's contacts, earliest contact and figures at the recording's current
    time (the caller sets it, e.g. ``rec.set_time("step", sequence=k)``).

    ``x0``, ``x1``, ``triangles`` and ``parents`` are the step's arrays, as given to
    :meth:`topoccd.Ccd.query`; ``report`` its result (with ``geometry=True`` for the exact
    contact points and normals; without, a contact is drawn at its features' positions at
    its time of impact, with no normal). At most ``max_primitives`` contacts are logged (the
    earliest); returns the notes saying what was left out.
    """
    return _log_report(x0, x1, triangles, report, parents, recording, max_primitives,
                       max_primitives, prefix)


def _log_report(x0: Any, x1: Any, triangles: Any, report: Any, parents: Any, recording: Any,
                budget: int, cap: int, prefix: str) -> List[str]:
    x1 = np.asarray(x1, dtype=np.float64)
    pos0 = _full_x0(np.asarray(x0, dtype=np.float64), x1, parents)
    tris = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    notes: List[str] = []
    lo, hi = (pos0.min(axis=0), pos0.max(axis=0)) if len(pos0) else (np.zeros(3), np.ones(3))
    diagonal = float(np.linalg.norm(hi - lo)) or 1.0
    radius, normal_length = diagonal * 0.002, diagonal * 0.02

    contacts = _contacts(report)
    total = len(contacts)
    if total > budget:
        contacts.sort(key=lambda c: (c[0], c[1], c[2]))
        notes.append(_budget_note(budget, total, "contacts", cap))
        contacts = contacts[:budget]

    def at(v: int, t: float) -> np.ndarray:
        return pos0[v] + (x1[v] - pos0[v]) * t

    faces, face_colors, verts, vert_colors, edges, edge_colors = [], [], [], [], [], []
    points, normals, colors, labels = [], [], [], []
    for toi, kind, ids, i in contacts:
        color = toi_color(toi)
        if kind == 0:
            v, f = ids
            faces.append(pos0[tris[f]])
            face_colors.append(color)
            verts.append(pos0[v])
            vert_colors.append(color)
            if report.vf_point is not None:
                point, normal = report.vf_point[i], report.vf_normal[i]
            else:
                point, normal = at(v, toi), np.zeros(3)
        else:
            a0, a1, b0, b1 = ids
            edges += [pos0[[a0, a1]], pos0[[b0, b1]]]
            edge_colors += [color, color]
            if report.ee_point is not None:
                point, normal = report.ee_point[i], report.ee_normal[i]
            else:
                point = (at(a0, toi) + at(a1, toi) + at(b0, toi) + at(b1, toi)) / 4
                normal = np.zeros(3)
        points.append(point)
        normals.append(np.asarray(normal) * normal_length)
        colors.append(color)
        labels.append(_label(kind, ids, toi))

    def arr(xs: Sequence[Any], shape: Tuple[int, ...]) -> np.ndarray:
        return np.asarray(xs, dtype=np.float32).reshape((-1,) + shape)

    corners = arr(faces, (3, 3)).reshape(-1, 3)
    n = len(faces)
    _log(
        recording,
        f"{prefix}/contacts/faces",
        rr.Mesh3D(
            vertex_positions=corners,
            triangle_indices=np.arange(3 * n, dtype=np.uint32).reshape(-1, 3),
            vertex_colors=np.repeat(np.asarray(face_colors, dtype=np.uint8).reshape(-1, 3), 3, axis=0),
        ),
    )
    _log(recording, f"{prefix}/contacts/vertices",
         rr.Points3D(arr(verts, (3,)), colors=np.asarray(vert_colors, dtype=np.uint8).reshape(-1, 3), radii=radius * 1.5))
    _log(recording, f"{prefix}/contacts/edges",
         rr.LineStrips3D(arr(edges, (2, 3)), colors=np.asarray(edge_colors, dtype=np.uint8).reshape(-1, 3), radii=radius))
    color_array = np.asarray(colors, dtype=np.uint8).reshape(-1, 3)
    _log(recording, f"{prefix}/contacts/points",
         rr.Points3D(arr(points, (3,)), colors=color_array, radii=radius, labels=labels, show_labels=False))
    _log(recording, f"{prefix}/contacts/normals",
         rr.Arrows3D(origins=arr(points, (3,)), vectors=arr(normals, (3,)), colors=color_array))

    earliest = getattr(report, "earliest", None)
    if earliest is not None:
        kind = 0 if earliest[0] == "vf" else 1
        ids, toi = tuple(int(x) for x in earliest[1:-1]), float(earliest[-1])
        match = [i for t, k, c, i in _contacts(report) if k == kind and c == ids]
        if match and kind == 0 and report.vf_point is not None:
            point = report.vf_point[match[0]]
        elif match and kind == 1 and report.ee_point is not None:
            point = report.ee_point[match[0]]
        elif kind == 0:
            point = at(ids[0], toi)
        else:
            point = sum(at(v, toi) for v in ids) / 4
        _log(recording, f"{prefix}/earliest",
             rr.Points3D(arr([point], (3,)), colors=_EARLIEST, radii=radius * 4,
                         labels=["earliest: " + _label(kind, ids, toi)]))
    else:
        _log(recording, f"{prefix}/earliest", rr.Points3D(np.zeros((0, 3), dtype=np.float32)))

    seconds, stats = dict(report.seconds), dict(report.stats)
    for phase in ("total", "build", "traverse", "narrow", "clustering", "merging"):
        if seconds.get(phase) is not None:
            _log(recording, f"{prefix}/stats/seconds/{phase}", rr.Scalars(float(seconds[phase])))
    _log(recording, f"{prefix}/stats/candidates/vf", rr.Scalars(float(stats.get("vf_tests", 0))))
    _log(recording, f"{prefix}/stats/candidates/ee", rr.Scalars(float(stats.get("ee_tests", 0))))
    _log(recording, f"{prefix}/stats/bv_tests", rr.Scalars(float(stats.get("bv_tests", 0))))
    _log(recording, f"{prefix}/stats/contacts", rr.Scalars(float(total)))
    _log(recording, f"{prefix}/stats/triangles", rr.Scalars(float(len(tris))))
    return notes


def _crack_edges(triangles: np.ndarray, parents: Optional[np.ndarray]) -> np.ndarray:
    """The edges whose two ends are a new vertex or its parent: along the fresh cracks."""
    if parents is None or len(parents) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    split = np.unique(np.asarray(parents, dtype=np.int64).reshape(-1))
    e = triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    e = np.sort(e[np.isin(e[:, 0], split) & np.isin(e[:, 1], split)], axis=1)
    return np.unique(e, axis=0)


def log_step(
    step: int,
    x0: Any,
    x1: Any,
    triangles: Any,
    report: Any,
    *,
    parents: Any = None,
    recording: Any = None,
    max_primitives: int = DEFAULT_MAX_PRIMITIVES,
    summary: Optional[str] = None,
) -> List[str]:
    """Logs step ``step`` on the timeline ``step``: the mesh at t=0 with the step's triangles,
    the fresh cracks, then :func:`log_report`. Returns the notes saying what the cap of
    ``max_primitives`` per step (mesh triangles, contacts, crack edges) left out; they are
    logged as warnings in ``topoccd/notes`` too.
    """
    if recording is None:
        rr.set_time("step", sequence=int(step))
    else:
        recording.set_time("step", sequence=int(step))
    x1 = np.asarray(x1, dtype=np.float64)
    pos0 = _full_x0(np.asarray(x0, dtype=np.float64), x1, parents)
    tris = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    budget = max_primitives
    notes: List[str] = []
    if len(tris) <= budget:
        budget -= len(tris)
        mesh = rr.Mesh3D(
            vertex_positions=pos0.astype(np.float32),
            triangle_indices=tris.astype(np.uint32),
            albedo_factor=_NEUTRAL,
        )
    else:
        notes.append(
            f"the mesh ({len(tris)} triangles) is over the cap of {max_primitives} primitives "
            "per step (max_primitives): not recorded"
        )
        mesh = rr.Mesh3D(
            vertex_positions=np.zeros((0, 3), dtype=np.float32),
            triangle_indices=np.zeros((0, 3), dtype=np.uint32),
        )
    _log(recording, "topoccd/mesh", mesh)
    contacts = len(report.vf_toi) + len(report.ee_toi)
    notes += _log_report(x0, x1, tris, report, parents, recording, budget, max_primitives,
                         "topoccd")
    budget -= min(contacts, budget)
    cracks = _crack_edges(tris, parents)
    if len(cracks) > budget:
        notes.append(
            f"{budget} of the {len(cracks)} crack edges recorded: the cap of {max_primitives} "
            "primitives per step (max_primitives) reached"
        )
        cracks = cracks[:budget]
    _log(recording, "topoccd/cracks/edges",
         rr.LineStrips3D(pos0[cracks].astype(np.float32).reshape(-1, 2, 3), colors=_CRACK))
    new = np.asarray(parents, dtype=np.int64).reshape(-1, 2)[:, 0] if parents is not None else []
    _log(recording, "topoccd/cracks/vertices",
         rr.Points3D(pos0[np.asarray(new, dtype=np.int64)].astype(np.float32).reshape(-1, 3), colors=_CRACK))
    text = summary if summary is not None else (
        f"{len(report.vf_toi)} vf and {len(report.ee_toi)} ee contacts, earliest toi "
        f"{report.earliest_toi}"
    )
    _log(recording, "topoccd/notes", rr.TextLog(f"step {step}: {text}", level=rr.TextLogLevel.INFO))
    for note in notes:
        _log(recording, "topoccd/notes", rr.TextLog(f"step {step}: {note}", level=rr.TextLogLevel.WARN))
    return notes


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m topoccd.rerun SEQ [-o OUT.rrd]``: records every step of a sequence."""
    import topoccd

    parser = argparse.ArgumentParser(
        prog="python -m topoccd.rerun",
        description="Record every step of a frame sequence for the Rerun viewer.",
    )
    parser.add_argument("seq", help="folder of frames (0000.ply, 0001.ply, ... and .parents)")
    parser.add_argument("-o", "--out", help="write this .rrd file (default: spawn a viewer)")
    parser.add_argument("--method", default="auto", choices=["auto", "bvh", "cluster", "brute"])
    parser.add_argument("--max-primitives", type=int, default=DEFAULT_MAX_PRIMITIVES)
    args = parser.parse_args(argv)
    if args.max_primitives < 1:
        parser.error("--max-primitives must be at least 1")
    try:
        seq = topoccd.read_sequence(args.seq)
    except (OSError, ValueError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    rec = rr.RecordingStream("topoccd", recording_id=None)
    if args.out:
        if not args.out.lower().endswith(".rrd"):
            print(f"error: {args.out}: -o takes a file ending in .rrd", file=sys.stderr)
            return 2
        try:
            with open(args.out, "ab"):
                pass
            rec.save(args.out, default_blueprint=blueprint())
        except OSError as err:
            print(f"error: {args.out}: cannot write the recording: {err}", file=sys.stderr)
            return 2
    else:
        if shutil.which("rerun") is None:
            print(
                "error: without -o the recording goes to a Rerun viewer, but no `rerun` is on the "
                f"PATH: pip install rerun-sdk=={RERUN_VERSION} provides it; or write a file with "
                "-o OUT.rrd",
                file=sys.stderr,
            )
            return 2
        rec.spawn(default_blueprint=blueprint())
    ccd = topoccd.Ccd()
    warned = False
    try:
        for k, (x0, x1, tris, parents) in enumerate(seq):
            report = ccd.query(x0, x1, tris, parents=parents, method=args.method, geometry=True)
            notes = log_step(k, x0, x1, tris, report, parents=parents, recording=rec,
                             max_primitives=args.max_primitives)
            print(f"step {k:04}: {len(report.vf)} vf and {len(report.ee)} ee contacts, "
                  f"earliest toi {report.earliest_toi}")
            if notes and not warned:
                warned = True
                print(f"warning: step {k}: {'; '.join(notes)}", file=sys.stderr)
    except (OSError, ValueError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    finally:
        rec.flush()
        if args.out:
            rec.disconnect()
    return 0


if __name__ == "__main__":
    sys.exit(main())
