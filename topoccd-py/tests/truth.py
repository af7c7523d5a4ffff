"""The exact ground truth of the shared whole-step scenes (Sample-Scalable-CCD-Data)."""

import json
import re
from pathlib import Path

import numpy as np


def libigl_edges(triangles: np.ndarray) -> np.ndarray:
    """Every undirected edge once as (i, j), i < j, sorted by j then i (igl::edges' order)."""
    e = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    e = np.sort(e, axis=1)
    e = np.unique(e, axis=0)
    order = np.lexsort((e[:, 0], e[:, 1]))
    return e[order]


class Scene:
    """One step of a shared scene: its frames and the pairs that touch."""

    def __init__(self, folder: Path) -> None:
        frames = sorted(
            (folder / "frames").glob("*.ply"),
            key=lambda p: int(re.findall(r"\d+", p.stem)[-1]),
        )
        assert len(frames) == 2, frames
        self.folder, self.start, self.end = folder, frames[0], frames[1]
        self.number = re.findall(r"\d+", self.start.stem)[-1]

    def touching(self, triangles: np.ndarray, vertices: int):
        """(vf, ee): sets of (vertex, face) and ((a0, a1), (b0, b1)) that touch."""
        edges = libigl_edges(triangles)
        nv, ne = vertices, len(edges)

        def load(kind: str):
            pairs = json.loads((self.folder / "boxes" / f"{self.number}{kind}.json").read_text())
            truth = json.loads(
                (self.folder / "mma_bool" / f"{self.number}{kind}_mma_bool.json").read_text()
            )
            assert len(pairs) == len(truth)
            return [p for p, t in zip(pairs, truth) if t]

        vf = {(v, f - nv - ne) for v, f in load("vf")}
        ee = set()
        for a, b in load("ee"):
            ea, eb = tuple(edges[a - nv]), tuple(edges[b - nv])
            ee.add((min(ea, eb), max(ea, eb)))
        return vf, ee

    def vf_tois(self, triangles: np.ndarray, vertices: int):
        """{(vertex, face): earliest root} from toi/<a>vf_toi.txt (cloth-funnel only)."""
        path = self.folder / "toi" / f"{self.number}vf_toi.txt"
        if not path.exists():
            return {}
        edges = libigl_edges(triangles)
        pairs = json.loads((self.folder / "boxes" / f"{self.number}vf.json").read_text())
        out = {}
        for line in path.read_text().splitlines():
            fields = line.split()
            if fields:
                v, f = pairs[int(fields[0])]
                out[(v, f - vertices - len(edges))] = float(fields[1])
        return out


def report_pairs(report):
    vf = {(int(v), int(f)) for v, f in report.vf.tolist()}
    ee = {((a0, a1), (b0, b1)) for a0, a1, b0, b1 in report.ee.tolist()}
    return vf, ee
