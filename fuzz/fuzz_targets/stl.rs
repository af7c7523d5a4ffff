//! The STL reader on arbitrary bytes (ASCII and binary): a mesh or an error, never a panic.
//! A mesh it returns must be a consistent weld of the file's corners:
//! - every index in range, no triangle with a repeated vertex, no two vertices at one position;
//! - the face map present exactly when a facet was dropped, one entry per triangle, facets in
//!   increasing order;
//! - for a binary file (checked by decoding its records here, independently of the reader),
//!   each triangle's corners are the `f32` corners of the facet its face map names.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::collections::HashSet;
use std::path::Path;
use topoccd::io::{read_stl_from, MeshNote};

/// A position's bits, with `-0.0` as `0.0` (how STL corners are welded).
fn key(p: &[f64; 3]) -> [u64; 3] {
    p.map(|c| (c + 0.0).to_bits())
}

/// The facets' corners of a binary STL, if `data` is exactly one.
fn binary_facets(data: &[u8]) -> Option<Vec<[[f64; 3]; 3]>> {
    let count = u32::from_le_bytes(data.get(80..84)?.try_into().ok()?) as usize;
    if data.len() != 84 + 50 * count {
        return None;
    }
    let f = |b: &[u8]| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    let facets = data[84..]
        .chunks_exact(50)
        .map(|r| {
            let corner = |k: usize| {
                let c = &r[12 + 12 * k..24 + 12 * k];
                [f(&c[0..4]), f(&c[4..8]), f(&c[8..12])]
            };
            [corner(0), corner(1), corner(2)]
        })
        .collect();
    Some(facets)
}

fuzz_target!(|data: &[u8]| {
    let Ok(mesh) = read_stl_from(data, Path::new("fuzz.stl")) else {
        return;
    };
    let n = mesh.positions.len();
    for t in &mesh.triangles {
        assert!(
            t.iter().all(|&i| (i as usize) < n),
            "index out of range: {t:?}"
        );
        assert!(
            t[0] != t[1] && t[1] != t[2] && t[0] != t[2],
            "degenerate: {t:?}"
        );
    }
    let keys: HashSet<[u64; 3]> = mesh.positions.iter().map(key).collect();
    assert_eq!(keys.len(), n, "two vertices at one position");
    let Some(MeshNote::Welded {
        corners,
        vertices,
        dropped,
    }) = mesh.notes.first().cloned()
    else {
        panic!("no weld note: {:?}", mesh.notes);
    };
    assert_eq!((corners % 3, vertices), (0, n));
    assert_eq!(corners / 3 - dropped, mesh.triangles.len());
    assert_eq!(mesh.face_origin.is_some(), dropped > 0);
    let facet_of = |t: usize| match &mesh.face_origin {
        Some(origin) => origin[t].face as usize,
        None => t,
    };
    if let Some(origin) = &mesh.face_origin {
        assert_eq!(origin.len(), mesh.triangles.len());
        assert!(origin.windows(2).all(|w| w[0].face < w[1].face));
        assert!(origin
            .iter()
            .all(|o| o.sub == 0 && (o.face as usize) < corners / 3));
    }
    if let Some(facets) = binary_facets(data) {
        assert_eq!(facets.len(), corners / 3);
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let facet = &facets[facet_of(t)];
            for k in 0..3 {
                assert_eq!(key(&mesh.positions[tri[k] as usize]), key(&facet[k]));
            }
        }
    }
});
