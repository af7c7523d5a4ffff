//! Malformed input through the built `topoccd` binary: every error goes to stderr with a
//! non-zero exit and a message naming the file and the problem, stdout stays empty (or valid
//! JSON with `--json`), and nothing panics. Valid but degenerate input (an empty mesh, a single
//! triangle) is not an error.

use std::path::Path;
use std::time::{Duration, Instant};

mod common;
use common::{Run, TempDir};

const SUITE: &str = "malformed";

fn topoccd_env(args: &[&Path], env: &[(&str, &str)]) -> Run {
    common::run(None, args, env)
}

fn topoccd(args: &[&Path]) -> Run {
    topoccd_env(args, &[])
}

fn p(s: &str) -> &Path {
    Path::new(s)
}

/// Asserts a failure: exit code 2, an `error:` on stderr containing every one of `needles`,
/// and on stdout nothing, or with `--json` one JSON object `{"error": ...}` saying the same.
fn assert_fails(run: &Run, needles: &[&str]) {
    assert_eq!(run.output.status.code(), Some(2), "stderr: {}", run.stderr);
    if !run.stdout.is_empty() {
        let json: serde_json::Value = serde_json::from_str(run.stdout.trim())
            .unwrap_or_else(|e| panic!("stdout is not JSON ({e}): {}", run.stdout));
        let message = json["error"].as_str().unwrap_or_default();
        assert!(
            run.stderr.contains(message) && !message.is_empty(),
            "stdout: {}",
            run.stdout
        );
    }
    assert!(run.stderr.starts_with("error: "), "stderr: {}", run.stderr);
    for needle in needles {
        assert!(
            run.stderr.contains(needle),
            "no {needle:?} in: {}",
            run.stderr
        );
    }
}

/// The JSON object a successful `--json` run printed on one line.
fn json(run: &Run) -> serde_json::Value {
    assert!(run.output.status.success(), "stderr: {}", run.stderr);
    assert_eq!(run.stdout.lines().count(), 1, "stdout: {}", run.stdout);
    serde_json::from_str(&run.stdout).expect("stdout is valid JSON")
}

/// An ASCII PLY file of float vertices and uchar/int faces.
fn ply(vertices: &[[f64; 3]], faces: &[[i64; 3]]) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\n\
         property float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        vertices.len(),
        faces.len()
    );
    for [x, y, z] in vertices {
        s += &format!("{x} {y} {z}\n");
    }
    for [a, b, c] in faces {
        s += &format!("3 {a} {b} {c}\n");
    }
    s
}

/// A binary little-endian PLY file of double vertices and uchar/int faces, with the counts
/// the header declares given separately from the data.
fn binary_ply(declared: (u64, u64), vertices: &[[f64; 3]], faces: &[[i32; 3]]) -> Vec<u8> {
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty double x\n\
         property double y\nproperty double z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        declared.0, declared.1
    )
    .into_bytes();
    for v in vertices {
        bytes.extend(v.iter().flat_map(|c| c.to_le_bytes()));
    }
    for f in faces {
        bytes.push(3);
        bytes.extend(f.iter().flat_map(|i| i.to_le_bytes()));
    }
    bytes
}

const SQUARE: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [1.0, 1.0, 0.0],
];

#[test]
fn wrong_magic_is_refused() {
    let tmp = TempDir::new(SUITE, "magic");
    let obj_in_ply = tmp.file("mesh.ply", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let path = obj_in_ply.display().to_string();
    for json in [false, true] {
        let mut args = vec![p("step"), &obj_in_ply, &obj_in_ply];
        if json {
            args.push(p("--json"));
        }
        let run = topoccd(&args);
        assert_fails(
            &run,
            &[
                &path,
                "not a PLY file (it does not start with the line 'ply')",
            ],
        );
    }
}

#[test]
fn truncated_binary_ply_names_the_element() {
    let tmp = TempDir::new(SUITE, "truncated");
    let whole = binary_ply((4, 2), &SQUARE, &[[0, 1, 2], [1, 3, 2]]);
    let good = tmp.file("good.ply", &whole);
    let cut = tmp.file("cut.ply", &whole[..whole.len() - 5]);
    let run = topoccd(&[p("step"), p("--json"), &good, &cut]);
    assert_fails(
        &run,
        &[&format!("{}: file ended in face 1 of 2", cut.display())],
    );
    // Cut inside the vertices: the faces' index lists could be empty (one byte each), so the
    // file is too short for its header's counts, which is seen before reading any data.
    let cut = tmp.file("short.ply", &whole[..whole.len() - 2 * 13 - 10]);
    let run = topoccd(&[p("step"), p("--json"), &good, &cut]);
    assert_fails(
        &run,
        &[&format!(
            "{}: the file has 258 bytes, too few for the 4 vertex elements its header declares \
             (at least 268 bytes with the header and the elements before them): the file is \
             truncated or its header is wrong",
            cut.display()
        )],
    );
}

#[test]
fn wrong_element_counts_are_refused() {
    let tmp = TempDir::new(SUITE, "counts");
    let good = tmp.file(
        "good.ply",
        binary_ply((4, 2), &SQUARE, &[[0, 1, 2], [1, 3, 2]]),
    );
    assert_eq!(
        json(&topoccd(&[p("step"), p("--json"), &good, &good]))["triangles"],
        2
    );
    // More faces, or more vertices, declared than present: where the file could still hold
    // them (if the index lists were empty), reading stops where the data runs out; where it
    // cannot, right after the header.
    for (name, declared, needle) in [
        ("faces.ply", (4, 3), "file ended in face 2 of 3"),
        (
            "vertex.ply",
            (5, 2),
            "face 0 of 2 has 0 vertices, but only triangles",
        ),
        ("faces30.ply", (4, 30), "too few for the 30 face elements"),
        ("vertices9.ply", (9, 2), "too few for the 9 vertex elements"),
    ] {
        let bad = tmp.file(name, binary_ply(declared, &SQUARE, &[[0, 1, 2], [1, 3, 2]]));
        let run = topoccd(&[p("step"), &bad, &bad]);
        assert_fails(&run, &[&bad.display().to_string(), needle]);
    }
    // Fewer vertices declared than present: the faces are read from the fourth vertex's
    // bytes, whose first byte (of 0.0) is an empty index list.
    let bad = tmp.file(
        "fewer.ply",
        binary_ply((3, 2), &SQUARE, &[[0, 1, 2], [1, 3, 2]]),
    );
    let run = topoccd(&[p("step"), &bad, &bad]);
    assert_fails(
        &run,
        &[&bad.display().to_string(), "face 0 of 2 has 0 vertices"],
    );
}

#[test]
fn absurd_counts_fail_fast_without_allocating() {
    let tmp = TempDir::new(SUITE, "absurd");
    let header = "ply\nformat binary_little_endian 1.0\nelement vertex 10000000000\n\
                  property float x\nproperty float y\nproperty float z\nelement face 20000000000\n\
                  property list uchar int vertex_indices\nend_header\n";
    let absurd = tmp.file("absurd.ply", header);
    let started = Instant::now();
    let run = topoccd(&[p("step"), p("--json"), &absurd, &absurd]);
    assert!(started.elapsed() < Duration::from_secs(10));
    assert_fails(
        &run,
        &[
            &absurd.display().to_string(),
            "the file has 189 bytes, too few for the 10000000000 vertex elements its header \
             declares (at least 120000000189 bytes",
        ],
    );
}

#[test]
fn face_index_out_of_range_names_the_face() {
    let tmp = TempDir::new(SUITE, "range");
    let bad = tmp.file("bad.ply", ply(&SQUARE, &[[0, 1, 2], [1, 4, 2]]));
    let run = topoccd(&[p("step"), &bad, &bad]);
    assert_fails(
        &run,
        &[
            &bad.display().to_string(),
            "face 1 of 2 (line 15): vertex index 4 is out of range for 4 vertices",
        ],
    );
}

#[test]
fn mismatched_vertex_counts_name_both_files() {
    let tmp = TempDir::new(SUITE, "mismatch");
    let four = tmp.file("four.ply", ply(&SQUARE, &[[0, 1, 2]]));
    let three = tmp.file("three.ply", ply(&SQUARE[..3], &[[0, 1, 2]]));
    let four_obj = tmp.file("four.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\n");
    // From the PLY headers, and from the meshes read (OBJ has no header).
    for (t0, t1) in [(&four, &three), (&four_obj, &three)] {
        let run = topoccd(&[p("step"), p("--json"), t0, t1]);
        let expected = format!(
            "{} has 4 vertices but {} has 3: a step needs the same vertices at t=0 and t=1",
            t0.display(),
            t1.display()
        );
        assert_fails(&run, &[&expected]);
    }
}

#[test]
fn non_finite_coordinates_are_refused() {
    let tmp = TempDir::new(SUITE, "nan");
    let good = tmp.file("good.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let nan = tmp.file("nan.obj", "v 0 0 0\nv 1 NaN 0\nv 0 1 0\nf 1 2 3\n");
    let run = topoccd(&[p("step"), &good, &nan]);
    assert_fails(
        &run,
        &[
            &nan.display().to_string(),
            "vertex 1 has a non-finite coordinate at t=1",
        ],
    );
}

#[test]
fn an_empty_mesh_has_no_contacts() {
    let tmp = TempDir::new(SUITE, "empty");
    let empty_ply = tmp.file("empty.ply", ply(&[], &[]));
    let empty_obj = tmp.file("empty.obj", "# nothing\n");
    let lonely_vertices = tmp.file("vertices.obj", "v 0 0 0\nv 1 0 0\n");
    for (t0, t1) in [
        (&empty_ply, &empty_ply),
        (&empty_obj, &empty_obj),
        (&empty_ply, &empty_obj),
        (&lonely_vertices, &lonely_vertices),
    ] {
        for method in ["bvh", "brute"] {
            let run = topoccd(&[p("step"), p("--json"), p("--method"), p(method), t0, t1]);
            let out = json(&run);
            assert_eq!(out["triangles"], 0);
            assert_eq!(out["vf"], 0, "{out}");
            assert_eq!(out["ee"], 0, "{out}");
            assert!(out["earliest_toi"].is_null(), "{out}");
        }
    }
    let run = topoccd(&[p("step"), &empty_ply, &empty_ply]);
    assert!(run.output.status.success(), "{}", run.stderr);
    assert!(run
        .stdout
        .starts_with("0 vertices, 0 triangles: 0 vf and 0 ee contacts, earliest toi none"));
}

#[test]
fn a_single_triangle_has_no_contacts() {
    let tmp = TempDir::new(SUITE, "one");
    let t0 = tmp.file("t0.ply", ply(&SQUARE[..3], &[[0, 1, 2]]));
    let t1 = tmp.file(
        "t1.ply",
        ply(
            &[[0.0, 0.0, 1.0], [2.0, 0.0, 0.0], [0.0, 1.0, -1.0]],
            &[[0, 1, 2]],
        ),
    );
    for method in ["bvh", "brute"] {
        let run = topoccd(&[p("step"), p("--json"), p("--method"), p(method), &t0, &t1]);
        let out = json(&run);
        assert_eq!(
            (out["vertices"].as_u64(), out["triangles"].as_u64()),
            (Some(3), Some(1))
        );
        assert_eq!((out["vf"].as_u64(), out["ee"].as_u64()), (Some(0), Some(0)));
        assert!(out["earliest_toi"].is_null(), "{out}");
    }
}

#[test]
fn a_step_over_the_memory_limit_is_refused_up_front() {
    let tmp = TempDir::new(SUITE, "memory");
    let t0 = tmp.file("t0.ply", ply(&SQUARE, &[[0, 1, 2], [1, 3, 2]]));
    let t1 = tmp.file(
        "t1.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n",
    );
    let needs = "a step of 4 vertices and 2 triangles needs about 16.00 MiB (estimated), \
                 more than the limit of 1 MiB";
    // From the PLY headers, and from the meshes read.
    for t1 in [&t0, &t1] {
        let run = topoccd(&[p("step"), p("--json"), p("--max-memory"), p("1M"), &t0, t1]);
        assert_fails(
            &run,
            &[needs, "set by --max-memory", "refused before", "'off'"],
        );
        let run = topoccd_env(
            &[p("step"), p("--json"), &t0, t1],
            &[("TOPOCCD_MAX_MEMORY", "1M")],
        );
        assert_fails(&run, &[needs, "set by TOPOCCD_MAX_MEMORY"]);
    }
    // The flag wins over the variable; 'off' skips the check.
    let run = topoccd_env(
        &[
            p("step"),
            p("--json"),
            p("--max-memory"),
            p("off"),
            &t0,
            &t0,
        ],
        &[("TOPOCCD_MAX_MEMORY", "1M")],
    );
    assert_eq!(json(&run)["vf"], 0);
    let run = topoccd_env(
        &[p("step"), p("--json"), &t0, &t0],
        &[("TOPOCCD_MAX_MEMORY", "1G")],
    );
    assert_eq!(json(&run)["triangles"], 2);
    // A malformed limit is an error, not ignored.
    let run = topoccd_env(&[p("step"), &t0, &t0], &[("TOPOCCD_MAX_MEMORY", "lots")]);
    assert_fails(&run, &["TOPOCCD_MAX_MEMORY: \"lots\" is not a size"]);
    let run = topoccd(&[p("step"), p("--max-memory"), p("12Q"), &t0, &t0]);
    assert_eq!(run.output.status.code(), Some(2), "{}", run.stderr);
    assert!(
        run.stdout.is_empty() && run.stderr.contains("is not a size"),
        "{}",
        run.stderr
    );
}

#[test]
fn malformed_query_files_and_sequences_are_refused() {
    let tmp = TempDir::new(SUITE, "queries");
    std::fs::create_dir_all(tmp.0.join("set/vertex-face")).expect("mkdir");
    let csv = tmp.file("set/vertex-face/q.csv", "1,1,0,1,0,1,0\n1,1,0,1,0,1,0\n");
    let run = topoccd(&[p("queries"), &tmp.0]);
    assert_fails(
        &run,
        &[
            &format!("{}:2", csv.display()),
            "2 rows is not a whole number of 8-row queries",
        ],
    );

    let seq = TempDir::new(SUITE, "sequence");
    seq.file("0000.ply", ply(&SQUARE, &[[0, 1, 2]]));
    let run = topoccd(&[p("run"), &seq.0]);
    assert_fails(&run, &["a sequence needs at least two frames", "found 1"]);
    seq.file("0001.ply", ply(&SQUARE, &[[0, 1, 2]]));
    seq.file("0001.parents", "4 0\n");
    let run = topoccd(&[p("run"), &seq.0]);
    assert_fails(&run, &["0001.parents:1: NEW_ID 4 is not a new vertex"]);
}

/// Invalid query options are refused by every command that runs steps, with the library's own
/// message (one argument struct, one validation).
#[test]
fn invalid_options_are_refused_by_every_command_alike() {
    let dir = TempDir::new(SUITE, "options");
    let tri = ply(
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[[0, 1, 2]],
    );
    let a = dir.file("0000.ply", &tri);
    let b = dir.file("0001.ply", &tri);
    let cases: [(&[&str], &str); 5] = [
        (&["--tolerance", "0"], "tolerance must be in (0, 1), got 0"),
        (
            &["--tolerance", "NaN"],
            "tolerance must be in (0, 1), got NaN",
        ),
        (&["--tmax", "2"], "tmax must be in (0, 1], got 2"),
        (
            &["--min-distance", "-1"],
            "min_distance must be finite and >= 0, got -1",
        ),
        (
            &["--max-iterations", "0"],
            "max_iterations must be at least 1, got 0",
        ),
    ];
    for (flags, message) in cases {
        let flags: Vec<&Path> = flags.iter().map(|f| p(f)).collect();
        let step: Vec<&Path> = [p("step"), a.as_path(), b.as_path()]
            .into_iter()
            .chain(flags.iter().copied())
            .collect();
        let run: Vec<&Path> = [p("run"), dir.0.as_path()]
            .into_iter()
            .chain(flags.iter().copied())
            .collect();
        let bench: Vec<&Path> = [p("bench"), dir.0.as_path()]
            .into_iter()
            .chain(flags.iter().copied())
            .collect();
        for args in [step, run, bench] {
            let out = topoccd(&args);
            assert_fails(&out, &[message]);
        }
    }
    // k is checked by the shared arguments too (bench once ran k=18 for --k 8).
    for command in ["step", "bench"] {
        let args: Vec<&Path> = match command {
            "step" => vec![p("step"), a.as_path(), b.as_path(), p("--k"), p("8")],
            _ => vec![p("bench"), dir.0.as_path(), p("--k"), p("8")],
        };
        let out = topoccd(&args);
        assert_eq!(
            out.output.status.code(),
            Some(2),
            "{command}: {}",
            out.stderr
        );
        assert!(
            out.stderr.contains("k must be 6, 14, 18 or 26, got 8"),
            "{command}: {}",
            out.stderr
        );
    }
}

/// `step --earliest --json` names the earliest pair and lists the pair(s) reaching it, and
/// `--pairs` writes them.
#[test]
fn earliest_shows_its_pairs() {
    let dir = TempDir::new(SUITE, "earliest");
    // A vertex (3) of a small carrier triangle falls through a fixed triangle at t = 0.5.
    let t0 = ply(
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.2, 0.2, 1.0],
            [0.3, 0.2, 3.0],
            [0.2, 0.3, 3.0],
        ],
        &[[0, 1, 2], [3, 4, 5]],
    );
    let t1 = ply(
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.2, 0.2, -1.0],
            [0.3, 0.2, 1.0],
            [0.2, 0.3, 1.0],
        ],
        &[[0, 1, 2], [3, 4, 5]],
    );
    let (a, b) = (dir.file("a.ply", &t0), dir.file("b.ply", &t1));
    let pairs = dir.0.join("pairs.csv");
    let out = topoccd(&[
        p("step"),
        &a,
        &b,
        p("--earliest"),
        p("--json"),
        p("--pairs"),
        &pairs,
    ]);
    assert_eq!(out.output.status.code(), Some(0), "{}", out.stderr);
    let j = json(&out);
    let toi = j["earliest_toi"].as_f64().expect("an earliest time");
    assert!((toi - 0.5).abs() < 1e-6, "{j}");
    assert_eq!(j["earliest"]["Vf"]["vertex"], 3, "{j}");
    assert_eq!(j["earliest"]["Vf"]["face"], 0, "{j}");
    assert_eq!(j["vf"], 1, "{j}");
    assert_eq!(j["unresolved"], 0, "{j}");
    assert_eq!(j["pairs"]["vf"][0]["vertex"], 3, "{j}");
    let written = std::fs::read_to_string(&pairs).expect("the pairs file");
    assert!(written.starts_with("vf,3,0,0.4999"), "{written}");
}
