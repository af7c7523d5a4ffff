//! Issue 51, item 7: the commands with their caps lifted, in a subprocess under a 1 GiB
//! address-space limit (`ulimit -v`), on collapsed input (the integer-cast cloth-funnel step):
//! each exits with an error that names the allocation, never an abort. (`check`, which has no
//! cap, has the same fallible pair lists, but exhausting 1 GiB takes 10^8 exact tests of
//! collapsed triangles, over ten minutes: not run here.)

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{integer_cast_funnel, TempDir};

/// Runs `topoccd ARGS` under a 1 GiB address-space limit; asserts that it failed with an
/// error naming the allocation. Returns its stderr.
fn fails_out_of_memory(args: &[&Path]) -> String {
    let stderr = fails_under_limit(args);
    assert!(
        stderr.contains("out of memory: could not allocate") && stderr.contains("bytes for the"),
        "{stderr}"
    );
    stderr
}

/// Runs `topoccd ARGS` under a 1 GiB address-space limit; asserts that it exited with an
/// error (an exit code, not a signal) and did not panic. Returns its stderr.
fn fails_under_limit(args: &[&Path]) -> String {
    let mut command = Command::new("sh");
    command
        .arg("-c")
        .arg("ulimit -v 1048576 && exec \"$@\"")
        .arg("sh")
        .arg(env!("CARGO_BIN_EXE_topoccd"))
        .args(args)
        .env_remove("TOPOCCD_MAX_MEMORY")
        .env("MALLOC_ARENA_MAX", "2");
    let out = command.output().expect("sh runs");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    // An exit code, not a signal (an abort is SIGABRT).
    assert!(
        out.status.code().is_some_and(|c| c != 0),
        "{:?}\n{stderr}",
        out.status
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

/// Issue 51: a file as large as its header says (sparse: it takes no disk space) whose
/// vertices do not fit in memory. Every command that reads it exits with an error naming the
/// file and what it was reading.
#[test]
fn a_file_larger_than_memory_is_an_error_not_an_abort() {
    let dir = TempDir::new("memory-limit", "file");
    let vertices = 200_000_000u64;
    let header = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {vertices}\nproperty float x\n\
         property float y\nproperty float z\nelement face 0\n\
         property list uchar int vertex_indices\nend_header\n"
    );
    let path = dir.file("huge.ply", &header);
    let file = std::fs::OpenOptions::new()
        .write(true)
        .open(&path)
        .expect("opens");
    file.set_len(header.len() as u64 + 12 * vertices)
        .expect("a sparse file");
    drop(file);
    let p = |s: &str| PathBuf::from(s);
    let commands = [
        vec![p("check"), path.clone()],
        vec![p("proximity"), path.clone(), p("--dhat"), p("1e-3")],
        vec![
            p("step"),
            path.clone(),
            path.clone(),
            p("--max-memory"),
            p("off"),
        ],
    ];
    for args in commands {
        let refs: Vec<&Path> = args.iter().map(PathBuf::as_path).collect();
        let stderr = fails_under_limit(&refs);
        let expected = format!(
            "{}: out of memory reading the vertex positions",
            path.display()
        );
        assert!(stderr.contains(&expected), "{args:?}: {stderr}");
        println!("{:?}: {stderr}", args[0]);
    }
}

#[test]
fn uncapped_commands_fail_cleanly_under_an_address_space_limit() {
    let dir = TempDir::new("memory-limit", "commands");
    let Some([f0, f1]) = integer_cast_funnel(&dir) else {
        return;
    };
    let p = |s: &str| PathBuf::from(s);
    let off = [p("--max-contacts"), p("off")];
    let mut args = vec![p("proximity"), f0.clone(), p("--dhat"), p("1e-3")];
    args.extend(off.clone());
    let refs: Vec<&Path> = args.iter().map(PathBuf::as_path).collect();
    println!("proximity: {}", fails_out_of_memory(&refs));
    for mode in [None, Some("--earliest")] {
        let mut args = vec![
            p("step"),
            f0.clone(),
            f1.clone(),
            p("--max-memory"),
            p("off"),
        ];
        args.extend(off.clone());
        args.extend(mode.map(p));
        let refs: Vec<&Path> = args.iter().map(PathBuf::as_path).collect();
        println!("step {mode:?}: {}", fails_out_of_memory(&refs));
    }
}
