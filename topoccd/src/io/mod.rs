//! File formats: PLY and OBJ meshes, the query CSV files, the ground truth of the shared data.

pub mod queries;
