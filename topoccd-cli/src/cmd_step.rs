//! `topoccd step T0 T1`: the CCD query of one step between two mesh files.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use topoccd::Ccd;

use crate::common::*;
use crate::query_args::{MethodArgs, QueryArgs};
use crate::record::Recorder;

/// Arguments of `topoccd step`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Positions at t=0 (.ply, .obj or .stl).
    t0: PathBuf,
    #[command(flatten)]
    loose: LooseArgs,
    /// Positions at t=1 and the step's triangles (.ply, .obj or .stl), same vertex count as T0
    /// (or more, with --parents).
    t1: PathBuf,
    #[command(flatten)]
    method: MethodArgs,
    #[command(flatten)]
    query: QueryArgs,
    /// Write one line per colliding pair to FILE (`-`: stdout, and the summary line goes to
    /// stderr): `vf,VERTEX,FACE,TOI` or `ee,A0,A1,B0,B1,TOI`. When T1 had polygons split into
    /// triangles, vf lines end with two more fields, `,FILE_FACE,SUB`: the face of T1's file
    /// and the triangle's rank within it.
    #[arg(long, value_name = "FILE")]
    pairs: Option<PathBuf>,
    /// A topology change: vertices of T1 beyond T0's count are new, and FILE gives their
    /// parents, one line `NEW_ID PARENT_ID` each (the format of a sequence's `NNNN.parents`). A
    /// new vertex starts the step at its parent's position; without a parent it does not move.
    #[arg(long, value_name = "FILE")]
    parents: Option<PathBuf>,
    /// Merge vertices whose positions are identical at t=0 and at t=1 (UV seams, poles of a UV
    /// sphere): such duplicates touch from the start and give spurious contacts at t=0.
    /// Triangles that become degenerate are dropped. Ids in the output stay those of the input
    /// files (a merged vertex is named by the lowest id of its group).
    #[arg(long)]
    weld: bool,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// With --json, include every contact (in --earliest mode the earliest pairs are always
    /// included).
    #[arg(long)]
    with_pairs: bool,
    /// Refuse a step whose estimated memory exceeds SIZE: bytes, or a number with K, M, G or
    /// T (powers of 1024), or `off` to skip the check. Default: $TOPOCCD_MAX_MEMORY, else the
    /// memory available (MemAvailable of /proc/meminfo; no check where that is unknown).
    #[arg(long, value_name = "SIZE", value_parser = parse_memory_limit)]
    max_memory: Option<MemoryLimit>,
    #[command(flatten)]
    record: RecordArgs,
}

/// Runs the command.
pub fn run(args: &Args) -> Result<()> {
    let limit = match args.max_memory {
        Some(limit) => limit,
        None => MemoryLimit::from_env()?,
    };
    let mut options = args.query.options_within(limit)?;
    let to_stdout = args.pairs.as_deref() == Some(Path::new("-"));
    if to_stdout && args.json {
        bail!("--pairs - and --json would both write to stdout; use --json --with-pairs to have the pairs in the JSON");
    }
    if let Some(p) = &args.pairs {
        if !to_stdout {
            refuse_overwrite(p, &[&args.t0, &args.t1])?;
            writable(p)?;
        }
    }
    let name = format!("topoccd step {} {}", args.t0.display(), args.t1.display());
    let recorder = Recorder::open(&args.record, &name, &[&args.t0, &args.t1])?;
    // The recording shows each contact's point and normal.
    options.geometry |= recorder.is_some();
    let input = read_step_input(
        &args.t0,
        &args.t1,
        limit,
        args.parents.as_deref(),
        args.weld,
        args.loose.loose,
    )?;
    for message in &input.messages {
        eprintln!("{message}");
    }
    let mut ccd = Ccd::new();
    let method = args.method.method.into();
    options.deadline = args.query.deadline();
    let mut report = with_spinner("querying the step", || {
        ccd.query(&input.step, method, &options)
    })?;
    args.query.check_deadline(&report)?;
    if let Some(mut recorder) = recorder {
        // In the step's ids (welded ones included), before the renaming to the files' ids.
        let summary = StepOut::new(&input.step, method, options.mode, &report, false).text();
        recorder.step(0, &input.step, &report, &ccd, method, &summary)?;
        recorder.finish()?;
    }
    rename(
        &mut report,
        input.vertex_ids.as_deref(),
        input.triangle_ids.as_deref(),
    );
    let face_origin = input.face_origin.as_deref();
    if let Some(p) = &args.pairs {
        write_pairs(p, &report, &[&args.t0, &args.t1], face_origin)?;
    }
    let out = StepOut::new(&input.step, method, options.mode, &report, args.with_pairs);
    if args.json {
        println!("{}", serde_json::to_string(&out)?);
    } else if to_stdout {
        eprintln!("{}", out.text());
    } else {
        println!("{}", out.text());
    }
    Ok(())
}
