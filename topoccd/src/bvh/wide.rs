//! A wide hierarchy: four children per node, their boxes side by side in `f32` (structure of
//! arrays, every bound rounded outward as [`CompactKdop`] rounds it), so that one pass of
//! twelve comparisons over four lanes, which the compiler turns into a few SIMD instructions,
//! tests a query box against all four children at once.
//!
//! Built by collapsing a binary [`Bvh`] (each wide node takes its binary node's children, then
//! opens the internal ones among them, widest first, until it has four), so the wide tree has
//! the binary build's splits and a third of its depth. Its leaves are numbered in the order a
//! depth-first walk meets them, so that every child covers a contiguous range of leaf
//! positions: a query for the leaves after a position (each unordered pair once, in a
//! self-query) skips the subtrees that end before it. The nodes come in pre-order (a child
//! after its parent), so a refit is one backward pass.
//!
//! It knows boxes and leaf ids only; the work at the leaves is a closure.

use crate::kdop::CompactKdop;
use crate::math::DVec3;

use super::{Bvh, BvhWorkspace};

/// The box type of the wide hierarchy's leaves and queries.
pub(crate) type Box3 = CompactKdop<3>;

/// The children per node.
pub(crate) const WIDTH: usize = 4;

/// A child slot holding nothing.
const EMPTY: u32 = u32::MAX;
/// Marks a child slot that holds a leaf (its position, in the low bits).
const LEAF_BIT: u32 = 1 << 31;

/// One node: up to four children, their boxes axis by axis (`lo[axis][child]`). An empty
/// slot's box is empty (`+inf` to `-inf`), so it never overlaps.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(crate) struct WideNode {
    lo: [[f32; WIDTH]; 3],
    hi: [[f32; WIDTH]; 3],
    /// A node's index, or [`LEAF_BIT`] and a leaf position, or [`EMPTY`].
    child: [u32; WIDTH],
    /// The end (exclusive) of the leaf positions under each child.
    end: [u32; WIDTH],
}

impl WideNode {
    const EMPTY: Self = Self {
        lo: [[f32::INFINITY; WIDTH]; 3],
        hi: [[f32::NEG_INFINITY; WIDTH]; 3],
        child: [EMPTY; WIDTH],
        end: [0; WIDTH],
    };

    /// The lanes whose child box shares a point with `q`, as bits: twelve comparisons over
    /// four lanes (SSE on x86-64, where it is always present; elsewhere a loop without
    /// branches, `&` not `&&`, which the compiler vectorises).
    #[inline(always)]
    fn overlap_mask(&self, q: &Query) -> u32 {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_mm_and_ps, _mm_cmple_ps, _mm_load_ps, _mm_movemask_ps};
            // SAFETY: SSE is part of the x86-64 baseline; `lo[a]` and `hi[a]` are 16 bytes at
            // 16-byte alignment (the node is aligned to 32, each row four `f32`s at an offset
            // multiple of 16).
            unsafe {
                let lo = [0, 1, 2].map(|a| _mm_load_ps(self.lo[a].as_ptr()));
                let hi = [0, 1, 2].map(|a| _mm_load_ps(self.hi[a].as_ptr()));
                let mut ok = _mm_and_ps(_mm_cmple_ps(lo[0], q.hi[0]), _mm_cmple_ps(q.lo[0], hi[0]));
                for a in 1..3 {
                    ok = _mm_and_ps(ok, _mm_cmple_ps(lo[a], q.hi[a]));
                    ok = _mm_and_ps(ok, _mm_cmple_ps(q.lo[a], hi[a]));
                }
                _mm_movemask_ps(ok) as u32
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let mut ok = [true; WIDTH];
            for a in 0..3 {
                for (c, o) in ok.iter_mut().enumerate() {
                    *o &= (self.lo[a][c] <= q.b.hi[a]) & (q.b.lo[a] <= self.hi[a][c]);
                }
            }
            let mut m = 0;
            for (c, o) in ok.iter().enumerate() {
                m |= u32::from(*o) << c;
            }
            m
        }
    }

    /// The box of lane `c`.
    #[inline]
    fn lane(&self, c: usize) -> Box3 {
        Box3 {
            lo: [self.lo[0][c], self.lo[1][c], self.lo[2][c]],
            hi: [self.hi[0][c], self.hi[1][c], self.hi[2][c]],
        }
    }

    #[inline]
    fn set_lane(&mut self, c: usize, b: &Box3) {
        for a in 0..3 {
            self.lo[a][c] = b.lo[a];
            self.hi[a][c] = b.hi[a];
        }
    }

    /// The union of the lanes' boxes.
    #[inline]
    fn union(&self) -> Box3 {
        let mut b = Box3 {
            lo: [f32::INFINITY; 3],
            hi: [f32::NEG_INFINITY; 3],
        };
        for a in 0..3 {
            for c in 0..WIDTH {
                b.lo[a] = b.lo[a].min(self.lo[a][c]);
                b.hi[a] = b.hi[a].max(self.hi[a][c]);
            }
        }
        b
    }
}

/// A query box, its bounds broadcast to the four lanes once per query.
#[derive(Clone, Copy)]
struct Query {
    #[cfg(target_arch = "x86_64")]
    lo: [std::arch::x86_64::__m128; 3],
    #[cfg(target_arch = "x86_64")]
    hi: [std::arch::x86_64::__m128; 3],
    #[cfg(not(target_arch = "x86_64"))]
    b: Box3,
}

impl Query {
    #[inline(always)]
    fn new(b: &Box3) -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::_mm_set1_ps;
            // SAFETY: SSE is part of the x86-64 baseline.
            unsafe {
                Self {
                    lo: b.lo.map(|x| _mm_set1_ps(x)),
                    hi: b.hi.map(|x| _mm_set1_ps(x)),
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            Self { b: *b }
        }
    }
}

/// A four-wide hierarchy over `f32` boxes (see the module).
#[derive(Clone, Debug, Default)]
pub(crate) struct WideBvh {
    /// Pre-order; node 0 is the root (none when there is no leaf).
    nodes: Vec<WideNode>,
    /// Leaf position to leaf id.
    ids: Vec<u32>,
    /// The binary tree collapsed (kept for its node array).
    binary: Bvh<Box3>,
}

impl WideBvh {
    /// The leaf ids in position order (a depth-first walk's).
    pub fn ids(&self) -> &[u32] {
        &self.ids
    }

    /// Number of leaves.
    pub fn leaf_count(&self) -> usize {
        self.ids.len()
    }

    /// Builds the tree over `n` leaves, leaf `i` with box `volume(i)` and represented by
    /// `center(i)` when splitting: the binary build of [`Bvh::rebuild_from_fn`], collapsed.
    pub fn rebuild(
        &mut self,
        n: usize,
        center: impl Fn(usize) -> DVec3 + Sync,
        volume: impl Fn(u32) -> Box3 + Sync,
        ws: &mut BvhWorkspace,
    ) {
        self.nodes.clear();
        self.ids.clear();
        if n == 0 {
            return;
        }
        // At most 2^30 leaves (the binary build's limit), so positions fit below LEAF_BIT.
        self.binary.rebuild_from_fn(n, center, volume, ws);
        let bin = std::mem::take(&mut self.binary);
        let nodes = bin.nodes();
        if let Some(id) = nodes[0].leaf() {
            let mut root = WideNode::EMPTY;
            root.set_lane(0, &nodes[0].volume);
            root.child[0] = LEAF_BIT;
            root.end[0] = 1;
            self.nodes.push(root);
            self.ids.push(id);
        } else {
            self.collapse(nodes, 0);
        }
        self.binary = bin;
    }

    /// Emits the wide node of binary internal node `b` and, after it, its subtrees; returns
    /// its index.
    fn collapse(&mut self, bin: &[super::Node<Box3>], b: u32) -> u32 {
        let at = self.nodes.len() as u32;
        self.nodes.push(WideNode::EMPTY);
        let mut kids: [u32; WIDTH] = [EMPTY; WIDTH];
        let [c0, c1] = bin[b as usize].children().expect("an internal node");
        kids[0] = c0;
        kids[1] = c1;
        let mut k = 2;
        while k < WIDTH {
            // Open the widest internal child, in place (its halves keep the walk's order).
            let open = (0..k)
                .filter(|&i| bin[kids[i] as usize].children().is_some())
                .max_by(|&i, &j| {
                    let e = |i: usize| bin[kids[i] as usize].volume.extent();
                    e(i).total_cmp(&e(j))
                });
            let Some(i) = open else { break };
            let [g0, g1] = bin[kids[i] as usize].children().expect("internal");
            kids.copy_within(i + 1..k, i + 2);
            kids[i] = g0;
            kids[i + 1] = g1;
            k += 1;
        }
        let mut node = WideNode::EMPTY;
        for (c, &kid) in kids[..k].iter().enumerate() {
            let n = &bin[kid as usize];
            node.set_lane(c, &n.volume);
            if let Some(id) = n.leaf() {
                node.child[c] = LEAF_BIT | self.ids.len() as u32;
                self.ids.push(id);
            } else {
                node.child[c] = self.collapse(bin, kid);
            }
            node.end[c] = self.ids.len() as u32;
        }
        self.nodes[at as usize] = node;
        at
    }

    /// Gives the leaves new boxes, `volume(id)`, in the same tree (one backward pass).
    /// Returns the summed extents of every child box, and the number of child boxes.
    pub fn refit(&mut self, volume: impl Fn(u32) -> Box3) -> (f64, usize) {
        let (mut size, mut count) = (0.0, 0);
        for i in (0..self.nodes.len()).rev() {
            let (head, tail) = self.nodes.split_at_mut(i + 1);
            let node = &mut head[i];
            for c in 0..WIDTH {
                let ch = node.child[c];
                if ch == EMPTY {
                    continue;
                }
                let b = if ch & LEAF_BIT != 0 {
                    volume(self.ids[(ch & !LEAF_BIT) as usize])
                } else {
                    tail[ch as usize - i - 1].union()
                };
                node.set_lane(c, &b);
                size += b.extent();
                count += 1;
            }
        }
        (size, count)
    }

    /// The summed extents of every child box, and the number of child boxes.
    pub fn size(&self) -> (f64, usize) {
        let (mut size, mut count) = (0.0, 0);
        for n in &self.nodes {
            for c in 0..WIDTH {
                if n.child[c] != EMPTY {
                    size += n.lane(c).extent();
                    count += 1;
                }
            }
        }
        (size, count)
    }

    /// Calls `leaf(position)` for every leaf at a position `>= from` whose box shares a point
    /// with `q` (the id is [`WideBvh::ids`]`[position]`), using `stack` as scratch. Returns
    /// the number of node visits (each tests four boxes).
    #[inline]
    pub fn query(
        &self,
        q: &Box3,
        from: u32,
        stack: &mut Vec<u32>,
        mut leaf: impl FnMut(u32),
    ) -> u64 {
        if self.nodes.is_empty() {
            return 0;
        }
        let q = Query::new(q);
        stack.clear();
        stack.push(0);
        let mut visits = 0;
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            visits += 1;
            let mut m = node.overlap_mask(&q);
            while m != 0 {
                let c = m.trailing_zeros() as usize;
                m &= m - 1;
                if node.end[c] <= from {
                    continue;
                }
                let ch = node.child[c];
                if ch & LEAF_BIT != 0 {
                    let pos = ch & !LEAF_BIT;
                    if pos >= from {
                        leaf(pos);
                    }
                } else {
                    stack.push(ch);
                }
            }
        }
        visits
    }

    /// Checks the tree against `volume(id)`: every leaf once, every child box containing its
    /// subtree's, the leaf ranges contiguous. For the tests.
    #[cfg(test)]
    pub fn validate(&self, n: usize, volume: impl Fn(u32) -> Box3) -> Result<(), String> {
        let mut seen = vec![false; n];
        for &id in &self.ids {
            if id as usize >= n || std::mem::replace(&mut seen[id as usize], true) {
                return Err(format!("leaf {id} twice or out of range"));
            }
        }
        if seen.iter().any(|s| !s) || self.ids.len() != n {
            return Err("a leaf is missing".into());
        }
        for (i, node) in self.nodes.iter().enumerate() {
            for c in 0..WIDTH {
                let ch = node.child[c];
                if ch == EMPTY {
                    continue;
                }
                let b = node.lane(c);
                let inner = if ch & LEAF_BIT != 0 {
                    let pos = ch & !LEAF_BIT;
                    if node.end[c] != pos + 1 {
                        return Err(format!("node {i} lane {c}: leaf range"));
                    }
                    volume(self.ids[pos as usize])
                } else {
                    if (ch as usize) <= i {
                        return Err(format!("node {i}: child {ch} before it"));
                    }
                    self.nodes[ch as usize].union()
                };
                if !super::BoundingVolume::contains(&b, &inner) {
                    return Err(format!("node {i} lane {c}: box does not contain its subtree"));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
