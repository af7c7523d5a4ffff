//! The paper's generated scenes at scale 0.1: on every step, the cluster and BVH methods report
//! the brute-force oracle's pairs, with bitwise-equal times of impact.
//!
//! The oracle filters pairs by swept boxes only, so it also reports the narrow phase's false
//! positives (features passing within rounding distance, like a vertex 2e-13 from a face's corner
//! in the generated airbag), which the hierarchies' k-DOPs may prove separated and never test.
//! So the check is: every method's pair is the oracle's, with the same time; and every oracle
//! pair a method lacks is provably separated (the padded swept k-DOPs of its two features are
//! disjoint), so no contact is lost.

use std::path::Path;

use topoccd::io::sequence::step_from_frames;
use topoccd::kdop::Kdop;
use topoccd::math::DVec3;
use topoccd::scene::paper::{generate_frames, GenOptions, PaperScene};
use topoccd::step::{Ccd, Method, QueryOptions, Report, Step};

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

/// The padded swept 18-DOP of a feature given by its vertices (1, 2 or 3 of them).
fn swept(step: &Step, vertices: &[u32]) -> Kdop<9> {
    let at = |x: &[DVec3]| [0, 1, 2].map(|k| x[vertices[k.min(vertices.len() - 1)] as usize]);
    Kdop::<9>::swept_triangle(&at(step.x0()), &at(step.x1()), 0.0)
}

/// Checks `got` against the oracle as described in the module documentation.
fn check(step: &Step, oracle: &Pairs, got: &Pairs, what: &str) {
    for p in &got.0 {
        assert!(oracle.0.contains(p), "{what}: vf {p:?} not in the oracle");
    }
    for p in &got.1 {
        assert!(oracle.1.contains(p), "{what}: ee {p:?} not in the oracle");
    }
    let tris = step.triangles();
    for &(v, f, toi) in oracle.0.iter().filter(|p| !got.0.contains(p)) {
        let separated = !swept(step, &[v]).overlaps(&swept(step, &tris[f as usize]));
        assert!(
            separated,
            "{what}: missed vf ({v}, {f}) at {}",
            f64::from_bits(toi)
        );
    }
    for &(a, b, toi) in oracle.1.iter().filter(|p| !got.1.contains(p)) {
        let separated = !swept(step, &a).overlaps(&swept(step, &b));
        assert!(
            separated,
            "{what}: missed ee ({a:?}, {b:?}) at {}",
            f64::from_bits(toi)
        );
    }
}

#[test]
fn every_method_equals_the_oracle_on_every_step_of_every_scene() {
    let options = QueryOptions::default();
    let mut ccd = Ccd::new();
    for scene in PaperScene::ALL {
        let gen = GenOptions {
            scale: 0.1,
            frames: 3,
            seed: 3,
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
            let oracle = pairs(&ccd.query(&step, Method::Brute, &options));
            for method in [Method::Bvh, Method::Cluster] {
                let got = pairs(&ccd.query(&step, method, &options));
                check(&step, &oracle, &got, &format!("{scene} step {k}, {method}"));
            }
            contacts += oracle.0.len() + oracle.1.len();
        }
        assert!(contacts > 0, "{scene}: no contact at all");
    }
}
