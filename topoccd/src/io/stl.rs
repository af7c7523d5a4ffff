//! STL meshes (ASCII and binary): a triangle soup, welded into an indexed mesh.
//!
//! Written by hand rather than with the `stl_io` crate: ours names the file, the triangle and
//! the line in every error, reads `f64` coordinates from ASCII files without rounding them to
//! `f32`, and welds on exact coordinates (`stl_io` also welds, but its errors are bare
//! `std::io::Error`s).

use super::{FaceOrigin, IoError, Mesh, MeshNote};
use crate::alloc::{self, try_push, AllocError};
use std::collections::HashMap;
use std::fs::File;
use std::io::Read;
use std::path::Path;

/// Bytes of a binary STL header (80) plus the triangle count (4).
const BINARY_HEAD: usize = 84;
/// Bytes of one binary STL triangle: normal, three corners (12 `f32`), attribute (`u16`).
const BINARY_TRIANGLE: usize = 50;

/// Reads an STL mesh from a file. See [`read_stl_from`].
///
/// ```no_run
/// let mesh = topoccd::io::read_stl(std::path::Path::new("part.stl"))?;
/// println!("{} vertices, {} triangles", mesh.positions.len(), mesh.triangles.len());
/// # Ok::<(), topoccd::io::IoError>(())
/// ```
pub fn read_stl(path: &Path) -> Result<Mesh, IoError> {
    super::mesh::not_a_folder(path)?;
    let file = File::open(path).map_err(|e| IoError::os(path, "open", e))?;
    read_stl_from(file, path)
}

/// Reads an STL mesh (ASCII or binary) from any reader; `name` is the file name used in error
/// messages.
///
/// A file is binary when its length is exactly 84 bytes plus 50 per triangle of the count it
/// declares (binary files may start with `solid` too); otherwise it is ASCII if it starts with
/// `solid`, and binary (and then too short or too long) if not. Trailing bytes after the
/// declared triangles of a binary file are an error, as they mean the count is wrong.
///
/// STL stores each triangle with its own three corners; corners with identical coordinates
/// (`-0.0` and `0.0` count as identical) become one vertex, numbered in order of first
/// appearance, so that neighbouring triangles share vertices. A triangle with two identical
/// corners is dropped (it cannot collide as a triangle); then [`Mesh::face_origin`] maps the
/// remaining triangles to the file's facets. [`Mesh::notes`] says what was welded and dropped.
/// Facet normals and attribute bytes are ignored.
///
/// ```
/// use std::path::Path;
/// use topoccd::io::read_stl_from;
/// let text = "solid square\n\
///   facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n vertex 1 1 0\n endloop\n endfacet\n\
///   facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 1 0\n vertex 0 1 0\n endloop\n endfacet\n\
///   endsolid square\n";
/// let mesh = read_stl_from(text.as_bytes(), Path::new("square.stl"))?;
/// assert_eq!(mesh.positions.len(), 4);
/// assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
/// let bad = text.replace("vertex 0 1 0", "vertex 0 one 0");
/// let err = read_stl_from(bad.as_bytes(), Path::new("square.stl")).unwrap_err();
/// assert_eq!(err.to_string(), "square.stl: triangle 1 at line 13: bad number 'one'");
/// # Ok::<(), topoccd::io::IoError>(())
/// ```
pub fn read_stl_from(mut reader: impl Read, name: &Path) -> Result<Mesh, IoError> {
    let bytes = read_all(&mut reader, name)?;
    let declared = bytes
        .get(80..BINARY_HEAD)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as usize);
    let exact_binary = declared.is_some_and(|n| {
        Some(bytes.len()) == n.checked_mul(BINARY_TRIANGLE).map(|b| b + BINARY_HEAD)
    });
    let starts_solid = bytes.trim_ascii_start().starts_with(b"solid");
    let corners = if !exact_binary && starts_solid {
        read_ascii(&bytes, name)?
    } else {
        read_binary(&bytes, name)?
    };
    weld_soup(&corners).map_err(|e| IoError::memory(name, e))
}

/// The whole input, in a buffer that grows fallibly.
fn read_all(reader: &mut impl Read, name: &Path) -> Result<Vec<u8>, IoError> {
    let mut bytes = Vec::new();
    let mut chunk = vec![0u8; 1 << 16];
    loop {
        let n = match reader.read(&mut chunk) {
            Ok(0) => return Ok(bytes),
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(IoError::os(name, "read", e)),
        };
        alloc::grow(&mut bytes, n, "file contents").map_err(|e| IoError::memory(name, e))?;
        bytes.extend_from_slice(&chunk[..n]);
    }
}

fn stl_error(name: &Path, triangle: usize, line: Option<usize>, message: String) -> IoError {
    IoError::Stl {
        path: name.to_path_buf(),
        triangle,
        line,
        message,
    }
}

/// The corners of a binary file, three per triangle.
fn read_binary(bytes: &[u8], name: &Path) -> Result<Vec<[f64; 3]>, IoError> {
    let Some(count) = bytes.get(80..BINARY_HEAD) else {
        return Err(stl_error(
            name,
            0,
            None,
            format!(
                "the file has {} bytes, too few for a binary STL header (84 bytes) and not an \
                 ASCII STL (it does not start with 'solid')",
                bytes.len()
            ),
        ));
    };
    let count = u32::from_le_bytes([count[0], count[1], count[2], count[3]]) as usize;
    let body = &bytes[BINARY_HEAD..];
    let whole = body.len() / BINARY_TRIANGLE;
    if whole < count {
        return Err(stl_error(
            name,
            whole,
            None,
            format!(
                "the file ends inside triangle {whole}: the binary header declares {count} \
                 triangles ({} bytes), the file has {} bytes",
                BINARY_HEAD as u128 + count as u128 * BINARY_TRIANGLE as u128,
                bytes.len()
            ),
        ));
    }
    if body.len() != count * BINARY_TRIANGLE {
        return Err(stl_error(
            name,
            count,
            None,
            format!(
                "{} bytes follow the {count} triangles the binary header declares: the count \
                 is wrong, or the file is not STL",
                body.len() - count * BINARY_TRIANGLE
            ),
        ));
    }
    let mut corners =
        alloc::with_capacity(count * 3, "corners").map_err(|e| IoError::memory(name, e))?;
    for record in body.chunks_exact(BINARY_TRIANGLE) {
        // Skip the normal (12 bytes); the corners follow, the attribute (2 bytes) ends it.
        for corner in record[12..48].chunks_exact(12) {
            let c = |k: usize| {
                let b = &corner[4 * k..4 * k + 4];
                f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            };
            corners.push([c(0), c(1), c(2)]);
        }
    }
    Ok(corners)
}

/// The corners of an ASCII file, three per triangle.
fn read_ascii(bytes: &[u8], name: &Path) -> Result<Vec<[f64; 3]>, IoError> {
    let text = String::from_utf8_lossy(bytes);
    let mut tokens = Tokens {
        words: alloc::try_collect(
            text.lines()
                .enumerate()
                .flat_map(|(i, line)| line.split_ascii_whitespace().map(move |w| (i + 1, w))),
            "words",
        )
        .map_err(|e| IoError::memory(name, e))?,
        next: 0,
        line: 1,
        triangle: 0,
        name,
    };
    let mut corners = Vec::new();
    tokens.expect("solid")?;
    tokens.rest_of_line_is_a_name();
    loop {
        match tokens.next_word() {
            None => return Err(tokens.error("the file ends without 'endsolid'".into())),
            Some(w) if w.eq_ignore_ascii_case("endsolid") => {
                // Another solid may follow.
                tokens.rest_of_line_is_a_name();
                match tokens.next_word() {
                    None => return Ok(corners),
                    Some(w) if w.eq_ignore_ascii_case("solid") => tokens.rest_of_line_is_a_name(),
                    Some(w) => {
                        return Err(
                            tokens.error(format!("expected 'solid' or the end, found '{w}'"))
                        )
                    }
                }
            }
            Some(w) if w.eq_ignore_ascii_case("facet") => {
                tokens.expect("normal")?;
                for _ in 0..3 {
                    tokens.number()?;
                }
                tokens.expect("outer")?;
                tokens.expect("loop")?;
                for _ in 0..3 {
                    tokens.expect("vertex")?;
                    let corner = [tokens.number()?, tokens.number()?, tokens.number()?];
                    try_push(&mut corners, corner, "corners")
                        .map_err(|e| IoError::memory(name, e))?;
                }
                tokens.expect("endloop")?;
                tokens.expect("endfacet")?;
                tokens.triangle += 1;
            }
            Some(w) => {
                return Err(tokens.error(format!("expected 'facet' or 'endsolid', found '{w}'")))
            }
        }
    }
}

/// The words of an ASCII STL file with their lines.
struct Tokens<'a, 't> {
    words: Vec<(usize, &'t str)>,
    next: usize,
    /// The line of the last word read.
    line: usize,
    triangle: usize,
    name: &'a Path,
}

impl<'t> Tokens<'_, 't> {
    fn next_word(&mut self) -> Option<&'t str> {
        let &(line, word) = self.words.get(self.next)?;
        self.next += 1;
        self.line = line;
        Some(word)
    }

    fn error(&self, message: String) -> IoError {
        stl_error(self.name, self.triangle, Some(self.line), message)
    }

    fn expect(&mut self, keyword: &str) -> Result<(), IoError> {
        match self.next_word() {
            Some(w) if w.eq_ignore_ascii_case(keyword) => Ok(()),
            Some(w) => Err(self.error(format!("expected '{keyword}', found '{w}'"))),
            None => Err(self.error(format!("the file ends where '{keyword}' was expected"))),
        }
    }

    fn number(&mut self) -> Result<f64, IoError> {
        match self.next_word() {
            Some(w) => w
                .parse()
                .map_err(|_| self.error(format!("bad number '{w}'"))),
            None => Err(self.error("the file ends where a number was expected".into())),
        }
    }

    /// Skips the optional name after `solid` / `endsolid` (the words left on that line).
    fn rest_of_line_is_a_name(&mut self) {
        while self
            .words
            .get(self.next)
            .is_some_and(|&(line, _)| line == self.line)
        {
            self.next += 1;
        }
    }
}

/// Welds a triangle soup (three corners per triangle) on exact coordinates; drops triangles
/// with a repeated vertex.
fn weld_soup(corners: &[[f64; 3]]) -> Result<Mesh, AllocError> {
    let mut index: HashMap<[u64; 3], u32> = HashMap::new();
    index
        .try_reserve(corners.len() / 2)
        .map_err(|_| AllocError::of::<([u64; 3], u32)>("vertex map", corners.len() / 2))?;
    let mut positions = Vec::new();
    let mut ids = alloc::with_capacity(corners.len(), "corner ids")?;
    for &p in corners {
        let key = p.map(|c| (c + 0.0).to_bits());
        let id = match index.entry(key) {
            std::collections::hash_map::Entry::Occupied(e) => *e.get(),
            std::collections::hash_map::Entry::Vacant(e) => {
                try_push(&mut positions, p, "vertex positions")?;
                *e.insert((positions.len() - 1) as u32)
            }
        };
        ids.push(id);
    }
    let mut triangles = alloc::with_capacity(ids.len() / 3, "triangles")?;
    let mut origin = alloc::with_capacity(ids.len() / 3, "face map")?;
    for (facet, t) in ids.chunks_exact(3).enumerate() {
        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
            triangles.push([t[0], t[1], t[2]]);
            origin.push(FaceOrigin {
                face: facet as u32,
                sub: 0,
            });
        }
    }
    let facets = corners.len() / 3;
    let dropped = facets - triangles.len();
    let notes = vec![MeshNote::Welded {
        corners: corners.len(),
        vertices: positions.len(),
        dropped,
    }];
    Ok(Mesh {
        positions,
        triangles,
        edges: Vec::new(),
        face_origin: (dropped > 0).then_some(origin),
        notes,
    })
}
