"""Bad input raises the right exception, naming the element; never a crash."""

import numpy as np
import pytest
import topoccd
from scenes import falling_triangle


def q(**changes):
    x0, x1, tris = falling_triangle()
    args = {"x0": x0, "x1": x1, "triangles": tris}
    options = {k: v for k, v in changes.items() if k not in args}
    args.update({k: v for k, v in changes.items() if k in args})
    return topoccd.query(args["x0"], args["x1"], args["triangles"], **options)


def test_exception_classes():
    assert issubclass(topoccd.InputError, ValueError)
    assert issubclass(topoccd.OptionsError, ValueError)
    assert issubclass(topoccd.FormatError, OSError)


def test_nan_names_the_vertex():
    x0, x1, _ = falling_triangle()
    x1[4, 1] = np.nan
    with pytest.raises(topoccd.InputError, match=r"vertex 4"):
        q(x1=x1)
    x0[2, 0] = np.inf
    with pytest.raises(topoccd.InputError, match=r"vertex 2"):
        q(x0=x0)


def test_index_out_of_range_names_the_triangle():
    with pytest.raises(topoccd.InputError, match=r"triangle 1.*7"):
        q(triangles=[[0, 1, 2], [3, 4, 7]])


def test_negative_and_huge_indices_name_the_element():
    with pytest.raises(topoccd.InputError, match=r"triangles\[1, 2\] = -1"):
        q(triangles=[[0, 1, 2], [3, 4, -1]])
    with pytest.raises(topoccd.InputError, match=r"triangles\[0, 0\]"):
        q(triangles=np.array([[2**40, 1, 2]]))


def test_repeated_vertex():
    with pytest.raises(topoccd.InputError, match=r"triangle 0"):
        q(triangles=[[0, 0, 2]])


@pytest.mark.parametrize(
    "changes, pattern",
    [
        ({"x0": np.zeros((6, 2))}, r"x0 must have shape \(n, 3\), got \(6, 2\)"),
        ({"x1": np.zeros(18)}, r"x1 must have shape \(n, 3\), got \(18,\)"),
        ({"x1": np.zeros((6, 3, 1))}, r"x1 must have shape"),
        ({"triangles": [0, 1, 2]}, r"triangles must have shape \(m, 3\), got \(3,\)"),
        ({"triangles": [[0, 1, 2, 3]]}, r"triangles must have shape \(m, 3\)"),
        ({"triangles": [[0.0, 1.0, 2.5]]}, r"triangles must hold integers"),
        ({"x0": np.zeros((6, 3), dtype=complex)}, r"x0 must hold real numbers"),
        ({"x0": [["a", "b", "c"]] * 6}, r"x0"),
        ({"x0": [[0, 0], [1, 1, 1]]}, r"x0"),
        ({"parents": [[6, 3, 1]]}, r"parents must have shape \(m, 2\)"),
        ({"groups": np.zeros((6, 1), dtype=int)}, r"groups must have shape \(n,\)"),
        ({"groups": [1.5] * 6}, r"groups must hold integers"),
    ],
)
def test_wrong_shape_or_dtype(changes, pattern):
    with pytest.raises(topoccd.InputError, match=pattern):
        q(**changes)


def test_vertex_count_mismatch():
    x0, x1, _ = falling_triangle()
    with pytest.raises(topoccd.InputError):
        q(x0=np.vstack([x0, x0[:1]]))


def test_bad_parents_name_the_row():
    x0, x1, tris = falling_triangle()
    x1b = np.vstack([x1, x1[3]])
    with pytest.raises(topoccd.InputError, match=r"(row|parents).*1|1.*(row|parents)"):
        topoccd.query(x0, x1b, tris, parents=[[6, 3], [6, 99]])
    with pytest.raises(topoccd.InputError, match=r"parents\[0, 1\] = -3"):
        topoccd.query(x0, x1b, tris, parents=[[6, -3]])


def test_groups_of_the_wrong_length():
    with pytest.raises(topoccd.InputError, match=r"5 group ids for 6 vertices|groups"):
        q(groups=np.zeros(5, dtype=int))


@pytest.mark.parametrize(
    "options, pattern",
    [
        ({"tolerance": 0.0}, "tolerance"),
        ({"tolerance": 1.5}, "tolerance"),
        ({"tmax": 0.0}, "tmax"),
        ({"tmax": 2.0}, "tmax"),
        ({"min_distance": -1.0}, "min_distance"),
        ({"min_distance": float("nan")}, "min_distance"),
        ({"max_iterations": 0}, "max_iterations"),
        ({"max_iterations": -5}, "max_iterations"),
        ({"k": 8}, "k must be 6, 14, 18 or 26, got 8"),
        ({"method": "octree"}, "method"),
        ({"mode": "first"}, "mode"),
        ({"growth": "fast"}, "growth"),
        ({"threads": 0}, "threads"),
    ],
)
def test_invalid_options(options, pattern):
    with pytest.raises(topoccd.OptionsError, match=pattern):
        q(**options)


def test_wrong_option_types_are_type_errors():
    with pytest.raises(TypeError):
        q(tolerance="small")
    with pytest.raises(TypeError):
        q(bogus=1)


def test_file_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        topoccd.read_mesh(tmp_path / "absent.ply")
    bad = tmp_path / "bad.ply"
    bad.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 1000\n"
                    b"property float x\nproperty float y\nproperty float z\nend_header\n\0\0")
    with pytest.raises(topoccd.FormatError, match="bad.ply"):
        topoccd.read_mesh(bad)
    obj = tmp_path / "tri.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n")
    with pytest.raises(topoccd.FormatError, match=r"tri.obj.*line 4.*9"):
        topoccd.read_mesh(obj)
    unknown = tmp_path / "mesh.xyz"
    unknown.write_text("0 0 0\n")
    with pytest.raises(topoccd.FormatError, match="mesh.xyz"):
        topoccd.read_mesh(unknown)
    with pytest.raises(OSError):
        topoccd.read_sequence(tmp_path / "no-such-folder")
    with pytest.raises(topoccd.FormatError, match="at least two frames"):
        topoccd.read_sequence(tmp_path)
