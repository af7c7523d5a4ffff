//! Proximity on every generated scene: the hierarchy's pairs equal the brute-force oracle's,
//! at both ends of each step, with rods (free edges) and particles (free points) added among
//! the triangles, with groups, refitted across configurations, on one and two threads.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use topoccd::{
    Ccd, Configuration, ProximityMethod, ProximityOptions, ProximityReport, ProximityStats,
};
use topoccd_scenes::SceneKind;

/// The pairs without the figures.
fn pairs(r: &ProximityReport) -> ProximityReport {
    ProximityReport {
        stats: ProximityStats::default(),
        ..r.clone()
    }
}

/// Adds rods (polylines of `rod` vertices starting near random mesh vertices) and particles
/// (near random mesh vertices) to both configurations, offset by about `gap`.
fn add_codim(x0: &mut Vec<[f64; 3]>, x1: &mut Vec<[f64; 3]>, seed: u64, gap: f64) -> Vec<[u32; 2]> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n = x0.len();
    let mut edges = Vec::new();
    let jitter = |rng: &mut ChaCha8Rng, p: [f64; 3]| p.map(|c| c + rng.random_range(-gap..gap));
    for _ in 0..20 {
        let mut prev: Option<u32> = None;
        let start = rng.random_range(0..n);
        for k in 0..8 {
            let at = (start + 3 * k) % n;
            let (a, b) = (jitter(&mut rng, x0[at]), jitter(&mut rng, x1[at]));
            x0.push(a);
            x1.push(b);
            let v = x0.len() as u32 - 1;
            if let Some(p) = prev {
                edges.push([p, v]);
            }
            prev = Some(v);
        }
    }
    let rods_end = x0.len();
    for k in 0..200 {
        // Every fourth particle near a rod's vertex, the others near the mesh's.
        let at = if k % 4 == 0 {
            rng.random_range(n..rods_end)
        } else {
            rng.random_range(0..n)
        };
        let (a, b) = (jitter(&mut rng, x0[at]), jitter(&mut rng, x1[at]));
        x0.push(a);
        x1.push(b);
    }
    edges
}

#[test]
fn every_generated_scene_equals_the_oracle() {
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    for kind in SceneKind::ALL {
        for seed in [1, 7] {
            let size = if kind == SceneKind::SmallObjects {
                12
            } else {
                24
            };
            let step = kind.generate(size, seed);
            let mut x0 = step.x0().to_vec();
            let mut x1 = step.x1().to_vec();
            let tris = step.triangles().to_vec();
            // The bounding box's diagonal.
            let (lo, hi) = x0
                .iter()
                .fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), p| {
                    (
                        [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                        [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
                    )
                });
            let diag = (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt();
            let edges = add_codim(&mut x0, &mut x1, seed, 0.01 * diag);
            let groups: Vec<u32> = (0..x0.len() as u32).map(|v| v % 3).collect();
            let mut ccd = Ccd::new();
            let mut found = [0usize; 4];
            for (k, x) in [&x0, &x1].into_iter().enumerate() {
                for dhat in [0.005 * diag, 0.02 * diag] {
                    for with_groups in [false, true] {
                        let config = Configuration::new(x, &tris[..], &edges).unwrap();
                        let config = if with_groups {
                            config.with_groups(&groups).unwrap()
                        } else {
                            config
                        };
                        let options = ProximityOptions {
                            dhat,
                            ..ProximityOptions::default()
                        };
                        let brute = ProximityOptions {
                            method: ProximityMethod::Brute,
                            ..options
                        };
                        let what = format!(
                            "{} seed {seed} end {k} dhat {dhat} groups {with_groups}",
                            kind.name()
                        );
                        let oracle = one.install(|| Ccd::new().proximity(&config, &brute).unwrap());
                        let got = two.install(|| ccd.proximity(&config, &options).unwrap());
                        assert_eq!(pairs(&got), pairs(&oracle), "{what}");
                        let single =
                            one.install(|| Ccd::new().proximity(&config, &options).unwrap());
                        assert_eq!(pairs(&single), pairs(&got), "{what}: 1 and 2 threads");
                        found[0] += got.vf.len();
                        found[1] += got.ee.len();
                        found[2] += got.ve.len();
                        found[3] += got.vv.len();
                    }
                }
            }
            assert!(
                found.iter().all(|&n| n > 0),
                "{} seed {seed}: {found:?}",
                kind.name()
            );
        }
    }
}
