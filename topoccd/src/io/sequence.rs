//! Frame sequences: a folder of frames `0000.ply`, `0001.ply`, ... (PLY or OBJ, by extension).
//!
//! Step `k` goes from frame `k` to frame `k + 1` and uses frame `k + 1`'s triangles. Vertex ids
//! persist from frame to frame; a topology change may remove triangles and append vertices (a cut
//! or a fracture duplicates the vertices along the crack), so the vertex count never shrinks. A
//! new vertex (id at least frame `k`'s vertex count) starts the step at its *parent's* position in
//! frame `k`, given by an optional file `NNNN.parents` beside frame `NNNN` (here `k + 1`): one line
//! `NEW_ID PARENT_ID` per new vertex, `#` comments and blank lines allowed. A new vertex without a
//! parent starts where it ends (it does not move during the step).

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

use thiserror::Error;

use super::{read_mesh, write_mesh, IoError, Mesh};
use crate::mesh::{Step, StepError};

/// Why a sequence could not be read.
#[derive(Debug, Error)]
pub enum SequenceError {
    /// The folder could not be listed.
    #[error("{path}: cannot list the folder")]
    Folder {
        /// The folder.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// Fewer than two frames: no step.
    #[error(
        "{path}: a sequence needs at least two frames (0000.ply, 0001.ply, ...), found {found}"
    )]
    TooFewFrames {
        /// The folder.
        path: PathBuf,
        /// Frames found.
        found: usize,
    },
    /// The numbering has a gap, does not start at 0, or a number appears twice.
    #[error("{path}: frame {expected:04} is missing (frames must be numbered 0000, 0001, ... without gaps); found {found}")]
    Numbering {
        /// The folder.
        path: PathBuf,
        /// The frame number expected next.
        expected: u64,
        /// The file found in its place.
        found: String,
    },
    /// A frame could not be read.
    #[error(transparent)]
    Frame(#[from] IoError),
    /// A frame has fewer vertices than the one before.
    #[error("{path}: {vertices} vertices, fewer than the {previous} of the previous frame (vertex ids persist, so the count may only grow)")]
    Shrinks {
        /// The frame.
        path: PathBuf,
        /// Its vertex count.
        vertices: usize,
        /// The previous frame's vertex count.
        previous: usize,
    },
    /// A line of a parents file is malformed or names a vertex out of range.
    #[error("{path}:{line}: {message}")]
    Parents {
        /// The parents file.
        path: PathBuf,
        /// Line number, 1-based.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The step built from two frames is invalid (NaN coordinates, bad triangles, ...).
    #[error("step {step} ({path}): {source}")]
    Step {
        /// The step's index (its first frame's number).
        step: usize,
        /// The frame whose triangles the step uses.
        path: PathBuf,
        /// What is wrong.
        source: StepError,
    },
}

/// A frame sequence on disk: the frame files, in order.
#[derive(Clone, Debug)]
pub struct Sequence {
    /// The folder.
    pub dir: PathBuf,
    /// The frame files, `frames[k]` being frame `k`.
    pub frames: Vec<PathBuf>,
}

impl Sequence {
    /// Lists the frames of a folder and checks their numbering.
    pub fn open(dir: &Path) -> Result<Self, SequenceError> {
        let folder_err = |source| SequenceError::Folder {
            path: dir.to_path_buf(),
            source,
        };
        let mut numbered: BTreeMap<u64, Vec<PathBuf>> = BTreeMap::new();
        for entry in fs::read_dir(dir).map_err(folder_err)? {
            let path = entry.map_err(folder_err)?.path();
            let ext = path
                .extension()
                .and_then(|e| e.to_str())
                .map(str::to_ascii_lowercase);
            if !matches!(ext.as_deref(), Some("ply" | "obj")) {
                continue;
            }
            let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
            if stem.is_empty() || !stem.bytes().all(|b| b.is_ascii_digit()) {
                continue;
            }
            if let Ok(n) = stem.parse::<u64>() {
                numbered.entry(n).or_default().push(path);
            }
        }
        let mut frames = Vec::with_capacity(numbered.len());
        for (expected, (n, mut paths)) in numbered.into_iter().enumerate() {
            paths.sort();
            let expected = expected as u64;
            if n != expected || paths.len() > 1 {
                let found = paths
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(" and ");
                return Err(SequenceError::Numbering {
                    path: dir.to_path_buf(),
                    expected: if n != expected {
                        expected
                    } else {
                        expected + 1
                    },
                    found,
                });
            }
            frames.extend(paths);
        }
        if frames.len() < 2 {
            return Err(SequenceError::TooFewFrames {
                path: dir.to_path_buf(),
                found: frames.len(),
            });
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            frames,
        })
    }

    /// Number of steps (frames less one).
    pub fn steps(&self) -> usize {
        self.frames.len() - 1
    }

    /// Iterates over the steps, reading each frame once.
    pub fn iter(&self) -> StepIter<'_> {
        StepIter {
            sequence: self,
            next: 0,
            previous: None,
        }
    }
}

/// Iterator over the steps of a [`Sequence`]: yields `(k, step)` for step `k`.
pub struct StepIter<'a> {
    sequence: &'a Sequence,
    next: usize,
    previous: Option<Mesh>,
}

impl Iterator for StepIter<'_> {
    type Item = Result<(usize, Step<'static>), SequenceError>;

    fn next(&mut self) -> Option<Self::Item> {
        let k = self.next;
        if k >= self.sequence.steps() {
            return None;
        }
        self.next += 1;
        let result = (|| {
            let start = match self.previous.take() {
                Some(mesh) => mesh,
                None => read_mesh(&self.sequence.frames[k])?,
            };
            let end = read_mesh(&self.sequence.frames[k + 1])?;
            let step = step_between(&start, &end, &self.sequence.frames[k + 1], k)?;
            self.previous = Some(end);
            Ok((k, step))
        })();
        if result.is_err() {
            self.next = self.sequence.steps(); // stop after the first error
        }
        Some(result)
    }
}

/// Path of the parents file that belongs to a frame file.
pub fn parents_path(frame: &Path) -> PathBuf {
    frame.with_extension("parents")
}

/// Builds step `k` from its two frames; `end_path` names frame `k + 1` (its parents file is
/// looked up beside it).
pub fn step_between(
    start: &Mesh,
    end: &Mesh,
    end_path: &Path,
    k: usize,
) -> Result<Step<'static>, SequenceError> {
    let (n0, n1) = (start.positions.len(), end.positions.len());
    let parents_file = parents_path(end_path);
    // (A shrinking vertex count is reported by `step_from_frames`.)
    let parents = if n1 >= n0 && parents_file.exists() {
        read_parents(&parents_file, n0, n1)?
    } else {
        Vec::new()
    };
    step_from_frames(start, end, &parents, end_path, k)
}

/// Builds step `k` from its two frames and the `(new, parent)` pairs of the vertices new in
/// `end` (already validated: `start.len() <= new < end.len()`, `parent < start.len()`); `end_path`
/// only names the frame in errors. A new vertex without a parent starts where it ends.
pub fn step_from_frames(
    start: &Mesh,
    end: &Mesh,
    parents: &[(u32, u32)],
    end_path: &Path,
    k: usize,
) -> Result<Step<'static>, SequenceError> {
    let (n0, n1) = (start.positions.len(), end.positions.len());
    if n1 < n0 {
        return Err(SequenceError::Shrinks {
            path: end_path.to_path_buf(),
            vertices: n1,
            previous: n0,
        });
    }
    let rows: Vec<[u32; 2]> = parents.iter().map(|&(new, parent)| [new, parent]).collect();
    Step::with_parents(
        start.positions.clone(),
        end.positions.clone(),
        end.triangles.clone(),
        &rows,
    )
    .map_err(|source| SequenceError::Step {
        step: k,
        path: end_path.to_path_buf(),
        source,
    })
}

/// Reads a parents file: pairs `(new, parent)` with `previous <= new < current` and
/// `parent < previous`, each new vertex at most once. See [`parse_parents`] for the format.
pub fn read_parents(
    path: &Path,
    previous: usize,
    current: usize,
) -> Result<Vec<(u32, u32)>, SequenceError> {
    let text = fs::read_to_string(path).map_err(|e| {
        SequenceError::Frame(IoError::Io {
            path: path.to_path_buf(),
            action: "read",
            source: e,
        })
    })?;
    parse_parents(&text, path, previous, current)
}

/// Parses the text of a parents file; `path` only names the file in errors. `previous` is the
/// vertex count of the step's first frame, `current` that of its second: each line
/// `NEW_ID PARENT_ID` needs `previous <= NEW_ID < current` and `PARENT_ID < previous`, and a
/// new vertex may be given a parent at most once. `#` starts a comment; blank lines are
/// skipped.
///
/// ```
/// use std::path::Path;
/// use topoccd::io::sequence::{parse_parents, SequenceError};
/// let text = "# NEW_ID PARENT_ID\n4 0\n5 2  # the crack's other side\n";
/// assert_eq!(parse_parents(text, Path::new("0001.parents"), 4, 6)?, vec![(4, 0), (5, 2)]);
/// let err = parse_parents("4 0\n4 1\n", Path::new("0001.parents"), 4, 6).unwrap_err();
/// assert_eq!(err.to_string(), "0001.parents:2: NEW_ID 4 is given a parent twice");
/// # Ok::<(), SequenceError>(())
/// ```
pub fn parse_parents(
    text: &str,
    path: &Path,
    previous: usize,
    current: usize,
) -> Result<Vec<(u32, u32)>, SequenceError> {
    let mut seen = vec![false; current.saturating_sub(previous)];
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let err = |message: String| SequenceError::Parents {
            path: path.to_path_buf(),
            line: i + 1,
            message,
        };
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split_whitespace().collect();
        let [new, parent] = fields[..] else {
            return Err(err(format!(
                "expected two vertex ids `NEW_ID PARENT_ID`, found {:?}",
                line
            )));
        };
        let parse = |s: &str, what: &str| {
            s.parse::<u32>()
                .map_err(|_| err(format!("{what} {s:?} is not a vertex id")))
        };
        let (new, parent) = (parse(new, "NEW_ID")?, parse(parent, "PARENT_ID")?);
        if (new as usize) < previous || new as usize >= current {
            return Err(err(format!(
                "NEW_ID {new} is not a new vertex: new vertices of this frame are {previous}..{current}"
            )));
        }
        if parent as usize >= previous {
            return Err(err(format!(
                "PARENT_ID {parent} is out of range: the previous frame has {previous} vertices"
            )));
        }
        let slot = &mut seen[new as usize - previous];
        if *slot {
            return Err(err(format!("NEW_ID {new} is given a parent twice")));
        }
        *slot = true;
        out.push((new, parent));
    }
    Ok(out)
}

/// Writes frame `k` of a sequence as `dir/kkkk.ply`, with its parents file if `parents` is not
/// empty. Refuses to overwrite an existing frame.
pub fn write_frame(
    dir: &Path,
    k: usize,
    mesh: &Mesh,
    parents: &[(u32, u32)],
) -> Result<PathBuf, IoError> {
    let path = dir.join(format!("{k:04}.ply"));
    if path.exists() {
        return Err(IoError::Io {
            path,
            action: "write",
            source: std::io::Error::new(
                std::io::ErrorKind::AlreadyExists,
                "frame exists already; refusing to overwrite it",
            ),
        });
    }
    write_mesh(&path, mesh)?;
    if !parents.is_empty() {
        let mut text = String::with_capacity(parents.len() * 16);
        text.push_str(
            "# NEW_ID PARENT_ID: a new vertex starts the step at its parent's position\n",
        );
        for (new, parent) in parents {
            text.push_str(&format!("{new} {parent}\n"));
        }
        let ppath = parents_path(&path);
        fs::write(&ppath, text).map_err(|source| IoError::Io {
            path: ppath.clone(),
            action: "write",
            source,
        })?;
    }
    Ok(path)
}
