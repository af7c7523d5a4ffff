//! Writing Wavefront OBJ meshes: `v` and `f` lines, coordinates in shortest round-trip form.

use super::{IoError, Mesh};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Writes a mesh as OBJ text: one `v x y z` line per vertex, one `f a b c` line (1-based) per
/// triangle. Coordinates are printed in the shortest form that parses back to the same `f64`,
/// so reading the file back with [`read_obj`](super::read_obj) gives the same positions bit for
/// bit (except the sign and payload of a NaN) and the same triangles.
///
/// ```
/// use topoccd::io::{read_obj, write_obj, Mesh};
/// use topoccd::math::DVec3;
/// let mesh = Mesh {
///     positions: vec![DVec3::ZERO, DVec3::new(1e-300, -0.0, 2.5), DVec3::splat(0.1)],
///     triangles: vec![[0, 1, 2]],
/// };
/// let path = std::env::temp_dir().join(format!("topoccd-doc-write-obj-{}.obj", std::process::id()));
/// write_obj(&path, &mesh)?;
/// assert_eq!(read_obj(&path)?, mesh);
/// std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_obj(path: &Path, mesh: &Mesh) -> Result<(), IoError> {
    let file = File::create(path).map_err(|e| IoError::os(path, "create", e))?;
    write_obj_to(file, mesh, path)
}

/// Writes a mesh as OBJ text (see [`write_obj`]) to any writer; `name` is the file name used
/// in error messages.
///
/// ```
/// use std::path::Path;
/// use topoccd::io::{write_obj_to, Mesh};
/// use topoccd::math::DVec3;
/// let mesh = Mesh { positions: vec![DVec3::X, DVec3::Y, DVec3::Z], triangles: vec![[0, 1, 2]] };
/// let mut bytes = Vec::new();
/// write_obj_to(&mut bytes, &mesh, Path::new("memory.obj"))?;
/// let text = String::from_utf8(bytes).unwrap();
/// assert!(text.ends_with("v 1.0 0.0 0.0\nv 0.0 1.0 0.0\nv 0.0 0.0 1.0\nf 1 2 3\n"));
/// # Ok::<(), topoccd::io::IoError>(())
/// ```
pub fn write_obj_to(output: impl Write, mesh: &Mesh, name: &Path) -> Result<(), IoError> {
    let mut out = BufWriter::with_capacity(1 << 16, output);
    let write_error = |e| IoError::os(name, "write", e);
    writeln!(
        out,
        "# written by topoccd: {} vertices, {} triangles",
        mesh.positions.len(),
        mesh.triangles.len()
    )
    .map_err(write_error)?;
    for p in &mesh.positions {
        // `{:?}` prints the shortest decimal that parses back to the same f64.
        writeln!(out, "v {:?} {:?} {:?}", p.x, p.y, p.z).map_err(write_error)?;
    }
    for &[a, b, c] in &mesh.triangles {
        let one_based = |i: u32| u64::from(i) + 1;
        writeln!(out, "f {} {} {}", one_based(a), one_based(b), one_based(c))
            .map_err(write_error)?;
    }
    out.flush().map_err(write_error)
}
