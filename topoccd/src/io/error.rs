//! Why a file could not be read or written, and where in the file the problem is.

use std::fmt;
use std::path::PathBuf;
use thiserror::Error;

/// Where in a file a problem was found.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    /// A line of a text file (OBJ, JSON), 1-based.
    Line(usize),
    /// An element of a PLY file, numbered as in the file: the `index`-th (0-based) of the
    /// `count` elements named `name` that the header declares. In an ASCII file `line` (1-based)
    /// is the line that holds the element; in a binary file it is `None`.
    Element {
        /// Name of the element, as in the header (`vertex`, `face`, ...).
        name: String,
        /// Index of the element, 0-based, in the numbering of the file.
        index: usize,
        /// Number of such elements the header declares.
        count: usize,
        /// The line of an ASCII file (1-based); `None` in binary files.
        line: Option<usize>,
    },
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(line) => write!(f, "line {line}"),
            Location::Element {
                name,
                index,
                count,
                line,
            } => {
                write!(f, "{name} {index} of {count}")?;
                if let Some(line) = line {
                    write!(f, " (line {line})")?;
                }
                Ok(())
            }
        }
    }
}

/// Why a mesh, a frame or a ground-truth file could not be read or written. Every variant names
/// the file; parse errors also name the line (text formats) or the element (binary PLY).
#[derive(Debug, Error)]
pub enum IoError {
    /// The operating system refused to open, read, list or write the file; `source` says why.
    #[error("{path}: cannot {action}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// What was attempted: `open`, `read`, `write`, `list`...
        action: &'static str,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The memory for what the file holds could not be allocated (the system, or an
    /// address-space limit, refused it): the file is larger than the memory left, or its header
    /// declares more than memory holds. Nothing is aborted; the reader stops here.
    #[error("{path}: out of memory reading the {what}: could not allocate {bytes} bytes")]
    OutOfMemory {
        /// The file.
        path: PathBuf,
        /// What was being read (`"vertex positions"`, `"triangles"`, `"line"`...).
        what: &'static str,
        /// The bytes asked for.
        bytes: usize,
    },
    /// A folder was given where a mesh file was expected.
    #[error(
        "{path}: is a folder, not a mesh file (expected a .ply, .obj or .stl file; a folder of \
         frames is a sequence)"
    )]
    Folder {
        /// The folder.
        path: PathBuf,
    },
    /// The file name does not end in a known mesh extension.
    #[error("{path}: unknown mesh format (expected the extension .ply, .obj or .stl)")]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The file does not start with the PLY magic line `ply`.
    #[error("{path}: not a PLY file (it does not start with the line 'ply')")]
    NotPly {
        /// The file.
        path: PathBuf,
    },
    /// The PLY header is malformed (as reported by the PLY parser).
    #[error("{path}: invalid PLY header{}: {message}", line_suffix(*line))]
    PlyHeader {
        /// The file.
        path: PathBuf,
        /// The header line (1-based), when known.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// The PLY header is valid but does not describe a triangle mesh this crate reads: no
    /// `vertex` element, coordinates that are not `float` or `double`, no face index list...
    #[error("{path}: unsupported PLY layout: {message}")]
    PlyLayout {
        /// The file.
        path: PathBuf,
        /// What is missing or unsupported.
        message: String,
    },
    /// The PLY header declares more elements than the file has bytes for: refused right after
    /// the header, before any data is read or allocated (a truncated file, or a corrupt count).
    #[error(
        "{path}: the file has {size} bytes, too few for the {count} {element} elements its \
         header declares (at least {needed} bytes with the header and the elements before them): \
         the file is truncated or its header is wrong"
    )]
    CountsExceedFile {
        /// The file.
        path: PathBuf,
        /// The first element, in the order of the header, that does not fit.
        element: String,
        /// How many of it the header declares.
        count: usize,
        /// The fewest bytes the header and the elements up to this one take (saturated at
        /// `u64::MAX`).
        needed: u64,
        /// The size of the file in bytes.
        size: u64,
    },
    /// The file ended before all the elements its header declares.
    #[error("{path}: file ended in {location}")]
    Truncated {
        /// The file.
        path: PathBuf,
        /// The element (or line) being read when the data ran out.
        location: Location,
    },
    /// A PLY element could not be decoded (a malformed number, a bad list length...).
    #[error("{path}: cannot read {location}: {message}")]
    PlyElement {
        /// The file.
        path: PathBuf,
        /// The element.
        location: Location,
        /// What is wrong.
        message: String,
    },
    /// A face has fewer than three vertices (larger polygons are split into triangles).
    #[error(
        "{path}: {location} has {vertices} vertices, but only triangles and polygons (3 or more \
         vertices) are supported"
    )]
    NotTriangle {
        /// The file.
        path: PathBuf,
        /// The face (PLY) or the line (OBJ).
        location: Location,
        /// How many vertices it has.
        vertices: usize,
    },
    /// A PLY file has vertices but no element that carries triangles (`face` or `tristrips`):
    /// a point cloud, or faces under another name. Refused rather than read as a mesh without
    /// triangles, which would find no contact and look like a clean answer.
    #[error(
        "{path}: {vertices} vertices but no triangles: the file has no 'face' or 'tristrips' \
         element (its elements: {}); topoccd needs a triangle mesh",
        elements.join(", ")
    )]
    NoFaces {
        /// The file.
        path: PathBuf,
        /// The vertex count.
        vertices: usize,
        /// The elements the header declares.
        elements: Vec<String>,
    },
    /// An STL file is malformed: a syntax error in ASCII, or a binary file shorter than its
    /// triangle count says.
    #[error("{path}: triangle {triangle}{}: {message}", line_suffix(*line))]
    Stl {
        /// The file.
        path: PathBuf,
        /// The triangle (facet) where reading stopped, counted from 0.
        triangle: usize,
        /// The line (ASCII), 1-based.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// A face refers to a vertex that does not exist. `index` is the value as written in the
    /// file: 0-based in PLY; in OBJ 1-based, or negative (relative to the vertices before it).
    #[error("{path}: {location}: vertex index {index} is out of range for {vertices} vertices")]
    IndexOutOfRange {
        /// The file.
        path: PathBuf,
        /// The face (PLY) or the line (OBJ).
        location: Location,
        /// The index as written in the file.
        index: i64,
        /// The number of vertices it must address (in OBJ, for a negative index, the number
        /// defined before the face).
        vertices: usize,
    },
    /// An OBJ line could not be parsed.
    #[error("{path}: line {line}: {message}")]
    ObjSyntax {
        /// The file.
        path: PathBuf,
        /// The line, 1-based.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The mesh cannot be written in the requested format (an index too large for the format).
    #[error("{path}: cannot write the mesh: {message}")]
    Unrepresentable {
        /// The file.
        path: PathBuf,
        /// What does not fit.
        message: String,
    },
    /// A JSON file is malformed or does not have the expected shape.
    #[error("{path}: invalid JSON at line {line}")]
    Json {
        /// The file.
        path: PathBuf,
        /// The line (1-based) where the JSON parser stopped.
        line: usize,
        /// The parser's error.
        #[source]
        source: serde_json::Error,
    },
    /// A scene directory does not hold the expected files.
    #[error("{path}: {message}")]
    SceneLayout {
        /// The directory (or file) that is not as expected.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A candidate-pair file and its ground-truth file list different numbers of entries.
    #[error("{pairs_path} lists {pairs} pairs but {bools_path} has {bools} ground-truth values")]
    CountMismatch {
        /// The candidate-pair file.
        pairs_path: PathBuf,
        /// Its number of pairs.
        pairs: usize,
        /// The ground-truth file.
        bools_path: PathBuf,
        /// Its number of values.
        bools: usize,
    },
    /// A candidate pair names ids that do not fit the scene (out of range, or the wrong kind of
    /// feature for the file).
    #[error("{path}: pair {pair} (0-based) {ids:?}: {message}")]
    BadPair {
        /// The candidate-pair file.
        path: PathBuf,
        /// Index of the pair in the file's list, 0-based.
        pair: usize,
        /// The two ids as written.
        ids: [u64; 2],
        /// What is wrong.
        message: String,
    },
}

fn line_suffix(line: Option<usize>) -> String {
    line.map(|l| format!(" at line {l}")).unwrap_or_default()
}

impl IoError {
    /// An [`IoError::OutOfMemory`] for `path`.
    pub(crate) fn memory(path: &std::path::Path, e: crate::alloc::AllocError) -> Self {
        IoError::OutOfMemory {
            path: path.to_path_buf(),
            what: e.what,
            bytes: e.bytes,
        }
    }

    /// An [`IoError::Io`] for `path`.
    pub(crate) fn os(path: &std::path::Path, action: &'static str, source: std::io::Error) -> Self {
        IoError::Io {
            path: path.to_path_buf(),
            action,
            source,
        }
    }
}
