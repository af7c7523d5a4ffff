//! Wavefront OBJ meshes: a small hand parser (`v`, `f` and `l` carry data; polygons are split
//! into triangles, polylines into edges) and a writer whose coordinates round-trip exactly.

use super::faces::FaceList;
use super::lines::{read_line, LineError};
use super::{IoError, Location, Mesh, MeshNote};
use crate::alloc::{grow, try_push, AllocError};
use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::Path;

/// Statements that are recognised and skipped.
const IGNORED: [&str; 8] = ["vn", "vt", "vp", "o", "g", "s", "usemtl", "mtllib"];

/// Statements that carry geometry other than faces and polylines (points): skipped, counted
/// and reported in [`Mesh::notes`].
const COUNTED: [&str; 1] = ["p"];

/// Reads an OBJ mesh from a file. See [`read_obj_from`] for what is accepted.
///
/// ```no_run
/// let mesh = topoccd::io::read_obj(std::path::Path::new("cloth.obj"))?;
/// println!("{} vertices, {} triangles", mesh.positions.len(), mesh.triangles.len());
/// # Ok::<(), topoccd::io::IoError>(())
/// ```
pub fn read_obj(path: &Path) -> Result<Mesh, IoError> {
    super::mesh::not_a_folder(path)?;
    let file = File::open(path).map_err(|e| IoError::os(path, "open", e))?;
    read_obj_from(file, path)
}

/// Reads an OBJ mesh from any reader; `name` is the file name used in error messages.
///
/// Data statements: `v x y z` (optionally followed by `w`, or by a colour `r g b`) and
/// `f a b c ...`, each corner written `a`, `a/t`, `a//n` or `a/t/n`, with 1-based indices or
/// negative ones (relative to the vertices defined so far). Texture and normal indices are
/// checked for syntax only. A face of more than three corners is split into triangles (a fan
/// if it is convex, ear clipping otherwise: see
/// [`triangulate_polygon`](super::triangulate_polygon)), and [`Mesh::face_origin`] maps each
/// triangle back to its `f` statement (counted from 0). `l a b c ...` (a polyline of two or
/// more vertices, each written `a` or `a/t`) is read as its segments into [`Mesh::edges`] (free
/// edges: rods, hair); `p` (points) is skipped and counted in [`Mesh::notes`]; `vn`, `vt`, `vp`, `o`, `g`, `s`, `usemtl`, `mtllib`,
/// comments (`#` to the end of the line) and blank lines are skipped silently; any other
/// statement is an error, as is a face of fewer than three corners. Errors name the line,
/// counted from 1.
///
/// ```
/// use std::path::Path;
/// use topoccd::io::{read_obj_from, IoError, Location, MeshNote};
/// let text = "# a triangle\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/2 -1/3\n";
/// let mesh = read_obj_from(text.as_bytes(), Path::new("tri.obj"))?;
/// assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
/// assert_eq!(mesh.face_origin, None);
/// let quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nl 1 3 -1\np 2\n";
/// let mesh = read_obj_from(quad.as_bytes(), Path::new("quad.obj"))?;
/// assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
/// assert_eq!(mesh.edges, vec![[0, 2], [2, 3]]);
/// assert!(matches!(&mesh.notes[1], MeshNote::Skipped { count: 1, first_line: 7, .. }));
/// let err = read_obj_from("v 0 0 0\nl 1\n".as_bytes(), Path::new("l.obj")).unwrap_err();
/// assert_eq!(err.to_string(), "l.obj: line 2: a polyline needs two or more vertices, found 1");
/// let err = read_obj_from("v 0 0 0\nv 1 0 0\nf 1 2\n".as_bytes(), Path::new("edge.obj"))
///     .unwrap_err();
/// assert!(matches!(err, IoError::NotTriangle { location: Location::Line(3), vertices: 2, .. }));
/// # Ok::<(), IoError>(())
/// ```
pub fn read_obj_from(reader: impl Read, name: &Path) -> Result<Mesh, IoError> {
    let mut input = BufReader::with_capacity(1 << 16, reader);
    let mut parser = ObjParser {
        name,
        line: 0,
        mesh: Mesh::default(),
        faces: FaceList::default(),
        corners: Vec::new(),
        resolved: Vec::new(),
        skipped: [(0, 0); COUNTED.len()],
        forward: Vec::new(),
    };
    let mut bytes = Vec::new();
    loop {
        bytes.clear();
        let read = read_line(&mut input, &mut bytes, "line").map_err(|e| match e {
            LineError::Io(e) => IoError::os(name, "read", e),
            LineError::Memory(e) => IoError::memory(name, e),
        })?;
        if read == 0 {
            break;
        }
        parser.line += 1;
        let content = match bytes.iter().position(|&b| b == b'#') {
            Some(hash) => &bytes[..hash],
            None => &bytes[..],
        };
        parser.statement(&String::from_utf8_lossy(content))?;
    }
    parser.finish()
}

/// The state of one parse.
struct ObjParser<'a> {
    name: &'a Path,
    /// The current line, 1-based.
    line: usize,
    mesh: Mesh,
    faces: FaceList,
    /// Scratch: the current face's corners as written, then resolved.
    corners: Vec<i64>,
    resolved: Vec<u32>,
    /// Per [`COUNTED`] keyword: how many, and the first line.
    skipped: [(usize, usize); COUNTED.len()],
    /// Positive indices that pointed past the vertices defined so far, as (line, index as
    /// written); checked against the final vertex count.
    forward: Vec<(usize, i64)>,
}

impl ObjParser<'_> {
    fn memory(&self, e: AllocError) -> IoError {
        IoError::memory(self.name, e)
    }

    fn syntax(&self, message: String) -> IoError {
        IoError::ObjSyntax {
            path: self.name.to_path_buf(),
            line: self.line,
            message,
        }
    }

    fn statement(&mut self, text: &str) -> Result<(), IoError> {
        let mut tokens = text.split_ascii_whitespace();
        match tokens.next() {
            None => Ok(()),
            Some("v") => self.vertex(tokens),
            Some("f") => self.face(tokens),
            Some("l") => self.polyline(tokens),
            Some(keyword) if IGNORED.contains(&keyword) => Ok(()),
            Some(keyword) if COUNTED.contains(&keyword) => {
                let k = COUNTED.iter().position(|&c| c == keyword).unwrap_or(0);
                let (count, first) = &mut self.skipped[k];
                *count += 1;
                if *first == 0 {
                    *first = self.line;
                }
                Ok(())
            }
            Some(other) => Err(self.syntax(format!(
                "unsupported statement '{other}' (only v, f and l are read; {}, {} are skipped)",
                COUNTED.join(", "),
                IGNORED.join(", ")
            ))),
        }
    }

    fn vertex<'t>(&mut self, tokens: impl Iterator<Item = &'t str>) -> Result<(), IoError> {
        let mut values = [0.0f64; 7];
        let mut count = 0;
        for token in tokens {
            if count == values.len() {
                return Err(self.syntax("too many numbers in a vertex".into()));
            }
            values[count] = token
                .parse()
                .map_err(|_| self.syntax(format!("bad number '{token}' in a vertex")))?;
            count += 1;
        }
        if !matches!(count, 3 | 4 | 6 | 7) {
            return Err(self.syntax(format!(
                "a vertex needs x y z [w] or x y z r g b, found {count} numbers"
            )));
        }
        try_push(
            &mut self.mesh.positions,
            [values[0], values[1], values[2]],
            "vertex positions",
        )
        .map_err(|e| self.memory(e))
    }

    fn face<'t>(&mut self, tokens: impl Iterator<Item = &'t str>) -> Result<(), IoError> {
        let mut corners = std::mem::take(&mut self.corners);
        corners.clear();
        for token in tokens {
            let corner = self.corner(token)?;
            try_push(&mut corners, corner, "face corners").map_err(|e| self.memory(e))?;
        }
        if corners.len() < 3 {
            return Err(IoError::NotTriangle {
                path: self.name.to_path_buf(),
                location: Location::Line(self.line),
                vertices: corners.len(),
            });
        }
        self.resolve(&corners)?;
        self.corners = corners;
        self.faces
            .polygon(&self.resolved)
            .map_err(|e| IoError::memory(self.name, e))
    }

    /// The corners as written (1-based, or negative: relative), resolved to 0-based vertex
    /// indices into `resolved`; indices past the vertices defined so far are checked at the
    /// end.
    fn resolve(&mut self, corners: &[i64]) -> Result<(), IoError> {
        let defined = self.mesh.positions.len();
        self.resolved.clear();
        grow(&mut self.resolved, corners.len(), "face corners").map_err(|e| self.memory(e))?;
        for &index in corners {
            let resolved = match index {
                i if i > 0 => i - 1,
                i => defined as i64 + i, // negative: relative; 0 stays invalid below
            };
            let fits = u32::try_from(resolved).ok().filter(|_| index != 0);
            match fits {
                Some(r) if index < 0 || (r as usize) < defined => self.resolved.push(r),
                Some(r) if index > 0 => {
                    try_push(&mut self.forward, (self.line, index), "forward references")
                        .map_err(|e| IoError::memory(self.name, e))?;
                    self.resolved.push(r);
                }
                _ => {
                    return Err(IoError::IndexOutOfRange {
                        path: self.name.to_path_buf(),
                        location: Location::Line(self.line),
                        index,
                        vertices: defined,
                    })
                }
            }
        }
        Ok(())
    }

    /// A polyline `l a b c ...` (two or more vertices, each `a` or `a/t`): its segments, into
    /// [`Mesh::edges`].
    fn polyline<'t>(&mut self, tokens: impl Iterator<Item = &'t str>) -> Result<(), IoError> {
        let mut corners = std::mem::take(&mut self.corners);
        corners.clear();
        for token in tokens {
            let corner = self.corner(token)?;
            try_push(&mut corners, corner, "polyline").map_err(|e| self.memory(e))?;
        }
        if corners.len() < 2 {
            return Err(self.syntax(format!(
                "a polyline needs two or more vertices, found {}",
                corners.len()
            )));
        }
        self.resolve(&corners)?;
        self.corners = corners;
        let ids = &self.resolved;
        let edges = &mut self.mesh.edges;
        grow(edges, ids.len() - 1, "edges").map_err(|e| IoError::memory(self.name, e))?;
        edges.extend(ids.windows(2).map(|w| [w[0], w[1]]));
        Ok(())
    }

    /// The vertex index of one face corner `a`, `a/t`, `a//n` or `a/t/n`, as written.
    fn corner(&self, token: &str) -> Result<i64, IoError> {
        let mut parts = token.split('/');
        let vertex = parts.next().unwrap_or_default();
        let index = vertex.parse::<i64>().map_err(|_| {
            self.syntax(format!(
                "bad vertex index '{vertex}' in face corner '{token}'"
            ))
        })?;
        let mut others = 0;
        for part in parts {
            others += 1;
            if others > 2 || !(part.is_empty() || part.parse::<i64>().is_ok()) {
                return Err(self.syntax(format!(
                    "bad face corner '{token}' (expected a, a/t, a//n or a/t/n)"
                )));
            }
        }
        Ok(index)
    }

    /// Checks the forward references against the final vertex count, splits the polygons and
    /// notes what was skipped.
    fn finish(self) -> Result<Mesh, IoError> {
        let mut mesh = self.mesh;
        let vertices = mesh.positions.len();
        if let Some(&(line, index)) = self.forward.iter().find(|(_, i)| *i as usize > vertices) {
            return Err(IoError::IndexOutOfRange {
                path: self.name.to_path_buf(),
                location: Location::Line(line),
                index,
                vertices,
            });
        }
        let (triangles, origin) = self
            .faces
            .finish(&mesh.positions, &mut mesh.notes)
            .map_err(|e| IoError::memory(self.name, e))?;
        mesh.triangles = triangles;
        mesh.face_origin = origin;
        for (keyword, &(count, first_line)) in COUNTED.iter().zip(&self.skipped) {
            if count > 0 {
                mesh.notes.push(MeshNote::Skipped {
                    keyword: (*keyword).to_owned(),
                    count,
                    first_line,
                });
            }
        }
        Ok(mesh)
    }
}

/// Writes a mesh as OBJ text: one `v x y z` line per vertex, one `f a b c` line (1-based) per
/// triangle. Coordinates are printed in the shortest form that parses back to the same `f64`,
/// so reading the file back with [`read_obj`](super::read_obj) gives the same positions bit for
/// bit (except the sign and payload of a NaN) and the same triangles.
///
/// ```
/// use topoccd::io::{read_obj, write_obj, Mesh};
/// let mesh = Mesh::new(
///     vec![[0.0; 3], [1e-300, -0.0, 2.5], [0.1; 3]],
///     vec![[0, 1, 2]],
/// );
/// let path = std::env::temp_dir().join(format!("topoccd-doc-write-obj-{}.obj", std::process::id()));
/// write_obj(&path, &mesh)?;
/// assert_eq!(read_obj(&path)?, mesh);
/// std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_obj(path: &Path, mesh: &Mesh) -> Result<(), IoError> {
    let file = File::create(path).map_err(|e| IoError::os(path, "create", e))?;
    write_obj_to(file, mesh, path)
}

/// Writes a mesh as OBJ text (see [`write_obj`]) to any writer; `name` is the file name used
/// in error messages.
///
/// ```
/// use std::path::Path;
/// use topoccd::io::{write_obj_to, Mesh};
/// let mesh = Mesh::new(
///     vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
///     vec![[0, 1, 2]],
/// );
/// let mut bytes = Vec::new();
/// write_obj_to(&mut bytes, &mesh, Path::new("memory.obj"))?;
/// let text = String::from_utf8(bytes).unwrap();
/// assert!(text.ends_with("v 1.0 0.0 0.0\nv 0.0 1.0 0.0\nv 0.0 0.0 1.0\nf 1 2 3\n"));
/// # Ok::<(), topoccd::io::IoError>(())
/// ```
pub fn write_obj_to(output: impl Write, mesh: &Mesh, name: &Path) -> Result<(), IoError> {
    let mut out = BufWriter::with_capacity(1 << 16, output);
    let write_error = |e| IoError::os(name, "write", e);
    writeln!(
        out,
        "# written by topoccd: {} vertices, {} triangles",
        mesh.positions.len(),
        mesh.triangles.len()
    )
    .map_err(write_error)?;
    for p in &mesh.positions {
        // `{:?}` prints the shortest decimal that parses back to the same f64.
        writeln!(out, "v {:?} {:?} {:?}", p[0], p[1], p[2]).map_err(write_error)?;
    }
    let one_based = |i: u32| u64::from(i) + 1;
    for &[a, b, c] in &mesh.triangles {
        writeln!(out, "f {} {} {}", one_based(a), one_based(b), one_based(c))
            .map_err(write_error)?;
    }
    for &[a, b] in &mesh.edges {
        writeln!(out, "l {} {}", one_based(a), one_based(b)).map_err(write_error)?;
    }
    out.flush().map_err(write_error)
}
