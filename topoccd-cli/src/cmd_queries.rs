//! `topoccd queries DIR [--json]`: the elementary tests against exact ground truth.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use serde::Serialize;
use topoccd::io::queries::{find_query_files, read_query_file, QueryKind};
use topoccd::narrow::{edge_edge, vertex_face, EdgeEdge, NarrowOptions, Outcome, VertexFace};
use topoccd::Certainty;

/// Arguments of `topoccd queries`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Folder searched recursively for `vertex-face/*.csv` and `edge-edge/*.csv` files.
    dir: PathBuf,
    /// One JSON object per kind per line instead of a table.
    #[arg(long)]
    json: bool,
    /// Search tolerance, in time units (see `NarrowOptions::tolerance`).
    #[arg(long, default_value_t = NarrowOptions::default().tolerance)]
    tolerance: f64,
    /// Also write every query's outcome to FILE, one line
    /// `KIND,FILE,LINE,TOUCHING,HIT,TOI,CERTAINTY` (TOI empty without a hit, in the shortest
    /// form that reads back to the same f64; CERTAINTY resolved, iteration_limit or
    /// invalid_input), for comparisons with other implementations.
    #[arg(long, value_name = "FILE")]
    outcomes: Option<PathBuf>,
}

/// Counts for one kind of query.
#[derive(Serialize, Debug)]
struct Summary {
    kind: &'static str,
    queries: usize,
    positives: usize,
    false_negatives: usize,
    false_positives: usize,
    seconds: f64,
}

/// Runs the command; exit status 1 if any touching query was missed.
pub fn run(args: &Args) -> Result<ExitCode> {
    if !(args.tolerance > 0.0 && args.tolerance < 1.0) {
        bail!("--tolerance must be in (0, 1), got {}", args.tolerance);
    }
    let options = NarrowOptions {
        tolerance: args.tolerance,
        ..NarrowOptions::default()
    };
    let files = find_query_files(&args.dir)?;
    if files.is_empty() {
        bail!(
            "{}: no query files (*/vertex-face/*.csv or */edge-edge/*.csv) below this folder",
            args.dir.display()
        );
    }
    // Read everything first, so a malformed file stops the run before any result is printed.
    let mut loaded = Vec::with_capacity(files.len());
    for (kind, path) in &files {
        loaded.push((*kind, read_query_file(path)?));
    }
    let mut any_false_negative = false;
    let mut outcomes = String::new();
    for kind in [QueryKind::VertexFace, QueryKind::EdgeEdge] {
        let mut s = Summary {
            kind: kind.short_name(),
            queries: 0,
            positives: 0,
            false_negatives: 0,
            false_positives: 0,
            seconds: 0.0,
        };
        let start = Instant::now();
        for ((_, path), (_, records)) in files.iter().zip(&loaded).filter(|(_, (k, _))| *k == kind)
        {
            for q in records {
                let outcome = match kind {
                    QueryKind::VertexFace => {
                        vertex_face(&VertexFace::from_points(q.points), &options)
                    }
                    QueryKind::EdgeEdge => edge_edge(&EdgeEdge::from_points(q.points), &options),
                };
                let hit = outcome.is_contact();
                if args.outcomes.is_some() {
                    let (toi, certainty) = match outcome {
                        Outcome::Separated => (String::new(), "resolved"),
                        Outcome::Contact { toi, certainty } => (
                            format!("{toi:?}"),
                            match certainty {
                                Certainty::Resolved => "resolved",
                                Certainty::IterationLimit => "iteration_limit",
                                Certainty::InvalidInput => "invalid_input",
                            },
                        ),
                    };
                    outcomes.push_str(&format!(
                        "{},{},{},{},{hit},{toi},{certainty}\n",
                        kind.short_name(),
                        path.display(),
                        q.line,
                        q.touching
                    ));
                }
                s.queries += 1;
                s.positives += usize::from(hit);
                s.false_negatives += usize::from(q.touching && !hit);
                s.false_positives += usize::from(!q.touching && hit);
            }
        }
        s.seconds = start.elapsed().as_secs_f64();
        any_false_negative |= s.false_negatives > 0;
        if args.json {
            println!("{}", serde_json::to_string(&s)?);
        } else {
            println!(
                "{:<3} queries {:>6}  positives {:>6}  false negatives {:>4}  false positives {:>5}  seconds {:.4}",
                s.kind, s.queries, s.positives, s.false_negatives, s.false_positives, s.seconds
            );
        }
    }
    if let Some(file) = &args.outcomes {
        std::fs::write(file, outcomes)
            .with_context(|| format!("{}: cannot write", file.display()))?;
    }
    Ok(if any_false_negative {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}
