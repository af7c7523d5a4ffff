//! The tables of `bench` and `demo` as text, each column explained in a legend.

use super::tables::InputTables;
use super::words::{plural, thousands};

/// Prints the tables of one input as text, each column explained in a legend under its table.
pub fn print_text(t: &InputTables) {
    let triangles = if t.triangles[0] == t.triangles[1] {
        plural(t.triangles[0], "triangle")
    } else {
        format!(
            "{} to {} triangles",
            thousands(t.triangles[0]),
            thousands(t.triangles[1])
        )
    };
    println!(
        "== {} ({}, {triangles}){}",
        t.input,
        plural(t.steps, "step"),
        if t.agree { "" } else { "  METHODS DISAGREE" }
    );
    println!(
        "Table 1: time and work per step (averages over {})",
        plural(t.steps, "step")
    );
    // Every phase any method has, in pipeline order.
    let phase_names: Vec<&str> = ["clustering", "merging", "build", "traverse", "narrow"]
        .into_iter()
        .filter(|p| {
            t.methods
                .iter()
                .any(|m| m.seconds.iter().any(|s| s.0 == *p))
        })
        .collect();
    let mut header = format!("  {:<8}", "method");
    for p in &phase_names {
        header.push_str(&format!(" {:>13}", format!("{p} ms")));
    }
    header.push_str(&format!(
        " {:>10} {:>12} {:>12} {:>13}",
        "total ms", "BV tests", "elem. tests", "contacts/step"
    ));
    println!("{header}");
    for m in &t.methods {
        let mut line = format!("  {:<8}", m.method);
        for p in &phase_names {
            match m.seconds.iter().find(|s| s.0 == *p) {
                Some(s) => line.push_str(&format!(" {:>13.2}", s.1 * 1e3)),
                None => line.push_str(&format!(" {:>13}", "-")),
            }
        }
        line.push_str(&format!(
            " {:>10.2} {:>12.0} {:>12.0} {:>13.1}",
            m.total * 1e3,
            m.bv_tests,
            m.elementary_tests,
            m.contacts
        ));
        println!("{line}");
    }
    println!("  What the columns mean:");
    let has = |name: &str| t.methods.iter().any(|m| m.method == name);
    if has("bvh") {
        println!("    bvh: a bounding-volume hierarchy (a tree of boxes around the triangles), rebuilt when the triangles change");
    }
    if has("cluster") {
        println!(
            "    cluster: the paper's method: triangles grouped into clusters that stay valid \
             over the step, a hierarchy per cluster"
        );
    }
    if has("brute") {
        println!("    brute: every pair of features tested, no hierarchy (the reference)");
    }
    for p in &phase_names {
        let what = match *p {
            "clustering" => "grouping the triangles into leaf clusters (cluster only)",
            "merging" => "merging leaf clusters into intermediate clusters (cluster only)",
            "build" => "building the bounding volumes and hierarchies",
            "traverse" => "finding the pairs of bounding volumes that overlap",
            "narrow" => "the exact tests of the candidate pairs",
            _ => "",
        };
        println!("    {p} ms: milliseconds spent on {what}");
    }
    println!("    BV tests: bounding-volume overlap tests (cheap box-against-box checks)");
    println!(
        "    elem. tests: elementary tests, the exact continuous tests of a vertex against a \
         triangle or an edge against an edge"
    );
    println!("    contacts/step: colliding pairs found per step (the same for every method)");
    if let Some(c) = &t.clusters {
        println!("Table 2: the cluster method's clusters (averages per step)");
        println!(
            "  {:.0} leaf clusters, {:.0} intermediate clusters, {:.1} triangles per leaf cluster, \
             {:.0} leaf-cluster hierarchies built",
            c.leaf, c.intermediate, c.triangles_per_leaf, c.lazy_bvhs
        );
        println!(
            "  Leaf clusters are groups of neighbouring triangles; intermediate clusters group \
             leaf clusters. A leaf cluster's hierarchy is built only when another cluster comes \
             near it (lazily)."
        );
    }
    if let Some(s) = t.speedup_cluster_over_bvh {
        println!("Speedup of cluster over bvh: {s:.2}x (bvh's total time / cluster's)");
    }
}
