//! `--rerun`: a recording of a generated sequence with a cut, read back with Rerun's own reader
//! (`rerun rrd verify`, and rerun-sdk's `RrdReader` through `tests/rrd_dump.py`), checked
//! against the command's own JSON report and the sequence's parents files.
//!
//! With the feature `rerun` these tests need rerun-sdk 0.36.3: its `rerun` command on the PATH
//! (or `TOPOCCD_RERUN_BIN`), with the Python that has the package beside it (a venv's `bin/`)
//! or in `TOPOCCD_RERUN_PYTHON`. Without them they fail under CI (`CI` set) and skip, saying
//! so, elsewhere. Without the feature, `--rerun` says how to get it.

mod common;

use std::path::PathBuf;

use common::{run, TempDir};

/// `topoccd gen SCENE DIR/seq --scale SCALE --frames FRAMES`, checked; the sequence's folder.
fn generate(dir: &TempDir, scene: &str, scale: &str, frames: &str) -> PathBuf {
    let seq = dir.0.join("seq");
    let args = [
        "gen",
        scene,
        seq.to_str().unwrap(),
        "--scale",
        scale,
        "--frames",
        frames,
    ];
    let g = run(None, &args, &[]);
    assert!(g.output.status.success(), "{}", g.stderr);
    seq
}

#[cfg(not(feature = "rerun"))]
#[test]
fn without_the_feature_rerun_says_how_to_get_it() {
    let dir = TempDir::new("rerun", "nofeature");
    let seq = generate(&dir, "nidus", "0.02", "2");
    let out = dir.0.join("out.rrd");
    let r = run(
        None,
        &[
            "run",
            seq.to_str().unwrap(),
            "--rerun",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert_eq!(r.output.status.code(), Some(2), "{}", r.stderr);
    assert!(r.stderr.contains("--features rerun"), "{}", r.stderr);
    assert!(!out.exists());
}

#[cfg(feature = "rerun")]
mod with_feature {
    use std::collections::BTreeMap;
    use std::path::{Path, PathBuf};
    use std::process::Command;

    use serde_json::Value;

    use super::{generate, run, TempDir};

    /// The rerun-sdk tools: the `rerun` command and a Python that imports `rerun`.
    struct Tools {
        rerun: PathBuf,
        python: PathBuf,
        /// A config home of our own, where the analytics are disabled.
        home: TempDir,
    }

    fn on_path(name: &str) -> Option<PathBuf> {
        let paths = std::env::var_os("PATH")?;
        std::env::split_paths(&paths)
            .map(|d| d.join(name))
            .find(|p| p.is_file())
    }

    impl Tools {
        fn find(name: &str) -> Option<Self> {
            let rerun = std::env::var_os("TOPOCCD_RERUN_BIN")
                .map(PathBuf::from)
                .or_else(|| on_path("rerun"));
            let Some(rerun) = rerun else {
                let why = "rerun-sdk's `rerun` is not on the PATH (pip install rerun-sdk==0.36.3)";
                assert!(std::env::var_os("CI").is_none(), "{why}");
                eprintln!("SKIPPED: {why}");
                return None;
            };
            let python = std::env::var_os("TOPOCCD_RERUN_PYTHON")
                .map(PathBuf::from)
                .unwrap_or_else(|| rerun.with_file_name("python"));
            let home = TempDir::new("rerun-home", name);
            let tools = Tools {
                rerun,
                python,
                home,
            };
            // Rerun's usage analytics off, in a config home of our own, before anything else.
            let out = tools
                .command(&tools.rerun)
                .args(["analytics", "disable"])
                .output();
            let out = out.expect("run rerun analytics disable");
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            Some(tools)
        }

        fn command(&self, program: &Path) -> Command {
            let mut c = Command::new(program);
            c.env("HOME", &self.home.0)
                .env("XDG_CONFIG_HOME", self.home.0.join("config"))
                .env("XDG_DATA_HOME", self.home.0.join("data"));
            c
        }

        /// `rerun rrd verify`, then the recording's entities, step by step.
        fn read(&self, rrd: &Path) -> Value {
            let verify = self
                .command(&self.rerun)
                .args(["rrd", "verify"])
                .arg(rrd)
                .output()
                .expect("run rerun rrd verify");
            assert!(
                verify.status.success(),
                "rerun rrd verify {}: {}",
                rrd.display(),
                String::from_utf8_lossy(&verify.stderr)
            );
            let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/rrd_dump.py");
            let out = self
                .command(&self.python)
                .arg(script)
                .arg(rrd)
                .output()
                .expect("run rrd_dump.py");
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            serde_json::from_slice(&out.stdout).expect("rrd_dump.py prints JSON")
        }
    }

    /// `entities[path][step]["count"]`, 0 where absent.
    fn count(rec: &Value, path: &str, step: usize) -> u64 {
        rec["entities"][path][step.to_string()]["count"]
            .as_u64()
            .unwrap_or(0)
    }

    fn steps_of(rec: &Value, path: &str) -> Vec<usize> {
        let mut steps: Vec<usize> = rec["entities"][path]
            .as_object()
            .unwrap_or_else(|| panic!("no entity {path} in {rec}"))
            .keys()
            .map(|k| k.parse().expect("a step number"))
            .collect();
        steps.sort_unstable();
        steps
    }

    /// A small generated sequence with a cut: its folder, and the parents rows of each step.
    fn cut_sequence(dir: &TempDir) -> (PathBuf, Vec<usize>) {
        let seq = generate(dir, "nidus-cut", "0.05", "4");
        // Step k goes from frame k to frame k+1, whose parents file lists the new vertices.
        let parents = (1..4)
            .map(|f| {
                std::fs::read_to_string(seq.join(format!("{f:04}.parents")))
                    .map(|s| {
                        s.lines()
                            .filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
                            .count()
                    })
                    .unwrap_or(0)
            })
            .collect();
        (seq, parents)
    }

    /// `topoccd run --json` lines of the steps.
    fn steps_json(stdout: &str) -> Vec<Value> {
        stdout
            .lines()
            .map(|l| serde_json::from_str::<Value>(l).expect("a JSON line"))
            .filter(|v| v.get("step").is_some())
            .collect()
    }

    const ENTITIES: [&str; 16] = [
        "/topoccd/mesh",
        "/topoccd/contacts/faces",
        "/topoccd/contacts/vertices",
        "/topoccd/contacts/edges",
        "/topoccd/contacts/points",
        "/topoccd/contacts/normals",
        "/topoccd/earliest",
        "/topoccd/cracks/edges",
        "/topoccd/cracks/vertices",
        "/topoccd/stats/seconds/total",
        "/topoccd/stats/candidates/vf",
        "/topoccd/stats/candidates/ee",
        "/topoccd/stats/bv_tests",
        "/topoccd/stats/contacts",
        "/topoccd/stats/triangles",
        "/topoccd/notes",
    ];

    #[test]
    fn run_records_every_step_as_its_report_says() {
        let Some(tools) = Tools::find("run") else {
            return;
        };
        let dir = TempDir::new("rerun", "run");
        let (seq, parents) = cut_sequence(&dir);
        assert!(parents.iter().any(|&n| n > 0), "the sequence has no cut");
        let rrd = dir.0.join("run.rrd");
        let r = run(
            None,
            &[
                "run",
                seq.to_str().unwrap(),
                "--json",
                "--rerun",
                rrd.to_str().unwrap(),
            ],
            &[],
        );
        assert!(r.output.status.success(), "{}", r.stderr);
        let steps = steps_json(&r.stdout);
        assert_eq!(steps.len(), 3);
        let rec = tools.read(&rrd);
        assert_eq!(rec["recordings"], 1);
        assert_eq!(rec["application_id"], "topoccd");
        let mut paths: Vec<&str> = rec["entities"]
            .as_object()
            .unwrap()
            .keys()
            .map(String::as_str)
            .collect();
        paths.sort_unstable();
        for e in ENTITIES {
            assert!(paths.contains(&e), "{e} missing from {paths:?}");
            assert_eq!(steps_of(&rec, e), [0, 1, 2], "{e}");
        }
        assert!(!paths.iter().any(|p| p.starts_with("/topoccd/volumes")));
        let mut contacts_total = 0;
        for (k, s) in steps.iter().enumerate() {
            assert_eq!(s["step"], k);
            let contacts = s["vf"].as_u64().unwrap() + s["ee"].as_u64().unwrap();
            contacts_total += contacts;
            assert_eq!(
                count(&rec, "/topoccd/mesh", k),
                s["triangles"].as_u64().unwrap()
            );
            assert_eq!(
                count(&rec, "/topoccd/contacts/points", k),
                contacts,
                "step {k}"
            );
            assert_eq!(count(&rec, "/topoccd/contacts/normals", k), contacts);
            assert_eq!(
                count(&rec, "/topoccd/contacts/faces", k),
                s["vf"].as_u64().unwrap()
            );
            assert_eq!(
                count(&rec, "/topoccd/contacts/edges", k),
                2 * s["ee"].as_u64().unwrap()
            );
            let value = &rec["entities"]["/topoccd/stats/contacts"][k.to_string()]["values"][0];
            assert_eq!(value.as_f64(), Some(contacts as f64));
            assert_eq!(
                count(&rec, "/topoccd/earliest", k),
                u64::from(contacts > 0),
                "step {k}"
            );
            assert_eq!(
                count(&rec, "/topoccd/cracks/vertices", k),
                parents[k] as u64
            );
            assert_eq!(
                count(&rec, "/topoccd/cracks/edges", k) > 0,
                parents[k] > 0,
                "step {k}"
            );
        }
        assert!(contacts_total > 0, "the sequence has no contact to record");
        // No cap applied: the notes hold one line per step, none a warning.
        let notes = &rec["entities"]["/topoccd/notes"];
        for k in 0..3 {
            assert_eq!(notes[k.to_string()]["count"], 1);
        }
    }

    #[test]
    fn a_mesh_that_keeps_its_triangles_is_counted_at_every_step() {
        // nidus has no cut: after step 0 only the positions are logged, the viewer (and the
        // reader) keep the triangles.
        let Some(tools) = Tools::find("nocut") else {
            return;
        };
        let dir = TempDir::new("rerun", "nocut");
        let seq = generate(&dir, "nidus", "0.02", "4");
        let rrd = dir.0.join("nocut.rrd");
        let r = run(
            None,
            &[
                "run",
                seq.to_str().unwrap(),
                "--json",
                "--rerun",
                rrd.to_str().unwrap(),
            ],
            &[],
        );
        assert!(r.output.status.success(), "{}", r.stderr);
        let steps = steps_json(&r.stdout);
        let rec = tools.read(&rrd);
        assert_eq!(steps_of(&rec, "/topoccd/mesh"), [0, 1, 2]);
        for (k, s) in steps.iter().enumerate() {
            assert_eq!(
                count(&rec, "/topoccd/mesh", k),
                s["triangles"].as_u64().unwrap()
            );
            assert_eq!(count(&rec, "/topoccd/cracks/vertices", k), 0);
        }
    }

    #[test]
    fn volumes_step_and_demo_record_too() {
        let Some(tools) = Tools::find("more") else {
            return;
        };
        let dir = TempDir::new("rerun", "more");
        let (seq, _) = cut_sequence(&dir);
        let rrd = dir.0.join("volumes.rrd");
        let r = run(
            None,
            &[
                "run",
                seq.to_str().unwrap(),
                "--method",
                "cluster",
                "--rerun",
                rrd.to_str().unwrap(),
                "--rerun-volumes",
            ],
            &[],
        );
        assert!(r.output.status.success(), "{}", r.stderr);
        let rec = tools.read(&rrd);
        for k in 0..3 {
            assert!(count(&rec, "/topoccd/volumes/leaves", k) > 0);
            assert!(count(&rec, "/topoccd/volumes/intermediate", k) > 0);
            assert!(count(&rec, "/topoccd/stats/seconds/clustering", k) == 1);
        }
        // `step` records its one step at 0, with the parents' fresh crack.
        let (t0, t1) = (seq.join("0000.ply"), seq.join("0001.ply"));
        let parents = seq.join("0001.parents");
        let rrd = dir.0.join("step.rrd");
        let mut args = vec![
            "step".to_string(),
            t0.display().to_string(),
            t1.display().to_string(),
            "--json".into(),
            "--rerun".into(),
            rrd.display().to_string(),
        ];
        if parents.exists() {
            args.extend(["--parents".into(), parents.display().to_string()]);
        }
        let r = run(None, &args, &[]);
        assert!(r.output.status.success(), "{}", r.stderr);
        let s: Value = serde_json::from_str(&r.stdout).unwrap();
        let rec = tools.read(&rrd);
        assert_eq!(steps_of(&rec, "/topoccd/mesh"), [0]);
        assert_eq!(
            count(&rec, "/topoccd/mesh", 0),
            s["triangles"].as_u64().unwrap()
        );
        let contacts = s["vf"].as_u64().unwrap() + s["ee"].as_u64().unwrap();
        assert_eq!(count(&rec, "/topoccd/contacts/points", 0), contacts);
        // `demo` records the default method's steps.
        let rrd = dir.0.join("demo.rrd");
        let r = run(
            None,
            &[
                "demo",
                "--scene",
                "nidus-cut",
                "--scale",
                "0.02",
                "--frames",
                "3",
                "--rerun",
                rrd.to_str().unwrap(),
            ],
            &[],
        );
        assert!(r.output.status.success(), "{}", r.stderr);
        let rec = tools.read(&rrd);
        assert_eq!(steps_of(&rec, "/topoccd/mesh"), [0, 1]);
        assert!(count(&rec, "/topoccd/mesh", 0) > 0);
    }

    #[test]
    fn the_cap_says_so_in_the_recording() {
        let Some(tools) = Tools::find("cap") else {
            return;
        };
        let dir = TempDir::new("rerun", "cap");
        let (seq, _) = cut_sequence(&dir);
        let rrd = dir.0.join("cap.rrd");
        let r = run(
            None,
            &[
                "run",
                seq.to_str().unwrap(),
                "--json",
                "--rerun",
                rrd.to_str().unwrap(),
                "--rerun-max-primitives",
                "3",
            ],
            &[],
        );
        assert!(r.output.status.success(), "{}", r.stderr);
        assert!(
            r.stderr.contains("warning: --rerun: step 0"),
            "{}",
            r.stderr
        );
        let steps = steps_json(&r.stdout);
        let rec = tools.read(&rrd);
        let notes: BTreeMap<String, Value> =
            serde_json::from_value(rec["entities"]["/topoccd/notes"].clone()).unwrap();
        for (k, s) in steps.iter().enumerate() {
            // The mesh is over the cap: not recorded, and the notes say so.
            assert_eq!(count(&rec, "/topoccd/mesh", k), 0);
            let lines = notes[&k.to_string()]["values"].to_string();
            assert!(lines.contains("over the cap of 3 primitives"), "{lines}");
            let contacts = s["vf"].as_u64().unwrap() + s["ee"].as_u64().unwrap();
            assert_eq!(count(&rec, "/topoccd/contacts/points", k), contacts.min(3));
            // The figures still hold the report's count.
            let value = &rec["entities"]["/topoccd/stats/contacts"][k.to_string()]["values"][0];
            assert_eq!(value.as_f64(), Some(contacts as f64));
        }
    }

    #[test]
    fn bad_paths_and_a_missing_viewer_are_clear_errors() {
        let dir = TempDir::new("rerun", "bad");
        let seq = generate(&dir, "nidus", "0.02", "2");
        let s = seq.to_str().unwrap();
        let cases: [(&[&str], &str); 4] = [
            (
                &["run", s, "--rerun", "/no/such/folder/out.rrd"],
                "does not exist",
            ),
            (&["run", s, "--rerun", "out.png"], "ending in .rrd"),
            (&["run", s, "--rerun", s], "ending in .rrd"),
            (&["run", s, "--rerun-volumes"], "needs --rerun"),
        ];
        for (args, message) in cases {
            let r = run(None, args, &[]);
            assert_eq!(r.output.status.code(), Some(2), "{args:?}: {}", r.stderr);
            assert!(r.stderr.contains(message), "{args:?}: {}", r.stderr);
        }
        // No viewer: an empty PATH.
        let empty = dir.0.join("empty");
        std::fs::create_dir_all(&empty).unwrap();
        for command in [vec!["run", s, "--rerun"], vec!["demo", "--rerun"]] {
            let r = run(None, &command, &[("PATH", empty.to_str().unwrap())]);
            assert_eq!(r.output.status.code(), Some(2), "{}", r.stderr);
            assert!(
                r.stderr.contains("pip install rerun-sdk==0.36.3"),
                "{}",
                r.stderr
            );
        }
    }
}
