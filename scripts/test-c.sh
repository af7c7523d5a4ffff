#!/usr/bin/env bash
# The C API (topoccd-c: libtopoccd_c, topoccd.h) and its C++ wrapper (topoccd.hpp), tested the
# way C and C++ programs use them; scripts/test.sh runs it, so CI does.
#
#  1. Builds the library and the CLI it is compared with (cargo, release; the CLI is
#     $TOPOCCD_CLI instead when set).
#  2. Builds the examples (topoccd-c/examples: step and line_search, in C and C++) with plain
#     cc and g++ against libtopoccd_c.a, and with CMake: topoccd-c as the top-level project
#     (then installed to a temporary prefix), a consumer project that finds the installed
#     package (find_package, shared library), one that adds topoccd-c as a subdirectory (static
#     library, cargo run by the build), and cc with pkg-config's flags.
#  3. Runs the examples: `step T0 T1` on cloth-funnel's step must print the contact count and
#     earliest time of the data's exact ground truth (134; 0.0452322, within the tolerance
#     below it) and its pairs must be those of `topoccd step --pairs -`; the same on the steps
#     of a generated nidus-cut sequence with their parents files; `line_search` must give the
#     earliest times of `topoccd run --earliest --json`.
#     `ipc` (the contact potential, in C and C++) checks itself against independent truth
#     and must exit 0: the analytic barrier energy and gradient of a point over a triangle,
#     and, on a cloth patch over a floor, the gradient and Hessian against central finite
#     differences and the projected Hessian's PSD-ness.
#  4. Runs the C and C++ tests (topoccd-c/tests) under AddressSanitizer and UBSan (leaks
#     included), the C++ ones with and without Eigen, and checks that a column-major Eigen
#     matrix is refused at compile time, and that a reference into a temporary (the dangling
#     `const topoccd_step& s = frames.step().c();`) does not compile. tests/freed.c (a query through a freed copy of a
#     handle: best effort, it reads freed memory on purpose) runs without the sanitizer.
#  5. Compiles and runs every ```c and ```cpp code block of README.md and docs/guide/src/*.md
#     as a program of its own (under ASan), because every code block of the README and the
#     guide must run; and the crate-level example of topoccd-c/src/lib.rs (its `//!` lines). The rule for such blocks: a block is a whole program, with its includes
#     and main(), reading no file. A block meant as a fragment (a declaration, a few lines of a
#     larger program) is marked with ",ignore" after its language, as in ```cpp,ignore or
#     ```c,ignore, and is skipped. Blocks of other languages (cmake, sh, ...) are not run here.
#
# Needs the Rust toolchain, python3, a C and C++ compiler, cmake, pkg-config and Eigen 3; when
# one is missing it stops at once and prints the apt-get line to run (it installs nothing). Reads the shared
# data at ../shared/data (or $TOPOCCD_DATA); without it the cloth-funnel check is skipped
# loudly, or fails with TOPOCCD_REQUIRE_DATA=1 (as .ci/run sets it). Takes about a minute
# after the cargo builds.
set -euo pipefail
cd "$(dirname "$0")/.."
root="$PWD"
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"

passed=0
failed=0
pass() { passed=$((passed + 1)); }
fail() {
    failed=$((failed + 1))
    echo "FAILED: $*" >&2
}

echo "== [${SECONDS} s] C and C++: tools"
missing=()
command -v cmake >/dev/null || missing+=(cmake)
command -v g++ >/dev/null || missing+=(g++)
command -v pkg-config >/dev/null || missing+=(pkg-config)
if ! { command -v pkg-config >/dev/null && pkg-config --exists eigen3; }; then
    missing+=(libeigen3-dev)
fi
if [ "${#missing[@]}" -gt 0 ]; then
    # Never installed from here (a user is not root, and a test must not change the system).
    echo "error: the C and C++ tests need ${missing[*]}; on Debian or Ubuntu run:" >&2
    echo "    sudo apt-get install -y ${missing[*]}" >&2
    exit 1
fi
CC="${CC:-cc}"
CXX="${CXX:-g++}"
EIGEN_FLAGS="$(pkg-config --cflags eigen3)"

echo "== [${SECONDS} s] C and C++: the library and the CLI (cargo build --release)"
cargo build --release --quiet -p topoccd-c
# The CLI compared with: $TOPOCCD_CLI when set (scripts/test.sh passes the one it built with
# the whole workspace), else this build of target/release/topoccd.
if [ -n "${TOPOCCD_CLI:-}" ]; then
    cli="$TOPOCCD_CLI"
    [ -x "$cli" ] || { echo "error: TOPOCCD_CLI=$cli is not an executable" >&2; exit 1; }
else
    cargo build --release --quiet -p topoccd-cli
    cli="$root/target/release/topoccd"
fi
lib="$root/target/release/libtopoccd_c.a"
system_libs=(-lpthread -ldl -lm)
include="$root/topoccd-c/include"

work="$root/target/test-c"
rm -rf "$work"
mkdir -p "$work/plain" "$work/asan" "$work/docs"
cflags=(-std=c11 -O2 -Wall -Wextra -Werror -pedantic)
cxxflags=(-std=c++17 -O2 -Wall -Wextra -Werror -pedantic)
asan=(-g -O1 -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:exitcode=23"
export UBSAN_OPTIONS="print_stacktrace=1"

echo "== [${SECONDS} s] C and C++: the examples with plain cc and g++"
for ex in step line_search proximity ipc; do
    "$CC" "${cflags[@]}" -I"$include" "topoccd-c/examples/$ex.c" "$lib" "${system_libs[@]}" \
        -o "$work/plain/$ex"
    # shellcheck disable=SC2086
    "$CXX" "${cxxflags[@]}" -I"$include" $EIGEN_FLAGS "topoccd-c/examples/$ex.cpp" "$lib" \
        "${system_libs[@]}" -o "$work/plain/${ex}_cpp"
    "$CXX" "${cxxflags[@]}" -DTOPOCCD_NO_EIGEN -I"$include" "topoccd-c/examples/$ex.cpp" "$lib" \
        "${system_libs[@]}" -o "$work/plain/${ex}_cpp_no_eigen"
done
pass

echo "== [${SECONDS} s] C and C++: the examples with CMake (top level, install, find_package, add_subdirectory)"
cmake_quiet() { "$@" >"$work/cmake.log" 2>&1 || { cat "$work/cmake.log" >&2; return 1; }; }
prefix="$work/prefix"
# The cargo target folder is the workspace's: cargo finds the library built above.
cmake_quiet cmake -S topoccd-c -B "$work/cmake" -DCMAKE_BUILD_TYPE=Release \
    -DTOPOCCD_CARGO_TARGET_DIR="$root/target" -DCMAKE_INSTALL_PREFIX="$prefix"
cmake_quiet cmake --build "$work/cmake" -j 2
cmake_quiet cmake --install "$work/cmake"
cmake_quiet cmake -S topoccd-c/tests/consumer -B "$work/consumer-package" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" -DTOPOCCD_SHARED=ON
cmake_quiet cmake --build "$work/consumer-package" -j 2
if ldd "$work/consumer-package/consumer_step" | grep -q "$prefix/lib/libtopoccd_c.so"; then
    pass
else
    fail "the find_package consumer does not use the installed shared library"
fi
cmake_quiet cmake -S topoccd-c/tests/consumer -B "$work/consumer-subdirectory" \
    -DCMAKE_BUILD_TYPE=Release -DTOPOCCD_SOURCE="$root/topoccd-c" \
    -DTOPOCCD_CARGO_TARGET_DIR="$root/target"
cmake_quiet cmake --build "$work/consumer-subdirectory" -j 2
# shellcheck disable=SC2046
"$CC" "${cflags[@]}" topoccd-c/examples/step.c \
    $(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs topoccd) \
    -Wl,-rpath,"$prefix/lib" -o "$work/plain/step_pkg_config"
pass

step_bins=("$work/plain/step" "$work/plain/step_cpp" "$work/plain/step_cpp_no_eigen"
    "$work/plain/step_pkg_config" "$work/cmake/topoccd_step" "$work/cmake/topoccd_step_cpp"
    "$work/consumer-package/consumer_step" "$work/consumer-subdirectory/consumer_step")
search_bins=("$work/plain/line_search" "$work/plain/line_search_cpp"
    "$work/plain/line_search_cpp_no_eigen" "$work/cmake/topoccd_line_search"
    "$work/cmake/topoccd_line_search_cpp" "$work/consumer-package/consumer_line_search_cpp"
    "$work/consumer-subdirectory/consumer_line_search_cpp")

# The pairs of a step example's output and of `topoccd step --pairs -`, compared exactly
# (ids, and times of impact as doubles: the example prints 17 digits, the CLI the shortest
# form; both read back to the same double).
same_pairs() {
    python3 - "$1" "$2" <<'EOF'
import sys
def pairs(path):
    out = []
    for line in open(path):
        f = line.strip().split(",")
        if f[0] in ("vf", "ee"):
            n = 3 if f[0] == "vf" else 5
            out.append((f[0], tuple(int(x) for x in f[1:n]), float(f[n]), tuple(f[n + 1:])))
    return out
a, b = pairs(sys.argv[1]), pairs(sys.argv[2])
if a != b or not a:
    sys.exit(f"{len(a)} pairs against the CLI's {len(b)}, not the same")
EOF
}

check_step() { # NAME T0 T1 [PARENTS]
    local name="$1" t0="$2" t1="$3" parents="${4:-}"
    local cli_args=() ex_args=("$t0" "$t1")
    if [ -n "$parents" ]; then
        cli_args=(--parents "$parents")
        ex_args+=("$parents")
    fi
    "$cli" step "$t0" "$t1" "${cli_args[@]}" --pairs - >"$work/cli.txt" 2>/dev/null
    for bin in "${step_bins[@]}"; do
        if ! "$bin" "${ex_args[@]}" >"$work/example.txt" 2>"$work/example.err"; then
            fail "$bin on $name: $(cat "$work/example.err")"
        elif ! same_pairs "$work/example.txt" "$work/cli.txt" 2>"$work/compare.err"; then
            fail "$bin on $name: $(cat "$work/compare.err")"
        else
            pass
        fi
    done
    echo "   $name: $(head -1 "$work/example.txt") (${#step_bins[@]} builds, the CLI's pairs)"
}

echo "== [${SECONDS} s] C and C++: the examples against the ground truth and the CLI"
data="${TOPOCCD_DATA:-../shared/data}"
funnel="$data/scenes/cloth-funnel"
if [ -f "$funnel/frames/227.ply" ]; then
    # The exact ground truth: the touching pairs of mma_bool, the earliest exact root of toi/.
    read -r truth_count truth_toi < <(python3 - "$funnel" <<'EOF'
import json, sys
d = sys.argv[1]
count = sum(sum(1 for b in json.load(open(f"{d}/mma_bool/227{k}_mma_bool.json")) if b) for k in ("vf", "ee"))
toi = min(float(line.split()[1]) for k in ("vf", "ee") for line in open(f"{d}/toi/227{k}_toi.txt") if line.strip())
print(count, repr(toi))
EOF
)
    for bin in "${step_bins[@]}"; do
        "$bin" "$funnel/frames/227.ply" "$funnel/frames/228.ply" >"$work/example.txt"
        out="$(head -1 "$work/example.txt")"
        if python3 - "$out" "$truth_count" "$truth_toi" <<'EOF'
import sys
line, count, toi = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
words = line.split()
got_count, got_toi = int(words[0]), float(words[-1])
# The issue's figures, and the data's: 134 contacts; the earliest time conservative (never
# later than the exact one) and within the default tolerance (1e-6) of it.
ok = got_count == count == 134 and toi - 1e-6 <= got_toi <= toi and abs(toi - 0.0452322) < 5e-8
sys.exit(0 if ok else f"printed '{line}'; truth {count} contacts, earliest {toi}")
EOF
        then pass; else fail "$bin on cloth-funnel"; fi
    done
    echo "   cloth-funnel: ${truth_count} contacts, earliest exact toi ${truth_toi} (ground truth)"
    check_step "cloth-funnel 227-228" "$funnel/frames/227.ply" "$funnel/frames/228.ply"
elif [ -n "${TOPOCCD_REQUIRE_DATA:-}" ]; then
    fail "the shared data is not at $data (TOPOCCD_REQUIRE_DATA is set)"
else
    echo "WARNING: the shared data is not at $data: the cloth-funnel check checked NOTHING" >&2
fi

seq_dir="$work/nidus-cut"
"$cli" gen nidus-cut "$seq_dir" --frames 3 --seed 1 >/dev/null
for k in 1 2; do
    t0="$seq_dir/000$((k - 1)).ply" t1="$seq_dir/000$k.ply"
    [ -f "$seq_dir/000$k.parents" ] || fail "nidus-cut frame $k has no parents file"
    check_step "nidus-cut step $((k - 1)) (a cut)" "$t0" "$t1" "$seq_dir/000$k.parents"
done

"$cli" run "$seq_dir" --earliest --json >"$work/run.jsonl" 2>/dev/null
for bin in "${search_bins[@]}"; do
    "$bin" "$seq_dir" >"$work/search.txt" 2>"$work/search.err" || fail "$bin: $(cat "$work/search.err")"
    if python3 - "$work/search.txt" "$work/run.jsonl" <<'EOF'
import json, re, sys
lines = [l for l in open(sys.argv[1]) if l.startswith("step ")]
runs = [json.loads(l) for l in open(sys.argv[2])]
runs = [r for r in runs if "step" in r]
assert len(lines) == len(runs) == 2, (len(lines), len(runs))
for line, run in zip(lines, runs):
    m = re.match(r"step (\d+): earliest toi (\S+) \((\d+) vf, (\d+) ee\)", line)
    k, toi, vf, ee = int(m[1]), m[2], int(m[3]), int(m[4])
    want = run["earliest_toi"]
    assert k == run["step"] and (vf, ee) == (run["vf"], run["ee"]), (line, run)
    assert (toi == "none") if want is None else float(toi) == want, (line, want)
# With Eigen, the step cut short where the line search stops has no contact.
for l in open(sys.argv[1]):
    if l.startswith("  the step to"):
        assert l.rstrip().endswith(": 0 contacts"), l
EOF
    then pass; else fail "$bin: not the earliest times of topoccd run --earliest"; fi
done
echo "   nidus-cut line search: $(grep -c '^step' "$work/search.txt") steps, the CLI's earliest times (${#search_bins[@]} builds)"

echo "== [${SECONDS} s] C and C++: the ipc examples (analytic values, finite differences, PSD)"
ipc_bins=("$work/plain/ipc" "$work/plain/ipc_cpp" "$work/plain/ipc_cpp_no_eigen"
    "$work/cmake/topoccd_ipc" "$work/cmake/topoccd_ipc_cpp")
for bin in "${ipc_bins[@]}"; do
    if "$bin" >"$work/ipc.txt" 2>"$work/ipc.err"; then
        pass
    else
        cat "$work/ipc.err" >&2
        fail "$bin: its checks failed"
    fi
done
echo "   $(grep -c . "$work/ipc.txt") lines, $(tail -1 "$work/ipc.txt") (${#ipc_bins[@]} builds)"

echo "== [${SECONDS} s] C and C++: the tests under AddressSanitizer and UBSan"
run_test() { # BINARY: its last line must be "N passed, 0 failed"
    local out
    if out="$("$1" 2>"$work/test.err")"; then
        echo "   $(basename "$1"): $(echo "$out" | tail -1)"
        pass
    else
        cat "$work/test.err" >&2
        fail "$(basename "$1"): $(echo "$out" | tail -1)"
    fi
}
"$CC" -std=c11 -Wall -Wextra -Werror "${asan[@]}" -I"$include" topoccd-c/tests/api.c "$lib" \
    "${system_libs[@]}" -o "$work/asan/api_c"
run_test "$work/asan/api_c"
# shellcheck disable=SC2086
"$CXX" -std=c++17 -Wall -Wextra -Werror "${asan[@]}" -I"$include" $EIGEN_FLAGS \
    topoccd-c/tests/api.cpp "$lib" "${system_libs[@]}" -o "$work/asan/api_cpp"
run_test "$work/asan/api_cpp"
"$CXX" -std=c++17 -Wall -Wextra -Werror "${asan[@]}" -DTOPOCCD_NO_EIGEN -I"$include" \
    topoccd-c/tests/api.cpp "$lib" "${system_libs[@]}" -o "$work/asan/api_cpp_no_eigen"
run_test "$work/asan/api_cpp_no_eigen"
"$CC" "${cflags[@]}" -I"$include" topoccd-c/tests/freed.c "$lib" "${system_libs[@]}" \
    -o "$work/plain/freed"
run_test "$work/plain/freed"
# The caps lifted under a 1 GiB address-space limit: an out-of-memory status, no abort
# (no sanitizers: their shadow memory does not fit the limit).
"$CC" "${cflags[@]}" -I"$include" topoccd-c/tests/memory.c "$lib" "${system_libs[@]}" \
    -o "$work/plain/memory"
MALLOC_ARENA_MAX=2 run_test "$work/plain/memory"
cat >"$work/column_major.cpp" <<'EOF'
#include <topoccd.hpp>
int main() {
    Eigen::MatrixXd x(3, 3);
    Eigen::MatrixXi f(1, 3);
    topoccd::Ccd().query(x, x, f);
}
EOF
# shellcheck disable=SC2086
if "$CXX" -std=c++17 -fsyntax-only -I"$include" $EIGEN_FLAGS "$work/column_major.cpp" \
    2>"$work/column_major.err"; then
    fail "a column-major Eigen matrix compiled (it would have to be copied)"
elif grep -q "row-major order" "$work/column_major.err"; then
    echo "   a column-major Eigen matrix is refused at compile time"
    pass
else
    cat "$work/column_major.err" >&2
    fail "a column-major Eigen matrix failed to compile for another reason"
fi

# The wrapper's accessors that return a reference into their object are deleted on temporaries:
# each of these lines would keep a dangling reference, and must not compile (one file each).
dangling=(
    'topoccd::Frames f = topoccd::Frames::read(argv[1], argv[2]); const topoccd_step& s = f.step().c(); return (int)s.x0_count;'
    'const topoccd_query_options& o = topoccd::QueryOptions().mode(topoccd::Mode::Earliest).c(); return (int)o.mode;'
    'const topoccd_query_options& o = topoccd::QueryOptions().c(); return (int)o.mode;'
    'topoccd_line_search_options o = topoccd::LineSearchOptions().c(); return (int)o.check_start;'
    'topoccd_line_search_options o = topoccd::LineSearchOptions().check_start(true).c(); return (int)o.check_start;'
    'std::vector<std::array<double, 3>> x; std::vector<std::array<uint32_t, 3>> t; std::vector<std::array<uint32_t, 2>> p; const topoccd_step& s = topoccd::Step(x, x, t).parents(p).c(); return (int)s.x0_count;'
)
for k in "${!dangling[@]}"; do
    printf '#include <topoccd.hpp>\nint main(int, char** argv) { %s }\n' "${dangling[$k]}" \
        >"$work/dangling_$k.cpp"
    if "$CXX" -std=c++17 -fsyntax-only -DTOPOCCD_NO_EIGEN -I"$include" "$work/dangling_$k.cpp" \
        2>"$work/dangling.err"; then
        fail "a reference into a temporary compiled: ${dangling[$k]}"
    elif grep -q "deleted" "$work/dangling.err"; then
        pass
    else
        cat "$work/dangling.err" >&2
        fail "dangling_$k.cpp failed to compile for another reason than the deleted overload"
    fi
done
# The same accessors on an lvalue compile (the check above is not vacuous).
printf '#include <topoccd.hpp>\nint main(int, char** argv) { topoccd::Frames f = topoccd::Frames::read(argv[1], argv[2]); topoccd::Step step = f.step(); const topoccd_step& s = step.c(); topoccd::QueryOptions q; topoccd::LineSearchOptions l; return (int)(s.x0_count + q.c().mode + l.c().check_start); }\n' \
    >"$work/lvalue.cpp"
if "$CXX" -std=c++17 -fsyntax-only -DTOPOCCD_NO_EIGEN -I"$include" "$work/lvalue.cpp" 2>"$work/lvalue.err"; then
    echo "   references into temporaries are refused at compile time (${#dangling[@]} forms)"
    pass
else
    cat "$work/lvalue.err" >&2
    fail "the accessors on lvalues do not compile"
fi

echo "== [${SECONDS} s] C and C++: the code blocks of README.md and docs/guide/src/*.md"
docs=(README.md topoccd-c/src/lib.rs)
if compgen -G "docs/guide/src/*.md" >/dev/null; then docs+=(docs/guide/src/*.md); fi
python3 - "$work/docs" "${docs[@]}" <<'EOF'
import pathlib, re, sys
out = pathlib.Path(sys.argv[1])
for doc in sys.argv[2:]:
    text = pathlib.Path(doc).read_text()
    if doc.endswith(".rs"):  # the crate's documentation: its `//!` lines
        text = "\n".join(l[4:] if l.startswith("//! ") else l[3:] for l in text.splitlines()
                         if l.startswith("//!")) + "\n"
    for n, m in enumerate(re.finditer(r"^```([^\n]*)\n(.*?)^```\s*$", text, re.M | re.S)):
        info = [w.strip() for w in m[1].split(",")]
        if info[0] not in ("c", "cpp", "c++") or "ignore" in info[1:]:
            continue
        ext = "c" if info[0] == "c" else "cpp"
        line = text.count("\n", 0, m.start()) + 1
        name = re.sub(r"[^A-Za-z0-9]+", "_", doc) + f"_line{line}.{ext}"
        (out / name).write_text(m[2])
EOF
blocks=0
for src in "$work"/docs/*.c "$work"/docs/*.cpp; do
    [ -e "$src" ] || continue
    blocks=$((blocks + 1))
    bin="${src%.*}"
    case "$src" in
        *.c) compile=("$CC" -std=c11 -Wall -Wextra -Werror "${asan[@]}") ;;
        *) compile=("$CXX" -std=c++17 -Wall -Wextra -Werror "${asan[@]}") ;;
    esac
    # shellcheck disable=SC2086
    if ! "${compile[@]}" -I"$include" $EIGEN_FLAGS "$src" "$lib" "${system_libs[@]}" -o "$bin" \
        2>"$work/block.err"; then
        cat "$work/block.err" >&2
        fail "$(basename "$src") does not compile"
    elif ! timeout 60 "$bin" >"$work/block.out" 2>&1; then
        cat "$work/block.out" >&2
        fail "$(basename "$src") failed"
    else
        pass
    fi
done
echo "   $blocks code blocks compiled and run"

echo "C and C++ checks: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
