//! A static bounding-box tree over the triangles of one configuration, and its
//! self-traversal: every pair of leaves' triangles whose closed boxes overlap. The boxes are
//! the triangles' exact `f64` bounds, so touching triangles have touching boxes.

use crate::alloc::{try_append, try_push, AllocError};

/// What the pairs' buffers are called in an allocation failure.
const PAIRS: &str = "intersecting triangle pairs";

/// An axis-aligned box.
#[derive(Clone, Copy, Debug)]
pub struct Aabb {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        min: [f64::INFINITY; 3],
        max: [f64::NEG_INFINITY; 3],
    };

    pub fn of(points: &[[f64; 3]]) -> Aabb {
        points.iter().fold(Aabb::EMPTY, |b, p| b.join_point(p))
    }

    fn join_point(self, p: &[f64; 3]) -> Aabb {
        Aabb {
            min: std::array::from_fn(|k| self.min[k].min(p[k])),
            max: std::array::from_fn(|k| self.max[k].max(p[k])),
        }
    }

    fn join(self, o: &Aabb) -> Aabb {
        self.join_point(&o.min).join_point(&o.max)
    }

    /// Closed boxes overlap (touching counts).
    pub fn overlaps(&self, o: &Aabb) -> bool {
        (0..3).all(|k| self.min[k] <= o.max[k] && o.min[k] <= self.max[k])
    }

    fn centre(&self, k: usize) -> f64 {
        0.5 * self.min[k] + 0.5 * self.max[k]
    }
}

/// At most this many triangles per leaf.
const LEAF: usize = 4;

#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    /// A leaf: `items[start..start + count]`; an inner node (`count == 0`): children
    /// `start` and `start + 1`.
    start: u32,
    count: u32,
}

/// The tree: nodes in depth-first order of construction, leaves naming ranges of `items`.
pub struct Tree {
    nodes: Vec<Node>,
    items: Vec<u32>,
}

impl Tree {
    /// Builds the tree over `boxes` by median splits along the widest axis of the centres.
    pub fn build(boxes: &[Aabb]) -> Tree {
        let mut tree = Tree {
            nodes: Vec::with_capacity(2 * boxes.len() / LEAF + 1),
            items: (0..boxes.len() as u32).collect(),
        };
        if !boxes.is_empty() {
            tree.nodes.push(Node {
                bounds: Aabb::EMPTY,
                start: 0,
                count: 0,
            });
            tree.split(0, 0, boxes.len(), boxes);
        }
        tree
    }

    fn split(&mut self, node: usize, lo: usize, hi: usize, boxes: &[Aabb]) {
        let items = &mut self.items[lo..hi];
        let bounds = items
            .iter()
            .fold(Aabb::EMPTY, |b, &i| b.join(&boxes[i as usize]));
        if items.len() <= LEAF {
            self.nodes[node] = Node {
                bounds,
                start: lo as u32,
                count: items.len() as u32,
            };
            return;
        }
        let (lo_c, hi_c) = items.iter().fold(
            ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
            |(mut lo, mut hi), &i| {
                let b = &boxes[i as usize];
                for k in 0..3 {
                    let c = b.centre(k);
                    lo[k] = lo[k].min(c);
                    hi[k] = hi[k].max(c);
                }
                (lo, hi)
            },
        );
        let spread = |k: usize| hi_c[k] - lo_c[k];
        let axis = (0..3)
            .max_by(|&a, &b| spread(a).total_cmp(&spread(b)))
            .unwrap_or(0);
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |&a, &b| {
            boxes[a as usize]
                .centre(axis)
                .total_cmp(&boxes[b as usize].centre(axis))
                .then(a.cmp(&b))
        });
        let first = self.nodes.len();
        let empty = Node {
            bounds: Aabb::EMPTY,
            start: 0,
            count: 0,
        };
        self.nodes.extend([empty, empty]);
        self.nodes[node] = Node {
            bounds,
            start: first as u32,
            count: 0,
        };
        self.split(first, lo, lo + mid, boxes);
        self.split(first + 1, lo + mid, hi, boxes);
    }

    fn leaf(&self, n: &Node) -> &[u32] {
        &self.items[n.start as usize..(n.start + n.count) as usize]
    }

    /// Calls `visit(a, b)` once for every pair of distinct items whose boxes overlap, the
    /// root's two halves side by side on the rayon pool. `visit` returns the pairs it keeps;
    /// they are returned in the traversal's order, whatever the thread count.
    #[cfg(test)]
    pub fn self_pairs<T: Send>(
        &self,
        boxes: &[Aabb],
        visit: &(impl Fn(u32, u32) -> Option<T> + Sync),
    ) -> Result<Vec<T>, AllocError> {
        self.self_pairs_until(boxes, visit, &|| false)
    }

    /// [`Tree::self_pairs`] that gives up once `halt` returns `true` (asked as each node or
    /// pair of nodes is entered): what it returns then is only part of the pairs. An error
    /// if the pairs' buffers cannot grow.
    pub fn self_pairs_until<T: Send>(
        &self,
        boxes: &[Aabb],
        visit: &(impl Fn(u32, u32) -> Option<T> + Sync),
        halt: &(impl Fn() -> bool + Sync),
    ) -> Result<Vec<T>, AllocError> {
        if self.nodes.is_empty() {
            return Ok(Vec::new());
        }
        self.within(0, (boxes, halt), visit, 0)
    }

    /// Pairs inside node `n`.
    fn within<T: Send>(
        &self,
        n: usize,
        (boxes, halt): (&[Aabb], &(impl Fn() -> bool + Sync)),
        visit: &(impl Fn(u32, u32) -> Option<T> + Sync),
        depth: u32,
    ) -> Result<Vec<T>, AllocError> {
        if halt() {
            return Ok(Vec::new());
        }
        let node = self.nodes[n];
        if node.count > 0 {
            let items = self.leaf(&node);
            let mut out = Vec::new();
            for (k, &a) in items.iter().enumerate() {
                for &b in &items[k + 1..] {
                    if boxes[a as usize].overlaps(&boxes[b as usize]) {
                        if let Some(p) = visit(a, b) {
                            try_push(&mut out, p, PAIRS)?;
                        }
                    }
                }
            }
            return Ok(out);
        }
        let (l, r) = (node.start as usize, node.start as usize + 1);
        let (out, (inner, across)) = if depth < 8 {
            rayon::join(
                || self.within(l, (boxes, halt), visit, depth + 1),
                || {
                    rayon::join(
                        || self.within(r, (boxes, halt), visit, depth + 1),
                        || self.across(l, r, (boxes, halt), visit, depth + 1),
                    )
                },
            )
        } else {
            let left = self.within(l, (boxes, halt), visit, depth + 1);
            let right = self.within(r, (boxes, halt), visit, depth + 1);
            (
                left,
                (right, self.across(l, r, (boxes, halt), visit, depth + 1)),
            )
        };
        let (mut out, mut inner, mut across) = (out?, inner?, across?);
        try_append(&mut out, &mut inner, PAIRS)?;
        try_append(&mut out, &mut across, PAIRS)?;
        Ok(out)
    }

    /// Pairs between nodes `a` and `b`.
    fn across<T: Send>(
        &self,
        a: usize,
        b: usize,
        (boxes, halt): (&[Aabb], &(impl Fn() -> bool + Sync)),
        visit: &(impl Fn(u32, u32) -> Option<T> + Sync),
        depth: u32,
    ) -> Result<Vec<T>, AllocError> {
        let (na, nb) = (self.nodes[a], self.nodes[b]);
        if !na.bounds.overlaps(&nb.bounds) || halt() {
            return Ok(Vec::new());
        }
        match (na.count > 0, nb.count > 0) {
            (true, true) => {
                let mut out = Vec::new();
                for &x in self.leaf(&na) {
                    for &y in self.leaf(&nb) {
                        if boxes[x as usize].overlaps(&boxes[y as usize]) {
                            if let Some(p) = visit(x, y) {
                                try_push(&mut out, p, PAIRS)?;
                            }
                        }
                    }
                }
                Ok(out)
            }
            // Descend the inner node (the left one when both are inner).
            (false, _) => self.descend(a, b, true, (boxes, halt), visit, depth),
            (true, false) => self.descend(b, a, false, (boxes, halt), visit, depth),
        }
    }

    /// Pairs between the children of inner node `inner` and node `other`; `inner_first`
    /// keeps each pair's order as `across(a, b)` gave it.
    fn descend<T: Send>(
        &self,
        inner: usize,
        other: usize,
        inner_first: bool,
        (boxes, halt): (&[Aabb], &(impl Fn() -> bool + Sync)),
        visit: &(impl Fn(u32, u32) -> Option<T> + Sync),
        depth: u32,
    ) -> Result<Vec<T>, AllocError> {
        let c = self.nodes[inner].start as usize;
        let go = |child: usize| {
            if inner_first {
                self.across(child, other, (boxes, halt), visit, depth + 1)
            } else {
                self.across(other, child, (boxes, halt), visit, depth + 1)
            }
        };
        let (first, second) = if depth < 8 {
            rayon::join(|| go(c), || go(c + 1))
        } else {
            (go(c), go(c + 1))
        };
        let (mut first, mut second) = (first?, second?);
        try_append(&mut first, &mut second, PAIRS)?;
        Ok(first)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tree's pairs are exactly the brute-force pairs of overlapping boxes.
    #[test]
    fn pairs_match_brute_force() {
        let mut seed = 7u64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [0usize, 1, 2, 5, 17, 300] {
            let boxes: Vec<Aabb> = (0..n)
                .map(|_| {
                    let p = [next() * 10.0, next() * 10.0, next() * 10.0];
                    let q = [p[0] + next(), p[1] + next(), p[2] + next()];
                    Aabb::of(&[p, q])
                })
                .collect();
            let tree = Tree::build(&boxes);
            let mut got = tree
                .self_pairs(&boxes, &|a, b| Some((a.min(b), a.max(b))))
                .unwrap();
            got.sort_unstable();
            let mut want = Vec::new();
            for a in 0..n {
                for b in a + 1..n {
                    if boxes[a].overlaps(&boxes[b]) {
                        want.push((a as u32, b as u32));
                    }
                }
            }
            assert_eq!(got, want, "{n} boxes");
        }
    }
}
