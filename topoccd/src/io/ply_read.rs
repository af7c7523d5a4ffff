//! Reading PLY meshes through `ply-rs-bw`: ASCII and binary (either byte order), `float` or
//! `double` coordinates, face index lists of any integer types (polygons split into triangles),
//! triangle strips. The parser's errors are wrapped
//! so that they name the file and the element.

use super::faces::FaceList;
use super::lines::{read_line, LineError};
use super::ply_elements::{PlyEdge, PlyFace, PlyVertex, Skip, INDEX_LISTS};
use super::{IoError, Location, Mesh};
use crate::alloc::{grow, try_push};
use ply_rs_bw::parser::{ParseError, Parser, Reader};
use ply_rs_bw::ply::{ElementDef, Encoding, Header, PropertyAccess, PropertyType, ScalarType};
use std::fs::File;
use std::io::{BufRead, BufReader, ErrorKind, Read};
use std::path::Path;

/// Elements preallocated at most, whatever the header claims: a corrupt count must not
/// allocate gigabytes before the data runs out.
const MAX_PREALLOCATED: usize = 1 << 16;

/// Reads a PLY mesh from a file. See [`read_ply_from`] for what is accepted. As the file's size
/// is known, a header declaring more elements than the file can hold (a truncated file, or a
/// corrupt count such as 10^10 vertices) is refused right after the header, before any data is
/// read or memory reserved: [`IoError::CountsExceedFile`].
///
/// ```no_run
/// use std::path::Path;
/// let mesh = topoccd::io::read_ply(Path::new("../../shared/data/scenes/cloth-funnel/frames/227.ply"))?;
/// assert_eq!(mesh.triangles.len(), 18_484);
/// # Ok::<(), topoccd::io::IoError>(())
/// ```
pub fn read_ply(path: &Path) -> Result<Mesh, IoError> {
    let (file, size) = open_sized(path)?;
    read_ply_sized(file, path, size)
}

/// Opens a file, with its size if it is a regular file (not a pipe or a device).
fn open_sized(path: &Path) -> Result<(File, Option<u64>), IoError> {
    super::mesh::not_a_folder(path)?;
    let file = File::open(path).map_err(|e| IoError::os(path, "open", e))?;
    let size = file
        .metadata()
        .ok()
        .filter(|m| m.is_file())
        .map(|m| m.len());
    Ok((file, size))
}

/// The element counts a PLY header declares, read by [`read_ply_header`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlyCounts {
    /// Number of `vertex` elements.
    pub vertices: usize,
    /// Number of `face` elements (0 when there is no `face` element).
    pub faces: usize,
}

/// Reads only the header of a PLY file: the vertex and face counts it declares, after the same
/// checks as [`read_ply`] makes before reading any data (the magic line, the header syntax, a
/// triangle-mesh layout, and counts whose data fit in the file's size). A caller can thus
/// refuse a mesh too large for its memory before reading it.
///
/// ```
/// use topoccd::io::{read_ply_header, write_ply, Mesh, PlyCounts};
/// let mesh = Mesh::new(
///     vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
///     vec![[0, 1, 2]],
/// );
/// let path = std::env::temp_dir().join(format!("topoccd-doc-header-{}.ply", std::process::id()));
/// write_ply(&path, &mesh)?;
/// assert_eq!(read_ply_header(&path)?, PlyCounts { vertices: 3, faces: 1 });
/// std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_ply_header(path: &Path) -> Result<PlyCounts, IoError> {
    let (file, size) = open_sized(path)?;
    let mut input = BufReader::with_capacity(1 << 16, file);
    let (header, _, _) = read_checked_header(&mut input, path, size)?;
    Ok(PlyCounts {
        vertices: header.elements.get("vertex").map_or(0, |e| e.count),
        faces: header.elements.get("face").map_or(0, |e| e.count),
    })
}

/// Reads a PLY mesh from any reader; `name` is the file name used in error messages.
///
/// Accepts ASCII and binary little- or big-endian files. The `vertex` element must have `x`,
/// `y`, `z` of type `float` or `double`. Triangles come from a `face` element, a `tristrips`
/// element, or both, each with an integer list named `vertex_indices` or `vertex_index`:
/// - a face of more than three indices is split into triangles (a fan if it is convex, ear
///   clipping otherwise: see [`triangulate_polygon`](super::triangulate_polygon)); a face of
///   fewer than three is an error;
/// - a strip record `a b c d ...` gives the triangles `(a, b, c)`, `(c, b, d)`, ..., with `-1`
///   restarting the strip; triangles with a repeated vertex (stitches) are dropped.
///
/// When anything was split, [`Mesh::face_origin`] maps each triangle to its record (the records
/// of `face` and `tristrips` counted together from 0, in file order) and [`Mesh::notes`] says
/// what was done. A file with vertices but neither a `face` nor a `tristrips` element (a point
/// cloud) is refused ([`IoError::NoFaces`]): it has nothing to collide; an explicit
/// `element face 0` is read as a mesh without triangles. Other elements and properties
/// (normals, colours, ...) are ignored. Never panics; errors name the element where reading
/// stopped, counted from 0 as in the file ("face 3 of 12").
///
/// ```
/// use std::path::Path;
/// use topoccd::io::{read_ply_from, IoError};
/// let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
///             property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
///             end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
/// let mesh = read_ply_from(text.as_bytes(), Path::new("tri.ply"))?;
/// assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
/// let bad = text.replace("3 0 1 2", "3 0 1 7");
/// let err = read_ply_from(bad.as_bytes(), Path::new("tri.ply")).unwrap_err();
/// assert!(matches!(err, IoError::IndexOutOfRange { index: 7, .. }));
/// assert_eq!(
///     err.to_string(),
///     "tri.ply: face 0 of 1 (line 13): vertex index 7 is out of range for 3 vertices"
/// );
/// # Ok::<(), IoError>(())
/// ```
pub fn read_ply_from(reader: impl Read, name: &Path) -> Result<Mesh, IoError> {
    read_ply_sized(reader, name, None)
}

/// [`read_ply_from`], refusing right after the header if `size` (the file's size in bytes,
/// when known) cannot hold the elements the header declares.
fn read_ply_sized(reader: impl Read, name: &Path, size: Option<u64>) -> Result<Mesh, IoError> {
    let mut input = BufReader::with_capacity(1 << 16, reader);
    let (header, vertex_count, next_line) = read_checked_header(&mut input, name, size)?;
    let mut elements = Elements {
        name,
        encoding: header.encoding,
        next_line,
        text: String::new(),
    };
    let mut positions = Vec::new();
    let mut faces = FaceList::default();
    let mut ids = Vec::new();
    let mut edges = Vec::new();
    for def in header.elements.values().take(needed_elements(&header)) {
        match def.name.as_str() {
            "vertex" => {
                grow(
                    &mut positions,
                    def.count.min(MAX_PREALLOCATED),
                    "vertex positions",
                )
                .map_err(|e| IoError::memory(name, e))?;
                elements.read(&mut input, def, |_, v: PlyVertex| {
                    try_push(&mut positions, v.0, "vertex positions")
                        .map_err(|e| IoError::memory(name, e))
                })?;
            }
            "face" => {
                elements.read(&mut input, def, |location, f: PlyFace| {
                    f.corners(location, vertex_count, name, &mut ids)?;
                    faces.polygon(&ids).map_err(|e| IoError::memory(name, e))
                })?;
            }
            "tristrips" => {
                elements.read(&mut input, def, |location, f: PlyFace| {
                    f.strip(location, vertex_count, name, &mut ids)?;
                    faces.strip(&ids).map_err(|e| IoError::memory(name, e))
                })?;
            }
            "edge" => {
                elements.read(&mut input, def, |location, e: PlyEdge| {
                    let ends = e.ends(location, vertex_count, name)?;
                    try_push(&mut edges, ends, "edges").map_err(|e| IoError::memory(name, e))
                })?;
            }
            _ => elements.read(&mut input, def, |_, _: Skip| Ok(()))?,
        }
    }
    debug_assert_eq!(positions.len(), vertex_count);
    let mut notes = Vec::new();
    let (triangles, face_origin) = faces
        .finish(&positions, &mut notes)
        .map_err(|e| IoError::memory(name, e))?;
    Ok(Mesh {
        positions,
        triangles,
        edges,
        face_origin,
        notes,
    })
}

/// Reads and checks the header: the magic line, the syntax, the layout, and (when `size` is
/// known) that the file can hold the declared elements. Returns the header, the vertex count
/// and the line (1-based) of the first element.
fn read_checked_header(
    input: &mut impl BufRead,
    name: &Path,
    size: Option<u64>,
) -> Result<(Header, usize, usize), IoError> {
    check_magic(input, name)?;
    // The header is parsed from our own copy, so that an error can quote the offending line;
    // the payload is then read straight from `input`.
    let header_text = read_header_text(input, name)?;
    let mut header_reader = Reader::new(header_text.as_slice());
    let header = Parser::<Skip>::new()
        .read_header(&mut header_reader)
        .map_err(|e| header_error(&e, &header_text, name))?;
    let vertex_count = check_layout(&header, name)?;
    if let Some(size) = size {
        check_declared_size(&header, header_text.len() as u64, size, name)?;
    }
    Ok((header, vertex_count, header_reader.line()))
}

/// The elements that carry triangles.
const FACE_ELEMENTS: [&str; 2] = ["face", "tristrips"];

/// How many elements of the header (in order) are read: up to the last `vertex`, `face` or
/// `tristrips`; whatever follows is not looked at.
fn needed_elements(header: &Header) -> usize {
    header
        .elements
        .values()
        .rposition(|def| {
            def.name == "vertex" || def.name == "edge" || FACE_ELEMENTS.contains(&def.name.as_str())
        })
        .map_or(0, |last| last + 1)
}

/// The fewest bytes one element of `def` can take. Binary: the sizes of its scalars plus the
/// count of each list (a list may be empty). ASCII: one character per value (a list's count at
/// least) and one separator or newline after each, or one newline for an element without
/// properties.
fn min_element_bytes(def: &ElementDef, encoding: Encoding) -> u64 {
    let properties = def.properties.values().map(|p| &p.data_type);
    match encoding {
        Encoding::Ascii => (2 * def.properties.len() as u64).max(1),
        Encoding::BinaryBigEndian | Encoding::BinaryLittleEndian => properties
            .map(|t| match t {
                PropertyType::Scalar(s) | PropertyType::List(s, _) => scalar_bytes(s),
            })
            .sum(),
    }
}

fn scalar_bytes(t: &ScalarType) -> u64 {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

/// Refuses a header whose elements cannot fit in a file of `size` bytes (a truncated file, or
/// corrupt counts such as 10^10 vertices in a file of a few kilobytes) before any data is read.
fn check_declared_size(
    header: &Header,
    header_bytes: u64,
    size: u64,
    name: &Path,
) -> Result<(), IoError> {
    // The last ASCII line may lack its newline.
    let slack = u128::from(header.encoding == Encoding::Ascii);
    let mut needed = u128::from(header_bytes);
    for def in header.elements.values().take(needed_elements(header)) {
        needed += def.count as u128 * u128::from(min_element_bytes(def, header.encoding));
        if needed.saturating_sub(slack) > u128::from(size) {
            return Err(IoError::CountsExceedFile {
                path: name.to_path_buf(),
                element: def.name.clone(),
                count: def.count,
                needed: u64::try_from(needed - slack).unwrap_or(u64::MAX),
                size,
            });
        }
    }
    Ok(())
}

/// Refuses anything that does not start with the magic line `ply`.
fn check_magic(input: &mut impl BufRead, name: &Path) -> Result<(), IoError> {
    let start = input.fill_buf().map_err(|e| IoError::os(name, "read", e))?;
    let magic = start.starts_with(b"ply") && matches!(start.get(3), None | Some(b'\n' | b'\r'));
    if magic {
        Ok(())
    } else {
        Err(IoError::NotPly {
            path: name.to_path_buf(),
        })
    }
}

/// The longest header we accept: more is not a mesh header but a file without `end_header`.
const MAX_HEADER_BYTES: u64 = 1 << 20;

/// The header lines, up to and including `end_header` (or all that is there if it is missing).
fn read_header_text(input: &mut impl BufRead, name: &Path) -> Result<Vec<u8>, IoError> {
    let mut text = Vec::new();
    loop {
        let start = text.len();
        let budget = MAX_HEADER_BYTES.saturating_sub(start as u64);
        let read = input
            .take(budget)
            .read_until(b'\n', &mut text)
            .map_err(|e| IoError::os(name, "read", e))?;
        let line = text[start..].trim_ascii();
        if read == 0 || line == b"end_header" {
            return Ok(text);
        }
        if text.len() as u64 >= MAX_HEADER_BYTES {
            return Err(IoError::PlyHeader {
                path: name.to_path_buf(),
                line: None,
                message: format!("no 'end_header' in the first {MAX_HEADER_BYTES} bytes"),
            });
        }
    }
}

/// A header error quoting the offending line, with the first sentence of the parser's message.
fn header_error(e: &ParseError, header_text: &[u8], name: &Path) -> IoError {
    let reason = clean_message(e);
    let reason = reason.split("; ").next().unwrap_or_default();
    let quoted = e
        .line()
        .and_then(|line| header_text.split(|&b| b == b'\n').nth(line.checked_sub(1)?))
        .map(|text| {
            String::from_utf8_lossy(text.trim_ascii())
                .chars()
                .take(80)
                .collect::<String>()
        })
        .filter(|text| !text.is_empty());
    let message = match quoted {
        Some(text) => format!("{} in '{text}'", reason.trim_end_matches('.')),
        None => reason.to_owned(),
    };
    IoError::PlyHeader {
        path: name.to_path_buf(),
        line: e.line(),
        message,
    }
}

/// Checks that the header describes a triangle mesh we can read; returns the vertex count.
fn check_layout(header: &Header, name: &Path) -> Result<usize, IoError> {
    let layout_error = |message: String| IoError::PlyLayout {
        path: name.to_path_buf(),
        message,
    };
    let vertex = header
        .elements
        .get("vertex")
        .ok_or_else(|| layout_error("there is no 'vertex' element".into()))?;
    for axis in ["x", "y", "z"] {
        match vertex.properties.get(axis).map(|p| &p.data_type) {
            Some(PropertyType::Scalar(ScalarType::Float | ScalarType::Double)) => {}
            Some(other) => {
                return Err(layout_error(format!(
                    "vertex property '{axis}' has type {other:?}; expected float or double"
                )))
            }
            None => return Err(layout_error(format!("vertex property '{axis}' is missing"))),
        }
    }
    for element in FACE_ELEMENTS {
        let Some(face) = header.elements.get(element) else {
            continue;
        };
        let lists: Vec<_> = face
            .properties
            .values()
            .filter(|p| INDEX_LISTS.contains(&p.name.as_str()))
            .collect();
        match lists.as_slice() {
            [] if face.count == 0 => {}
            [] => {
                return Err(layout_error(format!(
                    "the '{element}' element has no 'vertex_indices' or 'vertex_index' list"
                )))
            }
            [list] => {
                if !matches!(&list.data_type, PropertyType::List(count, index)
                    if is_integer(count) && is_integer(index))
                {
                    return Err(layout_error(format!(
                        "{element} property '{}' has type {:?}; expected a list of integers",
                        list.name, list.data_type
                    )));
                }
            }
            _ => {
                return Err(layout_error(format!(
                    "the '{element}' element has both 'vertex_indices' and 'vertex_index'"
                )))
            }
        }
    }
    let has_faces = FACE_ELEMENTS
        .iter()
        .chain(&["edge"])
        .any(|e| header.elements.contains_key(*e));
    if vertex.count > 0 && !has_faces {
        return Err(IoError::NoFaces {
            path: name.to_path_buf(),
            vertices: vertex.count,
            elements: header.elements.keys().cloned().collect(),
        });
    }
    Ok(vertex.count)
}

fn is_integer(t: &ScalarType) -> bool {
    !matches!(t, ScalarType::Float | ScalarType::Double)
}

/// Reads the elements of the payload one by one, keeping track of where we are.
struct Elements<'a> {
    name: &'a Path,
    encoding: Encoding,
    /// In ASCII files, the line of the next element (1-based).
    next_line: usize,
    /// Scratch line of ASCII files.
    text: String,
}

impl Elements<'_> {
    /// Reads all `def.count` elements of `def`, handing each to `each` with its location.
    fn read<E: PropertyAccess>(
        &mut self,
        input: &mut impl BufRead,
        def: &ElementDef,
        mut each: impl FnMut(&dyn Fn() -> Location, E) -> Result<(), IoError>,
    ) -> Result<(), IoError> {
        if def.properties.is_empty() && self.encoding != Encoding::Ascii {
            // Binary elements without properties take no bytes: nothing to read, and a huge
            // count must not spin.
            return Ok(());
        }
        let parser = Parser::<E>::new();
        for index in 0..def.count {
            let ascii = self.encoding == Encoding::Ascii;
            let line = self.next_line + index;
            let location = || Location::Element {
                name: def.name.clone(),
                index,
                count: def.count,
                line: ascii.then_some(line),
            };
            let element = match self.encoding {
                Encoding::Ascii => match self.read_text_line(input)? {
                    Ok(0) => Err(ParseError::from(std::io::Error::from(
                        ErrorKind::UnexpectedEof,
                    ))),
                    Ok(_) => parser.read_ascii_element(self.text.trim_end(), def),
                    Err(e) => Err(e),
                },
                Encoding::BinaryBigEndian => parser.read_big_endian_element(input, def),
                Encoding::BinaryLittleEndian => parser.read_little_endian_element(input, def),
            };
            let element = element.map_err(|e| {
                let line = ascii.then_some((self.text.as_str(), def));
                self.element_error(&e, location(), line)
            })?;
            each(&location, element)?;
        }
        if self.encoding == Encoding::Ascii {
            self.next_line += def.count;
        }
        Ok(())
    }

    /// Reads the next line of an ASCII file into `self.text` (growing it fallibly): its length
    /// in bytes, or the parser's error for a line that is not UTF-8.
    fn read_text_line(
        &mut self,
        input: &mut impl BufRead,
    ) -> Result<Result<usize, ParseError>, IoError> {
        let mut bytes = std::mem::take(&mut self.text).into_bytes();
        bytes.clear();
        let read = read_line(input, &mut bytes, "line").map_err(|e| match e {
            LineError::Io(e) => IoError::os(self.name, "read", e),
            LineError::Memory(e) => IoError::memory(self.name, e),
        })?;
        Ok(match String::from_utf8(bytes) {
            Ok(text) => {
                self.text = text;
                Ok(read)
            }
            Err(_) => Err(ParseError::from(std::io::Error::new(
                ErrorKind::InvalidData,
                "stream did not contain valid UTF-8",
            ))),
        })
    }

    /// The error of an element the parser refused; `line`, in an ASCII file, is its text and
    /// definition, for a message of our own (the parser's names its grammar's internals).
    fn element_error(
        &self,
        e: &ParseError,
        location: Location,
        line: Option<(&str, &ElementDef)>,
    ) -> IoError {
        if e.kind() == ErrorKind::UnexpectedEof {
            IoError::Truncated {
                path: self.name.to_path_buf(),
                location,
            }
        } else {
            let message = line.and_then(|(text, def)| ascii_diagnosis(text, def));
            IoError::PlyElement {
                path: self.name.to_path_buf(),
                location,
                message: message.unwrap_or_else(|| clean_message(e)),
            }
        }
    }
}

/// What is wrong with the ASCII line `text` of an element of `def`: the first value that is not
/// a number of its property's type, or a count of values that does not match; `None` if the
/// line looks right.
fn ascii_diagnosis(text: &str, def: &ElementDef) -> Option<String> {
    let why = ascii_fault(text, def)?;
    Some(format!("{why}, in '{}'", text.trim()))
}

/// [`ascii_diagnosis`] without the line.
fn ascii_fault(text: &str, def: &ElementDef) -> Option<String> {
    let mut tokens = text.split_whitespace().enumerate();
    let check = |(k, token): (usize, &str), name: &str, t: &ScalarType| -> Option<String> {
        let what = format!("value {} ('{token}', property '{name}')", k + 1);
        if is_integer(t) {
            if token.parse::<i64>().is_err() {
                return Some(format!("{what} is not an integer"));
            }
        } else {
            match token.parse::<f64>() {
                Ok(x) if !x.is_finite() => {
                    return Some(format!(
                        "{what} is not a finite number: coordinates must be finite"
                    ))
                }
                Ok(_) => {}
                Err(_) => return Some(format!("{what} is not a number")),
            }
        }
        None
    };
    let mut expected = 0;
    for property in def.properties.values() {
        match &property.data_type {
            PropertyType::Scalar(t) => {
                expected += 1;
                let Some(token) = tokens.next() else { break };
                if let Some(why) = check(token, &property.name, t) {
                    return Some(why);
                }
            }
            PropertyType::List(count_type, t) => {
                expected += 1;
                let Some(token) = tokens.next() else { break };
                if let Some(why) = check(token, &property.name, count_type) {
                    return Some(why);
                }
                let n: usize = token.1.parse().ok()?;
                expected += n;
                for _ in 0..n {
                    let Some(token) = tokens.next() else { break };
                    if let Some(why) = check(token, &property.name, t) {
                        return Some(why);
                    }
                }
            }
        }
    }
    let found = text.split_whitespace().count();
    (found != expected)
        .then(|| format!("the line holds {found} values where the header declares {expected}"))
}

/// The parser's message on one line, without its own "Line N: " prefix.
fn clean_message(e: &ParseError) -> String {
    let text = e.to_string();
    let text = match e.line() {
        Some(line) => text
            .strip_prefix(&format!("Line {line}: "))
            .map(str::to_owned)
            .unwrap_or(text),
        None => text,
    };
    text.split(['\n', '\t'])
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}
