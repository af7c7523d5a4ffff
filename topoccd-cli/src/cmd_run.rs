//! `topoccd run SEQ_DIR`: every step of a frame sequence, with a progress bar.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use indicatif::ProgressBar;
use serde::Serialize;
use topoccd::check::step_intersections;
use topoccd::io::read_mesh;
use topoccd::io::sequence::Sequence;
use topoccd::{Ccd, Frame, Step};

use crate::common::*;
use crate::query_args::{MethodArgs, QueryArgs};
use crate::record::Recorder;

/// Arguments of `topoccd run`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Folder of frames named a common prefix and a consecutive number from any start
    /// (`0000.ply`, `0001.ply`, ... or `frame_1.obj`, `frame_2.obj`, ...), with optional
    /// parents files beside them (`0001.parents`); or a scene folder with `frames/`.
    seq_dir: PathBuf,
    #[command(flatten)]
    loose: LooseArgs,
    #[command(flatten)]
    method: MethodArgs,
    #[command(flatten)]
    query: QueryArgs,
    /// With --json, include each step's contacts (in --earliest mode the earliest pairs are
    /// always included).
    #[arg(long)]
    with_pairs: bool,
    /// Print JSON Lines: one JSON object per line, one per step (the keys of `topoccd step
    /// --json` plus `step`), then a summary object `{"summary": ...}`.
    #[arg(long)]
    json: bool,
    /// Write each step's colliding pairs to DIR/NNNN.csv (NNNN: the step's first frame), in the
    /// format of `topoccd step --pairs`.
    #[arg(long, value_name = "DIR")]
    pairs_dir: Option<PathBuf>,
    #[command(flatten)]
    record: RecordArgs,
    /// Skip the static check of each step's start (a warning on stderr when a frame starts
    /// intersecting: see `topoccd check`).
    #[arg(long)]
    no_check: bool,
}

/// One step's JSON line.
#[derive(Serialize)]
struct StepLine<'a> {
    step: usize,
    #[serde(flatten)]
    out: &'a StepOut<'a>,
}

/// The summary at the end of a run.
#[derive(Serialize, Debug, Default)]
struct Summary {
    steps: usize,
    steps_with_contacts: usize,
    vf: usize,
    ee: usize,
    ve: usize,
    vv: usize,
    earliest_toi: Option<f64>,
    query_seconds: f64,
    wall_seconds: f64,
}

/// Prints the reader's notes on the first frame, and a warning if vertices of it coincide.
fn warn_first_frame(sequence: &Sequence) -> Result<()> {
    let first = &sequence.frames[0];
    let mesh = read_mesh(first)?;
    for note in &mesh.notes {
        eprintln!("note: {}: {note}", first.display());
    }
    let remedy = "Merge them in the frames (`topoccd step --weld` does it for one step)";
    for w in input_warning_lines(first, &mesh.positions, &mesh.triangles, remedy) {
        eprintln!("{w}");
    }
    Ok(())
}

/// Watches the frames of a run for intersecting triangles: a warning on stderr when a frame
/// intersects and the one before it did not (so a sequence that stays intersecting warns once).
#[derive(Default)]
struct IntersectionWatch {
    intersecting: bool,
}

impl IntersectionWatch {
    /// Checks one end of `step`; `frame` names its file.
    fn check(&mut self, step: &Step<'_>, end: Frame, frame: &Path, bar: &ProgressBar) {
        let pairs = step_intersections(step, end);
        if !pairs.is_empty() && !self.intersecting {
            let shown: Vec<String> = pairs
                .iter()
                .take(3)
                .map(|[a, b]| format!("{a} and {b}"))
                .collect();
            bar.suspend(|| {
                eprintln!(
                    "warning: {}: {} pairs of triangles intersect (triangles {}{}); a step's \
                     contacts are those that begin during it, so triangles that already pass \
                     through each other may go unreported. `topoccd check {}` lists them \
                     (`--no-check` skips this check).",
                    frame.display(),
                    pairs.len(),
                    shown.join(", "),
                    if pairs.len() > shown.len() {
                        ", ..."
                    } else {
                        ""
                    },
                    frame.display()
                )
            });
        }
        self.intersecting = !pairs.is_empty();
    }
}

/// Runs the command.
pub fn run(args: &Args) -> Result<()> {
    let mut options = args.query.options()?;
    let sequence = Sequence::open(&args.seq_dir)?.with_loose_vertices(args.loose.loose);
    if let Some(w) = left_out_warning(&sequence) {
        eprintln!("{w}");
    }
    let inputs: Vec<&Path> = sequence.frames.iter().map(PathBuf::as_path).collect();
    let name = format!("topoccd run {}", args.seq_dir.display());
    let mut recorder = Recorder::open(&args.record, &name, &inputs)?;
    // The recording shows each contact's point and normal.
    options.geometry |= recorder.is_some();
    if let Some(dir) = &args.pairs_dir {
        prepare_dir(dir)?;
    }
    warn_first_frame(&sequence)?;
    let started = Instant::now();
    let bar = progress(sequence.steps(), "steps");
    // Keep the elapsed time moving during a long step.
    bar.enable_steady_tick(Duration::from_millis(250));
    let mut ccd = Ccd::new();
    let mut summary = Summary::default();
    let mut watch = IntersectionWatch::default();
    let mut last = None;
    for item in sequence.iter() {
        let (k, step) = item?;
        if !args.no_check {
            watch.check(&step, Frame::Start, &sequence.frames[k], &bar);
        }
        let method = args.method.method.into();
        options.deadline = args.query.deadline();
        let report = ccd.query(&step, method, &options)?;
        args.query.check_deadline(&report).with_context(|| {
            let name = |i: usize| sequence.frames[i].display().to_string();
            format!("step {k} ({} -> {})", name(k), name(k + 1))
        })?;
        if let Some(dir) = &args.pairs_dir {
            let inputs: Vec<&Path> = sequence.frames.iter().map(PathBuf::as_path).collect();
            write_pairs(&dir.join(format!("{k:04}.csv")), &report, &inputs, None)?;
        }
        let out = StepOut::new(&step, method, options.mode, &report, args.with_pairs);
        if let Some(recorder) = &mut recorder {
            recorder.step(k, &step, &report, &ccd, method, &out.text())?;
        }
        summary.steps += 1;
        summary.vf += report.vf.len();
        summary.ee += report.ee.len();
        summary.ve += report.ve.len();
        summary.vv += report.vv.len();
        summary.steps_with_contacts += usize::from(report.contact_count() > 0);
        summary.query_seconds += report.stats.seconds.total;
        if let Some(t) = report.earliest_toi() {
            summary.earliest_toi = Some(summary.earliest_toi.map_or(t, |e: f64| e.min(t)));
        }
        bar.inc(1);
        if args.json {
            bar.suspend(|| -> Result<()> {
                println!(
                    "{}",
                    serde_json::to_string(&StepLine { step: k, out: &out })?
                );
                Ok(())
            })?;
        } else {
            // Results go to stdout whether or not stderr (the progress bar) is a terminal.
            bar.suspend(|| println!("step {k:04}: {}", out.text()));
        }
        last = Some((k, step));
    }
    if let (false, Some((k, step))) = (args.no_check, &last) {
        watch.check(step, Frame::End, &sequence.frames[k + 1], &bar);
    }
    if let Some(recorder) = recorder {
        recorder.finish()?;
    }
    bar.finish_and_clear();
    summary.wall_seconds = started.elapsed().as_secs_f64();
    if args.json {
        println!(
            "{}",
            serde_json::to_string(&serde_json::json!({ "summary": summary }))?
        );
    } else {
        println!(
            "{} steps ({} with contacts): {} vf and {} ee contacts{}, earliest toi {}; query {:.3} s, wall {:.3} s",
            summary.steps,
            summary.steps_with_contacts,
            summary.vf,
            summary.ee,
            if summary.ve + summary.vv > 0 {
                format!(", {} ve and {} vv", summary.ve, summary.vv)
            } else {
                String::new()
            },
            summary.earliest_toi.map_or("none".into(), |t| t.to_string()),
            summary.query_seconds,
            summary.wall_seconds
        );
    }
    Ok(())
}
