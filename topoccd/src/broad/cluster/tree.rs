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

use crate::broad::triangle_volumes;
use crate::bvh::{Bvh, BvhError, BvhWorkspace, Leaf};
use super::{Clustering, GrownLeaf};
use crate::kdop::Kdop;

use crate::mesh::Step;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Receiver;

/// Rebuilds `bvh` over `triangles`, triangle `t` a leaf with the volume `tri[t]` (a leaf
/// cluster's lazy hierarchy, whether built ahead or when needed); `items` and `ws` are scratch.
fn rebuild_over<const H: usize>(
    bvh: &mut Bvh<Kdop<H>>,
    tri: &[Kdop<H>],
    triangles: &[u32],
    items: &mut Vec<Leaf<Kdop<H>>>,
    ws: &mut BvhWorkspace,
) {
    items.clear();
    items.extend(triangles.iter().map(|&t| Leaf {
        id: t,
        volume: tri[t as usize],
    }));
    bvh.rebuild(items, ws);
}

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
    /// Scratch: the intermediate clusters with a sub-tree, by slot.
    scratch_ids: Vec<u32>,
    /// Hierarchies over leaf clusters' triangles built ahead, while the clustering grew
    /// ([`ClusterTree::build_ahead`]), by increasing leaf id; [`ClusterTree::build_lazies`]
    /// takes those it needs and drops the rest.
    ahead: Vec<(u32, Bvh<Kdop<H>>)>,
    /// Scratch of [`ClusterTree::build_ahead`].
    ahead_left: Vec<(u32, Bvh<Kdop<H>>)>,
}

impl<const H: usize> ClusterTree<H> {
    /// Computes the volumes of the step's triangles swept over `[0, tmax]`, inflated by
    /// `inflation`, on the rayon pool. They do not depend on the clustering, so this may run
    /// while it grows.
    pub fn sweep(&mut self, step: &Step, (tmax, inflation): (f64, f64)) {
        triangle_volumes(step, (tmax, inflation), &mut self.tri);
    }

    /// Builds, ahead of need, the hierarchy over the triangles of each leaf cluster received
    /// (as [`build_lazies`](ClusterTree::build_lazies) would build it, from the volumes of
    /// [`ClusterTree::sweep`], which must have run on this step), until the channel closes:
    /// one at a time while the clustering grows, then, once `grown` is set, those left in
    /// parallel.
    pub fn build_ahead(&mut self, leaves: Receiver<GrownLeaf>, grown: &AtomicBool) {
        self.ahead.clear();
        let tri = &self.tri;
        let build = |(items, ws): &mut (Vec<Leaf<Kdop<H>>>, BvhWorkspace), triangles: &[u32]| {
            let mut bvh = Bvh::new();
            rebuild_over(&mut bvh, tri, triangles, items, ws);
            bvh
        };
        let mut scratch = (Vec::new(), BvhWorkspace::default());
        while !grown.load(Ordering::Acquire) {
            let Ok((leaf, triangles)) = leaves.recv() else {
                return;
            };
            self.ahead.push((leaf, build(&mut scratch, &triangles)));
        }
        let left: Vec<GrownLeaf> = leaves.iter().collect();
        left.into_par_iter()
            .map_init(
                || (Vec::new(), BvhWorkspace::default()),
                |scratch, (leaf, triangles)| (leaf, build(scratch, &triangles)),
            )
            .collect_into_vec(&mut self.ahead_left);
        self.ahead.append(&mut self.ahead_left);
    }

    /// Computes the volumes of the clusters from those of the triangles ([`ClusterTree::sweep`],
    /// which must have run on this step) and builds the top tree and the sub-trees, on the
    /// rayon pool (the same trees for any thread count); forgets the lazy hierarchies of the
    /// previous step.
    pub fn build(&mut self, c: &Clustering, ws: &mut BvhWorkspace) {
        debug_assert_eq!(self.tri.len(), c.leaf_of_triangle.len());
        let tri = &self.tri;
        (0..c.leaves.len())
            .into_par_iter()
            .with_min_len(256)
            .map(|l| Leaf {
                id: l as u32,
                volume: c
                    .leaf_triangles(l)
                    .iter()
                    .fold(Kdop::EMPTY, |v, &t| v.merge(&tri[t as usize])),
            })
            .collect_into_vec(&mut self.leaf);
        let leaf = &self.leaf;
        (0..c.intermediates.len())
            .into_par_iter()
            .with_min_len(256)
            .map(|i| Leaf {
                id: i as u32,
                volume: c
                    .intermediate_leaves(i)
                    .iter()
                    .fold(Kdop::EMPTY, |v, &l| v.merge(&leaf[l as usize].volume)),
            })
            .collect_into_vec(&mut self.ic);
        self.top.rebuild(&self.ic, ws);

        // Sub-trees: slots in order of the intermediate clusters, built in parallel.
        self.sub_of_ic.clear();
        self.scratch_ids.clear();
        for i in 0..c.intermediates.len() {
            if c.intermediate_leaves(i).len() < 2 {
                self.sub_of_ic.push(NONE);
            } else {
                self.sub_of_ic.push(self.scratch_ids.len() as u32);
                self.scratch_ids.push(i as u32);
            }
        }
        self.sub_count = self.scratch_ids.len();
        if self.subs.len() < self.sub_count {
            self.subs.resize_with(self.sub_count, Bvh::new);
        }
        let leaf = &self.leaf;
        self.subs[..self.sub_count]
            .par_iter_mut()
            .zip(self.scratch_ids.par_iter())
            .with_min_len(16)
            .for_each_init(
                || (Vec::new(), BvhWorkspace::default()),
                |(leaves, ws), (sub, &i)| {
                    leaves.clear();
                    leaves.extend(
                        c.intermediate_leaves(i as usize)
                            .iter()
                            .map(|&l| leaf[l as usize]),
                    );
                    sub.rebuild(leaves, ws);
                },
            );

        self.lazy_of_leaf.clear();
        self.lazy_of_leaf.resize(c.leaves.len(), NONE);
        self.lazy_count = 0;
    }

    /// The sub-tree of intermediate cluster `ic` (which must have two leaves or more).
    #[inline]
    pub fn sub(&self, ic: u32) -> &Bvh<Kdop<H>> {
        &self.subs[self.sub_of_ic[ic as usize] as usize]
    }

    /// Builds the hierarchies over the triangles of the leaf clusters `needed` (increasing,
    /// none built yet this step), in parallel, taking those built ahead instead where there are;
    /// slots in the order of `needed`, so the same trees for any thread count. Returns how many
    /// were taken from those built ahead (whose others are dropped).
    pub fn build_lazies(&mut self, c: &Clustering, needed: &[u32]) -> usize {
        debug_assert!(needed.windows(2).all(|w| w[0] < w[1]));
        let first = self.lazy_count;
        for (k, &l) in needed.iter().enumerate() {
            debug_assert_eq!(self.lazy_of_leaf[l as usize], NONE);
            self.lazy_of_leaf[l as usize] = (first + k) as u32;
        }
        self.lazy_count += needed.len();
        if self.lazy.len() < self.lazy_count {
            self.lazy.resize_with(self.lazy_count, Bvh::new);
        }
        // The hierarchies built ahead (the same trees), swapped in; the rest built here.
        let mut built = vec![false; needed.len()];
        for (leaf, bvh) in &mut self.ahead {
            if let Ok(k) = needed.binary_search(leaf) {
                std::mem::swap(&mut self.lazy[first + k], bvh);
                built[k] = true;
            }
        }
        self.ahead.clear();
        let ahead = built.iter().filter(|&&b| b).count();
        let tri = &self.tri;
        self.lazy[first..self.lazy_count]
            .par_iter_mut()
            .zip(needed.par_iter())
            .zip(built.par_iter())
            .with_min_len(4)
            .filter(|(_, &built)| !built)
            .map(|(pair, _)| pair)
            .for_each_init(
                || (Vec::new(), BvhWorkspace::default()),
                |(leaves, ws), (bvh, &l)| {
                    rebuild_over(bvh, tri, c.leaf_triangles(l as usize), leaves, ws);
                },
            );
        ahead
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
