//! The paper's generated scenes at scale 0.1 (seeds 1, 2 and 7): on every step, the brute-force
//! oracle, the per-step BVH and the cluster method report the same pairs with bitwise-equal
//! times of impact, with the crack filter on (the default) and off.
//!
//! Each pair also passes the checks every method shares (the pair filter and the owner
//! triangles' k-DOP test, see the library's `broad` module), so even the narrow phase's false
//! positives (features passing within rounding distance, like a vertex 2e-13 from a face's
//! corner in the generated airbag) are the same for all.

use std::path::Path;

use topoccd::io::sequence::step_from_frames;
use topoccd::{Ccd, Method, QueryOptions, Report};
use topoccd_scenes::paper::{generate_frames, GenOptions, PaperScene};

/// The pairs of a report with their times' bits.
type Pairs = (Vec<(u32, u32, u64)>, Vec<([u32; 2], [u32; 2], u64)>);

fn pairs(r: &Report) -> Pairs {
    (
        r.vf.iter()
            .map(|c| (c.vertex, c.face, c.toi.to_bits()))
            .collect(),
        r.ee.iter().map(|c| (c.a, c.b, c.toi.to_bits())).collect(),
    )
}

/// Every step of `scene` at scale 0.1 with seeds 1, 2 and 7.
fn check_scene(scene: PaperScene) {
    let mut ccd = Ccd::new();
    {
        for seed in [1, 2, 7] {
            let gen = GenOptions {
                scale: 0.1,
                frames: 3,
                seed,
            };
            let (frames, _) = generate_frames(scene, &gen);
            let mut contacts = 0;
            for (k, pair) in frames.windows(2).enumerate() {
                let step = step_from_frames(
                    &pair[0].mesh,
                    &pair[1].mesh,
                    &pair[1].parents,
                    Path::new("(generated)"),
                    k,
                )
                .expect("generated steps are valid");
                for crack_filter in [true, false] {
                    let options = QueryOptions {
                        crack_filter,
                        ..QueryOptions::default()
                    };
                    let oracle = pairs(&ccd.query(&step, Method::Brute, &options).unwrap());
                    for method in [Method::Bvh, Method::Cluster] {
                        let got = pairs(&ccd.query(&step, method, &options).unwrap());
                        let what = format!(
                            "{scene} seed {seed} step {k} {method} crack filter {crack_filter}"
                        );
                        assert_eq!(got.0, oracle.0, "{what}: vertex-face");
                        assert_eq!(got.1, oracle.1, "{what}: edge-edge");
                    }
                    contacts += oracle.0.len() + oracle.1.len();
                }
            }
            assert!(contacts > 0, "{scene} seed {seed}: no contact at all");
        }
    }
}

macro_rules! scene_tests {
    ($($name:ident: $scene:expr),* $(,)?) => {$(
        #[test]
        fn $name() {
            check_scene($scene);
        }
    )*};
}

scene_tests! {
    every_method_reports_the_same_pairs_on_nidus: PaperScene::Nidus,
    every_method_reports_the_same_pairs_on_nidus_cut: PaperScene::NidusCut,
    every_method_reports_the_same_pairs_on_airbag: PaperScene::Airbag,
    every_method_reports_the_same_pairs_on_lion: PaperScene::Lion,
    every_method_reports_the_same_pairs_on_bunny_dragon: PaperScene::BunnyDragon,
    every_method_reports_the_same_pairs_on_crash: PaperScene::Crash,
}

#[test]
fn the_scene_list_is_complete() {
    assert_eq!(PaperScene::ALL.len(), 6);
}
