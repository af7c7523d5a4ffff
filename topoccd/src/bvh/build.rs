//! Top-down construction: median split along the longest axis of the leaves' centres.

use super::{BoundingVolume, Bvh, BvhWorkspace, Leaf, Node, LEAF};

impl<V: BoundingVolume> Bvh<V> {
    /// Rebuilds the hierarchy over `leaves`, reusing this tree's node array and the workspace.
    ///
    /// Top-down: a range of leaves is split at its median along the axis where the leaves'
    /// centres ([`BoundingVolume::center`]) spread most, ties broken by the leaves' positions in
    /// `leaves`, so the tree depends only on the input. The depth is `ceil(log2 n)`, and the
    /// two children of a node are adjacent in [`Bvh::nodes`] and come after it.
    ///
    /// ```
    /// use topoccd::bvh::{Bvh, BvhWorkspace, Leaf};
    /// use topoccd::kdop::Kdop;
    /// use topoccd::math::DVec3;
    /// let leaves: Vec<_> = (0..10u32)
    ///     .map(|i| Leaf { id: 100 + i, volume: Kdop::<9>::from_point(DVec3::splat(i as f64)) })
    ///     .collect();
    /// let mut bvh = Bvh::new();
    /// bvh.rebuild(&leaves, &mut BvhWorkspace::default());
    /// assert_eq!(bvh.nodes().len(), 19);
    /// assert_eq!(bvh.leaf_count(), 10);
    /// assert!(bvh.validate(&leaves).is_ok());
    /// ```
    pub fn rebuild(&mut self, leaves: &[Leaf<V>], ws: &mut BvhWorkspace) {
        self.nodes.clear();
        if leaves.is_empty() {
            return;
        }
        debug_assert!(leaves.len() < (u32::MAX / 2) as usize);
        self.nodes.reserve(2 * leaves.len() - 1);
        let items = &mut ws.items;
        items.clear();
        items.extend(
            leaves
                .iter()
                .enumerate()
                .map(|(i, l)| (l.volume.center().to_array(), i as u32)),
        );
        let placeholder = leaves[0].volume;
        self.nodes.push(Node {
            volume: placeholder,
            a: 0,
            b: 0,
        });
        ws.ranges.clear();
        ws.ranges.push((0, 0, leaves.len() as u32));
        while let Some((node, begin, end)) = ws.ranges.pop() {
            let range = &mut items[begin as usize..end as usize];
            if range.len() == 1 {
                let leaf = &leaves[range[0].1 as usize];
                self.nodes[node as usize] = Node {
                    volume: leaf.volume,
                    a: leaf.id,
                    b: LEAF,
                };
                continue;
            }
            let axis = longest_axis(range);
            let mid = range.len() / 2;
            range.select_nth_unstable_by(mid, |x, y| {
                x.0[axis].total_cmp(&y.0[axis]).then(x.1.cmp(&y.1))
            });
            let first = self.nodes.len() as u32;
            for _ in 0..2 {
                self.nodes.push(Node {
                    volume: placeholder,
                    a: 0,
                    b: 0,
                });
            }
            self.nodes[node as usize].a = first;
            self.nodes[node as usize].b = first + 1;
            let split = begin + mid as u32;
            ws.ranges.push((first + 1, split, end));
            ws.ranges.push((first, begin, split));
        }
        // Children come after their parent: fill the volumes from the back.
        for i in (0..self.nodes.len()).rev() {
            if let Some([l, r]) = self.nodes[i].children() {
                debug_assert!(l as usize > i && r as usize > i);
                let v = self.nodes[l as usize]
                    .volume
                    .merge(&self.nodes[r as usize].volume);
                self.nodes[i].volume = v;
            }
        }
    }
}

/// The axis along which the centres spread most.
fn longest_axis(range: &[([f64; 3], u32)]) -> usize {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for (c, _) in range {
        for k in 0..3 {
            lo[k] = lo[k].min(c[k]);
            hi[k] = hi[k].max(c[k]);
        }
    }
    let ext = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
    if ext[0] >= ext[1] && ext[0] >= ext[2] {
        0
    } else if ext[1] >= ext[2] {
        1
    } else {
        2
    }
}
