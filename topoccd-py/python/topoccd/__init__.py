"""Continuous collision detection for deforming, topology-changing triangle meshes.

numpy in, numpy out, in the conventions of ipctk: positions at t=0 and t=1 as ``(n, 3)``
arrays, triangles as ``(m, 3)`` integer arrays, keyword options with the library's defaults.

Example: the earliest time of impact of a step, for a line search::

    import numpy as np, topoccd

    ccd = topoccd.Ccd()                      # keep it: buffers are reused across steps
    report = ccd.query(x0, x1, triangles)    # every colliding pair of the step
    report.vf, report.vf_toi                 # (N, 2) (vertex, face), (N,) times
    report.ee, report.ee_toi                 # (M, 4) (a0, a1, b0, b1), (M,) times
    alpha = 1.0 if report.earliest_toi is None else 0.8 * report.earliest_toi

Contents:

- :class:`Ccd` and :func:`query`: one step's contacts (``mode="all"``) or its earliest time
  (``mode="earliest"``), with parents for a topology change and groups for the pair filter.
- :class:`Report`: the pairs, their times and certainty codes, optional contact geometry,
  the earliest pair, the work counters and the time of each phase.
- :func:`point_triangle_ccd`, :func:`edge_edge_ccd`, :func:`point_edge_ccd`,
  :func:`point_point_ccd`: one pair of features, or a batch of
  pairs, in the IPC toolkit's shape.
- :func:`collision_free_stepsize`, :func:`is_step_collision_free`: a line search's questions.
- :func:`intersecting_triangles`: the triangles of one configuration that intersect.
- :func:`proximity` and :meth:`Ccd.proximity`: every primitive pair closer than ``dhat`` at one
  configuration (free edges and points included), with distances and closest-feature types
  (:data:`POINT_TRIANGLE_TYPES`, :data:`EDGE_EDGE_TYPES`, :data:`POINT_EDGE_TYPES`).
- :func:`read_mesh`, :func:`read_sequence`: PLY / OBJ frames as numpy arrays.
- :mod:`topoccd.batch`: every step of a frame sequence over Ray tasks or a process pool.
- Errors: :class:`InputError` and :class:`OptionsError` (both ``ValueError``),
  :class:`FormatError` (an ``OSError``) for malformed files; ``TimeoutError`` after
  ``timeout=``; :class:`InputWarning` (a ``UserWarning``) for input that is valid but likely a
  mistake (coincident vertices, zero-area triangles, positions cast to integers).
- Limits: ``max_contacts=`` bounds the report (``report.truncated`` says so), ``timeout=``
  bounds the time, and Ctrl-C stops a running query.
"""

from typing import Optional

from ._topoccd import (
    Ccd,
    FormatError,
    InputError,
    InputWarning,
    OptionsError,
    Proximity,
    Report,
    DEFAULT_MAX_CONTACTS,
    Sequence,
    __version__,
    edge_edge_ccd,
    intersecting_triangles,
    point_edge_ccd,
    point_point_ccd,
    point_triangle_ccd,
    read_mesh,
    read_primitives,
    read_sequence,
)
from .line_search import Earliest, collision_free_stepsize, is_step_collision_free
from . import batch  # noqa: E402  (imports Ray only when used)

__all__ = [
    "batch",
    "Ccd",
    "Report",
    "Proximity",
    "proximity",
    "POINT_TRIANGLE_TYPES",
    "EDGE_EDGE_TYPES",
    "POINT_EDGE_TYPES",
    "POINT_POINT_TYPES",
    "Sequence",
    "query",
    "read_mesh",
    "read_primitives",
    "read_sequence",
    "point_triangle_ccd",
    "edge_edge_ccd",
    "point_edge_ccd",
    "point_point_ccd",
    "collision_free_stepsize",
    "is_step_collision_free",
    "Earliest",
    "intersecting_triangles",
    "InputError",
    "InputWarning",
    "OptionsError",
    "FormatError",
    "RESOLVED",
    "ITERATION_LIMIT",
    "INVALID_INPUT",
    "CERTAINTY",
    "__version__",
    "DEFAULT_MAX_CONTACTS",
]

#: Certainty code of a contact decided by the elementary test.
RESOLVED = 0
#: Certainty code of a pair still undecided after ``max_iterations`` (reported conservatively).
ITERATION_LIMIT = 1
#: Certainty code of a pair whose arithmetic was not finite (reported conservatively).
INVALID_INPUT = 2
#: The names of ``Proximity.vf_type`` codes (the IPC toolkit's ``PointTriangleDistanceType``):
#: a corner, an edge (edge k from corner k to k+1), or the interior of the triangle.
POINT_TRIANGLE_TYPES = ("P_T0", "P_T1", "P_T2", "P_E0", "P_E1", "P_E2", "P_T")
#: The names of ``Proximity.ee_type`` codes (``EdgeEdgeDistanceType``): an endpoint or the
#: interior of each edge.
EDGE_EDGE_TYPES = (
    "EA0_EB0", "EA0_EB1", "EA1_EB0", "EA1_EB1", "EA_EB0", "EA_EB1", "EA0_EB", "EA1_EB", "EA_EB",
)
#: The names of ``Proximity.ve_type`` codes (``PointEdgeDistanceType``).
POINT_EDGE_TYPES = ("P_E0", "P_E1", "P_E")
#: The names of ``Proximity.vv_type`` codes.
POINT_POINT_TYPES = ("P_P",)
#: The certainty codes by name.
CERTAINTY = {RESOLVED: "resolved", ITERATION_LIMIT: "iteration_limit", INVALID_INPUT: "invalid_input"}


def query(
    x0,
    x1,
    triangles,
    *,
    parents=None,
    groups=None,
    edges=None,
    method: str = "auto",
    mode: str = "all",
    tolerance: float = 1e-6,
    min_distance: float = 0.0,
    tmax: float = 1.0,
    max_iterations: int = 1_000_000,
    k: int = 18,
    growth: Optional[str] = None,
    threads: Optional[int] = None,
    geometry: bool = False,
    crack_filter: bool = True,
    max_contacts: Optional[int] = DEFAULT_MAX_CONTACTS,
    timeout: Optional[float] = None,
    **deprecated,
) -> Report:
    """One query with a fresh :class:`Ccd`: every contact of one step, or the earliest.

    Same arguments, result and exceptions as :meth:`Ccd.query`; in a simulation loop keep a
    :class:`Ccd` instead, so that its buffers are reused.

    Example: a triangle falls through a fixed one; its lowest vertex touches at t=0.5.
        >>> import numpy as np, topoccd
        >>> fixed = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
        >>> falling = np.array([[0.2, 0.2, 1], [0.3, 0.2, 1.5], [0.2, 0.3, 1.5]])
        >>> x0 = np.vstack([fixed, falling]); x1 = np.vstack([fixed, falling - [0, 0, 2]])
        >>> r = topoccd.query(x0, x1, [[0, 1, 2], [3, 4, 5]], mode="earliest")
        >>> r.earliest[:3], round(r.earliest_toi, 4)
        (('vf', 3, 0), 0.5)
    """
    return Ccd().query(
        x0,
        x1,
        triangles,
        parents=parents,
        groups=groups,
        edges=edges,
        method=method,
        mode=mode,
        tolerance=tolerance,
        min_distance=min_distance,
        tmax=tmax,
        max_iterations=max_iterations,
        k=k,
        growth=growth,
        threads=threads,
        geometry=geometry,
        crack_filter=crack_filter,
        max_contacts=max_contacts,
        timeout=timeout,
        **deprecated,
    )


def proximity(
    x,
    triangles,
    dhat: float,
    *,
    edges=None,
    dmin: float = 0.0,
    ccd: Optional[Ccd] = None,
    groups=None,
    max_contacts: Optional[int] = DEFAULT_MAX_CONTACTS,
    timeout: Optional[float] = None,
    threads: Optional[int] = None,
) -> Proximity:
    """Every primitive pair of one configuration closer than ``dhat + dmin``.

    Vertex-face, edge-edge (the triangles' edges and the free ``edges``), free point-free edge and
    free point-free point pairs (free points: vertices in no triangle and no edge), with their
    distances (not squared) and closest-feature types, each kind sorted. Features sharing a
    vertex are not paired; ``groups`` apply as in :meth:`Ccd.query`. No pair closer than
    ``dhat + dmin`` is missed; a pair beyond it is reported only within a rounding bound
    (about 1e-14 times the pair's size).

    Pass ``ccd=`` the :class:`Ccd` of the simulation: its hierarchy is kept and refitted
    across a solver's iterations. ``max_contacts`` caps the pairs at one million by default
    (``None`` lifts it). A vertex near an edge or corner comes back once per face around it;
    the potentials' collision set (``topoccd.ipc``) merges such repeats with their
    multiplicity. Other arguments as :meth:`Ccd.proximity`.

    Example: a particle (3) 0.5e-3 above a triangle, and a rod (4, 5) 0.2e-3 above it,
    crossing two of its edges.
        >>> import topoccd
        >>> x = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, 0.5e-3],
        ...      [0.5, -0.5, 0.2e-3], [0.6, 0.5, 0.2e-3]]
        >>> p = topoccd.proximity(x, [[0, 1, 2]], 1e-3, edges=[[4, 5]])
        >>> p.vf.tolist(), [topoccd.POINT_TRIANGLE_TYPES[t] for t in p.vf_type]
        ([[3, 0]], ['P_T'])
        >>> p.ee.tolist(), p.ee_distance.round(6).tolist()
        ([[0, 1, 4, 5], [1, 2, 4, 5]], [0.0002, 0.0002])
        >>> [topoccd.EDGE_EDGE_TYPES[t] for t in p.ee_type]
        ['EA_EB', 'EA_EB']
    """
    ccd = Ccd() if ccd is None else ccd
    return ccd.proximity(
        x,
        triangles,
        dhat,
        edges=edges,
        dmin=dmin,
        groups=groups,
        max_contacts=max_contacts,
        timeout=timeout,
        threads=threads,
    )
