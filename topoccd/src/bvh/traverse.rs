//! Traversals: all overlapping leaf pairs of one tree, or of two trees.

use super::{BoundingVolume, Bvh, BvhWorkspace, Node};

impl<V: BoundingVolume> Bvh<V> {
    /// Calls `leaf_pair(a, b)` for every unordered pair of distinct leaves whose volumes
    /// overlap, each pair once (in a deterministic order, with `a` and `b` in no particular
    /// order), never a leaf with itself. Returns the number of bounding-volume overlap tests.
    ///
    /// ```
    /// use topoccd::bvh::{Bvh, Leaf};
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// // Four points on a line, volumes of radius 0.6 around x = 0, 1, 2, 5.
    /// let leaves: Vec<_> = [0.0, 1.0, 2.0, 5.0]
    ///     .iter()
    ///     .enumerate()
    ///     .map(|(i, &x)| {
    ///         let mut volume = Kdop::<9>::from_point(DVec3::new(x, 0.0, 0.0));
    ///         volume.inflate(0.6);
    ///         Leaf { id: i as u32, volume }
    ///     })
    ///     .collect();
    /// let bvh = Bvh::from_leaves(&leaves);
    /// let mut pairs = Vec::new();
    /// bvh.self_pairs(&mut Default::default(), |a, b| pairs.push((a.min(b), a.max(b))));
    /// pairs.sort();
    /// assert_eq!(pairs, vec![(0, 1), (1, 2)]);
    /// ```
    pub fn self_pairs(&self, ws: &mut BvhWorkspace, mut leaf_pair: impl FnMut(u32, u32)) -> u64 {
        let nodes = &self.nodes[..];
        let mut tests = 0u64;
        if nodes.is_empty() {
            return 0;
        }
        let stack = &mut ws.pairs;
        stack.clear();
        stack.push((0, 0));
        while let Some((a, b)) = stack.pop() {
            if a == b {
                // A subtree against itself: each child against itself, and the two children.
                if let Some([l, r]) = nodes[a as usize].children() {
                    stack.push((l, r));
                    stack.push((r, r));
                    stack.push((l, l));
                }
                continue;
            }
            tests += 1;
            descend(nodes, nodes, a, b, stack, &mut leaf_pair);
        }
        tests
    }

    /// Calls `leaf(id)` for every leaf whose volume overlaps `volume`, each once, in a
    /// deterministic order. Returns the number of bounding-volume overlap tests. The query of
    /// one volume against a tree, for a caller that has a few volumes and no tree of its own.
    ///
    /// ```
    /// use topoccd::bvh::{Bvh, Leaf};
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let leaves: Vec<_> = [0.0, 2.0, 4.0]
    ///     .iter()
    ///     .enumerate()
    ///     .map(|(i, &x)| Leaf {
    ///         id: i as u32,
    ///         volume: Kdop::<3>::from_points(&[DVec3::splat(x), DVec3::splat(x + 1.0)]),
    ///     })
    ///     .collect();
    /// let bvh = Bvh::from_leaves(&leaves);
    /// let probe = Kdop::<3>::from_points(&[DVec3::splat(1.5), DVec3::splat(4.5)]);
    /// let mut hits = Vec::new();
    /// bvh.volume_leaves(&probe, &mut Default::default(), |id| hits.push(id));
    /// assert_eq!(hits, vec![1, 2]);
    /// ```
    pub fn volume_leaves(
        &self,
        volume: &V,
        ws: &mut BvhWorkspace,
        mut leaf: impl FnMut(u32),
    ) -> u64 {
        let nodes = &self.nodes[..];
        let mut tests = 0u64;
        if nodes.is_empty() {
            return 0;
        }
        let stack = &mut ws.pairs;
        stack.clear();
        stack.push((0, 0));
        while let Some((n, _)) = stack.pop() {
            tests += 1;
            let node = &nodes[n as usize];
            if !node.volume.overlaps(volume) {
                continue;
            }
            match node.children() {
                None => leaf(node.a),
                Some([l, r]) => {
                    stack.push((r, 0));
                    stack.push((l, 0));
                }
            }
        }
        tests
    }

    /// Calls `leaf_pair(a, b)` for every leaf `a` of `self` and leaf `b` of `other` whose
    /// volumes overlap, each pair once, in a deterministic order. Returns the number of
    /// bounding-volume overlap tests.
    ///
    /// ```
    /// use topoccd::bvh::{Bvh, Leaf};
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let boxes = |xs: &[f64]| -> Vec<Leaf<Kdop<3>>> {
    ///     xs.iter().enumerate().map(|(i, &x)| Leaf {
    ///         id: i as u32,
    ///         volume: Kdop::from_points(&[DVec3::splat(x), DVec3::splat(x + 1.0)]),
    ///     }).collect()
    /// };
    /// let a = Bvh::from_leaves(&boxes(&[0.0, 3.0]));
    /// let b = Bvh::from_leaves(&boxes(&[10.0, 3.5, 0.5]));
    /// let mut pairs = Vec::new();
    /// a.tree_pairs(&b, &mut Default::default(), |x, y| pairs.push((x, y)));
    /// pairs.sort();
    /// assert_eq!(pairs, vec![(0, 2), (1, 1)]);
    /// ```
    pub fn tree_pairs(
        &self,
        other: &Bvh<V>,
        ws: &mut BvhWorkspace,
        mut leaf_pair: impl FnMut(u32, u32),
    ) -> u64 {
        let (na, nb) = (&self.nodes[..], &other.nodes[..]);
        let mut tests = 0u64;
        if na.is_empty() || nb.is_empty() {
            return 0;
        }
        let stack = &mut ws.pairs;
        stack.clear();
        stack.push((0, 0));
        while let Some((a, b)) = stack.pop() {
            tests += 1;
            descend(na, nb, a, b, stack, &mut leaf_pair);
        }
        tests
    }
}

/// Tests node `a` of `na` against node `b` of `nb`; on overlap, reports a leaf pair or pushes
/// the child pairs (both nodes are split when both are internal).
#[inline]
fn descend<V: BoundingVolume>(
    na: &[Node<V>],
    nb: &[Node<V>],
    a: u32,
    b: u32,
    stack: &mut Vec<(u32, u32)>,
    leaf_pair: &mut impl FnMut(u32, u32),
) {
    let (x, y) = (&na[a as usize], &nb[b as usize]);
    if !x.volume.overlaps(&y.volume) {
        return;
    }
    match (x.children(), y.children()) {
        (None, None) => leaf_pair(x.a, y.a),
        (None, Some([l, r])) => {
            stack.push((a, r));
            stack.push((a, l));
        }
        (Some([l, r]), None) => {
            stack.push((r, b));
            stack.push((l, b));
        }
        (Some([al, ar]), Some([bl, br])) => {
            stack.push((ar, br));
            stack.push((ar, bl));
            stack.push((al, br));
            stack.push((al, bl));
        }
    }
}
