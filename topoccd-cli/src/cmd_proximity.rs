//! `topoccd proximity FRAME --dhat D`: every primitive pair of one frame closer than `dhat`
//! (plus `--dmin`), with its distance and closest-feature type (the library's
//! `Ccd::proximity`). The file's edge elements (PLY `edge`, OBJ `l`) in no triangle are free
//! edges, and vertices in neither are free points. Exit status 0, or 2 on an error.

use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use serde::Serialize;
use topoccd::io::{read_mesh, FilePrimitives};

use crate::common::LooseArgs;
use topoccd::{Ccd, Configuration, ProximityOptions, ProximityReport, StopReason};

/// Arguments of `topoccd proximity`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The mesh file (PLY, OBJ or STL).
    frame: PathBuf,
    #[command(flatten)]
    loose: LooseArgs,
    /// The distance threshold, in the frame's units, > 0.
    #[arg(long)]
    dhat: f64,
    /// The minimum distance offset, >= 0: pairs closer than dhat + dmin are reported.
    #[arg(long, default_value_t = 0.0)]
    dmin: f64,
    /// Write every pair, one line `KIND,INDICES...,DISTANCE,TYPE` (`vf,V,F,...`,
    /// `ee,A0,A1,B0,B1,...`, `ve,V,E0,E1,...`, `vv,A,B,...`; types as the library's and
    /// ipctk's names, e.g. `P_T`, `EA_EB`) to FILE (`-` for stdout; the summary then goes to
    /// stderr).
    #[arg(long, value_name = "FILE|-")]
    pairs: Option<PathBuf>,
    /// Stop once N pairs are found (a number, or `off` for no cap); the output then says it
    /// holds only part of the pairs. Default: one million, as every other command.
    #[arg(long, value_name = "N|off", value_parser = crate::query_args::parse_cap)]
    max_contacts: Option<crate::query_args::Cap>,
    /// Print one JSON object (counts, seconds) instead of text.
    #[arg(long)]
    json: bool,
    /// Stop the query after SECONDS (from when it starts) and exit with an error that says
    /// so. Default: no time limit.
    #[arg(long, value_name = "SECONDS", value_parser = crate::query_args::parse_timeout)]
    timeout: Option<f64>,
}

/// The names of the types, in the order of their codes (ipctk's names).
const PT: [&str; 7] = ["P_T0", "P_T1", "P_T2", "P_E0", "P_E1", "P_E2", "P_T"];
const EE: [&str; 9] = [
    "EA0_EB0", "EA0_EB1", "EA1_EB0", "EA1_EB1", "EA_EB0", "EA_EB1", "EA0_EB", "EA1_EB", "EA_EB",
];
const PE: [&str; 3] = ["P_E0", "P_E1", "P_E"];

/// The JSON output.
#[derive(Serialize)]
struct ProximityOut<'a> {
    frame: &'a Path,
    vertices: usize,
    triangles: usize,
    free_edges: usize,
    free_points: usize,
    /// Whether the query stopped at the cap (`--max-contacts`) with part of the pairs.
    truncated: bool,
    dhat: f64,
    dmin: f64,
    vf: usize,
    ee: usize,
    ve: usize,
    vv: usize,
    /// The library's figures (hierarchy, traversal, distances).
    stats: topoccd::ProximityStats,
    seconds: f64,
}

/// Every pair as lines of text (see [`Args::pairs`]).
fn pair_lines(r: &ProximityReport) -> String {
    let mut s = String::with_capacity(r.len() * 40);
    for p in &r.vf {
        let _ = writeln!(
            s,
            "vf,{},{},{:e},{}",
            p.vertex, p.face, p.distance, PT[p.kind as usize]
        );
    }
    for p in &r.ee {
        let _ = writeln!(
            s,
            "ee,{},{},{},{},{:e},{}",
            p.a[0], p.a[1], p.b[0], p.b[1], p.distance, EE[p.kind as usize]
        );
    }
    for p in &r.ve {
        let _ = writeln!(
            s,
            "ve,{},{},{},{:e},{}",
            p.vertex, p.edge[0], p.edge[1], p.distance, PE[p.kind as usize]
        );
    }
    for p in &r.vv {
        let _ = writeln!(s, "vv,{},{},{:e},P_P", p.a, p.b, p.distance);
    }
    s
}

/// Runs the command.
pub fn run(args: &Args) -> Result<ExitCode> {
    let started = Instant::now();
    let mesh = read_mesh(&args.frame)?;
    for note in &mesh.notes {
        eprintln!("note: {}: {note}", args.frame.display());
    }
    let options = ProximityOptions {
        dhat: args.dhat,
        dmin: args.dmin,
        deadline: crate::query_args::deadline_after(args.timeout),
        max_contacts: match args.max_contacts {
            Some(crate::query_args::Cap::At(n)) => Some(n),
            Some(crate::query_args::Cap::Off) => None,
            None => Some(topoccd::DEFAULT_MAX_CONTACTS),
        },
        ..ProximityOptions::default()
    };
    options.validate()?;
    let loose = mesh.loose_vertices();
    if let Some(w) = crate::common::loose::loose_warning(&args.frame, &loose, args.loose.loose) {
        eprintln!("{w}");
    }
    let config = Configuration::new(&mesh.positions, &mesh.triangles, &mesh.edges)
        .with_context(|| args.frame.display().to_string())?
        .with_free_points(args.loose.loose.are_points());
    let primitives = FilePrimitives::of_configuration(&config);
    let report = Ccd::new().proximity(&config, &options)?;
    match report.truncated {
        Some(StopReason::Deadline) => bail!(
            "{}: stopped at --timeout {} s before every pair was found: raise --timeout",
            args.frame.display(),
            args.timeout.unwrap_or_default()
        ),
        Some(StopReason::MaxContacts) => eprintln!(
            "warning: {}: stopped at --max-contacts {} before every pair was found: the \
             output holds only these pairs (`--max-contacts off` lifts the cap)",
            args.frame.display(),
            report.len()
        ),
        Some(why) => bail!(
            "{}: stopped ({why:?}) before every pair was found ({} found)",
            args.frame.display(),
            report.len()
        ),
        None => {}
    }
    let seconds = started.elapsed().as_secs_f64();
    if let Some(target) = &args.pairs {
        let text = pair_lines(&report);
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
    let line = if args.json {
        serde_json::to_string(&ProximityOut {
            frame: &args.frame,
            vertices: mesh.positions.len(),
            triangles: mesh.triangles.len(),
            free_edges: primitives.free_edges.len(),
            free_points: primitives.free_points.len(),
            truncated: report.truncated.is_some(),
            dhat: args.dhat,
            dmin: args.dmin,
            vf: report.vf.len(),
            ee: report.ee.len(),
            ve: report.ve.len(),
            vv: report.vv.len(),
            stats: report.stats,
            seconds,
        })?
    } else {
        format!(
            "{}: {} pairs closer than {}: {} vertex-face, {} edge-edge, {} point-edge, {} \
             point-point ({seconds:.3} s)",
            args.frame.display(),
            report.len(),
            args.dhat + args.dmin,
            report.vf.len(),
            report.ee.len(),
            report.ve.len(),
            report.vv.len()
        )
    };
    if to_stdout {
        println!("{line}");
    } else {
        eprintln!("{line}");
    }
    Ok(ExitCode::SUCCESS)
}
