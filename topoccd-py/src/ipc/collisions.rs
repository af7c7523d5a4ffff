//! The library's collision set (`topoccd::ipc::NormalCollisions`) seen as ipctk names it:
//! edge ids into the mesh's own `edges`, weights and mollifier thresholds, for
//! `topoccd.ipc`'s collision objects; and the map from the library's edge ids to the
//! mesh's, for the tangential collisions' ids.

use std::collections::HashMap;

use topoccd::ProximityReport;

/// One collision: kind (0 vv, 1 ev, 2 ee, 3 fv), its two ids as ipctk names them, weight
/// and, for edge-edge, the mollifier's threshold.
#[derive(Clone, Copy, Debug)]
pub struct Collision {
    pub kind: u8,
    pub ids: [u32; 2],
    pub weight: f64,
    pub eps_x: f64,
}

/// The mesh's edges, as the candidates name them.
pub struct MeshView<'a> {
    pub edges: &'a [[u32; 2]],
}

/// The collisions, kind by kind in ipctk's order (vv, ev, ee, fv).
#[derive(Default)]
pub struct Collisions {
    pub items: Vec<Collision>,
    pub counts: [usize; 4],
    pub dmin: f64,
    pub num_vertices: usize,
    /// The mesh's edge id of each of the library's edges (`core.edges`), `u32::MAX` for
    /// one the mesh does not list.
    pub edge_map: Vec<u32>,
}

/// Error of a conversion: a collision names an edge the mesh does not list.
#[derive(Debug)]
pub struct MissingEdge(pub [u32; 2]);

/// The raw pairs of a report as ipctk's candidates name them: vv `(a, b)`, ev
/// `(edge, vertex)`, ee `(edge, edge)`, fv `(face, vertex)` (pairs naming an unknown edge are
/// skipped: the build reports them).
pub fn candidate_ids(mesh: &MeshView<'_>, report: &ProximityReport) -> [Vec<[u32; 2]>; 4] {
    let edge_of: HashMap<(u32, u32), u32> = (mesh.edges.iter().enumerate())
        .map(|(i, e)| ((e[0].min(e[1]), e[0].max(e[1])), i as u32))
        .collect();
    let find = |a: u32, b: u32| edge_of.get(&(a.min(b), a.max(b))).copied();
    let vv = report.vv.iter().map(|p| [p.a, p.b]).collect();
    let ev = (report.ve.iter())
        .filter_map(|p| Some([find(p.edge[0], p.edge[1])?, p.vertex]))
        .collect();
    let ee = (report.ee.iter())
        .filter_map(|p| {
            let (a, b) = (find(p.a[0], p.a[1])?, find(p.b[0], p.b[1])?);
            Some([a.min(b), a.max(b)])
        })
        .collect();
    let fv = report.vf.iter().map(|p| [p.face, p.vertex]).collect();
    [vv, ev, ee, fv]
}

/// The mesh's edge id of each of the library's edges (`u32::MAX` for one the mesh does not
/// list).
pub fn edge_map(mesh_edges: &[[u32; 2]], core_edges: &[[u32; 2]]) -> Vec<u32> {
    let edge_of: HashMap<(u32, u32), u32> = (mesh_edges.iter().enumerate())
        .map(|(i, e)| ((e[0].min(e[1]), e[0].max(e[1])), i as u32))
        .collect();
    (core_edges.iter())
        .map(|e| {
            let key = (e[0].min(e[1]), e[0].max(e[1]));
            edge_of.get(&key).copied().unwrap_or(u32::MAX)
        })
        .collect()
}

/// The library's collisions with the mesh's own edge ids (ipctk's ids index the mesh's
/// `edges`), through `edge_map` (of [`edge_map`]).
pub fn from_core(
    core: &topoccd::ipc::NormalCollisions,
    edge_map: Vec<u32>,
    num_vertices: usize,
) -> Result<Collisions, MissingEdge> {
    let find = |id: u32| match edge_map[id as usize] {
        u32::MAX => Err(MissingEdge(core.edges[id as usize])),
        e => Ok(e),
    };
    let mut items = Vec::with_capacity(core.len());
    for c in &core.vv {
        items.push(Collision {
            kind: 0,
            ids: c.vertices,
            weight: c.weight,
            eps_x: 0.0,
        });
    }
    for c in &core.ev {
        items.push(Collision {
            kind: 1,
            ids: [find(c.edge_id)?, c.vertex],
            weight: c.weight,
            eps_x: 0.0,
        });
    }
    for c in &core.ee {
        items.push(Collision {
            kind: 2,
            ids: [find(c.edge_ids[0])?, find(c.edge_ids[1])?],
            weight: c.weight,
            eps_x: c.eps_x,
        });
    }
    for c in &core.fv {
        items.push(Collision {
            kind: 3,
            ids: [c.face, c.vertex],
            weight: c.weight,
            eps_x: 0.0,
        });
    }
    let counts = [core.vv.len(), core.ev.len(), core.ee.len(), core.fv.len()];
    Ok(Collisions {
        items,
        counts,
        dmin: core.dmin,
        num_vertices,
        edge_map,
    })
}
