//! `topoccd step T0 T1`: the CCD query of one step between two mesh files.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use serde::Serialize;
use topoccd::io::{
    available_memory, read_mesh, read_ply_header, MemoryEstimate, MeshFormat, PlyCounts,
};
use topoccd::{Ccd, Contact, EeContact, Method, Mode, Report, Seconds, Stats, Step, VfContact};

use crate::query_args::{MethodArgs, QueryArgs};

/// Arguments of `topoccd step`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Positions at t=0 (.ply or .obj).
    t0: PathBuf,
    /// Positions at t=1 and the step's triangles (.ply or .obj), same vertex count as T0.
    t1: PathBuf,
    #[command(flatten)]
    method: MethodArgs,
    #[command(flatten)]
    query: QueryArgs,
    /// Write one line per colliding pair: `vf,VERTEX,FACE,TOI` or `ee,A0,A1,B0,B1,TOI`.
    #[arg(long, value_name = "FILE")]
    pairs: Option<PathBuf>,
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
}

/// The environment variable that sets the default of `--max-memory`.
pub const MAX_MEMORY_ENV: &str = "TOPOCCD_MAX_MEMORY";

/// How much memory a step may need, and where that limit comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MemoryLimit {
    /// No check.
    Off,
    /// At most this many bytes.
    Bytes(u64, LimitSource),
}

/// Where a memory limit comes from, for the error message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LimitSource {
    /// `--max-memory`.
    Flag,
    /// `$TOPOCCD_MAX_MEMORY`.
    Env,
    /// `MemAvailable` of `/proc/meminfo`.
    Available,
}

fn parse_memory_limit(s: &str) -> Result<MemoryLimit, String> {
    parse_size(s).map(|limit| {
        limit.map_or(MemoryLimit::Off, |b| {
            MemoryLimit::Bytes(b, LimitSource::Flag)
        })
    })
}

/// `off` (or `none`) as `None`; else bytes, or a number with a suffix K, M, G or T (powers of
/// 1024, optionally followed by `B` or `iB`).
fn parse_size(s: &str) -> Result<Option<u64>, String> {
    let text = s.trim();
    if text.eq_ignore_ascii_case("off") || text.eq_ignore_ascii_case("none") {
        return Ok(None);
    }
    let upper = text.to_ascii_uppercase();
    let number = upper.trim_end_matches("IB").trim_end_matches('B');
    let (digits, shift) = match number.chars().last() {
        Some('K') => (&number[..number.len() - 1], 10),
        Some('M') => (&number[..number.len() - 1], 20),
        Some('G') => (&number[..number.len() - 1], 30),
        Some('T') => (&number[..number.len() - 1], 40),
        _ => (number, 0),
    };
    let bad = || format!("{s:?} is not a size (bytes, or a number with K, M, G or T; or 'off')");
    let value: f64 = digits.trim().parse().map_err(|_| bad())?;
    let bytes = value * (1u64 << shift) as f64;
    if !(bytes.is_finite() && bytes >= 0.0 && bytes < u64::MAX as f64) {
        return Err(bad());
    }
    Ok(Some(bytes as u64))
}

impl MemoryLimit {
    /// The default limit: `$TOPOCCD_MAX_MEMORY` if set, else the available memory, else none.
    pub fn from_env() -> Result<Self> {
        if let Some(value) = std::env::var_os(MAX_MEMORY_ENV) {
            let text = value.to_string_lossy();
            let limit = parse_size(&text).map_err(|e| anyhow::anyhow!("{MAX_MEMORY_ENV}: {e}"))?;
            return Ok(limit.map_or(MemoryLimit::Off, |b| {
                MemoryLimit::Bytes(b, LimitSource::Env)
            }));
        }
        Ok(available_memory().map_or(MemoryLimit::Off, |b| {
            MemoryLimit::Bytes(b, LimitSource::Available)
        }))
    }

    /// Refuses a step of this size if its estimate exceeds the limit.
    fn check(&self, vertices: usize, triangles: usize, t0: &Path, t1: &Path) -> Result<()> {
        let MemoryLimit::Bytes(limit, source) = *self else {
            return Ok(());
        };
        let estimate = MemoryEstimate::of_step(vertices, triangles);
        if let Err(e) = estimate.check(limit) {
            let whence = match source {
                LimitSource::Flag => "set by --max-memory".to_string(),
                LimitSource::Env => format!("set by {MAX_MEMORY_ENV}"),
                LimitSource::Available => "available (MemAvailable in /proc/meminfo)".to_string(),
            };
            bail!(
                "step from {} to {}: {e}, {whence}; refused before reading or building it. \
                 Use --max-memory SIZE (or {MAX_MEMORY_ENV}) to raise the limit, or 'off' to skip \
                 the check",
                t0.display(),
                t1.display(),
            );
        }
        Ok(())
    }
}

/// The JSON summary of one step: the library's own report types.
#[derive(Serialize, Debug)]
pub struct StepOut<'r> {
    vertices: usize,
    triangles: usize,
    method: String,
    mode: &'static str,
    /// Vertex-face contacts reported (in `--earliest` mode, the earliest pairs).
    vf: usize,
    /// Edge-edge contacts reported (in `--earliest` mode, the earliest pairs).
    ee: usize,
    /// Contacts whose certainty is not `Resolved` (the search gave up conservatively).
    unresolved: usize,
    earliest_toi: Option<f64>,
    /// The earliest contact, with its pair, time and certainty.
    earliest: Option<&'r Contact>,
    seconds: &'r Seconds,
    stats: &'r Stats,
    /// The contacts themselves: always in `--earliest` mode, else with `--with-pairs`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pairs: Option<PairsOut<'r>>,
}

/// The contacts of a report.
#[derive(Serialize, Debug)]
pub struct PairsOut<'r> {
    vf: &'r [VfContact],
    ee: &'r [EeContact],
}

impl<'r> StepOut<'r> {
    /// Summarises a report of `step`; `with_pairs` includes the contacts.
    pub fn new(
        step: &Step,
        method: Method,
        mode: Mode,
        report: &'r Report,
        with_pairs: bool,
    ) -> Self {
        let earliest_mode = mode == Mode::Earliest;
        Self {
            vertices: step.vertex_count(),
            triangles: step.triangles().len(),
            method: method.to_string(),
            mode: if earliest_mode { "earliest" } else { "all" },
            vf: report.vf.len(),
            ee: report.ee.len(),
            unresolved: report.unresolved,
            earliest_toi: report.earliest_toi(),
            earliest: report.earliest.as_ref(),
            seconds: &report.stats.seconds,
            stats: &report.stats,
            pairs: (with_pairs || earliest_mode).then_some(PairsOut {
                vf: &report.vf,
                ee: &report.ee,
            }),
        }
    }

    /// One line of text.
    pub fn text(&self) -> String {
        let s = &self.stats;
        let what = if self.mode == "earliest" {
            format!(
                "earliest toi {}, reached by {} vf and {} ee pairs",
                self.earliest_toi
                    .map_or("none".to_string(), |t| t.to_string()),
                self.vf,
                self.ee
            )
        } else {
            format!(
                "{} vf and {} ee contacts, earliest toi {}",
                self.vf,
                self.ee,
                self.earliest_toi
                    .map_or("none".to_string(), |t| t.to_string())
            )
        };
        let earliest = match self.earliest {
            Some(Contact::Vf(c)) => format!(" (vertex {} - face {})", c.vertex, c.face),
            Some(Contact::Ee(c)) => {
                format!(" (edge {}-{} - edge {}-{})", c.a[0], c.a[1], c.b[0], c.b[1])
            }
            None => String::new(),
        };
        let unresolved = if self.unresolved > 0 {
            format!(
                "; {} contacts UNRESOLVED (the search gave up; their times are only lower bounds)",
                self.unresolved
            )
        } else {
            String::new()
        };
        format!(
            "{} vertices, {} triangles: {what}{earliest}{unresolved}; {:.4} s (build {:.4}, traverse {:.4}, narrow {:.4}); {} bv, {} vf, {} ee tests",
            self.vertices,
            self.triangles,
            self.seconds.total,
            self.seconds.build,
            self.seconds.traverse,
            self.seconds.narrow,
            s.bv_tests,
            s.vf_tests,
            s.ee_tests,
        ) + &self.clusters_text()
    }

    /// The cluster figures as text, empty for the other methods.
    fn clusters_text(&self) -> String {
        let Some(c) = &self.stats.cluster else {
            return String::new();
        };
        format!(
            "; clustering {:.4} s, merging {:.4} s; {} leaf clusters ({:.1} triangles each), {} intermediate, {} lazy BVHs, {} leaf pairs",
            c.clustering_seconds,
            c.merging_seconds,
            c.leaf,
            c.triangles_per_leaf,
            c.intermediate,
            c.lazy_bvhs,
            c.leaf_pairs
        )
    }
}

/// Reads the two frames of a step: positions of both, triangles of the second. Refuses a step
/// whose estimated memory exceeds the default [`MemoryLimit::from_env`].
pub fn read_step(t0: &Path, t1: &Path) -> Result<Step<'static>> {
    read_step_within(t0, t1, MemoryLimit::from_env()?)
}

/// The counts a PLY file's header declares; `None` for other formats (counted once read).
fn header_counts(path: &Path) -> Result<Option<PlyCounts>> {
    match MeshFormat::of_path(path)? {
        MeshFormat::Ply => Ok(Some(read_ply_header(path)?)),
        MeshFormat::Obj | MeshFormat::Stl => Ok(None),
    }
}

fn vertex_mismatch(t0: &Path, n0: usize, t1: &Path, n1: usize) -> anyhow::Error {
    anyhow::anyhow!(
        "{} has {n0} vertices but {} has {n1}: a step needs the same vertices at t=0 and t=1",
        t0.display(),
        t1.display(),
    )
}

/// [`read_step`] with the given memory limit, checked from the PLY headers before reading
/// the data, and from the meshes read before building the step.
pub fn read_step_within(t0: &Path, t1: &Path, limit: MemoryLimit) -> Result<Step<'static>> {
    if let (Some(c0), Some(c1)) = (header_counts(t0)?, header_counts(t1)?) {
        if c0.vertices != c1.vertices {
            return Err(vertex_mismatch(t0, c0.vertices, t1, c1.vertices));
        }
        limit.check(c1.vertices, c1.faces, t0, t1)?;
    }
    let m0 = read_mesh(t0)?;
    let m1 = read_mesh(t1)?;
    if m0.positions.len() != m1.positions.len() {
        return Err(vertex_mismatch(
            t0,
            m0.positions.len(),
            t1,
            m1.positions.len(),
        ));
    }
    limit.check(m1.positions.len(), m1.triangles.len(), t0, t1)?;
    Step::new(m0.positions, m1.positions, m1.triangles)
        .with_context(|| format!("step from {} to {}", t0.display(), t1.display()))
}

/// Writes the pairs of a report, one per line, refusing to overwrite any of `inputs`.
pub fn write_pairs(path: &Path, report: &Report, inputs: &[&Path]) -> Result<()> {
    refuse_overwrite(path, inputs)?;
    let file = File::create(path).with_context(|| format!("{}: cannot create", path.display()))?;
    let mut out = BufWriter::new(file);
    for c in &report.vf {
        writeln!(out, "vf,{},{},{}", c.vertex, c.face, c.toi)?;
    }
    for c in &report.ee {
        writeln!(
            out,
            "ee,{},{},{},{},{}",
            c.a[0], c.a[1], c.b[0], c.b[1], c.toi
        )?;
    }
    out.flush()
        .with_context(|| format!("{}: cannot write", path.display()))
}

/// Fails if `output` names the same file as one of `inputs`.
pub fn refuse_overwrite(output: &Path, inputs: &[&Path]) -> Result<()> {
    let canon = |p: &Path| std::fs::canonicalize(p).ok();
    if let Some(out) = canon(output) {
        for input in inputs {
            if canon(input).as_ref() == Some(&out) {
                bail!(
                    "{}: refusing to overwrite an input file with output",
                    output.display()
                );
            }
        }
    }
    Ok(())
}

/// Runs the command.
pub fn run(args: &Args) -> Result<()> {
    let options = args.query.options()?;
    if let Some(p) = &args.pairs {
        refuse_overwrite(p, &[&args.t0, &args.t1])?;
    }
    let started = Instant::now();
    let limit = match args.max_memory {
        Some(limit) => limit,
        None => MemoryLimit::from_env()?,
    };
    let step = read_step_within(&args.t0, &args.t1, limit)?;
    let read_seconds = started.elapsed().as_secs_f64();
    let mut ccd = Ccd::new();
    let method = args.method.method.into();
    let report = ccd.query(&step, method, &options)?;
    if let Some(p) = &args.pairs {
        write_pairs(p, &report, &[&args.t0, &args.t1])?;
    }
    let out = StepOut::new(&step, method, options.mode, &report, args.with_pairs);
    if args.json {
        println!("{}", serde_json::to_string(&out)?);
    } else {
        println!("{}", out.text());
        eprintln!("(reading the two frames took {read_seconds:.3} s)");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_suffixes() {
        assert_eq!(parse_size("123"), Ok(Some(123)));
        assert_eq!(parse_size("4K"), Ok(Some(4096)));
        assert_eq!(parse_size("1.5GiB"), Ok(Some(3 << 29)));
        assert_eq!(parse_size("512mb"), Ok(Some(512 << 20)));
        assert_eq!(parse_size(" 2T "), Ok(Some(2 << 40)));
        assert_eq!(parse_size("off"), Ok(None));
        assert_eq!(parse_size("None"), Ok(None));
        for bad in ["", "G", "-1G", "lots", "1e30T", "NaN", "inf"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
    }
}
