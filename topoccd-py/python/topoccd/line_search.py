"""Line-search helpers in the shape of the IPC toolkit's: how far along a step the mesh may move
without contact, and whether a whole step is free of contact.

Both run one ``mode="earliest"`` query. Pass ``ccd=`` a :class:`topoccd.Ccd` kept across the
simulation so that its buffers are reused.
"""

import warnings
from typing import NamedTuple, Optional, Tuple, Union

import numpy as np

from ._topoccd import Ccd, InputError, OptionsError, intersecting_triangles

__all__ = ["collision_free_stepsize", "is_step_collision_free", "Earliest"]

#: Old keyword names, accepted for one release with a ``DeprecationWarning``.
DEPRECATED_KEYWORDS = {"min_separation": "min_distance", "t_max": "tmax", "rescaling": "conservative_rescaling"}


def renamed_keywords(function: str, given: dict, deprecated: dict) -> dict:
    """``given`` (the new names' values) updated from ``deprecated`` (old names), each old name
    warned about once; a keyword that is neither is a ``TypeError``, as Python's own."""
    for old, value in deprecated.items():
        new = DEPRECATED_KEYWORDS.get(old)
        if new is None or new not in given:
            raise TypeError(f"{function}() got an unexpected keyword argument {old!r}")
        warnings.warn(
            f"{function}(): the keyword {old!r} is deprecated, use {new!r} "
            "(the IPC toolkit's name; the old one goes in the next release)",
            DeprecationWarning,
            stacklevel=3,
        )
        given[new] = value
    return given


class Earliest(NamedTuple):
    """The earliest contact of a step, as :func:`collision_free_stepsize` returns it with
    ``return_earliest=True``.

    Attributes:
        kind: ``"vf"`` (a vertex and a face), ``"ee"`` (two edges), ``"ve"`` (a free point and
            an edge) or ``"vv"`` (two free points).
        indices: ``(vertex, face)``, ``(a0, a1, b0, b1)``, ``(vertex, e0, e1)`` or ``(a, b)``,
            as in ``Report.vf``, ``Report.ee``, ``Report.ve`` and ``Report.vv``.
        toi: its time of impact (never later than the contact).
        certainty: 0 resolved, 1 iteration limit, 2 invalid input (see ``topoccd.CERTAINTY``):
            not 0 means the search gave up and ``toi`` is only a lower bound.
    """

    kind: str
    indices: Tuple[int, ...]
    toi: float
    certainty: int


def _earliest_of(report) -> Optional[Earliest]:
    if report.earliest is None:
        return None
    kind, *rest = report.earliest
    indices, toi = tuple(int(i) for i in rest[:-1]), float(rest[-1])
    pairs, codes = {
        "vf": (report.vf, report.vf_certainty),
        "ee": (report.ee, report.ee_certainty),
        "ve": (report.ve, report.ve_certainty),
        "vv": (report.vv, report.vv_certainty),
    }[kind]
    row = np.flatnonzero((pairs == np.asarray(indices)).all(axis=1))
    certainty = int(codes[row[0]]) if len(row) else 0
    return Earliest(kind, indices, toi, certainty)


def _earliest_query(x0, x1, triangles, ccd, check_start, parents, **options):
    if check_start:
        # The t=0 positions of the vertices that exist then; a new vertex of a topology change
        # starts on its parent, which the check joins to it (as the query's crack filter does).
        start = np.asarray(x0, dtype=np.float64)
        n1 = len(np.asarray(x1))
        if parents is not None and len(np.asarray(parents)) and n1 > len(start):
            rows = np.asarray(parents, dtype=np.int64).reshape(-1, 2)
            full = np.array(x1, dtype=np.float64)  # a new vertex without a parent does not move
            full[: len(start)] = start
            new = rows[rows[:, 0] >= len(start)]
            full[new[:, 0]] = start[new[:, 1]]
            pairs = intersecting_triangles(full, triangles, parents=rows)
        else:
            pairs = intersecting_triangles(start, triangles)
        if len(pairs):
            a, b = (int(i) for i in pairs[0])
            raise InputError(
                f"triangles {a} and {b} intersect at t=0 ({len(pairs)} intersecting pairs): the step "
                "starts in contact (check_start=True)"
            )
    ccd = Ccd() if ccd is None else ccd
    return ccd.query(x0, x1, triangles, mode="earliest", parents=parents, **options)


def _at_zero(report) -> bool:
    """Whether the query stopped on its cap: in ``mode="earliest"`` it does so only once it
    knows the earliest time is 0 (its kept pairs may then lie within the tolerance of 0)."""
    return report.truncated is not None and report.truncated["reason"] == "max_contacts"


def collision_free_stepsize(
    x0,
    x1,
    triangles,
    *,
    min_distance: float = 0.0,
    conservative_rescaling: float = 0.8,
    ccd: Optional[Ccd] = None,
    parents=None,
    groups=None,
    edges=None,
    method: str = "auto",
    tolerance: float = 1e-6,
    tmax: float = 1.0,
    max_iterations: int = 1_000_000,
    threads: Optional[int] = None,
    max_contacts: Optional[int] = 1,
    timeout: Optional[float] = None,
    check_start: bool = False,
    return_earliest: bool = False,
    **deprecated,
) -> Union[float, Tuple[float, Optional[Earliest]]]:
    """The fraction of the step from ``x0`` to ``x1`` that the mesh may take without contact.

    It is ``conservative_rescaling`` times the earliest time of impact (features closer than
    ``min_distance`` count as touching), or ``tmax`` when nothing comes that close over
    ``[0, tmax]``. It is 0 when features already touch at the start.

    Triangles that already pass through each other at t=0 are not a contact of the step
    unless a vertex-face or edge-edge pair touches during it: without ``check_start`` such a
    start can give ``tmax``. ``check_start=True`` runs the exact static check
    (:func:`topoccd.intersecting_triangles`) on the t=0 positions first and raises
    :class:`InputError` naming a pair.

    Args:
        x0, x1, triangles, parents, groups, edges, method, tolerance, tmax, max_iterations,
            threads, timeout: as in :meth:`topoccd.Ccd.query` (``edges``: free edges, in no
            triangle, for rods and hair; vertices in neither are free points). ``timeout`` raises
            ``TimeoutError`` (no step size is safe from a query cut short).
        max_contacts: the pairs the query keeps at its earliest time. Default 1: only the
            earliest contact matters, and the query stops as soon as it proves one at time 0
            (the answer is then 0), so a collapsed step answers at once. The earliest time
            stays exact for any cap.
        min_distance: the minimum separation, in coordinate units, >= 0.
        conservative_rescaling: the fraction of the earliest time returned, in (0, 1]. Default 0.8, the
            IPC toolkit's conservative rescaling: the step stops short of the contact.
        ccd: a :class:`topoccd.Ccd` to run the query (a fresh one by default).
        check_start: refuse a start where triangles intersect (default False).
        return_earliest: also return the earliest contact, an :class:`Earliest` or ``None``,
            so that a simulator can stop the touching vertices without a second query.

    The old keywords ``min_separation``, ``t_max`` and ``rescaling`` still work for one
    release, with a ``DeprecationWarning``.

    Returns:
        float: the step fraction, in ``[0, tmax]``; with ``return_earliest=True``, the tuple
        ``(alpha, earliest)``.

    Raises:
        InputError, OptionsError, TimeoutError: as :meth:`topoccd.Ccd.query`; OptionsError also
        for a ``conservative_rescaling`` out of range; InputError for an intersecting start
        with ``check_start=True``.

    Example: a triangle falls through a fixed one; first contact at t=0.5.
        >>> import numpy as np, topoccd
        >>> fixed = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
        >>> falling = np.array([[0.2, 0.2, 1], [0.3, 0.2, 1], [0.2, 0.3, 1]])
        >>> x0 = np.vstack([fixed, falling]); x1 = np.vstack([fixed, falling - [0, 0, 2]])
        >>> alpha = topoccd.collision_free_stepsize(x0, x1, [[0, 1, 2], [3, 4, 5]])
        >>> round(alpha, 4)
        0.4
        >>> alpha, earliest = topoccd.collision_free_stepsize(
        ...     x0, x1, [[0, 1, 2], [3, 4, 5]], return_earliest=True)
        >>> earliest.kind, earliest.indices, round(earliest.toi, 4), earliest.certainty
        ('vf', (3, 0), 0.5, 0)
    """
    o = renamed_keywords(
        "collision_free_stepsize",
        dict(min_distance=min_distance, tmax=tmax, conservative_rescaling=conservative_rescaling),
        deprecated,
    )
    min_distance, tmax, conservative_rescaling = o["min_distance"], o["tmax"], o["conservative_rescaling"]
    if not 0.0 < conservative_rescaling <= 1.0:
        raise OptionsError(f"conservative_rescaling must be in (0, 1], got {conservative_rescaling}")
    report = _earliest_query(
        x0,
        x1,
        triangles,
        ccd,
        check_start,
        parents,
        min_distance=min_distance,
        groups=groups,
        edges=edges,
        method=method,
        tolerance=tolerance,
        tmax=tmax,
        max_iterations=max_iterations,
        threads=threads,
        max_contacts=max_contacts,
        timeout=timeout,
    )
    if _at_zero(report):
        alpha = 0.0
    elif report.earliest_toi is None:
        alpha = float(tmax)
    else:
        alpha = conservative_rescaling * report.earliest_toi
    if return_earliest:
        return alpha, _earliest_of(report)
    return alpha


def is_step_collision_free(
    x0,
    x1,
    triangles,
    *,
    min_distance: float = 0.0,
    ccd: Optional[Ccd] = None,
    parents=None,
    groups=None,
    edges=None,
    method: str = "auto",
    tolerance: float = 1e-6,
    tmax: float = 1.0,
    max_iterations: int = 1_000_000,
    threads: Optional[int] = None,
    max_contacts: Optional[int] = 1,
    timeout: Optional[float] = None,
    check_start: bool = False,
    **deprecated,
) -> bool:
    """``True`` when no two features come within ``min_distance`` of each other over
    ``[0, tmax]`` of the step from ``x0`` to ``x1``; ``False`` when some may (a contact,
    including one the search gave up on and reported to stay safe).

    For the contact itself, use ``collision_free_stepsize(..., return_earliest=True)``.
    Arguments (``check_start``, ``timeout``, ``max_contacts`` and the deprecated names
    included) as :func:`collision_free_stepsize`.

    Example:
        >>> import numpy as np, topoccd
        >>> fixed = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
        >>> falling = np.array([[0.2, 0.2, 1], [0.3, 0.2, 1], [0.2, 0.3, 1]])
        >>> x0 = np.vstack([fixed, falling]); x1 = np.vstack([fixed, falling - [0, 0, 2]])
        >>> topoccd.is_step_collision_free(x0, x1, [[0, 1, 2], [3, 4, 5]])
        False
        >>> topoccd.is_step_collision_free(x0, x1, [[0, 1, 2], [3, 4, 5]], tmax=0.4)
        True
    """
    o = renamed_keywords("is_step_collision_free", dict(min_distance=min_distance, tmax=tmax), deprecated)
    report = _earliest_query(
        x0,
        x1,
        triangles,
        ccd,
        check_start,
        parents,
        min_distance=o["min_distance"],
        groups=groups,
        edges=edges,
        method=method,
        tolerance=tolerance,
        tmax=o["tmax"],
        max_iterations=max_iterations,
        threads=threads,
        max_contacts=max_contacts,
        timeout=timeout,
    )
    return report.earliest_toi is None and not _at_zero(report)
