//! Contacts to show: reading a pairs file, and the triangles a list of contacts involves.
//!
//! A pairs file has one contact per line, fields separated by commas (spaces around them
//! ignored); empty lines and lines starting with `#` are skipped:
//!
//! ```text
//! vf,VERTEX,FACE,TOI
//! ee,A0,A1,B0,B1,TOI
//! ```
//!
//! Vertex and face numbers are 0-based, as in the step's mesh; `TOI` is in `[0, 1]`.

use std::fmt;
use std::path::{Path, PathBuf};

use topoccd::mesh::Topology;

/// One contact of a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Contact {
    /// A vertex touches a face.
    VertexFace {
        /// The vertex.
        vertex: u32,
        /// The face (triangle number).
        face: u32,
        /// Time of impact, in `[0, 1]`.
        toi: f64,
    },
    /// Edge `a` (its two vertices) touches edge `b`.
    EdgeEdge {
        /// First edge.
        a: [u32; 2],
        /// Second edge.
        b: [u32; 2],
        /// Time of impact, in `[0, 1]`.
        toi: f64,
    },
}

/// A pairs file that could not be read, with the file and (for its content) the line.
#[derive(Debug)]
pub struct PairsError {
    /// The pairs file.
    pub path: PathBuf,
    /// 1-based line number, or `None` when the file could not be read at all.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for PairsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{line}: {}", self.path.display(), self.message),
            None => write!(f, "{}: {}", self.path.display(), self.message),
        }
    }
}

impl std::error::Error for PairsError {}

/// Reads a pairs file (see the [module documentation](self)) for a step of `vertices` vertices
/// and `faces` triangles; every number must be in range.
pub fn read_pairs(path: &Path, vertices: usize, faces: usize) -> Result<Vec<Contact>, PairsError> {
    let text = std::fs::read_to_string(path).map_err(|e| PairsError {
        path: path.to_path_buf(),
        line: None,
        message: e.to_string(),
    })?;
    parse_pairs(&text, path, vertices, faces)
}

/// Parses the text of a pairs file; `path` only names it in errors.
pub fn parse_pairs(
    text: &str,
    path: &Path,
    vertices: usize,
    faces: usize,
) -> Result<Vec<Contact>, PairsError> {
    let mut contacts = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let contact = parse_line(line, vertices, faces).map_err(|message| PairsError {
            path: path.to_path_buf(),
            line: Some(k + 1),
            message,
        })?;
        contacts.push(contact);
    }
    Ok(contacts)
}

fn parse_line(line: &str, vertices: usize, faces: usize) -> Result<Contact, String> {
    let fields: Vec<&str> = line.split(',').map(str::trim).collect();
    let index = |k: usize, what: &str, limit: usize| -> Result<u32, String> {
        let value: u32 = fields[k]
            .parse()
            .map_err(|_| format!("{what} '{}' is not a non-negative integer", fields[k]))?;
        if value as usize >= limit {
            return Err(format!(
                "{what} {value} is out of range (the step has {limit})"
            ));
        }
        Ok(value)
    };
    let toi = |k: usize| -> Result<f64, String> {
        match fields[k].parse::<f64>() {
            Ok(t) if (0.0..=1.0).contains(&t) => Ok(t),
            _ => Err(format!("TOI '{}' is not a number in [0, 1]", fields[k])),
        }
    };
    match (fields[0], fields.len()) {
        // (6 fields: `topoccd step --pairs` adds the face of the file and the sub-triangle
        // when polygons were split; the picture uses the step's triangle, field 2.)
        ("vf", 4 | 6) => Ok(Contact::VertexFace {
            vertex: index(1, "vertex", vertices)?,
            face: index(2, "face", faces)?,
            toi: toi(3)?,
        }),
        ("ee", 6) => {
            let a = [index(1, "vertex", vertices)?, index(2, "vertex", vertices)?];
            let b = [index(3, "vertex", vertices)?, index(4, "vertex", vertices)?];
            if a[0] == a[1] || b[0] == b[1] {
                return Err("an edge joins a vertex to itself".into());
            }
            Ok(Contact::EdgeEdge { a, b, toi: toi(5)? })
        }
        ("vf", n) => Err(format!(
            "expected vf,VERTEX,FACE,TOI (4 fields, or 6 with FILE_FACE,SUB), got {n} fields"
        )),
        ("ee", n) => Err(format!(
            "expected ee,A0,A1,B0,B1,TOI (6 fields), got {n} fields"
        )),
        (kind, _) => Err(format!("unknown contact kind '{kind}' (expected vf or ee)")),
    }
}

/// Marks the triangles involved in `contacts` among the `faces` triangles of `topo`: for a
/// vertex-face contact the face and every triangle containing the vertex, for an edge-edge
/// contact every triangle containing either edge. Numbers out of range mark nothing.
pub fn contact_triangles(contacts: &[Contact], topo: &Topology, faces: usize) -> Vec<bool> {
    let mut marked = vec![false; faces];
    let vertex_count = topo.vertex_offsets.len().saturating_sub(1);
    let mut mark = |t: u32| {
        if let Some(m) = marked.get_mut(t as usize) {
            *m = true;
        }
    };
    let triangles_of = |v: u32| {
        if (v as usize) < vertex_count {
            topo.triangles_of(v)
        } else {
            &[]
        }
    };
    for contact in contacts {
        match *contact {
            Contact::VertexFace { vertex, face, .. } => {
                mark(face);
                triangles_of(vertex).iter().for_each(|&t| mark(t));
            }
            Contact::EdgeEdge { a, b, .. } => {
                for [v0, v1] in [a, b] {
                    // Triangles of v0 that also contain v1 (both lists are sorted).
                    let others = triangles_of(v1);
                    for &t in triangles_of(v0) {
                        if others.binary_search(&t).is_ok() {
                            mark(t);
                        }
                    }
                }
            }
        }
    }
    marked
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Vec<Contact>, PairsError> {
        parse_pairs(text, Path::new("p.csv"), 5, 3)
    }

    fn error(text: &str) -> String {
        parse(text).unwrap_err().to_string()
    }

    #[test]
    fn reads_both_kinds_with_comments_and_spaces() {
        let c = parse("# header\n\nvf,4,2,0.5\n ee , 0, 1 ,2,3, 1\n").unwrap();
        assert_eq!(
            c,
            vec![
                Contact::VertexFace {
                    vertex: 4,
                    face: 2,
                    toi: 0.5
                },
                Contact::EdgeEdge {
                    a: [0, 1],
                    b: [2, 3],
                    toi: 1.0
                }
            ]
        );
    }

    #[test]
    fn errors_name_the_file_and_line() {
        assert_eq!(
            error("vf,0,0,0\nvf,1,2\n"),
            "p.csv:2: expected vf,VERTEX,FACE,TOI (4 fields, or 6 with FILE_FACE,SUB), got 3 fields"
        );
        assert_eq!(
            error("ee,0,1,2,3,4,0.1"),
            "p.csv:1: expected ee,A0,A1,B0,B1,TOI (6 fields), got 7 fields"
        );
        assert_eq!(
            error("fv,0,0,0"),
            "p.csv:1: unknown contact kind 'fv' (expected vf or ee)"
        );
        assert_eq!(
            error("vf,5,0,0"),
            "p.csv:1: vertex 5 is out of range (the step has 5)"
        );
        assert_eq!(
            error("vf,0,3,0"),
            "p.csv:1: face 3 is out of range (the step has 3)"
        );
        assert_eq!(
            error("vf,-1,0,0"),
            "p.csv:1: vertex '-1' is not a non-negative integer"
        );
        assert_eq!(
            error("vf,0,0,1.5"),
            "p.csv:1: TOI '1.5' is not a number in [0, 1]"
        );
        assert_eq!(
            error("vf,0,0,NaN"),
            "p.csv:1: TOI 'NaN' is not a number in [0, 1]"
        );
        assert_eq!(
            error("ee,1,1,2,3,0"),
            "p.csv:1: an edge joins a vertex to itself"
        );
        let missing = read_pairs(Path::new("/nonexistent/pairs.csv"), 1, 1).unwrap_err();
        assert!(missing.to_string().starts_with("/nonexistent/pairs.csv: "));
    }

    #[test]
    fn marks_the_triangles_around_each_contact() {
        // A strip of four triangles: 0 = (0,1,2), 1 = (1,3,2), 2 = (2,3,4), 3 = (3,5,4).
        let tris = [[0, 1, 2], [1, 3, 2], [2, 3, 4], [3, 5, 4]];
        let topo = Topology::new(&tris, 6);
        let vf = Contact::VertexFace {
            vertex: 0,
            face: 3,
            toi: 0.0,
        };
        assert_eq!(
            contact_triangles(&[vf], &topo, 4),
            [true, false, false, true]
        );
        let ee = Contact::EdgeEdge {
            a: [3, 2],
            b: [5, 4],
            toi: 0.0,
        };
        assert_eq!(
            contact_triangles(&[ee], &topo, 4),
            [false, true, true, true]
        );
        // Not an edge of the mesh (0 and 3 share no triangle), and out of range: nothing.
        let none = Contact::EdgeEdge {
            a: [0, 3],
            b: [9, 10],
            toi: 0.0,
        };
        assert_eq!(contact_triangles(&[none], &topo, 4), [false; 4]);
        assert_eq!(contact_triangles(&[], &topo, 4), [false; 4]);
    }
}
