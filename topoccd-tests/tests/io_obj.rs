//! OBJ reading: every corner form, relative indices, skipped statements, and errors that name
//! the file and the line.

#[path = "../../topoccd/tests/io_util/mod.rs"]
mod io_util;

use io_util::{same_bits, scene_dir, TempDir};
use std::path::{Path, PathBuf};
use topoccd::io::{
    read_mesh, read_obj, read_obj_from, read_ply, scene_frames, write_obj, IoError, Location, Mesh,
};

fn parse(text: &str) -> Result<Mesh, IoError> {
    read_obj_from(text.as_bytes(), Path::new("test.obj"))
}

/// Writes `text` to a temp file and reads it through `read_mesh`; returns the error and path.
fn read_err(tmp: &TempDir, text: &str) -> (IoError, PathBuf) {
    let path = tmp.file("bad.obj", text);
    match read_mesh(&path) {
        Ok(mesh) => panic!("read as {mesh:?}"),
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

#[test]
fn every_corner_form_and_skipped_statement() {
    let text = "\
# exported by hand\r
mtllib scene.mtl\r
o cloth\r
g part one\r
s off\r
usemtl red\r
v 0 0 0\r
v 1.5 -2 3e-3 1.0\r
v  .5\t0.25   -1. # trailing comment\r
\r
vt 0.5 0.5\r
vn 0 0 1\r
vp 0.1\r
v 1 1 1 0.2 0.4 0.6\r
f 1 2 3\r
f 1/1 2/1 3/1\r
f 2//1 3//1 4//1\r
f 4/1/1 3/1/1 1/1/1\r
f -1 -2 -3\r
f -4/1 2//1 -1/1/1";
    let mesh = parse(text).expect("parse");
    assert_eq!(
        mesh.positions,
        vec![[0.0; 3], [1.5, -2.0, 3e-3], [0.5, 0.25, -1.0], [1.0; 3]]
    );
    assert_eq!(
        mesh.triangles,
        vec![
            [0, 1, 2],
            [0, 1, 2],
            [1, 2, 3],
            [3, 2, 0],
            [3, 2, 1],
            [0, 1, 3]
        ]
    );
}

#[test]
fn relative_indices_count_the_vertices_defined_so_far() {
    let mesh =
        parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf -3 -2 -1\n").expect("parse");
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [1, 2, 3]]);
    // Positive indices may refer to vertices defined later in the file.
    let mesh = parse("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").expect("forward references");
    assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
}

#[test]
fn bad_number_names_the_line() {
    let tmp = TempDir::new("io-obj-number");
    let (e, path) = read_err(&tmp, "v 0 0 0\n# fine\nv 1 0 0\nv 0 1,5 0\nf 1 2 3\n");
    assert!(matches!(e, IoError::ObjSyntax { line: 4, .. }), "{e:?}");
    assert_names(&e, &path, "line 4: bad number '1,5'");
    let (e, path) = read_err(&tmp, "v 0 0 0\nv 1 0\n");
    assert!(matches!(e, IoError::ObjSyntax { line: 2, .. }), "{e:?}");
    assert_names(&e, &path, "line 2: a vertex needs");
    let (e, path) = read_err(&tmp, "v 0 0 0\n\n\nf 1 x 1\n");
    assert!(matches!(e, IoError::ObjSyntax { line: 4, .. }), "{e:?}");
    assert_names(&e, &path, "line 4: bad vertex index 'x'");
    let (e, path) = read_err(&tmp, "v 0 0 0\nf 1/1/1/1 1 1\n");
    assert!(matches!(e, IoError::ObjSyntax { line: 2, .. }), "{e:?}");
    assert_names(&e, &path, "bad face corner '1/1/1/1'");
    let (e, path) = read_err(&tmp, "v 0 0 0\ncurv 0 1 1\n");
    assert!(matches!(e, IoError::ObjSyntax { line: 2, .. }), "{e:?}");
    assert_names(&e, &path, "unsupported statement 'curv'");
}

#[test]
fn face_index_zero_names_the_line() {
    let tmp = TempDir::new("io-obj-zero");
    let (e, path) = read_err(&tmp, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 0 1 2\n");
    assert!(
        matches!(
            e,
            IoError::IndexOutOfRange {
                location: Location::Line(5),
                index: 0,
                vertices: 3,
                ..
            }
        ),
        "{e:?}"
    );
    assert_names(
        &e,
        &path,
        "line 5: vertex index 0 is out of range for 3 vertices",
    );
}

#[test]
fn out_of_range_indices_name_the_line() {
    let tmp = TempDir::new("io-obj-range");
    // Too far back, relative to the two vertices defined before line 3.
    let (e, path) = read_err(&tmp, "v 0 0 0\nv 1 0 0\nf -3 1 2\nv 0 1 0\n");
    assert!(
        matches!(
            e,
            IoError::IndexOutOfRange {
                location: Location::Line(3),
                index: -3,
                vertices: 2,
                ..
            }
        ),
        "{e:?}"
    );
    assert_names(&e, &path, "line 3");
    // Past the end of the file's vertices: the first offending line is named.
    let (e, path) = read_err(
        &tmp,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\nf 1 2 5\n",
    );
    assert!(
        matches!(
            e,
            IoError::IndexOutOfRange {
                location: Location::Line(5),
                index: 4,
                vertices: 3,
                ..
            }
        ),
        "{e:?}"
    );
    assert_names(&e, &path, "line 5: vertex index 4");
}

#[test]
fn faces_need_three_corners() {
    let tmp = TempDir::new("io-obj-edge");
    // (Quads and larger polygons are split into triangles: see io_polygons.rs.)
    let (e, path) = read_err(
        &tmp,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\nf 1 2\n",
    );
    assert_names(&e, &path, "line 6 has 2 vertices");
    let (e, _) = read_err(&tmp, "v 0 0 0\nv 1 0 0\nf 1 2\n");
    assert!(
        matches!(
            e,
            IoError::NotTriangle {
                location: Location::Line(3),
                vertices: 2,
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn invalid_utf8_outside_data_is_harmless() {
    let mut bytes = b"# caf\xe9\ng groupe \xe9t\xe9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_vec();
    let mesh = read_obj_from(bytes.as_slice(), Path::new("latin1.obj")).expect("parse");
    assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    bytes.extend_from_slice(b"v 1 \xff 0\n");
    let e = read_obj_from(bytes.as_slice(), Path::new("latin1.obj")).expect_err("bad byte");
    assert!(matches!(e, IoError::ObjSyntax { line: 7, .. }), "{e:?}");
}

#[test]
fn real_frame_round_trips_through_obj() {
    let Some(dir) = scene_dir("cloth-ball") else {
        return;
    };
    let frames = scene_frames(&dir).expect("frames");
    let original = read_ply(&frames.t0).expect("read");
    let tmp = TempDir::new("io-obj-real");
    let path = tmp.path("ball.obj");
    write_obj(&path, &original).expect("write");
    assert!(same_bits(&read_obj(&path).expect("read back"), &original));
}
