"""Property tests of the Python boundary (hypothesis): whatever the arrays' shapes, dtypes,
memory orders and strides, with NaN, infinities or nothing in them, a query either raises a
documented error (``InputError``, ``OptionsError``) or gives exactly the result of the same
values passed as contiguous float64 positions and int64 indices."""

import warnings

import numpy as np
import pytest
import topoccd
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

# Values a float32 and a float16 hold exactly, so that casting a float64 array to them and back
# is the identity for the reference as for the input (the cast is the caller's, not ours).
COORD = st.integers(-64, 64).map(lambda k: k / 16.0)
POSITION_DTYPES = [np.float64, np.float32, np.float16, np.int8, np.int32, np.int64, np.uint16]
INDEX_DTYPES = [np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint32, np.uint64]
LAYOUTS = ["c", "fortran", "strided", "reversed", "list", "readonly"]


def layout(array: np.ndarray, how: str):
    """The same values in another layout."""
    if how == "c":
        return np.ascontiguousarray(array)
    if how == "fortran":
        return np.asfortranarray(array)
    if how == "strided":
        doubled = np.repeat(array, 2, axis=0)
        return doubled[::2]
    if how == "reversed":
        if array.ndim < 2:
            return np.ascontiguousarray(array[::-1])[::-1]
        return np.ascontiguousarray(array[:, ::-1])[:, ::-1]
    if how == "list":
        return array.tolist()
    if how == "readonly":
        copy = np.array(array)
        copy.setflags(write=False)
        return copy
    raise ValueError(how)


@st.composite
def steps(draw):
    """A small step (maybe empty) as float64 positions and int64 indices."""
    n = draw(st.integers(0, 9))
    x0 = np.array(draw(st.lists(st.tuples(COORD, COORD, COORD), min_size=n, max_size=n)))
    x0 = x0.reshape(n, 3).astype(np.float64)
    moves = draw(st.lists(st.tuples(COORD, COORD, COORD), min_size=n, max_size=n))
    x1 = x0 + np.array(moves, dtype=np.float64).reshape(n, 3)
    tris = []
    if n >= 3:
        count = draw(st.integers(0, 6))
        for _ in range(count):
            tri = draw(st.lists(st.integers(0, n - 1), min_size=3, max_size=3, unique=True))
            tris.append(tri)
    triangles = np.array(tris, dtype=np.int64).reshape(-1, 3)
    return x0, x1, triangles


def outcome(**kwargs):
    """The report's content, or the exception's type and message."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", topoccd.InputWarning)
            r = topoccd.query(threads=1, **kwargs)
    except (topoccd.InputError, topoccd.OptionsError) as e:
        return (type(e), str(e))
    return (
        r.vf.tolist(),
        r.vf_toi.tolist(),
        r.vf_certainty.tolist(),
        r.ee.tolist(),
        r.ee_toi.tolist(),
        r.ee_certainty.tolist(),
        r.earliest,
        r.unresolved,
        r.truncated,
    )


SETTINGS = settings(
    max_examples=150,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


@SETTINGS
@given(
    step=steps(),
    dtypes=st.tuples(
        st.sampled_from(POSITION_DTYPES),
        st.sampled_from(POSITION_DTYPES),
        st.sampled_from(INDEX_DTYPES),
    ),
    layouts=st.tuples(*[st.sampled_from(LAYOUTS)] * 3),
    method=st.sampled_from(["bvh", "brute", "cluster"]),
    mode=st.sampled_from(["all", "earliest"]),
    cap=st.one_of(st.none(), st.integers(0, 5)),
)
def test_any_layout_gives_the_contiguous_float64_result(step, dtypes, layouts, method, mode, cap):
    x0, x1, triangles = step
    # The caller's arrays: the values cast to the caller's dtypes (indices that do not fit
    # the index dtype are out of this test's range).
    if triangles.size and triangles.max() > np.iinfo(dtypes[2]).max:
        return
    user = [x0.astype(dtypes[0]), x1.astype(dtypes[1]), triangles.astype(dtypes[2])]
    reference = [
        np.ascontiguousarray(user[0], dtype=np.float64),
        np.ascontiguousarray(user[1], dtype=np.float64),
        np.ascontiguousarray(user[2], dtype=np.int64),
    ]
    given_arrays = [layout(a, how) for a, how in zip(user, layouts)]
    options = {"method": method, "mode": mode, "max_contacts": cap}
    expected = outcome(x0=reference[0], x1=reference[1], triangles=reference[2], **options)
    got = outcome(x0=given_arrays[0], x1=given_arrays[1], triangles=given_arrays[2], **options)
    assert got == expected


@SETTINGS
@given(
    step=steps(),
    where=st.tuples(st.integers(0, 1), st.integers(0, 100), st.integers(0, 2)),
    bad=st.sampled_from([np.nan, np.inf, -np.inf]),
    how=st.sampled_from(LAYOUTS),
)
def test_a_non_finite_coordinate_is_an_input_error_naming_the_vertex(step, where, bad, how):
    x0, x1, triangles = step
    if len(x0) == 0:
        return
    frame, row, col = where[0], where[1] % len(x0), where[2]
    arrays = [x0.copy(), x1.copy()]
    arrays[frame][row, col] = bad
    with pytest.raises(topoccd.InputError, match=rf"vertex {row} has a non-finite coordinate"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", topoccd.InputWarning)
            topoccd.query(layout(arrays[0], how), layout(arrays[1], how), triangles)


SHAPES = st.lists(st.integers(0, 4), min_size=0, max_size=3).map(tuple)


@SETTINGS
@given(shapes=st.tuples(SHAPES, SHAPES, SHAPES), dtype=st.sampled_from(POSITION_DTYPES))
def test_any_shape_is_valid_or_an_input_error(shapes, dtype):
    """Arrays of arbitrary shapes (empty ones included): a valid step, or an ``InputError``
    naming the array, never another exception."""
    x0 = np.zeros(shapes[0], dtype=dtype)
    x1 = np.zeros(shapes[1], dtype=dtype)
    triangles = np.zeros(shapes[2], dtype=np.int64)
    # Valid only as a step: `(n, 3)` positions (or `(0,)`, no vertices) with as many rows at
    # t=0 as at t=1, and no triangles (`(0, 3)` or `(0,)`): a triangle of zeros repeats a
    # vertex, or names one that does not exist.
    def positions_ok(shape):
        return (len(shape) == 2 and shape[1] == 3) or shape == (0,)

    valid = (
        positions_ok(shapes[0])
        and positions_ok(shapes[1])
        and shapes[0][0] == shapes[1][0]
        and shapes[2] in ((0,), (0, 3))
    )
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", topoccd.InputWarning)
            r = topoccd.query(x0, x1, triangles)
    except topoccd.InputError as e:
        assert not valid, e
        assert any(name in str(e) for name in ("x0", "x1", "triangles", "vertex", "triangle"))
        return
    assert valid
    assert len(r) == 0


@SETTINGS
@given(
    tolerance=st.floats(allow_nan=True, allow_infinity=True),
    tmax=st.floats(allow_nan=True, allow_infinity=True),
    min_distance=st.floats(allow_nan=True, allow_infinity=True),
    max_contacts=st.one_of(st.none(), st.integers(-3, 3)),
    timeout=st.one_of(st.none(), st.floats(allow_nan=True, allow_infinity=True)),
)
def test_any_option_value_is_valid_or_an_options_error(
    tolerance, tmax, min_distance, max_contacts, timeout
):
    fixed = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float64)
    valid = (
        0 < tolerance < 1
        and 0 < tmax <= 1
        and 0 <= min_distance < float("inf")
        and (max_contacts is None or max_contacts >= 0)
        and (timeout is None or 0 < timeout < 1e9)
    )
    try:
        topoccd.query(
            fixed,
            fixed,
            [[0, 1, 2]],
            tolerance=tolerance,
            tmax=tmax,
            min_distance=min_distance,
            max_contacts=max_contacts,
            timeout=timeout,
        )
    except topoccd.OptionsError:
        assert not valid
        return
    except TimeoutError:
        # A valid timeout too short for the query: the documented outcome.
        assert valid and timeout is not None and timeout < 0.1
        return
    assert valid
