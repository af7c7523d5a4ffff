//! A step's results as the commands print and write them: one line of text, JSON, pairs files.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use anyhow::{Context, Result};
use serde::Serialize;
use topoccd::io::FaceOrigin;
use topoccd::{
    Contact, EeContact, Method, Mode, Report, Seconds, Stats, Step, Truncation, VeContact,
    VfContact, VvContact,
};

use super::files::refuse_overwrite;

/// The JSON summary of one step: the library's own report types.
#[derive(Serialize, Debug)]
pub struct StepOut<'r> {
    vertices: usize,
    triangles: usize,
    /// Free edges (in no triangle) the step was queried with.
    free_edges: usize,
    /// Free points (vertices in no triangle and no edge, read as particles) it was queried
    /// with.
    free_points: usize,
    method: String,
    mode: &'static str,
    /// Vertex-face contacts reported (in `--earliest` mode, the earliest pairs).
    vf: usize,
    /// Edge-edge contacts reported (in `--earliest` mode, the earliest pairs).
    ee: usize,
    /// Vertex-edge contacts (a free point and a free edge) reported.
    ve: usize,
    /// Vertex-vertex contacts (two free points) reported.
    vv: usize,
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
    ve: &'r [VeContact],
    vv: &'r [VvContact],
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
        let primitives = topoccd::io::FilePrimitives::of_step(step);
        Self {
            vertices: step.vertex_count(),
            triangles: step.triangles().len(),
            free_edges: primitives.free_edges.len(),
            free_points: primitives.free_points.len(),
            method: method.to_string(),
            mode: if earliest_mode { "earliest" } else { "all" },
            vf: report.vf.len(),
            ee: report.ee.len(),
            ve: report.ve.len(),
            vv: report.vv.len(),
            unresolved: report.unresolved,
            earliest_toi: report.earliest_toi(),
            earliest: report.earliest.as_ref(),
            truncated: report.truncated.as_ref(),
            seconds: &report.stats.seconds,
            stats: &report.stats,
            pairs: (with_pairs || earliest_mode).then_some(PairsOut {
                vf: &report.vf,
                ee: &report.ee,
                ve: &report.ve,
                vv: &report.vv,
            }),
        }
    }

    /// One line of text.
    pub fn text(&self) -> String {
        let s = &self.stats;
        // Free points and edges (codimensional geometry): named only when they collide.
        let codim = if self.ve + self.vv > 0 {
            format!(" ({} ve and {} vv)", self.ve, self.vv)
        } else {
            String::new()
        };
        let what = if self.mode == "earliest" {
            format!(
                "earliest toi {}, reached by {} vf and {} ee pairs{codim}",
                self.earliest_toi
                    .map_or("none".to_string(), |t| t.to_string()),
                self.vf,
                self.ee
            )
        } else {
            format!(
                "{} vf and {} ee contacts{codim}, earliest toi {}",
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
