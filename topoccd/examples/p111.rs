use topoccd::io::*;
use topoccd::narrow::*;
fn main() {
    let d = std::path::Path::new("/work/shared/data/scenes/cloth-funnel");
    let f = scene_frames(d).unwrap();
    let m0 = read_mesh(&f.t0).unwrap();
    let m1 = read_mesh(&f.t1).unwrap();
    let t = read_scene_truth(d).unwrap();
    let ((a, b), _) = t.ee_all[111];
    let x0 = |i: u32| m0.positions[i as usize];
    let x1 = |i: u32| m1.positions[i as usize];
    let q = EdgeEdge::from_points([
        x0(a[0]),
        x0(a[1]),
        x0(b[0]),
        x0(b[1]),
        x1(a[0]),
        x1(a[1]),
        x1(b[0]),
        x1(b[1]),
    ]);
    println!("{:?}", edge_edge(&q, &NarrowOptions::default()));
}
