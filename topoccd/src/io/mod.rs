//! File formats: PLY, OBJ and STL meshes, the query CSV files, the ground truth of the shared
//! data.
//!
//! - [`read_mesh`] / [`write_mesh`] choose PLY, OBJ (or STL, read only) by the file extension;
//!   [`read_ply`], [`read_obj`], [`read_stl`], [`write_ply`], [`write_obj`] name the format, and
//!   the `*_from` / `*_to` variants work on any reader or writer. Polygons and triangle strips
//!   are split into triangles ([`triangulate_polygon`]), with a map back to the file's faces
//!   ([`Mesh::face_origin`]) and notes on what was done ([`Mesh::notes`]).
//! - [`coincident_vertices`] finds duplicate vertices at one position (seams, poles), which
//!   touch at t=0; [`weld`] merges them. [`input_warnings`] finds those, zero-area triangles
//!   and positions cast to integers, for a front end to warn about before a query.
//! - With the feature `internals`: `queries` reads the narrow-phase query files (exact
//!   rationals and ground truth), `scene_frames` and `read_scene_truth` the whole-step scenes
//!   of the shared data, and `MemoryEstimate` refuses a step too large for memory up front.
//! - [`sequence`] reads and writes frame sequences (`0000.ply`, `0001.ply`, ... and `.parents`).
//! - [`with_file_primitives`]: what a file holds besides its triangles (free edges, and its
//!   loose vertices as free points unless [`LooseVertices::Ignore`]), the one rule of every
//!   reader and command.
//! - [`read_ply_header`] gives a PLY file's counts before reading it.
//! - Every error is an [`IoError`] that names the file, and the line (text formats) or the
//!   element (binary PLY) where reading stopped.

internal!(limits, queries, scene);

mod degenerate;
mod error;
mod faces;
mod lines;
mod mesh;
mod obj;
mod ply_elements;
mod ply_read;
mod ply_write;
mod polygon;
mod primitives;
pub mod sequence;
mod stl;
mod weld;

pub use degenerate::{input_warnings, InputWarning};
pub use error::{IoError, Location};
#[cfg(feature = "internals")]
pub use limits::{
    available_memory, Bytes, MemoryEstimate, TooLarge, BASE_BYTES, BYTES_PER_TRIANGLE,
    BYTES_PER_VERTEX,
};
pub use mesh::{read_mesh, write_mesh, FaceOrigin, Mesh, MeshFormat, MeshNote};
pub use obj::{read_obj, read_obj_from, write_obj, write_obj_to};
pub use ply_read::{read_ply, read_ply_from, read_ply_header, PlyCounts};
pub use ply_write::{write_ply, write_ply_to};
pub use polygon::{triangulate_polygon, PolygonSplit};
pub use primitives::{
    loose_vertices, with_file_primitives, FilePrimitives, LooseVertices, UnknownLooseVertices,
};
#[cfg(feature = "internals")]
pub use scene::{
    frame_number, libigl_edges, read_scene_truth, scene_frames, EdgePair, SceneFrames, SceneTruth,
};
pub use stl::{read_stl, read_stl_from};
pub use weld::{apply_weld, coincident_vertices, weld, weld_frames, WeldedFrames};
