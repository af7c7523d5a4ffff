//! Traversals: all overlapping leaf pairs of one tree, or of two trees.

use super::{BoundingVolume, Bvh, BvhWorkspace, Node, LEAF};

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
        let stack = &mut ws.pairs;
        stack.clear();
        if self.nodes.len() > 1 {
            stack.push((0, 0));
        }
        run(&self.nodes, &self.nodes, stack, &TestAll, &mut leaf_pair)
    }

    /// Starts a [`Bvh::self_pairs`] traversal that runs in pieces ([`Bvh::self_pairs_resume`]):
    /// `stack` holds its state between the pieces (the caller's, not the workspace's, so that
    /// other traversals may run in between).
    pub(crate) fn self_pairs_start(&self, stack: &mut Vec<(u32, u32)>) {
        stack.clear();
        if self.nodes.len() > 1 {
            stack.push((0, 0));
        }
    }

    /// Continues the traversal started by [`Bvh::self_pairs_start`] on `stack` until it has
    /// reported at least `at_least` leaf pairs in this call (at most three more: a node pair
    /// gives up to four) or it is over (`stack` empty). Over all its pieces it reports the
    /// pairs of [`Bvh::self_pairs`], in the same order. Returns the overlap tests of this piece.
    pub(crate) fn self_pairs_resume(
        &self,
        stack: &mut Vec<(u32, u32)>,
        at_least: usize,
        mut leaf_pair: impl FnMut(u32, u32),
    ) -> u64 {
        let mut sink = Counting {
            stack,
            leaf_pair: &mut leaf_pair,
            reported: 0,
        };
        let mut tests = 0u64;
        while sink.reported < at_least {
            let Some((a, tagged)) = sink.stack.pop() else {
                break;
            };
            tests += step(&self.nodes, &self.nodes, a, tagged, &TestAll, &mut sink);
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
        if na.is_empty() || nb.is_empty() {
            return 0;
        }
        let stack = &mut ws.pairs;
        stack.clear();
        let tests = 1;
        if !na[0].volume.overlaps(&nb[0].volume) {
            return tests;
        }
        match (na[0].leaf(), nb[0].leaf()) {
            (Some(x), Some(y)) => {
                leaf_pair(x, y);
                tests
            }
            _ => {
                stack.push((0, OTHER));
                tests + run(na, nb, stack, &TestAll, &mut leaf_pair)
            }
        }
    }
}

/// In the pairs on the stack of [`run`], marks a node of the second tree (whose index may
/// equal the first's) so that the pair `(a, a | OTHER)` is not read as "a subtree against
/// itself". A tree has at most `2^30` leaves ([`Bvh::rebuild`] checks), so fewer than `2^31`
/// nodes, and never has this bit in a node index.
pub(super) const OTHER: u32 = 1 << 31;

/// What a self-traversal may know of a pair of leaves before testing their volumes, from their
/// node indices: a caller whose leaves are triangles can drop, without a test, pairs it would
/// drop anyway once they overlap (neighbours it has proved free of contact). Skipping such a
/// pair changes only the tests made, never the pairs a caller keeps.
pub(crate) trait LeafCheck: Sync {
    /// `true`: the leaves of nodes `a` and `b` give nothing; no test is made.
    fn skip(&self, a: u32, b: u32) -> bool;
}

/// Tests every leaf pair.
pub(crate) struct TestAll;

impl LeafCheck for TestAll {
    #[inline(always)]
    fn skip(&self, _: u32, _: u32) -> bool {
        false
    }
}

/// Where one step of the traversal puts its output: the node pairs still to descend, and the
/// overlapping leaf pairs.
pub(super) trait Sink {
    /// A stack entry (see [`step`]) to process later.
    fn push(&mut self, a: u32, b: u32);
    /// An overlapping pair of leaves, by leaf id.
    fn leaf(&mut self, x: u32, y: u32);
}

/// The sink of a sequential traversal: a stack and the caller's closure.
struct Stack<'a, F> {
    stack: &'a mut Vec<(u32, u32)>,
    leaf_pair: &'a mut F,
}

impl<F: FnMut(u32, u32)> Sink for Stack<'_, F> {
    #[inline(always)]
    fn push(&mut self, a: u32, b: u32) {
        self.stack.push((a, b));
    }

    #[inline(always)]
    fn leaf(&mut self, x: u32, y: u32) {
        (self.leaf_pair)(x, y)
    }
}

/// The sink of a traversal in pieces: [`Stack`], counting the leaf pairs reported.
struct Counting<'a, F> {
    stack: &'a mut Vec<(u32, u32)>,
    leaf_pair: &'a mut F,
    reported: usize,
}

impl<F: FnMut(u32, u32)> Sink for Counting<'_, F> {
    #[inline(always)]
    fn push(&mut self, a: u32, b: u32) {
        self.stack.push((a, b));
    }

    #[inline(always)]
    fn leaf(&mut self, x: u32, y: u32) {
        self.reported += 1;
        (self.leaf_pair)(x, y)
    }
}

/// The traversal loop shared by the self and the two-tree traversals: pops and processes
/// entries (see [`step`]) until the stack is empty. Returns the number of overlap tests.
pub(super) fn run<V: BoundingVolume>(
    na: &[Node<V>],
    nb: &[Node<V>],
    stack: &mut Vec<(u32, u32)>,
    check: &impl LeafCheck,
    leaf_pair: &mut impl FnMut(u32, u32),
) -> u64 {
    let mut tests = 0u64;
    while let Some((a, tagged)) = stack.pop() {
        tests += step(na, nb, a, tagged, check, &mut Stack { stack, leaf_pair });
    }
    tests
}

/// Processes one entry of the traversal:
/// - `(x, x)`: internal node `x` of `na` against itself (no test needed): its two children
///   are tested against each other and each internal one is pushed against itself;
/// - `(a, b | OTHER)` or, within one tree, `(a, b)` with `a != b`: two nodes known to overlap,
///   at least one internal: the children of the internal ones are tested against each other
///   (or against the leaf), and each overlapping pair is reported (two leaves) or pushed.
///
/// Children are tested as soon as their parents' pair is processed, so only overlapping pairs
/// are pushed. Pairs of leaves that `check` skips are not tested. Returns the number of
/// overlap tests.
#[inline(always)]
pub(super) fn step<V: BoundingVolume>(
    na: &[Node<V>],
    nb: &[Node<V>],
    a: u32,
    tagged: u32,
    check: &impl LeafCheck,
    sink: &mut impl Sink,
) -> u64 {
    if a == tagged {
        let c = na[a as usize].a;
        let tests = test(na, na, c, c + 1, 0, check, sink);
        for x in [c + 1, c] {
            if na[x as usize].b != LEAF {
                sink.push(x, x);
            }
        }
        return tests;
    }
    let tag = tagged & OTHER;
    let b = tagged & !OTHER;
    let (x, y) = (&na[a as usize], &nb[b as usize]);
    match (x.b != LEAF, y.b != LEAF) {
        (true, true) => {
            let mut tests = 0;
            for i in [x.a, x.b] {
                for j in [y.a, y.b] {
                    tests += test(na, nb, i, j, tag, check, sink);
                }
            }
            tests
        }
        (true, false) => {
            test(na, nb, x.a, b, tag, check, sink) + test(na, nb, x.b, b, tag, check, sink)
        }
        (false, true) => {
            test(na, nb, a, y.a, tag, check, sink) + test(na, nb, a, y.b, tag, check, sink)
        }
        (false, false) => unreachable!("leaf pairs are reported, not pushed"),
    }
}

/// Tests node `a` of `na` against node `b` of `nb` (unless both are leaves that `check`
/// skips); on overlap, reports the leaf pair or pushes the pair (with `tag`, [`OTHER`] for
/// two trees). Returns the tests made (0 or 1).
#[inline(always)]
fn test<V: BoundingVolume>(
    na: &[Node<V>],
    nb: &[Node<V>],
    a: u32,
    b: u32,
    tag: u32,
    check: &impl LeafCheck,
    sink: &mut impl Sink,
) -> u64 {
    let (x, y) = (&na[a as usize], &nb[b as usize]);
    let leaves = x.b == LEAF && y.b == LEAF;
    if leaves && check.skip(a, b) {
        return 0;
    }
    if x.volume.overlaps(&y.volume) {
        if leaves {
            sink.leaf(x.a, y.a);
        } else {
            sink.push(a, b | tag);
        }
    }
    1
}
