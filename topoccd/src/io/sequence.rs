//! Frame sequences: a folder of frames `0000.ply`, `0001.ply`, ... (PLY, OBJ or STL, by
//! extension).
//!
//! A frame file's name is any prefix followed by its number (`0000.ply`, `frame_0001.obj`,
//! `mesh.12.ply`, `cloth_ball92.ply`); all frames share one prefix, and their numbers are
//! consecutive from any start (`frame_0001`, `frame_0002`, ...; zero-padding optional). Frame
//! `k` of the sequence is the `k`-th number. A scene folder of the shared data (frames in a
//! `frames/` subfolder beside `boxes/` and `mma_bool/`) opens as the sequence of its `frames/`.
//!
//! Step `k` goes from frame `k` to frame `k + 1` and uses frame `k + 1`'s triangles. Vertex ids
//! persist from frame to frame; a topology change may remove triangles and append vertices (a cut
//! or a fracture duplicates the vertices along the crack), so the vertex count never shrinks. A
//! new vertex (id at least frame `k`'s vertex count) starts the step at its *parent's* position in
//! frame `k`, given by an optional parents file beside frame `k + 1`, of the same name with the
//! extension `.parents` (`0001.parents` beside `0001.ply`, `frame_0002.parents` beside
//! `frame_0002.obj`): one line `NEW_ID PARENT_ID` per new vertex, `#` comments and blank lines
//! allowed. A new vertex without a parent starts where it ends (it does not move during the
//! step).
//!
//! [`Sequence::load`] reads one step as plain data ([`StepFrames`]); [`Sequence::iter`],
//! [`step_between`] and [`step_from_frames`] build [`Step`]s directly.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

use thiserror::Error;

use super::{
    read_mesh, with_file_primitives, write_mesh, FaceOrigin, IoError, LooseVertices, Mesh, MeshNote,
};
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
        "{path}: a sequence needs at least two frames (files named a common prefix and a \
         consecutive number: 0000.ply, 0001.ply, ... or frame_1.obj, frame_2.obj, ...), found \
         {found}{}",
        ignored_list(ignored)
    )]
    TooFewFrames {
        /// The folder.
        path: PathBuf,
        /// Frames found.
        found: usize,
        /// The files of the folder that are not frames, each with the reason.
        ignored: Vec<String>,
    },
    /// The frame files have more than one prefix (`a_0.ply`, `b_0.ply`, ...).
    #[error(
        "{path}: frame files with {} different prefixes ({}); a sequence folder holds one \
         series of frames",
        series.len(),
        series.join("; ")
    )]
    Ambiguous {
        /// The folder.
        path: PathBuf,
        /// Each series: its prefix and files, as text.
        series: Vec<String>,
    },
    /// The numbering has a gap, or a number appears twice.
    #[error("{path}: frame {expected} is missing (frames must be numbered consecutively from the first one, {first}); found {found}")]
    Numbering {
        /// The folder.
        path: PathBuf,
        /// The number of the first frame.
        first: u64,
        /// The frame number expected next.
        expected: u64,
        /// The file found in its place.
        found: String,
    },
    /// [`Sequence::load`] was asked for a step that does not exist.
    #[error("{path}: no step {step}: the sequence has {steps} steps")]
    NoSuchStep {
        /// The folder.
        path: PathBuf,
        /// The step asked for.
        step: usize,
        /// Steps in the sequence.
        steps: usize,
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

/// The ignored files as text for [`SequenceError::TooFewFrames`]: at most 12 named.
fn ignored_list(ignored: &[String]) -> String {
    const SHOWN: usize = 12;
    if ignored.is_empty() {
        return String::new();
    }
    let mut text = format!(
        "; ignored: {}",
        ignored[..ignored.len().min(SHOWN)].join(", ")
    );
    if ignored.len() > SHOWN {
        text.push_str(&format!(" and {} more", ignored.len() - SHOWN));
    }
    text
}

/// The extensions of frame files (lower case).
const FRAME_EXTENSIONS: [&str; 3] = ["ply", "obj", "stl"];

/// A frame sequence on disk: the frame files, in order.
#[derive(Clone, Debug)]
pub struct Sequence {
    /// The folder of the frames (`<scene>/frames` for a scene folder).
    pub dir: PathBuf,
    /// The frame files, `frames[k]` being frame `k`.
    pub frames: Vec<PathBuf>,
    /// The number in the name of frame 0 (the first frame).
    pub first: u64,
    /// The other files of the folder (not frames of the series, nor parents files), each with
    /// why it was left out: a front end says so, so that a folder holding two frames among
    /// other files is not taken as a sequence silently.
    pub ignored: Vec<String>,
    /// What the frames' loose vertices are, for [`Sequence::iter`]'s steps (see
    /// [`Sequence::with_loose_vertices`]).
    pub loose_vertices: LooseVertices,
}

/// A file name split into its prefix and the number that ends its stem.
fn split_name(path: &Path) -> Result<(String, u64), &'static str> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some(e) if FRAME_EXTENSIONS.contains(&e) => {}
        Some("parents") => return Err("parents"),
        _ => return Err("not a .ply, .obj or .stl file"),
    }
    let stem = path
        .file_stem()
        .and_then(|s| s.to_str())
        .ok_or("not a UTF-8 name")?;
    let prefix = stem.trim_end_matches(|c: char| c.is_ascii_digit());
    if prefix.len() == stem.len() {
        return Err("no number at the end of its name");
    }
    let number = stem[prefix.len()..]
        .parse()
        .map_err(|_| "its number is too large")?;
    Ok((prefix.to_owned(), number))
}

impl Sequence {
    /// Lists the frames of a folder and checks their numbering (see the [module
    /// documentation](self) for the names). A folder without frame files but with a `frames/`
    /// subfolder (a scene folder of the shared data) opens as that subfolder. When fewer than
    /// two frames are found, the error names the files that were ignored, and why.
    ///
    /// ```
    /// use topoccd::io::sequence::{write_frame, Sequence, SequenceError};
    /// use topoccd::io::{write_mesh, Mesh};
    /// let dir = std::env::temp_dir().join(format!("topoccd-doc-seq-{}", std::process::id()));
    /// std::fs::create_dir_all(&dir)?;
    /// let mesh = Mesh::new(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]);
    /// write_mesh(&dir.join("frame_0001.obj"), &mesh)?;
    /// let err = Sequence::open(&dir).unwrap_err();
    /// assert!(err.to_string().contains("found 1"), "{err}");
    /// std::fs::write(dir.join("notes.txt"), "")?;
    /// write_mesh(&dir.join("frame_0002.obj"), &mesh)?;
    /// let seq = Sequence::open(&dir)?;
    /// assert_eq!((seq.steps(), seq.first), (1, 1));
    /// let step = seq.load(0)?;
    /// assert!(step.end.ends_with("frame_0002.obj"));
    /// std::fs::remove_dir_all(&dir)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn open(dir: &Path) -> Result<Self, SequenceError> {
        let folder_err = |source| SequenceError::Folder {
            path: dir.to_path_buf(),
            source,
        };
        let mut entries = Vec::new();
        for entry in fs::read_dir(dir).map_err(folder_err)? {
            entries.push(entry.map_err(folder_err)?.path());
        }
        entries.sort();
        let mut series: BTreeMap<String, BTreeMap<u64, Vec<PathBuf>>> = BTreeMap::new();
        let mut ignored = Vec::new();
        for path in entries {
            let shown = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            if path.is_dir() {
                ignored.push(format!("{shown}/ (a folder)"));
                continue;
            }
            match split_name(&path) {
                Ok((prefix, number)) => {
                    series
                        .entry(prefix)
                        .or_default()
                        .entry(number)
                        .or_default()
                        .push(path);
                }
                Err("parents") => {}
                Err(why) => ignored.push(format!("{shown} ({why})")),
            }
        }
        if series.is_empty() && dir.join("frames").is_dir() {
            return Self::open(&dir.join("frames"));
        }
        if series.len() > 1 {
            return Err(SequenceError::Ambiguous {
                path: dir.to_path_buf(),
                series: series
                    .iter()
                    .map(|(prefix, numbered)| {
                        let files = numbered.values().map(Vec::len).sum::<usize>();
                        format!("'{prefix}': {files} file(s)")
                    })
                    .collect(),
            });
        }
        let numbered = series.into_values().next().unwrap_or_default();
        let first = numbered.keys().next().copied().unwrap_or(0);
        let mut frames = Vec::with_capacity(numbered.len());
        for (expected, (n, paths)) in (first..).zip(numbered) {
            if n != expected || paths.len() > 1 {
                let found = paths
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(" and ");
                return Err(SequenceError::Numbering {
                    path: dir.to_path_buf(),
                    first,
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
                ignored,
            });
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            frames,
            first,
            ignored,
            loose_vertices: LooseVertices::Points,
        })
    }

    /// The sequence, its steps ([`Sequence::iter`]) reading loose vertices as `loose` says
    /// (see [`with_file_primitives`]; the default is [`LooseVertices::Points`]).
    pub fn with_loose_vertices(mut self, loose: LooseVertices) -> Self {
        self.loose_vertices = loose;
        self
    }

    /// Reads step `k` (frames `k` and `k + 1`, and the parents file of frame `k + 1` if there
    /// is one) as plain data: see [`StepFrames`].
    pub fn load(&self, k: usize) -> Result<StepFrames, SequenceError> {
        if k >= self.steps() {
            return Err(SequenceError::NoSuchStep {
                path: self.dir.clone(),
                step: k,
                steps: self.steps(),
            });
        }
        let (start, end) = (&self.frames[k], &self.frames[k + 1]);
        let parents = parents_path(end);
        StepFrames::new(
            k,
            read_mesh(start)?,
            read_mesh(end)?,
            start,
            end,
            parents.exists().then_some(parents.as_path()),
        )
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
            let step = step_between_loose(
                &start,
                &end,
                &self.sequence.frames[k + 1],
                k,
                self.sequence.loose_vertices,
            )?;
            self.previous = Some(end);
            Ok((k, step))
        })();
        if result.is_err() {
            self.next = self.sequence.steps(); // stop after the first error
        }
        Some(result)
    }
}

/// One step of a sequence as plain data, read by [`Sequence::load`]: the positions of both
/// frames, the triangles of the second, and the parents of the vertices new in the second.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepFrames {
    /// The step's index in the sequence (its first frame's rank, from 0).
    pub index: usize,
    /// Positions of frame `k` (t=0): possibly fewer than `x1` (a topology change appends
    /// vertices).
    pub x0: Vec<[f64; 3]>,
    /// Positions of frame `k + 1` (t=1).
    pub x1: Vec<[f64; 3]>,
    /// Triangles of frame `k + 1`, used over the whole step.
    pub triangles: Vec<[u32; 3]>,
    /// Free edges of frame `k + 1` ([`Mesh::edges`]), used over the whole step (see
    /// [`with_file_edges`]).
    pub edges: Vec<[u32; 2]>,
    /// `[child, parent]` rows of frame `k + 1`'s parents file: `x0.len() <= child < x1.len()`,
    /// `parent < x0.len()`, each child at most once. Empty without a parents file.
    pub parents: Vec<[u32; 2]>,
    /// The map from `triangles` to the faces of frame `k + 1`'s file (see
    /// [`Mesh::face_origin`]); `None` when triangle `t` is face `t`.
    pub face_origin: Option<Vec<FaceOrigin>>,
    /// What the readers noted about either frame (see [`Mesh::notes`]), with the file.
    pub notes: Vec<(PathBuf, MeshNote)>,
    /// Frame `k`'s file.
    pub start: PathBuf,
    /// Frame `k + 1`'s file.
    pub end: PathBuf,
}

impl StepFrames {
    /// Step `index` from two frames read already: checks that the vertex count does not shrink
    /// and reads `parents_file` (if any: see [`parse_parents`] for its format). This is also
    /// the way to build one step from two files and a parents file outside a sequence folder.
    pub fn new(
        index: usize,
        start: Mesh,
        end: Mesh,
        start_path: &Path,
        end_path: &Path,
        parents_file: Option<&Path>,
    ) -> Result<Self, SequenceError> {
        let (n0, n1) = (start.positions.len(), end.positions.len());
        if n1 < n0 {
            return Err(SequenceError::Shrinks {
                path: end_path.to_path_buf(),
                vertices: n1,
                previous: n0,
            });
        }
        let parents = match parents_file {
            Some(file) => read_parents(file, n0, n1)?
                .into_iter()
                .map(|(child, parent)| [child, parent])
                .collect(),
            None => Vec::new(),
        };
        let notes = (start
            .notes
            .into_iter()
            .map(|n| (start_path.to_path_buf(), n)))
        .chain(end.notes.into_iter().map(|n| (end_path.to_path_buf(), n)))
        .collect();
        Ok(Self {
            index,
            x0: start.positions,
            x1: end.positions,
            triangles: end.triangles,
            edges: end.edges,
            parents,
            face_origin: end.face_origin,
            notes,
            start: start_path.to_path_buf(),
            end: end_path.to_path_buf(),
        })
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
    step_between_loose(start, end, end_path, k, LooseVertices::Points)
}

/// [`step_between`], the loose vertices read as `loose` says ([`with_file_primitives`]).
pub fn step_between_loose(
    start: &Mesh,
    end: &Mesh,
    end_path: &Path,
    k: usize,
    loose: LooseVertices,
) -> Result<Step<'static>, SequenceError> {
    let (n0, n1) = (start.positions.len(), end.positions.len());
    let parents_file = parents_path(end_path);
    // (A shrinking vertex count is reported by `step_from_frames`.)
    let parents = if n1 >= n0 && parents_file.exists() {
        read_parents(&parents_file, n0, n1)?
    } else {
        Vec::new()
    };
    step_from_frames_loose(start, end, &parents, end_path, k, loose)
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
    step_from_frames_loose(start, end, parents, end_path, k, LooseVertices::Points)
}

/// [`step_from_frames`], the loose vertices read as `loose` says ([`with_file_primitives`]).
pub fn step_from_frames_loose(
    start: &Mesh,
    end: &Mesh,
    parents: &[(u32, u32)],
    end_path: &Path,
    k: usize,
    loose: LooseVertices,
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
    .and_then(|step| with_file_primitives(step, &end.edges, loose))
    .map_err(|source| SequenceError::Step {
        step: k,
        path: end_path.to_path_buf(),
        source,
    })
}

/// `step` with the free edges of a frame file (`end`'s: PLY `edge` elements, OBJ `l` lines)
/// and its loose vertices as free points: [`with_file_primitives`] with the default rule
/// ([`LooseVertices::Points`]).
pub fn with_file_edges(
    step: Step<'static>,
    edges: &[[u32; 2]],
) -> Result<Step<'static>, StepError> {
    with_file_primitives(step, edges, LooseVertices::Points)
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
