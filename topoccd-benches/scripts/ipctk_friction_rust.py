#!/usr/bin/env python3
"""Friction conformance of topoccd's Rust library against the IPC toolkit 1.6.1.

Usage:  pip install ipctk==1.6.1 numpy scipy        (no topoccd Python package needed)
        python3 topoccd-benches/scripts/ipctk_friction_rust.py [--data ../shared/data]
            [--dump target/release/examples/ipc_dump] [--scenes cloth-funnel,hair]

The Rust side is the example `ipc_dump` (built here with cargo unless --dump names it): it reads
raw files from a folder and writes the barrier's and friction's numbers back. The scenes are
those of ipctk_potentials.py: cloth-funnel 227 and cloth-ball 92 (the shared data's first
frames), a hair bundle (free edges) and particles over a floor (free points and triangles),
generated from the same seeds. dhat = 1e-3 x the bounding-box diagonal; rest = the frame, then
the frame shifted by a seeded field; ipctk's defaults, then area weighting.

Friction: mu = 0.5, the normal forces of the barrier of unit stiffness at x (lagged: both
libraries take them from the same collisions), eps_v = 1e-3 dhat, the velocities a seeded
field of scale 1e-2 dhat (mostly the kinetic regime), then of scale 1e-3 dhat (mostly the
mollified one, slip speeds below eps_v). Prints the
relative differences of the friction energy, gradient (norm of the difference over the norm)
and Hessian, plain and PSD-projected (Frobenius), and the same for the barrier, per case and
the worst over all; exits non-zero if a worst difference is above --tol.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import scipy.sparse as sp

os.environ.setdefault("OMP_NUM_THREADS", "1")
import ipctk  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def hair(seed=1, strands=40, per=60):
    """Strands as polylines (free edges) twisting around each other (ipctk_potentials.py's)."""
    rng = np.random.default_rng(seed)
    x, E = [], []
    for s in range(strands):
        r, phase = 0.02 + 0.03 * rng.random(), 2 * np.pi * rng.random()
        t = np.linspace(0, 1, per)
        pts = np.column_stack([
            r * np.cos(phase + 6 * t) + 0.002 * rng.normal(size=per),
            r * np.sin(phase + 6 * t) + 0.002 * rng.normal(size=per),
            t,
        ])
        x.append(pts)
        E += [[s * per + i, s * per + i + 1] for i in range(per - 1)]
    return np.vstack(x), np.array(E, np.int32), np.zeros((0, 3), np.int32)


def particles(seed=2, n=3000, grid=30):
    """Free points in a slab over a triangulated floor (ipctk_potentials.py's)."""
    rng = np.random.default_rng(seed)
    s = np.linspace(0, 1, grid)
    X, Y = np.meshgrid(s, s, indexing="ij")
    floor = np.column_stack([X.ravel(), Y.ravel(), 0.002 * rng.normal(size=grid * grid)])
    F = []
    for i in range(grid - 1):
        for j in range(grid - 1):
            a, b, c, d = i * grid + j, (i + 1) * grid + j, (i + 1) * grid + j + 1, i * grid + j + 1
            F += [[a, b, c], [a, c, d]]
    pts = np.column_stack([rng.random(n), rng.random(n), 0.003 + 0.02 * rng.random(n)])
    F = np.array(F, np.int32)
    return np.vstack([floor, pts]), ipctk.edges(F), F


def read_ply(path):
    """Vertices and triangles of a binary or ASCII PLY file (the shared frames)."""
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        fmt = next(h for h in header if h.startswith("format")).split()[1]
        types = {"float": "f4", "float32": "f4", "double": "f8", "float64": "f8", "uchar": "u1",
                 "uint8": "u1", "char": "i1", "int8": "i1", "int": "i4", "int32": "i4",
                 "uint": "u4", "uint32": "u4", "short": "i2", "ushort": "u2"}
        nv = nf = 0
        vprops, ftypes, cur = [], None, None
        for h in header:
            p = h.split()
            if p[0] == "element":
                cur = p[1]
                nv = int(p[2]) if cur == "vertex" else nv
                nf = int(p[2]) if cur == "face" else nf
            elif p[0] == "property" and cur == "vertex":
                vprops.append((p[-1], types[p[1]]))
            elif p[0] == "property" and cur == "face":
                ftypes = (types[p[2]], types[p[3]])
        if fmt == "ascii":
            rows = [f.readline().split() for _ in range(nv + nf)]
            names = [n for n, _ in vprops]
            V = np.array([[float(r[names.index(c)]) for c in "xyz"] for r in rows[:nv]])
            F = np.array([[int(v) for v in r[1:4]] for r in rows[nv:]], np.int32)
            return V, F
        end = "<" if "little" in fmt else ">"
        vdt = np.dtype([(n, end + t) for n, t in vprops])
        vert = np.frombuffer(f.read(nv * vdt.itemsize), dtype=vdt)
        fdt = np.dtype([("n", end + ftypes[0]), ("i", end + ftypes[1], 3)])
        faces = np.frombuffer(f.read(nf * fdt.itemsize), dtype=fdt)
        if not (faces["n"] == 3).all():
            raise ValueError(f"{path}: not a triangle mesh")
        V = np.column_stack([vert["x"], vert["y"], vert["z"]]).astype(np.float64)
        return V, faces["i"].astype(np.int32)


def frame(data, name):
    folder = Path(data) / "scenes" / name / "frames"
    if not folder.is_dir():
        raise SystemExit(f"error: {folder} not found (the shared data; see --data)")
    first = sorted(p for p in folder.iterdir() if p.suffix == ".ply")[0]
    x, F = read_ply(first)
    return x, ipctk.edges(F), F


def rel(a, b):
    n = np.linalg.norm(b)
    return np.linalg.norm(a - b) / n if n > 0 else np.linalg.norm(a - b)


def fro(A, B):
    n = sp.linalg.norm(B)
    return sp.linalg.norm(A - B) / n if n > 0 else sp.linalg.norm(A - B)


def scalar(a, b):
    return abs(a - b) / abs(b) if b else abs(a)


def csr(folder, name, n):
    ip = np.fromfile(folder / f"{name}.indptr.u64", "<u8").astype(np.int64)
    ix = np.fromfile(folder / f"{name}.indices.u64", "<u8").astype(np.int64)
    d = np.fromfile(folder / f"{name}.data.f64", "<f8")
    return sp.csr_matrix((d, ix, ip), shape=(n, n))


def ours(dump, folder, rest, x, E, F, free_edges, dhat, area, U):
    x.astype("<f8").tofile(folder / "x.f64")
    rest.astype("<f8").tofile(folder / "rest.f64")
    F.astype("<u4").tofile(folder / "faces.u32")
    (E if free_edges else np.zeros((0, 2))).astype("<u4").tofile(folder / "edges.u32")
    U.astype("<f8").tofile(folder / "vel.f64")
    params = dict(dhat=dhat, dmin=0.0, kappa=1.0, area_weighting=area, mu=0.5,
                  eps_v=1e-3 * dhat, friction_kappa=1.0)
    (folder / "params.json").write_text(json.dumps(params))
    subprocess.run([str(dump), str(folder)], check=True, stdout=subprocess.DEVNULL,
                   env={**os.environ, "RAYON_NUM_THREADS": "1"})
    out = json.loads((folder / "out.json").read_text())
    n = x.size
    return dict(
        e=out["energy"], g=np.fromfile(folder / "grad.f64", "<f8"),
        H=csr(folder, "hess_none", n), Hp=csr(folder, "hess_clamp", n),
        De=out["friction"]["energy"], nT=out["friction"]["collisions"],
        Dg=np.fromfile(folder / "friction_grad.f64", "<f8"),
        DH=csr(folder, "friction_hess_none", n), DHp=csr(folder, "friction_hess_clamp", n),
    )


def theirs(rest, x, E, F, dhat, area, U):
    mesh = ipctk.CollisionMesh(np.asfortranarray(rest), np.asfortranarray(E), np.asfortranarray(F))
    C = ipctk.NormalCollisions()
    C.use_area_weighting = area
    C.build(mesh, x, dhat)
    B = ipctk.BarrierPotential(dhat, 1.0)
    T = ipctk.TangentialCollisions()
    T.build(mesh, x, C, B, 0.5)
    D = ipctk.FrictionPotential(1e-3 * dhat)
    psd = ipctk.PSDProjectionMethod.CLAMP
    return dict(
        e=B(C, mesh, x), g=B.gradient(C, mesh, x), H=B.hessian(C, mesh, x),
        Hp=B.hessian(C, mesh, x, project_hessian_to_psd=psd),
        De=D(T, mesh, U), nT=len(T), Dg=D.gradient(T, mesh, U), DH=D.hessian(T, mesh, U),
        DHp=D.hessian(T, mesh, U, project_hessian_to_psd=psd),
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=str(ROOT / ".." / "shared" / "data"))
    ap.add_argument("--dump", help="the ipc_dump example's binary (default: built with cargo)")
    ap.add_argument("--scenes", default="cloth-funnel,cloth-ball,hair,particles")
    ap.add_argument("--tol", type=float, default=1e-9)
    args = ap.parse_args()
    dump = args.dump
    if dump is None:
        subprocess.run(["cargo", "build", "--release", "-q", "-p", "topoccd", "--example", "ipc_dump"],
                       check=True, cwd=ROOT)
        dump = ROOT / "target" / "release" / "examples" / "ipc_dump"
    makers = {
        "cloth-funnel": lambda: frame(args.data, "cloth-funnel"),
        "cloth-ball": lambda: frame(args.data, "cloth-ball"),
        "hair": hair,
        "particles": particles,
    }
    worst = {}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for name in args.scenes.split(","):
            x, E, F = makers[name]()
            x = np.ascontiguousarray(x, np.float64)
            E, F = np.ascontiguousarray(E, np.int32), np.ascontiguousarray(F, np.int32)
            diag = float(np.linalg.norm(x.max(axis=0) - x.min(axis=0)))
            dhat = 1e-3 * diag
            U0 = np.random.default_rng(11).normal(size=x.shape)
            shifted = x + np.random.default_rng(3).normal(scale=0.1 * dhat, size=x.shape)
            print(f"\n## {name}: {len(x)} vertices, {len(E)} edges, {len(F)} faces, dhat = {dhat:.4g}")
            cases = [(r, area, v) for r in (("frame", x), ("shifted", shifted))
                     for area in (False, True) for v in (1e-2, 1e-3)]
            for (rest_name, rest), area, scale in cases:
                U = scale * dhat * U0
                a = ours(dump, folder, rest, x, E, F, len(F) == 0, dhat, area, U)
                b = theirs(rest, x, E, F, dhat, area, U)
                figures = {
                    "friction_energy": scalar(a["De"], b["De"]),
                    "friction_gradient": rel(a["Dg"], b["Dg"]),
                    "friction_hessian": fro(a["DH"], b["DH"]),
                    "friction_hessian_psd": fro(a["DHp"], b["DHp"]),
                    "barrier_energy": scalar(a["e"], b["e"]),
                    "barrier_gradient": rel(a["g"], b["g"]),
                    "barrier_hessian": fro(a["H"], b["H"]),
                    "barrier_hessian_psd": fro(a["Hp"], b["Hp"]),
                }
                for k, v in figures.items():
                    worst[k] = max(worst.get(k, 0.0), v)
                same = "" if a["nT"] == b["nT"] else f" (DIFFER: ours {a['nT']})"
                print(f"- rest={rest_name} area_weighting={area} |v| ~ {scale:g} dhat: {b['nT']} tangential collisions{same}, "
                      f"friction energy {b['De']:.6e}")
                print("  " + ", ".join(f"{k} {v:.1e}" for k, v in figures.items()))
                worst["tangential_count_mismatch"] = max(worst.get("tangential_count_mismatch", 0),
                                                         float(a["nT"] != b["nT"]))
    print("\n## Worst relative difference over all cases")
    for k, v in worst.items():
        print(f"- {k}: {v:.2e}")
    bad = [k for k, v in worst.items() if not v <= args.tol]
    if bad:
        print(f"error: above --tol {args.tol:g}: {', '.join(bad)}", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
