//! The leaves' features laid out in the hierarchy's leaf order, so that the leaf pairs of a
//! traversal, which come in spatial order, read memory that is close together: per leaf, its
//! vertices and the ranges of the vertices and edges it owns, with their boxes (recomputed
//! every query). Arranged again whenever the hierarchy is built.

use crate::bvh::Bvh;
use crate::math::DVec3;

use super::boxes::{inflated, Box3};
use super::primitives::{Kind, Primitives};

/// One leaf, at its place in the hierarchy's order.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Slot {
    pub kind: Kind,
    /// The leaf's id (a triangle's id is its index).
    pub id: u32,
    /// The leaf's vertices (unused ones `u32::MAX`).
    pub verts: [u32; 3],
    /// The vertices it owns: `Slots::verts[v0..v0 + nv]`.
    pub v0: u32,
    pub nv: u32,
    /// The edges it owns: `Slots::edges[e0..e0 + ne]`.
    pub e0: u32,
    pub ne: u32,
}

/// The leaves in the hierarchy's order and the features they own, with boxes.
#[derive(Clone, Debug, Default)]
pub(crate) struct Slots {
    /// Leaf id to its place in `slots`.
    pub slot_of: Vec<u32>,
    pub slots: Vec<Slot>,
    /// The owned vertices, leaf by leaf.
    pub verts: Vec<u32>,
    /// The owned edges (`[i, j]`, `i < j`), leaf by leaf.
    pub edges: Vec<[u32; 2]>,
    /// Each leaf's box (this query's).
    pub lbox: Vec<Box3>,
    /// Each owned vertex's box.
    pub vbox: Vec<Box3>,
    /// Each owned edge's box.
    pub ebox: Vec<Box3>,
}

impl Slots {
    /// Lays the leaves out in the order of `bvh`'s leaf nodes.
    pub fn arrange(&mut self, prims: &Primitives, bvh: &Bvh<Box3>) {
        let n = prims.leaves.len();
        self.slot_of.clear();
        self.slot_of.resize(n, u32::MAX);
        self.slots.clear();
        self.verts.clear();
        self.edges.clear();
        let order = bvh.nodes().iter().filter_map(|node| node.leaf());
        for id in order {
            let l = &prims.leaves[id as usize];
            self.slot_of[id as usize] = self.slots.len() as u32;
            self.slots.push(Slot {
                kind: l.kind,
                id,
                verts: l.verts,
                v0: self.verts.len() as u32,
                nv: u32::from(l.nv),
                e0: self.edges.len() as u32,
                ne: u32::from(l.ne),
            });
            self.verts.extend_from_slice(&l.owned_v[..l.nv as usize]);
            (self.edges).extend(
                l.owned_e[..l.ne as usize]
                    .iter()
                    .map(|&e| prims.edges[e as usize]),
            );
        }
        debug_assert_eq!(self.slots.len(), n);
    }

    /// This query's boxes at positions `x`, inflated by `h`.
    pub fn fit(&mut self, x: &[DVec3], h: f64) {
        let p = |v: u32| x[v as usize];
        self.lbox.clear();
        self.lbox.extend(self.slots.iter().map(|s| match s.kind {
            Kind::Triangle => inflated(&s.verts.map(p), h),
            Kind::Edge => inflated(&[p(s.verts[0]), p(s.verts[1])], h),
            Kind::Point => inflated(&[p(s.verts[0])], h),
        }));
        self.vbox.clear();
        self.vbox
            .extend(self.verts.iter().map(|&v| inflated(&[p(v)], h)));
        self.ebox.clear();
        (self.ebox).extend(self.edges.iter().map(|e| inflated(&e.map(p), h)));
    }
}
