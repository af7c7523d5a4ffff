//! Free edges in files (PLY `edge` elements, OBJ `l` lines, read and written) and the
//! codimensional scenes (hair, particles in a funnel): their steps with free edges and points
//! give the same contacts with every method.

use std::path::Path;

use topoccd::io::{read_obj_from, read_ply_from, write_obj_to, write_ply_to, IoError, Mesh};
use topoccd::{Ccd, Method, QueryOptions, Step};
use topoccd_scenes::codim::{codim_frames, CodimScene};

fn rod_and_triangle() -> Mesh {
    Mesh {
        positions: vec![
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 1.0],
            [0.5, 0.5, 2.0],
        ],
        triangles: vec![[0, 1, 2]],
        edges: vec![[3, 4], [4, 0]],
        ..Mesh::default()
    }
}

#[test]
fn ply_and_obj_round_trip_free_edges() {
    let mesh = rod_and_triangle();
    let mut bytes = Vec::new();
    write_ply_to(&mut bytes, &mesh, Path::new("m.ply")).unwrap();
    assert_eq!(
        read_ply_from(bytes.as_slice(), Path::new("m.ply")).unwrap(),
        mesh
    );
    let mut text = Vec::new();
    write_obj_to(&mut text, &mesh, Path::new("m.obj")).unwrap();
    assert!(String::from_utf8_lossy(&text).ends_with("l 4 5\nl 5 1\n"));
    assert_eq!(
        read_obj_from(text.as_slice(), Path::new("m.obj")).unwrap(),
        mesh
    );
}

#[test]
fn ply_edges_without_faces_are_read_and_bad_ones_named() {
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
               property float z\nelement edge 2\nproperty int vertex1\nproperty uchar vertex2\n\
               end_header\n0 0 0\n1 0 0\n2 0 0\n0 1\n1 2\n";
    let mesh = read_ply_from(ply.as_bytes(), Path::new("hair.ply")).unwrap();
    assert_eq!(mesh.edges, vec![[0, 1], [1, 2]]);
    assert!(mesh.triangles.is_empty());
    let bad = ply.replace("1 2\n", "1 7\n");
    let err = read_ply_from(bad.as_bytes(), Path::new("hair.ply")).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::IndexOutOfRange {
                index: 7,
                vertices: 3,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("hair.ply"), "{err}");
    let missing = ply.replace("property uchar vertex2\n", "");
    let missing = missing.replace("0 1\n1 2\n", "0\n1\n");
    let err = read_ply_from(missing.as_bytes(), Path::new("hair.ply")).unwrap_err();
    assert!(err.to_string().contains("'vertex1' and 'vertex2'"), "{err}");
}

#[test]
fn obj_polylines_name_their_line() {
    let err =
        read_obj_from("v 0 0 0\nv 1 0 0\nl 1 3\n".as_bytes(), Path::new("l.obj")).unwrap_err();
    assert!(
        matches!(err, IoError::IndexOutOfRange { index: 3, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("line 3"), "{err}");
}

#[test]
fn codimensional_scenes_agree_across_methods() {
    for scene in CodimScene::ALL {
        let frames = codim_frames(scene, 6, 3);
        assert_eq!(frames, codim_frames(scene, 6, 3), "{scene:?}: seeded");
        let mut kinds = [0usize; 4];
        let mut ccds: Vec<Ccd> = (0..3).map(|_| Ccd::new()).collect();
        for pair in frames.windows(2) {
            let (a, b) = (&pair[0], &pair[1]);
            // A frame survives a PLY round trip, free edges included.
            let mut bytes = Vec::new();
            write_ply_to(&mut bytes, a, Path::new("f.ply")).unwrap();
            assert_eq!(
                &read_ply_from(bytes.as_slice(), Path::new("f.ply")).unwrap(),
                a
            );
            let step = Step::new(&a.positions, &b.positions, &a.triangles)
                .unwrap()
                .with_edges(&a.edges)
                .unwrap();
            let reports: Vec<_> = [Method::Brute, Method::Bvh, Method::Cluster]
                .iter()
                .zip(&mut ccds)
                .map(|(&m, ccd)| ccd.query(&step, m, &QueryOptions::default()).unwrap())
                .collect();
            for r in &reports[1..] {
                assert_eq!(
                    (&r.vf, &r.ee, &r.ve, &r.vv),
                    (
                        &reports[0].vf,
                        &reports[0].ee,
                        &reports[0].ve,
                        &reports[0].vv
                    ),
                    "{scene:?}: {:?}",
                    r.stats.method
                );
            }
            let r = &reports[0];
            for (k, n) in [r.vf.len(), r.ee.len(), r.ve.len(), r.vv.len()]
                .into_iter()
                .enumerate()
            {
                kinds[k] += n;
            }
        }
        eprintln!("{scene:?}: contacts (vf, ee, ve, vv) {kinds:?}");
        match scene {
            CodimScene::HairBundle => assert!(kinds[1] > 0, "strands cross: {kinds:?}"),
            CodimScene::FunnelParticles => {
                assert!(kinds[0] > 0, "particles hit the funnel: {kinds:?}")
            }
            CodimScene::RodRain => {
                assert!(kinds.iter().all(|&n| n > 0), "every kind: {kinds:?}")
            }
        }
    }
}
