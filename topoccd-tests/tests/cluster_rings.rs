//! Partial and whole rings: every leaf with several triangles is re-certified from scratch with
//! a fresh [`DiskBuilder`] (its direction and centre, all triangles in one batch, the whole
//! boundary), the clustering is deterministic, and partial rings never make more leaves than
//! whole rings on smooth input.

mod mesh_util;

use topoccd::broad::cluster::{
    cluster, ClusterOptions, Clustering, DiskBuilder, LeafCertificate, LeafDirection, RingGrowth,
};
use topoccd::mesh::Topology;
use topoccd::Step;

fn recertify(name: &str, step: &Step, options: &ClusterOptions) -> Clustering {
    let topo = Topology::new(step.triangles(), step.vertex_count());
    let c = cluster(step, &topo, options);
    let mut again = cluster(step, &topo, options);
    // Everything but the wall times.
    again.stats.clustering_seconds = c.stats.clustering_seconds;
    again.stats.merging_seconds = c.stats.merging_seconds;
    assert!(c == again, "{name}: not deterministic");
    let mut disk = DiskBuilder::default();
    for (l, leaf) in c.leaves.iter().enumerate() {
        if leaf.certificate == LeafCertificate::SingleTriangle {
            assert_eq!(leaf.triangles.len(), 1, "{name}: leaf {l}");
            continue;
        }
        disk.begin(
            &topo,
            step.vertex_count(),
            leaf.direction,
            leaf.centre,
            options.subdivisions,
        );
        let checked = disk
            .extend(step, &topo, c.leaf_triangles(l))
            .and_then(|()| disk.check_boundary(step, &topo, true));
        assert_eq!(checked, Ok(()), "{name}: leaf {l} is not a certified disk");
    }
    c
}

/// `random` smooth random steps, then `crumpled` crumpled sheets of side `side`, named.
fn random_and_crumpled(random: u64, crumpled: u64, side: usize) -> Vec<(String, Step<'static>)> {
    let mut steps: Vec<(String, Step)> = (0..random)
        .map(|s| (format!("random {s}"), mesh_util::random_smooth(s)))
        .collect();
    for s in 0..crumpled {
        steps.push((format!("crumpled {s}"), mesh_util::crumpled(side, s)));
    }
    steps
}

#[test]
fn partial_leaves_are_certified_disks() {
    let mut steps = random_and_crumpled(12, 4, 24);
    steps.push(("helicoid".into(), mesh_util::sinking_helicoid()));
    steps.push(("tight fold".into(), mesh_util::tight_fold()));
    steps.push(("partial tear".into(), mesh_util::partial_tear()));
    let (mut partial_leaves, mut whole_leaves) = (0, 0);
    for (name, step) in &steps {
        for direction in [LeafDirection::Seed, LeafDirection::Neighbourhood] {
            let options = ClusterOptions {
                phi_filter: false,
                direction,
                ..ClusterOptions::default()
            };
            let c = recertify(&format!("{name} {direction:?}"), step, &options);
            if direction == LeafDirection::Seed {
                partial_leaves += c.leaves.len();
            }
        }
        let whole = ClusterOptions {
            phi_filter: false,
            rings: RingGrowth::Whole,
            ..ClusterOptions::default()
        };
        whole_leaves += recertify(&format!("{name} whole"), step, &whole)
            .leaves
            .len();
    }
    println!("leaves: partial rings {partial_leaves}, whole rings {whole_leaves}");
    assert!(partial_leaves < whole_leaves);
}

/// Partial growth skips offers bound to be refused: a refused candidate is offered again only
/// once a triangle around it joins, and a candidate carried over to the next round starts it
/// refused. Growing without those shortcuts (every refused candidate offered after every pass
/// that adds and again in the next round) gives the same clustering, stop reasons and failure
/// counts included.
#[test]
fn growth_shortcuts_change_no_decision() {
    use topoccd::broad::cluster::{cluster_with, ClusterWorkspace};
    use topoccd_scenes::SceneKind;
    let mut steps = random_and_crumpled(6, 3, 40);
    for kind in SceneKind::ALL {
        steps.push((kind.name().to_string(), kind.generate(40, 1)));
    }
    let mut tracked_rounds = 0;
    for (name, step) in &steps {
        let topo = Topology::new(step.triangles(), step.vertex_count());
        for direction in [LeafDirection::Seed, LeafDirection::Neighbourhood] {
            let options = ClusterOptions {
                phi_filter: false,
                direction,
                ..ClusterOptions::default()
            };
            let mut fast = ClusterWorkspace::default();
            let mut reference = ClusterWorkspace::default();
            reference.reference_growth(true);
            let a = cluster_with(step, &topo, &options, &mut fast);
            let mut b = cluster_with(step, &topo, &options, &mut reference);
            b.stats.clustering_seconds = a.stats.clustering_seconds;
            b.stats.merging_seconds = a.stats.merging_seconds;
            assert!(
                a == b,
                "{name} {direction:?}: the shortcuts changed the clustering"
            );
            // Rounds big enough for the tracked offers (32 candidates or more).
            tracked_rounds += a.leaves.iter().filter(|l| l.triangles.len() >= 64).count();
        }
    }
    assert!(
        tracked_rounds > 0,
        "no leaf grew big enough to use the shortcuts"
    );
}
