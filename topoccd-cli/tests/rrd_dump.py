"""Reads a .rrd recording with Rerun's own reader (rerun-sdk's ``RrdReader``) and prints, as
JSON, what each entity holds at each step: the number of instances of its main component
(positions, triangles, strips, scalars, text lines) and, for scalars and text, the values.

Used by the tests of ``topoccd --rerun`` (topoccd-cli/tests/rerun.rs) and of the Python
helpers (topoccd-py/tests/test_rerun.py): ``python rrd_dump.py FILE.rrd``.
"""

import json
import sys

from rerun.experimental import RrdReader

# The component whose length is an entity's count, by archetype.
MAIN = {
    "Mesh3D": "Mesh3D:triangle_indices",
    "Points3D": "Points3D:positions",
    "LineStrips3D": "LineStrips3D:strips",
    "Arrows3D": "Arrows3D:vectors",
    "Boxes3D": "Boxes3D:half_sizes",
    "Scalars": "Scalars:scalars",
    "TextLog": "TextLog:text",
}


def dump(path):
    """``{"application_id": ..., "entities": {path: {step: {"count": n, "values": [...]}}}}``.
    The count is the viewer's (latest-at): a step that logs an entity without its main
    component (a mesh's positions only) keeps the count of the latest step that logged it.
    A step an entity was logged at more than once (the notes) gets the values in order."""
    reader = RrdReader(path)
    recordings = reader.recordings()
    out = {"recordings": len(recordings), "entities": {}}
    if recordings:
        out["application_id"] = recordings[0].application_id
    rows = {}  # entity -> step -> [archetype, count or None, values]
    for chunk in reader.stream():
        batch = chunk.to_record_batch()
        names = batch.schema.names
        if "step" not in names:
            continue
        steps = batch.column("step").to_pylist()
        entity = rows.setdefault(chunk.entity_path, {})
        for archetype, column in MAIN.items():
            if not any(n.startswith(archetype + ":") for n in names):
                continue
            cells = batch.column(column).to_pylist() if column in names else [None] * len(steps)
            for step, cell in zip(steps, cells):
                row = entity.setdefault(step, [archetype, None, []])
                if cell is not None:
                    row[1] = (row[1] or 0) + len(cell)
                    if archetype in ("Scalars", "TextLog"):
                        row[2].extend(cell)
    for path, entity in rows.items():
        latest = 0
        out["entities"][path] = {}
        for step in sorted(entity):
            archetype, count, values = entity[step]
            latest = latest if count is None else count
            out["entities"][path][str(step)] = {
                "archetype": archetype,
                "count": latest,
                "values": values,
            }
    return out


if __name__ == "__main__":
    json.dump(dump(sys.argv[1]), sys.stdout)
