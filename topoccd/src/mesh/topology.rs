//! Connectivity derived from the triangles of one step: edges and incidences. Computed anew for
//! every step in linear time (counting sorts), so topology changes cost nothing extra.

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
        // Half-edges bucketed by their smaller vertex (a counting sort), each bucket (a few
        // half-edges) sorted by the larger vertex: equal keys become one edge, and the edges
        // come out sorted lexicographically.
        let mut start = vec![0u32; vertex_count + 1];
        for tri in triangles {
            for k in 0..3 {
                start[tri[k].min(tri[(k + 1) % 3]) as usize + 1] += 1;
            }
        }
        for i in 0..vertex_count {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        // (larger vertex, slot 3 t + k) of each half-edge.
        let mut half = vec![(0u32, 0u32); triangles.len() * 3];
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let f = &mut fill[a.min(b) as usize];
                half[*f as usize] = (a.max(b), (t * 3 + k) as u32);
                *f += 1;
            }
        }
        let mut edges: Vec<[u32; 2]> = Vec::with_capacity(half.len() / 2 + 1);
        let mut triangle_edges = vec![[0u32; 3]; triangles.len()];
        for (v, range) in start.windows(2).enumerate() {
            let bucket = &mut half[range[0] as usize..range[1] as usize];
            bucket.sort_unstable();
            for &(hi, slot) in &*bucket {
                let key = [v as u32, hi];
                if edges.last() != Some(&key) {
                    edges.push(key);
                }
                let e = (edges.len() - 1) as u32;
                triangle_edges[(slot / 3) as usize][(slot % 3) as usize] = e;
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::collections::BTreeSet;

    /// Against a set-based derivation: the edges are the distinct undirected sides, sorted;
    /// each triangle's sides map to them; each vertex lists its triangles in order.
    #[test]
    fn matches_a_set_based_derivation() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for n in [3usize, 5, 40, 300] {
            let triangles: Vec<[u32; 3]> = (0..2 * n)
                .map(|_| loop {
                    let t = [0; 3].map(|_| rng.random_range(0..n as u32));
                    if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                        break t;
                    }
                })
                .collect();
            let topo = Topology::new(&triangles, n + 2);
            let side = |t: &[u32; 3], k: usize| {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                [a.min(b), a.max(b)]
            };
            let set: BTreeSet<[u32; 2]> = triangles
                .iter()
                .flat_map(|t| (0..3).map(move |k| side(t, k)))
                .collect();
            assert_eq!(topo.edges, set.into_iter().collect::<Vec<_>>());
            for (t, tri) in triangles.iter().enumerate() {
                for k in 0..3 {
                    assert_eq!(topo.edges[topo.triangle_edges[t][k] as usize], side(tri, k));
                }
            }
            for v in 0..n as u32 + 2 {
                let mine: Vec<u32> = (0..triangles.len() as u32)
                    .filter(|&t| triangles[t as usize].contains(&v))
                    .collect();
                assert_eq!(topo.triangles_of(v), mine.as_slice());
            }
        }
    }
}
