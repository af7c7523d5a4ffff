//! Connectivity derived from the triangles of one step: edges and incidences. Computed anew for
//! every step in linear time (counting sorts), so topology changes cost nothing extra. Big
//! meshes are done on the current rayon pool, into the same result.

use std::sync::atomic::{AtomicU32, AtomicU64, Ordering::Relaxed};

use rayon::prelude::*;

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

/// Meshes with at least this many triangles are done on the rayon pool (the result does not
/// depend on it).
const PARALLEL_TRIANGLES: usize = 1 << 15;

/// The parallel counting sorts split the buckets into this many ranges of consecutive buckets.
const RANGES: usize = 256;

/// The edges of a range of vertices, their owners, and each vertex's edge count.
type RangeEdges = (Vec<[u32; 2]>, Vec<u32>, Vec<u32>);

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
        if triangles.len() >= PARALLEL_TRIANGLES {
            Self::parallel(triangles, vertex_count)
        } else {
            Self::sequential(triangles, vertex_count)
        }
    }

    /// [`Topology::new`] on the calling thread.
    fn sequential(triangles: &[[u32; 3]], vertex_count: usize) -> Self {
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
            edge_owner,
            triangle_edges,
            vertex_offsets,
            vertex_triangles,
        }
    }

    /// [`Topology::new`] on the current rayon pool: the same counting sorts, with atomic
    /// counters, each bucket then sorted, so the result does not depend on the order in which
    /// the threads filled it.
    fn parallel(triangles: &[[u32; 3]], vertex_count: usize) -> Self {
        // Half-edges by smaller vertex, as (larger vertex, slot 3 t + k), sorted in each bucket.
        let (start, half) = bucket_sort(triangles.len(), vertex_count, |t, k| {
            let (lo, hi) = side(&triangles[t], k);
            (lo, (hi as u64) << 32 | (t * 3 + k) as u64)
        });
        let hi_of = |h: u64| (h >> 32) as u32;
        let ranges = bucket_ranges(&start);
        // Per range of vertices: its edges, their owners, and each vertex's edge count.
        let parts: Vec<RangeEdges> = ranges
            .par_iter()
            .map(|&(v0, v1)| {
                let (mut edges, mut owners, mut counts) = (Vec::new(), Vec::new(), Vec::new());
                for v in v0..v1 {
                    let bucket = &half[start[v] as usize..start[v + 1] as usize];
                    let before = edges.len();
                    for (i, &h) in bucket.iter().enumerate() {
                        if i == 0 || hi_of(bucket[i - 1]) != hi_of(h) {
                            edges.push([v as u32, hi_of(h)]);
                            owners.push((h as u32) / 3);
                        }
                    }
                    counts.push((edges.len() - before) as u32);
                }
                (edges, owners, counts)
            })
            .collect();
        let edge_count = parts.iter().map(|p| p.0.len()).sum();
        let mut edges = Vec::with_capacity(edge_count);
        let mut edge_owner = Vec::with_capacity(edge_count);
        let mut edge_start = Vec::with_capacity(vertex_count);
        let mut sum = 0u32;
        for (e, o, counts) in parts {
            edges.extend_from_slice(&e);
            edge_owner.extend_from_slice(&o);
            for c in counts {
                edge_start.push(sum);
                sum += c;
            }
        }
        // Each side's edge: its smaller vertex's first edge plus the rank of its larger vertex
        // among the distinct larger vertices of the bucket.
        let mut triangle_edges = Vec::with_capacity(triangles.len());
        triangle_edges.par_extend(triangles.par_iter().with_min_len(4096).map(|tri| {
            std::array::from_fn(|k| {
                let (lo, hi) = side(tri, k);
                let bucket = &half[start[lo as usize] as usize..start[lo as usize + 1] as usize];
                let mut rank = 0;
                for (i, &h) in bucket.iter().enumerate() {
                    let h = hi_of(h);
                    if h == hi {
                        break;
                    }
                    if i + 1 < bucket.len() && hi_of(bucket[i + 1]) != h {
                        rank += 1;
                    }
                }
                edge_start[lo as usize] + rank
            })
        }));

        let (vertex_offsets, incident) =
            bucket_sort(triangles.len(), vertex_count, |t, k| (triangles[t][k], t as u64));
        let mut vertex_triangles = Vec::with_capacity(incident.len());
        vertex_triangles.par_extend(incident.par_iter().with_min_len(4096).map(|&t| t as u32));
        Self {
            edges,
            edge_owner,
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

/// A counting sort, on the rayon pool, of the `3 n` entries `entry(t, k) = (bucket, value)`
/// (`t < n`, `k < 3`) into `buckets` buckets. Returns the bucket offsets (`buckets + 1` of them)
/// and the values, sorted within each bucket: the same for any thread count.
fn bucket_sort(
    n: usize,
    buckets: usize,
    entry: impl Fn(usize, usize) -> (u32, u64) + Sync,
) -> (Vec<u32>, Vec<u64>) {
    let counters: Vec<AtomicU32> = (0..buckets).into_par_iter().map(|_| AtomicU32::new(0)).collect();
    (0..n).into_par_iter().with_min_len(4096).for_each(|t| {
        for k in 0..3 {
            counters[entry(t, k).0 as usize].fetch_add(1, Relaxed);
        }
    });
    let mut offsets = Vec::with_capacity(buckets + 1);
    let mut sum = 0u32;
    offsets.push(0);
    for c in &counters {
        sum += c.load(Relaxed);
        offsets.push(sum);
    }
    // The counters become each bucket's fill cursor.
    counters
        .par_iter()
        .zip(&offsets[..buckets])
        .for_each(|(c, &o)| c.store(o, Relaxed));
    let slots: Vec<AtomicU64> = (0..3 * n).into_par_iter().map(|_| AtomicU64::new(0)).collect();
    (0..n).into_par_iter().with_min_len(4096).for_each(|t| {
        for k in 0..3 {
            let (b, value) = entry(t, k);
            let i = counters[b as usize].fetch_add(1, Relaxed);
            slots[i as usize].store(value, Relaxed);
        }
    });
    let mut values: Vec<u64> = slots.into_par_iter().map(AtomicU64::into_inner).collect();
    // Sort each bucket, ranges of buckets in parallel.
    let mut parts = Vec::new();
    let mut rest = &mut values[..];
    for (b0, b1) in bucket_ranges(&offsets) {
        let len = (offsets[b1] - offsets[b0]) as usize;
        let (part, tail) = std::mem::take(&mut rest).split_at_mut(len);
        parts.push((b0, b1, part));
        rest = tail;
    }
    parts.into_par_iter().for_each(|(b0, b1, part)| {
        let base = offsets[b0];
        for b in b0..b1 {
            part[(offsets[b] - base) as usize..(offsets[b + 1] - base) as usize].sort_unstable();
        }
    });
    (offsets, values)
}

/// [`RANGES`] ranges `(first, end)` of consecutive buckets covering all the buckets of
/// `offsets` (`buckets + 1` offsets).
fn bucket_ranges(offsets: &[u32]) -> Vec<(usize, usize)> {
    let buckets = offsets.len() - 1;
    let step = buckets.div_ceil(RANGES).max(1);
    (0..buckets)
        .step_by(step)
        .map(|b0| (b0, (b0 + step).min(buckets)))
        .collect()
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
            let topo = Topology::sequential(&triangles, n + 2);
            let par = Topology::parallel(&triangles, n + 2);
            assert_eq!(
                (&par.edges, &par.edge_owner, &par.triangle_edges),
                (&topo.edges, &topo.edge_owner, &topo.triangle_edges)
            );
            assert_eq!(
                (&par.vertex_offsets, &par.vertex_triangles),
                (&topo.vertex_offsets, &topo.vertex_triangles)
            );
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

    /// The parallel derivation equals the sequential one on a mesh big enough to be split, on
    /// pools of one and two threads.
    #[test]
    fn parallel_equals_sequential() {
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
        let seq = Topology::sequential(&triangles, n as usize);
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let par = pool.install(|| Topology::parallel(&triangles, n as usize));
            assert_eq!(par.edges, seq.edges);
            assert_eq!(par.edge_owner, seq.edge_owner);
            assert_eq!(par.triangle_edges, seq.triangle_edges);
            assert_eq!(par.vertex_offsets, seq.vertex_offsets);
            assert_eq!(par.vertex_triangles, seq.vertex_triangles);
        }
    }
}
