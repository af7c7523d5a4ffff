//! The collision set, as ipctk 1.6.1's `NormalCollisions::build` (IPC set type) makes it from
//! the pairs within `dhat + dmin`: each pair's closest-feature type at the current positions
//! reduces it to a vertex-vertex, edge-vertex, edge-edge or face-vertex collision, repeats are
//! merged with their weights summed, and nearly parallel edge pairs stay edge-edge with the
//! mollifier (threshold from the rest positions).
//!
//! A stand-in in the bindings until `topoccd::ipc` lands: see the crate's report.

use std::collections::HashMap;

use topoccd::ProximityReport;

use super::distance::{edge_edge_type, ee_distance2, point_edge_type, point_triangle_type};

/// One collision's stencil: kind (0 vv, 1 ev, 2 ee, 3 fv), its two ids as ipctk names them,
/// its vertices (`v`, then the primitive's), weight and, for edge-edge, the mollifier's
/// threshold and the closest-feature type cached at the build.
#[derive(Clone, Copy, Debug)]
pub struct Collision {
    pub kind: u8,
    pub ids: [u32; 2],
    pub verts: [u32; 4],
    pub weight: f64,
    pub eps_x: f64,
    pub dtype: u8,
}

impl Collision {
    pub fn nverts(&self) -> usize {
        [2, 3, 4, 4][self.kind as usize]
    }
}

/// The mesh as the build reads it.
pub struct MeshView<'a> {
    pub rest: &'a [f64],
    pub edges: &'a [[u32; 2]],
    pub faces: &'a [[u32; 3]],
    pub vertex_areas: &'a [f64],
    pub edge_areas: &'a [f64],
}

/// The collisions, kind by kind in ipctk's order (vv, ev, ee, fv).
#[derive(Default)]
pub struct Collisions {
    pub items: Vec<Collision>,
    pub counts: [usize; 4],
    pub dmin: f64,
    pub num_vertices: usize,
}

fn p3(x: &[f64], i: u32) -> [f64; 3] {
    let i = 3 * i as usize;
    [x[i], x[i + 1], x[i + 2]]
}

fn d2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum()
}

fn cross_norm2(ea0: [f64; 3], ea1: [f64; 3], eb0: [f64; 3], eb1: [f64; 3]) -> f64 {
    let u = [ea1[0] - ea0[0], ea1[1] - ea0[1], ea1[2] - ea0[2]];
    let v = [eb1[0] - eb0[0], eb1[1] - eb0[1], eb1[2] - eb0[2]];
    let c = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    c[0] * c[0] + c[1] * c[1] + c[2] * c[2]
}

#[derive(Default)]
struct Builder {
    vv: Vec<Collision>,
    vv_id: HashMap<(u32, u32), usize>,
    ev: Vec<Collision>,
    ev_id: HashMap<(u32, u32), usize>,
    ee: Vec<Collision>,
    fv: Vec<Collision>,
}

impl Builder {
    fn add_vv(&mut self, a: u32, b: u32, w: f64) {
        let key = (a.min(b), a.max(b));
        if let Some(&i) = self.vv_id.get(&key) {
            self.vv[i].weight += w;
            return;
        }
        self.vv_id.insert(key, self.vv.len());
        self.vv.push(Collision {
            kind: 0,
            ids: [a, b],
            verts: [a, b, 0, 0],
            weight: w,
            eps_x: 0.0,
            dtype: 0,
        });
    }

    fn add_ev(&mut self, edges: &[[u32; 2]], e: u32, v: u32, w: f64) {
        if let Some(&i) = self.ev_id.get(&(e, v)) {
            self.ev[i].weight += w;
            return;
        }
        self.ev_id.insert((e, v), self.ev.len());
        let [e0, e1] = edges[e as usize];
        self.ev.push(Collision {
            kind: 1,
            ids: [e, v],
            verts: [v, e0, e1, 0],
            weight: w,
            eps_x: 0.0,
            dtype: 2,
        });
    }
}

/// Error of a build: a pair names an edge the mesh does not list.
#[derive(Debug)]
pub struct MissingEdge(pub [u32; 2]);

/// Builds the set from a proximity report at positions `x` (flat), for `dhat` and `dmin`.
pub fn build(
    mesh: &MeshView<'_>,
    x: &[f64],
    report: &ProximityReport,
    dhat: f64,
    dmin: f64,
    area_weighting: bool,
) -> Result<Collisions, MissingEdge> {
    let active = (dmin + dhat) * (dmin + dhat);
    let edge_of: HashMap<(u32, u32), u32> = (mesh.edges.iter().enumerate())
        .map(|(i, e)| ((e[0].min(e[1]), e[0].max(e[1])), i as u32))
        .collect();
    let find = |a: u32, b: u32| {
        edge_of
            .get(&(a.min(b), a.max(b)))
            .copied()
            .ok_or(MissingEdge([a, b]))
    };
    let va = |v: u32| mesh.vertex_areas[v as usize];
    let ea = |e: u32| mesh.edge_areas[e as usize];
    let mut b = Builder::default();

    // Free point against free point.
    for p in &report.vv {
        if d2(p3(x, p.a), p3(x, p.b)) < active {
            let w = if area_weighting {
                0.5 * (va(p.a) + va(p.b))
            } else {
                1.0
            };
            b.add_vv(p.a, p.b, w);
        }
    }
    // Free point against free edge.
    for p in &report.ve {
        let e = find(p.edge[0], p.edge[1])?;
        let [e0, e1] = mesh.edges[e as usize];
        let (pv, q0, q1) = (p3(x, p.vertex), p3(x, e0), p3(x, e1));
        let t = point_edge_type(pv, q0, q1);
        let dist = super::distance::pe_distance2(pv, q0, q1, t);
        if dist >= active {
            continue;
        }
        let w = if area_weighting {
            0.5 * va(p.vertex)
        } else {
            1.0
        };
        match t {
            0 => b.add_vv(p.vertex, e0, w),
            1 => b.add_vv(p.vertex, e1, w),
            _ => b.add_ev(mesh.edges, e, p.vertex, w),
        }
    }
    // Edge against edge.
    for p in &report.ee {
        let (mut ia, mut ib) = (find(p.a[0], p.a[1])?, find(p.b[0], p.b[1])?);
        if ia > ib {
            std::mem::swap(&mut ia, &mut ib);
        }
        let [a0, a1] = mesh.edges[ia as usize];
        let [b0, b1] = mesh.edges[ib as usize];
        let (xa0, xa1, xb0, xb1) = (p3(x, a0), p3(x, a1), p3(x, b0), p3(x, b1));
        let actual = edge_edge_type(xa0, xa1, xb0, xb1);
        let dist = ee_distance2(xa0, xa1, xb0, xb1, actual);
        if dist >= active {
            continue;
        }
        let (r0, r1, s0, s1) = (
            p3(mesh.rest, a0),
            p3(mesh.rest, a1),
            p3(mesh.rest, b0),
            p3(mesh.rest, b1),
        );
        let eps_x = 1e-3 * d2(r0, r1) * d2(s0, s1);
        let t = if cross_norm2(xa0, xa1, xb0, xb1) < eps_x {
            8
        } else {
            actual
        };
        let w = if area_weighting {
            0.25 * (ea(ia) + ea(ib))
        } else {
            1.0
        };
        match t {
            0 => b.add_vv(a0, b0, w),
            1 => b.add_vv(a0, b1, w),
            2 => b.add_vv(a1, b0, w),
            3 => b.add_vv(a1, b1, w),
            4 => b.add_ev(mesh.edges, ia, b0, w),
            5 => b.add_ev(mesh.edges, ia, b1, w),
            6 => b.add_ev(mesh.edges, ib, a0, w),
            7 => b.add_ev(mesh.edges, ib, a1, w),
            _ => b.ee.push(Collision {
                kind: 2,
                ids: [ia, ib],
                verts: [a0, a1, b0, b1],
                weight: w,
                eps_x,
                dtype: actual,
            }),
        }
    }
    // Vertex against face.
    for p in &report.vf {
        let f = mesh.faces[p.face as usize];
        let (pv, t0, t1, t2) = (p3(x, p.vertex), p3(x, f[0]), p3(x, f[1]), p3(x, f[2]));
        let t = point_triangle_type(pv, t0, t1, t2);
        let dist = super::distance::pt_distance2(pv, t0, t1, t2, t);
        if dist >= active {
            continue;
        }
        let w = if area_weighting {
            0.25 * va(p.vertex)
        } else {
            1.0
        };
        match t {
            0..=2 => b.add_vv(p.vertex, f[t as usize], w),
            3..=5 => {
                let k = (t - 3) as usize;
                let e = find(f[k], f[(k + 1) % 3])?;
                b.add_ev(mesh.edges, e, p.vertex, w)
            }
            _ => b.fv.push(Collision {
                kind: 3,
                ids: [p.face, p.vertex],
                verts: [p.vertex, f[0], f[1], f[2]],
                weight: w,
                eps_x: 0.0,
                dtype: 6,
            }),
        }
    }
    let counts = [b.vv.len(), b.ev.len(), b.ee.len(), b.fv.len()];
    let mut items = b.vv;
    items.extend(b.ev);
    items.extend(b.ee);
    items.extend(b.fv);
    Ok(Collisions {
        items,
        counts,
        dmin,
        num_vertices: x.len() / 3,
    })
}

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
