//! `topoccd bench INPUT...`: the paper's tables 1 and 2, every method on every step of every
//! input in one process, alternating the order of the methods from step to step.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Result;
use topoccd::{Ccd, Method};

use crate::common::*;
use crate::query_args::{MethodArg, QueryArgs};

/// Arguments of `topoccd bench`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Frame sequences (folders of `0000.ply`, `0001.ply`, ...) or scene folders holding
    /// `frames/` with two numbered frames (like `../shared/data/scenes/cloth-ball`).
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// Methods to compare, comma-separated.
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [MethodArg::Bvh, MethodArg::Cluster])]
    methods: Vec<MethodArg>,
    #[command(flatten)]
    query: QueryArgs,
    /// Print the tables as one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Draw the time of each step for each method as a PNG.
    #[arg(long, value_name = "FILE.png")]
    plot: Option<PathBuf>,
}

/// Runs the command. Exit status 1 if the methods disagree on any step.
pub fn run(args: &Args) -> Result<std::process::ExitCode> {
    let options = args.query.options()?;
    if let Some(plot) = &args.plot {
        let inputs: Vec<&Path> = args.inputs.iter().map(PathBuf::as_path).collect();
        refuse_overwrite(plot, &inputs)?;
        writable(plot)?;
    }
    let started = Instant::now();
    let mut ccds = vec![Ccd::new(); args.methods.len()];
    let mut all = Vec::new();
    let mut series = Vec::new();
    for input in &args.inputs {
        let source = Source::open(input)?;
        let name = input.display().to_string();
        let (tables, totals) = bench_source(&name, &source, &args.methods, &options, &mut ccds)?;
        if !args.json {
            print_text(&tables);
        }
        series.push(crate::plot::PlotInput {
            name: tables.input.clone(),
            per_step: totals,
            phases: tables
                .methods
                .iter()
                .map(|m| {
                    m.seconds
                        .iter()
                        .copied()
                        .filter(|s| s.0 != "total")
                        .collect()
                })
                .collect(),
        });
        all.push(tables);
    }
    if args.json {
        println!(
            "{}",
            serde_json::to_string(&serde_json::json!({
                "inputs": all,
                "wall_seconds": started.elapsed().as_secs_f64(),
            }))?
        );
    }
    if let Some(plot) = &args.plot {
        let names: Vec<String> = args
            .methods
            .iter()
            .map(|m| Method::from(*m).to_string())
            .collect();
        crate::plot::step_times(plot, &names, &series)?;
    }
    Ok(if all.iter().all(|t| t.agree) {
        std::process::ExitCode::SUCCESS
    } else {
        std::process::ExitCode::from(1)
    })
}
