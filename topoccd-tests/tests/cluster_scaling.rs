//! Cost of the clustering on a 100K-triangle deforming cloth-like sheet, with a reused
//! workspace (as a simulator calls it every step). Prints the figures; asserts only a generous
//! bound, so that a shared machine does not make it flaky.

use std::time::Instant;
use topoccd::broad::cluster::{cluster_with, ClusterOptions, ClusterWorkspace};
use topoccd::math::DVec3;
use topoccd::mesh::Topology;
use topoccd::Step;

/// An `n x n` quad grid (2 n^2 triangles) on `[0, 1]^2`, draped by `f0` at t=0 and `f1` at t=1.
fn sheet(n: u32, f0: impl Fn(f64, f64) -> DVec3, f1: impl Fn(f64, f64) -> DVec3) -> Step<'static> {
    let (mut x0, mut x1) = (Vec::new(), Vec::new());
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            x0.push(f0(u, v));
            x1.push(f1(u, v));
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut tris = Vec::with_capacity((2 * n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Step::new(x0, x1, tris).expect("valid sheet")
}

fn run(name: &str, step: &Step, options: &ClusterOptions) -> f64 {
    let topo = Topology::new(step.triangles(), step.vertex_count());
    let mut workspace = ClusterWorkspace::default();
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..3 {
        let started = Instant::now();
        let c = cluster_with(step, &topo, options, &mut workspace);
        best = best.min(started.elapsed().as_secs_f64());
        last = Some(c);
    }
    if let Some(c) = last {
        let s = c.stats;
        println!(
            "{name}: {} triangles -> {} leaves ({:.1} tri/leaf), {} ICs ({:.1} tri/IC); \
             leaves {:.1} ms + merge {:.1} ms, best total {:.1} ms; stops phi {} cert {} \
             exhausted {}; failures {:?}",
            s.triangles,
            s.leaves,
            s.triangles_per_leaf,
            s.intermediates,
            s.triangles_per_intermediate,
            s.clustering_seconds * 1e3,
            s.merging_seconds * 1e3,
            best * 1e3,
            s.stops_phi,
            s.stops_certificate,
            s.stops_exhausted,
            s.disk_failures
        );
    }
    best
}

#[test]
fn hundred_thousand_triangle_sheets() {
    let n = 224; // 100,352 triangles
    let paper = ClusterOptions::default();
    let certificate_only = ClusterOptions {
        phi_filter: false,
        ..ClusterOptions::default()
    };
    let flat = sheet(
        n,
        |u, v| DVec3::new(u, v, 0.0),
        |u, v| DVec3::new(u + 0.01 * v, v, 0.02),
    );
    let cloth = sheet(
        n,
        |u, v| DVec3::new(u, v, 0.03 * (9.0 * u).sin() * (7.0 * v).cos()),
        |u, v| {
            DVec3::new(
                u + 0.002,
                v,
                0.03 * (9.0 * u + 0.3).sin() * (7.0 * v).cos() - 0.01,
            )
        },
    );
    let mut worst: f64 = 0.0;
    for (name, step) in [("flat 100K", &flat), ("cloth 100K", &cloth)] {
        worst = worst.max(run(name, step, &paper));
        worst = worst.max(run(&format!("{name} (no phi)"), step, &certificate_only));
    }
    assert!(worst < 5.0, "clustering 100K triangles took {worst} s");
}
