//! File formats: PLY and OBJ meshes, the query CSV files, the ground truth of the shared data.
//!
//! - [`read_mesh`] / [`write_mesh`] choose PLY or OBJ by the file extension; [`read_ply`],
//!   [`read_obj`], [`write_ply`], [`write_obj`] name the format, and the `*_from` / `*_to`
//!   variants work on any reader or writer.
//! - [`queries`] reads the narrow-phase query files (exact rationals and ground truth).
//! - [`sequence`] reads and writes frame sequences (`0000.ply`, `0001.ply`, ... and `.parents`).
//! - [`scene_frames`] and [`read_scene_truth`] read the whole-step scenes of the shared data.
//! - [`MemoryEstimate`] and [`available_memory`] let a caller refuse a step too large for
//!   memory before reading it ([`read_ply_header`] gives a PLY file's counts).
//! - Every error is an [`IoError`] that names the file, and the line (text formats) or the
//!   element (binary PLY) where reading stopped.

mod error;
mod limits;
mod mesh;
mod obj;
mod ply_elements;
mod ply_read;
mod ply_write;
pub mod queries;
mod scene;
pub mod sequence;

pub use error::{IoError, Location};
pub use limits::{
    available_memory, Bytes, MemoryEstimate, TooLarge, BASE_BYTES, BYTES_PER_TRIANGLE,
    BYTES_PER_VERTEX,
};
pub use mesh::{read_mesh, write_mesh, Mesh, MeshFormat};
pub use obj::{read_obj, read_obj_from, write_obj, write_obj_to};
pub use ply_read::{read_ply, read_ply_from, read_ply_header, PlyCounts};
pub use ply_write::{write_ply, write_ply_to};
pub use scene::{
    frame_number, libigl_edges, read_scene_truth, scene_frames, EdgePair, SceneFrames, SceneTruth,
};
