//! The `topoccd` command-line tool. Results go to stdout, errors and progress to stderr.

mod cmd_bench;
mod cmd_check;
mod cmd_demo;
mod cmd_gen;
mod cmd_queries;
mod cmd_render;
mod cmd_run;
mod cmd_step;
mod common;
mod plot;
mod query_args;
mod record;
mod render;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Continuous collision detection for deforming, topology-changing triangle meshes.
#[derive(Parser, Debug)]
#[command(name = "topoccd", version, about)]
struct Cli {
    /// Threads for the elementary tests (default: one per core), 1 to 4096 (as the Python
    /// package's `threads=`). Results are identical for any count; use 1 for single-core
    /// timings.
    #[arg(long, global = true, value_name = "N", value_parser = parse_threads)]
    threads: Option<usize>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// The main job on a built-in scene: generate a small topology-changing scene in memory,
    /// run every step with each method, print the paper's tables.
    Demo(cmd_demo::Args),
    /// Run the elementary tests on every query file below a folder and compare with its ground
    /// truth (files `*/vertex-face/*.csv` and `*/edge-edge/*.csv`, as in Sample-Queries).
    Queries(cmd_queries::Args),
    /// Continuous collision detection over one step between two mesh files (the faces are
    /// T1's): every vertex-face and edge-edge contact with its time of impact.
    Step(cmd_step::Args),
    /// Every step of a frame sequence (a folder of `0000.ply`, `0001.ply`, ...), with a progress
    /// bar, one line (or JSON object) per step and a summary.
    Run(cmd_run::Args),
    /// The paper's tables 1 and 2: each method on every step of each input, alternating the
    /// methods per step, with the speedup of `cluster` over `bvh`.
    Bench(cmd_bench::Args),
    /// Draw a mesh or a step as a PNG: leaf clusters coloured and intermediate clusters
    /// outlined, contacts in red, or connected components (orthographic, no display needed).
    Render(cmd_render::Args),
    /// Generate a frame sequence of one of the paper's scenes (nidus, nidus-cut, airbag, lion,
    /// bunny-dragon, crash) into a new or empty folder.
    Gen(cmd_gen::Args),
    /// The pairs of triangles of one frame that intersect or touch (sharing no vertex),
    /// decided exactly; exit status 1 when there are any. A CCD step assumes none at its start.
    Check(cmd_check::Args),
}

/// The most threads `--threads` takes (the Python package's `threads=` has the same range).
const MAX_THREADS: usize = 4096;

fn parse_threads(s: &str) -> Result<usize, String> {
    let n: usize = s.parse().map_err(|_| format!("{s:?} is not a number"))?;
    if (1..=MAX_THREADS).contains(&n) {
        Ok(n)
    } else {
        Err(format!("threads must be in [1, {MAX_THREADS}], got {n}"))
    }
}

fn main() -> ExitCode {
    // Rust ignores SIGPIPE, so a write to a closed pipe would panic in `println!`; restore the
    // default, so that `topoccd run --json | head` ends quietly like any Unix tool.
    #[cfg(unix)]
    // SAFETY: setting a signal's disposition to the default at start-up, before any thread.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    if let Some(n) = cli.threads {
        if let Err(err) = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
        {
            eprintln!("error: cannot set up {n} threads: {err}");
            return ExitCode::from(2);
        }
    }
    let result = match cli.command {
        Command::Demo(args) => cmd_demo::run(&args).map(|()| ExitCode::SUCCESS),
        Command::Queries(args) => cmd_queries::run(&args),
        Command::Step(args) => cmd_step::run(&args).map(|()| ExitCode::SUCCESS),
        Command::Run(args) => cmd_run::run(&args).map(|()| ExitCode::SUCCESS),
        Command::Bench(args) => cmd_bench::run(&args),
        Command::Render(args) => cmd_render::run(&args),
        Command::Gen(args) => cmd_gen::run(&args).map(|()| ExitCode::SUCCESS),
        Command::Check(args) => cmd_check::run(&args),
    };
    match result {
        Ok(code) => code,
        Err(err) => {
            eprintln!("error: {err:#}");
            // With --json, stdout stays valid JSON (lines) whatever happens: the error is one
            // more object.
            if std::env::args().any(|a| a == "--json") {
                println!("{}", serde_json::json!({ "error": format!("{err:#}") }));
            }
            ExitCode::from(2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn threads_take_the_python_range() {
        assert_eq!(parse_threads("1"), Ok(1));
        assert_eq!(parse_threads("4096"), Ok(4096));
        assert_eq!(
            parse_threads("0"),
            Err("threads must be in [1, 4096], got 0".to_string())
        );
        assert!(parse_threads("4097").is_err());
        assert!(parse_threads("-1").is_err());
        assert!(parse_threads("two").is_err());
    }
}
