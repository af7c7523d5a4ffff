//! Connectivity derived from the triangles of one step: edges and incidences. Computed anew for
//! every step in linear time (after a sort), so topology changes cost nothing extra.

/// Edges and incidences of a triangle soup.
#[derive(Clone, Debug, Default)]
pub struct Topology {
    /// Every undirected edge once, as `[i, j]` with `i < j`, sorted lexicographically.
    pub edges: Vec<[u32; 2]>,
    /// For each triangle `[a, b, c]`, the indices into `edges` of its edges `ab`, `bc`, `ca`.
    pub triangle_edges: Vec<[u32; 3]>,
    /// Triangles incident to each vertex: those of vertex `i` are
    /// `vertex_triangles[vertex_offsets[i]..vertex_offsets[i + 1]]`, in increasing order.
    pub vertex_offsets: Vec<u32>,
    /// See [`Topology::vertex_offsets`].
    pub vertex_triangles: Vec<u32>,
}

impl Topology {
    /// Derives the topology of `triangles` over `vertex_count` vertices. The triangles must be
    /// valid (as checked by [`Step::new`](super::Step::new)).
    ///
    /// ```
    /// use topoccd::mesh::Topology;
    /// let topo = Topology::new(&[[0, 1, 2], [2, 1, 3]], 4);
    /// assert_eq!(topo.edges, vec![[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]]);
    /// assert_eq!(topo.triangles_of(1), &[0, 1]);
    /// ```
    pub fn new(triangles: &[[u32; 3]], vertex_count: usize) -> Self {
        // Half-edges keyed by their undirected edge, then sorted: equal keys become one edge.
        let mut half: Vec<([u32; 2], u32)> = Vec::with_capacity(triangles.len() * 3);
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                half.push(([a.min(b), a.max(b)], (t * 3 + k) as u32));
            }
        }
        half.sort_unstable();
        let mut edges: Vec<[u32; 2]> = Vec::with_capacity(half.len() / 2 + 1);
        let mut triangle_edges = vec![[0u32; 3]; triangles.len()];
        for (key, slot) in &half {
            if edges.last() != Some(key) {
                edges.push(*key);
            }
            let e = (edges.len() - 1) as u32;
            triangle_edges[(*slot / 3) as usize][(*slot % 3) as usize] = e;
        }

        let mut vertex_offsets = vec![0u32; vertex_count + 1];
        for tri in triangles {
            for &v in tri {
                vertex_offsets[v as usize + 1] += 1;
            }
        }
        for i in 0..vertex_count {
            vertex_offsets[i + 1] += vertex_offsets[i];
        }
        let mut fill = vertex_offsets.clone();
        let mut vertex_triangles = vec![0u32; triangles.len() * 3];
        for (t, tri) in triangles.iter().enumerate() {
            for &v in tri {
                vertex_triangles[fill[v as usize] as usize] = t as u32;
                fill[v as usize] += 1;
            }
        }
        Self {
            edges,
            triangle_edges,
            vertex_offsets,
            vertex_triangles,
        }
    }

    /// The triangles incident to vertex `v`, in increasing order.
    pub fn triangles_of(&self, v: u32) -> &[u32] {
        let lo = self.vertex_offsets[v as usize] as usize;
        let hi = self.vertex_offsets[v as usize + 1] as usize;
        &self.vertex_triangles[lo..hi]
    }
}
