//! The `topoccd` command-line tool. Results go to stdout, errors and progress to stderr.

mod cmd_gen;
mod cmd_queries;
mod cmd_step;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Continuous collision detection for deforming, topology-changing triangle meshes.
#[derive(Parser, Debug)]
#[command(name = "topoccd", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run the elementary tests on every query file below a folder and compare with its ground
    /// truth (files `*/vertex-face/*.csv` and `*/edge-edge/*.csv`, as in Sample-Queries).
    Queries(cmd_queries::Args),
    /// Continuous collision detection over one step between two mesh files (the faces are
    /// T1's): every vertex-face and edge-edge contact with its time of impact.
    Step(cmd_step::Args),
    /// Generate a frame sequence of one of the paper's scenes (nidus, nidus-cut, airbag, lion,
    /// bunny-dragon, crash) into a new or empty folder.
    Gen(cmd_gen::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Queries(args) => cmd_queries::run(&args),
        Command::Step(args) => cmd_step::run(&args).map(|()| ExitCode::SUCCESS),
        Command::Gen(args) => cmd_gen::run(&args).map(|()| ExitCode::SUCCESS),
    };
    match result {
        Ok(code) => code,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::from(2)
        }
    }
}
