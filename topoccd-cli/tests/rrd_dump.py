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
    """``{"application_id": ..., "entities": {path: {step: {"count": n, "values": [...]}}}}``;
    a step an entity was logged at more than once (the notes) gets the rows in order."""
    reader = RrdReader(path)
    recordings = reader.recordings()
    out = {"recordings": len(recordings), "entities": {}}
    if recordings:
        out["application_id"] = recordings[0].application_id
    for chunk in reader.stream():
        batch = chunk.to_record_batch()
        names = batch.schema.names
        if "step" not in names:
            continue
        steps = batch.column("step").to_pylist()
        entity = out["entities"].setdefault(chunk.entity_path, {})
        for archetype, column in MAIN.items():
            if column not in names:
                continue
            for step, cell in zip(steps, batch.column(column).to_pylist()):
                row = entity.setdefault(str(step), {"archetype": archetype, "count": 0, "values": []})
                row["count"] += 0 if cell is None else len(cell)
                if archetype in ("Scalars", "TextLog") and cell is not None:
                    row["values"].extend(cell)
    return out


if __name__ == "__main__":
    json.dump(dump(sys.argv[1]), sys.stdout)
