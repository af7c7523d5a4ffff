//! The in-memory triangle mesh of the file formats, and reading or writing one by extension.

use super::{read_obj, read_ply, write_obj, write_ply, IoError};
use std::path::Path;

/// A triangle mesh as stored in a file: positions and triangles, in the order of the file.
/// Nothing is validated beyond what the format needs (indices in range, three vertices per
/// face); [`Step::new`](crate::step::Step::new) checks the rest (finite coordinates, repeated
/// vertices).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions `[x, y, z]`; vertex `i` is `positions[i]`.
    pub positions: Vec<[f64; 3]>,
    /// Triangles as 0-based vertex indices, in the order of the file (face numbering).
    pub triangles: Vec<[u32; 3]>,
}

/// The mesh file formats this crate reads and writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Stanford PLY: ASCII or binary (either byte order) on reading; binary little-endian with
    /// `double` coordinates on writing.
    Ply,
    /// Wavefront OBJ (text); only `v` and `f` statements carry data.
    Obj,
}

impl MeshFormat {
    /// The format named by the extension of `path` (`.ply` or `.obj`, case-insensitive).
    ///
    /// ```
    /// use std::path::Path;
    /// use topoccd::io::{IoError, MeshFormat};
    /// assert_eq!(MeshFormat::of_path(Path::new("a/b.PLY"))?, MeshFormat::Ply);
    /// assert_eq!(MeshFormat::of_path(Path::new("frame.obj"))?, MeshFormat::Obj);
    /// assert!(matches!(
    ///     MeshFormat::of_path(Path::new("mesh.stl")),
    ///     Err(IoError::UnknownFormat { .. })
    /// ));
    /// # Ok::<(), IoError>(())
    /// ```
    pub fn of_path(path: &Path) -> Result<Self, IoError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("ply") => Ok(MeshFormat::Ply),
            Some("obj") => Ok(MeshFormat::Obj),
            _ => Err(IoError::UnknownFormat {
                path: path.to_path_buf(),
            }),
        }
    }
}

/// Reads a mesh, choosing the format by the extension of `path` (see [`MeshFormat::of_path`]).
///
/// ```
/// use topoccd::io::{read_mesh, write_mesh, Mesh};
/// let mesh = Mesh {
///     positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.1]],
///     triangles: vec![[0, 1, 2]],
/// };
/// let path = std::env::temp_dir().join(format!("topoccd-doc-read-mesh-{}.ply", std::process::id()));
/// write_mesh(&path, &mesh)?;
/// assert_eq!(read_mesh(&path)?, mesh);
/// std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_mesh(path: &Path) -> Result<Mesh, IoError> {
    match MeshFormat::of_path(path)? {
        MeshFormat::Ply => read_ply(path),
        MeshFormat::Obj => read_obj(path),
    }
}

/// Writes a mesh, choosing the format by the extension of `path`: `.ply` is written as binary
/// little-endian with `double` coordinates, `.obj` as text. Both round-trip exactly through
/// [`read_mesh`].
///
/// ```
/// use topoccd::io::{read_mesh, write_mesh, Mesh};
/// let mesh = Mesh {
///     positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.1, 0.2, 1.0 / 3.0]],
///     triangles: vec![[2, 1, 0]],
/// };
/// let path = std::env::temp_dir().join(format!("topoccd-doc-write-mesh-{}.obj", std::process::id()));
/// write_mesh(&path, &mesh)?;
/// assert_eq!(read_mesh(&path)?, mesh);
/// std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_mesh(path: &Path, mesh: &Mesh) -> Result<(), IoError> {
    match MeshFormat::of_path(path)? {
        MeshFormat::Ply => write_ply(path, mesh),
        MeshFormat::Obj => write_obj(path, mesh),
    }
}
