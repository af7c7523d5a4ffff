//! Issue 12: STL files (ASCII and binary), written here by hand, read through `read_mesh`
//! with their corners welded into shared vertices; errors name the file and the triangle.

mod io_util;

use io_util::TempDir;
use std::path::Path;
use topoccd::io::{read_mesh, read_stl_from, FaceOrigin, IoError, MeshFormat, MeshNote};

/// The 12 triangles of the unit cube, as corner coordinates (a triangle soup).
fn cube_soup() -> Vec<[[f32; 3]; 3]> {
    let c = |i: u32| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32];
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    quads
        .iter()
        .flat_map(|q| [[c(q[0]), c(q[1]), c(q[2])], [c(q[0]), c(q[2]), c(q[3])]])
        .collect()
}

fn binary_stl(header: &[u8], soup: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut bytes = vec![0u8; 80];
    bytes[..header.len()].copy_from_slice(header);
    bytes.extend((soup.len() as u32).to_le_bytes());
    for t in soup {
        bytes.extend([0.0f32; 3].iter().flat_map(|v| v.to_le_bytes())); // normal
        for corner in t {
            bytes.extend(corner.iter().flat_map(|v| v.to_le_bytes()));
        }
        bytes.extend([0u8, 0]); // attribute
    }
    bytes
}

fn ascii_stl(soup: &[[[f32; 3]; 3]]) -> String {
    let mut text = String::from("solid cube exported by hand\n");
    for t in soup {
        text.push_str("  facet normal 0 0 0\n    outer loop\n");
        for c in t {
            text.push_str(&format!("      vertex {:e} {:e} {:e}\n", c[0], c[1], c[2]));
        }
        text.push_str("    endloop\n  endfacet\n");
    }
    text.push_str("endsolid cube\n");
    text
}

#[test]
fn binary_and_ascii_stl_read_as_the_same_welded_cube() {
    // Issue 12: "No STL".
    let tmp = TempDir::new("io-stl-cube");
    let soup = cube_soup();
    let binary = tmp.file("cube.stl", binary_stl(b"binary cube", &soup));
    let ascii = tmp.file("cube_ascii.STL", ascii_stl(&soup));
    // A binary file whose header starts with "solid", as several exporters write.
    let tricky = tmp.file("solid.stl", binary_stl(b"solid but binary", &soup));
    assert_eq!(
        MeshFormat::of_path(&binary).expect("format"),
        MeshFormat::Stl
    );
    let meshes: Vec<_> = [&binary, &ascii, &tricky]
        .iter()
        .map(|p| read_mesh(p).unwrap_or_else(|e| panic!("{e}")))
        .collect();
    for mesh in &meshes {
        assert_eq!(mesh, &meshes[0]);
    }
    let mesh = &meshes[0];
    // 36 corners welded into the cube's 8 vertices, in order of first appearance.
    assert_eq!(mesh.positions.len(), 8);
    assert_eq!(mesh.triangles.len(), 12);
    assert_eq!(
        &mesh.positions[..3],
        &[[0.0; 3], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]]
    );
    assert_eq!(mesh.triangles[0], [0, 1, 2]);
    assert_eq!(mesh.face_origin, None);
    assert_eq!(
        mesh.notes,
        vec![MeshNote::Welded {
            corners: 36,
            vertices: 8,
            dropped: 0
        }]
    );
    // Welded: every edge of the closed cube is shared by two triangles.
    let mut edges: Vec<[u32; 2]> = mesh
        .triangles
        .iter()
        .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable();
    assert!(edges.chunks(2).all(|w| w[0] == w[1]));
}

#[test]
fn welding_is_exact_and_drops_collapsed_facets() {
    let mut soup = cube_soup();
    // A corner one f32 step away from (1, 1, 0) stays a vertex of its own; -0.0 welds with 0.
    soup.push([
        [0.0, 0.0, 3.0],
        [1.0, 1.0 + f32::EPSILON, 0.0],
        [-0.0, 0.0, 0.0],
    ]);
    // A facet with two identical corners is dropped, and the face map keeps the facet numbers.
    soup.push([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
    soup.push([[0.0, 0.0, 3.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]]);
    let mesh = read_stl_from(binary_stl(b"", &soup).as_slice(), Path::new("w.stl")).expect("w");
    assert_eq!(mesh.positions.len(), 10);
    assert_eq!(mesh.triangles.len(), 14);
    assert_eq!(mesh.triangles[12], [8, 9, 0]);
    assert_eq!(mesh.origin(13), FaceOrigin { face: 14, sub: 0 });
    assert_eq!(
        mesh.notes,
        vec![MeshNote::Welded {
            corners: 45,
            vertices: 10,
            dropped: 1
        }]
    );
}

#[test]
fn stl_errors_name_the_file_and_the_triangle() {
    let tmp = TempDir::new("io-stl-errors");
    let soup = cube_soup();
    // Binary, cut inside triangle 7.
    let bytes = binary_stl(b"", &soup);
    let cut = tmp.file("cut.stl", &bytes[..84 + 50 * 7 + 20]);
    let e = read_mesh(&cut).expect_err("truncated");
    assert!(
        matches!(
            e,
            IoError::Stl {
                triangle: 7,
                line: None,
                ..
            }
        ),
        "{e:?}"
    );
    let message = e.to_string();
    assert!(
        message.starts_with(&format!("{}: triangle 7", cut.display())),
        "{message}"
    );
    assert!(message.contains("declares 12 triangles"), "{message}");
    // Binary with bytes after the declared triangles.
    let mut long = bytes.clone();
    long.extend([0u8; 7]);
    let e = read_mesh(&tmp.file("long.stl", &long)).expect_err("trailing bytes");
    assert!(
        e.to_string().contains("7 bytes follow the 12 triangles"),
        "{e}"
    );
    // ASCII with a bad number in facet 2: facet k starts on line 2 + 7k, its third vertex is
    // on line 6 + 7k.
    let text = ascii_stl(&soup);
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    lines[5 + 7 * 2] = "      vertex 1 x 0".into();
    let bad = tmp.file("bad.stl", lines.join("\n"));
    let e = read_mesh(&bad).expect_err("bad number");
    assert!(
        matches!(
            e,
            IoError::Stl {
                triangle: 2,
                line: Some(20),
                ..
            }
        ),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        format!("{}: triangle 2 at line 20: bad number 'x'", bad.display())
    );
    // ASCII without its end.
    let open = tmp.file("open.stl", text.replace("endsolid cube\n", ""));
    let e = read_mesh(&open).expect_err("no endsolid");
    assert!(e.to_string().contains("triangle 12"), "{e}");
    assert!(e.to_string().contains("without 'endsolid'"), "{e}");
    // Too short to be anything.
    let e = read_mesh(&tmp.file("tiny.stl", b"abc")).expect_err("tiny");
    assert!(
        e.to_string().contains("too few for a binary STL header"),
        "{e}"
    );
}
