//! Issue 12 through the built `topoccd` binary: output that pipes (`--pairs -`, `run`'s lines
//! on stdout when stderr is not a terminal, no timing chatter, `bench --json` types), one
//! topology-changing step with `--parents`, coincident vertices warned about and `--weld`ed,
//! reader notes, and `run` on the folders `bench` accepts.

use std::path::Path;

mod common;
use common::{Run, TempDir};

const SUITE: &str = "frontdoor";

/// Runs the binary in `cwd` with stdout and stderr both piped (neither is a terminal).
fn topoccd_in(cwd: &Path, args: &[&str]) -> Run {
    common::run(Some(cwd), args, &[])
}

fn ok(run: &Run) {
    assert!(
        run.output.status.success(),
        "exit {:?}\nstdout: {}\nstderr: {}",
        run.output.status.code(),
        run.stdout,
        run.stderr
    );
}

fn obj(positions: &[[f64; 3]], triangles: &[&[u32]]) -> String {
    let mut text = String::new();
    for p in positions {
        text.push_str(&format!("v {:?} {:?} {:?}\n", p[0], p[1], p[2]));
    }
    for t in triangles {
        let ids: Vec<String> = t.iter().map(|i| (i + 1).to_string()).collect();
        text.push_str(&format!("f {}\n", ids.join(" ")));
    }
    text
}

/// A static sheet of two triangles whose shared edge is made of duplicated vertices (a UV
/// seam: 3 sits on 1, 4 on 2), and a small triangle falling through it at t = 0.5.
fn seam_frames(z: f64) -> String {
    obj(
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.2, 0.2, z],
            [0.3, 0.2, z],
            [0.2, 0.3, z],
        ],
        &[&[0, 1, 2], &[3, 5, 4], &[6, 7, 8]],
    )
}

fn json(text: &str) -> serde_json::Value {
    serde_json::from_str(text.trim()).unwrap_or_else(|e| panic!("not JSON ({e}): {text}"))
}

#[test]
fn pairs_dash_writes_the_pairs_to_stdout_and_the_summary_to_stderr() {
    // Issue 12: "`--pairs -` creates a file named `-`".
    let tmp = TempDir::new(SUITE, "pairs-dash");
    tmp.file("t0.obj", seam_frames(1.0));
    tmp.file("t1.obj", seam_frames(-1.0));
    let run = topoccd_in(
        &tmp.0,
        &["step", "--weld", "--pairs", "-", "t0.obj", "t1.obj"],
    );
    ok(&run);
    assert!(!tmp.0.join("-").exists(), "a file named '-' was created");
    let lines: Vec<&str> = run.stdout.lines().collect();
    assert!(!lines.is_empty());
    assert!(
        lines
            .iter()
            .all(|l| l.starts_with("vf,") || l.starts_with("ee,")),
        "{}",
        run.stdout
    );
    // Ids are those of the files, although vertices 3 and 4 were merged.
    assert!(
        lines.iter().any(|l| l.starts_with("vf,6,0,")),
        "{}",
        run.stdout
    );
    assert!(
        run.stderr.contains("vertices, "),
        "summary on stderr: {}",
        run.stderr
    );
    // Issue 12: "(reading the two frames took 0.000 s)" on stderr for every step.
    assert!(
        !run.stderr.contains("reading the two frames took"),
        "{}",
        run.stderr
    );
    // With --json the pairs go in the JSON instead.
    let run = topoccd_in(
        &tmp.0,
        &["step", "--json", "--pairs", "-", "t0.obj", "t1.obj"],
    );
    assert_eq!(run.output.status.code(), Some(2));
    assert!(run.stderr.contains("--with-pairs"), "{}", run.stderr);
}

#[test]
fn coincident_vertices_are_warned_about_and_welded() {
    // Issue 12: duplicates "give thousands of spurious contacts at t=0 (earliest 0.0 instead of
    // 0.5) with no warning".
    let tmp = TempDir::new(SUITE, "weld");
    tmp.file("t0.obj", seam_frames(1.0));
    tmp.file("t1.obj", seam_frames(-1.0));
    let plain = topoccd_in(&tmp.0, &["step", "--json", "t0.obj", "t1.obj"]);
    ok(&plain);
    assert!(
        plain
            .stderr
            .contains("warning: t0.obj: 2 vertices sit exactly on another vertex"),
        "{}",
        plain.stderr
    );
    assert!(plain.stderr.contains("--weld"), "{}", plain.stderr);
    let toi = |run: &Run| {
        json(&run.stdout)["earliest_toi"]
            .as_f64()
            .expect("a contact")
    };
    assert!(toi(&plain) < 1e-6, "{}", plain.stdout);
    let welded = topoccd_in(&tmp.0, &["step", "--json", "--weld", "t0.obj", "t1.obj"]);
    ok(&welded);
    assert!((toi(&welded) - 0.5).abs() < 1e-3, "{}", welded.stdout);
    assert!(!welded.stderr.contains("warning:"), "{}", welded.stderr);
    assert!(
        welded
            .stderr
            .contains("--weld merged 2 vertices (in 2 groups)"),
        "{}",
        welded.stderr
    );
    // The step's own counts are those of the welded mesh.
    assert_eq!(json(&welded.stdout)["vertices"], 7);
}

#[test]
fn one_topology_changing_step_with_parents() {
    // Issue 12: "`step` has no `--parents`, so one topology-changing step needs a folder".
    let tmp = TempDir::new(SUITE, "parents");
    let sheet = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let top = [[0.2, 0.2, 1.0], [0.6, 0.2, 1.0], [0.2, 0.6, 1.0]];
    let mut p0 = sheet.to_vec();
    p0.extend(top);
    tmp.file("t0.obj", obj(&p0, &[&[0, 1, 2], &[3, 4, 5]]));
    // Vertex 3 is cut off: its copy 6 falls through the sheet, the rest stays.
    let mut p1 = p0.clone();
    p1.push([0.2, 0.2, -1.0]);
    tmp.file("t1.obj", obj(&p1, &[&[0, 1, 2], &[6, 4, 5]]));
    tmp.file("cut.parents", "# NEW_ID PARENT_ID\n6 3\n");
    let without = topoccd_in(&tmp.0, &["step", "t0.obj", "t1.obj"]);
    assert_eq!(without.output.status.code(), Some(2));
    assert!(
        without.stderr.contains("--parents FILE"),
        "{}",
        without.stderr
    );
    let run = topoccd_in(
        &tmp.0,
        &[
            "step",
            "--parents",
            "cut.parents",
            "--pairs",
            "-",
            "t0.obj",
            "t1.obj",
        ],
    );
    ok(&run);
    let hit = run
        .stdout
        .lines()
        .find(|l| l.starts_with("vf,6,0,"))
        .unwrap_or_else(|| panic!("no contact of the new vertex: {}", run.stdout));
    let t: f64 = hit
        .rsplit(',')
        .next()
        .and_then(|t| t.parse().ok())
        .expect("toi");
    assert!((t - 0.5).abs() < 1e-3, "{hit}");
    // A bad parents file names itself and the line.
    tmp.file("bad.parents", "6 3\n6 4\n");
    let bad = topoccd_in(
        &tmp.0,
        &["step", "--parents", "bad.parents", "t0.obj", "t1.obj"],
    );
    assert_eq!(bad.output.status.code(), Some(2));
    assert!(bad.stderr.contains("bad.parents:2"), "{}", bad.stderr);
    let both = topoccd_in(
        &tmp.0,
        &[
            "step",
            "--weld",
            "--parents",
            "cut.parents",
            "t0.obj",
            "t1.obj",
        ],
    );
    assert_eq!(both.output.status.code(), Some(2));
}

#[test]
fn quads_are_read_noted_and_their_pairs_name_the_face() {
    let tmp = TempDir::new(SUITE, "quads");
    let quad = |z: f64| {
        obj(
            &[
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.3, 0.6, z],
                [0.4, 0.6, z],
                [0.3, 0.7, z],
            ],
            &[&[0, 1, 2, 3], &[4, 5, 6]],
        )
    };
    tmp.file("t0.obj", quad(1.0));
    tmp.file("t1.obj", quad(-1.0));
    let run = topoccd_in(&tmp.0, &["step", "--pairs", "-", "t0.obj", "t1.obj"]);
    ok(&run);
    assert!(
        run.stderr.contains(
            "note: t1.obj: 1 polygon(s) with more than 3 vertices split into 2 triangles"
        ),
        "{}",
        run.stderr
    );
    // Vertex 4 at (0.3, 0.6) is over the quad's second triangle (0, 2, 3): face 0, sub 1.
    assert!(
        run.stdout
            .lines()
            .any(|l| l.starts_with("vf,4,1,") && l.ends_with(",0,1")),
        "{}",
        run.stdout
    );
}

/// A sequence folder of `frame_NNNN.obj` from 1, the falling triangle of [`seam_frames`].
fn prefixed_sequence(tmp: &TempDir, frames: usize) {
    for k in 0..frames {
        let z = 1.0 - 2.0 * k as f64 / (frames - 1) as f64;
        tmp.file(&format!("seq/frame_{:04}.obj", k + 1), seam_frames(z));
    }
}

#[test]
fn run_prints_each_step_on_stdout_when_stderr_is_not_a_terminal() {
    // Issue 12: "`topoccd run seq > out 2> err` prints only the summary".
    let tmp = TempDir::new(SUITE, "run-lines");
    prefixed_sequence(&tmp, 3);
    let run = topoccd_in(&tmp.0, &["run", "seq"]);
    ok(&run);
    let steps: Vec<&str> = run
        .stdout
        .lines()
        .filter(|l| l.starts_with("step "))
        .collect();
    assert_eq!(steps.len(), 2, "{}", run.stdout);
    assert!(steps[0].starts_with("step 0000: "), "{}", run.stdout);
    assert!(run
        .stdout
        .lines()
        .last()
        .unwrap_or("")
        .starts_with("2 steps"));
    assert!(!run.stderr.contains("step 0000"), "{}", run.stderr);
    // The seam's duplicates are warned about once, for the first frame.
    assert!(
        run.stderr
            .contains("warning: seq/frame_0001.obj: 2 vertices sit exactly"),
        "{}",
        run.stderr
    );
    // With a broken frame in the middle, the earlier steps' lines are already out.
    tmp.file("seq/frame_0004.obj", seam_frames(-2.0));
    tmp.file("seq/frame_0003.obj", "v 0 0 0\nf 1 2 3\n");
    let broken = topoccd_in(&tmp.0, &["run", "seq"]);
    assert_eq!(broken.output.status.code(), Some(2));
    assert!(
        broken.stdout.starts_with("step 0000: "),
        "{}",
        broken.stdout
    );
    assert!(
        broken.stderr.contains("frame_0003.obj"),
        "{}",
        broken.stderr
    );
}

#[test]
fn run_accepts_what_bench_accepts_and_bench_json_has_typed_fields() {
    // Issue 12: "`run` refuses the shared scene folders that `bench` accepts"; "in `bench
    // --json`, `seconds` is a list of `[name, value]` pairs and `contacts` is a float".
    let tmp = TempDir::new(SUITE, "scene");
    for sub in ["boxes", "mma_bool"] {
        std::fs::create_dir_all(tmp.0.join("scene").join(sub)).expect("mkdir");
    }
    tmp.file("scene/frames/cloth_ball92.obj", seam_frames(1.0));
    tmp.file("scene/frames/cloth_ball93.obj", seam_frames(-1.0));
    let run = topoccd_in(&tmp.0, &["run", "scene"]);
    ok(&run);
    assert!(run.stdout.starts_with("step 0000: "), "{}", run.stdout);
    let bench = topoccd_in(
        &tmp.0,
        &["bench", "--json", "--methods", "bvh,brute", "scene"],
    );
    ok(&bench);
    let value = json(&bench.stdout);
    let method = &value["inputs"][0]["methods"][0];
    let seconds = method["seconds"].as_object().expect("seconds is an object");
    for phase in ["build", "traverse", "narrow", "total"] {
        assert!(seconds[phase].is_f64(), "{phase}: {method}");
    }
    for count in ["contacts", "bv_tests", "elementary_tests"] {
        assert!(method[count].is_u64(), "{count}: {method}");
    }
}
