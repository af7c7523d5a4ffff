//! Frame sequences: steps built from consecutive frames, parents files, and bad sequences.

use std::fs;
use std::path::PathBuf;

use topoccd::io::sequence::{write_frame, Sequence, SequenceError};
use topoccd::io::{write_mesh, IoError, Mesh};

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("topoccd-seq-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn tri(z: f64) -> Mesh {
    Mesh {
        positions: vec![[0.0, 0.0, z], [1.0, 0.0, z], [0.0, 1.0, z]],
        triangles: vec![[0, 1, 2]],
        ..Mesh::default()
    }
}

/// Frame 1 splits vertex 2 of frame 0: vertex 3 is new, its parent is 2.
fn split() -> Mesh {
    let mut m = tri(1.0);
    m.positions.push([0.0, 2.0, 1.0]);
    m.triangles = vec![[0, 1, 3]];
    m
}

#[test]
fn steps_use_the_next_frames_triangles_and_parent_positions() {
    let dir = temp_dir("ok");
    write_frame(&dir, 0, &tri(0.0), &[]).expect("frame 0");
    write_frame(&dir, 1, &split(), &[(3, 2)]).expect("frame 1");
    write_frame(&dir, 2, &split(), &[]).expect("frame 2");
    let seq = Sequence::open(&dir).expect("sequence");
    assert_eq!(seq.steps(), 2);
    let steps: Vec<_> = seq.iter().collect::<Result<_, _>>().expect("steps");
    let (k, s0) = &steps[0];
    assert_eq!(*k, 0);
    assert_eq!(s0.triangles(), &[[0, 1, 3]]);
    // Vertex 3 starts at its parent's position in frame 0.
    assert_eq!(s0.x0()[3], [0.0, 1.0, 0.0]);
    assert_eq!(s0.x1()[3], [0.0, 2.0, 1.0]);
    // Without a parents file a vertex that exists in both frames just moves.
    assert_eq!(steps[1].1.x0()[3], [0.0, 2.0, 1.0]);
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn new_vertex_without_parent_starts_where_it_ends() {
    let dir = temp_dir("noparent");
    write_frame(&dir, 0, &tri(0.0), &[]).expect("frame 0");
    write_frame(&dir, 1, &split(), &[]).expect("frame 1");
    let (_, step) = Sequence::open(&dir)
        .expect("seq")
        .iter()
        .next()
        .expect("one")
        .expect("ok");
    assert_eq!(step.pos0()[3], step.pos1()[3]);
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn bad_sequences_name_the_frame_and_line() {
    // A gap in the numbering.
    let dir = temp_dir("gap");
    write_frame(&dir, 0, &tri(0.0), &[]).expect("0");
    write_frame(&dir, 2, &tri(0.0), &[]).expect("2");
    match Sequence::open(&dir) {
        Err(e @ SequenceError::Numbering { expected: 1, .. }) => {
            assert!(e.to_string().contains("0002.ply"), "{e}")
        }
        other => panic!("expected a numbering error, got {other:?}"),
    }
    // A single frame.
    let one = temp_dir("one");
    write_frame(&one, 0, &tri(0.0), &[]).expect("0");
    assert!(matches!(
        Sequence::open(&one),
        Err(SequenceError::TooFewFrames { found: 1, .. })
    ));
    // A vertex count that shrinks.
    let shrink = temp_dir("shrink");
    write_frame(&shrink, 0, &split(), &[]).expect("0");
    write_frame(&shrink, 1, &tri(1.0), &[]).expect("1");
    let err = Sequence::open(&shrink)
        .expect("seq")
        .iter()
        .next()
        .expect("step");
    match err {
        Err(
            e @ SequenceError::Shrinks {
                vertices: 3,
                previous: 4,
                ..
            },
        ) => {
            assert!(e.to_string().contains("0001.ply"), "{e}")
        }
        other => panic!("expected a shrink error, got {other:?}"),
    }
    // A parent id out of range, on line 2 of the parents file.
    let parent = temp_dir("parent");
    write_frame(&parent, 0, &tri(0.0), &[]).expect("0");
    write_frame(&parent, 1, &split(), &[]).expect("1");
    fs::write(parent.join("0001.parents"), "# comment\n3 7\n").expect("parents");
    match Sequence::open(&parent)
        .expect("seq")
        .iter()
        .next()
        .expect("step")
    {
        Err(e @ SequenceError::Parents { line: 2, .. }) => {
            assert!(e.to_string().contains("0001.parents:2"), "{e}");
            assert!(e.to_string().contains("PARENT_ID 7"), "{e}");
        }
        other => panic!("expected a parents error, got {other:?}"),
    }
    // A truncated frame.
    let trunc = temp_dir("trunc");
    write_frame(&trunc, 0, &tri(0.0), &[]).expect("0");
    let p1 = write_frame(&trunc, 1, &tri(1.0), &[]).expect("1");
    let bytes = fs::read(&p1).expect("read");
    fs::write(&p1, &bytes[..bytes.len() - 5]).expect("truncate");
    match Sequence::open(&trunc)
        .expect("seq")
        .iter()
        .next()
        .expect("step")
    {
        Err(SequenceError::Frame(e @ IoError::Truncated { .. })) => {
            assert!(e.to_string().contains("0001.ply"), "{e}")
        }
        other => panic!("expected a truncation error, got {other:?}"),
    }
    for d in [dir, one, shrink, parent, trunc] {
        let _ = fs::remove_dir_all(d);
    }
}

#[test]
fn write_frame_never_overwrites() {
    let dir = temp_dir("overwrite");
    write_frame(&dir, 0, &tri(0.0), &[]).expect("first write");
    let before = fs::read(dir.join("0000.ply")).expect("read");
    assert!(write_frame(&dir, 0, &tri(5.0), &[]).is_err());
    assert_eq!(fs::read(dir.join("0000.ply")).expect("read"), before);
    // An OBJ frame mixes in fine.
    write_mesh(&dir.join("0001.obj"), &tri(1.0)).expect("obj");
    assert_eq!(Sequence::open(&dir).expect("seq").steps(), 1);
    let _ = fs::remove_dir_all(&dir);
}
