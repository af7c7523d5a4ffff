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
    groups_by_key(positions.len(), triangles, |v| key(&positions[v]))
}

/// The groups of vertices used by `triangles` whose keys are equal, as [`coincident_vertices`]
/// describes them.
fn groups_by_key<K: std::hash::Hash + Eq>(
    vertices: usize,
    triangles: &[[u32; 3]],
    key: impl Fn(usize) -> K,
) -> Vec<Vec<u32>> {
    let mut used = vec![false; vertices];
    for &v in triangles.iter().flatten() {
        if let Some(u) = used.get_mut(v as usize) {
            *u = true;
        }
    }
    let mut first: HashMap<K, u32> = HashMap::new();
    let mut group_of: HashMap<u32, usize> = HashMap::new();
    let mut groups: Vec<Vec<u32>> = Vec::new();
    for (v, &is_used) in used.iter().enumerate() {
        if !is_used {
            continue;
        }
        let rep = *first.entry(key(v)).or_insert(v as u32);
        if rep != v as u32 {
            let g = *group_of.entry(rep).or_insert_with(|| {
                groups.push(vec![rep]);
                groups.len() - 1
            });
            groups[g].push(v as u32);
        }
    }
    groups.sort_unstable_by_key(|g| g[0]);
    groups
}

/// The two frames of a step welded by [`weld_frames`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WeldedFrames {
    /// Positions at t=0, welded.
    pub x0: Vec<[f64; 3]>,
    /// Positions at t=1, welded.
    pub x1: Vec<[f64; 3]>,
    /// Triangles in the new ids, without those that became degenerate.
    pub triangles: Vec<[u32; 3]>,
    /// `map[old] = new` for every vertex.
    pub map: Vec<u32>,
    /// `first[new]`: the lowest old id merged into `new` (to name it as the input did).
    pub first: Vec<u32>,
    /// `kept[t]`: the index in the input's triangles of triangle `t`.
    pub kept: Vec<u32>,
    /// The groups of vertices merged (see [`coincident_vertices`]).
    pub groups: Vec<Vec<u32>>,
}

/// Welds the two frames of a step: merges the vertices (used by `triangles`) whose positions
/// are bit-identical at t=0 *and* at t=1, so that two vertices that only meet at one end of
/// the step stay apart. `x0` and `x1` must have one length, and every index of `triangles` be
/// in range. The kept vertices and triangles keep their order; degenerate triangles are
/// dropped ([`WeldedFrames::kept`] says which remain).
///
/// ```
/// use topoccd::io::weld_frames;
/// let x0 = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
/// let mut x1 = x0;
/// let welded = weld_frames(&x0, &x1, &[[0, 1, 2], [3, 4, 2]]);
/// assert_eq!(welded.triangles, vec![[0, 1, 2], [1, 3, 2]]);
/// assert_eq!((welded.map[3], welded.first[1]), (1, 1));
/// x1[3] = [1.0, 0.0, 0.5]; // vertices 1 and 3 part during the step: not merged
/// assert!(weld_frames(&x0, &x1, &[[0, 1, 2], [3, 4, 2]]).groups.is_empty());
/// ```
pub fn weld_frames(x0: &[[f64; 3]], x1: &[[f64; 3]], triangles: &[[u32; 3]]) -> WeldedFrames {
    debug_assert_eq!(x0.len(), x1.len());
    let n = x0.len().min(x1.len());
    let groups = groups_by_key(n, triangles, |v| (key(&x0[v]), key(&x1[v])));
    let (map, first) = renumber(n, &groups);
    let mut welded = WeldedFrames {
        x0: first.iter().map(|&v| x0[v as usize]).collect(),
        x1: first.iter().map(|&v| x1[v as usize]).collect(),
        ..WeldedFrames::default()
    };
    for (t, tri) in triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|v| map[v as usize]);
        if a != b && b != c && a != c {
            welded.triangles.push([a, b, c]);
            welded.kept.push(t as u32);
        }
    }
    welded.map = map;
    welded.first = first;
    welded.groups = groups;
    welded
}

/// The map from old to new ids merging each group into its first vertex, and for each new id
/// its first old id.
fn renumber(vertices: usize, groups: &[Vec<u32>]) -> (Vec<u32>, Vec<u32>) {
    let mut rep: Vec<u32> = (0..vertices as u32).collect();
    for g in groups {
        for &v in &g[1..] {
            rep[v as usize] = g[0];
        }
    }
    let mut map = vec![0u32; vertices];
    let mut first = Vec::with_capacity(vertices);
    for (v, &r) in rep.iter().enumerate() {
        if r as usize == v {
            map[v] = first.len() as u32;
            first.push(v as u32);
        } else {
            // The representative is the group's first id, so it is numbered already.
            map[v] = map[r as usize];
        }
    }
    (map, first)
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
    let (map, first) = renumber(mesh.positions.len(), &groups);
    let positions: Vec<[f64; 3]> = first.iter().map(|&v| mesh.positions[v as usize]).collect();
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
    let edges = (mesh.edges.iter())
        .map(|e| e.map(|v| map[v as usize]))
        .filter(|e| e[0] != e[1])
        .collect();
    let welded = Mesh {
        positions,
        triangles,
        edges,
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
