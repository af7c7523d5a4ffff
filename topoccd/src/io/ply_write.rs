//! Writing PLY meshes: binary little-endian, `double` coordinates, `uchar int` index lists.

use super::{IoError, Mesh};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Writes a mesh as binary little-endian PLY with `double x, y, z` and a face list
/// `uchar int vertex_indices`. Reading it back with [`read_ply`](super::read_ply) gives the same
/// positions bit for bit and the same triangles.
///
/// ```
/// use topoccd::io::{read_ply, write_ply, Mesh};
/// let mesh = Mesh::new(
///     vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 0.1, -0.3]],
///     vec![[0, 2, 1]],
/// );
/// let path = std::env::temp_dir().join(format!("topoccd-doc-write-ply-{}.ply", std::process::id()));
/// write_ply(&path, &mesh)?;
/// assert_eq!(read_ply(&path)?, mesh);
/// std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_ply(path: &Path, mesh: &Mesh) -> Result<(), IoError> {
    check_indices(mesh, path)?;
    let file = File::create(path).map_err(|e| IoError::os(path, "create", e))?;
    write_ply_to(file, mesh, path)
}

/// Writes a mesh as binary little-endian PLY (see [`write_ply`]) to any writer; `name` is the
/// file name used in error messages.
///
/// ```
/// use std::path::Path;
/// use topoccd::io::{read_ply_from, write_ply_to, Mesh};
/// let mesh = Mesh::new(vec![[1.0; 3]; 3], vec![[0, 1, 2]]);
/// let mut bytes = Vec::new();
/// write_ply_to(&mut bytes, &mesh, Path::new("memory.ply"))?;
/// assert!(bytes.starts_with(b"ply\nformat binary_little_endian 1.0\n"));
/// assert_eq!(read_ply_from(bytes.as_slice(), Path::new("memory.ply"))?, mesh);
/// # Ok::<(), topoccd::io::IoError>(())
/// ```
pub fn write_ply_to(output: impl Write, mesh: &Mesh, name: &Path) -> Result<(), IoError> {
    check_indices(mesh, name)?;
    let mut out = BufWriter::with_capacity(1 << 16, output);
    let header = format!(
        "ply\n\
         format binary_little_endian 1.0\n\
         comment written by topoccd\n\
         element vertex {}\n\
         property double x\n\
         property double y\n\
         property double z\n\
         element face {}\n\
         property list uchar int vertex_indices\n\
         {}end_header\n",
        mesh.positions.len(),
        mesh.triangles.len(),
        if mesh.edges.is_empty() {
            String::new()
        } else {
            format!(
                "element edge {}\nproperty int vertex1\nproperty int vertex2\n",
                mesh.edges.len()
            )
        }
    );
    let write_error = |e| IoError::os(name, "write", e);
    out.write_all(header.as_bytes()).map_err(write_error)?;
    for p in &mesh.positions {
        let mut record = [0u8; 24];
        for (chunk, c) in record.chunks_exact_mut(8).zip(p) {
            chunk.copy_from_slice(&c.to_le_bytes());
        }
        out.write_all(&record).map_err(write_error)?;
    }
    for triangle in &mesh.triangles {
        let mut record = [3u8; 13];
        for (chunk, &i) in record[1..].chunks_exact_mut(4).zip(triangle) {
            // `check_indices` guarantees that every index fits in an `int`.
            chunk.copy_from_slice(&i.to_le_bytes());
        }
        out.write_all(&record).map_err(write_error)?;
    }
    for &[a, b] in &mesh.edges {
        let mut record = [0u8; 8];
        record[..4].copy_from_slice(&a.to_le_bytes());
        record[4..].copy_from_slice(&b.to_le_bytes());
        out.write_all(&record).map_err(write_error)?;
    }
    out.flush().map_err(write_error)
}

/// PLY `int` indices are signed 32-bit: refuse larger ones before writing anything.
fn check_indices(mesh: &Mesh, name: &Path) -> Result<(), IoError> {
    let limit = i32::MAX as u32;
    match mesh
        .triangles
        .iter()
        .enumerate()
        .find_map(|(t, tri)| tri.iter().find(|&&i| i > limit).map(|&i| (t, i)))
    {
        Some((triangle, index)) => Err(IoError::Unrepresentable {
            path: name.to_path_buf(),
            message: format!(
                "triangle {triangle} has vertex index {index}, more than a PLY int can hold"
            ),
        }),
        None => match mesh.edges.iter().position(|e| e.iter().any(|&i| i > limit)) {
            Some(edge) => Err(IoError::Unrepresentable {
                path: name.to_path_buf(),
                message: format!("edge {edge} has a vertex index more than a PLY int can hold"),
            }),
            None => Ok(()),
        },
    }
}
