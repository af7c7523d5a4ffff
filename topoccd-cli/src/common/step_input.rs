//! Reading the steps of the commands: two frames, a parents file, welding; warnings on the
//! input.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use topoccd::io::sequence::{Sequence, StepFrames};
use topoccd::io::{
    input_warnings, read_mesh, read_ply_header, weld_frames, with_file_primitives, FaceOrigin,
    InputWarning, LooseVertices, MeshFormat, PlyCounts,
};
use topoccd::Step;

use super::memory::MemoryLimit;

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
        .and_then(|step| with_file_primitives(step, &m1.edges, LooseVertices::Points))
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
    loose_rule: LooseVertices,
) -> Result<StepInput> {
    let loose = loose_rule;
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
            .and_then(|step| with_file_primitives(step, &frames.edges, loose))
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
        if !m1.edges.is_empty() {
            bail!(
                "--weld cannot be combined with free edges ({} has {} edges): welding renumbers \
                 the vertices the edges name",
                t1.display(),
                m1.edges.len()
            );
        }
        let w = weld_frames(&m0.positions, &m1.positions, &m1.triangles);
        let loose = m1.loose_vertices().len();
        if loose > 0 && loose_rule.are_points() {
            messages.push(format!(
                "warning: {}: --weld ignores its {loose} vertices in no face and no edge (they \
                 are free points without --weld)",
                t1.display()
            ));
        }
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
    let step = Step::new(m0.positions, m1.positions, m1.triangles)
        .and_then(|step| with_file_primitives(step, &m1.edges, loose))
        .with_context(context)?;
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

/// A warning naming the files of the sequence's folder that are not its frames (at most 12),
/// `None` when there are none: a folder holding two frames among other files is then not taken
/// as a sequence silently.
pub fn left_out_warning(sequence: &Sequence) -> Option<String> {
    const SHOWN: usize = 12;
    let ignored = &sequence.ignored;
    if ignored.is_empty() {
        return None;
    }
    let name = |p: &PathBuf| {
        p.file_name()
            .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
    };
    let more = if ignored.len() > SHOWN {
        format!(" and {} more", ignored.len() - SHOWN)
    } else {
        String::new()
    };
    Some(format!(
        "warning: {}: the sequence is the {} frames {} ... {} ({} steps); left out: {}{more}",
        sequence.dir.display(),
        sequence.frames.len(),
        name(&sequence.frames[0]),
        name(&sequence.frames[sequence.frames.len() - 1]),
        sequence.steps(),
        ignored[..ignored.len().min(SHOWN)].join(", "),
    ))
}
