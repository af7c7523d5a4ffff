//! The shared whole-step scenes (`shared/data/scenes/<scene>`): their two frame files, and the
//! ground truth of the step (the touching vertex-face and edge-edge pairs), mapped from the
//! data's single id space to vertex, edge and face numbers.

use super::{read_ply, IoError};
use std::path::{Path, PathBuf};

/// The frame files of one step of a scene: positions at t=0 and at t=1.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneFrames {
    /// The lower-numbered frame: positions at t=0 (and the faces of the step).
    pub t0: PathBuf,
    /// The higher-numbered frame: positions at t=1.
    pub t1: PathBuf,
}

/// The number at the end of a frame file's stem (`cloth_ball92.ply` gives 92, `227.ply` gives
/// 227), or `None` if the stem does not end in a digit or the number overflows.
///
/// ```
/// use std::path::Path;
/// use topoccd::io::frame_number;
/// assert_eq!(frame_number(Path::new("frames/cloth_ball92.ply")), Some(92));
/// assert_eq!(frame_number(Path::new("227.ply")), Some(227));
/// assert_eq!(frame_number(Path::new("mesh.ply")), None);
/// ```
pub fn frame_number(path: &Path) -> Option<u64> {
    let stem = path.file_stem()?.to_str()?;
    let digits = stem.len() - stem.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    stem[stem.len() - digits..].parse().ok()
}

/// Finds the two frame files of a scene: the `.ply` files of `<scene_dir>/frames`, ordered by
/// the number that ends their names (see [`frame_number`]), so that `t0` is the lower one.
/// Exactly two `.ply` files with distinct numbers must be there.
///
/// ```no_run
/// use std::path::Path;
/// use topoccd::io::{read_ply, scene_frames};
/// let frames = scene_frames(Path::new("../../shared/data/scenes/cloth-ball"))?;
/// assert!(frames.t0.ends_with("cloth_ball92.ply") && frames.t1.ends_with("cloth_ball93.ply"));
/// let (start, end) = (read_ply(&frames.t0)?, read_ply(&frames.t1)?);
/// # Ok::<(), topoccd::io::IoError>(())
/// ```
pub fn scene_frames(scene_dir: &Path) -> Result<SceneFrames, IoError> {
    let dir = scene_dir.join("frames");
    let entries = std::fs::read_dir(&dir).map_err(|e| IoError::os(&dir, "list", e))?;
    let mut frames = Vec::new();
    for entry in entries {
        let path = entry.map_err(|e| IoError::os(&dir, "list", e))?.path();
        let is_ply = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("ply"));
        if !is_ply {
            continue;
        }
        let number = frame_number(&path).ok_or_else(|| IoError::SceneLayout {
            path: path.clone(),
            message: "a frame file name must end in its frame number".into(),
        })?;
        frames.push((number, path));
    }
    frames.sort();
    match frames.as_slice() {
        [(n0, t0), (n1, t1)] if n0 != n1 => Ok(SceneFrames {
            t0: t0.clone(),
            t1: t1.clone(),
        }),
        [(n, _), (_, _)] => Err(IoError::SceneLayout {
            path: dir,
            message: format!("both .ply files carry the frame number {n}"),
        }),
        _ => Err(IoError::SceneLayout {
            path: dir,
            message: format!("expected two .ply frame files, found {}", frames.len()),
        }),
    }
}

/// Two edges, each as `[i, j]` with `i < j` (vertex ids).
pub type EdgePair = ([u32; 2], [u32; 2]);

/// The exact ground truth of one step of a shared scene.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SceneTruth {
    /// Number of vertices of the t=0 frame.
    pub vertices: usize,
    /// Number of faces of the t=0 frame.
    pub faces: usize,
    /// The edges in libigl order (see [`libigl_edges`]): edge `k` of the data is `edges[k]`.
    pub edges: Vec<[u32; 2]>,
    /// The touching (vertex, face) pairs, in the order of the data files.
    pub vf: Vec<(u32, u32)>,
    /// The touching edge pairs, in the order of the data files; each edge as `[i, j]` with
    /// `i < j` (vertex ids), the two edges ordered so that the first is lexicographically less.
    pub ee: Vec<([u32; 2], [u32; 2])>,
    /// Number of vertex-face candidate pairs in the data (touching or not).
    pub vf_candidates: usize,
    /// Number of edge-edge candidate pairs in the data (touching or not).
    pub ee_candidates: usize,
    /// Every vertex-face candidate pair `(vertex, face)` in file order, with its exact answer.
    pub vf_all: Vec<((u32, u32), bool)>,
    /// Every edge-edge candidate pair in file order (edges as in [`SceneTruth::ee`], not
    /// reordered), with its exact answer.
    pub ee_all: Vec<(EdgePair, bool)>,
}

/// Every undirected edge of `triangles` once, as `[i, j]` with `i < j`, sorted by `j` and then
/// by `i`: the order of libigl's `igl::edges`, which numbers the edges of the shared scenes.
///
/// ```
/// use topoccd::io::libigl_edges;
/// assert_eq!(
///     libigl_edges(&[[0, 1, 2], [2, 1, 3]]),
///     vec![[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]]
/// );
/// assert_eq!(libigl_edges(&[[3, 0, 1]]), vec![[0, 1], [0, 3], [1, 3]]);
/// ```
pub fn libigl_edges(triangles: &[[u32; 3]]) -> Vec<[u32; 2]> {
    let mut edges: Vec<[u32; 2]> = triangles
        .iter()
        .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable_by_key(|&[i, j]| (j, i));
    edges.dedup();
    edges
}

/// Reads the ground truth of one step of a shared scene directory: the faces of the t=0 frame
/// (`frames/*.ply`, see [`scene_frames`]), the candidate pairs `boxes/<a>vf.json` and
/// `boxes/<a>ee.json` and their exact answers `mma_bool/<a>vf_mma_bool.json` and
/// `mma_bool/<a>ee_mma_bool.json`, where `<a>` is the number of the t=0 frame.
///
/// Every candidate pair is checked (touching or not): the pair and answer counts must agree, a
/// vertex-face pair must be `[vertex id, face id]` and an edge-edge pair two distinct edge ids,
/// all in range of the id scheme (vertices, then edges in libigl order, then faces).
///
/// ```no_run
/// use std::path::Path;
/// let truth = topoccd::io::read_scene_truth(Path::new("../../shared/data/scenes/cloth-funnel"))?;
/// assert_eq!((truth.vf.len(), truth.ee.len()), (27, 107));
/// # Ok::<(), topoccd::io::IoError>(())
/// ```
pub fn read_scene_truth(scene_dir: &Path) -> Result<SceneTruth, IoError> {
    let frames = scene_frames(scene_dir)?;
    let step = frame_number(&frames.t0).ok_or_else(|| IoError::SceneLayout {
        path: frames.t0.clone(),
        message: "a frame file name must end in its frame number".into(),
    })?;
    let mesh = read_ply(&frames.t0)?;
    let edges = libigl_edges(&mesh.triangles);
    let ids = IdScheme {
        vertices: mesh.positions.len() as u64,
        edges: edges.len() as u64,
        faces: mesh.triangles.len() as u64,
    };

    let boxes = scene_dir.join("boxes");
    let answers = scene_dir.join("mma_bool");
    let vf_candidates = read_pairs(
        boxes.join(format!("{step}vf.json")),
        answers.join(format!("{step}vf_mma_bool.json")),
        |pair| ids.vertex_face(pair),
    )?;
    let ee_candidates = read_pairs(
        boxes.join(format!("{step}ee.json")),
        answers.join(format!("{step}ee_mma_bool.json")),
        |pair| ids.edge_edge(pair),
    )?;

    let vf = touching(&vf_candidates);
    let ee = touching(&ee_candidates)
        .into_iter()
        .map(|(a, b)| {
            let (ea, eb) = (edges[a as usize], edges[b as usize]);
            (ea.min(eb), ea.max(eb))
        })
        .collect();
    let ee_all = ee_candidates
        .iter()
        .map(|&((a, b), touch)| ((edges[a as usize], edges[b as usize]), touch))
        .collect();
    Ok(SceneTruth {
        vf_all: vf_candidates.clone(),
        ee_all,
        vertices: mesh.positions.len(),
        faces: mesh.triangles.len(),
        edges,
        vf,
        ee,
        vf_candidates: vf_candidates.len(),
        ee_candidates: ee_candidates.len(),
    })
}

/// A candidate pair as two feature numbers, and whether it touches.
type Candidate = ((u32, u32), bool);

/// The pairs whose answer is `true`.
fn touching(candidates: &[Candidate]) -> Vec<(u32, u32)> {
    candidates
        .iter()
        .filter_map(|&(pair, touch)| touch.then_some(pair))
        .collect()
}

/// Reads a pair file and its answer file; `map` turns the ids of a pair into feature numbers or
/// says what is wrong with them.
fn read_pairs(
    pairs_path: PathBuf,
    bools_path: PathBuf,
    map: impl Fn([u64; 2]) -> Result<(u32, u32), String>,
) -> Result<Vec<Candidate>, IoError> {
    let pairs: Vec<[u64; 2]> = read_json(&pairs_path, |b| serde_json::from_slice(b))?;
    let bools: Vec<bool> = read_json(&bools_path, |b| serde_json::from_slice(b))?;
    if pairs.len() != bools.len() {
        return Err(IoError::CountMismatch {
            pairs: pairs.len(),
            bools: bools.len(),
            pairs_path,
            bools_path,
        });
    }
    pairs
        .iter()
        .zip(bools)
        .enumerate()
        .map(|(pair, (&ids, touch))| {
            map(ids)
                .map(|features| (features, touch))
                .map_err(|message| IoError::BadPair {
                    path: pairs_path.clone(),
                    pair,
                    ids,
                    message,
                })
        })
        .collect()
}

/// Reads a JSON file with `parse` (`serde_json::from_slice` at a concrete type).
fn read_json<T>(
    path: &Path,
    parse: impl FnOnce(&[u8]) -> serde_json::Result<T>,
) -> Result<T, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::os(path, "read", e))?;
    parse(&bytes).map_err(|source| IoError::Json {
        path: path.to_path_buf(),
        line: source.line(),
        source,
    })
}

/// The single id space of the data: vertices `[0, nV)`, then edges `[nV, nV+nE)`, then faces
/// `[nV+nE, nV+nE+nF)`.
struct IdScheme {
    vertices: u64,
    edges: u64,
    faces: u64,
}

impl IdScheme {
    fn vertex(&self, id: u64) -> Option<u32> {
        (id < self.vertices).then(|| u32::try_from(id).ok())?
    }

    fn edge(&self, id: u64) -> Option<u32> {
        let e = id.checked_sub(self.vertices)?;
        (e < self.edges).then(|| u32::try_from(e).ok())?
    }

    fn face(&self, id: u64) -> Option<u32> {
        let f = id.checked_sub(self.vertices + self.edges)?;
        (f < self.faces).then(|| u32::try_from(f).ok())?
    }

    /// What an id names, for error messages.
    fn kind(&self, id: u64) -> &'static str {
        if self.vertex(id).is_some() {
            "vertex"
        } else if self.edge(id).is_some() {
            "edge"
        } else if self.face(id).is_some() {
            "face"
        } else {
            "out of range"
        }
    }

    fn ranges(&self) -> String {
        let (v, e, f) = (self.vertices, self.edges, self.faces);
        format!(
            "vertex ids are [0, {v}), edge ids [{v}, {}), face ids [{}, {})",
            v + e,
            v + e,
            v + e + f
        )
    }

    fn vertex_face(&self, [a, b]: [u64; 2]) -> Result<(u32, u32), String> {
        match (self.vertex(a), self.face(b)) {
            (Some(v), Some(f)) => Ok((v, f)),
            _ => Err(format!(
                "expected [vertex, face], found [{}, {}] ({})",
                self.kind(a),
                self.kind(b),
                self.ranges()
            )),
        }
    }

    fn edge_edge(&self, [a, b]: [u64; 2]) -> Result<(u32, u32), String> {
        match (self.edge(a), self.edge(b)) {
            (Some(ea), Some(eb)) if ea != eb => Ok((ea, eb)),
            (Some(_), Some(_)) => Err("an edge paired with itself".into()),
            _ => Err(format!(
                "expected [edge, edge], found [{}, {}] ({})",
                self.kind(a),
                self.kind(b),
                self.ranges()
            )),
        }
    }
}
