//! `topoccd proximity FRAME --dhat D`: the pairs it writes are the brute-force oracle's on the
//! same file, free edges (PLY `edge` elements) and free points included; `--timeout` is
//! checked like the other commands'.

mod common;

use common::{run, TempDir};
use topoccd::io::read_mesh;
use topoccd::{proximity, Configuration, ProximityMethod, ProximityOptions};

/// The oracle's pairs on `frame` for `dhat`, as the CLI's lines without distance and type,
/// sorted; with the file's free edges, or without them.
fn oracle(frame: &std::path::Path, dhat: f64, with_edges: bool) -> Vec<String> {
    let mesh = read_mesh(frame).unwrap();
    let edges = if with_edges { &mesh.edges[..] } else { &[] };
    let config = Configuration::new(&mesh.positions, &mesh.triangles, edges).unwrap();
    let options = ProximityOptions {
        dhat,
        method: ProximityMethod::Brute,
        max_contacts: None,
        ..ProximityOptions::default()
    };
    let r = proximity(&config, &options).unwrap();
    let mut lines: Vec<String> = (r.vf.iter().map(|p| format!("vf,{},{}", p.vertex, p.face)))
        .chain((r.ee.iter()).map(|p| format!("ee,{},{},{},{}", p.a[0], p.a[1], p.b[0], p.b[1])))
        .chain((r.ve.iter()).map(|p| format!("ve,{},{},{}", p.vertex, p.edge[0], p.edge[1])))
        .chain(r.vv.iter().map(|p| format!("vv,{},{}", p.a, p.b)))
        .collect();
    lines.sort();
    lines
}

/// The CLI's `--pairs -` lines without their distance and type, sorted.
fn cli_pairs(frame: &std::path::Path, dhat: f64, extra: &[&str]) -> Vec<String> {
    let dhat = dhat.to_string();
    let mut args = vec![
        "proximity",
        frame.to_str().unwrap(),
        "--dhat",
        &dhat,
        "--pairs",
        "-",
    ];
    args.extend_from_slice(extra);
    let r = run(None, &args, &[]);
    assert!(r.output.status.success(), "{}", r.stderr);
    let mut lines: Vec<String> = (r.stdout.lines())
        .map(|l| {
            let mut fields: Vec<&str> = l.split(',').collect();
            fields.truncate(fields.len() - 2);
            fields.join(",")
        })
        .collect();
    lines.sort();
    lines
}

#[test]
fn the_pairs_are_the_oracles_with_free_edges_and_points() {
    // rod-rain's frame 1 of 3 (t = 1/2) has its particles among the rods.
    for (scene, dhat, frames) in [
        ("hair", 0.05, "2"),
        ("funnel-particles", 0.05, "2"),
        ("rod-rain", 0.1, "3"),
    ] {
        let dir = TempDir::new("proximity", scene);
        let seq = dir.0.join("seq");
        let g = run(
            None,
            &["gen", scene, seq.to_str().unwrap(), "--frames", frames],
            &[],
        );
        assert!(g.output.status.success(), "{}", g.stderr);
        let frame = seq.join("0001.ply");
        let expected = oracle(&frame, dhat, true);
        assert!(expected.len() > 100, "{scene}: {} pairs", expected.len());
        assert_eq!(cli_pairs(&frame, dhat, &[]), expected, "{scene}");
        // The hair's free edges change the answer: a reader that dropped them would fail
        // above. (The particles are free points: no edge element.)
        if scene == "hair" {
            assert_ne!(oracle(&frame, dhat, false), expected, "{scene}");
        }
        // rod-rain has point-edge and point-point pairs.
        if scene == "rod-rain" {
            for kind in ["ve,", "vv,"] {
                assert!(
                    expected.iter().any(|l| l.starts_with(kind)),
                    "{scene}: {kind}"
                );
            }
        }
    }
}

#[test]
fn timeout_is_checked_before_any_work() {
    let dir = TempDir::new("proximity", "timeout");
    let seq = dir.0.join("seq");
    let g = run(
        None,
        &["gen", "hair", seq.to_str().unwrap(), "--frames", "2"],
        &[],
    );
    assert!(g.output.status.success(), "{}", g.stderr);
    let frame = seq.join("0001.ply");
    for bad in ["0", "soon", "inf"] {
        let args = [
            "proximity",
            frame.to_str().unwrap(),
            "--dhat",
            "0.05",
            "--timeout",
            bad,
        ];
        let r = run(None, &args, &[]);
        assert_eq!(r.output.status.code(), Some(2), "--timeout {bad}");
        assert!(
            r.stderr.contains("seconds"),
            "--timeout {bad}: {}",
            r.stderr
        );
    }
    // A generous one changes nothing.
    let got = cli_pairs(&frame, 0.05, &["--timeout", "60"]);
    assert_eq!(got, oracle(&frame, 0.05, true));
}
