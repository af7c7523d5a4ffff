//! The hierarchy of [`Method::Cluster`](crate::Method::Cluster) (section 4.3 of the paper):
//! k-DOPs of the triangles, of the leaf clusters and of the intermediate clusters, a tree over
//! the intermediate clusters whose leaves each carry a sub-tree over that cluster's leaf
//! clusters, and the hierarchies over a leaf cluster's triangles, built lazily.
//!
//! The two levels together are one hierarchy "built over the intermediate clusters, with leaf
//! clusters as its leaves": the top tree groups intermediate clusters, each sub-tree groups the
//! leaf clusters of one intermediate cluster. A traversal of the top tree against itself never
//! pairs an intermediate cluster with itself, so whole sub-trees inside one intermediate cluster
//! are pruned without a single test. Every volume is built once per step from the triangles'
//! swept k-DOPs, which are computed once and reused by the lazy hierarchies; no node array is
//! freed between steps.

use crate::bvh::{Bvh, BvhError, BvhWorkspace, Leaf};
use super::Clustering;
use crate::kdop::Kdop;

use crate::broad::triangle_volumes;
use crate::mesh::Step;

/// Marks a leaf cluster without a lazy hierarchy, or an intermediate cluster without sub-tree.
pub(crate) const NONE: u32 = u32::MAX;

/// The hierarchy of one step over its clusters, for k-DOPs of `H` slabs. Buffers are kept
/// across steps; nothing else is.
#[derive(Clone, Debug, Default)]
pub(crate) struct ClusterTree<const H: usize> {
    /// Swept k-DOP of each triangle, inflated by the minimum separation.
    pub tri: Vec<Kdop<H>>,
    /// Volume of each leaf cluster (the union of its triangles'), `id` = the leaf's index.
    pub leaf: Vec<Leaf<Kdop<H>>>,
    /// Volume of each intermediate cluster (the union of its leaves'), `id` = its index.
    pub ic: Vec<Leaf<Kdop<H>>>,
    /// The tree over the intermediate clusters.
    pub top: Bvh<Kdop<H>>,
    /// Slot in `subs` of each intermediate cluster's sub-tree, [`NONE`] for a single leaf.
    pub sub_of_ic: Vec<u32>,
    /// Sub-trees over the leaf clusters of intermediate clusters; the first `sub_count` are
    /// this step's, the rest are kept for their memory.
    subs: Vec<Bvh<Kdop<H>>>,
    sub_count: usize,
    /// Slot in `lazy` of each leaf cluster's triangle hierarchy, [`NONE`] if not built.
    lazy_of_leaf: Vec<u32>,
    /// Lazy hierarchies over leaf clusters' triangles (first `lazy_count` are this step's).
    lazy: Vec<Bvh<Kdop<H>>>,
    lazy_count: usize,
    /// Scratch: the leaves of the tree being built.
    scratch: Vec<Leaf<Kdop<H>>>,
}

impl<const H: usize> ClusterTree<H> {
    /// Computes the volumes of the triangles and clusters and builds the top tree and the
    /// sub-trees; forgets the lazy hierarchies of the previous step.
    pub fn build(&mut self, step: &Step, c: &Clustering, inflation: f64, ws: &mut BvhWorkspace) {
        triangle_volumes(step, inflation, &mut self.tri);
        let tri = &self.tri;
        self.leaf.clear();
        self.leaf.extend((0..c.leaves.len()).map(|l| {
            Leaf {
                id: l as u32,
                volume: c
                    .leaf_triangles(l)
                    .iter()
                    .fold(Kdop::EMPTY, |v, &t| v.merge(&tri[t as usize])),
            }
        }));
        let leaf = &self.leaf;
        self.ic.clear();
        self.ic.extend((0..c.intermediates.len()).map(|i| {
            Leaf {
                id: i as u32,
                volume: c
                    .intermediate_leaves(i)
                    .iter()
                    .fold(Kdop::EMPTY, |v, &l| v.merge(&leaf[l as usize].volume)),
            }
        }));
        self.top.rebuild(&self.ic, ws);

        self.sub_of_ic.clear();
        self.sub_count = 0;
        for i in 0..c.intermediates.len() {
            let members = c.intermediate_leaves(i);
            if members.len() < 2 {
                self.sub_of_ic.push(NONE);
                continue;
            }
            self.scratch.clear();
            self.scratch
                .extend(members.iter().map(|&l| self.leaf[l as usize]));
            if self.sub_count == self.subs.len() {
                self.subs.push(Bvh::new());
            }
            self.subs[self.sub_count].rebuild(&self.scratch, ws);
            self.sub_of_ic.push(self.sub_count as u32);
            self.sub_count += 1;
        }

        self.lazy_of_leaf.clear();
        self.lazy_of_leaf.resize(c.leaves.len(), NONE);
        self.lazy_count = 0;
    }

    /// The sub-tree of intermediate cluster `ic` (which must have two leaves or more).
    #[inline]
    pub fn sub(&self, ic: u32) -> &Bvh<Kdop<H>> {
        &self.subs[self.sub_of_ic[ic as usize] as usize]
    }

    /// Whether leaf cluster `leaf` has its triangle hierarchy this step.
    #[inline]
    pub fn has_lazy(&self, leaf: u32) -> bool {
        self.lazy_of_leaf[leaf as usize] != NONE
    }

    /// Builds the hierarchy over the triangles of leaf cluster `leaf` unless built already this
    /// step. Returns whether it built one.
    pub fn ensure_lazy(&mut self, c: &Clustering, leaf: u32, ws: &mut BvhWorkspace) -> bool {
        if self.has_lazy(leaf) {
            return false;
        }
        self.scratch.clear();
        let tri = &self.tri;
        self.scratch
            .extend(c.leaf_triangles(leaf as usize).iter().map(|&t| Leaf {
                id: t,
                volume: tri[t as usize],
            }));
        if self.lazy_count == self.lazy.len() {
            self.lazy.push(Bvh::new());
        }
        self.lazy[self.lazy_count].rebuild(&self.scratch, ws);
        self.lazy_of_leaf[leaf as usize] = self.lazy_count as u32;
        self.lazy_count += 1;
        true
    }

    /// The lazy hierarchy of leaf cluster `leaf`, built by [`ClusterTree::ensure_lazy`].
    #[inline]
    pub fn lazy(&self, leaf: u32) -> &Bvh<Kdop<H>> {
        let slot = self.lazy_of_leaf[leaf as usize];
        debug_assert_ne!(slot, NONE, "leaf cluster {leaf} has no lazy hierarchy");
        &self.lazy[slot as usize]
    }

    /// Checks every tree of the step against its leaves: the top tree, the sub-trees and the
    /// lazy hierarchies built, and that the volumes of the clusters contain their parts'.
    pub fn validate(&self, c: &Clustering) -> Result<(), BvhError> {
        self.top.validate(&self.ic)?;
        for (i, ic) in self.ic.iter().enumerate() {
            let members = c.intermediate_leaves(i);
            for &l in members {
                let leaf = &self.leaf[l as usize];
                if !ic.volume.contains(&leaf.volume) {
                    return Err(BvhError::BadLeaf { id: leaf.id });
                }
            }
            let slot = self.sub_of_ic[i];
            if slot != NONE {
                let leaves: Vec<_> = members.iter().map(|&l| self.leaf[l as usize]).collect();
                self.subs[slot as usize].validate(&leaves)?;
            }
        }
        for (l, &slot) in self.lazy_of_leaf.iter().enumerate() {
            let tris: Vec<_> = c
                .leaf_triangles(l)
                .iter()
                .map(|&t| Leaf {
                    id: t,
                    volume: self.tri[t as usize],
                })
                .collect();
            if tris
                .iter()
                .any(|t| !self.leaf[l].volume.contains(&t.volume))
            {
                return Err(BvhError::BadLeaf { id: l as u32 });
            }
            if slot != NONE {
                self.lazy[slot as usize].validate(&tris)?;
            }
        }
        Ok(())
    }
}
