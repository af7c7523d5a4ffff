//! Rule 6 of the pair filter without the tree: the neighbouring triangles that still give
//! candidates.

use rayon::prelude::*;

use crate::mesh::filter::shared_corners;
use crate::mesh::star::StarView;
use crate::mesh::Topology;

/// The neighbouring triangle pairs `[s, t]` (`s < t`, sharing a vertex) that share no vertex
/// with a certified star (all of them without `stars`), each once (from its smallest shared
/// vertex), in vertex order, into `out`. Only the stars that failed are looked at.
pub(super) fn neighbours(
    stars: Option<StarView<'_>>,
    topo: &Topology,
    tris: &[[u32; 3]],
    out: &mut Vec<[u32; 2]>,
) {
    let certified = |v: u32| stars.is_some_and(|s| s.certified(v));
    let of = |v: u32| {
        let fan = topo.triangles_of(v);
        let mut pairs = Vec::new();
        if certified(v) {
            return pairs;
        }
        for (i, &s) in fan.iter().enumerate() {
            for &t in &fan[i + 1..] {
                let (a, b) = (tris[s as usize], tris[t as usize]);
                let equal = shared_corners(a, b);
                // Shared vertices, smallest first: `v` must be the smallest, and none certified.
                let shared = (0..3).filter(|&i| equal >> (3 * i) & 7 != 0).map(|i| a[i]);
                let mut first = u32::MAX;
                let mut any_certified = false;
                for w in shared {
                    first = first.min(w);
                    any_certified |= w != v && certified(w);
                }
                if first == v && !any_certified {
                    pairs.push([s, t]);
                }
            }
        }
        pairs
    };
    let n = topo.vertex_offsets.len().saturating_sub(1) as u32;
    out.par_extend(
        (0..n)
            .into_par_iter()
            .with_min_len(1 << 12)
            .flat_map_iter(of),
    );
}

