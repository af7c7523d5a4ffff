//! `topoccd check FRAME`: on the first frames of the generated scenes (clean: a CCD scene
//! starts without contact) and their later frames (the generators' response lets surfaces
//! cross a little), the same pairs as the library; exit status 0 or 1; errors naming the file
//! and line; and the warning of `topoccd run` when a frame starts intersecting.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use topoccd::check::step_intersections;
use topoccd::io::sequence::Sequence;
use topoccd::Frame;

/// A fresh folder under the system temp dir, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        let path = std::env::temp_dir().join(format!("topoccd-check-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).expect("create temp dir");
        TempDir(path)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn topoccd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_topoccd"))
        .args(args)
        .output()
        .expect("run topoccd")
}

fn gen(scene: &str, dir: &Path, frames: &str) {
    let out = topoccd(&[
        "gen",
        scene,
        dir.to_str().expect("utf-8 path"),
        "--scale",
        "0.05",
        "--frames",
        frames,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The CLI's pairs of a frame (`--pairs -`), and its exit status.
fn cli_pairs(frame: &Path) -> (Vec<[u32; 2]>, Option<i32>) {
    let out = topoccd(&["check", frame.to_str().expect("utf-8"), "--pairs", "-"]);
    let pairs = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| {
            let (a, b) = l.split_once(',').expect("a,b");
            [a.parse().expect("id"), b.parse().expect("id")]
        })
        .collect();
    (pairs, out.status.code())
}

#[test]
fn generated_scenes_start_clean_and_later_frames_match_the_library() {
    let root = TempDir::new("scenes");
    let mut later = 0;
    for scene in [
        "nidus",
        "nidus-cut",
        "airbag",
        "lion",
        "bunny-dragon",
        "crash",
    ] {
        let dir = root.0.join(scene);
        gen(scene, &dir, "3");
        let first = dir.join("0000.ply");
        let (pairs, code) = cli_pairs(&first);
        assert_eq!(
            (pairs.len(), code),
            (0, Some(0)),
            "{scene}: the first frame intersects"
        );
        // Each later frame as the library sees it: the end of its step, with that step's
        // parents (the file beside the frame, which the CLI reads by default).
        let sequence = Sequence::open(&dir).expect("a sequence");
        for item in sequence.iter() {
            let (k, step) = item.expect("a step");
            let want = step_intersections(&step, Frame::End);
            let (got, code) = cli_pairs(&sequence.frames[k + 1]);
            assert_eq!(got, want, "{scene}, frame {}", k + 1);
            assert_eq!(code, Some(i32::from(!want.is_empty())));
            later += want.len();
        }
    }
    assert!(
        later > 0,
        "no later frame intersects: the comparison checked little"
    );
}

#[test]
fn json_text_and_errors() {
    let dir = TempDir::new("io");
    let mesh = dir.0.join("pierced.obj");
    std::fs::write(
        &mesh,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0.2 0.2 -1\nv 0.3 0.2 1\nv 0.2 0.3 1\nf 1 2 3\nf 4 5 6\n",
    )
    .expect("write");
    let path = mesh.to_str().expect("utf-8");
    let out = topoccd(&["check", path, "--json"]);
    assert_eq!(out.status.code(), Some(1));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(json["intersecting"], 1);
    assert_eq!(json["pairs"], serde_json::json!([[0, 1]]));
    let out = topoccd(&["check", path]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("1 intersecting pairs") && text.contains("triangles 0 and 1"),
        "{text}"
    );

    // Joined vertices: a parents file that makes the two triangles neighbours.
    let parents = dir.0.join("joins.parents");
    std::fs::write(&parents, "# NEW_ID PARENT_ID\n3 0\n").expect("write");
    let out = topoccd(&["check", path, "--parents", parents.to_str().expect("utf-8")]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    // A bad parents line names the file and line; --pairs never overwrites the input.
    std::fs::write(&parents, "3 0\n3 99\n").expect("write");
    let out = topoccd(&["check", path, "--parents", parents.to_str().expect("utf-8")]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        err.contains("joins.parents:2: vertex 99 is out of range"),
        "{err}"
    );
    let out = topoccd(&["check", path, "--pairs", path]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("would overwrite"));
    let missing = dir.0.join("missing.ply");
    let out = topoccd(&["check", missing.to_str().expect("utf-8")]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing.ply"));
}

#[test]
fn run_warns_when_a_frame_starts_intersecting() {
    let dir = TempDir::new("run");
    let seq = dir.0.join("nidus");
    gen("nidus", &seq, "3");
    let seq_text = seq.to_str().expect("utf-8");
    let sequence = Sequence::open(&seq).expect("a sequence");
    let step = sequence.iter().next().expect("a step").expect("readable").1;
    let at_frame_1 = step_intersections(&step, Frame::End);
    assert!(
        !at_frame_1.is_empty(),
        "the generated frame 1 should intersect"
    );

    let out = topoccd(&["run", seq_text]);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("warning:")).collect();
    // Frame 0 is clean, frame 1 starts intersecting (one warning), frame 2 stays so (none).
    assert_eq!(warnings.len(), 1, "{err}");
    let expected = format!(
        "0001.ply: {} pairs of triangles intersect",
        at_frame_1.len()
    );
    assert!(warnings[0].contains(&expected), "{err}");
    let out = topoccd(&["run", seq_text, "--no-check"]);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("warning:"));
}
