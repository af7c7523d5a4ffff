//! Codimensional geometry: the free edges (edges in no triangle) a step may carry
//! ([`Step::with_edges`](super::Step::with_edges)) and its free points (vertices in no
//! triangle and no edge), derived once per query from the step and its [`Topology`].
//!
//! # Which pairs a step with free edges and points needs
//! Every primitive is a closed convex set: a triangle, a segment (a free edge) or a point. Two
//! of them come within a distance `d` exactly when one of the following feature pairs does
//! (the distance of two convex polytopes is reached at a pair of their faces one of which is
//! a vertex, or at two edges):
//! - triangle and triangle: a vertex of one and the other triangle (vertex-face), or an edge of
//!   each (edge-edge), as for meshes;
//! - triangle and segment: an end of the segment and the triangle (vertex-face), or the segment
//!   and an edge of the triangle (edge-edge); a corner of the triangle against the segment is
//!   such an edge-edge pair (the corner is an end of a triangle edge);
//! - segment and segment: edge-edge;
//! - point and triangle: vertex-face;
//! - point and segment: vertex-edge;
//! - point and point: vertex-vertex.
//!
//! So the pairs that meshes alone do not cover are: vertex-face pairs of a *free vertex* (an
//! end of a free edge in no triangle, or a free point) against every face, edge-edge pairs of
//! a free edge against every edge (of a triangle or free), vertex-edge pairs of a free point
//! against a free edge, and vertex-vertex pairs of two free points. A free point against a
//! triangle's edge or corner, and a free edge's end against a triangle's edge, are already
//! vertex-face and edge-edge pairs with that triangle. The pair filter then applies as for any
//! pair: features that share a vertex are left out, and parents, groups and `can_collide`
//! apply to their vertices.

use super::{Step, Topology};

/// The free primitives of one step.
#[derive(Clone, Debug, Default)]
pub(crate) struct Codim {
    /// The free edges: the step's edges that are in no triangle, each `[i, j]` with `i < j`,
    /// sorted, each once.
    pub edges: Vec<[u32; 2]>,
    /// The free points: vertices in no triangle and no edge, increasing (none when the step
    /// ignores them: [`Step::free_points`]).
    pub points: Vec<u32>,
    /// The vertices in no triangle that are in a free edge or are free points, increasing:
    /// those whose vertex-face pairs the triangles' broad phases do not see.
    pub free_vertices: Vec<u32>,
}

impl Codim {
    /// The free primitives of `step`, `None` when the step has no edges set
    /// ([`Step::edges`] is `None`): then vertices in no triangle are ignored, as before.
    pub fn new(step: &Step, topo: &Topology) -> Option<Self> {
        let given = step.edges()?;
        let n = step.vertex_count();
        let in_triangle = |v: u32| !topo.triangles_of(v).is_empty();
        let mut edges: Vec<[u32; 2]> = given
            .iter()
            .map(|&[i, j]| [i.min(j), i.max(j)])
            .filter(|e| topo.edges.binary_search(e).is_err())
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let mut in_edge = vec![false; n];
        for &[i, j] in &edges {
            in_edge[i as usize] = true;
            in_edge[j as usize] = true;
        }
        let mut points = Vec::new();
        let mut free_vertices = Vec::new();
        for v in 0..n as u32 {
            if in_triangle(v) {
                continue;
            }
            if !in_edge[v as usize] {
                if step.free_points() {
                    points.push(v);
                    free_vertices.push(v);
                }
            } else {
                free_vertices.push(v);
            }
        }
        Some(Self {
            edges,
            points,
            free_vertices,
        })
    }

    /// Whether there is anything free at all.
    pub fn is_empty(&self) -> bool {
        self.edges.is_empty() && self.free_vertices.is_empty()
    }
}
