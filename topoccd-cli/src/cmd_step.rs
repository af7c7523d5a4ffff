//! `topoccd step T0 T1`: the CCD query of one step between two mesh files.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use serde::Serialize;
use topoccd::io::sequence::StepFrames;
use topoccd::io::{
    available_memory, input_warnings, read_mesh, read_ply_header, weld_frames, FaceOrigin,
    InputWarning, MemoryEstimate, MeshFormat, PlyCounts,
};
use topoccd::{
    Ccd, Contact, EeContact, Method, Mode, Report, Seconds, Stats, Step, Truncation, VfContact,
};

use crate::cmd_run::with_spinner;
use crate::query_args::{MethodArgs, QueryArgs};

/// Arguments of `topoccd step`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Positions at t=0 (.ply, .obj or .stl).
    t0: PathBuf,
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
    /// `null` when the query ran to its end; else why it stopped (`max_contacts`), where
    /// and how far it got: the report holds only part of the step's contacts.
    truncated: Option<&'r Truncation>,
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
            truncated: report.truncated.as_ref(),
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
            Some(Contact::Ve(c)) => {
                format!(" (vertex {} - edge {}-{})", c.vertex, c.edge[0], c.edge[1])
            }
            Some(Contact::Vv(c)) => format!(" (vertex {} - vertex {})", c.a, c.b),
            None => String::new(),
        };
        let truncated = match self.truncated {
            Some(t) => format!(
                "; TRUNCATED ({}: the first contacts of {} traversal tasks; the step has more: \
                 --max-contacts N or off raises the cap)",
                t.reason, t.tasks
            ),
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
            "{} vertices, {} triangles: {what}{earliest}{truncated}{unresolved}; {:.4} s (build {:.4}, traverse {:.4}, narrow {:.4}); {} bv, {} vf, {} ee tests",
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
            "; clustering {:.4} s, merging {:.4} s; {} leaf clusters ({:.1} triangles each, {} carried over), {} intermediate, {} lazy BVHs, {} leaf pairs",
            c.clustering_seconds,
            c.merging_seconds,
            c.leaf,
            c.triangles_per_leaf,
            c.reused_leaves,
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
    if path.is_dir() {
        return Err(topoccd::io::IoError::Folder {
            path: path.to_path_buf(),
        }
        .into());
    }
    match MeshFormat::of_path(path)? {
        MeshFormat::Ply => Ok(Some(read_ply_header(path)?)),
        MeshFormat::Obj | MeshFormat::Stl => Ok(None),
    }
}

fn vertex_mismatch(t0: &Path, n0: usize, t1: &Path, n1: usize) -> anyhow::Error {
    anyhow::anyhow!(
        "{} has {n0} vertices but {} has {n1}: a step needs the same vertices at t=0 and t=1 \
         (for a topology change that adds vertices, give their parents with --parents FILE)",
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

/// One step as `topoccd step` reads it: the step, and what the output needs to name vertices
/// and faces as the input files do.
pub struct StepInput {
    /// The step.
    pub step: Step<'static>,
    /// `vertex_ids[v]`: the id in the files of the step's vertex `v` (`None`: the same).
    pub vertex_ids: Option<Vec<u32>>,
    /// `triangle_ids[t]`: the index in T1's triangles of the step's triangle `t` (`None`: the
    /// same).
    pub triangle_ids: Option<Vec<u32>>,
    /// T1's map from its triangles to the faces of its file (`None`: triangle `t` is face `t`).
    pub face_origin: Option<Vec<FaceOrigin>>,
    /// Notes and warnings for stderr, one per line.
    pub messages: Vec<String>,
}

/// Reads a step with the options of `topoccd step`: a parents file (a topology change), or
/// welding; warns of coincident vertices when not welding.
pub fn read_step_input(
    t0: &Path,
    t1: &Path,
    limit: MemoryLimit,
    parents: Option<&Path>,
    weld: bool,
) -> Result<StepInput> {
    if parents.is_some() && weld {
        bail!("--weld cannot be combined with --parents (the vertex ids of a topology change must stay as they are)");
    }
    if let (Some(c0), Some(c1)) = (header_counts(t0)?, header_counts(t1)?) {
        if c0.vertices != c1.vertices && parents.is_none() {
            return Err(vertex_mismatch(t0, c0.vertices, t1, c1.vertices));
        }
        limit.check(c1.vertices, c1.faces, t0, t1)?;
    }
    let m0 = read_mesh(t0)?;
    let m1 = read_mesh(t1)?;
    let mut messages: Vec<String> = [(t0, &m0.notes), (t1, &m1.notes)]
        .iter()
        .flat_map(|(path, notes)| {
            notes
                .iter()
                .map(move |n| format!("note: {}: {n}", path.display()))
        })
        .collect();
    limit.check(m1.positions.len(), m1.triangles.len(), t0, t1)?;
    let context = || format!("step from {} to {}", t0.display(), t1.display());
    if let Some(parents) = parents {
        let frames = StepFrames::new(0, m0, m1, t0, t1, Some(parents))?;
        let step = Step::with_parents(frames.x0, frames.x1, frames.triangles, &frames.parents)
            .with_context(context)?;
        return Ok(StepInput {
            step,
            vertex_ids: None,
            triangle_ids: None,
            face_origin: frames.face_origin,
            messages,
        });
    }
    if m0.positions.len() != m1.positions.len() {
        return Err(vertex_mismatch(
            t0,
            m0.positions.len(),
            t1,
            m1.positions.len(),
        ));
    }
    if weld {
        let w = weld_frames(&m0.positions, &m1.positions, &m1.triangles);
        let merged = m0.positions.len() - w.x0.len();
        messages.push(format!(
            "note: --weld merged {merged} vertices (in {} groups) and dropped {} degenerate \
             triangles; ids in the output are those of the input files",
            w.groups.len(),
            m1.triangles.len() - w.triangles.len()
        ));
        let step = Step::new(w.x0, w.x1, w.triangles).with_context(context)?;
        return Ok(StepInput {
            step,
            vertex_ids: Some(w.first),
            triangle_ids: Some(w.kept),
            face_origin: m1.face_origin,
            messages,
        });
    }
    let remedy = "--weld merges vertices that coincide at t=0 and t=1";
    messages.extend(input_warning_lines(
        t0,
        &m0.positions,
        &m1.triangles,
        remedy,
    ));
    let step = Step::new(m0.positions, m1.positions, m1.triangles).with_context(context)?;
    Ok(StepInput {
        step,
        vertex_ids: None,
        triangle_ids: None,
        face_origin: m1.face_origin,
        messages,
    })
}

/// The warnings on the input read from `path` ([`input_warnings`], the library's check that the
/// Python package shares), one line each; `remedy` ends the warning of coincident vertices.
pub fn input_warning_lines(
    path: &Path,
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
    remedy: &str,
) -> Vec<String> {
    input_warnings(positions, triangles)
        .iter()
        .map(|w| {
            let remedy = match w {
                InputWarning::CoincidentVertices { .. } => format!(". {remedy}"),
                _ => String::new(),
            };
            format!("warning: {}: {w}{remedy}", path.display())
        })
        .collect()
}

/// Renames the contacts of a report from the step's ids to the input files' ids.
pub fn rename(report: &mut Report, vertex_ids: Option<&[u32]>, triangle_ids: Option<&[u32]>) {
    // Both maps increase, so the report's order (by vertex, face / by edges) is kept.
    let v = |i: u32| vertex_ids.map_or(i, |m| m[i as usize]);
    let t = |i: u32| triangle_ids.map_or(i, |m| m[i as usize]);
    let vf = |c: &mut VfContact| {
        c.vertex = v(c.vertex);
        c.face = t(c.face);
    };
    let ee = |c: &mut EeContact| {
        c.a = c.a.map(v);
        c.b = c.b.map(v);
    };
    report.vf.iter_mut().for_each(vf);
    report.ee.iter_mut().for_each(ee);
    for c in &mut report.ve {
        c.vertex = v(c.vertex);
        c.edge = c.edge.map(v);
    }
    for c in &mut report.vv {
        [c.a, c.b] = [v(c.a), v(c.b)];
    }
    match &mut report.earliest {
        Some(Contact::Vf(c)) => vf(c),
        Some(Contact::Ee(c)) => ee(c),
        Some(Contact::Ve(c)) => {
            c.vertex = v(c.vertex);
            c.edge = c.edge.map(v);
        }
        Some(Contact::Vv(c)) => [c.a, c.b] = [v(c.a), v(c.b)],
        None => {}
    }
}

/// Writes the pairs of a report, one per line, to `path` (`-`: stdout), refusing to overwrite
/// any of `inputs`. With a face map, vf lines end with the face of the file and the rank of
/// the triangle within it.
pub fn write_pairs(
    path: &Path,
    report: &Report,
    inputs: &[&Path],
    face_origin: Option<&[FaceOrigin]>,
) -> Result<()> {
    if path == Path::new("-") {
        let stdout = std::io::stdout();
        return write_pairs_to(stdout.lock(), report, face_origin)
            .context("cannot write the pairs to stdout");
    }
    refuse_overwrite(path, inputs)?;
    let file = File::create(path).with_context(|| format!("{}: cannot create", path.display()))?;
    write_pairs_to(file, report, face_origin)
        .with_context(|| format!("{}: cannot write", path.display()))
}

fn write_pairs_to(
    out: impl Write,
    report: &Report,
    face_origin: Option<&[FaceOrigin]>,
) -> std::io::Result<()> {
    let mut out = BufWriter::new(out);
    for c in &report.vf {
        write!(out, "vf,{},{},{}", c.vertex, c.face, c.toi)?;
        if let Some(o) = face_origin.and_then(|m| m.get(c.face as usize)) {
            write!(out, ",{},{}", o.face, o.sub)?;
        }
        writeln!(out)?;
    }
    for c in &report.ee {
        writeln!(
            out,
            "ee,{},{},{},{},{}",
            c.a[0], c.a[1], c.b[0], c.b[1], c.toi
        )?;
    }
    for c in &report.ve {
        writeln!(out, "ve,{},{},{},{}", c.vertex, c.edge[0], c.edge[1], c.toi)?;
    }
    for c in &report.vv {
        writeln!(out, "vv,{},{},{}", c.a, c.b, c.toi)?;
    }
    out.flush()
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
    let limit = match args.max_memory {
        Some(limit) => limit,
        None => MemoryLimit::from_env()?,
    };
    let options = args.query.options_within(limit)?;
    let to_stdout = args.pairs.as_deref() == Some(Path::new("-"));
    if to_stdout && args.json {
        bail!("--pairs - and --json would both write to stdout; use --json --with-pairs to have the pairs in the JSON");
    }
    if let Some(p) = &args.pairs {
        if !to_stdout {
            refuse_overwrite(p, &[&args.t0, &args.t1])?;
            crate::cmd_render::writable(p)?;
        }
    }
    let input = read_step_input(
        &args.t0,
        &args.t1,
        limit,
        args.parents.as_deref(),
        args.weld,
    )?;
    for message in &input.messages {
        eprintln!("{message}");
    }
    let mut ccd = Ccd::new();
    let method = args.method.method.into();
    let mut report = with_spinner("querying the step", || {
        ccd.query(&input.step, method, &options)
    })?;
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
