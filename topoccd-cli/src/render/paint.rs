//! What colour each triangle gets, and which of its edges are outlined: by object, by cluster,
//! or by contact.

use super::palette::{categorical, CONTACT, NEUTRAL};
use topoccd::broad::cluster::Clustering;
use topoccd::mesh::Topology;

/// How one triangle is drawn (before shading).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TriangleStyle {
    /// Base colour, lit by [`shade`](super::palette::shade).
    pub color: [u8; 3],
    /// Which edges get a dark outline: edge `k` joins vertex `k` to vertex `(k + 1) % 3`.
    pub outline: [bool; 3],
}

impl TriangleStyle {
    /// A plain triangle of colour `color`.
    pub fn plain(color: [u8; 3]) -> Self {
        Self {
            color,
            outline: [false; 3],
        }
    }
}

/// The connected components of the triangles, linked through shared vertices: the component of
/// each triangle, numbered from 0 in the order of their lowest triangle, and their number.
pub fn connected_components(triangles: &[[u32; 3]], vertex_count: usize) -> (Vec<u32>, usize) {
    // Union-find over vertices, with path halving and union by smaller root (deterministic).
    let mut parent: Vec<u32> = (0..vertex_count as u32).collect();
    fn find(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            let grand = parent[parent[v as usize] as usize];
            parent[v as usize] = grand;
            v = grand;
        }
        v
    }
    for tri in triangles {
        let valid = tri.iter().all(|&v| (v as usize) < vertex_count);
        debug_assert!(valid, "triangle {tri:?} out of range");
        if !valid {
            continue;
        }
        for k in 1..3 {
            let (a, b) = (find(&mut parent, tri[0]), find(&mut parent, tri[k]));
            if a != b {
                parent[a.max(b) as usize] = a.min(b);
            }
        }
    }
    let mut id_of_root = vec![u32::MAX; vertex_count];
    let mut count = 0u32;
    let ids = triangles
        .iter()
        .map(|tri| {
            if (tri[0] as usize) >= vertex_count {
                return 0;
            }
            let root = find(&mut parent, tri[0]) as usize;
            if id_of_root[root] == u32::MAX {
                id_of_root[root] = count;
                count += 1;
            }
            id_of_root[root]
        })
        .collect();
    (ids, count as usize)
}

/// One colour per connected component (see [`connected_components`]), no outlines.
pub fn paint_objects(component_of_triangle: &[u32]) -> Vec<TriangleStyle> {
    component_of_triangle
        .iter()
        .map(|&c| TriangleStyle::plain(categorical(c)))
        .collect()
}

/// One colour per leaf cluster; outlined edges are those between two intermediate clusters
/// (some triangle on the edge lies in another intermediate cluster than the rest) and the
/// boundary edges (in one triangle only), like the paper's figures 4 and 5.
pub fn paint_clusters(clustering: &Clustering, topo: &Topology) -> Vec<TriangleStyle> {
    let intermediate_of = |t: usize| {
        let leaf = clustering.leaf_of_triangle[t] as usize;
        clustering.intermediate_of_leaf[leaf]
    };
    // Per edge: number of triangles, the first one's intermediate cluster, whether they differ.
    let mut uses = vec![0u32; topo.edges.len()];
    let mut first = vec![u32::MAX; topo.edges.len()];
    let mut mixed = vec![false; topo.edges.len()];
    for (t, edges) in topo.triangle_edges.iter().enumerate() {
        let ic = intermediate_of(t);
        for &e in edges {
            let e = e as usize;
            uses[e] += 1;
            if first[e] == u32::MAX {
                first[e] = ic;
            } else if first[e] != ic {
                mixed[e] = true;
            }
        }
    }
    topo.triangle_edges
        .iter()
        .enumerate()
        .map(|(t, edges)| TriangleStyle {
            color: categorical(clustering.leaf_of_triangle[t]),
            outline: edges.map(|e| uses[e as usize] == 1 || mixed[e as usize]),
        })
        .collect()
}

/// Triangles involved in a contact in red, the others in light grey, no outlines.
pub fn paint_contacts(involved: &[bool]) -> Vec<TriangleStyle> {
    involved
        .iter()
        .map(|&hit| TriangleStyle::plain(if hit { CONTACT } else { NEUTRAL }))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use topoccd::broad::cluster::{cluster, ClusterOptions};
    use topoccd::math::DVec3;
    use topoccd::Step;

    #[test]
    fn components_through_shared_vertices_only() {
        // Two triangles sharing vertex 2, one apart, one touching the first only by position.
        let tris = [[0, 1, 2], [2, 3, 4], [5, 6, 7], [7, 8, 5]];
        let (ids, n) = connected_components(&tris, 10);
        assert_eq!((ids, n), (vec![0, 0, 1, 1], 2));
        let (ids, n) = connected_components(&[[4, 5, 6], [0, 1, 2], [6, 7, 8]], 9);
        assert_eq!((ids, n), (vec![0, 1, 0], 2));
        assert_eq!(connected_components(&[], 3), (vec![], 0));
    }

    #[test]
    fn cluster_outlines_lie_on_the_boundary_and_between_intermediate_clusters() {
        // A flat 6x6 grid: one intermediate cluster, so only the boundary is outlined.
        let n = 7u32;
        let x: Vec<DVec3> = (0..n * n)
            .map(|i| DVec3::new(f64::from(i % n), f64::from(i / n), 0.0))
            .collect();
        let mut tris = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let v = j * n + i;
                tris.push([v, v + 1, v + n + 1]);
                tris.push([v, v + n + 1, v + n]);
            }
        }
        let step = Step::new(x.clone(), x, tris).unwrap();
        let topo = Topology::new(step.triangles(), step.vertex_count());
        let mut clustering = cluster(&step, &topo, &ClusterOptions::default());
        let styles = paint_clusters(&clustering, &topo);
        let boundary = |[a, b]: [u32; 2]| {
            let on = |v: u32, c: u32| v % n == c || v / n == c;
            (on(a, 0) && on(b, 0)) || (on(a, n - 1) && on(b, n - 1))
        };
        let outlined_edges = |styles: &[TriangleStyle]| {
            let mut edges: Vec<u32> = Vec::new();
            for (t, s) in styles.iter().enumerate() {
                for k in 0..3 {
                    if s.outline[k] {
                        edges.push(topo.triangle_edges[t][k]);
                    }
                }
            }
            edges
        };
        if clustering.intermediates.len() == 1 {
            let edges = outlined_edges(&styles);
            assert_eq!(edges.len(), 24);
            assert!(edges.iter().all(|&e| boundary(topo.edges[e as usize])));
        }
        // Split into two intermediate clusters by hand: the edges between them get outlined.
        let left = |t: usize| step.triangles()[t].iter().all(|&v| v % n <= 3);
        clustering.leaf_of_triangle = (0..step.triangles().len() as u32).collect();
        clustering.intermediate_of_leaf = (0..step.triangles().len())
            .map(|t| u32::from(!left(t)))
            .collect();
        let edges = outlined_edges(&paint_clusters(&clustering, &topo));
        let inner: Vec<u32> = edges
            .into_iter()
            .filter(|&e| !boundary(topo.edges[e as usize]))
            .collect();
        // The cut runs along x = 3 (six edges), each drawn from both sides.
        assert_eq!(inner.len(), 12);
        assert!(inner.iter().all(|&e| {
            let [a, b] = topo.edges[e as usize];
            a % n == 3 && b % n == 3
        }));
        assert_eq!(styles.len(), step.triangles().len());
    }

    #[test]
    fn contacts_in_red_over_grey() {
        let s = paint_contacts(&[true, false]);
        assert_eq!(
            s,
            [TriangleStyle::plain(CONTACT), TriangleStyle::plain(NEUTRAL)]
        );
    }
}
