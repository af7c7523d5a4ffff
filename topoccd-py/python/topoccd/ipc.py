"""The contact potentials in the IPC toolkit's names and shapes: ``import topoccd.ipc as ipctk``.

A solver written against ipctk 1.6.1's Python API runs on topoccd when only its import changes,
for the calls an incremental-potential-contact Newton iteration makes: :class:`CollisionMesh`,
:func:`edges`, :class:`Candidates`, :class:`NormalCollisions`, :class:`BarrierPotential`,
:class:`TangentialCollisions`, :class:`FrictionPotential`, :class:`PSDProjectionMethod`,
:func:`compute_collision_free_stepsize`, :func:`is_step_collision_free`,
:func:`initial_barrier_stiffness` and :func:`update_barrier_stiffness`, with ipctk's
signatures, keywords, defaults and attributes.

Shapes, as ipctk's: positions ``(#V, 3)`` float64; gradients flat ``(3 #V,)``
(``x0, y0, z0, x1, ...``); Hessians ``scipy.sparse.csc_matrix`` ``(3 #V, 3 #V)``, int32
indices; distances that ipctk returns squared (``compute_minimum_distance``) are squared here
too.

What differs:

- The pairs within ``dhat`` come from topoccd's exact proximity query (``topoccd.Ccd``), so
  ``broad_phase=`` is accepted and ignored, and the line-search helpers run topoccd's exact
  CCD (``narrow_phase_ccd=`` is ignored too): see :func:`topoccd.collision_free_stepsize`.
- Triangles may change between calls: build the next :class:`CollisionMesh` (it is cheap) and
  keep the same :class:`NormalCollisions` and potentials; nothing else is rebuilt.
- ``IMPROVED_MAX_APPROX``: an edge-edge collision and a correction of the same features are
  merged, whichever order they name the edges in. ipctk merges them only when its broad
  phase met the edges in the same order; otherwise it keeps both, whose barriers cancel but
  whose PSD-projected Hessians (projected one collision at a time) do not.
- 3D only; no ``displacement_map``; the ``OGC`` collision set, shape derivatives, adhesion,
  anisotropic friction and a custom ``blend_mu`` are not offered (``NotImplementedError``). The area weights are the barycentric ones computed from the rest
  positions: setting ``vertex_areas`` / ``edge_areas`` does not change them.
- Any other ipctk name raises an ``AttributeError`` naming topoccd's own call, if any.

Example: one point 1e-3 above a triangle, ``dhat = 1e-2``: the energy is
``stiffness * b(d^2, dhat^2)`` with ipctk's clamped log barrier ``b``.

    >>> import numpy as np
    >>> import topoccd.ipc as ipctk
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, 1e-3]])
    >>> F = np.array([[0, 1, 2]])
    >>> mesh = ipctk.CollisionMesh(V, ipctk.edges(F), F)
    >>> C = ipctk.NormalCollisions()
    >>> C.build(mesh, V, 1e-2)
    >>> len(C), len(C.fv_collisions)
    (1, 1)
    >>> B = ipctk.BarrierPotential(1e-2, 100.0)
    >>> d2, dhat2 = 1e-6, 1e-4
    >>> bool(np.isclose(B(C, mesh, V), -100 * (d2 - dhat2) ** 2 * np.log(d2 / dhat2)))
    True
    >>> B.gradient(C, mesh, V).shape, B.hessian(C, mesh, V).format
    ((12,), 'csc')
"""

from enum import IntEnum
from typing import List, Optional, Tuple

import numpy as np

from . import _topoccd
from .line_search import collision_free_stepsize as _collision_free_stepsize
from .line_search import is_step_collision_free as _is_step_collision_free

__all__ = [
    "CollisionMesh",
    "edges",
    "Candidates",
    "NormalCollisions",
    "NormalCollision",
    "VertexVertexNormalCollision",
    "EdgeVertexNormalCollision",
    "EdgeEdgeNormalCollision",
    "FaceVertexNormalCollision",
    "BarrierPotential",
    "Barrier",
    "ClampedLogBarrier",
    "barrier",
    "barrier_first_derivative",
    "barrier_second_derivative",
    "TangentialCollisions",
    "TangentialCollision",
    "FrictionPotential",
    "PSDProjectionMethod",
    "NONE",
    "CLAMP",
    "ABS",
    "compute_collision_free_stepsize",
    "is_step_collision_free",
    "initial_barrier_stiffness",
    "update_barrier_stiffness",
    "world_bbox_diagonal_length",
]


class PSDProjectionMethod(IntEnum):
    """How each collision's local Hessian is made positive semi-definite before assembly
    (ipctk's ``PSDProjectionMethod``)."""

    #: No projection.
    NONE = 0
    #: Negative eigenvalues clamped to zero.
    CLAMP = 1
    #: Negative eigenvalues replaced by their absolute values.
    ABS = 2


NONE = PSDProjectionMethod.NONE
CLAMP = PSDProjectionMethod.CLAMP
ABS = PSDProjectionMethod.ABS


def _psd(method) -> int:
    try:
        return int(PSDProjectionMethod(int(method)))
    except (TypeError, ValueError):
        raise _topoccd.OptionsError(
            f"project_hessian_to_psd must be a PSDProjectionMethod (NONE, CLAMP or ABS), got {method!r}"
        ) from None


def _positions(x, mesh: "CollisionMesh", name: str) -> np.ndarray:
    """``x`` as a C-contiguous float64 ``(#V, 3)`` array (no copy when it already is one)."""
    a = np.asarray(x, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 3:
        raise _topoccd.InputError(f"{name} must have shape (#V, 3), got {a.shape}")
    if a.shape[0] != mesh.num_vertices:
        raise _topoccd.InputError(
            f"{name} has {a.shape[0]} rows but the mesh has {mesh.num_vertices} vertices"
        )
    return np.ascontiguousarray(a)


def _index_rows(a, cols: int, name: str) -> np.ndarray:
    if a is None:
        return np.zeros((0, cols), np.int32)
    a = np.asarray(a)
    if a.size == 0:
        return np.zeros((0, cols), np.int32)
    if a.ndim != 2 or a.shape[1] != cols:
        raise _topoccd.InputError(f"{name} must have shape (m, {cols}), got {a.shape}")
    if a.dtype.kind not in "iu":
        raise _topoccd.InputError(f"{name} must hold integers (vertex indices), got dtype {a.dtype}")
    return np.ascontiguousarray(a, dtype=np.int32)


def edges(F) -> np.ndarray:
    """The unique edges of the triangles ``F`` as an ``(#E, 2)`` int32 array: each edge once as
    ``(i, j)`` with ``i < j``, sorted by ``j`` then ``i`` (ipctk's and libigl's order)."""
    F = _index_rows(F, 3, "F")
    if len(F) == 0:
        return np.zeros((0, 2), np.int32)
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    e = np.unique(e, axis=0)
    return np.ascontiguousarray(e[np.lexsort((e[:, 0], e[:, 1]))], dtype=np.int32)


def world_bbox_diagonal_length(vertices) -> float:
    """The length of the diagonal of the bounding box of ``vertices``."""
    v = np.asarray(vertices, dtype=np.float64)
    return float(np.linalg.norm(v.max(axis=0) - v.min(axis=0))) if len(v) else 0.0


class CollisionMesh:
    """The surface: rest positions, edges (those of the faces and free ones) and faces.

    ``CollisionMesh(rest_positions, edges=None, faces=None, displacement_map=None)``, as
    ipctk's (``edges`` must contain every edge of ``faces``, as :func:`edges` gives them, plus
    free edges; vertices in no edge are free points). The rest positions give the area weights
    and the edge-edge mollifier's threshold.
    """

    def __init__(self, rest_positions, edges=None, faces=None, displacement_map=None):
        if displacement_map is not None and getattr(displacement_map, "shape", (0, 0))[0] != 0:
            raise NotImplementedError(
                "topoccd.ipc.CollisionMesh has no displacement_map: pass the collision mesh's "
                "own vertices (map the full mesh yourself)"
            )
        rest = np.array(rest_positions, dtype=np.float64, order="C")
        if rest.ndim != 2 or rest.shape[1] != 3:
            raise _topoccd.InputError(
                f"rest_positions must have shape (#V, 3) (topoccd.ipc is 3D only), got {rest.shape}"
            )
        rest.setflags(write=False)
        self._rest = rest
        self._edges = _index_rows(edges, 2, "edges")
        self._faces = _index_rows(faces, 3, "faces")
        n = len(rest)
        for name, a in (("edges", self._edges), ("faces", self._faces)):
            if a.size and (a.min() < 0 or a.max() >= n):
                raise _topoccd.InputError(f"{name} index a vertex outside [0, {n})")
        self._edges.setflags(write=False)
        self._faces.setflags(write=False)
        # Faces to edges, and the free (codimensional) edges and vertices.
        key = lambda a, b: np.minimum(a, b).astype(np.int64) * n + np.maximum(a, b)  # noqa: E731
        ekeys = key(self._edges[:, 0], self._edges[:, 1])
        order = np.argsort(ekeys, kind="stable")
        f2e = np.zeros((len(self._faces), 3), np.int32)
        in_face = np.zeros(len(self._edges), bool)
        for j in range(3):
            fk = key(self._faces[:, j], self._faces[:, (j + 1) % 3])
            pos = np.searchsorted(ekeys[order], fk)
            ok = (pos < len(order)) & (ekeys[order][np.minimum(pos, len(order) - 1)] == fk)
            if len(fk) and not ok.all():
                f = int(np.flatnonzero(~ok)[0])
                raise _topoccd.InputError(
                    f"edges lacks the edge ({self._faces[f, j]}, {self._faces[f, (j + 1) % 3]}) "
                    f"of face {f}: pass edges=topoccd.ipc.edges(faces) (plus the free edges)"
                )
            f2e[:, j] = order[pos] if len(fk) else 0
            in_face[f2e[:, j]] = True
        f2e.setflags(write=False)
        self._faces_to_edges = f2e
        self._codim_edges = np.flatnonzero(~in_face).astype(np.int32)
        used = np.zeros(n, bool)
        used[self._edges.ravel()] = True
        used[self._faces.ravel()] = True
        self._codim_vertices = np.flatnonzero(~used).astype(np.int32)
        self._free_edges = np.ascontiguousarray(self._edges[self._codim_edges], dtype=np.int32)
        self._vertex_areas, self._edge_areas = self._areas()

    def _areas(self) -> Tuple[np.ndarray, np.ndarray]:
        """ipctk's barycentric areas: a vertex gets a third of each face around it, else half
        of each edge at it, else 1; an edge a third of each face at it, else its length."""
        x, E, F, n = self._rest, self._edges, self._faces, len(self._rest)
        elen = np.linalg.norm(x[E[:, 1]] - x[E[:, 0]], axis=1) if len(E) else np.zeros(0)
        v_edge = np.zeros(n)
        np.add.at(v_edge, E.ravel(), np.repeat(0.5 * elen, 2))
        has_edge = np.zeros(n, bool)
        has_edge[E.ravel()] = True
        farea = (
            0.5 * np.linalg.norm(np.cross(x[F[:, 1]] - x[F[:, 0]], x[F[:, 2]] - x[F[:, 0]]), axis=1)
            if len(F)
            else np.zeros(0)
        )
        v_face = np.zeros(n)
        np.add.at(v_face, F.ravel(), np.repeat(farea / 3.0, 3))
        has_face = np.zeros(n, bool)
        has_face[F.ravel()] = True
        e_face = np.zeros(len(E))
        np.add.at(e_face, self._faces_to_edges.ravel(), np.repeat(farea / 3.0, 3))
        e_has = np.zeros(len(E), bool)
        e_has[self._faces_to_edges.ravel()] = True
        vertex_areas = np.where(has_face, v_face, np.where(has_edge, v_edge, 1.0))
        edge_areas = np.where(e_has, e_face, elen)
        return vertex_areas, edge_areas

    # ipctk's properties.
    @property
    def rest_positions(self) -> np.ndarray:
        """The rest positions ``(#V, 3)`` (read-only)."""
        return self._rest

    @property
    def edges(self) -> np.ndarray:
        """The edges ``(#E, 2)`` int32 (read-only)."""
        return self._edges

    @property
    def faces(self) -> np.ndarray:
        """The faces ``(#F, 3)`` int32 (read-only)."""
        return self._faces

    @property
    def faces_to_edges(self) -> np.ndarray:
        """``(#F, 3)``: column j is the edge from corner j to corner j+1."""
        return self._faces_to_edges

    @property
    def codim_vertices(self) -> np.ndarray:
        """The vertices in no edge and no face."""
        return self._codim_vertices

    @property
    def codim_edges(self) -> np.ndarray:
        """The edges in no face."""
        return self._codim_edges

    @property
    def num_vertices(self) -> int:
        return len(self._rest)

    @property
    def num_edges(self) -> int:
        return len(self._edges)

    @property
    def num_faces(self) -> int:
        return len(self._faces)

    @property
    def num_codim_vertices(self) -> int:
        return len(self._codim_vertices)

    @property
    def num_codim_edges(self) -> int:
        return len(self._codim_edges)

    @property
    def dim(self) -> int:
        return 3

    @property
    def ndof(self) -> int:
        return 3 * len(self._rest)

    @property
    def full_num_vertices(self) -> int:
        return len(self._rest)

    @property
    def full_ndof(self) -> int:
        return 3 * len(self._rest)

    @property
    def vertex_areas(self) -> np.ndarray:
        """The barycentric vertex areas (as ipctk's) that area weighting uses."""
        return self._vertex_areas

    @vertex_areas.setter
    def vertex_areas(self, areas) -> None:
        a = np.array(areas, dtype=np.float64).reshape(-1)
        if a.shape != (self.num_vertices,):
            raise _topoccd.InputError(f"vertex_areas must have shape ({self.num_vertices},), got {a.shape}")
        self._vertex_areas = a

    @property
    def edge_areas(self) -> np.ndarray:
        """The edge areas used as collision weights (barycentric, as ipctk's)."""
        return self._edge_areas

    @edge_areas.setter
    def edge_areas(self, areas) -> None:
        a = np.array(areas, dtype=np.float64).reshape(-1)
        if a.shape != (self.num_edges,):
            raise _topoccd.InputError(f"edge_areas must have shape ({self.num_edges},), got {a.shape}")
        self._edge_areas = a

    def vertex_area(self, vi: int) -> float:
        return float(self._vertex_areas[vi])

    def edge_area(self, ei: int) -> float:
        return float(self._edge_areas[ei])

    def vertices(self, full_positions) -> np.ndarray:
        """The collision mesh's vertices from the full mesh's (the same here)."""
        return np.asarray(full_positions, dtype=np.float64)

    def displace_vertices(self, full_displacements) -> np.ndarray:
        """``rest_positions + full_displacements``."""
        return self._rest + np.asarray(full_displacements, dtype=np.float64)

    def map_displacements(self, full_displacements) -> np.ndarray:
        return np.asarray(full_displacements, dtype=np.float64)

    def to_full_dof(self, x):
        return x

    def __repr__(self) -> str:
        return f"<topoccd.ipc.CollisionMesh V={self.num_vertices} E={self.num_edges} F={self.num_faces}>"


class Candidates:
    """The primitive pairs within ``inflation_radius`` of one configuration (ipctk's
    ``Candidates`` for discrete collision detection).

    ipctk's are the pairs whose inflated boxes overlap, a superset; topoccd's are the pairs
    whose exact distance is below ``inflation_radius``, so :meth:`NormalCollisions.build` from
    either gives the same collisions. The continuous ``build(mesh, t0, t1, ...)`` is not
    offered: use :func:`topoccd.Ccd.query`.
    """

    def __init__(self):
        self._native = None
        self._mesh = None
        self._x = None
        self._radius = 0.0
        self._ccd = _topoccd.Ccd()

    def build(self, mesh: CollisionMesh, vertices, inflation_radius: float = 0, broad_phase=None, *rest):
        if rest or (broad_phase is not None and not _is_broad_phase(broad_phase)):
            raise NotImplementedError(
                "topoccd.ipc.Candidates.build(mesh, vertices_t0, vertices_t1, ...) is not offered: "
                "use topoccd.Ccd().query(x0, x1, triangles) for the pairs of a step"
            )
        x = _positions(vertices, mesh, "vertices")
        self._native = _topoccd.IpcCollisions()
        self._native.build(
            self._ccd, mesh._rest, x, mesh._edges, mesh._free_edges, mesh._faces,
            mesh._vertex_areas, mesh._edge_areas, float(inflation_radius), 0.0, False, False,
        )
        self._mesh, self._x, self._radius = mesh, x, float(inflation_radius)

    def _ids(self, kind: str) -> np.ndarray:
        if self._native is None:
            return np.zeros((0, 2), np.int64)
        return self._native.candidates(kind)

    @property
    def vv_candidates(self):
        return [VertexVertexCandidate(int(a), int(b)) for a, b in self._ids("vv")]

    @property
    def ev_candidates(self):
        return [EdgeVertexCandidate(int(a), int(b)) for a, b in self._ids("ev")]

    @property
    def ee_candidates(self):
        return [EdgeEdgeCandidate(int(a), int(b)) for a, b in self._ids("ee")]

    @property
    def fv_candidates(self):
        return [FaceVertexCandidate(int(a), int(b)) for a, b in self._ids("fv")]

    def __len__(self) -> int:
        return sum(len(self._ids(k)) for k in ("vv", "ev", "ee", "fv"))

    def empty(self) -> bool:
        return len(self) == 0

    def clear(self) -> None:
        self._native = None

    def __getitem__(self, i: int):
        items = self.vv_candidates + self.ev_candidates + self.ee_candidates + self.fv_candidates
        if not 0 <= i < len(items):
            raise IndexError("Candidate index is out of range!")
        return items[i]


def _is_broad_phase(obj) -> bool:
    return True


# --- collisions -------------------------------------------------------------------------


class _Stencil:
    """What ipctk's collisions and candidates share: their vertices."""

    def num_vertices(self) -> int:
        return len(self._vertices(None, None))

    def vertex_ids(self, edges, faces) -> List[int]:
        """The stencil's vertex ids, padded with -1 to four (as ipctk's)."""
        v = list(self._vertices(np.asarray(edges), np.asarray(faces)))
        return v + [-1] * (4 - len(v))

    def dof(self, X, edges, faces) -> np.ndarray:
        ids = self.vertex_ids(edges, faces)[: self.num_vertices()]
        return np.asarray(X, dtype=np.float64)[ids].reshape(-1)

    def __repr__(self) -> str:
        fields = ", ".join(f"{k}={v}" for k, v in self._fields())
        return f"{type(self).__name__}({fields})"

    def __eq__(self, other) -> bool:
        return type(self) is type(other) and tuple(self._fields()) == tuple(other._fields())

    def __hash__(self) -> int:
        return hash((type(self).__name__, tuple(self._fields())))


class VertexVertexCandidate(_Stencil):
    def __init__(self, vertex0_id: int, vertex1_id: int):
        self.vertex0_id, self.vertex1_id = int(vertex0_id), int(vertex1_id)

    def _vertices(self, edges, faces):
        return (self.vertex0_id, self.vertex1_id)

    def _fields(self):
        return [("vertex0_id", self.vertex0_id), ("vertex1_id", self.vertex1_id)]


class EdgeVertexCandidate(_Stencil):
    def __init__(self, edge_id: int, vertex_id: int):
        self.edge_id, self.vertex_id = int(edge_id), int(vertex_id)

    def _vertices(self, edges, faces):
        if edges is None:
            return (0, 0, 0)
        return (self.vertex_id, int(edges[self.edge_id, 0]), int(edges[self.edge_id, 1]))

    def _fields(self):
        return [("edge_id", self.edge_id), ("vertex_id", self.vertex_id)]


class EdgeEdgeCandidate(_Stencil):
    def __init__(self, edge0_id: int, edge1_id: int):
        self.edge0_id, self.edge1_id = int(edge0_id), int(edge1_id)

    def _vertices(self, edges, faces):
        if edges is None:
            return (0, 0, 0, 0)
        a, b = edges[self.edge0_id], edges[self.edge1_id]
        return (int(a[0]), int(a[1]), int(b[0]), int(b[1]))

    def _fields(self):
        return [("edge0_id", self.edge0_id), ("edge1_id", self.edge1_id)]


class FaceVertexCandidate(_Stencil):
    def __init__(self, face_id: int, vertex_id: int):
        self.face_id, self.vertex_id = int(face_id), int(vertex_id)

    def _vertices(self, edges, faces):
        if faces is None:
            return (0, 0, 0, 0)
        f = faces[self.face_id]
        return (self.vertex_id, int(f[0]), int(f[1]), int(f[2]))

    def _fields(self):
        return [("face_id", self.face_id), ("vertex_id", self.vertex_id)]


class NormalCollision(_Stencil):
    """A collision of a :class:`NormalCollisions`: its ids, ``weight`` and ``dmin`` (a copy:
    changing ``weight`` here does not change the set)."""

    weight: float = 1.0
    dmin: float = 0.0


class VertexVertexNormalCollision(VertexVertexCandidate, NormalCollision):
    def __init__(self, vertex0_id: int, vertex1_id: int, weight: float = 1.0, dmin: float = 0.0):
        super().__init__(vertex0_id, vertex1_id)
        self.weight, self.dmin = float(weight), float(dmin)


class EdgeVertexNormalCollision(EdgeVertexCandidate, NormalCollision):
    def __init__(self, edge_id: int, vertex_id: int, weight: float = 1.0, dmin: float = 0.0):
        super().__init__(edge_id, vertex_id)
        self.weight, self.dmin = float(weight), float(dmin)


class EdgeEdgeNormalCollision(EdgeEdgeCandidate, NormalCollision):
    def __init__(self, edge0_id: int, edge1_id: int, eps_x: float, weight: float = 1.0, dmin: float = 0.0):
        super().__init__(edge0_id, edge1_id)
        self.eps_x, self.weight, self.dmin = float(eps_x), float(weight), float(dmin)

    def _fields(self):
        return super()._fields() + [("eps_x", self.eps_x)]


class FaceVertexNormalCollision(FaceVertexCandidate, NormalCollision):
    def __init__(self, face_id: int, vertex_id: int, weight: float = 1.0, dmin: float = 0.0):
        super().__init__(face_id, vertex_id)
        self.weight, self.dmin = float(weight), float(dmin)


class _CollisionSetType(IntEnum):
    """ipctk's ``NormalCollisions.CollisionSetType`` (``OGC`` is not offered)."""

    IPC = 0
    IMPROVED_MAX_APPROX = 1
    OGC = 2


class NormalCollisions:
    """The collisions within ``dhat``, reduced to their closest features and merged with their
    multiplicity, as ipctk 1.6.1 builds them (order: vertex-vertex, edge-vertex, edge-edge,
    face-vertex).

    Options, settable before :meth:`build`: ``use_area_weighting`` (False),
    ``collision_set_type`` (``CollisionSetType.IPC``; ``IMPROVED_MAX_APPROX`` too),
    ``enable_shape_derivatives`` (False; True is not offered).

    One object can be built again and again, also on meshes whose triangles differ: it keeps
    a ``topoccd.Ccd`` whose buffers are reused.
    """

    CollisionSetType = _CollisionSetType
    IPC = _CollisionSetType.IPC
    IMPROVED_MAX_APPROX = _CollisionSetType.IMPROVED_MAX_APPROX
    OGC = _CollisionSetType.OGC

    def __init__(self):
        self._native = _topoccd.IpcCollisions()
        self._ccd = _topoccd.Ccd()
        self._mesh: Optional[CollisionMesh] = None
        self._cache = None
        self.use_area_weighting = False
        self.collision_set_type = _CollisionSetType.IPC
        self._shape = False

    @property
    def enable_shape_derivatives(self) -> bool:
        """Always False: shape derivatives are not offered."""
        return self._shape

    @enable_shape_derivatives.setter
    def enable_shape_derivatives(self, value: bool) -> None:
        if value:
            raise NotImplementedError("topoccd.ipc offers no shape derivatives")
        self._shape = False

    def build(self, *args, **kwargs) -> None:
        """``build(mesh, vertices, dhat, dmin=0, broad_phase=None)`` or
        ``build(candidates, mesh, vertices, dhat, dmin=0)``: the collisions of ``vertices``
        (``(#V, 3)``) closer than ``dhat`` (+ ``dmin``)."""
        if args and isinstance(args[0], Candidates):
            args = args[1:]
        return self._build(*args, **kwargs)

    def _build(self, mesh: CollisionMesh, vertices, dhat: float, dmin: float = 0, broad_phase=None) -> None:
        if not isinstance(mesh, CollisionMesh):
            raise TypeError(f"mesh must be a topoccd.ipc.CollisionMesh, got {type(mesh).__name__}")
        cst = _CollisionSetType(int(self.collision_set_type))
        if cst == _CollisionSetType.OGC:
            raise NotImplementedError("topoccd.ipc offers the IPC and IMPROVED_MAX_APPROX collision sets, not OGC")
        x = _positions(vertices, mesh, "vertices")
        self._native.build(
            self._ccd, mesh._rest, x, mesh._edges, mesh._free_edges, mesh._faces,
            mesh._vertex_areas, mesh._edge_areas, float(dhat), float(dmin), bool(self.use_area_weighting),
            cst == _CollisionSetType.IMPROVED_MAX_APPROX,
        )
        self._mesh = mesh
        self._cache = None

    def _items(self):
        if self._cache is None:
            n = self._native
            w = n.weights
            dmin = n.dmin
            out, k = [], 0
            for cls, kind in (
                (VertexVertexNormalCollision, "vv"),
                (EdgeVertexNormalCollision, "ev"),
                (EdgeEdgeNormalCollision, "ee"),
                (FaceVertexNormalCollision, "fv"),
            ):
                ids = n.ids(kind)
                if kind == "ee":
                    eps = n.eps_x
                    items = [cls(int(a), int(b), float(e), float(w[k + i]), dmin) for i, ((a, b), e) in enumerate(zip(ids, eps))]
                else:
                    items = [cls(int(a), int(b), float(w[k + i]), dmin) for i, (a, b) in enumerate(ids)]
                out.append(items)
                k += len(ids)
            self._cache = out
        return self._cache

    @property
    def vv_collisions(self) -> List[VertexVertexNormalCollision]:
        return list(self._items()[0])

    @property
    def ev_collisions(self) -> List[EdgeVertexNormalCollision]:
        return list(self._items()[1])

    @property
    def ee_collisions(self) -> List[EdgeEdgeNormalCollision]:
        return list(self._items()[2])

    @property
    def fv_collisions(self) -> List[FaceVertexNormalCollision]:
        return list(self._items()[3])

    @property
    def pv_collisions(self) -> list:
        """Always empty (no planes)."""
        return []

    def __len__(self) -> int:
        return len(self._native)

    def empty(self) -> bool:
        return len(self) == 0

    def clear(self) -> None:
        self._native = _topoccd.IpcCollisions()
        self._cache = None

    def _kind_of(self, i: int) -> int:
        if not isinstance(i, (int, np.integer)) or i < 0:
            raise TypeError(f"collision index must be a non-negative int, got {i!r}")
        counts = self._native.counts
        for k, c in enumerate(counts):
            if i < c:
                return k
            i -= c
        raise IndexError("Collision index is out of range!")

    def __getitem__(self, i: int) -> NormalCollision:
        k = self._kind_of(i)
        return self._items()[k][int(i) - sum(self._native.counts[:k])]

    def is_vertex_vertex(self, i: int) -> bool:
        return self._kind_of(i) == 0

    def is_edge_vertex(self, i: int) -> bool:
        return self._kind_of(i) == 1

    def is_edge_edge(self, i: int) -> bool:
        return self._kind_of(i) == 2

    def is_face_vertex(self, i: int) -> bool:
        return self._kind_of(i) == 3

    def is_plane_vertex(self, i: int) -> bool:
        self._kind_of(i)
        return False

    def compute_minimum_distance(self, mesh: CollisionMesh, vertices) -> float:
        """The smallest SQUARED distance over the collisions (as ipctk's), ``inf`` when there
        are none."""
        x = _positions(vertices, mesh, "vertices")
        return self._native.minimum_distance(x)

    def __repr__(self) -> str:
        vv, ev, ee, fv = self._native.counts
        return f"<topoccd.ipc.NormalCollisions vv={vv} ev={ev} ee={ee} fv={fv}>"


# --- barrier ----------------------------------------------------------------------------


class Barrier:
    """A barrier function ``b(d, dhat)`` of the squared distance (ipctk's ``Barrier``)."""

    _kind = "clamped_log"

    def __call__(self, d: float, dhat: float) -> float:
        return _topoccd.ipc_barrier(self._kind, 0, float(d), float(dhat))

    def first_derivative(self, d: float, dhat: float) -> float:
        return _topoccd.ipc_barrier(self._kind, 1, float(d), float(dhat))

    def second_derivative(self, d: float, dhat: float) -> float:
        return _topoccd.ipc_barrier(self._kind, 2, float(d), float(dhat))

    def units(self, dhat: float) -> float:
        return _topoccd.ipc_barrier(self._kind, 3, 0.0, float(dhat))


class ClampedLogBarrier(Barrier):
    """ipctk's default barrier, ``b(d) = -(d - dhat)^2 ln(d / dhat)`` for ``d < dhat``."""

    _kind = "clamped_log"


def barrier(d: float, dhat: float) -> float:
    """The clamped log barrier ``-(d - dhat)^2 ln(d / dhat)`` (0 from ``dhat`` on)."""
    return ClampedLogBarrier()(d, dhat)


def barrier_first_derivative(d: float, dhat: float) -> float:
    return ClampedLogBarrier().first_derivative(d, dhat)


def barrier_second_derivative(d: float, dhat: float) -> float:
    return ClampedLogBarrier().second_derivative(d, dhat)


def _csc(parts, n: int):
    """A ``scipy.sparse.csc_matrix`` of the symmetric Hessian from its CSR arrays (the CSR of
    a symmetric matrix is its CSC: no copy)."""
    import scipy.sparse  # lazily: scipy is the optional dependency `ipc`

    data, indices, indptr = parts
    return scipy.sparse.csc_matrix((data, indices, indptr), shape=(n, n), copy=False)


class BarrierPotential:
    """``BarrierPotential(dhat, stiffness, use_physical_barrier=False)``, or
    ``BarrierPotential(barrier, dhat, stiffness, use_physical_barrier=False)``: the sum over a
    :class:`NormalCollisions` of ``stiffness * weight * b(d^2 - dmin^2, 2 dmin dhat + dhat^2)``.

    ``B(collisions, mesh, X)`` the energy (float), ``B.gradient(...)`` ``(3 #V,)``,
    ``B.hessian(..., project_hessian_to_psd=PSDProjectionMethod.NONE)`` a ``csc_matrix``.
    """

    def __init__(self, *args, **kwargs):
        if args and isinstance(args[0], Barrier):
            self._barrier, args = args[0], args[1:]
        else:
            self._barrier = kwargs.pop("barrier", ClampedLogBarrier())
        self._init(*args, **kwargs)

    def _init(self, dhat: float, stiffness: float, use_physical_barrier: bool = False):
        if not type(self._barrier) in (ClampedLogBarrier, Barrier):
            raise NotImplementedError("topoccd.ipc offers the clamped log barrier only")
        self._native = _topoccd.IpcBarrierPotential(float(dhat), float(stiffness), bool(use_physical_barrier))

    @property
    def dhat(self) -> float:
        """The activation distance (not squared)."""
        return self._native.dhat

    @dhat.setter
    def dhat(self, value: float) -> None:
        self._native.dhat = float(value)

    @property
    def stiffness(self) -> float:
        """The barrier stiffness (ipctk 1.6.1's Python API has no such property; topoccd's
        extra)."""
        return self._native.stiffness

    @stiffness.setter
    def stiffness(self, value: float) -> None:
        self._native.stiffness = float(value)

    @property
    def use_physical_barrier(self) -> bool:
        return self._native.use_physical_barrier

    @property
    def barrier(self) -> Barrier:
        return self._barrier

    def _args(self, collisions, mesh, X):
        if isinstance(collisions, NormalCollision):
            raise NotImplementedError(
                "topoccd.ipc's potentials take a whole NormalCollisions, not one collision"
            )
        if not isinstance(collisions, NormalCollisions):
            raise TypeError(f"collisions must be a topoccd.ipc.NormalCollisions, got {type(collisions).__name__}")
        return collisions._native, _positions(X, mesh, "X")

    def __call__(self, collisions: NormalCollisions, mesh: CollisionMesh, X) -> float:
        c, x = self._args(collisions, mesh, X)
        return self._native.energy(c, x)

    def gradient(self, collisions: NormalCollisions, mesh: CollisionMesh, X) -> np.ndarray:
        c, x = self._args(collisions, mesh, X)
        return self._native.gradient(c, x)

    def hessian(self, collisions: NormalCollisions, mesh: CollisionMesh, X, project_hessian_to_psd=PSDProjectionMethod.NONE):
        c, x = self._args(collisions, mesh, X)
        return _csc(self._native.hessian(c, x, _psd(project_hessian_to_psd)), 3 * len(x))

    def force_magnitude(self, distance_squared: float, dmin: float) -> float:
        """The normal force magnitude of a collision at ``distance_squared`` (as friction
        uses it), for a unit weight."""
        return self._native.force_magnitude(float(distance_squared), float(dmin))


# --- friction ---------------------------------------------------------------------------


class TangentialCollision(_Stencil):
    """A tangential collision: ids, ``normal_force_magnitude``, ``mu_s``, ``mu_k``,
    ``weight``, ``closest_point`` and ``tangent_basis`` (3 x 2), from the lagged positions."""

    def __init__(self, kind: str, ids, normal_force_magnitude, mu_s, mu_k, weight, closest_point, tangent_basis):
        self._kind, self._ids = kind, (int(ids[0]), int(ids[1]))
        self.normal_force_magnitude, self.mu_s, self.mu_k, self.weight = (
            float(normal_force_magnitude), float(mu_s), float(mu_k), float(weight))
        self.closest_point, self.tangent_basis = closest_point, tangent_basis
        names = {"vv": ("vertex0_id", "vertex1_id"), "ev": ("edge_id", "vertex_id"),
                 "ee": ("edge0_id", "edge1_id"), "fv": ("face_id", "vertex_id")}[kind]
        for name, v in zip(names, self._ids):
            setattr(self, name, v)

    def _vertices(self, edges, faces):
        cls = {"vv": VertexVertexCandidate, "ev": EdgeVertexCandidate,
               "ee": EdgeEdgeCandidate, "fv": FaceVertexCandidate}[self._kind]
        return cls(*self._ids)._vertices(edges, faces)

    def _fields(self):
        return [("kind", self._kind), ("ids", self._ids)]


class TangentialCollisions:
    """The tangential collisions of a :class:`NormalCollisions` at the lagged positions:
    ``build(mesh, vertices, collisions, normal_potential, mu)`` or ``build(..., mu_s, mu_k)``
    (scalars or per-vertex arrays); static and kinetic friction as ipctk's smooth ``mu``."""

    def __init__(self):
        self._native = None

    def build(self, mesh: CollisionMesh, vertices, collisions: NormalCollisions,
              normal_potential: BarrierPotential, mu_s, mu_k=None, blend_mu=None) -> None:
        """``build(mesh, vertices, collisions, normal_potential, mu)``, ``(..., mu_s, mu_k)``
        with scalars, or with ``(#V,)`` arrays of per-vertex coefficients (blended per
        collision as ipctk's default ``blend_mu``, the average of the two sides)."""
        if blend_mu is not None:
            raise NotImplementedError(
                "topoccd.ipc.TangentialCollisions.build blends per-vertex mu by ipctk's default "
                "(the average); a custom blend_mu is not offered"
            )
        if not isinstance(collisions, NormalCollisions):
            raise TypeError(f"collisions must be a topoccd.ipc.NormalCollisions, got {type(collisions).__name__}")
        if not isinstance(normal_potential, BarrierPotential):
            raise TypeError(
                f"normal_potential must be a topoccd.ipc.BarrierPotential, got {type(normal_potential).__name__}")
        mu_k = mu_s if mu_k is None else mu_k
        if np.ndim(mu_s) != np.ndim(mu_k):
            raise _topoccd.InputError("mu_s and mu_k must both be scalars or both be per-vertex arrays")
        x = _positions(vertices, mesh, "vertices")

        def coefficients(mu, name):
            a = np.ascontiguousarray(np.atleast_1d(np.asarray(mu, dtype=np.float64)).reshape(-1))
            if np.ndim(mu) and a.shape != (mesh.num_vertices,):
                raise _topoccd.InputError(f"{name} must have shape ({mesh.num_vertices},), got {np.shape(mu)}")
            return a

        self._native = _topoccd.IpcTangentialCollisions(
            collisions._native, normal_potential._native, x,
            coefficients(mu_s, "mu_s"), coefficients(mu_k, "mu_k"))
        self._cache = None

    def _items(self):
        if self._native is None:
            return [[], [], [], []]
        if self._cache is None:
            n = self._native
            nf, ms, mk, w, cp, tb = (n.normal_force_magnitude, n.mu_s, n.mu_k, n.weights,
                                     n.closest_points, n.tangent_bases)
            out, k = [], 0
            for kind in ("vv", "ev", "ee", "fv"):
                ids = n.ids(kind)
                ncp = {"vv": 0, "ev": 1, "ee": 2, "fv": 2}[kind]
                out.append([TangentialCollision(kind, ids[i], nf[k + i], ms[k + i], mk[k + i], w[k + i],
                                                cp[k + i, :ncp].copy(), tb[k + i].copy())
                            for i in range(len(ids))])
                k += len(ids)
            self._cache = out
        return self._cache

    @property
    def vv_collisions(self):
        return list(self._items()[0])

    @property
    def ev_collisions(self):
        return list(self._items()[1])

    @property
    def ee_collisions(self):
        return list(self._items()[2])

    @property
    def fv_collisions(self):
        return list(self._items()[3])

    def __len__(self) -> int:
        return 0 if self._native is None else len(self._native)

    def empty(self) -> bool:
        return len(self) == 0

    def clear(self) -> None:
        self._native = None

    def __getitem__(self, i: int) -> TangentialCollision:
        items = [c for kind in self._items() for c in kind]
        if not isinstance(i, (int, np.integer)) or i < 0:
            raise TypeError(f"collision index must be a non-negative int, got {i!r}")
        if i >= len(items):
            raise IndexError("Collision index is out of range!")
        return items[i]


class FrictionPotential:
    """``FrictionPotential(eps_v)``: the smooth friction dissipative potential over a
    :class:`TangentialCollisions`, of the velocities (or displacements) ``X``; ``eps_v`` is the
    mollifier's threshold in the unit of ``X``."""

    def __init__(self, eps_v: float):
        eps_v = float(eps_v)
        if not eps_v > 0:
            raise _topoccd.OptionsError(f"eps_v must be > 0, got {eps_v}")
        self._eps_v = eps_v

    @property
    def eps_v(self) -> float:
        return self._eps_v

    @eps_v.setter
    def eps_v(self, value: float) -> None:
        self._eps_v = float(value)

    def _args(self, collisions, mesh, X):
        if not isinstance(collisions, TangentialCollisions):
            raise TypeError(f"collisions must be a topoccd.ipc.TangentialCollisions, got {type(collisions).__name__}")
        x = _positions(X, mesh, "X")
        return collisions._native, x

    def __call__(self, collisions: TangentialCollisions, mesh: CollisionMesh, X) -> float:
        t, x = self._args(collisions, mesh, X)
        return 0.0 if t is None else t.energy(x, self._eps_v)

    def gradient(self, collisions: TangentialCollisions, mesh: CollisionMesh, X) -> np.ndarray:
        t, x = self._args(collisions, mesh, X)
        return np.zeros(x.size) if t is None else t.gradient(x, self._eps_v)

    def hessian(self, collisions: TangentialCollisions, mesh: CollisionMesh, X, project_hessian_to_psd=PSDProjectionMethod.NONE):
        t, x = self._args(collisions, mesh, X)
        if t is None:
            import scipy.sparse

            return scipy.sparse.csc_matrix((x.size, x.size))
        return _csc(t.hessian(x, self._eps_v, _psd(project_hessian_to_psd)), x.size)


# --- line search and stiffness ----------------------------------------------------------


def _ccd_of(mesh: CollisionMesh):
    ccd = getattr(mesh, "_line_search_ccd", None)
    if ccd is None:
        ccd = mesh._line_search_ccd = _topoccd.Ccd()
    return ccd


def compute_collision_free_stepsize(mesh: CollisionMesh, vertices_t0, vertices_t1, min_distance: float = 0.0,
                                    broad_phase=None, narrow_phase_ccd=None) -> float:
    """The fraction in ``[0, 1]`` of the step from ``vertices_t0`` to ``vertices_t1`` free of
    contact: 0.8 times the earliest time of impact, by topoccd's exact CCD
    (:func:`topoccd.collision_free_stepsize` over the mesh's faces, free edges and points;
    ``broad_phase`` and ``narrow_phase_ccd`` are ignored)."""
    x0 = _positions(vertices_t0, mesh, "vertices_t0")
    x1 = _positions(vertices_t1, mesh, "vertices_t1")
    return _collision_free_stepsize(x0, x1, mesh._faces, edges=mesh._free_edges,
                                    min_distance=float(min_distance), ccd=_ccd_of(mesh))


def is_step_collision_free(mesh: CollisionMesh, vertices_t0, vertices_t1, min_distance: float = 0.0,
                           broad_phase=None, narrow_phase_ccd=None) -> bool:
    """``True`` when no two features come within ``min_distance`` during the step (what
    ipctk's returns too, whatever its docstring says); topoccd's exact CCD
    (:func:`topoccd.is_step_collision_free`)."""
    x0 = _positions(vertices_t0, mesh, "vertices_t0")
    x1 = _positions(vertices_t1, mesh, "vertices_t1")
    return _is_step_collision_free(x0, x1, mesh._faces, edges=mesh._free_edges,
                                   min_distance=float(min_distance), ccd=_ccd_of(mesh))


def initial_barrier_stiffness(bbox_diagonal: float, barrier: Barrier, dhat: float, average_mass: float,
                              grad_energy, grad_barrier, min_barrier_stiffness_scale: float = 1e11,
                              dmin: float = 0) -> Tuple[float, float]:
    """ipctk's initial stiffness: ``(kappa, max_kappa)`` from the gradients of the elastic
    energy and of the (unit-stiffness) barrier potential."""
    if not isinstance(barrier, ClampedLogBarrier) and type(barrier) is not Barrier:
        raise NotImplementedError("topoccd.ipc offers the clamped log barrier only")
    ge = np.ascontiguousarray(grad_energy, dtype=np.float64).reshape(-1)
    gb = np.ascontiguousarray(grad_barrier, dtype=np.float64).reshape(-1)
    if ge.shape != gb.shape:
        raise _topoccd.InputError(f"grad_energy {ge.shape} and grad_barrier {gb.shape} differ in size")
    return _topoccd.ipc_initial_barrier_stiffness(float(bbox_diagonal), float(dhat), float(average_mass), ge, gb,
                                                  float(min_barrier_stiffness_scale), float(dmin))


def update_barrier_stiffness(prev_min_distance: float, min_distance: float, max_barrier_stiffness: float,
                             barrier_stiffness: float, bbox_diagonal: float, dhat_epsilon_scale: float = 1e-9,
                             dmin: float = 0) -> float:
    """ipctk's adaptive stiffness: doubled (up to the maximum) while the minimum distance is
    below ``dhat_epsilon_scale * bbox_diagonal`` and shrinking. Distances as
    :meth:`NormalCollisions.compute_minimum_distance` gives them (squared)."""
    return _topoccd.ipc_update_barrier_stiffness(float(prev_min_distance), float(min_distance),
                                                 float(max_barrier_stiffness), float(barrier_stiffness),
                                                 float(bbox_diagonal), float(dhat_epsilon_scale), float(dmin))


# --- everything else --------------------------------------------------------------------

#: ipctk names outside the subset whose job topoccd does with a call of its own.
_NATIVE = {
    "Candidates.build(mesh, t0, t1)": "topoccd.Ccd().query(x0, x1, triangles)",
    "point_triangle_distance": "topoccd.proximity(x, triangles, dhat) (distances and closest-feature types)",
    "edge_edge_distance": "topoccd.proximity(x, triangles, dhat)",
    "point_edge_distance": "topoccd.proximity(x, triangles, dhat, edges=...)",
    "point_point_distance": "topoccd.proximity(x, triangles, dhat)",
    "has_intersections": "topoccd.intersecting_triangles(x, triangles)",
    "edge_edge_ccd": "topoccd.edge_edge_ccd",
    "point_triangle_ccd": "topoccd.point_triangle_ccd",
    "point_edge_ccd": "topoccd.point_edge_ccd",
    "point_point_ccd": "topoccd.point_point_ccd",
    "TightInclusionCCD": "topoccd.Ccd (exact CCD; tolerance=, max_iterations= on its queries)",
    "NarrowPhaseCCD": "topoccd.Ccd",
    "AdditiveCCD": "topoccd.Ccd",
    "BroadPhase": "topoccd.Ccd (its BVH is kept and refitted across calls)",
    "LBVH": "topoccd.Ccd", "BVH": "topoccd.Ccd", "HashGrid": "topoccd.Ccd",
    "SweepAndPrune": "topoccd.Ccd", "BruteForce": "topoccd.Ccd", "SpatialHash": "topoccd.Ccd",
}


def __getattr__(name: str):
    if name.startswith("__"):
        raise AttributeError(name)
    native = _NATIVE.get(name)
    hint = (f"use {native}" if native else
            "it is outside the subset topoccd.ipc mirrors (see help(topoccd.ipc)); topoccd's own "
            "calls are topoccd.Ccd.query, topoccd.proximity, topoccd.collision_free_stepsize")
    raise AttributeError(f"topoccd.ipc has no {name!r}; {hint}")
