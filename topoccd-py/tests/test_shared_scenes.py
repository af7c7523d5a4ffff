"""The shared real steps against their exact ground truth: every touching pair reported."""

import time

import numpy as np
import pytest
import topoccd
from truth import Scene, report_pairs


def check_scene(folder, method, mode="all"):
    scene = Scene(folder)
    x0, _ = topoccd.read_mesh(scene.start)
    x1, triangles = topoccd.read_mesh(scene.end)
    started = time.perf_counter()
    report = topoccd.Ccd().query(x0, x1, triangles, method=method, mode=mode)
    wall = time.perf_counter() - started
    vf_truth, ee_truth = scene.touching(triangles, len(x1))
    vf, ee = report_pairs(report)
    missed_vf, missed_ee = vf_truth - vf, ee_truth - ee
    assert not missed_vf, f"{len(missed_vf)} touching vf pairs missed, e.g. {sorted(missed_vf)[:5]}"
    assert not missed_ee, f"{len(missed_ee)} touching ee pairs missed, e.g. {sorted(missed_ee)[:5]}"
    print(
        f"{folder.name} {method}: {len(vf)} vf ({len(vf - vf_truth)} beyond the truth's list), "
        f"{len(ee)} ee ({len(ee - ee_truth)} beyond); query {report.seconds['total']:.3f} s, "
        f"Python wall {wall:.3f} s"
    )
    return scene, report, triangles, len(x1)


@pytest.mark.parametrize("method", ["bvh", "cluster"])
def test_cloth_funnel_reports_every_touching_pair(scenes_dir, method):
    scene, report, triangles, n = check_scene(scenes_dir / "cloth-funnel", method)
    assert report.unresolved == 0
    assert np.all(report.vf_certainty == 0) and np.all(report.ee_certainty == 0)
    # Times: never later than the exact first root, at most the tolerance (plus rounding) earlier.
    tois = dict(zip(map(tuple, report.vf.tolist()), report.vf_toi.tolist()))
    exact = scene.vf_tois(triangles, n)
    assert exact
    for pair, root in exact.items():
        assert root - 1e-5 <= tois[pair] <= root + 1e-9, (pair, tois[pair], root)
    assert report.earliest_toi <= 0.0452322 + 1e-7


def test_cloth_funnel_earliest_mode_agrees(scenes_dir):
    scene = Scene(scenes_dir / "cloth-funnel")
    x0, _ = topoccd.read_mesh(scene.start)
    x1, triangles = topoccd.read_mesh(scene.end)
    all_ = topoccd.query(x0, x1, triangles)
    earliest = topoccd.query(x0, x1, triangles, mode="earliest")
    assert earliest.earliest_toi == pytest.approx(all_.earliest_toi, abs=1e-6)


@pytest.mark.slow
def test_cloth_ball_reports_every_touching_pair(scenes_dir):
    check_scene(scenes_dir / "cloth-ball", "cluster")
