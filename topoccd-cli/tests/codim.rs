//! Codimensional geometry through the command line: `topoccd run` and `topoccd step` read free
//! edges from the frame files (PLY `edge` elements) and write the vertex-edge and
//! vertex-vertex contacts in their pairs files and JSON, the same as the library's report on
//! the same frames.

use std::path::{Path, PathBuf};
use std::process::Command;

use topoccd::io::{read_mesh, write_mesh, Mesh};
use topoccd::{query, Method, QueryOptions, Report, Step};

/// A fresh folder under the system temp dir, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        let path = std::env::temp_dir().join(format!("topoccd-codim-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        TempDir(path)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn topoccd(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_topoccd"))
        .args(args)
        .output()
        .expect("run topoccd");
    assert!(
        out.status.success(),
        "topoccd {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("utf-8")
}

/// The pairs file's lines the library's report gives, in the CLI's format.
fn pair_lines(r: &Report) -> Vec<String> {
    let vf =
        r.vf.iter()
            .map(|c| format!("vf,{},{},{}", c.vertex, c.face, c.toi));
    let ee =
        (r.ee.iter()).map(|c| format!("ee,{},{},{},{},{}", c.a[0], c.a[1], c.b[0], c.b[1], c.toi));
    let ve =
        (r.ve.iter()).map(|c| format!("ve,{},{},{},{}", c.vertex, c.edge[0], c.edge[1], c.toi));
    let vv = r.vv.iter().map(|c| format!("vv,{},{},{}", c.a, c.b, c.toi));
    vf.chain(ee).chain(ve).chain(vv).collect()
}

/// The pairs without their times, to compare with the oracle.
fn pairs_only(lines: &[String]) -> Vec<String> {
    let mut out: Vec<String> = lines
        .iter()
        .map(|l| l.rsplit_once(',').expect("a time").0.to_string())
        .collect();
    out.sort();
    out
}

/// Runs `topoccd run DIR --pairs-dir P` and checks every step's lines against the library on
/// the frames read back, and the pairs against the brute-force oracle. Returns all lines.
fn run_and_compare(dir: &Path, pairs: &Path) -> Vec<String> {
    topoccd(&[
        "run",
        dir.to_str().unwrap(),
        "--pairs-dir",
        pairs.to_str().unwrap(),
    ]);
    let mut frames: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ply"))
        .collect();
    frames.sort();
    assert!(frames.len() >= 2, "{frames:?}");
    let mut all = Vec::new();
    for (k, w) in frames.windows(2).enumerate() {
        let (m0, m1) = (read_mesh(&w[0]).unwrap(), read_mesh(&w[1]).unwrap());
        assert!(
            !m1.edges.is_empty(),
            "{}: the frame has edges",
            w[1].display()
        );
        let step = Step::new(&m0.positions, &m1.positions, &m1.triangles)
            .unwrap()
            .with_edges(&m1.edges)
            .unwrap();
        let library = pair_lines(&query(&step, Method::Auto, &QueryOptions::default()).unwrap());
        let oracle = pair_lines(&query(&step, Method::Brute, &QueryOptions::default()).unwrap());
        let file = pairs.join(format!("{k:04}.csv"));
        let cli: Vec<String> = std::fs::read_to_string(&file)
            .unwrap_or_else(|e| panic!("{}: {e}", file.display()))
            .lines()
            .map(str::to_string)
            .collect();
        assert_eq!(cli, library, "step {k}: the CLI's pairs are the library's");
        assert_eq!(
            pairs_only(&cli),
            pairs_only(&oracle),
            "step {k}: and the oracle's"
        );
        all.extend(cli);
    }
    all
}

#[test]
fn hair_run_reads_the_free_edges() {
    let (dir, pairs) = (TempDir::new("hair"), TempDir::new("hair-pairs"));
    topoccd(&["gen", "hair", dir.0.to_str().unwrap(), "--frames", "4"]);
    let lines = run_and_compare(&dir.0, &pairs.0);
    // Strands touch strands (edge-edge pairs of free edges) only when the edges were read.
    assert!(
        lines.iter().any(|l| l.starts_with("ee,")),
        "the hair bundle's strands collide: {lines:?}"
    );
}

/// A rod (the free edge 0-1) on the x axis; particle 2 falls across it at t=0.5, particle 3
/// onto particle 4 at t=0.25 (analytic times).
fn rod_and_particles(dir: &Path) {
    std::fs::create_dir_all(dir).unwrap();
    let x0 = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, 0.0, 1.0],
        [3.0, 0.0, 0.5],
        [3.0, 0.0, 0.0],
    ];
    let x1 = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, 0.0, -1.0],
        [3.0, 0.0, -1.5],
        [3.0, 0.0, 0.0],
    ];
    for (k, x) in [x0, x1].into_iter().enumerate() {
        let mut mesh = Mesh::new(x, Vec::new());
        mesh.edges = vec![[0, 1]];
        write_mesh(&dir.join(format!("{k:04}.ply")), &mesh).unwrap();
    }
}

#[test]
fn a_particle_crossing_a_rod_and_one_hitting_another() {
    let (dir, pairs) = (TempDir::new("rod"), TempDir::new("rod-pairs"));
    rod_and_particles(&dir.0);
    let lines = run_and_compare(&dir.0, &pairs.0);
    assert_eq!(pairs_only(&lines), ["ve,2,0,1", "vv,3,4"]);
    let toi = |prefix: &str| -> f64 {
        let line = lines.iter().find(|l| l.starts_with(prefix)).unwrap();
        line.rsplit_once(',').unwrap().1.parse().unwrap()
    };
    assert!(toi("ve,") <= 0.5 && toi("ve,") > 0.5 - 1e-6, "{lines:?}");
    assert!(toi("vv,") <= 0.25 && toi("vv,") > 0.25 - 1e-6, "{lines:?}");

    // `topoccd step --json --with-pairs`: the counts and the pairs of the new kinds.
    let (t0, t1) = (dir.0.join("0000.ply"), dir.0.join("0001.ply"));
    let json = topoccd(&[
        "step",
        t0.to_str().unwrap(),
        t1.to_str().unwrap(),
        "--json",
        "--with-pairs",
    ]);
    let v: serde_json::Value = serde_json::from_str(json.trim()).expect("one JSON object");
    assert_eq!(
        (v["ve"].as_u64(), v["vv"].as_u64()),
        (Some(1), Some(1)),
        "{json}"
    );
    assert_eq!(v["pairs"]["ve"][0]["vertex"], 2, "{json}");
    assert_eq!(v["pairs"]["vv"][0]["b"], 4, "{json}");
    assert!(
        v["earliest"]["Vv"].is_object(),
        "the earliest contact is the vv one: {json}"
    );
}
