"""One vocabulary: the option table of the guide (docs/guide/src/options.md) against the three
surfaces that name options outside Rust.

- Python: every keyword with a default of every public function and method of ``topoccd``
  (``topoccd.__all__``, the methods of its classes, ``topoccd.batch``) is in the table's Python
  column.
- C: every field of an options struct of ``topoccd-c/include/topoccd.h`` (a ``typedef struct
  topoccd_*_options``) but ``size`` and padding is in the table's C column.
- CLI: every long flag of ``topoccd --help`` and of each subcommand's ``--help`` that names
  an option of the table, or nearly does (a different spelling: ``t-max`` for ``tmax``,
  ``min-separation`` for ``min-distance``, ``timeout-seconds`` for ``timeout``), is the
  table's CLI spelling. Flags that are the command line's own (``--json``, ``--pairs-dir``)
  are not options of the library and are left alone.
- Back: each name the table gives exists where it says (a Python keyword, a C field, a flag).
- The deprecated names are accepted, with a warning naming the new one.
"""

import difflib
import inspect
import re
import subprocess
import warnings

import numpy as np
import pytest
import topoccd

from conftest import REPO

TABLE = REPO / "docs" / "guide" / "src" / "options.md"
HEADER = REPO / "topoccd-c" / "include" / "topoccd.h"
COLUMNS = ("option", "meaning", "range", "default", "Rust", "Python", "C", "CLI")
#: Names the table lists ahead of the code that adds them (none now: the CLI's --timeout
#: came with issue 43).
PENDING: set = set()


def table():
    """The rows of the guide's option table, as dicts of COLUMNS."""
    rows, header = [], None
    for line in TABLE.read_text().splitlines():
        if not line.startswith("|"):
            if header:
                break
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if header is None:
            header = cells
            assert tuple(cells) == COLUMNS, f"{TABLE}: columns {cells}, expected {COLUMNS}"
        elif not set(line) <= set("|-: "):
            assert len(cells) == len(COLUMNS), f"{TABLE}: a row of {len(cells)} cells: {line}"
            rows.append(dict(zip(COLUMNS, cells)))
    assert len(rows) >= 10, f"{TABLE}: {len(rows)} rows"
    return rows


def name(cell):
    """The name a cell gives: its first code span, or None for '-' and '(...)' cells."""
    if cell == "-" or cell.startswith("("):
        return None
    m = re.match(r"`([^`]+)`", cell)
    assert m, f"{TABLE}: a cell without a `name`: {cell!r}"
    return m.group(1)


def names(column):
    return {name(r[column]) for r in table()} - {None}


def near(a, b):
    """Two spellings of one name: equal but for case, '-' and '_', one the other plus a suffix
    (``timeout_seconds``), or close letter for letter."""
    na, nb = (re.sub(r"[-_]", "", x.lower()) for x in (a, b))
    if na == nb:
        return True
    if a.startswith(b + "_") or b.startswith(a + "_"):
        return True
    return difflib.SequenceMatcher(None, na, nb).ratio() >= 0.8


# Known pairs that are close in letters and mean different things.
DISTINCT = {frozenset(p) for p in [("max_contacts", "max_contact"), ("dhat", "dmin")]}

# Old spellings that must never come back (they are the deprecated aliases, hidden).
OLD = {"min_separation": "min_distance", "t_max": "tmax", "rescaling": "conservative_rescaling",
       "timeout_seconds": "timeout"}


def public_callables():
    """(qualified name, callable) of every public function and method of the package."""
    out = []
    modules = [topoccd, topoccd.batch]
    for module in modules:
        for attr in getattr(module, "__all__", None) or dir(module):
            if attr.startswith("_"):
                continue
            obj = getattr(module, attr)
            if inspect.isclass(obj) and obj.__module__.startswith("topoccd"):
                for m, f in vars(obj).items():
                    if not m.startswith("_") and callable(f):
                        out.append((f"{attr}.{m}", getattr(obj, m)))
            elif callable(obj) and not inspect.isclass(obj):
                out.append((f"{module.__name__}.{attr}", obj))
    return out


def keywords(f):
    """The keywords with a default (the options) of a callable."""
    try:
        sig = inspect.signature(f)
    except (TypeError, ValueError):
        return []
    return [
        p.name
        for p in sig.parameters.values()
        if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD) and p.default is not p.empty
    ]


def parameters(f):
    """Every named parameter of a callable, options or not (``dhat`` of ``proximity`` is one
    without a default)."""
    try:
        sig = inspect.signature(f)
    except (TypeError, ValueError):
        return []
    return [p.name for p in sig.parameters.values() if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)]


def test_every_python_keyword_is_in_the_table():
    allowed = names("Python")
    checked, wrong = 0, []
    for qualified, f in public_callables():
        for k in keywords(f):
            checked += 1
            if k not in allowed:
                close = [a for a in allowed if near(k, a)]
                hint = f" (the table spells it {close[0]!r})" if close else " (add a row to options.md)"
                wrong.append(f"{qualified}({k}=){hint}")
    assert checked >= 40, f"only {checked} keywords found: the signatures are not readable"
    assert not wrong, "keywords not in the option table:\n  " + "\n  ".join(wrong)
    # The main entry points are among those checked (the collection is not vacuous).
    assert {"min_distance", "tmax", "timeout"} <= set(keywords(topoccd.Ccd.query))
    assert "check_start" in keywords(topoccd.collision_free_stepsize)
    assert {"threads", "timeout"} <= set(keywords(topoccd.point_triangle_ccd))


def c_option_fields():
    """{struct: [field, ...]} of the options structs of topoccd.h."""
    text = HEADER.read_text()
    out = {}
    for m in re.finditer(r"typedef struct (topoccd_\w*options) \{(.*?)\} \1;", text, re.S):
        body = re.sub(r"//[^\n]*", "", m.group(2))
        fields = re.findall(r"(\w+)(?:\[[^\]]*\])?;", body)
        out[m.group(1)] = [f for f in fields if f != "size" and not f.startswith("_")]
    return out


def test_every_c_options_field_is_in_the_table():
    structs = c_option_fields()
    assert {"topoccd_query_options", "topoccd_line_search_options"} <= set(structs), structs
    allowed = names("C")
    wrong = [f"{s}.{f}" for s, fields in structs.items() for f in fields if f not in allowed]
    assert not wrong, "C options fields not in the option table: " + ", ".join(wrong)
    assert "timeout" in structs["topoccd_query_options"]


def cli_flags(cli):
    """{flag (without --): [command, ...]} over `topoccd --help` and each subcommand's."""
    def flags_of(*args):
        out = subprocess.run([cli, *args, "--help"], capture_output=True, text=True, check=True).stdout
        return set(re.findall(r"^\s+(?:-\w, )?--([a-z][a-z0-9-]*)", out, re.M)), out

    top, text = flags_of()
    commands = re.findall(r"^  ([a-z][a-z-]*)\s{2,}", text.split("Commands:")[1].split("Options:")[0], re.M)
    assert len(commands) >= 6, commands
    found = {f: ["topoccd"] for f in top}
    for c in commands:
        if c == "help":
            continue
        for f in flags_of(c)[0]:
            found.setdefault(f, []).append(c)
    found.pop("help", None)
    found.pop("version", None)
    return found


def test_every_cli_flag_that_names_an_option_is_spelled_as_the_table(cli):
    flags = cli_flags(cli)
    spelled = names("CLI")  # with their leading --
    table_flags = {s[2:] for s in spelled if s.startswith("--")}
    options = {r["option"] for r in table()} | names("Python") | names("C")
    wrong = []
    for flag, where in flags.items():
        if flag in table_flags:
            continue
        snake = flag.replace("-", "_")
        for o in options:
            plural = snake == o + "s"  # a list of them (`bench --methods bvh,cluster`)
            if near(snake, o) and not plural and frozenset((snake, o)) not in DISTINCT:
                wrong.append(f"--{flag} ({', '.join(where)}) looks like the option {o!r}")
        if snake in OLD:
            wrong.append(f"--{flag} ({', '.join(where)}) is the old name of {OLD[snake]!r}")
    assert not wrong, "command-line flags spelled otherwise than the option table:\n  " + "\n  ".join(wrong)
    # The main flags are there (the collection is not vacuous).
    assert {"min-distance", "tmax", "tolerance", "max-iterations", "max-contacts", "threads"} <= set(flags)


def test_every_name_of_the_table_exists(cli):
    py = {k for _, f in public_callables() for k in parameters(f)}
    c = {f for fields in c_option_fields().values() for f in fields}
    c_text = HEADER.read_text()
    flags = set(cli_flags(cli))
    missing = []
    for r in table():
        p, cf, fl = (None if n in PENDING else n for n in (name(r[c]) for c in ("Python", "C", "CLI")))
        if p and p not in py:
            missing.append(f"Python keyword {p}")
        # C: an options field, or another C name of the header (parents, topoccd_ccd*)
        if cf and cf not in c and not re.search(rf"\b{re.escape(cf.rstrip('*'))}\b", c_text):
            missing.append(f"C name {cf}")
        if fl and fl[2:] not in flags:
            missing.append(f"CLI flag {fl}")
    assert not missing, "the option table names what does not exist: " + ", ".join(missing)


def test_no_old_name_is_a_documented_option():
    for r in table():
        for column in ("Python", "C", "CLI"):
            n = name(r[column])
            if n:
                assert n.lstrip("-").replace("-", "_") not in OLD, f"{column}: {n}"


# The deprecated names, accepted for one release with a warning naming the new one.

FALL_X0 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, 1], [0.3, 0.2, 1], [0.2, 0.3, 1]], float)
FALL_X1 = FALL_X0 - np.r_[np.zeros((3, 3)), np.tile([0, 0, 2], (3, 1))]
TRIS = [[0, 1, 2], [3, 4, 5]]


@pytest.mark.parametrize(
    "call, old, new",
    [
        (lambda **k: topoccd.Ccd().query(FALL_X0, FALL_X1, TRIS, **k).earliest_toi, "t_max", "tmax"),
        (lambda **k: topoccd.query(FALL_X0, FALL_X1, TRIS, **k).earliest_toi, "t_max", "tmax"),
        (lambda **k: topoccd.collision_free_stepsize(FALL_X0, FALL_X1, TRIS, **k), "t_max", "tmax"),
        (lambda **k: topoccd.is_step_collision_free(FALL_X0, FALL_X1, TRIS, **k), "t_max", "tmax"),
    ],
)
def test_t_max_still_works_with_a_warning(call, old, new):
    with pytest.warns(DeprecationWarning, match=f"'{old}' is deprecated, use '{new}'"):
        got = call(**{old: 0.4})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert got == call(**{new: 0.4})


def test_min_separation_and_rescaling_still_work_with_a_warning():
    with pytest.warns(DeprecationWarning, match="'min_separation' is deprecated, use 'min_distance'"):
        old = topoccd.Ccd().query(FALL_X0, FALL_X1, TRIS, min_separation=0.5).earliest_toi
    assert old == topoccd.Ccd().query(FALL_X0, FALL_X1, TRIS, min_distance=0.5).earliest_toi
    assert old < 0.5 - 0.2  # 0.5 from the face: a quarter of the way down
    with pytest.warns(DeprecationWarning, match="'rescaling' is deprecated, use 'conservative_rescaling'"):
        alpha = topoccd.collision_free_stepsize(FALL_X0, FALL_X1, TRIS, rescaling=0.5)
    assert alpha == topoccd.collision_free_stepsize(FALL_X0, FALL_X1, TRIS, conservative_rescaling=0.5)
    with pytest.raises(TypeError, match="unexpected keyword argument 'rescaling'"):
        topoccd.is_step_collision_free(FALL_X0, FALL_X1, TRIS, rescaling=0.5)
    with pytest.raises(TypeError, match="unexpected keyword argument 'bogus'"):
        topoccd.Ccd().query(FALL_X0, FALL_X1, TRIS, bogus=1)


def test_the_cli_accepts_the_old_flags_with_a_note(cli, tmp_path):
    x0, x1 = tmp_path / "a.obj", tmp_path / "b.obj"
    for path, x in ((x0, FALL_X0), (x1, FALL_X1)):
        lines = [f"v {p[0]} {p[1]} {p[2]}" for p in x] + ["f 1 2 3", "f 4 5 6"]
        path.write_text("\n".join(lines) + "\n")

    def step(*flags):
        done = subprocess.run([cli, "step", str(x0), str(x1), "--json", *flags], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        return done.stdout, done.stderr

    for old, new, value in (("--t-max", "--tmax", "0.4"), ("--min-separation", "--min-distance", "0.5")):
        out_old, err_old = step(old, value)
        out_new, err_new = step(new, value)
        assert f"{old} is deprecated, use {new}" in err_old
        assert "deprecated" not in err_new
        assert re.sub(r'"seconds":\{[^}]*\}', "", out_old) == re.sub(r'"seconds":\{[^}]*\}', "", out_new)
