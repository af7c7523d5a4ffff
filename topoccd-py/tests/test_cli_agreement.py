"""The Python package and the CLI give the same pairs on a generated sequence."""

import numpy as np
import topoccd
from conftest import run_cli


def parse_pairs(text: str):
    vf, ee = [], []
    for line in text.splitlines():
        kind, *fields = line.split(",")
        if kind == "vf":
            vf.append((int(fields[0]), int(fields[1]), float(fields[2])))
        else:
            ee.append((*map(int, fields[:4]), float(fields[4])))
    return vf, ee


def test_sequence_steps_match_topoccd_run(sequence, cli_run, tmp_path):
    pairs_dir, lines = cli_run
    seq = topoccd.read_sequence(sequence)
    assert len(seq) == 3 and len(seq.frames) == 4
    ccd = topoccd.Ccd()
    for k, (x0, x1, triangles, parents) in enumerate(seq):
        assert x0.dtype == np.float64 and x0.shape[1] == 3 and triangles.shape[1] == 3
        assert parents.shape[1] == 2
        report = ccd.query(x0, x1, triangles, parents=parents, threads=1)
        cli_text = (pairs_dir / f"{k:04d}.csv").read_text()
        mine = tmp_path / f"{k:04d}.csv"
        report.write_pairs(mine)
        assert mine.read_text() == cli_text, f"step {k}: pairs differ from topoccd run"
        vf, ee = parse_pairs(cli_text)
        assert report.vf.tolist() == [[v, f] for v, f, _ in vf]
        assert report.ee.tolist() == [list(e[:4]) for e in ee]
        np.testing.assert_array_equal(report.vf_toi, [t for *_, t in vf])
        line = lines[k]
        assert line["step"] == k
        assert (line["vf"], line["ee"]) == (len(report.vf), len(report.ee))
        assert line["earliest_toi"] == report.earliest_toi
        assert line["vertices"] == report.stats["vertices"]
    assert len(lines) == 4 and "summary" in lines[-1]


def test_shared_step_matches_topoccd_step(scenes_dir, cli, tmp_path):
    from truth import Scene

    scene = Scene(scenes_dir / "cloth-funnel")
    out = tmp_path / "cli.csv"
    run_cli(cli, "step", str(scene.start), str(scene.end), "--pairs", str(out), "--json")
    x0, _ = topoccd.read_mesh(scene.start)
    x1, triangles = topoccd.read_mesh(scene.end)
    mine = tmp_path / "py.csv"
    topoccd.query(x0, x1, triangles).write_pairs(mine)
    assert mine.read_text() == out.read_text()
