//! The in-memory triangle mesh of the file formats, and reading or writing one by extension.

use super::{read_obj, read_ply, read_stl, write_obj, write_ply, IoError};
use std::fmt;
use std::path::Path;

/// A triangle mesh as read from a file: positions and triangles, in the order of the file.
/// Nothing is validated beyond what the format needs (indices in range, at least three vertices
/// per face); [`Step::new`](crate::Step::new) checks the rest (finite coordinates,
/// repeated vertices).
///
/// Polygons of more than three vertices (OBJ and PLY faces) and PLY triangle strips are split
/// into triangles; [`Mesh::face_origin`] then maps each triangle back to the face of the file
/// it came from, so that a contact can name the face a user knows.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions `[x, y, z]`; vertex `i` is `positions[i]`.
    pub positions: Vec<[f64; 3]>,
    /// Triangles as 0-based vertex indices, in the order of the file.
    pub triangles: Vec<[u32; 3]>,
    /// Edges that belong to no face, as 0-based vertex index pairs in the order of the file
    /// (PLY `edge` elements with `vertex1` and `vertex2`, OBJ `l` polylines split into their
    /// segments): rods, hair, yarn. Give them to [`Step::with_edges`](crate::Step::with_edges);
    /// vertices in no triangle and no edge are then free points.
    pub edges: Vec<[u32; 2]>,
    /// `None` when triangle `t` is face `t` of the file (every face was a triangle); otherwise
    /// `face_origin[t]` names the face of the file that triangle `t` belongs to (same length as
    /// [`Mesh::triangles`]). See [`Mesh::origin`].
    pub face_origin: Option<Vec<FaceOrigin>>,
    /// What the reader did beyond reading (polygons split, statements skipped, ...), for a
    /// caller to show; empty for a plain triangle mesh.
    pub notes: Vec<MeshNote>,
}

/// Where a triangle of a [`Mesh`] comes from: the face of the file (0-based, counted in file
/// order) and the triangle's rank among the triangles that face was split into (0 for a face
/// that was a triangle already).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FaceOrigin {
    /// The face of the file: OBJ `f` statements counted from 0; PLY records of the `face` and
    /// `tristrips` elements counted from 0 in file order (a strip record is one face).
    pub face: u32,
    /// The triangle's rank within its face, from 0.
    pub sub: u32,
}

/// Something a reader did that changes the mesh from what the file literally says, or that a
/// user should know. `Display` gives one plain sentence.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MeshNote {
    /// Polygons of more than three vertices were split into triangles: convex ones as a fan
    /// from their first vertex, non-convex ones by ear clipping (see
    /// [`triangulate_polygon`](super::triangulate_polygon)).
    Triangulated {
        /// Polygons split.
        polygons: usize,
        /// Of these, the non-convex ones (ear clipping).
        non_convex: usize,
        /// Of these, polygons that ear clipping could not split cleanly (self-intersecting,
        /// folded or without area): the remainder was split as a fan.
        irregular: usize,
        /// The first irregular polygon (its face number), if any.
        first_irregular: Option<u32>,
        /// Triangles made from the polygons.
        triangles: usize,
    },
    /// Triangle strips (a PLY `tristrips` element) were decoded into triangles.
    Strips {
        /// Strip records.
        records: usize,
        /// Triangles made.
        triangles: usize,
        /// Triangles with a repeated vertex (stitches between strips), dropped.
        degenerate: usize,
    },
    /// OBJ statements that carry no triangles (`l` polylines, `p` points) were skipped.
    Skipped {
        /// The statement's keyword.
        keyword: String,
        /// How many.
        count: usize,
        /// The line of the first one, 1-based.
        first_line: usize,
    },
    /// An STL triangle soup was welded: corners with identical coordinates became one vertex.
    Welded {
        /// Triangle corners in the file (three per triangle).
        corners: usize,
        /// Vertices after welding.
        vertices: usize,
        /// Facets dropped because two of their corners are identical.
        dropped: usize,
    },
    /// Coincident vertices were merged by [`weld`](super::weld).
    Merged {
        /// Vertices removed (merged into another).
        removed: usize,
        /// Triangles dropped because two of their corners became one vertex, by their index
        /// before welding.
        dropped: Vec<u32>,
    },
}

impl fmt::Display for MeshNote {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshNote::Triangulated {
                polygons,
                non_convex,
                irregular,
                first_irregular,
                triangles,
            } => {
                write!(
                    f,
                    "{polygons} polygon(s) with more than 3 vertices split into {triangles} \
                     triangles ({non_convex} non-convex, by ear clipping)"
                )?;
                if let Some(face) = first_irregular {
                    write!(
                        f,
                        "; {irregular} could not be split cleanly (self-intersecting or without \
                         area; the first is face {face}) and were split as a fan"
                    )?;
                }
                Ok(())
            }
            MeshNote::Strips {
                records,
                triangles,
                degenerate,
            } => write!(
                f,
                "{records} triangle strip(s) decoded into {triangles} triangles \
                 ({degenerate} degenerate stitching triangles dropped)"
            ),
            MeshNote::Skipped {
                keyword,
                count,
                first_line,
            } => write!(
                f,
                "{count} '{keyword}' statement(s) skipped (they carry no triangles; the first is \
                 on line {first_line})"
            ),
            MeshNote::Welded {
                corners,
                vertices,
                dropped,
            } => write!(
                f,
                "{corners} triangle corners welded into {vertices} vertices (identical \
                 coordinates); {dropped} facet(s) with two identical corners dropped"
            ),
            MeshNote::Merged { removed, dropped } => write!(
                f,
                "{removed} coincident vertices merged; {} triangle(s) became degenerate and were \
                 dropped",
                dropped.len()
            ),
        }
    }
}

impl Mesh {
    /// A mesh of these positions and triangles, with no face map and no notes.
    ///
    /// ```
    /// use topoccd::io::Mesh;
    /// let mesh = Mesh::new(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]);
    /// assert_eq!(mesh.origin(0).face, 0);
    /// ```
    pub fn new(positions: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Self {
        Self {
            positions,
            triangles,
            edges: Vec::new(),
            face_origin: None,
            notes: Vec::new(),
        }
    }

    /// The face of the file that triangle `t` comes from (see [`Mesh::face_origin`]).
    ///
    /// ```
    /// use std::path::Path;
    /// use topoccd::io::{read_obj_from, FaceOrigin};
    /// let quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 2 3 4\n";
    /// let mesh = read_obj_from(quad.as_bytes(), Path::new("quad.obj"))?;
    /// assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 1, 2], [0, 2, 3]]);
    /// assert_eq!(mesh.origin(2), FaceOrigin { face: 1, sub: 1 });
    /// # Ok::<(), topoccd::io::IoError>(())
    /// ```
    pub fn origin(&self, t: usize) -> FaceOrigin {
        match &self.face_origin {
            Some(map) => map[t],
            None => FaceOrigin {
                face: t as u32,
                sub: 0,
            },
        }
    }
}

/// The mesh file formats this crate reads and writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Stanford PLY: ASCII or binary (either byte order) on reading; binary little-endian with
    /// `double` coordinates on writing.
    Ply,
    /// Wavefront OBJ (text); `v`, `f` and `l` statements carry data.
    Obj,
    /// STL, ASCII or binary (read only): a triangle soup, welded on reading.
    Stl,
}

impl MeshFormat {
    /// The format named by the extension of `path` (`.ply`, `.obj` or `.stl`,
    /// case-insensitive).
    ///
    /// ```
    /// use std::path::Path;
    /// use topoccd::io::{IoError, MeshFormat};
    /// assert_eq!(MeshFormat::of_path(Path::new("a/b.PLY"))?, MeshFormat::Ply);
    /// assert_eq!(MeshFormat::of_path(Path::new("frame.obj"))?, MeshFormat::Obj);
    /// assert_eq!(MeshFormat::of_path(Path::new("part.stl"))?, MeshFormat::Stl);
    /// assert!(matches!(
    ///     MeshFormat::of_path(Path::new("mesh.off")),
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
            Some("stl") => Ok(MeshFormat::Stl),
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
/// let mesh = Mesh::new(
///     vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.1]],
///     vec![[0, 1, 2]],
/// );
/// let path = std::env::temp_dir().join(format!("topoccd-doc-read-mesh-{}.ply", std::process::id()));
/// write_mesh(&path, &mesh)?;
/// assert_eq!(read_mesh(&path)?, mesh);
/// std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_mesh(path: &Path) -> Result<Mesh, IoError> {
    not_a_folder(path)?;
    match MeshFormat::of_path(path)? {
        MeshFormat::Ply => read_ply(path),
        MeshFormat::Obj => read_obj(path),
        MeshFormat::Stl => read_stl(path),
    }
}

/// Refuses a folder given where a mesh file is expected ([`IoError::Folder`]).
pub(crate) fn not_a_folder(path: &Path) -> Result<(), IoError> {
    if path.is_dir() {
        return Err(IoError::Folder {
            path: path.to_path_buf(),
        });
    }
    Ok(())
}

/// Writes a mesh, choosing the format by the extension of `path`: `.ply` is written as binary
/// little-endian with `double` coordinates, `.obj` as text. Both round-trip exactly through
/// [`read_mesh`] (the face map and notes of a [`Mesh`] are not written). `.stl` is refused.
///
/// ```
/// use topoccd::io::{read_mesh, write_mesh, Mesh};
/// let mesh = Mesh::new(
///     vec![[0.0; 3], [1.0, 0.0, 0.0], [0.1, 0.2, 1.0 / 3.0]],
///     vec![[2, 1, 0]],
/// );
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
        MeshFormat::Stl => Err(IoError::Unrepresentable {
            path: path.to_path_buf(),
            message: "STL is read only (it would round the coordinates to f32 and lose the \
                      vertex ids); write .ply or .obj"
                .into(),
        }),
    }
}
