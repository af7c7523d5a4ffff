//! Hostile input through the built `topoccd` binary (issue 38): a collapsed mesh (positions
//! cast to integers) ends quickly with `--max-contacts` and is warned about, the same on any
//! thread count; `--threads` has the Python package's range; a folder given as a mesh, `nan`
//! in an ASCII PLY, an unwritable `--out` and a sequence folder holding other files each get a
//! clear message, before any work.

use std::path::Path;
use std::process::Command;

mod common;
use common::{Run, TempDir};

const SUITE: &str = "hostile";

fn topoccd(args: &[&str], dir: &Path) -> Run {
    common::run(Some(dir), args, &[])
}

fn assert_fails(run: &Run, needle: &str) {
    assert_eq!(run.output.status.code(), Some(2), "stderr: {}", run.stderr);
    assert!(run.stderr.contains(needle), "{}", run.stderr);
    assert!(run.stdout.is_empty(), "{}", run.stdout);
}

/// A `n x n` crumpled grid as OBJ text, its coordinates cast to integers (truncated).
fn collapsed_obj(n: u32) -> String {
    let mut text = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            let p = [
                2.5 * u - 1.25 + 0.3 * (7.0 * v).sin(),
                2.5 * v - 1.25,
                -1.0 + 0.9 * (5.0 * u).cos() * (3.0 * v).sin(),
            ];
            let [x, y, z] = p.map(f64::trunc);
            text += &format!("v {x} {y} {z}\n");
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            text += &format!("f {} {} {}\n", id(i, j), id(i + 1, j), id(i + 1, j + 1));
            text += &format!("f {} {} {}\n", id(i, j), id(i + 1, j + 1), id(i, j + 1));
        }
    }
    text
}

const TRIANGLES: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

#[test]
fn a_collapsed_step_is_warned_about_and_ends_with_a_cap() {
    let tmp = TempDir::new(SUITE, "collapsed");
    tmp.file("c.obj", collapsed_obj(24));
    let json = |threads: &str| {
        let args = [
            "--threads",
            threads,
            "step",
            "c.obj",
            "c.obj",
            "--method",
            "bvh",
            "--max-contacts",
            "5000",
            "--json",
            "--with-pairs",
        ];
        let run = topoccd(&args, &tmp.0);
        assert_eq!(run.output.status.code(), Some(0), "{}", run.stderr);
        (
            run.stderr,
            serde_json::from_str::<serde_json::Value>(&run.stdout).unwrap(),
        )
    };
    let (stderr, one) = json("1");
    let (_, two) = json("2");
    // Warned before the query: coincident vertices, zero-area triangles, whole coordinates.
    assert!(
        stderr.contains("vertices sit exactly on another vertex"),
        "{stderr}"
    );
    assert!(stderr.contains("triangles have zero area"), "{stderr}");
    assert!(stderr.contains("cast to integers"), "{stderr}");
    assert_eq!(one["truncated"]["reason"], "max_contacts");
    assert_eq!(
        one["vf"].as_u64().unwrap() + one["ee"].as_u64().unwrap(),
        5000
    );
    assert_eq!(
        one["pairs"], two["pairs"],
        "the same contacts on one and two threads"
    );
    assert_eq!(one["truncated"], two["truncated"]);
    // The text says so too.
    let run = topoccd(&["step", "c.obj", "c.obj", "--max-contacts", "10"], &tmp.0);
    assert!(
        run.stdout.contains("TRUNCATED (max_contacts"),
        "{}",
        run.stdout
    );
    // Earliest: toi 0, truncated.
    let args = [
        "step",
        "c.obj",
        "c.obj",
        "--earliest",
        "--max-contacts",
        "100",
        "--json",
    ];
    let run = topoccd(&args, &tmp.0);
    let out: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(out["earliest_toi"], 0.0);
    assert_eq!(out["truncated"]["reason"], "max_contacts");
}

/// Without `--max-contacts` the cap is what the memory limit allows: a collapsed step never
/// grows past it. `--max-contacts off` lifts it.
#[test]
fn the_default_cap_follows_the_memory_limit() {
    let tmp = TempDir::new(SUITE, "default-cap");
    tmp.file("c.obj", collapsed_obj(24));
    let json = |limit: &str, cap: &[&str]| {
        let mut args = vec!["--threads", "1", "step", "c.obj", "c.obj", "--json"];
        args.extend(["--max-memory", limit]);
        args.extend(cap);
        let run = topoccd(&args, &tmp.0);
        assert_eq!(run.output.status.code(), Some(0), "{}", run.stderr);
        serde_json::from_str::<serde_json::Value>(&run.stdout).unwrap()
    };
    let count = |v: &serde_json::Value| v["vf"].as_u64().unwrap() + v["ee"].as_u64().unwrap();
    let whole = json("off", &[]);
    assert!(whole["truncated"].is_null());
    assert!(count(&whole) > 500_000, "{}", count(&whole));
    // 32 MiB over (1 thread + 2) contacts of 112 bytes.
    let capped = json("32M", &[]);
    assert_eq!(capped["truncated"]["reason"], "max_contacts");
    assert_eq!(count(&capped), (32 << 20) / (3 * 112));
    assert!(json("32M", &["--max-contacts", "off"])["truncated"].is_null());
    assert_eq!(count(&json("32M", &["--max-contacts", "7"])), 7);
    // From the environment too.
    let output = Command::new(env!("CARGO_BIN_EXE_topoccd"))
        .current_dir(&tmp.0)
        .env("TOPOCCD_MAX_MEMORY", "32M")
        .args(["--threads", "1", "step", "c.obj", "c.obj", "--json"])
        .output()
        .expect("run topoccd");
    let v: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(count(&v), (32 << 20) / (3 * 112));
}

#[test]
fn threads_has_the_python_range() {
    let tmp = TempDir::new(SUITE, "threads");
    tmp.file("t.obj", TRIANGLES);
    for bad in ["0", "4097", "two"] {
        let run = topoccd(&["--threads", bad, "step", "t.obj", "t.obj"], &tmp.0);
        assert_eq!(run.output.status.code(), Some(2), "{bad}: {}", run.stderr);
        assert!(run.stderr.contains("--threads"), "{}", run.stderr);
    }
    let run = topoccd(&["--threads", "-1", "step", "t.obj", "t.obj"], &tmp.0);
    assert_eq!(run.output.status.code(), Some(2), "{}", run.stderr);
    let run = topoccd(&["--threads", "0", "step", "t.obj", "t.obj"], &tmp.0);
    assert!(
        run.stderr.contains("threads must be in [1, 4096], got 0"),
        "{}",
        run.stderr
    );
    // (The bounds themselves are a unit test of the parser: 4,096 threads take seconds to
    // start.)
    let run = topoccd(&["--threads", "3", "step", "t.obj", "t.obj"], &tmp.0);
    assert_eq!(run.output.status.code(), Some(0), "{}", run.stderr);
}

#[test]
fn a_folder_given_as_a_mesh_is_named_a_folder() {
    let tmp = TempDir::new(SUITE, "folder");
    tmp.file("t.obj", TRIANGLES);
    std::fs::create_dir_all(tmp.0.join("frames")).unwrap();
    std::fs::create_dir_all(tmp.0.join("mesh.ply")).unwrap();
    for folder in ["frames", "mesh.ply"] {
        let run = topoccd(&["step", folder, "t.obj"], &tmp.0);
        assert_fails(&run, &format!("{folder}: is a folder, not a mesh file"));
        let run = topoccd(&["render", folder, "--out", "x.png"], &tmp.0);
        assert_fails(&run, "is a folder, not a mesh file");
    }
}

#[test]
fn nan_in_an_ascii_ply_names_the_value_and_the_line() {
    let tmp = TempDir::new(SUITE, "nan");
    let header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                  property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                  end_header\n";
    tmp.file("n.ply", format!("{header}0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"));
    tmp.file("i.ply", format!("{header}0 0 0\n1 0 0\n0 1 inf\n3 0 1 2\n"));
    tmp.file(
        "w.ply",
        format!("{header}0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n"),
    );
    let run = topoccd(&["step", "n.ply", "n.ply"], &tmp.0);
    assert_fails(
        &run,
        "n.ply: cannot read vertex 1 of 3 (line 11): value 2 ('nan', property 'y') is not a \
         finite number",
    );
    assert!(!run.stderr.contains("expected one of"), "{}", run.stderr);
    let run = topoccd(&["step", "i.ply", "i.ply"], &tmp.0);
    assert_fails(
        &run,
        "(line 12): value 3 ('inf', property 'z') is not a finite number",
    );
    let run = topoccd(&["step", "w.ply", "w.ply"], &tmp.0);
    assert_fails(
        &run,
        "(line 11): value 3 ('zero', property 'z') is not a number",
    );
}

#[test]
fn an_unwritable_output_fails_before_any_work() {
    let tmp = TempDir::new(SUITE, "out");
    tmp.file("c.obj", collapsed_obj(4));
    let run = topoccd(&["render", "c.obj", "--out", "missing/x.png"], &tmp.0);
    assert_fails(
        &run,
        "missing/x.png: cannot write: the folder missing does not exist",
    );
    // Nothing was computed: the render prints its clusters only once it has them.
    assert!(!run.stderr.contains("clusters"), "{}", run.stderr);
    let run = topoccd(
        &["step", "c.obj", "c.obj", "--pairs", "missing/p.csv"],
        &tmp.0,
    );
    assert_fails(
        &run,
        "missing/p.csv: cannot write: the folder missing does not exist",
    );
    assert!(!run.stderr.contains("warning"), "{}", run.stderr);
    std::fs::create_dir_all(tmp.0.join("x.png")).unwrap();
    let run = topoccd(&["render", "c.obj", "--out", "x.png"], &tmp.0);
    assert_fails(&run, "x.png: cannot write: it is a folder");
    // A writable output is not left behind by the check when the command fails later.
    let run = topoccd(
        &["render", "c.obj", "--step", "nothing.obj", "--out", "y.png"],
        &tmp.0,
    );
    assert_eq!(run.output.status.code(), Some(2));
    assert!(!tmp.0.join("y.png").exists());
}

#[test]
fn a_sequence_folder_with_other_files_says_what_it_left_out() {
    let tmp = TempDir::new(SUITE, "seq");
    std::fs::create_dir_all(tmp.0.join("q")).unwrap();
    tmp.file("q/q0.obj", TRIANGLES);
    tmp.file("q/q1.obj", TRIANGLES);
    tmp.file("q/mesh.obj", TRIANGLES);
    tmp.file("q/notes.txt", "hi");
    let run = topoccd(&["run", "q"], &tmp.0);
    assert_eq!(run.output.status.code(), Some(0), "{}", run.stderr);
    assert!(
        run.stderr.contains(
            "warning: q: the sequence is the 2 frames q0.obj ... q1.obj (1 steps); left out: \
             mesh.obj (no number at the end of its name), notes.txt (not a .ply, .obj or .stl \
             file)"
        ),
        "{}",
        run.stderr
    );
    // A folder of frames alone: no warning.
    std::fs::remove_file(tmp.0.join("q/mesh.obj")).unwrap();
    std::fs::remove_file(tmp.0.join("q/notes.txt")).unwrap();
    let run = topoccd(&["run", "q"], &tmp.0);
    assert!(!run.stderr.contains("left out"), "{}", run.stderr);
}

/// `--timeout` (issue 43): a collapsed step without a cap has hundreds of millions of pairs at
/// t=0; `--timeout 0.5` ends it within about a second with an error that names the time limit
/// and what to do, for `step` and for `run`.
#[test]
fn timeout_ends_a_collapsed_step_with_a_clear_message() {
    let tmp = TempDir::new(SUITE, "timeout");
    tmp.file("c.obj", collapsed_obj(160));
    std::fs::create_dir_all(tmp.0.join("seq")).unwrap();
    for k in 0..2 {
        std::fs::write(tmp.0.join(format!("seq/{k:04}.obj")), collapsed_obj(160)).unwrap();
    }
    let step = [
        "--threads",
        "1",
        "step",
        "c.obj",
        "c.obj",
        "--method",
        "bvh",
        "--max-contacts",
        "off",
        "--timeout",
        "0.5",
    ];
    let run_args = [
        "--threads",
        "1",
        "run",
        "seq",
        "--no-check",
        "--max-contacts",
        "off",
        "--timeout",
        "0.5",
    ];
    for args in [&step[..], &run_args[..]] {
        let start = std::time::Instant::now();
        let run = topoccd(args, &tmp.0);
        let wall = start.elapsed().as_secs_f64();
        assert_ne!(
            run.output.status.code(),
            Some(0),
            "{args:?}: {}",
            run.stderr
        );
        assert!(
            run.stderr.contains("did not finish within --timeout 0.5 s"),
            "{args:?}: {}",
            run.stderr
        );
        assert!(run.stderr.contains("raise --timeout"), "{}", run.stderr);
        // Reading the meshes takes part of it; the query ends at 0.5 s (0.57 s in all here).
        assert!(wall < 1.5, "{args:?}: {wall} s");
    }
    // The static check, alike (hundreds of millions of touching pairs, no cap).
    let start = std::time::Instant::now();
    let run = topoccd(
        &["--threads", "1", "check", "c.obj", "--timeout", "0.5"],
        &tmp.0,
    );
    let wall = start.elapsed().as_secs_f64();
    assert_eq!(run.output.status.code(), Some(2), "{}", run.stderr);
    assert!(run.stderr.contains("stopped (deadline)"), "{}", run.stderr);
    assert!(wall < 1.5, "check: {wall} s");
    // A bad value is refused before any work.
    for bad in ["0", "soon"] {
        let run = topoccd(&["step", "c.obj", "c.obj", "--timeout", bad], &tmp.0);
        assert_fails(&run, "is not a positive number of seconds");
    }
}
