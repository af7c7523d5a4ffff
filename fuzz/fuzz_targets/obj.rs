//! The OBJ reader on arbitrary bytes: a mesh with indices in range, or an error; never a panic.
//!
//! A mesh it returns is also welded (files from modelers repeat vertices; `topoccd step
//! --weld` welds them), and the weld must be consistent: the map sends every vertex to one
//! at its position, the welded triangles are in range and not degenerate, no two of their
//! vertices share a position, and `weld_frames` of the mesh with itself at both ends of a
//! step gives the same triangles and map.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;
use topoccd::io::{coincident_vertices, read_obj_from, weld, weld_frames};

/// A position's bits, with `-0.0` as `0.0` (how vertices are welded).
fn key(p: &[f64; 3]) -> [u64; 3] {
    p.map(|c| (c + 0.0).to_bits())
}

fuzz_target!(|data: &[u8]| {
    let Ok(mesh) = read_obj_from(data, Path::new("fuzz.obj")) else {
        return;
    };
    let n = mesh.positions.len();
    assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));

    let (welded, map) = weld(&mesh);
    let m = welded.positions.len();
    assert_eq!(map.len(), n);
    assert!(m <= n && map.iter().all(|&v| (v as usize) < m));
    for &v in mesh.triangles.iter().flatten() {
        let w = map[v as usize] as usize;
        assert_eq!(key(&welded.positions[w]), key(&mesh.positions[v as usize]));
    }
    // The input's triangles renumbered, without the degenerate ones: in range (the map is),
    // none degenerate.
    let kept: Vec<[u32; 3]> = mesh
        .triangles
        .iter()
        .map(|t| t.map(|v| map[v as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .collect();
    assert_eq!(welded.triangles, kept);
    if let Some(origin) = &welded.face_origin {
        assert_eq!(origin.len(), welded.triangles.len());
    }
    assert!(coincident_vertices(&welded.positions, &welded.triangles).is_empty());

    let frames = weld_frames(&mesh.positions, &mesh.positions, &mesh.triangles);
    assert_eq!((&frames.triangles, &frames.map), (&welded.triangles, &map));
    assert_eq!(frames.x0.len(), m);
});
