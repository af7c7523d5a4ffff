//! Issue 51, item 7: the commands with their caps lifted, in a subprocess under a 1 GiB
//! address-space limit (`ulimit -v`), on collapsed input (the integer-cast cloth-funnel step):
//! each exits with an error that names the allocation, never an abort. (`check`, which has no
//! cap, has the same fallible pair lists, but exhausting 1 GiB takes 10^8 exact tests of
//! collapsed triangles, over ten minutes: not run here.)

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::TempDir;
use topoccd::io::read_mesh;

/// Frames 227 and 228 of cloth-funnel with their coordinates cast to `i32`, as OBJ files.
fn integer_cast_funnel(dir: &TempDir) -> Option<[PathBuf; 2]> {
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
        let mesh = read_mesh(&frames.join(format!("{n}.ply"))).expect("the frame reads");
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

/// Runs `topoccd ARGS` under a 1 GiB address-space limit; asserts that it failed with an
/// error naming the allocation. Returns its stderr.
fn fails_out_of_memory(args: &[&Path]) -> String {
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
    assert!(
        stderr.contains("out of memory: could not allocate") && stderr.contains("bytes for the"),
        "{stderr}"
    );
    stderr
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
