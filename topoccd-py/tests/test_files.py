"""Readers: meshes and sequences as numpy arrays."""

import numpy as np
import pytest
import topoccd


def test_read_mesh_of_a_shared_frame(scenes_dir):
    frames = sorted((scenes_dir / "cloth-funnel" / "frames").glob("*.ply"))
    x, t = topoccd.read_mesh(frames[0])
    assert x.shape == (9450, 3) and x.dtype == np.float64 and x.flags.c_contiguous
    assert t.shape == (18484, 3) and t.dtype == np.int64
    assert t.min() >= 0 and t.max() < len(x)
    x_str, _ = topoccd.read_mesh(str(frames[0]))
    np.testing.assert_array_equal(x, x_str)


def test_obj(tmp_path):
    path = tmp_path / "tri.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    x, t = topoccd.read_mesh(path)
    assert x.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]] and t.tolist() == [[0, 1, 2]]


def test_sequence_indexing(sequence):
    seq = topoccd.read_sequence(sequence)
    assert len(seq) == 3 and seq.folder == str(sequence)
    last = seq[-1]
    x0, x1, triangles, parents = seq[2]
    np.testing.assert_array_equal(last[1], x1)
    assert len(x0) <= len(x1)
    assert len(list(seq)) == 3
    with pytest.raises(IndexError):
        seq[3]
    with pytest.raises(IndexError):
        seq[-4]
    assert "3 steps" in repr(seq)
