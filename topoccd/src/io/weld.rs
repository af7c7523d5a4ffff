//! Coincident duplicate vertices: finding them, and merging them.
//!
//! Files from modelers often repeat a vertex at one position: along UV seams, at the poles of a
//! UV sphere, along hard edges. For collision detection such duplicates are two vertices that
//! touch at t=0: every triangle around one of them is "in contact" with the other from the
//! start, which buries the real first contact under spurious ones at t=0. [`coincident_vertices`]
//! finds them (a caller warns), [`weld`] merges them.

use super::{FaceOrigin, Mesh, MeshNote};
use std::collections::HashMap;

/// The key of a position: its bits, with `-0.0` as `0.0`.
fn key(p: &[f64; 3]) -> [u64; 3] {
    p.map(|c| (c + 0.0).to_bits())
}

/// The groups of vertices used by `triangles` that have bit-identical positions (`-0.0` and
/// `0.0` count as identical): each group holds two or more vertex ids in increasing order, the
/// groups are ordered by their first id. Vertices no triangle uses are not looked at. Runs in
/// linear expected time (hashing the coordinates' bits). Indices out of range of `positions`
/// are ignored.
///
/// ```
/// use topoccd::io::coincident_vertices;
/// let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0],
///                  [0.0, -0.0, 0.0], [0.0, 0.0, 1.0]];
/// let triangles = [[0, 1, 2], [3, 4, 5]];
/// assert_eq!(coincident_vertices(&positions, &triangles), vec![vec![0, 4], vec![1, 3]]);
/// ```
pub fn coincident_vertices(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<Vec<u32>> {
    let mut used = vec![false; positions.len()];
    for &v in triangles.iter().flatten() {
        if let Some(u) = used.get_mut(v as usize) {
            *u = true;
        }
    }
    let mut first: HashMap<[u64; 3], u32> = HashMap::new();
    let mut group_of: HashMap<u32, usize> = HashMap::new();
    let mut groups: Vec<Vec<u32>> = Vec::new();
    for (v, p) in positions.iter().enumerate() {
        if !used[v] {
            continue;
        }
        let v = v as u32;
        let rep = *first.entry(key(p)).or_insert(v);
        if rep != v {
            let g = *group_of.entry(rep).or_insert_with(|| {
                groups.push(vec![rep]);
                groups.len() - 1
            });
            groups[g].push(v);
        }
    }
    groups.sort_unstable_by_key(|g| g[0]);
    groups
}

/// Merges the coincident vertices of `mesh` (the groups of [`coincident_vertices`]) into the
/// first of each group. Returns the welded mesh and the map from old vertex ids to new ones
/// (`map[old] = new`, same length as `mesh.positions`). The kept vertices keep their order (new
/// ids are old ids less the merged vertices before them), unused vertices are kept. Triangles
/// keep their order; a triangle with two corners in one group becomes degenerate and is dropped.
/// The welded mesh's [`Mesh::face_origin`] maps its triangles to the faces of the original file
/// (it is `Some` whenever a triangle was dropped), and a [`MeshNote::Merged`] note lists the
/// dropped triangles by their index in `mesh`.
///
/// Every index of `mesh.triangles` must be in range of `mesh.positions` (as the readers
/// guarantee). To weld the other frame of a step the same way, use [`apply_weld`] with the map.
///
/// ```
/// use topoccd::io::{weld, Mesh};
/// // Two triangles that share an edge through duplicated vertices (a seam).
/// let mesh = Mesh::new(
///     vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0],
///          [1.0, 1.0, 0.0]],
///     vec![[0, 1, 2], [3, 5, 4]],
/// );
/// let (welded, map) = weld(&mesh);
/// assert_eq!(map, vec![0, 1, 2, 1, 2, 3]);
/// assert_eq!(welded.positions.len(), 4);
/// assert_eq!(welded.triangles, vec![[0, 1, 2], [1, 3, 2]]);
/// ```
pub fn weld(mesh: &Mesh) -> (Mesh, Vec<u32>) {
    let groups = coincident_vertices(&mesh.positions, &mesh.triangles);
    let mut rep: Vec<u32> = (0..mesh.positions.len() as u32).collect();
    for g in &groups {
        for &v in &g[1..] {
            rep[v as usize] = g[0];
        }
    }
    let mut map = vec![0u32; mesh.positions.len()];
    let mut positions = Vec::with_capacity(mesh.positions.len());
    for (v, &r) in rep.iter().enumerate() {
        if r as usize == v {
            map[v] = positions.len() as u32;
            positions.push(mesh.positions[v]);
        } else {
            // The representative is the group's first id, so it is numbered already.
            map[v] = map[r as usize];
        }
    }
    let mut triangles = Vec::with_capacity(mesh.triangles.len());
    let mut origin: Vec<FaceOrigin> = Vec::with_capacity(mesh.triangles.len());
    let mut dropped = Vec::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|v| map[v as usize]);
        if a == b || b == c || a == c {
            dropped.push(t as u32);
        } else {
            triangles.push([a, b, c]);
            origin.push(mesh.origin(t));
        }
    }
    let face_origin = if dropped.is_empty() {
        mesh.face_origin.clone()
    } else {
        Some(origin)
    };
    let mut notes = mesh.notes.clone();
    if !groups.is_empty() {
        notes.push(MeshNote::Merged {
            removed: mesh.positions.len() - positions.len(),
            dropped,
        });
    }
    let welded = Mesh {
        positions,
        triangles,
        face_origin,
        notes,
    };
    (welded, map)
}

/// The positions of another frame welded with the `map` of [`weld`]: new vertex `n` takes the
/// position of the first old vertex that maps to `n` (the group's representative).
///
/// ```
/// use topoccd::io::apply_weld;
/// let x1 = [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
/// assert_eq!(apply_weld(&x1, &[0, 1, 0]), vec![[0.0; 3], [1.0, 0.0, 0.0]]);
/// ```
pub fn apply_weld(positions: &[[f64; 3]], map: &[u32]) -> Vec<[f64; 3]> {
    debug_assert_eq!(positions.len(), map.len());
    let count = map.iter().map(|&n| n as usize + 1).max().unwrap_or(0);
    let mut out = vec![[0.0; 3]; count];
    let mut set = vec![false; count];
    for (p, &n) in positions.iter().zip(map) {
        if !set[n as usize] {
            set[n as usize] = true;
            out[n as usize] = *p;
        }
    }
    out
}
