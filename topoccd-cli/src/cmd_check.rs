//! `topoccd check FRAME`: the pairs of triangles of one frame that intersect (the static check
//! of `topoccd::check`). Exit status 0 when none do, 1 when some do, 2 on an error.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use serde::Serialize;
use topoccd::check::{frame_intersections_within, CheckLimits};
use topoccd::io::{read_mesh, FilePrimitives};

use crate::common::LooseArgs;
use topoccd::io::sequence::parents_path;

/// Arguments of `topoccd check`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The mesh file (PLY, OBJ or STL).
    frame: PathBuf,
    #[command(flatten)]
    loose: LooseArgs,
    /// Vertices that count as one, one line `NEW_ID PARENT_ID` each (a sequence's
    /// `NNNN.parents`): the two sides of a crack touch by construction and are not reported.
    /// Default: the file beside FRAME with the extension `.parents`, when there is one.
    #[arg(long, value_name = "FILE")]
    parents: Option<PathBuf>,
    /// Write every intersecting pair, one line `A,B` (triangle indices, A < B), to FILE (`-`
    /// for stdout; the summary then goes to stderr).
    #[arg(long, value_name = "FILE|-")]
    pairs: Option<PathBuf>,
    /// Print one JSON object (with every pair) instead of text.
    #[arg(long)]
    json: bool,
    /// Pairs listed in the text output (all of them are in --pairs and --json).
    #[arg(long, default_value_t = 10, value_name = "N")]
    limit: usize,
    /// Stop the check after SECONDS (from when it starts) and exit with an error that says
    /// so. Default: no time limit.
    #[arg(long, value_name = "SECONDS", value_parser = crate::query_args::parse_timeout)]
    timeout: Option<f64>,
}

/// The JSON output.
#[derive(Serialize)]
struct CheckOut<'a> {
    frame: &'a Path,
    vertices: usize,
    triangles: usize,
    /// Free edges (in no triangle) and free points of the file, as `step`, `run` and
    /// `proximity` read them (the check itself is over the triangles).
    free_edges: usize,
    free_points: usize,
    parents: Option<&'a Path>,
    intersecting: usize,
    pairs: &'a [[u32; 2]],
    seconds: f64,
}

/// Reads `NEW_ID PARENT_ID` lines (`#` starts a comment) naming vertices below `vertices`.
/// Errors name the file and line; [`frame_intersections`](topoccd::check::frame_intersections) checks the rest as
/// [`Step::with_parents`](topoccd::Step::with_parents) does (a child that is not new, a
/// vertex its own parent, a child given twice).
pub fn read_joins(path: &Path, vertices: usize) -> Result<Vec<[u32; 2]>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    let mut rows = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let ids: Vec<&str> = line.split_whitespace().collect();
        let where_ = format!("{}:{}", path.display(), i + 1);
        let [a, b] = ids[..] else {
            bail!("{where_}: expected two vertex ids `NEW_ID PARENT_ID`, found {line:?}");
        };
        let id = |s: &str| -> Result<u32> {
            match s.parse::<u32>() {
                Ok(v) if (v as usize) < vertices => Ok(v),
                Ok(v) => bail!(
                    "{where_}: vertex {v} is out of range (the frame has {vertices} vertices)"
                ),
                Err(_) => bail!("{where_}: {s:?} is not a vertex id"),
            }
        };
        rows.push([id(a)?, id(b)?]);
    }
    Ok(rows)
}

/// Runs the command.
pub fn run(args: &Args) -> Result<ExitCode> {
    let started = Instant::now();
    let mesh = read_mesh(&args.frame)?;
    for note in &mesh.notes {
        eprintln!("note: {}: {note}", args.frame.display());
    }
    let loose = mesh.loose_vertices();
    if let Some(w) = crate::common::loose::loose_warning(&args.frame, &loose, args.loose.loose) {
        eprintln!("{w}");
    }
    let primitives = FilePrimitives::of_mesh(&mesh, args.loose.loose);
    let beside = parents_path(&args.frame);
    let parents_file = match &args.parents {
        Some(p) => Some(p.clone()),
        None if beside.is_file() => {
            eprintln!(
                "note: {}: vertices and their parents count as one vertex (--parents FILE to choose another file)",
                beside.display()
            );
            Some(beside)
        }
        None => None,
    };
    let joins = match &parents_file {
        Some(p) => read_joins(p, mesh.positions.len())?,
        None => Vec::new(),
    };
    let x = &mesh.positions;
    // No cap, as before; a deadline with --timeout.
    let limits = CheckLimits {
        max_contacts: None,
        deadline: crate::query_args::deadline_after(args.timeout),
        cancel: None,
    };
    let pairs =
        frame_intersections_within(x, &mesh.triangles, &joins, &limits).with_context(|| {
            match &parents_file {
                Some(p) => format!("{} with {}", args.frame.display(), p.display()),
                None => args.frame.display().to_string(),
            }
        })?;
    let seconds = started.elapsed().as_secs_f64();
    if let Some(target) = &args.pairs {
        let mut text = String::with_capacity(pairs.len() * 12);
        for [a, b] in &pairs {
            text.push_str(&format!("{a},{b}\n"));
        }
        if target.as_os_str() == "-" {
            std::io::stdout().write_all(text.as_bytes())?;
        } else {
            if target == &args.frame {
                bail!("--pairs {} would overwrite the input", target.display());
            }
            std::fs::write(target, text)
                .with_context(|| format!("{}: cannot write", target.display()))?;
        }
    }
    let to_stdout = args.pairs.as_deref().is_none_or(|p| p.as_os_str() != "-");
    if args.json {
        let out = CheckOut {
            frame: &args.frame,
            vertices: x.len(),
            triangles: mesh.triangles.len(),
            free_edges: primitives.free_edges.len(),
            free_points: primitives.free_points.len(),
            parents: parents_file.as_deref(),
            intersecting: pairs.len(),
            pairs: &pairs,
            seconds,
        };
        let line = serde_json::to_string(&out)?;
        if to_stdout {
            println!("{line}");
        } else {
            eprintln!("{line}");
        }
    } else {
        let mut text = format!(
            "{}: {} triangles, {} intersecting pairs of triangles sharing no vertex ({seconds:.3} s)",
            args.frame.display(),
            mesh.triangles.len(),
            pairs.len()
        );
        for [a, b] in pairs.iter().take(args.limit) {
            text.push_str(&format!("\n  triangles {a} and {b}"));
        }
        if pairs.len() > args.limit {
            text.push_str(&format!(
                "\n  ... and {} more (--pairs FILE lists them all)",
                pairs.len() - args.limit
            ));
        }
        if to_stdout {
            println!("{text}");
        } else {
            eprintln!("{text}");
        }
    }
    Ok(if pairs.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
