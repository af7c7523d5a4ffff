"""Line-search helpers in the shape of the IPC toolkit's: how far along a step the mesh may move
without contact, and whether a whole step is free of contact.

Both run one ``mode="earliest"`` query. Pass ``ccd=`` a :class:`topoccd.Ccd` kept across the
simulation so that its buffers are reused.
"""

from typing import Optional

from ._topoccd import Ccd, OptionsError

__all__ = ["collision_free_stepsize", "is_step_collision_free"]


def _earliest(x0, x1, triangles, ccd, min_distance, **options):
    ccd = Ccd() if ccd is None else ccd
    return ccd.query(
        x0, x1, triangles, mode="earliest", min_distance=min_distance, **options
    )


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
    method: str = "auto",
    tolerance: float = 1e-6,
    tmax: float = 1.0,
    max_iterations: int = 1_000_000,
    threads: Optional[int] = None,
) -> float:
    """The fraction of the step from ``x0`` to ``x1`` that the mesh may take without contact.

    It is ``conservative_rescaling`` times the earliest time of impact (features closer than
    ``min_distance`` count as touching), or ``tmax`` when nothing comes that close over
    ``[0, tmax]``. It is 0 when features already touch at the start: check the start with
    :func:`topoccd.intersecting_triangles`.

    Args:
        x0, x1, triangles, parents, groups, method, tolerance, tmax, max_iterations,
            threads: as in :meth:`topoccd.Ccd.query`.
        min_distance: the minimum separation, in coordinate units, >= 0.
        conservative_rescaling: the fraction of the earliest time returned, in (0, 1]. Default 0.8, the
            IPC toolkit's conservative rescaling: the step stops short of the contact.
        ccd: a :class:`topoccd.Ccd` to run the query (a fresh one by default).

    Returns:
        float: the step fraction, in ``[0, tmax]``.

    Raises:
        InputError, OptionsError: as :meth:`topoccd.Ccd.query`; OptionsError also for a
        ``conservative_rescaling`` out of range.

    Example: a triangle falls through a fixed one; first contact at t=0.5.
        >>> import numpy as np, topoccd
        >>> fixed = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
        >>> falling = np.array([[0.2, 0.2, 1], [0.3, 0.2, 1], [0.2, 0.3, 1]])
        >>> x0 = np.vstack([fixed, falling]); x1 = np.vstack([fixed, falling - [0, 0, 2]])
        >>> alpha = topoccd.collision_free_stepsize(x0, x1, [[0, 1, 2], [3, 4, 5]])
        >>> round(alpha, 4)
        0.4
    """
    if not 0.0 < conservative_rescaling <= 1.0:
        raise OptionsError(f"conservative_rescaling must be in (0, 1], got {conservative_rescaling}")
    report = _earliest(
        x0,
        x1,
        triangles,
        ccd,
        min_distance,
        parents=parents,
        groups=groups,
        method=method,
        tolerance=tolerance,
        tmax=tmax,
        max_iterations=max_iterations,
        threads=threads,
    )
    if report.earliest_toi is None:
        return float(tmax)
    return conservative_rescaling * report.earliest_toi


def is_step_collision_free(
    x0,
    x1,
    triangles,
    *,
    min_distance: float = 0.0,
    ccd: Optional[Ccd] = None,
    parents=None,
    groups=None,
    method: str = "auto",
    tolerance: float = 1e-6,
    tmax: float = 1.0,
    max_iterations: int = 1_000_000,
    threads: Optional[int] = None,
) -> bool:
    """``True`` when no two features come within ``min_distance`` of each other over
    ``[0, tmax]`` of the step from ``x0`` to ``x1``; ``False`` when some may (a contact,
    including one the search gave up on and reported to stay safe).

    For the contact itself, run ``Ccd.query(..., mode="earliest")``: its ``earliest`` names
    the pair. Arguments as :func:`collision_free_stepsize`.

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
    report = _earliest(
        x0,
        x1,
        triangles,
        ccd,
        min_distance,
        parents=parents,
        groups=groups,
        method=method,
        tolerance=tolerance,
        tmax=tmax,
        max_iterations=max_iterations,
        threads=threads,
    )
    return report.earliest_toi is None
