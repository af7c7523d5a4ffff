//! The `topoccd` command-line tool.
use clap::Parser;

/// Continuous collision detection for topology-changing triangle meshes.
#[derive(Parser, Debug)]
#[command(name = "topoccd", version, about)]
enum Cli {}

fn main() {
    let _ = Cli::parse();
}
