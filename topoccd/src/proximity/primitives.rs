//! The primitives of a configuration: triangles, free edges and free points, as the leaves of
//! the proximity hierarchy, with the features each owns, so that every feature pair is looked
//! at from one leaf pair only.
//!
//! Every vertex is owned by one leaf: its incident triangle of lowest index, else its
//! incident free edge of lowest index, else its own free point. Every edge is owned by its
//! incident triangle of lowest index (a mesh edge) or by itself (a free edge). A vertex-face
//! pair is then looked at from the leaf pair (owner of the vertex, the face), an edge-edge
//! pair from (owner of one edge, owner of the other), and so on: once.

use crate::mesh::Topology;

use super::Configuration;

/// Leaves `[0, triangles)` are the triangles, then the free edges, then the free points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Triangle,
    Edge,
    Point,
}

/// One leaf: its vertices and the features it owns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct LeafPrim {
    pub kind: Kind,
    /// The leaf's vertices (`n` of them: 3, 2 or 1).
    pub verts: [u32; 3],
    pub n: u8,
    /// The vertices it owns (`nv` of them).
    pub owned_v: [u32; 3],
    pub nv: u8,
    /// The edges it owns, indices into [`Primitives::edges`] (`ne` of them).
    pub owned_e: [u32; 3],
    pub ne: u8,
}

impl LeafPrim {
    /// The leaf's vertices.
    #[inline]
    pub fn vertices(&self) -> &[u32] {
        &self.verts[..self.n as usize]
    }
}

/// The derived primitives of one configuration's topology, kept across queries for the same
/// triangles, edges and vertex count (compared exactly every query).
#[derive(Clone, Debug, Default)]
pub(crate) struct Primitives {
    /// Every edge once, `[i, j]` with `i < j`: the triangles' edges (sorted), then the free
    /// edges (sorted).
    pub edges: Vec<[u32; 2]>,
    /// The number of triangles' edges at the start of `edges`.
    pub mesh_edges: usize,
    /// The free points, increasing.
    pub points: Vec<u32>,
    /// The leaves: triangles, free edges, free points.
    pub leaves: Vec<LeafPrim>,
    /// The input they were derived from: triangles, edges as given, vertex count.
    key: Option<Key>,
}

/// What the primitives were derived from: the triangles, the edges as given, the vertex count,
/// whether loose vertices are free points.
type Key = (Vec<[u32; 3]>, Vec<[u32; 2]>, usize, bool);

impl Primitives {
    /// Whether `config` has the very triangles, edges and vertex count these were derived
    /// from.
    pub fn same(&self, config: &Configuration<'_>) -> bool {
        self.key.as_ref().is_some_and(|(t, e, n, p)| {
            *n == config.vertex_count()
                && *p == config.free_points()
                && t[..] == *config.triangles()
                && e[..] == *config.edges()
        })
    }

    /// Derives the primitives of `config`.
    pub fn derive(&mut self, config: &Configuration<'_>) {
        let tris = config.triangles();
        let n = config.vertex_count();
        let topo = Topology::new(tris, n);
        self.edges.clear();
        self.edges.extend_from_slice(&topo.edges);
        self.mesh_edges = topo.edges.len();
        let mut free: Vec<[u32; 2]> = (config.edges().iter())
            .map(|&[a, b]| [a.min(b), a.max(b)])
            .filter(|e| topo.edges.binary_search(e).is_err())
            .collect();
        free.sort_unstable();
        free.dedup();
        self.edges.extend_from_slice(&free);

        let mut owner = vec![u32::MAX; n];
        for (t, tri) in tris.iter().enumerate() {
            for &v in tri {
                if owner[v as usize] == u32::MAX {
                    owner[v as usize] = t as u32;
                }
            }
        }
        let first_edge_leaf = tris.len() as u32;
        for (k, e) in free.iter().enumerate() {
            for &v in e {
                if owner[v as usize] == u32::MAX {
                    owner[v as usize] = first_edge_leaf + k as u32;
                }
            }
        }
        self.points.clear();
        if config.free_points() {
            self.points
                .extend((0..n as u32).filter(|&v| owner[v as usize] == u32::MAX));
        }
        let first_point_leaf = first_edge_leaf + free.len() as u32;
        for (k, &v) in self.points.iter().enumerate() {
            owner[v as usize] = first_point_leaf + k as u32;
        }

        self.leaves.clear();
        for (t, tri) in tris.iter().enumerate() {
            let mut leaf = LeafPrim {
                kind: Kind::Triangle,
                verts: *tri,
                n: 3,
                owned_v: [0; 3],
                nv: 0,
                owned_e: [0; 3],
                ne: 0,
            };
            for &v in tri {
                if owner[v as usize] == t as u32 {
                    leaf.owned_v[leaf.nv as usize] = v;
                    leaf.nv += 1;
                }
            }
            for &e in &topo.triangle_edges[t] {
                if topo.edge_owner[e as usize] == t as u32 {
                    leaf.owned_e[leaf.ne as usize] = e;
                    leaf.ne += 1;
                }
            }
            self.leaves.push(leaf);
        }
        for (k, e) in free.iter().enumerate() {
            let id = first_edge_leaf + k as u32;
            let mut leaf = LeafPrim {
                kind: Kind::Edge,
                verts: [e[0], e[1], u32::MAX],
                n: 2,
                owned_v: [0; 3],
                nv: 0,
                owned_e: [(self.mesh_edges + k) as u32, 0, 0],
                ne: 1,
            };
            for &v in e {
                if owner[v as usize] == id {
                    leaf.owned_v[leaf.nv as usize] = v;
                    leaf.nv += 1;
                }
            }
            self.leaves.push(leaf);
        }
        for &v in &self.points {
            self.leaves.push(LeafPrim {
                kind: Kind::Point,
                verts: [v, u32::MAX, u32::MAX],
                n: 1,
                owned_v: [v, 0, 0],
                nv: 1,
                owned_e: [0; 3],
                ne: 0,
            });
        }
        self.key = Some((
            tris.to_vec(),
            config.edges().to_vec(),
            n,
            config.free_points(),
        ));
    }
}
