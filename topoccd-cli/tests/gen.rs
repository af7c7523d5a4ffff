//! `topoccd gen`: writes a readable sequence into a new folder, the same bytes for the same
//! seed, and refuses a folder that is not empty.

use std::path::{Path, PathBuf};
use std::process::Command;

use topoccd::io::sequence::Sequence;

/// A fresh path under the system temp dir (not created), removed on drop.
struct TempPath(PathBuf);

impl TempPath {
    fn new(tag: &str) -> Self {
        let path = std::env::temp_dir().join(format!("topoccd-gen-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        TempPath(path)
    }
}

impl Drop for TempPath {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn gen(scene: &str, dir: &Path, extra: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_topoccd"))
        .args(["gen", scene])
        .arg(dir)
        .args(["--scale", "0.02", "--frames", "4"])
        .args(extra)
        .output()
        .expect("run topoccd")
}

/// The files of a folder, sorted, with their bytes.
fn contents(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .expect("list")
        .map(|e| {
            let path = e.expect("entry").path();
            let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
            (
                name.unwrap_or_default(),
                std::fs::read(&path).expect("read"),
            )
        })
        .collect();
    files.sort();
    files
}

#[test]
fn gen_writes_a_sequence_that_reads_back() {
    let dir = TempPath::new("nidus-cut");
    let out = gen("nidus-cut", &dir.0, &["--seed", "4"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.starts_with("nidus-cut: 4 frames"), "{stdout}");
    let sequence = Sequence::open(&dir.0).expect("opens");
    assert_eq!(sequence.steps(), 3);
    for step in sequence.iter() {
        step.expect("every step reads back");
    }
    let files = contents(&dir.0);
    assert!(files.iter().any(|(name, _)| name.ends_with(".parents")));

    // The JSON summary has the contacts of every step.
    let json_dir = TempPath::new("json");
    let out = gen("airbag", &json_dir.0, &["--json"]);
    assert!(out.status.success());
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(summary["scene"], "Airbag");
    assert_eq!(summary["contacts"].as_array().map(Vec::len), Some(3));

    // Same seed, same bytes.
    let again = TempPath::new("nidus-cut-again");
    let out = gen("nidus-cut", &again.0, &["--seed", "4"]);
    assert!(out.status.success());
    assert_eq!(contents(&again.0), files);
}

#[test]
fn gen_refuses_a_folder_that_is_not_empty() {
    let dir = TempPath::new("full");
    std::fs::create_dir_all(&dir.0).expect("mkdir");
    std::fs::write(dir.0.join("keep.txt"), "mine").expect("write");
    let out = gen("airbag", &dir.0, &[]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("not empty"));
    assert_eq!(
        contents(&dir.0),
        vec![("keep.txt".into(), b"mine".to_vec())]
    );

    // An empty existing folder is fine.
    let empty = TempPath::new("empty");
    std::fs::create_dir_all(&empty.0).expect("mkdir");
    let out = gen("airbag", &empty.0, &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(Sequence::open(&empty.0).is_ok());
}

#[test]
fn gen_rejects_bad_arguments() {
    let dir = TempPath::new("bad");
    for args in [
        vec!["gen", "teapot"],
        vec!["gen", "lion", "--scale", "0"],
        vec!["gen", "lion", "--frames", "1"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_topoccd"))
            .args(&args[..2])
            .arg(&dir.0)
            .args(&args[2..])
            .output()
            .expect("run topoccd");
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(!dir.0.exists(), "{args:?} created the folder");
    }
}
