//! The parts of the proximity query timed one by one, for the floor of issue 42 (what the
//! best design could take): the features' boxes and the refit, the traversal alone (leaf
//! pairs counted), the traversal with the features' box rejects (the candidate feature
//! pairs written), the exact kernels over the candidates and over the reported pairs only
//! (each from a precomputed list, in a tight loop), and the report's sort. For the
//! `prox_probe` binary of `topoccd-benches`; with the feature `internals` only.

use std::hint::black_box;

use crate::distance::{edge_edge_distance, point_triangle_distance};
use crate::Ccd;

use super::pairs::Found;
use super::primitives::Kind;
use super::{Configuration, ProximityError, ProximityOptions, ProximityReport};

/// The figures of [`floor`]: counts, and seconds of each part (the median over the
/// repetitions, by the caller's clock).
#[derive(Clone, Debug, Default)]
pub struct FloorFigures {
    /// Overlapping leaf pairs (triangles, free edges, free points).
    pub leaf_pairs: u64,
    /// Vertex-face and edge-edge pairs past the features' boxes.
    pub candidates: (u64, u64),
    /// Vertex-face and edge-edge pairs reported.
    pub reported: (u64, u64),
    /// The features' boxes and the refit of the kept tree.
    pub fit: f64,
    /// The traversal alone, counting the overlapping leaf pairs.
    pub leaf_pairs_seconds: f64,
    /// The traversal with the features' box rejects, writing the candidates to a list.
    pub candidates_seconds: f64,
    /// The kernels (and the threshold test) over the candidates' list.
    pub kernels_candidates: f64,
    /// The kernels (and the threshold test) over the reported pairs' list.
    pub kernels_reported: f64,
    /// Sorting the report's pairs from the traversal's order.
    pub sort: f64,
    /// The feature tree (`features`): the vertex boxes and the refit of the kept tree.
    pub wide_fit: f64,
    /// The feature tree's queries with the per-pair tests and kernels (no sort).
    pub wide_find: f64,
    /// The feature tree's box tests (four per node visit).
    pub wide_box_tests: u64,
    /// The whole query on the kept `Ccd`: refit and traversal.
    pub query: f64,
    /// The whole query on the kept `Ccd` asked again at the same positions: the pairs it
    /// kept evaluated (see `cache`).
    pub reuse: f64,
}

/// Times each part of the proximity query on `config`, `reps` times each (median), by
/// `clock` (seconds), on the calling thread. Kernels run on vertex-face and edge-edge pairs
/// (the free points' pairs are left out: none in the frames measured).
pub fn floor(
    config: &Configuration<'_>,
    options: &ProximityOptions,
    reps: usize,
    clock: &dyn Fn() -> f64,
) -> Result<FloorFigures, ProximityError> {
    let mut ccd = Ccd::new();
    let report = ccd.proximity(config, options)?;
    let mut fig = FloorFigures {
        reported: (report.vf.len() as u64, report.ee.len() as u64),
        ..FloorFigures::default()
    };
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let reps = reps.max(1);
    let time = |f: &mut dyn FnMut()| {
        let mut t = Vec::with_capacity(reps);
        for _ in 0..reps {
            let s = clock();
            f();
            t.push(clock() - s);
        }
        median(t)
    };
    // A cap (never reached) keeps the query from evaluating the pairs the `Ccd` kept
    // (see `cache`): the refit and the traversal.
    let traverse = ProximityOptions {
        max_contacts: Some(usize::MAX),
        ..*options
    };
    fig.query = time(&mut || {
        black_box(ccd.proximity(config, &traverse).ok());
    });
    // Asked again after a move within the allowance (none here): the kept pairs evaluated.
    ccd.proximity(config, options)?;
    fig.reuse = time(&mut || {
        black_box(ccd.proximity(config, options).ok());
    });
    let st = &mut ccd.proximity;
    let (x, r) = (config.pos(), options.threshold());
    let tris = config.triangles();
    let big = super::boxes::largest_side(&st.prims, tris, x);
    let h = super::boxes::inflation(big, x, r);
    fig.fit = time(&mut || {
        black_box(st.fit(config, h));
    });
    let test = super::run::test(config, options);
    let (features, prims, fws) = (&mut st.features, &st.prims, &mut st.ws);
    fig.wide_fit = time(&mut || {
        black_box(features.fit(prims, x, h, fws));
    });
    let token = crate::query::CancelToken::default();
    let stop = super::run::Stop::cancel_only(&token);
    let mut box_tests = 0;
    fig.wide_find = time(&mut || {
        let (f, b) = features.find(&test, &stop, usize::MAX);
        black_box(f.len());
        box_tests = b;
    });
    fig.wide_box_tests = box_tests;
    let (slots, tree, ws) = (&st.slots, &st.tree, &mut st.ws);
    let mut leaf_pairs = 0u64;
    fig.leaf_pairs_seconds = time(&mut || {
        leaf_pairs = 0;
        tree.bvh.self_pairs(ws, |_, _| leaf_pairs += 1);
    });
    fig.leaf_pairs = leaf_pairs;
    // The candidates: the leaf pairs' features past the boxes, as the query takes them.
    let (mut vf, mut ee) = (Vec::new(), Vec::new());
    fig.candidates_seconds = time(&mut || {
        vf.clear();
        ee.clear();
        tree.bvh.self_pairs(ws, |a, b| {
            test.leaf_candidates(slots, a, b, &mut vf, &mut ee);
        });
    });
    fig.candidates = (vf.len() as u64, ee.len() as u64);
    let r2 = r * r;
    let kernels = |vf: &[(u32, u32)], ee: &[([u32; 2], [u32; 2])]| {
        let mut kept = 0usize;
        for &(v, f) in vf {
            let t = tris[f as usize].map(|i| x[i as usize]);
            let (d2, _) = point_triangle_distance(x[v as usize], t[0], t[1], t[2]);
            kept += usize::from(d2 < r2);
        }
        for &(a, b) in ee {
            let (d2, _) = edge_edge_distance(
                x[a[0] as usize],
                x[a[1] as usize],
                x[b[0] as usize],
                x[b[1] as usize],
            );
            kept += usize::from(d2 < r2);
        }
        black_box(kept)
    };
    fig.kernels_candidates = time(&mut || {
        kernels(&vf, &ee);
    });
    let rvf: Vec<(u32, u32)> = report.vf.iter().map(|p| (p.vertex, p.face)).collect();
    let ree: Vec<([u32; 2], [u32; 2])> = report.ee.iter().map(|p| (p.a, p.b)).collect();
    fig.kernels_reported = time(&mut || {
        kernels(&rvf, &ree);
    });
    // The report's pairs in the traversal's order, sorted.
    let mut found = Found::default();
    tree.bvh
        .self_pairs(ws, |a, b| test.leaf_pair(slots, a, b, &mut found));
    fig.sort = time(&mut || {
        let mut rep = ProximityReport {
            vf: found.vf.clone(),
            ee: found.ee.clone(),
            ve: found.ve.clone(),
            vv: found.vv.clone(),
            ..ProximityReport::default()
        };
        rep.sort();
        black_box(rep.len());
    });
    Ok(fig)
}

impl super::pairs::Test<'_> {
    /// The vertex-face and edge-edge pairs of the leaf pair `(a, b)` past the features'
    /// boxes and the shared-vertex filter, as [`Self::leaf_pair`] takes them, written out.
    fn leaf_candidates(
        &self,
        s: &super::slots::Slots,
        a: u32,
        b: u32,
        vf: &mut Vec<(u32, u32)>,
        ee: &mut Vec<([u32; 2], [u32; 2])>,
    ) {
        use super::boxes::overlap;
        let (sa, sb) = (s.slot_of[a as usize], s.slot_of[b as usize]);
        let (la, lb) = (&s.slots[sa as usize], &s.slots[sb as usize]);
        for (l, m, sm) in [(la, lb, sb), (lb, la, sa)] {
            if m.kind == Kind::Triangle {
                let tb = &s.lbox[sm as usize];
                for i in l.v0..l.v0 + l.nv {
                    let v = s.verts[i as usize];
                    if overlap(&s.vbox[i as usize], tb) && !m.verts.contains(&v) {
                        vf.push((v, m.id));
                    }
                }
            }
        }
        for i in la.e0..la.e0 + la.ne {
            let ea = s.edges[i as usize];
            for j in lb.e0..lb.e0 + lb.ne {
                let eb = s.edges[j as usize];
                if overlap(&s.ebox[i as usize], &s.ebox[j as usize])
                    && ea[0] != eb[0]
                    && ea[0] != eb[1]
                    && ea[1] != eb[0]
                    && ea[1] != eb[1]
                {
                    ee.push((ea, eb));
                }
            }
        }
    }
}
