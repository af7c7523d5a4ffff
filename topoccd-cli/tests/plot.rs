//! `topoccd bench --plot`: a one-step input is drawn as labelled bars, every input gets a
//! stacked per-phase view, and the legends sit beside the charts.

use std::process::Command;

fn topoccd(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_topoccd"))
        .args(args)
        .output()
        .expect("run topoccd")
}

#[test]
fn a_one_step_input_is_plotted_as_bars_with_a_per_phase_view() {
    let dir = std::env::temp_dir().join(format!("topoccd-plot-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let scene = dir.join("scene");
    let scene = scene.to_str().expect("UTF-8");
    let out = topoccd(&["gen", "nidus", scene, "--scale", "0.01", "--frames", "2"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let png = dir.join("plot.png");
    let out = topoccd(&[
        "bench",
        scene,
        "--methods",
        "bvh,cluster",
        "--plot",
        png.to_str().expect("UTF-8"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let img = image::open(&png).expect("a PNG").to_rgb8();
    assert_eq!(img.dimensions(), (1280, 340));
    let count = |c: [u8; 3]| img.pixels().filter(|p| p.0 == c).count();
    // The bvh and cluster bars (not lone dots) in the left chart...
    let (bvh, cluster) = (count([31, 119, 180]), count([214, 39, 40]));
    assert!(bvh > 2000 && cluster > 2000, "bars: {bvh} {cluster}");
    // ...and the stacked phases on the right: build, traverse, clustering at least.
    for (name, c) in [
        ("build", [23, 190, 207]),
        ("traverse", [127, 127, 127]),
        ("clustering", [255, 127, 14]),
    ] {
        assert!(count(c) > 200, "{name}: {} pixels", count(c));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
