//! One reading of every file: `gen S DIR` then `run DIR` gives the contacts `gen` reports, for
//! every scene and with 1 and 2 threads; `step`, `run`, `proximity` and `check` see the same
//! free edges and free points in one frame; `--scale` changes every scene's size.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

struct TempPath(PathBuf);

impl TempPath {
    fn new(tag: &str) -> Self {
        let path = std::env::temp_dir().join(format!("topoccd-loose-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        TempPath(path)
    }
}

impl Drop for TempPath {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn cli(args: &[&str]) -> (String, String, bool) {
    let out = Command::new(env!("CARGO_BIN_EXE_topoccd"))
        .args(args)
        .output()
        .expect("run topoccd");
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        out.status.success(),
    )
}

/// Every scene `gen` knows, from its own error message on an unknown one.
fn scenes() -> Vec<String> {
    let (_, err, ok) = cli(&["gen", "no-such-scene", "/nonexistent-topoccd-dir"]);
    assert!(!ok);
    let list = err
        .split("the scenes are ")
        .nth(1)
        .unwrap_or_else(|| panic!("no scene list in {err}"));
    let names: Vec<String> = list
        .lines()
        .next()
        .unwrap_or("")
        .split(", ")
        .map(|s| s.trim().trim_end_matches(['.', '"', '\'']).to_string())
        .collect();
    assert!(names.iter().any(|n| n == "funnel-particles"), "{names:?}");
    names
}

fn path(p: &Path) -> &str {
    p.to_str().expect("utf-8 temp path")
}

/// `gen` a small sequence: its JSON summary.
fn gen(scene: &str, dir: &Path, scale: &str) -> Value {
    let (out, err, ok) = cli(&[
        "gen",
        scene,
        path(dir),
        "--scale",
        scale,
        "--frames",
        "4",
        "--seed",
        "1",
        "--json",
    ]);
    assert!(ok, "gen {scene}: {err}");
    serde_json::from_str(out.trim()).expect("gen JSON")
}

/// The contacts of each step that `gen` reports, as `[vf, ee, ve, vv]` totals (vf + ee for
/// the paper's scenes, which report one count per step).
fn gen_contacts(summary: &Value) -> Vec<usize> {
    summary["contacts"]
        .as_array()
        .expect("contacts")
        .iter()
        .map(|c| match c {
            Value::Array(kinds) => kinds.iter().map(|k| k.as_u64().unwrap() as usize).sum(),
            n => n.as_u64().unwrap() as usize,
        })
        .collect()
}

/// The contacts of each step per kind, `[vf, ee, ve, vv]`, for the scenes that report kinds.
fn gen_kinds(summary: &Value) -> Option<Vec<Vec<u64>>> {
    (summary["contacts"].as_array()?.iter())
        .map(|c| Some(c.as_array()?.iter().map(|k| k.as_u64().unwrap()).collect()))
        .collect()
}

/// `run --json` per step: its JSON lines (without the summary).
fn run_lines(dir: &Path, threads: &str, extra: &[&str]) -> Vec<Value> {
    let mut args = vec![
        "--threads",
        threads,
        "run",
        path(dir),
        "--json",
        "--no-check",
    ];
    args.extend_from_slice(extra);
    let (out, err, ok) = cli(&args);
    assert!(ok, "run {}: {err}", dir.display());
    out.lines()
        .map(|l| serde_json::from_str::<Value>(l).expect("run JSON"))
        .filter(|v| v.get("summary").is_none())
        .collect()
}

fn total(line: &Value) -> usize {
    ["vf", "ee", "ve", "vv"]
        .iter()
        .map(|k| line[k].as_u64().unwrap_or(0) as usize)
        .sum()
}

#[test]
fn run_on_gen_frames_finds_the_contacts_gen_reports() {
    for scene in scenes() {
        let dir = TempPath::new(&scene);
        let summary = gen(&scene, &dir.0, "0.05");
        let expected = gen_contacts(&summary);
        for threads in ["1", "2"] {
            // gen counts every contact, crack contacts included.
            let lines = run_lines(&dir.0, threads, &["--keep-crack-contacts"]);
            let found: Vec<usize> = lines.iter().map(total).collect();
            assert_eq!(found, expected, "{scene}, {threads} thread(s)");
            if let Some(kinds) = gen_kinds(&summary) {
                let found: Vec<Vec<u64>> = (lines.iter())
                    .map(|l| {
                        ["vf", "ee", "ve", "vv"]
                            .map(|k| l[k].as_u64().unwrap())
                            .to_vec()
                    })
                    .collect();
                assert_eq!(found, kinds, "{scene}, {threads} thread(s), per kind");
            }
        }
    }
}

#[test]
fn scale_changes_every_scene() {
    for scene in scenes() {
        let small = TempPath::new(&format!("{scene}-s"));
        let large = TempPath::new(&format!("{scene}-l"));
        gen(&scene, &small.0, "0.2");
        gen(&scene, &large.0, "0.5");
        let size = |d: &Path| std::fs::metadata(d.join("0000.ply")).expect("frame").len();
        assert!(
            size(&small.0) < size(&large.0),
            "{scene}: --scale 0.2 and 0.5 give {} and {} bytes",
            size(&small.0),
            size(&large.0)
        );
    }
}

/// The free edges and free points of a frame, counted here from the file's own lists.
fn counted(frame: &Path, loose_points: bool) -> (usize, usize) {
    let mesh = topoccd::io::read_mesh(frame).expect("read");
    let mut sides = std::collections::BTreeSet::new();
    let mut used = vec![false; mesh.positions.len()];
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            sides.insert((a.min(b), a.max(b)));
            used[t[k] as usize] = true;
        }
    }
    let mut free = std::collections::BTreeSet::new();
    for &[a, b] in &mesh.edges {
        used[a as usize] = true;
        used[b as usize] = true;
        if !sides.contains(&(a.min(b), a.max(b))) {
            free.insert((a.min(b), a.max(b)));
        }
    }
    let points = if loose_points {
        used.iter().filter(|u| !**u).count()
    } else {
        0
    };
    (free.len(), points)
}

fn primitives(v: &Value) -> (usize, usize) {
    let n = |k: &str| v[k].as_u64().unwrap_or_else(|| panic!("no {k} in {v}")) as usize;
    (n("free_edges"), n("free_points"))
}

#[test]
fn every_command_reads_the_same_primitives() {
    for scene in ["funnel-particles", "hair", "rod-rain"] {
        let dir = TempPath::new(&format!("{scene}-p"));
        gen(scene, &dir.0, "0.2");
        let (f0, f1) = (dir.0.join("0000.ply"), dir.0.join("0001.ply"));
        for (loose, points) in [("points", true), ("ignore", false)] {
            let expected = counted(&f1, points);
            let flag = ["--loose-vertices", loose];
            let mut step = vec!["step", path(&f0), path(&f1), "--json"];
            step.extend_from_slice(&flag);
            let (out, err, ok) = cli(&step);
            assert!(ok, "{err}");
            let step: Value = serde_json::from_str(out.trim()).expect("step JSON");
            let run = &run_lines(&dir.0, "1", &flag)[0];
            let mut prox = vec!["proximity", path(&f1), "--dhat", "1e-3", "--json"];
            prox.extend_from_slice(&flag);
            let (out, err, ok) = cli(&prox);
            assert!(ok, "{err}");
            let prox: Value = serde_json::from_str(out.trim()).expect("proximity JSON");
            let mut check = vec!["check", path(&f1), "--json"];
            check.extend_from_slice(&flag);
            let (out, err, _) = cli(&check);
            let check: Value = serde_json::from_str(out.trim()).expect("check JSON");
            if expected.1 > 0 {
                assert!(err.contains("vertices in no face and no edge"), "{err}");
            }
            for (name, got) in [
                ("step", &step),
                ("run", run),
                ("proximity", &prox),
                ("check", &check),
            ] {
                assert_eq!(
                    primitives(got),
                    expected,
                    "{scene} --loose-vertices {loose}: {name}"
                );
            }
        }
    }
}
