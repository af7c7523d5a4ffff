//! Fragments: a mesh region partitioned into connected patches that can break off.

use std::collections::VecDeque;

use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Partitions the triangles `range` of `triangles` into about `count` connected fragments by
/// growing them breadth-first, in lockstep, from random seed triangles over shared edges (a
/// discrete geodesic Voronoi diagram). Triangles not reached (other components without a seed)
/// join a fragment of their own per component. Deterministic for the generator's state.
pub(crate) fn partition(
    triangles: &[[u32; 3]],
    range: std::ops::Range<usize>,
    count: usize,
    rng: &mut ChaCha8Rng,
) -> Vec<Vec<u32>> {
    let (start, len) = (range.start, range.len());
    if len == 0 {
        return Vec::new();
    }
    // Edge -> triangle pairs, by sorting (edge key, triangle).
    let mut edges: Vec<(u64, u32)> = Vec::with_capacity(3 * len);
    for (i, t) in triangles[range.clone()].iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
            edges.push((key, i as u32));
        }
    }
    edges.sort_unstable();
    // Adjacency lists in compressed form.
    let mut degree = vec![0u32; len + 1];
    let mut pairs = Vec::with_capacity(3 * len);
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j].0 == edges[i].0 {
            j += 1;
        }
        for x in i..j {
            for y in i..j {
                if x != y {
                    pairs.push((edges[x].1, edges[y].1));
                }
            }
        }
        i = j;
    }
    pairs.sort_unstable();
    for &(a, _) in &pairs {
        degree[a as usize + 1] += 1;
    }
    for k in 0..len {
        degree[k + 1] += degree[k];
    }
    let neighbours = |t: usize| &pairs[degree[t] as usize..degree[t + 1] as usize];

    let mut owner = vec![u32::MAX; len];
    let mut queue = VecDeque::new();
    let count = count.clamp(1, len);
    let mut fragments: Vec<Vec<u32>> = Vec::with_capacity(count);
    for _ in 0..count {
        let t = rng.random_range(0..len);
        if owner[t] == u32::MAX {
            owner[t] = fragments.len() as u32;
            fragments.push(vec![(start + t) as u32]);
            queue.push_back(t);
        }
    }
    let mut next_unreached = 0;
    loop {
        while let Some(t) = queue.pop_front() {
            let f = owner[t];
            for &(_, n) in neighbours(t) {
                let n = n as usize;
                if owner[n] == u32::MAX {
                    owner[n] = f;
                    fragments[f as usize].push((start + n) as u32);
                    queue.push_back(n);
                }
            }
        }
        // A component without a seed becomes a fragment of its own.
        while next_unreached < len && owner[next_unreached] != u32::MAX {
            next_unreached += 1;
        }
        if next_unreached == len {
            break;
        }
        owner[next_unreached] = fragments.len() as u32;
        fragments.push(vec![(start + next_unreached) as u32]);
        queue.push_back(next_unreached);
    }
    for f in &mut fragments {
        f.sort_unstable();
    }
    fragments
}
