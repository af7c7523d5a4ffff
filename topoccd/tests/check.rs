//! The static intersection check (`topoccd::check`): analytic cases (touching, coplanar,
//! crossing edges, a vertex on a face, and none where there is none, by one ulp), and the
//! tree's pairs against a brute-force double loop over every pair of triangles.

use topoccd::check::{intersections, step_intersections};
use topoccd::{Frame, Step};

/// A mesh of separate triangles, one per entry.
fn soup(triangles: &[[[f64; 3]; 3]]) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let x = triangles.iter().flatten().copied().collect();
    let t = (0..triangles.len() as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    (x, t)
}

fn pairs(triangles: &[[[f64; 3]; 3]]) -> Vec<[u32; 2]> {
    let (x, t) = soup(triangles);
    intersections(&x, &t).expect("valid mesh")
}

const BASE: [[f64; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

fn up(z: f64) -> f64 {
    f64::from_bits(z.to_bits() + 1) // the next f64 above a positive z (or above 0)
}

#[test]
fn a_vertex_on_a_face_touches_and_one_ulp_above_it_does_not() {
    let on = [[0.25, 0.25, 0.0], [0.25, 0.25, 1.0], [0.5, 0.25, 1.0]];
    assert_eq!(pairs(&[BASE, on]), vec![[0, 1]]);
    let above = [[0.25, 0.25, up(0.0)], [0.25, 0.25, 1.0], [0.5, 0.25, 1.0]];
    assert!(pairs(&[BASE, above]).is_empty());
    // On the face's edge and on its corner.
    let on_edge = [[0.5, 0.0, 0.0], [0.5, -0.5, 1.0], [0.7, -0.5, 1.0]];
    let on_corner = [[1.0, 0.0, 0.0], [2.0, 0.0, 1.0], [2.0, 1.0, 1.0]];
    assert_eq!(pairs(&[BASE, on_edge, on_corner]), vec![[0, 1], [0, 2]]);
}

#[test]
fn crossing_edges_and_edges_passing_by() {
    // Edge (0.5,-0.5,0)-(0.5,0.5,0) of the second triangle crosses base edge (0,0,0)-(1,0,0).
    let crossing = [[0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [0.5, 0.0, -1.0]];
    // ... or passes it by one ulp above (the base edge lies in z = 0).
    let passing = [[0.5, -0.5, up(0.0)], [0.5, 0.5, up(0.0)], [0.5, 0.0, 1.0]];
    assert_eq!(pairs(&[BASE, crossing, passing]), vec![[0, 1]]);
    // Two edges in space touching at one point: the second triangle's corner edge meets the
    // base edge from below the plane.
    let touching = [[0.5, 0.0, 0.0], [0.5, -1.0, -1.0], [0.6, -1.0, -1.0]];
    assert_eq!(pairs(&[BASE, touching]), vec![[0, 1]]);
}

#[test]
fn coplanar_triangles_overlapping_touching_and_apart() {
    let shift = |t: [[f64; 3]; 3], dx: f64, dy: f64| t.map(|p| [p[0] + dx, p[1] + dy, p[2]]);
    let overlapping = shift(BASE, 0.25, 0.25);
    let inside = [[0.1, 0.1, 0.0], [0.2, 0.1, 0.0], [0.1, 0.2, 0.0]];
    let corner_to_corner = shift(BASE, 1.0, 0.0);
    let edge_to_edge =
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]].map(|p| [p[0] + 3.0, p[1], p[2]]); // moved away, with its own partner below
    let partner = shift(BASE, 3.0, 0.0); // shares the hypotenuse line with edge_to_edge
    let apart = shift(BASE, f64::from_bits(1.0f64.to_bits() + 1), 0.0); // one ulp past x = 1
    assert_eq!(pairs(&[BASE, overlapping]), vec![[0, 1]]);
    assert_eq!(pairs(&[BASE, inside]), vec![[0, 1]]);
    assert_eq!(pairs(&[BASE, corner_to_corner]), vec![[0, 1]]);
    assert_eq!(pairs(&[edge_to_edge, partner]), vec![[0, 1]]);
    assert!(pairs(&[BASE, apart]).is_empty());
}

#[test]
fn none_where_there_is_none() {
    let lift = |t: [[f64; 3]; 3], dz: f64| t.map(|p| [p[0], p[1], p[2] + dz]);
    // Parallel copies, a far triangle, and a triangle standing beside the base.
    let beside = [[1.5, 0.0, -1.0], [1.5, 1.0, 0.0], [1.5, 0.0, 1.0]];
    assert!(pairs(&[BASE, lift(BASE, 1e-9), lift(BASE, 1.0), beside]).is_empty());
    assert!(pairs(&[]).is_empty() && pairs(&[BASE]).is_empty());
}

#[test]
fn neighbours_and_the_two_sides_of_a_fresh_cut_are_not_reported() {
    // Two triangles sharing vertex 0 fold through each other: not reported (shared vertex).
    let x = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, -1.0],
        [0.5, 0.5, 1.0],
    ];
    assert!(intersections(&x, &[[0u32, 1, 2], [0, 3, 4]])
        .unwrap()
        .is_empty());
    // A square cut along its diagonal: the halves touch along the cut. As one mesh with
    // separate vertices they intersect; with the cut's parents, they count as one vertex.
    let x0 = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    let x1 = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let triangles = [[0u32, 1, 2], [4, 3, 5]];
    assert_eq!(intersections(&x1, &triangles).unwrap(), vec![[0, 1]]);
    let step = Step::with_parents(&x0, &x1, &triangles, &[[4, 1], [5, 2]]).unwrap();
    assert!(step_intersections(&step, Frame::Start).is_empty());
    assert!(step_intersections(&step, Frame::End).is_empty());
}

#[test]
fn bad_input_is_refused_with_the_element() {
    let x = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [f64::NAN, 1.0, 0.0]];
    let err = intersections(&x, &[[0u32, 1, 2]]).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("vertex 2 has a non-finite coordinate"),
        "{err}"
    );
    let err = intersections(&x[..2], &[[0u32, 1, 2]]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "triangle 0 names vertex 2, but there are only 2 vertices"
    );
}

/// A seeded generator (splitmix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e3779b97f4a7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58476d1ce4e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d049bb133111eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

/// The pairs of a double loop over every two triangles, each pair checked on its own.
fn brute_force(x: &[[f64; 3]], t: &[[u32; 3]]) -> Vec<[u32; 2]> {
    let mut out = Vec::new();
    for a in 0..t.len() {
        for b in a + 1..t.len() {
            if intersections(x, &[t[a], t[b]]).expect("valid") == vec![[0, 1]] {
                out.push([a as u32, b as u32]);
            }
        }
    }
    out
}

#[test]
fn the_tree_finds_exactly_the_pairs_of_a_double_loop() {
    let mut rng = Rng(37);
    // Vertices on a small integer grid: many coplanar, touching and collinear configurations;
    // and vertices in general position. Triangles share vertices at random.
    for (grid, vertices, count) in [(4u64, 40usize, 150usize), (0, 120, 200)] {
        let x: Vec<[f64; 3]> = (0..vertices)
            .map(|_| {
                std::array::from_fn(|_| match grid {
                    0 => rng.below(1 << 20) as f64 / (1 << 16) as f64,
                    g => rng.below(g) as f64,
                })
            })
            .collect();
        let mut t = Vec::new();
        while t.len() < count {
            let tri = [0; 3].map(|_| rng.below(vertices as u64) as u32);
            if tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2] {
                t.push(tri);
            }
        }
        let got = intersections(&x, &t).expect("valid");
        let want = brute_force(&x, &t);
        assert!(!want.is_empty(), "the soup should intersect somewhere");
        assert_eq!(got, want, "grid {grid}");
    }
}
