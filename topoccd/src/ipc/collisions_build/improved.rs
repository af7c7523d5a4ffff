//! The corrections of the improved max approximation [Li et al. 2023] (ipctk's
//! `CollisionSetType::IMPROVED_MAX_APPROX`), added to the set of the plain build.
//!
//! The plain set sums a barrier per primitive pair, so one contact seen by several pairs is
//! counted several times: a vertex over an edge shared by two triangles is in two
//! vertex-face pairs, both reduced to the same edge-vertex collision. The improved
//! approximation subtracts the repeats, sub-pair by sub-pair, from the mesh's adjacency:
//!
//! - a vertex `v` near an edge `e` (from a vertex-face pair) whose edge has `k` triangles
//!   not containing `v`: `(1 - k)` times `v`'s weight on `(e, v)`;
//! - a vertex `p` near an edge `ea` (from an edge-edge pair) with `k` edges at `p` not
//!   touching `ea` and not nearly parallel to it: `(k - 1)` times `-ea`'s weight on
//!   `(ea, p)`, and each nearly parallel one gets a negative mollified edge-edge collision;
//! - two vertices close (from a vertex-face pair), neither adjacent to the other: `+1`
//!   times each one's weight, for each one not on the mesh's boundary;
//! - two vertices close (from a free point against a free edge): `(1 - k)` times each
//!   one's weight, `k` the other's neighbours but it.
//!
//! Each sub-pair counts once, and only when its own squared distance is below
//! `(dhat + dmin)^2`. A sub-pair's distance is never below its parent's, so every parent
//! is in the complete proximity report. The weights are those of the plain build: area
//! weights `0.5` (vertex against edge from points), `0.25` (vertex against face, edge
//! against edge) of the rest areas, or 1.

use std::collections::BTreeSet;

use super::super::mesh::IpcMesh;
use super::super::types::{mollifier_threshold, point_edge_sq, point_edge_type};
use super::Builder;
use crate::distance::{EdgeEdgeType, PointEdgeType};
use crate::ipc::CollisionOptions;
use crate::math::DVec3;
use crate::ProximityReport;

/// The adjacency the corrections read (ipctk's `CollisionMesh` adjacencies), each list
/// sorted and without repeats.
struct Adjacency {
    /// The vertices sharing an edge with each vertex.
    vertex_vertices: Vec<Vec<u32>>,
    /// The edges at each vertex.
    vertex_edges: Vec<Vec<u32>>,
    /// For each edge, the third corners of its triangles.
    edge_vertices: Vec<Vec<u32>>,
    /// A vertex is on the boundary unless one of its edges has two triangles or more.
    on_boundary: Vec<bool>,
}

impl Adjacency {
    fn new(n: usize, mesh: &IpcMesh, triangles: &[[u32; 3]]) -> Self {
        let mut vertex_vertices = vec![Vec::new(); n];
        let mut vertex_edges = vec![Vec::new(); n];
        for (i, &[a, b]) in mesh.edges.iter().enumerate() {
            vertex_vertices[a as usize].push(b);
            vertex_vertices[b as usize].push(a);
            vertex_edges[a as usize].push(i as u32);
            vertex_edges[b as usize].push(i as u32);
        }
        let mut edge_vertices = vec![Vec::new(); mesh.edges.len()];
        for (t, fe) in triangles.iter().zip(&mesh.face_edges) {
            for k in 0..3 {
                edge_vertices[fe[k] as usize].push(t[(k + 2) % 3]);
            }
        }
        for list in vertex_vertices
            .iter_mut()
            .chain(&mut vertex_edges)
            .chain(&mut edge_vertices)
        {
            list.sort_unstable();
            list.dedup();
        }
        let mut on_boundary = vec![true; n];
        for (e, opposite) in mesh.edges.iter().zip(&edge_vertices) {
            if opposite.len() >= 2 {
                on_boundary[e[0] as usize] = false;
                on_boundary[e[1] as usize] = false;
            }
        }
        Self {
            vertex_vertices,
            vertex_edges,
            edge_vertices,
            on_boundary,
        }
    }
}

/// Adds the improved max approximation's corrections for the pairs of `report` to `b`.
pub(super) fn add_corrections(
    b: &mut Builder,
    mesh: &IpcMesh,
    x: &[DVec3],
    rest: &[DVec3],
    triangles: &[[u32; 3]],
    report: &ProximityReport,
    options: &CollisionOptions,
) {
    let adj = Adjacency::new(x.len(), mesh, triangles);
    let r = options.dhat + options.dmin;
    let active = |d2: f64| d2 < r * r;
    let aw = options.use_area_weighting;
    // A vertex's or an edge's weight: `share` of its rest area, or 1 without area weighting.
    let va = |v: u32, share: f64| {
        if aw {
            share * mesh.vertex_area[v as usize]
        } else {
            1.0
        }
    };
    let ea_weight = |e: u32| {
        if aw {
            0.25 * mesh.edge_area[e as usize]
        } else {
            1.0
        }
    };
    let pe_sq = |v: u32, e: [u32; 2]| {
        let (p, e0, e1) = (x[v as usize], x[e[0] as usize], x[e[1] as usize]);
        point_edge_sq(p, e0, e1, point_edge_type(p, e0, e1))
    };
    let pp_sq = |a: u32, c: u32| (x[a as usize] - x[c as usize]).length_squared();
    let contains = |list: &[u32], v: u32| list.binary_search(&v).is_ok();

    // Free point against free edge: the vertex-vertex sub-pairs, negative.
    let mut vv_from_ev = BTreeSet::new();
    for p in &report.ve {
        for &e in &p.edge {
            if active(pp_sq(p.vertex, e)) {
                vv_from_ev.insert((p.vertex.min(e), p.vertex.max(e)));
            }
        }
    }
    for &(vi, vj) in &vv_from_ev {
        let mut w = 0.0;
        for (a, c) in [(vi, vj), (vj, vi)] {
            let near = &adj.vertex_vertices[c as usize];
            let k = near.len() - usize::from(contains(near, a));
            if k > 1 {
                w += (1.0 - k as f64) * va(a, 0.5);
            }
        }
        if w != 0.0 {
            b.add_vv(vi, vj, w);
        }
    }

    // Edge against edge: each edge with the other's endpoints.
    let mut ev_from_ee = BTreeSet::new();
    for p in &report.ee {
        let (ea, eb) = (mesh.edge(p.a[0], p.a[1]), mesh.edge(p.b[0], p.b[1]));
        for (ei, ej) in [(ea, eb), (eb, ea)] {
            let ends = mesh.edges[ei as usize];
            for &v in &mesh.edges[ej as usize] {
                if active(pe_sq(v, ends)) {
                    ev_from_ee.insert((ei, v));
                }
            }
        }
    }
    for &(ea, p) in &ev_from_ee {
        let a = mesh.edges[ea as usize];
        let w = -ea_weight(ea);
        let ty = point_edge_type(x[p as usize], x[a[0] as usize], x[a[1] as usize]);
        let mut unmollified = 0usize;
        for &eb in &adj.vertex_edges[p as usize] {
            let bb = mesh.edges[eb as usize];
            let q = if bb[0] == p { bb[1] } else { bb[0] };
            if q == a[0] || q == a[1] {
                continue;
            }
            let [ra0, ra1, rb0, rb1] = [a[0], a[1], bb[0], bb[1]].map(|v| rest[v as usize]);
            let eps_x = mollifier_threshold(ra0, ra1, rb0, rb1);
            let [xa0, xa1, xb0, xb1] = [a[0], a[1], bb[0], bb[1]].map(|v| x[v as usize]);
            if (xa1 - xa0).cross(xb1 - xb0).length_squared() >= eps_x {
                unmollified += 1;
                continue;
            }
            // Nearly parallel: a negative mollified edge-edge collision, typed by where p
            // is closest on ea.
            let at_b0 = p == bb[0];
            use EdgeEdgeType::*;
            let ee_ty = match (ty, at_b0) {
                (PointEdgeType::E0, true) => Ea0Eb0,
                (PointEdgeType::E0, false) => Ea0Eb1,
                (PointEdgeType::E1, true) => Ea1Eb0,
                (PointEdgeType::E1, false) => Ea1Eb1,
                (PointEdgeType::Interior, true) => EaEb0,
                (PointEdgeType::Interior, false) => EaEb1,
            };
            b.add_ee(mesh, ea, eb, a, bb, ee_ty, eps_x, w);
        }
        if unmollified != 1 {
            b.add_point_edge(ea, a, p, ty, (unmollified as f64 - 1.0) * w);
        }
    }

    // Vertex against face: the face's edges with the vertex, negative.
    let mut ev_from_fv = BTreeSet::new();
    let mut vv_from_fv = BTreeSet::new();
    for p in &report.vf {
        for &e in &mesh.face_edges[p.face as usize] {
            if active(pe_sq(p.vertex, mesh.edges[e as usize])) {
                ev_from_fv.insert((e, p.vertex));
            }
        }
        for &c in &triangles[p.face as usize] {
            if active(pp_sq(p.vertex, c)) {
                vv_from_fv.insert((p.vertex.min(c), p.vertex.max(c)));
            }
        }
    }
    for &(e, v) in &ev_from_fv {
        let opposite = &adj.edge_vertices[e as usize];
        let k = opposite.len() - usize::from(contains(opposite, v));
        if k > 1 {
            let ends = mesh.edges[e as usize];
            let ty = point_edge_type(x[v as usize], x[ends[0] as usize], x[ends[1] as usize]);
            b.add_point_edge(e, ends, v, ty, (1.0 - k as f64) * va(v, 0.25));
        }
    }
    // Vertex against face: the face's corners with the vertex, positive.
    for &(vi, vj) in &vv_from_fv {
        let mut w = 0.0;
        for (a, c) in [(vi, vj), (vj, vi)] {
            if adj.on_boundary[c as usize] || contains(&adj.vertex_vertices[c as usize], a) {
                continue;
            }
            w += va(a, 0.25);
        }
        if w != 0.0 {
            b.add_vv(vi, vj, w);
        }
    }
}

#[cfg(test)]
mod tests {
    //! Contacts that several primitive pairs see, with the weight each should have once
    //! counted (by hand from the approximation's definition): the plain set counts them
    //! once per pair, the improved one once.

    use crate::ipc::{CollisionOptions, CollisionSetType, NormalCollisions};
    use crate::{Ccd, Configuration};

    fn build(
        x: &[[f64; 3]],
        faces: &[[u32; 3]],
        free: &[[u32; 2]],
        set: CollisionSetType,
        area: bool,
    ) -> NormalCollisions {
        let config = Configuration::new(x, faces, free).unwrap();
        let options = CollisionOptions {
            dhat: 1e-2,
            use_area_weighting: area,
            collision_set_type: set,
            ..Default::default()
        };
        NormalCollisions::build(&mut Ccd::new(), &config, x, &options).unwrap()
    }

    #[test]
    fn a_point_over_a_shared_edge_counts_once() {
        // Two triangles folded down from their shared edge 0-1 (a ridge); a free point
        // 1e-3 above the ridge's middle, closest to the edge's interior in both.
        let x = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, -0.5],
            [0.5, -1.0, -0.5],
            [0.5, 0.0, 1e-3],
        ];
        let f = [[0, 1, 2], [1, 0, 3]];
        let plain = build(&x, &f, &[], CollisionSetType::Ipc, false);
        assert_eq!((plain.ev.len(), plain.ev[0].weight), (1, 2.0));
        let better = build(&x, &f, &[], CollisionSetType::ImprovedMaxApprox, false);
        assert_eq!(better.len(), 1);
        assert_eq!((better.ev[0].vertex, better.ev[0].weight), (4, 1.0));
        // Area weights: each vertex-face pair weighs a quarter of the free point's area (1).
        let better = build(&x, &f, &[], CollisionSetType::ImprovedMaxApprox, true);
        assert_eq!(better.ev[0].weight, 0.25);
    }

    #[test]
    fn a_point_over_the_centre_of_a_fan_counts_once() {
        // Six triangles around vertex 0, the apex of a cone; a free point 1e-3 above it,
        // closest to the apex in every triangle.
        let mut x = vec![[0.0, 0.0, 0.5]];
        for k in 0..6 {
            let a = k as f64 * std::f64::consts::PI / 3.0;
            x.push([a.cos(), a.sin(), 0.0]);
        }
        x.push([0.0, 0.0, 0.5 + 1e-3]);
        let f: Vec<[u32; 3]> = (0..6).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
        let plain = build(&x, &f, &[], CollisionSetType::Ipc, false);
        assert_eq!((plain.vv.len(), plain.vv[0].weight), (1, 6.0));
        // 6 pairs, minus one per spoke (each shared by two triangles), plus the point
        // against the interior vertex.
        let better = build(&x, &f, &[], CollisionSetType::ImprovedMaxApprox, false);
        assert_eq!(better.len(), 1);
        assert_eq!((better.vv[0].vertices, better.vv[0].weight), ([0, 7], 1.0));
    }

    #[test]
    fn a_polyline_corner_over_an_edge_counts_once() {
        // Edge 0-1 along x; a polyline 2-3-4 whose corner 3 is 1e-3 above the edge's
        // middle, its two edges rising away from it on either side.
        let x = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, -1.0, 1.0],
            [0.5, 0.0, 1e-3],
            [0.5, 1.0, 1.0],
        ];
        let e = [[0, 1], [2, 3], [3, 4]];
        let plain = build(&x, &[], &e, CollisionSetType::Ipc, false);
        assert_eq!((plain.ev.len(), plain.ev[0].weight), (1, 2.0));
        let better = build(&x, &[], &e, CollisionSetType::ImprovedMaxApprox, false);
        assert_eq!(better.len(), 1);
        assert_eq!((better.ev[0].edge, better.ev[0].vertex), ([0, 1], 3));
        assert_eq!(better.ev[0].weight, 1.0);
    }

    #[test]
    fn a_single_pair_is_unchanged() {
        // One triangle and a point over its interior: nothing is shared.
        let x = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.2, 0.2, 1e-3],
        ];
        let f = [[0, 1, 2]];
        for area in [false, true] {
            let plain = build(&x, &f, &[], CollisionSetType::Ipc, area);
            let better = build(&x, &f, &[], CollisionSetType::ImprovedMaxApprox, area);
            assert_eq!(plain.fv, better.fv);
            assert_eq!(better.len(), 1);
        }
    }
}
