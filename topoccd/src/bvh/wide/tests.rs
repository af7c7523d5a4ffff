//! The wide hierarchy against brute force (every leaf box tested) on seeded random and
//! degenerate boxes, after builds and refits, with and without a starting position.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{Box3, WideBvh};
use crate::bvh::{BoundingVolume, BvhWorkspace};
use crate::kdop::Kdop;
use crate::math::DVec3;

/// The box of points `p`, rounded outward to `f32`.
fn bx(p: &[DVec3]) -> Box3 {
    let (mut lo, mut hi) = (p[0], p[0]);
    for q in p {
        lo = lo.min(*q);
        hi = hi.max(*q);
    }
    Box3::outward(&Kdop {
        lo: lo.to_array(),
        hi: hi.to_array(),
    })
}

fn point(rng: &mut ChaCha8Rng, s: f64) -> DVec3 {
    DVec3::new(
        rng.random_range(-s..s),
        rng.random_range(-s..s),
        rng.random_range(-s..s),
    )
}

/// Builds over `boxes`, validates, and checks every query box of `queries` (and every leaf's
/// own box, from the position after it) against brute force.
fn check(tree: &mut WideBvh, boxes: &[Box3], queries: &[Box3], rebuild: bool) {
    let n = boxes.len();
    if rebuild {
        let center = |i: usize| {
            let b = &boxes[i];
            DVec3::from_array(std::array::from_fn(|k| {
                0.5 * (f64::from(b.lo[k]) + f64::from(b.hi[k]))
            }))
        };
        tree.rebuild(n, center, |i| boxes[i as usize], &mut BvhWorkspace::default());
    } else {
        tree.refit(|i| boxes[i as usize]);
    }
    tree.validate(n, |i| boxes[i as usize]).unwrap();
    let mut stack = Vec::new();
    for q in queries {
        let mut got = Vec::new();
        tree.query(q, 0, &mut stack, |pos| got.push(tree.ids()[pos as usize]));
        got.sort_unstable();
        let want: Vec<u32> = (0..n as u32)
            .filter(|&i| boxes[i as usize].overlaps(q))
            .collect();
        assert_eq!(got, want);
    }
    // Ordered self-query: every overlapping unordered pair once.
    let mut got = Vec::new();
    for (p, &id) in tree.ids().iter().enumerate() {
        tree.query(&boxes[id as usize], p as u32 + 1, &mut stack, |pos| {
            let other = tree.ids()[pos as usize];
            got.push((id.min(other), id.max(other)));
        });
    }
    got.sort_unstable();
    let mut want = Vec::new();
    for i in 0..n as u32 {
        for j in i + 1..n as u32 {
            if boxes[i as usize].overlaps(&boxes[j as usize]) {
                want.push((i, j));
            }
        }
    }
    assert_eq!(got, want);
}

#[test]
fn random_boxes_equal_brute_force_after_builds_and_refits() {
    let mut tree = WideBvh::default();
    for seed in 0..8 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let n = [0, 1, 2, 3, 4, 5, 17, 300][seed as usize];
        let mut centers: Vec<DVec3> = (0..n).map(|_| point(&mut rng, 1.0)).collect();
        let make = |c: &[DVec3], rng: &mut ChaCha8Rng| -> Vec<Box3> {
            c.iter().map(|&p| bx(&[p, p + point(rng, 0.1)])).collect()
        };
        let boxes = make(&centers, &mut rng);
        let queries: Vec<Box3> = (0..50)
            .map(|_| {
                let p = point(&mut rng, 1.2);
                bx(&[p, p + point(&mut rng, 0.3)])
            })
            .collect();
        check(&mut tree, &boxes, &queries, true);
        // Move every leaf: refitted, then rebuilt.
        for c in &mut centers {
            *c += point(&mut rng, 0.3);
        }
        let boxes = make(&centers, &mut rng);
        check(&mut tree, &boxes, &queries, false);
        check(&mut tree, &boxes, &queries, true);
    }
}

#[test]
fn degenerate_boxes_equal_brute_force() {
    let mut tree = WideBvh::default();
    let p = DVec3::new(0.3, -0.2, 0.1);
    // All leaves the same point; all the same box; points on a line; touching boxes
    // (shared faces only), zero-width boxes in one axis, and huge coordinates.
    let same: Vec<Box3> = (0..40).map(|_| bx(&[p])).collect();
    let line: Vec<Box3> = (0..40)
        .map(|i| bx(&[DVec3::new(i as f64, 0.0, 0.0)]))
        .collect();
    let touching: Vec<Box3> = (0..40)
        .map(|i| bx(&[DVec3::new(i as f64, 0.0, 0.0), DVec3::new(i as f64 + 1.0, 1.0, 1.0)]))
        .collect();
    let flat: Vec<Box3> = (0..40)
        .map(|i| {
            let x = (i % 7) as f64 * 0.25;
            bx(&[DVec3::new(x, 0.0, 0.5), DVec3::new(x + 0.5, 1.0, 0.5)])
        })
        .collect();
    let huge: Vec<Box3> = (0..40)
        .map(|i| bx(&[DVec3::splat(1e30 * (i as f64 - 20.0)), DVec3::splat(1e30 * (i as f64 - 19.5))]))
        .collect();
    let queries = vec![
        bx(&[p]),
        bx(&[DVec3::new(3.0, 0.0, 0.0)]),
        bx(&[DVec3::new(2.5, 0.5, 0.5), DVec3::new(4.0, 0.5, 0.5)]),
        bx(&[DVec3::new(0.0, 0.0, 0.5)]),
        bx(&[DVec3::splat(-1e31), DVec3::splat(1e31)]),
        bx(&[DVec3::splat(100.0)]),
    ];
    for boxes in [&same, &line, &touching, &flat, &huge] {
        check(&mut tree, boxes, &queries, true);
        check(&mut tree, boxes, &queries, false);
    }
}
