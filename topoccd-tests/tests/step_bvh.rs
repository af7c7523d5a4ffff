//! The k-DOPs and the hierarchy against brute force on seeded random input; the validator after
//! every build.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use topoccd::bvh::{BoundingVolume, Bvh, BvhWorkspace, Leaf};
use topoccd::kdop::Kdop;
use topoccd::math::DVec3;

fn point(rng: &mut ChaCha8Rng, scale: f64) -> DVec3 {
    DVec3::new(
        rng.random_range(-scale..scale),
        rng.random_range(-scale..scale),
        rng.random_range(-scale..scale),
    )
}

/// Swept volumes of `n` small random moving triangles in a cube of side 2, with ids shuffled
/// away from their positions.
fn leaves<const H: usize>(rng: &mut ChaCha8Rng, n: usize) -> Vec<Leaf<Kdop<H>>> {
    (0..n)
        .map(|i| {
            let c = point(rng, 1.0);
            let t0 = [0; 3].map(|_| c + point(rng, 0.08));
            let d = point(rng, 0.05);
            let t1 = t0.map(|p| p + d + point(rng, 0.01));
            Leaf {
                id: (i as u32).wrapping_mul(2_654_435_761) % 1_000_003,
                volume: Kdop::swept_triangle(&t0, &t1, 0.01),
            }
        })
        .collect()
}

fn brute_self<V: BoundingVolume>(leaves: &[Leaf<V>]) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for (i, a) in leaves.iter().enumerate() {
        for b in &leaves[i + 1..] {
            if a.volume.overlaps(&b.volume) {
                out.push((a.id.min(b.id), a.id.max(b.id)));
            }
        }
    }
    out.sort_unstable();
    out
}

fn check<const H: usize>(seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut ws = BvhWorkspace::default();
    let (mut bvh, mut other) = (Bvh::new(), Bvh::new());
    // Rebuild the same trees over different sizes: buffers are reused.
    for n in [0, 1, 2, 3, 7, 64, 300, 5, 500] {
        let a: Vec<Leaf<Kdop<H>>> = leaves(&mut rng, n);
        let b: Vec<Leaf<Kdop<H>>> = leaves(&mut rng, n / 2 + 1);
        bvh.rebuild(&a, &mut ws);
        assert_eq!(bvh.validate(&a), Ok(()), "H {H} n {n}");
        other.rebuild(&b, &mut ws);
        assert_eq!(other.validate(&b), Ok(()), "H {H} n {n}");
        assert_eq!(bvh.leaf_count(), n);

        let mut pairs = Vec::new();
        let tests = bvh.self_pairs(&mut ws, |x, y| {
            assert_ne!(x, y);
            pairs.push((x.min(y), x.max(y)));
        });
        let len = pairs.len();
        pairs.sort_unstable();
        pairs.dedup();
        assert_eq!(pairs.len(), len, "H {H} n {n}: a pair reported twice");
        assert_eq!(pairs, brute_self(&a), "H {H} n {n}");
        if n > 1 {
            assert!(
                tests > 0 && tests < (n * n) as u64,
                "H {H} n {n}: {tests} tests"
            );
        }

        let mut cross = Vec::new();
        bvh.tree_pairs(&other, &mut ws, |x, y| cross.push((x, y)));
        cross.sort_unstable();
        let mut expected: Vec<(u32, u32)> = a
            .iter()
            .flat_map(|x| b.iter().map(move |y| (x, y)))
            .filter(|(x, y)| x.volume.overlaps(&y.volume))
            .map(|(x, y)| (x.id, y.id))
            .collect();
        expected.sort_unstable();
        assert_eq!(cross, expected, "H {H} n {n}: tree against tree");
    }
}

#[test]
fn self_and_tree_pairs_match_brute_force() {
    for seed in 0..4 {
        check::<3>(seed);
        check::<7>(seed);
        check::<9>(seed);
        check::<13>(seed);
    }
}

#[test]
fn builds_are_deterministic() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let a: Vec<Leaf<Kdop<9>>> = leaves(&mut rng, 1000);
    let (x, y) = (Bvh::from_leaves(&a), Bvh::from_leaves(&a));
    assert_eq!(x.nodes(), y.nodes());
    let depth = |bvh: &Bvh<Kdop<9>>| {
        let mut stack = vec![(0u32, 0usize)];
        let mut deepest = 0;
        while let Some((n, d)) = stack.pop() {
            deepest = deepest.max(d);
            if let Some([l, r]) = bvh.nodes()[n as usize].children() {
                stack.extend([(l, d + 1), (r, d + 1)]);
            }
        }
        deepest
    };
    assert_eq!(depth(&x), 10); // ceil(log2(1000))
}

/// Inflation covers every point within the distance, for the non-unit directions too; swept
/// triangles contain the moving triangle at every time.
fn inflation_and_sweep<const H: usize>() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for _ in 0..200 {
        let t0 = [0; 3].map(|_| point(&mut rng, 1.0));
        let t1 = [0; 3].map(|_| point(&mut rng, 1.0));
        let d = rng.random_range(0.0..0.3);
        let swept = Kdop::<H>::swept_triangle(&t0, &t1, d);
        let tight = Kdop::<H>::swept_triangle(&t0, &t1, 0.0);
        assert!(swept.contains(&tight));
        for _ in 0..50 {
            let (t, u, v) = (
                rng.random::<f64>(),
                rng.random::<f64>(),
                rng.random::<f64>(),
            );
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            let at = |k: usize| t0[k] + (t1[k] - t0[k]) * t;
            let p = at(0) + (at(1) - at(0)) * u + (at(2) - at(0)) * v;
            assert!(tight.contains_point(p));
            let offset = point(&mut rng, 1.0).normalize_or_zero() * d * 0.999;
            assert!(swept.contains_point(p + offset), "H {H}");
        }
    }
}

#[test]
fn inflated_swept_volumes_are_conservative() {
    inflation_and_sweep::<3>();
    inflation_and_sweep::<7>();
    inflation_and_sweep::<9>();
    inflation_and_sweep::<13>();
}
