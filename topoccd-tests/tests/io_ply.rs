//! PLY reading and writing: the real frames of the shared scenes (both byte orders and
//! coordinate types), every other encoding and index type, and bit-exact round trips.

#[path = "../../topoccd/tests/io_util/mod.rs"]
mod io_util;

use io_util::{
    encode_ply, encode_ply_faces, ply_header, same_bits, scene_dir, Enc, PlySpec, TempDir,
};
use std::path::Path;
use std::time::Instant;
use topoccd::io::{
    read_mesh, read_ply, read_ply_from, scene_frames, write_mesh, write_ply, IoError, Mesh,
};

/// (scene, vertices, triangles, format line, coordinate type) as in the data README and files.
const SCENES: [(&str, usize, usize, &str, &str); 2] = [
    (
        "cloth-funnel",
        9_450,
        18_484,
        "binary_little_endian",
        "double",
    ),
    ("cloth-ball", 46_598, 92_230, "binary_big_endian", "float"),
];

#[test]
fn real_frames_have_the_documented_counts_and_encodings() {
    for (scene, vertices, triangles, format, coord) in SCENES {
        let Some(dir) = scene_dir(scene) else { return };
        let frames = scene_frames(&dir).expect("frames");
        let mut faces = Vec::new();
        for path in [&frames.t0, &frames.t1] {
            // Document which reader path each file exercises.
            let header = ply_header(path);
            assert!(header.contains(&format!("format {format} 1.0")), "{header}");
            assert!(header.contains(&format!("property {coord} x")), "{header}");
            assert!(
                header.contains("property list uchar int vertex_indices"),
                "{header}"
            );

            let mesh = read_ply(path).expect("read frame");
            assert_eq!(mesh.positions.len(), vertices, "{}", path.display());
            assert_eq!(mesh.triangles.len(), triangles, "{}", path.display());
            assert!(mesh
                .triangles
                .iter()
                .flatten()
                .all(|&i| (i as usize) < vertices));
            assert!(mesh.positions.iter().flatten().all(|c| c.is_finite()));
            // The mesh is not degenerate: positions spread out, every vertex used.
            let mut used = vec![false; vertices];
            mesh.triangles
                .iter()
                .flatten()
                .for_each(|&i| used[i as usize] = true);
            assert!(
                used.iter().all(|&u| u),
                "unused vertex in {}",
                path.display()
            );
            faces.push(mesh.triangles);
        }
        assert_eq!(
            faces[0], faces[1],
            "{scene}: the two frames have the same faces"
        );
    }
}

#[test]
fn reading_the_largest_frame_is_fast() {
    let Some(dir) = scene_dir("cloth-ball") else {
        return;
    };
    let frames = scene_frames(&dir).expect("frames");
    let _warm = read_ply(&frames.t0).expect("read");
    let start = Instant::now();
    let mesh = read_ply(&frames.t1).expect("read");
    let elapsed = start.elapsed();
    eprintln!(
        "read {} ({} faces) in {elapsed:?}",
        frames.t1.display(),
        mesh.triangles.len()
    );
    // The target is well under 100 ms in release; the bound leaves room for a busy machine
    // and debug builds.
    assert!(elapsed.as_secs_f64() < 2.0, "reading took {elapsed:?}");
}

#[test]
fn every_encoding_and_type_of_the_real_funnel_reads_the_same() {
    let Some(dir) = scene_dir("cloth-funnel") else {
        return;
    };
    let frames = scene_frames(&dir).expect("frames");
    let original = read_ply(&frames.t0).expect("read");
    let tmp = TempDir::new("io-ply-enc");
    let specs = [
        PlySpec {
            enc: Enc::Big,
            ..PlySpec::default()
        },
        PlySpec {
            enc: Enc::Ascii,
            ..PlySpec::default()
        },
        PlySpec {
            enc: Enc::Little,
            double: false,
            ..PlySpec::default()
        },
        PlySpec {
            enc: Enc::Ascii,
            double: false,
            count_ty: "int",
            index_ty: "uint",
            ..PlySpec::default()
        },
        PlySpec {
            enc: Enc::Big,
            index_ty: "uint",
            count_ty: "ushort",
            list_name: "vertex_index",
            extras: true,
            ..PlySpec::default()
        },
        PlySpec {
            enc: Enc::Little,
            index_ty: "ushort",
            count_ty: "char",
            extras: true,
            ..PlySpec::default()
        },
        PlySpec {
            enc: Enc::Ascii,
            index_ty: "int",
            count_ty: "uint",
            extras: true,
            ..PlySpec::default()
        },
    ];
    for (k, spec) in specs.iter().enumerate() {
        let path = tmp.file(&format!("funnel{k}.PLY"), encode_ply(&original, spec));
        let mesh = read_mesh(&path).unwrap_or_else(|e| panic!("{spec:?}: {e}"));
        let expected = if spec.double {
            original.clone()
        } else {
            Mesh {
                positions: original
                    .positions
                    .iter()
                    .map(|p| p.map(|c| f64::from(c as f32)))
                    .collect(),
                triangles: original.triangles.clone(),
                ..Mesh::default()
            }
        };
        assert!(same_bits(&mesh, &expected), "{spec:?}");
    }
}

#[test]
fn small_indices_and_extras_in_every_encoding() {
    let positions = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.1, 0.2, 0.3],
    ];
    let faces = vec![vec![0, 1, 2], vec![3, 2, 1]];
    let tmp = TempDir::new("io-ply-small");
    for enc in [Enc::Ascii, Enc::Little, Enc::Big] {
        for index_ty in ["char", "uchar", "short", "ushort", "int", "uint"] {
            for double in [false, true] {
                let spec = PlySpec {
                    enc,
                    double,
                    index_ty,
                    count_ty: "uchar",
                    extras: true,
                    ..PlySpec::default()
                };
                let path = tmp.file("small.ply", encode_ply_faces(&positions, &faces, &spec));
                let mesh = read_ply(&path).unwrap_or_else(|e| panic!("{spec:?}: {e}"));
                assert_eq!(mesh.triangles, vec![[0, 1, 2], [3, 2, 1]], "{spec:?}");
                let expected = if double { 0.3 } else { f64::from(0.3f32) };
                assert_eq!(mesh.positions[3][2], expected, "{spec:?}");
            }
        }
    }
}

#[test]
fn a_file_without_a_face_element_is_refused_unless_empty() {
    // Issue 12: a point cloud silently read as a mesh with 0 triangles (and no contact).
    let text = "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\nproperty double z\nend_header\n1 2 3\n4 5 6\n";
    let err = read_ply_from(text.as_bytes(), Path::new("points.ply")).expect_err("no faces");
    assert!(
        matches!(&err, IoError::NoFaces { vertices: 2, .. }),
        "{err:?}"
    );
    let message = err.to_string();
    assert!(
        message.starts_with("points.ply: 2 vertices but no triangles"),
        "{message}"
    );
    assert!(
        message.contains("no 'face' or 'tristrips' element"),
        "{message}"
    );
    // An explicit empty face element is a point set; no vertices at all is an empty mesh.
    let declared = text.replace(
        "end_header",
        "element face 0\nproperty list uchar int vertex_indices\nend_header",
    );
    let mesh = read_ply_from(declared.as_bytes(), Path::new("points.ply")).expect("read");
    assert_eq!(mesh.positions, vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
    assert!(mesh.triangles.is_empty());
    let empty = "ply\nformat ascii 1.0\nelement vertex 0\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
    let mesh = read_ply_from(empty.as_bytes(), Path::new("empty.ply")).expect("empty");
    assert_eq!(mesh, Mesh::default());
}

/// Positions that stress the round trip: signed zeros, subnormals, extremes, non-finite values.
fn tricky_mesh() -> Mesh {
    let specials = [
        0.0,
        -0.0,
        f64::MIN_POSITIVE,
        5e-324,
        -f64::MAX,
        f64::MAX,
        0.1,
        1.0 / 3.0,
        -2.5e-17,
        6.02214076e23,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    // A simple deterministic generator of arbitrary bit patterns (no NaN: NaN != NaN).
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let x = f64::from_bits(state);
        if x.is_nan() {
            1.5
        } else {
            x
        }
    };
    let mut positions: Vec<[f64; 3]> = specials.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    positions.extend((0..200).map(|_| [next(), next(), next()]));
    let n = positions.len() as u32;
    let triangles = (0..n)
        .map(|i| [i, (i * 7 + 1) % n, (i * 13 + 5) % n])
        .collect();
    Mesh::new(positions, triangles)
}

#[test]
fn write_then_read_is_bit_exact_in_both_formats() {
    let mesh = tricky_mesh();
    let tmp = TempDir::new("io-ply-roundtrip");
    for name in ["m.ply", "m.obj", "M.PLY", "M.Obj"] {
        let path = tmp.path(name);
        write_mesh(&path, &mesh).expect("write");
        let back = read_mesh(&path).expect("read back");
        assert!(same_bits(&back, &mesh), "{name}");
    }
    // The PLY writer's layout is the documented one.
    let header = ply_header(&tmp.path("m.ply"));
    assert!(header.contains("format binary_little_endian 1.0\n"));
    assert!(header.contains("property double x\nproperty double y\nproperty double z\n"));
    assert!(header.contains("property list uchar int vertex_indices\n"));
    let size = std::fs::metadata(tmp.path("m.ply")).expect("stat").len() as usize;
    assert_eq!(
        size,
        header.len() + 24 * mesh.positions.len() + 13 * mesh.triangles.len()
    );
}

#[test]
fn real_frames_round_trip_through_both_formats() {
    for (scene, ..) in SCENES {
        let Some(dir) = scene_dir(scene) else { return };
        let frames = scene_frames(&dir).expect("frames");
        let original = read_ply(&frames.t1).expect("read");
        let tmp = TempDir::new("io-ply-real-roundtrip");
        for name in ["frame.ply", "frame.obj"] {
            let path = tmp.path(name);
            write_mesh(&path, &original).expect("write");
            assert!(
                same_bits(&read_mesh(&path).expect("read back"), &original),
                "{scene} {name}"
            );
        }
    }
}

#[test]
fn an_empty_mesh_round_trips() {
    let tmp = TempDir::new("io-ply-empty");
    for name in ["e.ply", "e.obj"] {
        let path = tmp.path(name);
        write_ply_or_obj(&path);
        assert_eq!(read_mesh(&path).expect("read"), Mesh::default());
    }
}

fn write_ply_or_obj(path: &Path) {
    if path.extension().is_some_and(|e| e == "ply") {
        write_ply(path, &Mesh::default()).expect("write");
    } else {
        write_mesh(path, &Mesh::default()).expect("write");
    }
}
