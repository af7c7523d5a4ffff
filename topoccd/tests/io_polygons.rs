//! Issue 12, files from real tools: quads and n-gons (OBJ and PLY) are split into triangles
//! with a map back to the file's faces; OBJ `l` and `p` lines are skipped and counted; PLY
//! triangle strips are decoded; a PLY with vertices but no faces is refused loudly.

mod io_util;

use io_util::{encode_ply_faces, Enc, PlySpec, TempDir};
use std::path::Path;
use topoccd::io::{
    read_mesh, read_obj_from, read_ply_from, triangulate_polygon, FaceOrigin, IoError, Mesh,
    MeshNote, PolygonSplit,
};

/// Twice the area vector of a triangle.
fn area2(p: &[[f64; 3]], t: [u32; 3]) -> [f64; 3] {
    let [a, b, c] = t.map(|i| p[i as usize]);
    let (u, v) = (
        [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
        [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
    );
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

/// The polygon is covered exactly: the triangles' areas (all with the polygon's +z winding)
/// add up to the polygon's area.
fn assert_covers_planar(p: &[[f64; 3]], tris: &[[u32; 3]], area: f64) {
    let mut sum = 0.0;
    for &t in tris {
        let z = area2(p, t)[2];
        assert!(z > 0.0, "triangle {t:?} is flipped or flat");
        sum += z / 2.0;
    }
    assert!((sum - area).abs() < 1e-12, "area {sum}, expected {area}");
}

/// A Blender-style export: a cube of six quads, with a texture coordinate and normal on each
/// corner, an object line, smoothing off.
const CUBE_OBJ: &str = "\
# Blender 4.1
o Cube
v 1 1 -1
v 1 -1 -1
v 1 1 1
v 1 -1 1
v -1 1 -1
v -1 -1 -1
v -1 1 1
v -1 -1 1
vn 0 1 0
vt 0.625 0.5
s 0
f 1/1/1 5/1/1 7/1/1 3/1/1
f 4/1/1 3/1/1 7/1/1 8/1/1
f 8/1/1 7/1/1 5/1/1 6/1/1
f 6/1/1 2/1/1 4/1/1 8/1/1
f 2/1/1 1/1/1 3/1/1 4/1/1
f 6/1/1 5/1/1 1/1/1 2/1/1
";

#[test]
fn obj_quads_are_split_and_mapped_to_their_faces() {
    // Issue 12: "face 0 of 12 (line 27) has 4 vertices, but only triangles are supported".
    let mesh = read_obj_from(CUBE_OBJ.as_bytes(), Path::new("cube.obj")).expect("quads");
    assert_eq!(mesh.positions.len(), 8);
    assert_eq!(mesh.triangles.len(), 12);
    let origin = mesh.face_origin.as_ref().expect("a face map");
    for (t, o) in origin.iter().enumerate() {
        assert_eq!(
            *o,
            FaceOrigin {
                face: (t / 2) as u32,
                sub: (t % 2) as u32
            }
        );
    }
    // A fan from each quad's first corner, with the quad's winding.
    assert_eq!(&mesh.triangles[..2], &[[0, 4, 6], [0, 6, 2]]);
    assert_eq!(
        mesh.notes,
        vec![MeshNote::Triangulated {
            polygons: 6,
            non_convex: 0,
            irregular: 0,
            first_irregular: None,
            triangles: 12
        }]
    );
    assert!(mesh.notes[0].to_string().contains("6 polygon(s)"));
    // The cube is closed: every edge is shared by exactly two triangles.
    let mut edges: Vec<[u32; 2]> = mesh
        .triangles
        .iter()
        .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable();
    assert!(edges.chunks(2).all(|w| w[0] == w[1]) && edges.len() == 36);
}

#[test]
fn non_convex_polygons_are_ear_clipped_inside_the_polygon() {
    // An L-shape (area 3) and a U-shape (area 7), in the z=0 plane, counter-clockwise.
    let text = "\
v 0 0 0
v 2 0 0
v 2 1 0
v 1 1 0
v 1 2 0
v 0 2 0
f 1 2 3 4 5 6
v 10 0 0
v 13 0 0
v 13 3 0
v 12 3 0
v 12 1 0
v 11 1 0
v 11 3 0
v 10 3 0
f 7 8 9 10 11 12 13 14
";
    let mesh = read_obj_from(text.as_bytes(), Path::new("shapes.obj")).expect("n-gons");
    let split_of = |face| -> Vec<[u32; 3]> {
        (0..mesh.triangles.len())
            .filter(|&t| mesh.origin(t).face == face)
            .map(|t| mesh.triangles[t])
            .collect()
    };
    let (l, u) = (split_of(0), split_of(1));
    assert_eq!((l.len(), u.len()), (4, 6));
    assert_covers_planar(&mesh.positions, &l, 3.0);
    assert_covers_planar(&mesh.positions, &u, 7.0);
    assert!(matches!(
        mesh.notes[0],
        MeshNote::Triangulated {
            polygons: 2,
            non_convex: 2,
            irregular: 0,
            triangles: 10,
            ..
        }
    ));
    // The same polygon tilted out of the z=0 plane (a rotation about x) splits the same way.
    let tilt: Vec<[f64; 3]> = mesh.positions[..6]
        .iter()
        .map(|&[x, y, z]| [x, 0.6 * y - 0.8 * z, 0.8 * y + 0.6 * z])
        .collect();
    let mut out = Vec::new();
    assert_eq!(
        triangulate_polygon(&tilt, &[0, 1, 2, 3, 4, 5], &mut out),
        PolygonSplit::EarClipped
    );
    assert_eq!(out, l);
}

#[test]
fn self_intersecting_polygons_are_split_and_reported() {
    // A bow tie: no plane area to speak of, reported as irregular, still n - 2 triangles.
    let text = "v 0 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 4\nf 1 3 2\n";
    let mesh = read_obj_from(text.as_bytes(), Path::new("bowtie.obj")).expect("bow tie");
    assert_eq!(mesh.triangles.len(), 3);
    assert_eq!(mesh.origin(2), FaceOrigin { face: 1, sub: 0 });
    let note = &mesh.notes[0];
    assert!(
        matches!(
            note,
            MeshNote::Triangulated {
                irregular: 1,
                first_irregular: Some(0),
                ..
            }
        ),
        "{note:?}"
    );
    assert!(note.to_string().contains("the first is face 0"), "{note}");
}

#[test]
fn obj_line_and_point_statements_are_read_or_skipped_and_counted() {
    // Issue 12: "OBJ `l` and `p` lines are hard errors". Issue 42: `l` lines are free edges.
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3 1\np 1\nf 1 2 3\np 2 3\nl 3 1\n";
    let mesh = read_obj_from(text.as_bytes(), Path::new("lines.obj")).expect("l and p");
    assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    assert_eq!(mesh.edges, vec![[0, 1], [1, 2], [2, 0], [2, 0]]);
    assert_eq!(mesh.face_origin, None);
    assert_eq!(
        mesh.notes,
        vec![MeshNote::Skipped {
            keyword: "p".into(),
            count: 2,
            first_line: 6
        },]
    );
    assert_eq!(
        mesh.notes[0].to_string(),
        "2 'p' statement(s) skipped (they carry no triangles; the first is on line 6)"
    );
}

#[test]
fn ply_polygons_are_split_in_every_encoding() {
    let tmp = TempDir::new("io-poly-ply");
    let positions = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [2.0, 0.5, 0.0],
    ];
    let faces = vec![vec![0, 1, 2], vec![0, 1, 4, 2, 3], vec![1, 4, 2]];
    for enc in [Enc::Ascii, Enc::Little, Enc::Big] {
        let spec = PlySpec {
            enc,
            ..PlySpec::default()
        };
        let path = tmp.file("poly.ply", encode_ply_faces(&positions, &faces, &spec));
        let mesh = read_mesh(&path).unwrap_or_else(|e| panic!("{enc:?}: {e}"));
        assert_eq!(
            mesh.triangles,
            vec![[0, 1, 2], [0, 1, 4], [0, 4, 2], [0, 2, 3], [1, 4, 2]],
            "{enc:?}"
        );
        let faces: Vec<(u32, u32)> = (0..5)
            .map(|t| (mesh.origin(t).face, mesh.origin(t).sub))
            .collect();
        assert_eq!(faces, vec![(0, 0), (1, 0), (1, 1), (1, 2), (2, 0)]);
    }
}

/// A PLY file with a `tristrips` element and no `face` element, as some scanners and older
/// tools write.
fn strips_ply(with_face: bool) -> String {
    let mut text = String::from(
        "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n\
         property float z\n",
    );
    if with_face {
        text.push_str("element face 1\nproperty list uchar int vertex_indices\n");
    }
    text.push_str("element tristrips 1\nproperty list int int vertex_indices\nend_header\n");
    text.push_str("0 0 0\n0 1 0\n1 0 0\n1 1 0\n2 0 0\n2 1 0\n");
    if with_face {
        text.push_str("3 0 2 1\n");
    }
    // One strip of four triangles, a restart, then a strip with a stitching repeat.
    text.push_str("11 0 1 2 3 4 5 -1 3 5 5 4\n");
    text
}

#[test]
fn ply_triangle_strips_are_decoded() {
    // Issue 12: "A PLY with `tristrips` and no `face` element silently reads 0 triangles".
    let mesh =
        read_ply_from(strips_ply(false).as_bytes(), Path::new("strips.ply")).expect("strips");
    // 0 1 2 3 4 5: (0,1,2) (2,1,3) (2,3,4) (4,3,5), every other one reversed to keep the
    // winding; after the restart, 3 5 5 4 gives two degenerate stitches.
    assert_eq!(
        mesh.triangles,
        vec![[0, 1, 2], [2, 1, 3], [2, 3, 4], [4, 3, 5]]
    );
    assert_eq!(
        mesh.notes,
        vec![MeshNote::Strips {
            records: 1,
            triangles: 4,
            degenerate: 2
        }]
    );
    assert!(mesh.face_origin.is_some());
    assert_eq!(mesh.origin(3), FaceOrigin { face: 0, sub: 3 });
    // With a face element too, faces come first and strips continue the face numbering.
    let mesh = read_ply_from(strips_ply(true).as_bytes(), Path::new("both.ply")).expect("both");
    assert_eq!(mesh.triangles.len(), 5);
    assert_eq!(mesh.triangles[..2], [[0, 2, 1], [0, 1, 2]]);
    assert_eq!(mesh.origin(1), FaceOrigin { face: 1, sub: 0 });
    // Strips keep one winding: each decoded triangle has the same normal direction.
    let p = &mesh.positions;
    let zs: Vec<f64> = mesh.triangles.iter().map(|&t| area2(p, t)[2]).collect();
    assert!(zs[1..].iter().all(|&z| z < 0.0), "{zs:?}");
}

#[test]
fn a_ply_with_vertices_but_no_faces_is_refused_loudly() {
    let tmp = TempDir::new("io-poly-none");
    let text = strips_ply(false).replace("element tristrips 1", "element strips 1");
    let path = tmp.file("cloud.ply", &text);
    let err = read_mesh(&path).expect_err("no faces");
    assert!(
        matches!(err, IoError::NoFaces { vertices: 6, .. }),
        "{err:?}"
    );
    let message = err.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    assert!(
        message.contains("no 'face' or 'tristrips' element (its elements: vertex, strips)"),
        "{message}"
    );
}

#[test]
fn a_plain_triangle_mesh_has_no_face_map_and_no_notes() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let mesh = read_obj_from(text.as_bytes(), Path::new("tri.obj")).expect("tri");
    assert_eq!(
        mesh,
        Mesh::new(
            vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2]]
        )
    );
}
