//! What the tests of the built `topoccd` binary share: a temporary folder, a run of the
//! binary that asserts it did not panic, and the integer-cast cloth-funnel frames. Each test
//! file is a crate of its own and uses a part.
#![allow(dead_code)]

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh folder under the system's temporary folder, removed when dropped.
pub struct TempDir(pub PathBuf);

impl TempDir {
    /// The folder `topoccd-{suite}-{name}-{process id}`, emptied.
    pub fn new(suite: &str, name: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("topoccd-{suite}-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create the temporary folder");
        Self(dir)
    }

    /// Writes `bytes` to a file of the folder (making its parent folders) and returns its path.
    pub fn file(&self, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
        let path = self.0.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).expect("mkdir");
        }
        std::fs::write(&path, bytes).expect("write a test input");
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// What a run of the binary printed.
pub struct Run {
    pub output: Output,
    pub stdout: String,
    pub stderr: String,
}

/// Runs the binary with `args`, in `cwd` (else this process's folder), with `env` set and
/// without `TOPOCCD_MAX_MEMORY`, stdout and stderr piped (neither is a terminal); asserts
/// that it did not panic.
pub fn run<S: AsRef<OsStr>>(cwd: Option<&Path>, args: &[S], env: &[(&str, &str)]) -> Run {
    let mut command = Command::new(env!("CARGO_BIN_EXE_topoccd"));
    command.args(args).env_remove("TOPOCCD_MAX_MEMORY");
    if let Some(cwd) = cwd {
        command.current_dir(cwd);
    }
    for (key, value) in env {
        command.env(key, value);
    }
    let output = command.output().expect("run topoccd");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "a panic: {stderr}");
    Run {
        output,
        stdout,
        stderr,
    }
}

/// Frames 227 and 228 of cloth-funnel with their coordinates cast to `i32`, as OBJ files.
pub fn integer_cast_funnel(dir: &TempDir) -> Option<[PathBuf; 2]> {
    let frames = std::env::var_os("TOPOCCD_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data"))
        .join("scenes/cloth-funnel/frames");
    if !frames.is_dir() {
        assert!(
            std::env::var_os("TOPOCCD_REQUIRE_DATA").is_none(),
            "TOPOCCD_REQUIRE_DATA is set but the shared data is absent: {}",
            frames.display()
        );
        eprintln!("SKIPPED, NOT TESTED: no {}", frames.display());
        return None;
    }
    let cast = |n: u32| {
        let mesh =
            topoccd::io::read_mesh(&frames.join(format!("{n}.ply"))).expect("the frame reads");
        let mut obj = String::new();
        for p in &mesh.positions {
            let [x, y, z] = p.map(|c| c as i32);
            obj += &format!("v {x} {y} {z}\n");
        }
        for t in &mesh.triangles {
            obj += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        dir.file(&format!("{n}.obj"), obj)
    };
    Some([cast(227), cast(228)])
}
