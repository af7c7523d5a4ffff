//! The mesh data the collision set needs, derived at each build from the configuration's
//! triangles and free edges: the edge list, each triangle's edges, and the rest areas of
//! vertices and edges (ipctk's `CollisionMesh` areas).

// Index loops over small fixed-size arrays read as the formulas do.
#![allow(clippy::needless_range_loop)]

use std::collections::HashMap;

use crate::math::DVec3;

/// Edges, triangle-to-edge map and rest areas of one configuration.
pub(crate) struct IpcMesh {
    /// Every edge: the triangles' sides first (in the order of the triangles), then the
    /// free edges not already there.
    pub edges: Vec<[u32; 2]>,
    /// Edge index of `(min, max)` vertex pair.
    pub edge_id: HashMap<(u32, u32), u32>,
    /// For each triangle, its edges `t0 t1`, `t1 t2`, `t2 t0`.
    pub face_edges: Vec<[u32; 3]>,
    /// Rest vertex areas: a third of the adjacent triangles' areas, else half the adjacent
    /// edges' lengths, else 1 (only computed with area weighting).
    pub vertex_area: Vec<f64>,
    /// Rest edge areas: a third of the adjacent triangles' areas, else the edge's length.
    pub edge_area: Vec<f64>,
}

impl IpcMesh {
    pub(crate) fn new(
        n: usize,
        triangles: &[[u32; 3]],
        free_edges: &[[u32; 2]],
        rest: &[DVec3],
        areas: bool,
    ) -> Self {
        let key = |a: u32, b: u32| (a.min(b), a.max(b));
        let mut edges = Vec::with_capacity(triangles.len() * 3 / 2 + free_edges.len());
        let mut edge_id = HashMap::with_capacity(edges.capacity());
        let mut face_edges = Vec::with_capacity(triangles.len());
        for t in triangles {
            let mut fe = [0u32; 3];
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                fe[k] = *edge_id.entry(key(a, b)).or_insert_with(|| {
                    edges.push([a, b]);
                    (edges.len() - 1) as u32
                });
            }
            face_edges.push(fe);
        }
        for &[a, b] in free_edges {
            edge_id.entry(key(a, b)).or_insert_with(|| {
                edges.push([a, b]);
                (edges.len() - 1) as u32
            });
        }
        let (mut vertex_area, mut edge_area) = (Vec::new(), Vec::new());
        if areas {
            let len = |e: &[u32; 2]| (rest[e[0] as usize] - rest[e[1] as usize]).length();
            let mut by_edges = vec![-1.0f64; n];
            for e in &edges {
                let l = len(e);
                for &v in e {
                    let a = &mut by_edges[v as usize];
                    *a = a.max(0.0) + 0.5 * l;
                }
            }
            let mut by_faces = vec![-1.0f64; n];
            edge_area = vec![-1.0f64; edges.len()];
            for (t, fe) in triangles.iter().zip(&face_edges) {
                let [p0, p1, p2] = t.map(|v| rest[v as usize]);
                let third = 0.5 * (p1 - p0).cross(p2 - p0).length() / 3.0;
                for k in 0..3 {
                    let a = &mut by_faces[t[k] as usize];
                    *a = a.max(0.0) + third;
                    let a = &mut edge_area[fe[k] as usize];
                    *a = a.max(0.0) + third;
                }
            }
            vertex_area = by_faces
                .iter()
                .zip(&by_edges)
                .map(|(&f, &e)| {
                    if f >= 0.0 {
                        f
                    } else if e >= 0.0 {
                        e
                    } else {
                        1.0
                    }
                })
                .collect();
            for (a, e) in edge_area.iter_mut().zip(&edges) {
                if *a < 0.0 {
                    *a = len(e);
                }
            }
        }
        Self {
            edges,
            edge_id,
            face_edges,
            vertex_area,
            edge_area,
        }
    }

    /// The index of edge `a b` (either order), which must exist.
    #[inline]
    pub(crate) fn edge(&self, a: u32, b: u32) -> u32 {
        self.edge_id[&(a.min(b), a.max(b))]
    }
}
