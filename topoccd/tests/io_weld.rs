//! Issue 12: coincident duplicate vertices (the poles of a UV sphere: 16 vertices at each
//! pole) are found, and welded with a map from old to new vertex ids.

mod io_util;

use io_util::TempDir;
use topoccd::io::{
    apply_weld, coincident_vertices, read_mesh, weld, write_mesh, FaceOrigin, Mesh, MeshNote,
};

const SEGMENTS: u32 = 16;
const RINGS: u32 = 8;

/// A UV sphere as naive exporters write it: rows of `SEGMENTS` vertices from pole to pole,
/// the pole rows included (16 coincident vertices at each pole). `pole_quads`: the pole rows
/// are joined by whole quads (one of their two triangles has two pole corners, so it is
/// degenerate once welded) instead of by one triangle per segment.
fn uv_sphere(pole_quads: bool) -> Mesh {
    let id = |ring: u32, seg: u32| ring * SEGMENTS + seg % SEGMENTS;
    let mut positions = Vec::new();
    for ring in 0..=RINGS {
        let theta = std::f64::consts::PI * f64::from(ring) / f64::from(RINGS);
        for seg in 0..SEGMENTS {
            let phi = std::f64::consts::TAU * f64::from(seg) / f64::from(SEGMENTS);
            // Exact poles: sin(0) and sin(pi) rounded to 0 so that the pole rows coincide.
            let s = if ring == 0 || ring == RINGS {
                0.0
            } else {
                theta.sin()
            };
            positions.push([s * phi.cos(), s * phi.sin(), theta.cos()]);
        }
    }
    let mut triangles = Vec::new();
    for ring in 0..RINGS {
        for seg in 0..SEGMENTS {
            let (a, b) = (id(ring, seg), id(ring, seg + 1));
            let (c, d) = (id(ring + 1, seg), id(ring + 1, seg + 1));
            if ring != 0 || pole_quads {
                triangles.push([a, c, b]);
            }
            if ring != RINGS - 1 || pole_quads {
                triangles.push([b, c, d]);
            }
        }
    }
    Mesh::new(positions, triangles)
}

#[test]
fn uv_sphere_poles_are_found() {
    // Issue 12: "poles of a UV sphere: 16 coincident pole vertices ... with no warning".
    let sphere = uv_sphere(false);
    let groups = coincident_vertices(&sphere.positions, &sphere.triangles);
    let north: Vec<u32> = (0..SEGMENTS).collect();
    let south: Vec<u32> = (RINGS * SEGMENTS..(RINGS + 1) * SEGMENTS).collect();
    assert_eq!(groups, vec![north, south]);
    // Deterministic: the same answer whatever the order of the triangles.
    let mut shuffled = sphere.triangles.clone();
    shuffled.reverse();
    assert_eq!(coincident_vertices(&sphere.positions, &shuffled), groups);
}

#[test]
fn uv_sphere_poles_are_welded_with_a_map() {
    let sphere = uv_sphere(false);
    let (welded, map) = weld(&sphere);
    assert_eq!(map.len(), sphere.positions.len());
    assert_eq!(welded.positions.len(), sphere.positions.len() - 30);
    assert_eq!(welded.triangles.len(), sphere.triangles.len());
    // The north pole is vertex 0; the first ring follows; the south pole is the last vertex.
    assert!(map[..SEGMENTS as usize].iter().all(|&n| n == 0));
    assert_eq!(map[SEGMENTS as usize], 1);
    let south = welded.positions.len() as u32 - 1;
    assert!(map[(RINGS * SEGMENTS) as usize..]
        .iter()
        .all(|&n| n == south));
    // Positions and triangles follow the map, and nothing coincides any more.
    for (old, &new) in map.iter().enumerate() {
        assert_eq!(welded.positions[new as usize], sphere.positions[old]);
    }
    for (t, tri) in sphere.triangles.iter().enumerate() {
        assert_eq!(welded.triangles[t], tri.map(|v| map[v as usize]));
    }
    assert!(coincident_vertices(&welded.positions, &welded.triangles).is_empty());
    // Closed: every edge shared by two triangles, which was not so before welding.
    let closed = |m: &Mesh| {
        let mut edges: Vec<[u32; 2]> = m
            .triangles
            .iter()
            .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
            .map(|[a, b]| [a.min(b), a.max(b)])
            .collect();
        edges.sort_unstable();
        edges.len().is_multiple_of(2) && edges.chunks(2).all(|w| w[0] == w[1])
    };
    assert!(closed(&welded) && !closed(&sphere));
    assert_eq!(
        welded.notes,
        vec![MeshNote::Merged {
            removed: 30,
            dropped: vec![]
        }]
    );
    assert_eq!(welded.face_origin, None);
    // The other frame of a step is welded with the same map.
    let moved: Vec<[f64; 3]> = sphere
        .positions
        .iter()
        .map(|p| [p[0] + 0.5, p[1], p[2]])
        .collect();
    let x1 = apply_weld(&moved, &map);
    assert_eq!(x1.len(), welded.positions.len());
    assert_eq!(x1[0], [0.5, 0.0, 1.0]);
}

#[test]
fn welding_drops_collapsed_triangles_and_maps_the_rest_to_their_faces() {
    let sphere = uv_sphere(true);
    let (welded, _) = weld(&sphere);
    // One triangle per segment at each pole has two pole corners.
    let dropped: Vec<u32> = match &welded.notes[..] {
        [MeshNote::Merged {
            removed: 30,
            dropped,
        }] => dropped.clone(),
        other => panic!("{other:?}"),
    };
    assert_eq!(dropped.len(), 2 * SEGMENTS as usize);
    assert_eq!(
        welded.triangles.len(),
        sphere.triangles.len() - dropped.len()
    );
    for &t in &dropped {
        let [a, b, c] = sphere.triangles[t as usize];
        let pole = |v: u32| !(SEGMENTS..RINGS * SEGMENTS).contains(&v);
        assert!([a, b, c].iter().filter(|&&v| pole(v)).count() == 2);
    }
    // Every kept triangle names its face of the original mesh.
    let origin = welded.face_origin.as_ref().expect("map");
    let kept: Vec<u32> = (0..sphere.triangles.len() as u32)
        .filter(|t| !dropped.contains(t))
        .collect();
    assert_eq!(
        origin,
        &kept
            .iter()
            .map(|&face| FaceOrigin { face, sub: 0 })
            .collect::<Vec<_>>()
    );
    assert!(welded.notes[0]
        .to_string()
        .contains("32 triangle(s) became degenerate"));
}

#[test]
fn a_sphere_read_from_a_file_has_its_poles_found() {
    let tmp = TempDir::new("io-weld-file");
    let path = tmp.path("uv_sphere.obj");
    write_mesh(&path, &uv_sphere(false)).expect("write");
    let mesh = read_mesh(&path).expect("read");
    let groups = coincident_vertices(&mesh.positions, &mesh.triangles);
    assert_eq!(
        groups.iter().map(Vec::len).collect::<Vec<_>>(),
        vec![16, 16]
    );
}
