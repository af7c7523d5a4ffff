//! Malformed PLY input: each case must give the exact error variant, and a message that names
//! the file and the element (binary) or line (ASCII). Also: no input makes the reader panic.

mod io_util;

use io_util::{encode_ply_faces, scene_dir, Enc, PlySpec, TempDir};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::error::Error;
use std::path::{Path, PathBuf};
use topoccd::io::{
    read_mesh, read_ply, read_ply_from, read_ply_header, IoError, Location, PlyCounts,
};

const TRIANGLE: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [1.0, 1.0, 0.0],
];

fn faces(list: &[&[i64]]) -> Vec<Vec<i64>> {
    list.iter().map(|f| f.to_vec()).collect()
}

/// Reads `bytes` as a file named `name` in a temp dir; returns the error and the path.
fn read_err(tmp: &TempDir, name: &str, bytes: &[u8]) -> (IoError, PathBuf) {
    let path = tmp.file(name, bytes);
    match read_mesh(&path) {
        Ok(mesh) => panic!("{name} was read as {mesh:?}"),
        Err(e) => (e, path),
    }
}

fn assert_names(e: &IoError, path: &Path, what: &str) {
    let message = e.to_string();
    assert!(
        message.contains(&path.display().to_string()),
        "no file in: {message}"
    );
    assert!(message.contains(what), "no '{what}' in: {message}");
}

fn element(name: &str, index: usize, count: usize, line: Option<usize>) -> Location {
    Location::Element {
        name: name.into(),
        index,
        count,
        line,
    }
}

#[test]
fn wrong_magic_is_not_ply() {
    let tmp = TempDir::new("io-err-magic");
    for (name, bytes) in [
        ("obj.ply", &b"v 0 0 0\nv 1 0 0\n"[..]),
        ("plyx.ply", b"plyx\nformat ascii 1.0\nend_header\n"),
        ("empty.ply", b""),
        ("binary.ply", &[0u8, 159, 146, 150, 1, 2, 3][..]),
    ] {
        let (e, path) = read_err(&tmp, name, bytes);
        assert!(
            matches!(&e, IoError::NotPly { path: p } if *p == path),
            "{name}: {e:?}"
        );
        assert_names(&e, &path, "not a PLY file");
    }
}

#[test]
fn malformed_header_names_the_line() {
    let tmp = TempDir::new("io-err-header");
    let text =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty flaot y\nend_header\n";
    let (e, path) = read_err(&tmp, "header.ply", text.as_bytes());
    assert!(
        matches!(e, IoError::PlyHeader { line: Some(5), .. }),
        "{e:?}"
    );
    assert_names(&e, &path, "at line 5");
    let text = "ply\nformat ascii 1.0\nelement vertex 3\n";
    let (e, path) = read_err(&tmp, "noend.ply", text.as_bytes());
    assert!(matches!(e, IoError::PlyHeader { .. }), "{e:?}");
    assert_names(&e, &path, "end_header");
}

#[test]
fn layouts_that_are_not_triangle_meshes() {
    let tmp = TempDir::new("io-err-layout");
    let head = "ply\nformat ascii 1.0\n";
    for (name, header, what) in [
        ("novertex.ply", "element face 0\nproperty list uchar int vertex_indices\n", "no 'vertex' element"),
        ("intx.ply", "element vertex 1\nproperty int x\nproperty float y\nproperty float z\n", "'x' has type"),
        ("noz.ply", "element vertex 1\nproperty float x\nproperty float y\n", "'z' is missing"),
        (
            "nolist.ply",
            "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int corners\n",
            "no 'vertex_indices' or 'vertex_index'",
        ),
        (
            "floatlist.ply",
            "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar float vertex_indices\n",
            "expected a list of integers",
        ),
    ] {
        let text = format!("{head}{header}end_header\n");
        let (e, path) = read_err(&tmp, name, text.as_bytes());
        assert!(matches!(e, IoError::PlyLayout { .. }), "{name}: {e:?}");
        assert_names(&e, &path, what);
    }
}

#[test]
fn truncated_binary_names_the_element_where_it_ended() {
    let tmp = TempDir::new("io-err-trunc");
    let spec = PlySpec::default(); // little-endian, double, uchar int
    let bytes = encode_ply_faces(&TRIANGLE, &faces(&[&[0, 1, 2], &[1, 3, 2]]), &spec);
    let header = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .expect("header")
        + 11;
    // In the middle of vertex 2, at the end of vertex 3, inside face 1.
    for (cut, location, too_small_for_header) in [
        (header + 2 * 24 + 5, element("vertex", 2, 4, None), true),
        (header + 3 * 24, element("vertex", 3, 4, None), true),
        (header + 4 * 24 + 13 + 3, element("face", 1, 2, None), false),
    ] {
        // From a reader of unknown size, reading stops where the data runs out.
        let e = read_ply_from(&bytes[..cut], Path::new("cut.ply")).expect_err("cut");
        assert!(
            matches!(&e, IoError::Truncated { location: l, .. } if *l == location),
            "{e:?}"
        );
        assert_eq!(e.to_string(), format!("cut.ply: file ended in {location}"));
        // From a file, a size too small for the header's counts is seen before any data.
        let (e, path) = read_err(&tmp, "cut.ply", &bytes[..cut]);
        if too_small_for_header {
            assert!(matches!(&e, IoError::CountsExceedFile { .. }), "{e:?}");
            assert_names(
                &e,
                &path,
                "too few for the 4 vertex elements its header declares",
            );
        } else {
            assert!(
                matches!(&e, IoError::Truncated { location: l, .. } if *l == location),
                "{e:?}"
            );
            assert_names(&e, &path, &format!("file ended in {location}"));
        }
    }
    // Every shorter prefix of a binary file is an error, never a panic.
    for cut in 0..bytes.len() {
        assert!(
            read_ply_from(&bytes[..cut], Path::new("prefix.ply")).is_err(),
            "cut {cut}"
        );
    }
    assert!(read_ply_from(bytes.as_slice(), Path::new("whole.ply")).is_ok());
}

#[test]
fn truncated_real_frame_says_vertex_120_of_9450() {
    let Some(dir) = scene_dir("cloth-funnel") else {
        return;
    };
    let bytes = std::fs::read(dir.join("frames/227.ply")).expect("read frame");
    let header = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .expect("header")
        + 11;
    let tmp = TempDir::new("io-err-trunc-real");
    let cut = &bytes[..header + 120 * 24 + 7];
    let e = read_ply_from(cut, Path::new("227.ply")).expect_err("cut");
    assert!(matches!(e, IoError::Truncated { .. }), "{e:?}");
    assert_eq!(e.to_string(), "227.ply: file ended in vertex 120 of 9450");
    // As a file, its size gives the cut away right after the header.
    let (e, path) = read_err(&tmp, "227.ply", cut);
    assert!(matches!(e, IoError::CountsExceedFile { .. }), "{e:?}");
    assert_names(
        &e,
        &path,
        "too few for the 9450 vertex elements its header declares",
    );
    let (e, path) = read_err(&tmp, "227.ply", &bytes[..bytes.len() - 1]);
    assert_names(&e, &path, "file ended in face 18483 of 18484");
}

#[test]
fn truncated_ascii_names_the_line() {
    let tmp = TempDir::new("io-err-trunc-ascii");
    let spec = PlySpec {
        enc: Enc::Ascii,
        ..PlySpec::default()
    };
    let bytes = encode_ply_faces(&TRIANGLE, &faces(&[&[0, 1, 2], &[1, 3, 2]]), &spec);
    let text = String::from_utf8(bytes).expect("ascii");
    let cut = text.rfind("3 1 3 2").expect("last face");
    let (e, path) = read_err(&tmp, "cut.ply", &text.as_bytes()[..cut]);
    // 10 header lines, 4 vertex lines, face 0 on line 15: face 1 would be on line 16.
    assert!(
        matches!(&e, IoError::Truncated { location, .. } if *location == element("face", 1, 2, Some(16))),
        "{e:?}"
    );
    assert_names(&e, &path, "file ended in face 1 of 2 (line 16)");
}

#[test]
fn face_index_out_of_range_names_the_face() {
    let tmp = TempDir::new("io-err-range");
    for (enc, bad, line) in [
        (Enc::Little, 4, None),
        (Enc::Big, -1, None),
        (Enc::Ascii, 4, Some(17)),
    ] {
        let spec = PlySpec {
            enc,
            ..PlySpec::default()
        };
        let bytes = encode_ply_faces(
            &TRIANGLE,
            &faces(&[&[0, 1, 2], &[1, 3, 2], &[2, bad, 0]]),
            &spec,
        );
        let (e, path) = read_err(&tmp, "range.ply", &bytes);
        let expected = element("face", 2, 3, line);
        assert!(
            matches!(&e, IoError::IndexOutOfRange { location, index, vertices: 4, .. }
                if *location == expected && *index == bad),
            "{enc:?}: {e:?}"
        );
        assert_names(
            &e,
            &path,
            &format!("{expected}: vertex index {bad} is out of range"),
        );
    }
    // Unsigned indices beyond u32 cannot be written, but uint values beyond i32 can.
    let spec = PlySpec {
        index_ty: "uint",
        ..PlySpec::default()
    };
    let bytes = encode_ply_faces(&TRIANGLE, &faces(&[&[0, 1, 3_000_000_000]]), &spec);
    let (e, _) = read_err(&tmp, "huge.ply", &bytes);
    assert!(
        matches!(
            e,
            IoError::IndexOutOfRange {
                index: 3_000_000_000,
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn face_with_two_vertices_names_the_face() {
    let tmp = TempDir::new("io-err-edge");
    for (enc, line) in [(Enc::Little, None), (Enc::Ascii, Some(18))] {
        let spec = PlySpec {
            enc,
            ..PlySpec::default()
        };
        // (Four vertices are a quad, split into triangles: see io_polygons.rs.)
        let edge = faces(&[&[0, 1, 2], &[1, 3, 2], &[0, 1, 3, 2], &[0, 1]]);
        let (e, path) = read_err(&tmp, "edge.ply", &encode_ply_faces(&TRIANGLE, &edge, &spec));
        let expected = element("face", 3, 4, line);
        assert!(
            matches!(&e, IoError::NotTriangle { location, vertices: 2, .. } if *location == expected),
            "{enc:?}: {e:?}"
        );
        assert_names(&e, &path, &format!("{expected} has 2 vertices"));
    }
}

#[test]
fn bad_ascii_number_names_the_line() {
    let tmp = TempDir::new("io-err-ascii-number");
    let spec = PlySpec {
        enc: Enc::Ascii,
        ..PlySpec::default()
    };
    let bytes = encode_ply_faces(&TRIANGLE, &faces(&[&[0, 1, 2]]), &spec);
    let text = String::from_utf8(bytes)
        .expect("ascii")
        .replacen("1.0 1.0 0.0", "1.0 one 0.0", 1);
    let (e, path) = read_err(&tmp, "number.ply", text.as_bytes());
    let expected = element("vertex", 3, 4, Some(14));
    assert!(
        matches!(&e, IoError::PlyElement { location, .. } if *location == expected),
        "{e:?}"
    );
    assert_names(&e, &path, "cannot read vertex 3 of 4 (line 14)");
    assert!(e.to_string().contains("'1.0 one 0.0'"), "{e}");
}

#[test]
fn os_errors_keep_their_source_and_unknown_extensions_are_refused() {
    let tmp = TempDir::new("io-err-os");
    let missing = tmp.path("missing.ply");
    let e = read_ply(&missing).expect_err("missing file");
    match &e {
        IoError::Io { path, source, .. } => {
            assert_eq!(*path, missing);
            assert_eq!(source.kind(), std::io::ErrorKind::NotFound);
        }
        other => panic!("{other:?}"),
    }
    assert!(e.source().is_some());
    assert_names(&e, &missing, "cannot open");

    let off = tmp.file("mesh.off", b"OFF\n0 0 0\n");
    let e = read_mesh(&off).expect_err("off");
    assert!(matches!(e, IoError::UnknownFormat { .. }), "{e:?}");
    assert_names(&e, &off, ".ply, .obj or .stl");
}

#[test]
fn empty_elements_with_huge_counts_do_not_spin() {
    let mut bytes = b"ply\nformat binary_big_endian 1.0\nelement junk 18446744073709551615\n\
        element vertex 1\nproperty float x\nproperty float y\nproperty float z\n\
        element face 0\nproperty list uchar int vertex_indices\nend_header\n"
        .to_vec();
    bytes.extend([1.0f32, 2.0, 3.0].iter().flat_map(|c| c.to_be_bytes()));
    let mesh = read_ply_from(bytes.as_slice(), Path::new("junk.ply")).expect("read");
    assert_eq!(mesh.positions.len(), 1);
    assert_eq!(mesh.positions[0][2], 3.0);
}

#[test]
fn random_corruption_never_panics() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let positions: Vec<[f64; 3]> = (0..20).map(|i| [f64::from(i), 0.5, -1.0]).collect();
    let tris: Vec<Vec<i64>> = (0..30)
        .map(|i| vec![i % 20, (i + 1) % 20, (i + 7) % 20])
        .collect();
    let mut inputs = Vec::new();
    for enc in [Enc::Ascii, Enc::Little, Enc::Big] {
        for extras in [false, true] {
            inputs.push(encode_ply_faces(
                &positions,
                &tris,
                &PlySpec {
                    enc,
                    extras,
                    ..PlySpec::default()
                },
            ));
        }
    }
    let (mut ok, mut err) = (0, 0);
    for original in &inputs {
        for _ in 0..400 {
            let mut bytes = original.clone();
            for _ in 0..rng.random_range(1..4) {
                let at = rng.random_range(0..bytes.len());
                match rng.random_range(0..3) {
                    0 => bytes[at] = rng.random(),
                    1 => bytes.truncate(at),
                    _ => bytes.insert(at, rng.random()),
                }
                if bytes.is_empty() {
                    break;
                }
            }
            match read_ply_from(bytes.as_slice(), Path::new("fuzz.ply")) {
                Ok(mesh) => {
                    ok += 1;
                    let n = mesh.positions.len();
                    assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
                }
                Err(e) => {
                    err += 1;
                    assert!(e.to_string().contains("fuzz.ply"), "{e}");
                }
            }
        }
    }
    eprintln!("corrupted inputs: {ok} read, {err} refused");
    assert!(err > 0 && ok > 0);
}

/// The header of a binary little-endian file of float vertices and uchar/int faces.
fn binary_header(vertices: u64, faces: u64) -> String {
    format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {vertices}\nproperty float x\n\
         property float y\nproperty float z\nelement face {faces}\n\
         property list uchar int vertex_indices\nend_header\n"
    )
}

#[test]
fn absurd_counts_are_refused_right_after_the_header() {
    let tmp = TempDir::new("io-err-absurd");
    let header = binary_header(10_000_000_000, 20_000_000_000);
    let path = tmp.file("absurd.ply", &header);
    let started = std::time::Instant::now();
    for e in [
        read_ply(&path).expect_err("absurd"),
        read_ply_header(&path).expect_err("absurd"),
    ] {
        match &e {
            IoError::CountsExceedFile {
                element,
                count,
                needed,
                size,
                ..
            } => {
                assert_eq!((element.as_str(), *count), ("vertex", 10_000_000_000));
                assert_eq!(*size, header.len() as u64);
                assert_eq!(*needed, header.len() as u64 + 12 * 10_000_000_000);
            }
            other => panic!("{other:?}"),
        }
        assert_names(
            &e,
            &path,
            "absurd.ply: the file has 189 bytes, too few for the 10000000000 vertex elements its \
             header declares (at least 120000000189 bytes with the header and the elements before \
             them): the file is truncated or its header is wrong",
        );
    }
    // Without a size (any reader), the data runs out at once; nothing is allocated up front.
    let e = read_ply_from(header.as_bytes(), Path::new("absurd.ply")).expect_err("absurd");
    assert!(
        matches!(&e, IoError::Truncated { location, .. }
            if *location == element("vertex", 0, 10_000_000_000, None)),
        "{e:?}"
    );
    assert!(started.elapsed() < std::time::Duration::from_secs(5));
}

#[test]
fn declared_counts_are_checked_against_the_file_size() {
    let tmp = TempDir::new("io-err-size");
    let mut vertices = Vec::new();
    for v in TRIANGLE {
        vertices.extend(v.iter().flat_map(|&c| (c as f32).to_le_bytes()));
    }
    let face = [3u8, 0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0];
    // More vertices declared than present: 6 * 12 + 1 bytes cannot fit in 4 * 12 + 13.
    let mut bytes = binary_header(6, 1).into_bytes();
    bytes.extend(&vertices);
    bytes.extend(face);
    let path = tmp.file("vertices.ply", &bytes);
    let e = read_ply(&path).expect_err("too few vertices");
    assert!(
        matches!(&e, IoError::CountsExceedFile { element, count: 6, .. } if element == "vertex"),
        "{e:?}"
    );
    // More faces declared than bytes (an empty index list takes one byte): 14 > 13.
    let mut bytes = binary_header(4, 14).into_bytes();
    bytes.extend(&vertices);
    bytes.extend(face);
    let path = tmp.file("faces.ply", &bytes);
    let e = read_ply(&path).expect_err("too few faces");
    assert!(
        matches!(&e, IoError::CountsExceedFile { element, count: 14, .. } if element == "face"),
        "{e:?}"
    );
    assert_names(
        &e,
        &path,
        "too few for the 14 face elements its header declares",
    );
    // Up to that bound the check passes and reading says where the data ran out.
    let mut bytes = binary_header(4, 2).into_bytes();
    bytes.extend(&vertices);
    bytes.extend(face);
    let path = tmp.file("two.ply", &bytes);
    let e = read_ply(&path).expect_err("one face missing");
    assert!(
        matches!(&e, IoError::Truncated { location, .. } if *location == element("face", 1, 2, None)),
        "{e:?}"
    );
    assert_eq!(
        read_ply_header(&path).expect("the header fits"),
        PlyCounts {
            vertices: 4,
            faces: 2
        }
    );
}

#[test]
fn the_smallest_ascii_file_passes_the_size_check() {
    let tmp = TempDir::new("io-err-ascii-size");
    let head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nelement face 0\nproperty list uchar int vertex_indices\n\
                end_header\n";
    // Single-digit values, single spaces, and no newline at the end: exactly the minimum.
    let text = format!("{head}0 0 0\n1 0 0\n0 1 0");
    let mesh = read_ply(&tmp.file("min.ply", &text)).expect("minimal file");
    assert_eq!(mesh.positions.len(), 3);
    // One vertex more than the text can hold.
    let text = text.replace("element vertex 3", "element vertex 4");
    let e = read_ply(&tmp.file("more.ply", &text)).expect_err("4 vertices");
    assert!(
        matches!(&e, IoError::CountsExceedFile { element, count: 4, needed, size, .. }
            if element == "vertex" && *needed == *size + 6),
        "{e:?}"
    );
}

#[test]
fn empty_and_single_triangle_files_are_meshes() {
    let tmp = TempDir::new("io-err-empty");
    let empty = tmp.file(
        "empty.ply",
        "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
         property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
    );
    assert_eq!(
        read_ply(&empty).expect("empty"),
        topoccd::io::Mesh::default()
    );
    let empty_obj = tmp.file("empty.obj", "# no data\n\n");
    assert_eq!(
        read_mesh(&empty_obj).expect("empty"),
        topoccd::io::Mesh::default()
    );
    let one = tmp.file(
        "one.ply",
        encode_ply_faces(&TRIANGLE[..3], &faces(&[&[0, 1, 2]]), &PlySpec::default()),
    );
    let mesh = read_ply(&one).expect("one triangle");
    assert_eq!((mesh.positions.len(), mesh.triangles.len()), (3, 1));
}
