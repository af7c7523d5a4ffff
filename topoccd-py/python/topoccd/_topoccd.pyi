"""Type stubs of the Rust extension ``topoccd._topoccd`` (re-exported by ``topoccd``)."""

import os
from typing import Iterator, Literal, Optional, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "Ccd",
    "Report",
    "Sequence",
    "read_mesh",
    "read_primitives",
    "read_sequence",
    "point_triangle_ccd",
    "edge_edge_ccd",
    "point_edge_ccd",
    "point_point_ccd",
    "intersecting_triangles",
    "InputError",
    "InputWarning",
    "OptionsError",
    "FormatError",
    "__version__",
    "DEFAULT_MAX_CONTACTS",
]

__version__: str
DEFAULT_MAX_CONTACTS: int

_Path = Union[str, "os.PathLike[str]"]
_Method = Literal["bvh", "cluster", "brute", "auto"]
_Mode = Literal["all", "earliest"]
_Growth = Literal["certificate", "paper"]
_StepArrays = Tuple[
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.int64],
    npt.NDArray[np.int64],
]
_Earliest = Union[
    Tuple[Literal["vf"], int, int, float],
    Tuple[Literal["ee"], int, int, int, int, float],
]

class InputError(ValueError):
    """Invalid input arrays (shape, dtype, NaN, index out of range, bad parents or groups)."""

class OptionsError(ValueError):
    """A keyword option out of its range."""

class FormatError(OSError):
    """A mesh or sequence file that could be opened but not understood."""

class InputWarning(UserWarning):
    """Valid input that is likely a mistake (coincident vertices, zero-area triangles,
    positions cast to integers), warned about before a query runs."""

@final
class Report:
    """The result of one query, as numpy arrays (see ``help(topoccd.Report)``)."""

    vf: npt.NDArray[np.int64]
    """``(N, 2)`` colliding vertex-face pairs ``(vertex, face)``, sorted."""
    vf_toi: npt.NDArray[np.float64]
    """``(N,)`` times of impact in ``[0, tmax]``."""
    vf_certainty: npt.NDArray[np.uint8]
    """``(N,)`` 0 resolved, 1 iteration limit, 2 invalid input."""
    ee: npt.NDArray[np.int64]
    """``(M, 4)`` colliding edge-edge pairs ``(a0, a1, b0, b1)``, sorted."""
    ee_toi: npt.NDArray[np.float64]
    ee_certainty: npt.NDArray[np.uint8]
    ve: npt.NDArray[np.int64]
    """``(K, 3)`` colliding vertex-edge pairs ``(vertex, e0, e1)`` of free points and free
    edges (with ``edges=``), sorted."""
    ve_toi: npt.NDArray[np.float64]
    ve_certainty: npt.NDArray[np.uint8]
    vv: npt.NDArray[np.int64]
    """``(L, 2)`` colliding pairs of free points ``(a, b)``, ``a < b``, sorted."""
    vv_toi: npt.NDArray[np.float64]
    vv_certainty: npt.NDArray[np.uint8]
    vf_barycentric: Optional[npt.NDArray[np.float64]]
    """``(N, 3)`` with ``geometry=True``, else ``None``."""
    vf_point: Optional[npt.NDArray[np.float64]]
    vf_normal: Optional[npt.NDArray[np.float64]]
    ee_params: Optional[npt.NDArray[np.float64]]
    """``(M, 2)`` positions along edge a and edge b, in ``[0, 1]``."""
    ee_point: Optional[npt.NDArray[np.float64]]
    ee_normal: Optional[npt.NDArray[np.float64]]
    earliest_toi: Optional[float]
    earliest: Optional[_Earliest]
    unresolved: int
    earliest_complete: bool
    """Whether every pair within ``tolerance`` of the earliest time is listed."""
    truncated: Optional[dict]
    """``None``, or ``{"reason": "max_contacts", "phase": ..., "tasks": ...}`` when the report
    holds only the first ``max_contacts`` contacts."""
    stats: dict
    """``bv_tests``, ``vf_tests``, ``ee_tests``, ``peak_candidates``, ``vertices``, ``triangles``
    (and ``cluster``)."""
    seconds: dict
    """``build``, ``traverse``, ``narrow``, ``total`` (and ``clustering``, ``merging``)."""
    _x0_address: int
    _x1_address: int
    _borrowed: Tuple[bool, bool]
    def write_pairs(self, path: _Path) -> None:
        """Writes the pairs as ``topoccd step --pairs`` does."""
    def __len__(self) -> int: ...

@final
class Proximity:
    """The primitive pairs of one configuration closer than ``dhat + dmin``."""

    vf: npt.NDArray[np.int64]
    vf_distance: npt.NDArray[np.float64]
    vf_type: npt.NDArray[np.uint8]
    ee: npt.NDArray[np.int64]
    ee_distance: npt.NDArray[np.float64]
    ee_type: npt.NDArray[np.uint8]
    ve: npt.NDArray[np.int64]
    ve_distance: npt.NDArray[np.float64]
    ve_type: npt.NDArray[np.uint8]
    vv: npt.NDArray[np.int64]
    vv_distance: npt.NDArray[np.float64]
    vv_type: npt.NDArray[np.uint8]
    truncated: Optional[str]
    refitted: bool
    reused: bool
    seconds: float
    def __len__(self) -> int: ...

class Ccd:
    """A reusable query: keep one per simulation, call ``query`` once per step."""

    def __init__(self) -> None: ...
    def proximity(
        self,
        x: npt.ArrayLike,
        triangles: npt.ArrayLike,
        dhat: float,
        *,
        edges: Optional[npt.ArrayLike] = None,
        dmin: float = 0.0,
        groups: Optional[npt.ArrayLike] = None,
        max_contacts: Optional[int] = 1_000_000,
        timeout: Optional[float] = None,
        threads: Optional[int] = None,
    ) -> Proximity: ...
    def query(
        self,
        x0: npt.ArrayLike,
        x1: npt.ArrayLike,
        triangles: npt.ArrayLike,
        *,
        parents: Optional[npt.ArrayLike] = None,
        groups: Optional[npt.ArrayLike] = None,
        edges: Optional[npt.ArrayLike] = None,
        method: _Method = "auto",
        mode: _Mode = "all",
        tolerance: float = 1e-6,
        min_distance: float = 0.0,
        tmax: float = 1.0,
        max_iterations: int = 1_000_000,
        k: int = 18,
        growth: Optional[_Growth] = None,
        threads: Optional[int] = None,
        geometry: bool = False,
        crack_filter: bool = True,
        max_contacts: Optional[int] = 1_000_000,
        timeout: Optional[float] = None,
    ) -> Report:
        """Every contact of one step (or the earliest); see ``help(topoccd.Ccd.query)``."""

@final
class Sequence:
    """A frame sequence folder: ``len(seq)`` steps, ``seq[k] -> (x0, x1, triangles, parents)``."""

    frames: list[str]
    folder: str
    def __len__(self) -> int: ...
    def __getitem__(self, k: int, /) -> _StepArrays: ...
    def __iter__(self) -> Iterator[_StepArrays]: ...

def read_primitives(
    path: _Path, *, loose_vertices: str = "points"
) -> Tuple[npt.NDArray[np.int64], npt.NDArray[np.int64]]: ...
def read_mesh(path: _Path) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """Reads a ``.ply``, ``.obj`` or ``.stl`` triangle mesh: ``(positions (n, 3), triangles (m, 3))``."""

def read_sequence(folder: _Path) -> Sequence:
    """Opens a folder of frames ``0000.ply``, ``0001.ply``, ... (and ``.parents`` files)."""

_Points = npt.ArrayLike
_Hit = Tuple[bool, float]
_HitCertainty = Tuple[bool, float, int]
_Hits = Tuple[npt.NDArray[np.bool_], npt.NDArray[np.float64]]
_HitsCertainty = Tuple[npt.NDArray[np.bool_], npt.NDArray[np.float64], npt.NDArray[np.uint8]]

def point_triangle_ccd(
    *points: _Points,
    min_distance: float = 0.0,
    tmax: float = 1.0,
    tolerance: float = 1e-6,
    max_iterations: int = 1_000_000,
    certainty: bool = False,
    threads: Optional[int] = None,
    timeout: Optional[float] = None,
) -> Union[_Hit, _HitCertainty, _Hits, _HitsCertainty]:
    """One pair (eight ``(3,)`` points: ``p_t0, t0_t0, t1_t0, t2_t0, p_t1, t0_t1, t1_t1,
    t2_t1``) gives ``(hit, toi)``; a batch (two ``(N, 4, 3)`` arrays, at t=0 and t=1) gives
    arrays of N. ``certainty=True`` adds the certainty code(s). A batch runs on ``threads``
    threads (default: rayon's global pool, sized by ``RAYON_NUM_THREADS``) and stops with
    ``TimeoutError`` after ``timeout`` seconds."""

def edge_edge_ccd(
    *points: _Points,
    min_distance: float = 0.0,
    tmax: float = 1.0,
    tolerance: float = 1e-6,
    max_iterations: int = 1_000_000,
    certainty: bool = False,
    threads: Optional[int] = None,
    timeout: Optional[float] = None,
) -> Union[_Hit, _HitCertainty, _Hits, _HitsCertainty]:
    """As :func:`point_triangle_ccd`, for edges ``ea0, ea1, eb0, eb1``."""

def point_edge_ccd(
    *points: _Points,
    min_distance: float = 0.0,
    tmax: float = 1.0,
    tolerance: float = 1e-6,
    max_iterations: int = 1_000_000,
    certainty: bool = False,
) -> Union[_Hit, _HitCertainty, _Hits, _HitsCertainty]:
    """As :func:`point_triangle_ccd`, for a point and an edge ``p, e0, e1`` (six points, or two
    ``(N, 3, 3)`` arrays)."""

def point_point_ccd(
    *points: _Points,
    min_distance: float = 0.0,
    tmax: float = 1.0,
    tolerance: float = 1e-6,
    max_iterations: int = 1_000_000,
    certainty: bool = False,
) -> Union[_Hit, _HitCertainty, _Hits, _HitsCertainty]:
    """As :func:`point_triangle_ccd`, for two points ``p0, p1`` (four points, or two
    ``(N, 2, 3)`` arrays)."""

def intersecting_triangles(
    x: npt.ArrayLike,
    triangles: npt.ArrayLike,
    *,
    parents: Optional[npt.ArrayLike] = None,
    max_contacts: Optional[int] = 1_000_000,
    timeout: Optional[float] = None,
) -> npt.NDArray[np.int64]:
    """``(K, 2)`` pairs of triangles (sharing no vertex) that intersect or touch."""

# The native half of topoccd.ipc (use topoccd.ipc, not these).
_F64 = npt.NDArray[np.float64]
_I32 = npt.NDArray[np.int32]
_Csr = Tuple[_F64, _I32, _I32]

@final
class IpcCollisions:
    """A collision set built from one proximity query (see ``topoccd.ipc.NormalCollisions``)."""

    weights: _F64
    eps_x: _F64
    dmin: float
    counts: Tuple[int, int, int, int]
    def __init__(self) -> None: ...
    def build(
        self, ccd: Ccd, rest: _F64, x: _F64, edges: _I32, free_edges: _I32, faces: _I32,
        vertex_areas: _F64, edge_areas: _F64, dhat: float, dmin: float,
        use_area_weighting: bool, improved_max_approx: bool, /,
    ) -> None: ...
    def ids(self, kind: str, /) -> npt.NDArray[np.int64]: ...
    def candidates(self, kind: str, /) -> npt.NDArray[np.int64]: ...
    def minimum_distance(self, x: _F64, /) -> float: ...
    def __len__(self) -> int: ...

@final
class IpcBarrierPotential:
    """The barrier potential (see ``topoccd.ipc.BarrierPotential``)."""

    dhat: float
    stiffness: float
    use_physical_barrier: bool
    def __init__(self, dhat: float, stiffness: float, use_physical_barrier: bool, /) -> None: ...
    def energy(self, c: IpcCollisions, x: _F64, /) -> float: ...
    def gradient(self, c: IpcCollisions, x: _F64, /) -> _F64: ...
    def hessian(self, c: IpcCollisions, x: _F64, psd: int, /) -> _Csr: ...
    def force_magnitude(self, d2: float, dmin: float, /) -> float: ...

@final
class IpcTangentialCollisions:
    """Tangential collisions at lagged positions (see ``topoccd.ipc.TangentialCollisions``)."""

    normal_force_magnitude: _F64
    mu_s: _F64
    mu_k: _F64
    weights: _F64
    closest_points: _F64
    tangent_bases: _F64
    def __init__(self, c: IpcCollisions, b: IpcBarrierPotential, x: _F64, mu_s: float, mu_k: float, /) -> None: ...
    def ids(self, kind: str, /) -> npt.NDArray[np.int64]: ...
    def energy(self, u: _F64, eps_v: float, /) -> float: ...
    def gradient(self, u: _F64, eps_v: float, /) -> _F64: ...
    def hessian(self, u: _F64, eps_v: float, psd: int, /) -> _Csr: ...
    def __len__(self) -> int: ...

def ipc_barrier(kind: str, which: int, d: float, dhat: float, /) -> float: ...
def ipc_initial_barrier_stiffness(
    bbox_diagonal: float, dhat: float, average_mass: float, grad_energy: _F64, grad_barrier: _F64,
    min_barrier_stiffness_scale: float, dmin: float, /,
) -> Tuple[float, float]: ...
def ipc_update_barrier_stiffness(
    prev_min_distance: float, min_distance: float, max_barrier_stiffness: float,
    barrier_stiffness: float, bbox_diagonal: float, dhat_epsilon_scale: float, dmin: float, /,
) -> float: ...
