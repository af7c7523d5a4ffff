//! The two frames of a shared whole-step scene: `<scene>/frames/<name><number>.ply`.

use super::IoError;
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
