//! Connectivity derived from the triangles of one step: edges and incidences. Computed anew for
//! every step in linear time (counting sorts), so topology changes cost nothing extra. For big
//! meshes the edges and the incidences are derived side by side on the current rayon pool,
//! each by the same sequential code, so the result does not depend on the thread count.

/// Edges and incidences of a triangle soup.
#[derive(Clone, Debug, Default)]
pub struct Topology {
    /// Every undirected edge once, as `[i, j]` with `i < j`, sorted lexicographically.
    pub edges: Vec<[u32; 2]>,
    /// For each edge, the incident triangle of lowest index.
    pub edge_owner: Vec<u32>,
    /// For each triangle `[a, b, c]`, the indices into `edges` of its edges `ab`, `bc`, `ca`.
    pub triangle_edges: Vec<[u32; 3]>,
    /// Triangles incident to each vertex: those of vertex `i` are
    /// `vertex_triangles[vertex_offsets[i]..vertex_offsets[i + 1]]`, in increasing order.
    pub vertex_offsets: Vec<u32>,
    /// See [`Topology::vertex_offsets`].
    pub vertex_triangles: Vec<u32>,
}

/// Meshes with at least this many triangles have their edges and their incidences derived as
/// two rayon tasks (the result does not depend on it).
const PARALLEL_TRIANGLES: usize = 1 << 13;

/// The edges (sorted), each edge's owner, and each triangle's edges.
type EdgeParts = (Vec<[u32; 2]>, Vec<u32>, Vec<[u32; 3]>);

/// Side `k` of `tri` as `(smaller vertex, larger vertex)`.
#[inline]
fn side(tri: &[u32; 3], k: usize) -> (u32, u32) {
    let (a, b) = (tri[k], tri[(k + 1) % 3]);
    (a.min(b), a.max(b))
}

impl Topology {
    /// Derives the topology of `triangles` over `vertex_count` vertices. The triangles must be
    /// valid (as checked by [`Step::new`](super::Step::new)).
    ///
    /// ```
    /// use topoccd::mesh::Topology;
    /// let topo = Topology::new(&[[0, 1, 2], [2, 1, 3]], 4);
    /// assert_eq!(topo.edges, vec![[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]]);
    /// assert_eq!(topo.edge_owner, vec![0, 0, 0, 1, 1]);
    /// assert_eq!(topo.triangles_of(1), &[0, 1]);
    /// ```
    pub fn new(triangles: &[[u32; 3]], vertex_count: usize) -> Self {
        let edges = || Self::edges(triangles, vertex_count);
        let incidences = || Self::incidences(triangles, vertex_count);
        let ((edges, edge_owner, triangle_edges), (vertex_offsets, vertex_triangles)) =
            if triangles.len() >= PARALLEL_TRIANGLES {
                rayon::join(edges, incidences)
            } else {
                (edges(), incidences())
            };
        Self {
            edges,
            edge_owner,
            triangle_edges,
            vertex_offsets,
            vertex_triangles,
        }
    }

    /// The edges, their owners and each triangle's edges, on the calling thread.
    fn edges(triangles: &[[u32; 3]], vertex_count: usize) -> EdgeParts {
        // Half-edges bucketed by their smaller vertex (a counting sort), each bucket (a few
        // half-edges) sorted by the larger vertex: equal keys become one edge, and the edges
        // come out sorted lexicographically.
        let mut start = vec![0u32; vertex_count + 1];
        for tri in triangles {
            for k in 0..3 {
                start[side(tri, k).0 as usize + 1] += 1;
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
                let (lo, hi) = side(tri, k);
                let f = &mut fill[lo as usize];
                half[*f as usize] = (hi, (t * 3 + k) as u32);
                *f += 1;
            }
        }
        let mut edges: Vec<[u32; 2]> = Vec::with_capacity(half.len() / 2 + 1);
        let mut edge_owner = Vec::with_capacity(half.len() / 2 + 1);
        let mut triangle_edges = vec![[0u32; 3]; triangles.len()];
        for (v, range) in start.windows(2).enumerate() {
            let bucket = &mut half[range[0] as usize..range[1] as usize];
            bucket.sort_unstable();
            for &(hi, slot) in &*bucket {
                let key = [v as u32, hi];
                if edges.last() != Some(&key) {
                    // The first half-edge of the edge has the lowest slot, so triangle.
                    edges.push(key);
                    edge_owner.push(slot / 3);
                }
                let e = (edges.len() - 1) as u32;
                triangle_edges[(slot / 3) as usize][(slot % 3) as usize] = e;
            }
        }
        (edges, edge_owner, triangle_edges)
    }

    /// Each vertex's incident triangles, in increasing order (offsets and list), on the
    /// calling thread: a counting sort of the triangles' corners by vertex.
    fn incidences(triangles: &[[u32; 3]], vertex_count: usize) -> (Vec<u32>, Vec<u32>) {
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
        (vertex_offsets, vertex_triangles)
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
    use std::collections::{BTreeMap, BTreeSet};

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
                    let e = topo.triangle_edges[t][k] as usize;
                    assert_eq!(topo.edges[e], side(tri, k));
                    // The owner is the first triangle with that side.
                    let first = triangles.iter().position(|u| (0..3).any(|j| side(u, j) == side(tri, k)));
                    assert_eq!(Some(topo.edge_owner[e] as usize), first);
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

    /// A mesh big enough for the two tasks, on pools of one and two threads: the same result,
    /// and the one a map-based derivation gives (edges, owners as first occurrences, each
    /// triangle's edges, each vertex's triangles in order).
    #[test]
    fn big_meshes_on_one_and_two_threads() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let n = 20_000u32;
        let triangles: Vec<[u32; 3]> = (0..2 * n)
            .map(|_| loop {
                let t = [0; 3].map(|_| rng.random_range(0..n));
                if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                    break t;
                }
            })
            .collect();
        assert!(triangles.len() >= PARALLEL_TRIANGLES);
        let mut first: BTreeMap<[u32; 2], u32> = BTreeMap::new();
        let mut incident = vec![Vec::new(); n as usize];
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = side(tri, k);
                first.entry([a, b]).or_insert(t as u32);
                incident[tri[k] as usize].push(t as u32);
            }
        }
        let edges: Vec<[u32; 2]> = first.keys().copied().collect();
        let owners: Vec<u32> = first.values().copied().collect();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let topo = pool.install(|| Topology::new(&triangles, n as usize));
            assert_eq!(topo.edges, edges);
            assert_eq!(topo.edge_owner, owners);
            for (t, tri) in triangles.iter().enumerate() {
                for k in 0..3 {
                    let (a, b) = side(tri, k);
                    assert_eq!(topo.edges[topo.triangle_edges[t][k] as usize], [a, b]);
                }
            }
            for v in 0..n {
                assert_eq!(topo.triangles_of(v), incident[v as usize].as_slice());
            }
        }
    }
}
