//! Many small closed meshes moving into each other.

use std::collections::HashMap;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::assemble;
use glam::DVec3;
use topoccd::Step;

/// A unit icosphere: the icosahedron with each triangle split in four once (42 vertices, 80
/// triangles), the new vertices pushed onto the sphere.
fn icosphere() -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut verts: Vec<DVec3> = [
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ]
    .iter()
    .map(|&p| DVec3::from_array(p).normalize())
    .collect();
    let faces: [[u32; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
    let mut midpoint = |a: u32, b: u32, verts: &mut Vec<DVec3>| {
        *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
            verts.push((verts[a as usize] + verts[b as usize]).normalize());
            (verts.len() - 1) as u32
        })
    };
    let mut tris = Vec::with_capacity(80);
    for [a, b, c] in faces {
        let ab = midpoint(a, b, &mut verts);
        let bc = midpoint(b, c, &mut verts);
        let ca = midpoint(c, a, &mut verts);
        tris.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
    }
    (verts, tris)
}

/// A cube of half-width 0.8 (inside the unit sphere), 8 vertices, 12 triangles.
fn cube() -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let verts = (0..8)
        .map(|i| {
            let s = |bit: u32| if i & bit != 0 { 0.8 } else { -0.8 };
            DVec3::new(s(1), s(2), s(4))
        })
        .collect();
    let tris = vec![
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ];
    (verts, tris)
}

/// `count` small closed meshes (`count >= 2`; icospheres of 80 triangles and cubes of 12,
/// alternately) of radius 0.3 to 0.4, on a jittered cubic lattice of spacing 1. During the step
/// each moves by 0.3 to 0.8 in a random direction and turns by up to 30° about a random axis,
/// so neighbours (0.2 to 0.4 apart at t=0) run into each other.
///
/// ```
/// let step = topoccd_scenes::small_objects(8, 1);
/// assert_eq!(step.triangles().len(), 4 * 80 + 4 * 12);
/// ```
pub fn small_objects(count: usize, seed: u64) -> Step<'static> {
    let count = count.max(2);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let side = (count as f64).cbrt().ceil() as usize;
    let shapes = [icosphere(), cube()];
    let (mut x0, mut x1, mut tris) = (Vec::new(), Vec::new(), Vec::new());
    let unit = super::random_unit;
    for k in 0..count {
        let (verts, faces) = &shapes[k % 2];
        let cell = DVec3::new(
            (k % side) as f64,
            ((k / side) % side) as f64,
            (k / (side * side)) as f64,
        );
        let c0 = cell + 0.05 * unit(&mut rng);
        let c1 = c0 + rng.random_range(0.3..0.8) * unit(&mut rng);
        let radius = rng.random_range(0.3..0.4);
        let turn =
            glam::DQuat::from_axis_angle(unit(&mut rng), rng.random_range(0.0..30f64.to_radians()));
        let offset = x0.len() as u32;
        for &p in verts {
            x0.push(c0 + radius * p);
            x1.push(c1 + radius * (turn * p));
        }
        tris.extend(faces.iter().map(|t| t.map(|i| i + offset)));
    }
    assemble(x0, x1, tris)
}
