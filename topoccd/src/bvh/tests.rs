//! The parallel build and traversals against the sequential ones and brute force, on seeded
//! random input, for several thread counts.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{Bvh, BvhWorkspace, Leaf, ParOptions, ParPairs};
use crate::kdop::Kdop;
use crate::math::DVec3;

fn point(rng: &mut ChaCha8Rng, scale: f64) -> DVec3 {
    DVec3::new(
        rng.random_range(-scale..scale),
        rng.random_range(-scale..scale),
        rng.random_range(-scale..scale),
    )
}

/// Swept volumes of `n` small moving triangles, denser for bigger `n`, ids shuffled.
fn leaves(rng: &mut ChaCha8Rng, n: usize) -> Vec<Leaf<Kdop<9>>> {
    let size = 0.1 / (n.max(1) as f64).cbrt();
    (0..n)
        .map(|i| {
            let c = point(rng, 1.0);
            let t0 = [0; 3].map(|_| c + point(rng, size));
            let d = point(rng, size);
            let t1 = t0.map(|p| p + d);
            Leaf {
                id: (i as u32).wrapping_mul(2_654_435_761) % 1_000_003,
                volume: Kdop::swept_triangle(&t0, &t1, 0.0),
            }
        })
        .collect()
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
}

fn sorted(mut pairs: Vec<(u32, u32)>) -> Vec<(u32, u32)> {
    pairs.sort_unstable();
    pairs
}

fn brute_self(leaves: &[Leaf<Kdop<9>>]) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for (i, a) in leaves.iter().enumerate() {
        for b in &leaves[i + 1..] {
            if a.volume.overlaps(&b.volume) {
                out.push((a.id.min(b.id), a.id.max(b.id)));
            }
        }
    }
    sorted(out)
}

type Out = ParPairs<Vec<(u32, u32)>>;

#[test]
fn parallel_build_and_traversals_match_sequential_for_any_thread_count() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for n in [0, 1, 2, 3, 7, 64, 300, 2500, 9000, 30000] {
        let a = leaves(&mut rng, n);
        let b = leaves(&mut rng, n / 3 + 1);
        let mut ws = BvhWorkspace::default();
        let one = pool(1).install(|| Bvh::from_leaves(&a));
        assert_eq!(one.validate(&a), Ok(()), "n {n}");
        let other = Bvh::from_leaves(&b);

        let mut seq = Vec::new();
        let seq_tests = one.self_pairs(&mut ws, |x, y| seq.push((x.min(y), x.max(y))));
        let seq = sorted(seq);
        if n <= 2500 {
            assert_eq!(seq, brute_self(&a), "n {n}");
        }
        let mut cross = Vec::new();
        let cross_tests = one.tree_pairs(&other, &mut ws, |x, y| cross.push((x, y)));
        let cross = sorted(cross);

        let mut first: Option<(Out, Out)> = None;
        for threads in [1, 2, 3] {
            let (tree, own, two) = pool(threads).install(|| {
                let mut ws = BvhWorkspace::default();
                let tree = Bvh::from_leaves(&a);
                let own = tree.par_self_pairs(&mut ws, Vec::new, |v, x, y| v.push((x, y)));
                let two = tree.par_tree_pairs(&other, &mut ws, Vec::new, |v, x, y| v.push((x, y)));
                (tree, own, two)
            });
            assert_eq!(tree.nodes(), one.nodes(), "n {n}, {threads} threads: tree");
            assert_eq!(own.bv_tests, seq_tests, "n {n}, {threads} threads");
            assert_eq!(two.bv_tests, cross_tests, "n {n}, {threads} threads");
            let flat: Vec<(u32, u32)> = own.results.concat();
            let len = flat.len();
            let flat = sorted(
                flat.into_iter()
                    .map(|(x, y)| (x.min(y), x.max(y)))
                    .collect(),
            );
            assert_eq!(len, seq.len(), "n {n}, {threads} threads: a pair twice");
            assert_eq!(flat, seq, "n {n}, {threads} threads: self pairs");
            assert_eq!(sorted(two.results.concat()), cross, "n {n}: tree pairs");
            match &first {
                None => first = Some((own, two)),
                Some((o, t)) => {
                    assert_eq!(o, &own, "n {n}, {threads} threads: self output order");
                    assert_eq!(t, &two, "n {n}, {threads} threads: tree output order");
                }
            }
        }
    }
}

#[test]
fn rebuild_reuses_buffers_across_sizes() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let mut ws = BvhWorkspace::default();
    let mut bvh = Bvh::new();
    for n in [5000, 3, 0, 9000, 1, 4097] {
        let a = leaves(&mut rng, n);
        bvh.rebuild(&a, &mut ws);
        assert_eq!(bvh.validate(&a), Ok(()), "n {n}");
        assert_eq!(bvh.nodes(), Bvh::from_leaves(&a).nodes(), "n {n}");
    }
}

#[test]
fn refit_matches_brute_force_after_moving_the_leaves() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for n in [1, 2, 9, 700, 6000] {
        let a = leaves(&mut rng, n);
        let mut bvh = Bvh::from_leaves(&a);
        // New volumes for the same ids: every leaf shifted by its own random offset.
        let moved: Vec<Leaf<Kdop<9>>> = a
            .iter()
            .map(|l| {
                let d = point(&mut rng, 0.05);
                let mut v = l.volume;
                for k in 0..3 {
                    v.lo[k] += d[k];
                    v.hi[k] += d[k];
                }
                v.inflate(0.01);
                Leaf {
                    id: l.id,
                    volume: v,
                }
            })
            .collect();
        let by_id: std::collections::HashMap<u32, Kdop<9>> =
            moved.iter().map(|l| (l.id, l.volume)).collect();
        bvh.refit(|id| by_id[&id]);
        assert_eq!(bvh.validate(&moved), Ok(()), "n {n}");
        let mut pairs = Vec::new();
        bvh.self_pairs(&mut BvhWorkspace::default(), |x, y| {
            pairs.push((x.min(y), x.max(y)))
        });
        assert_eq!(sorted(pairs), brute_self(&moved), "n {n}");
    }
}

#[test]
fn batches_and_task_counts_give_the_same_pairs_in_the_same_order() {
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    let a = leaves(&mut rng, 12000);
    let b = leaves(&mut rng, 3000);
    let (x, y) = (Bvh::from_leaves(&a), Bvh::from_leaves(&b));
    let mut ws = BvhWorkspace::default();
    let all = x.par_self_pairs(&mut ws, Vec::new, |v, p, q| v.push((p, q)));
    let cross = x.par_tree_pairs(&y, &mut ws, Vec::new, |v, p, q| v.push((p, q)));
    for threads in [1, 2] {
        for (batch, grow) in [(1, false), (7, false), (100_000, false), (1, true), (7, true)] {
            let options = ParOptions {
                batch,
                grow,
                ..ParOptions::default()
            };
            let (own, two) = pool(threads).install(|| {
                let mut ws = BvhWorkspace::default();
                let (mut own, mut two) = (Vec::new(), Vec::new());
                let push = |v: &mut Vec<(u32, u32)>, p, q| v.push((p, q));
                let t1 = x.par_self_pairs_with(&mut ws, &options, Vec::new, push, |r| own.push(r));
                let t2 =
                    x.par_tree_pairs_with(&y, &mut ws, &options, Vec::new, push, |r| two.push(r));
                assert_eq!((t1, t2), (all.bv_tests, cross.bv_tests));
                (own, two)
            });
            assert_eq!(own, all.results, "{threads} threads, batch {batch}, {grow}");
            assert_eq!(two, cross.results, "{threads} threads, batch {batch}, {grow}");
        }
    }
    // Other task counts: other tasks, the same pairs.
    for min_tasks in [1, 3, 5000] {
        let options = ParOptions {
            min_tasks,
            min_nodes: 0,
            ..ParOptions::default()
        };
        let mut own = Vec::new();
        x.par_self_pairs_with(
            &mut ws,
            &options,
            Vec::new,
            |v, p, q| v.push((p.min(q), p.max(q))),
            |r| own.extend(r),
        );
        let expected: Vec<(u32, u32)> = all
            .results
            .concat()
            .into_iter()
            .map(|(p, q)| (p.min(q), p.max(q)))
            .collect();
        assert_eq!(sorted(own), sorted(expected), "min_tasks {min_tasks}");
    }
}

/// A traversal whose `consume` asks to stop hands over the batch under way in full, then
/// stops: its results are a prefix of the whole traversal's, cut at a batch boundary, the
/// same for any thread count; with growing batches, the second batch is twice the first.
#[test]
fn a_traversal_stops_after_the_batch_where_consume_asks() {
    use std::ops::ControlFlow;
    let mut rng = ChaCha8Rng::seed_from_u64(15);
    let a = leaves(&mut rng, 12000);
    let x = Bvh::from_leaves(&a);
    let all = x.par_self_pairs(&mut BvhWorkspace::default(), Vec::new, |v, p, q| {
        v.push((p, q))
    });
    assert!(all.results.len() > 100, "{} tasks", all.results.len());
    let batch = 16;
    // The first result (of the splitting), then two whole batches: results 2..=17 and
    // 18..=33, or 18..=49 when the batches grow.
    for (grow, expected) in [(false, 1 + 2 * batch), (true, 1 + 3 * batch)] {
        let options = ParOptions {
            batch,
            grow,
            ..ParOptions::default()
        };
        for threads in [1, 2] {
            // Ask to stop at the 20th result.
            let got = pool(threads).install(|| {
                let mut got = Vec::new();
                x.par_self_pairs_until(
                    &mut BvhWorkspace::default(),
                    &options,
                    &super::TestAll,
                    |_| Vec::new(),
                    |v, p, q| v.push((p, q)),
                    |_| {},
                    |r| {
                        got.push(r);
                        if got.len() >= 20 {
                            ControlFlow::Break(())
                        } else {
                            ControlFlow::Continue(())
                        }
                    },
                    &|_| false,
                );
                got
            });
            assert_eq!(got.len(), expected, "{threads} threads, grow {grow}");
            assert_eq!(got, all.results[..got.len()], "{threads} threads, grow {grow}");
        }
    }
}

/// The leaf ids below node `n`.
fn leaves_below(bvh: &Bvh<Kdop<9>>, n: u32, out: &mut Vec<u32>) {
    match bvh.nodes()[n as usize].children() {
        None => out.push(bvh.nodes()[n as usize].leaf().unwrap()),
        Some([a, b]) => {
            leaves_below(bvh, a, out);
            leaves_below(bvh, b, out);
        }
    }
}

/// The front covers every unrelated pair of leaves exactly once and no related pair, and the
/// traversal from it reports exactly the unrelated pairs whose volumes overlap (brute force),
/// for a relation that holds only between overlapping leaves, as [`Bvh::front`] needs.
#[test]
fn front_covers_the_unrelated_pairs_once() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for n in [2, 3, 17, 300, 1000] {
        let leaves = leaves(&mut rng, n);
        let bvh = Bvh::from_leaves(&leaves);
        let volume = |id: u32| leaves.iter().find(|l| l.id == id).unwrap().volume;
        // Related: overlapping, and ids of the same parity (about half the overlapping pairs).
        let rel = |x: u32, y: u32| x % 2 == y % 2 && volume(x).overlaps(&volume(y));
        let nodes = bvh.nodes();
        let leaf = |node: u32| nodes[node as usize].leaf().unwrap();
        let mut kept = super::Front::default();
        bvh.front(&|a, b| rel(leaf(a), leaf(b)), &mut kept);
        let front = kept.pairs.clone();
        let mut covered = std::collections::HashMap::new();
        for &(a, b) in &front {
            let (mut la, mut lb) = (Vec::new(), Vec::new());
            leaves_below(&bvh, a, &mut la);
            leaves_below(&bvh, b, &mut lb);
            for &x in &la {
                for &y in &lb {
                    *covered.entry((x.min(y), x.max(y))).or_insert(0) += 1;
                }
            }
        }
        for (i, a) in leaves.iter().enumerate() {
            for b in &leaves[i + 1..] {
                let key = (a.id.min(b.id), a.id.max(b.id));
                let times = covered.get(&key).copied().unwrap_or(0);
                let expected = if rel(a.id, b.id) { 0 } else { 1 };
                assert_eq!(times, expected, "n = {n}, pair {key:?}");
            }
        }
        let mut found = Vec::new();
        let tests = bvh.front_pairs(&front, &mut Vec::new(), &mut |x, y| {
            found.push((x.min(y), x.max(y)))
        });
        assert!(tests >= front.len() as u64);
        let expected: Vec<_> = brute_self(&leaves)
            .into_iter()
            .filter(|&(x, y)| !rel(x, y))
            .collect();
        assert_eq!(sorted(found), expected, "n = {n}");
    }
}

/// After the relation changes below a few leaves, updating the blocks of their ancestors gives
/// the front computed afresh.
#[test]
fn an_updated_front_is_the_front_computed_afresh() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    for n in [5, 64, 700] {
        let leaves = leaves(&mut rng, n);
        let bvh = Bvh::from_leaves(&leaves);
        let nodes = bvh.nodes();
        let volume = |node: u32| nodes[node as usize].volume;
        let mut parent = vec![0u32; nodes.len()];
        for (i, node) in nodes.iter().enumerate() {
            if let Some([a, b]) = node.children() {
                parent[a as usize] = i as u32;
                parent[b as usize] = i as u32;
            }
        }
        // Leaves are related by a label of theirs (and overlap); some labels then change.
        let mut label: Vec<u32> = (0..nodes.len()).map(|_| rng.random_range(0..3)).collect();
        let mut front = super::Front::default();
        for round in 0..5 {
            let rel = |a: u32, b: u32| {
                label[a as usize] == label[b as usize] && volume(a).overlaps(&volume(b))
            };
            if round == 0 {
                bvh.front(&rel, &mut front);
            }
            let mut fresh = super::Front::default();
            bvh.front(&rel, &mut fresh);
            assert_eq!(front.pairs, fresh.pairs, "n = {n}, round {round}");
            // Relabel a few leaves; their ancestors are dirty.
            let mut dirty = vec![false; nodes.len()];
            for _ in 0..rng.random_range(1..4) {
                let mut x = rng.random_range(0..nodes.len() as u32);
                while nodes[x as usize].leaf().is_none() {
                    x = rng.random_range(0..nodes.len() as u32);
                }
                label[x as usize] = rng.random_range(0..3);
                while x != 0 {
                    x = parent[x as usize];
                    dirty[x as usize] = true;
                }
            }
            let rel = |a: u32, b: u32| {
                label[a as usize] == label[b as usize] && volume(a).overlaps(&volume(b))
            };
            bvh.update_front(&rel, &|x| dirty[x as usize], &mut front);
        }
    }
}

/// A search for the front given too small a budget says so and leaves no front; given enough,
/// it finds the front of [`Bvh::front`], also when it updates a front kept from before.
#[test]
fn a_front_search_past_its_budget_gives_no_front() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let leaves = leaves(&mut rng, 300);
    let bvh = Bvh::from_leaves(&leaves);
    let nodes = bvh.nodes();
    let volume = |node: u32| nodes[node as usize].volume;
    let rel = |a: u32, b: u32| (a + b).is_multiple_of(3) && volume(a).overlaps(&volume(b));
    let mut whole = super::Front::default();
    bvh.front(&rel, &mut whole);
    assert!(!whole.pairs.is_empty());
    let mut front = super::Front::default();
    assert!(!bvh.front_within(&rel, &mut front, 10));
    assert!(front.pairs.is_empty());
    assert!(bvh.front_within(&rel, &mut front, u64::MAX - 1));
    assert_eq!(front.pairs, whole.pairs);
    // An update of every block: too small a budget drops the kept front too.
    assert!(!bvh.update_front_within(&rel, &|_| true, &mut front, 10));
    assert!(front.pairs.is_empty());
}

/// A self-traversal run in pieces of any size gives the pairs of the whole traversal, in the
/// same order, with the same tests; each piece stops within three pairs of its size.
#[test]
fn a_self_traversal_in_pieces_is_the_whole_traversal() {
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    for n in [0, 1, 2, 7, 300] {
        let leaves = leaves(&mut rng, n);
        let bvh = Bvh::from_leaves(&leaves);
        let mut ws = BvhWorkspace::default();
        let mut whole = Vec::new();
        let whole_tests = bvh.self_pairs(&mut ws, |a, b| whole.push((a, b)));
        assert_eq!(sorted(whole.clone()), brute_self(&leaves), "n = {n}");
        for piece in [1, 2, 5, 64, usize::MAX] {
            let mut stack = Vec::new();
            bvh.self_pairs_start(&mut stack);
            let (mut pieces, mut tests) = (Vec::new(), 0);
            while !stack.is_empty() {
                let before = pieces.len();
                tests += bvh.self_pairs_resume(&mut stack, piece, |a, b| pieces.push((a, b)));
                let got = pieces.len() - before;
                assert!(got < piece.saturating_add(4), "n = {n}, piece {piece}: {got}");
                assert!(got >= piece || stack.is_empty(), "n = {n}, piece {piece}");
            }
            assert_eq!(pieces, whole, "n = {n}, piece {piece}");
            assert_eq!(tests, whole_tests, "n = {n}, piece {piece}");
        }
    }
}
