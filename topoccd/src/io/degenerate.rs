//! Input that is valid but likely a mistake, found before a query runs so that a front end
//! (the command line, the Python package) can warn while there is still time to stop: vertices
//! that sit exactly on one another, triangles of zero area, and positions that are all whole
//! numbers on a mesh that collapsed (a cast to integers). One implementation, shared by every
//! front end, so they warn alike.

use super::coincident_vertices;

/// How many ids a warning names.
const SHOWN: usize = 6;

/// Something about a step's input that is valid but likely a mistake ([`input_warnings`]). Its
/// `Display` names how many elements, the first few, and the likely cause.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum InputWarning {
    /// Vertices used by the triangles sit exactly on another vertex: they touch from the
    /// start, and every feature around one is in contact with the other at t=0.
    CoincidentVertices {
        /// Vertices that sit on an earlier one (the size of each group less one, summed).
        duplicates: usize,
        /// Groups of vertices at one position.
        groups: usize,
        /// The first ids of the largest group (the first such group), at most six.
        largest: Vec<u32>,
        /// How many vertices the largest group holds.
        largest_size: usize,
    },
    /// Triangles whose three corners are collinear or coincide: they have no normal, and
    /// their features are tested as degenerate ones (slowly, and reported conservatively).
    ZeroAreaTriangles {
        /// How many.
        count: usize,
        /// The first of them, at most six.
        first: Vec<u32>,
    },
    /// Every coordinate is a whole number and the mesh is degenerate (vertices coincide or
    /// triangles have no area): most likely positions cast to integers, which truncates the
    /// fractions and collapses the mesh onto a few lattice points.
    IntegralCoordinates {
        /// Vertices used by the triangles (all of them with whole coordinates).
        vertices: usize,
    },
}

/// `a, b, c` with `, ...` when there are more than shown.
fn ids(shown: &[u32], total: usize) -> String {
    let text: Vec<String> = shown.iter().map(u32::to_string).collect();
    let more = if total > shown.len() { ", ..." } else { "" };
    format!("{}{more}", text.join(", "))
}

impl std::fmt::Display for InputWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            InputWarning::CoincidentVertices {
                duplicates,
                groups,
                largest,
                largest_size,
            } => write!(
                f,
                "{duplicates} vertices sit exactly on another vertex ({groups} groups; the \
                 largest has {largest_size} vertices: {}); duplicates touch from the start and \
                 give spurious contacts at t=0",
                ids(largest, *largest_size)
            ),
            InputWarning::ZeroAreaTriangles { count, first } => write!(
                f,
                "{count} triangles have zero area (triangles {}): their corners coincide or lie \
                 on a line, so they have no normal and are tested slowly, as degenerate \
                 features (a collapsed or badly triangulated mesh)",
                ids(first, *count)
            ),
            InputWarning::IntegralCoordinates { vertices } => write!(
                f,
                "every coordinate of the {vertices} vertices is a whole number and the mesh is \
                 degenerate: positions cast to integers (x.astype(int)) lose their fractions \
                 and collapse onto a few points, where nearly every pair of features touches \
                 at t=0; pass the floating-point positions"
            ),
        }
    }
}

/// The warnings for a mesh at one instant: its `positions` and the `triangles` using them
/// (vertices no triangle uses are not looked at; indices out of range are ignored). Linear in
/// the size of the mesh (a hash of the positions).
///
/// ```
/// use topoccd::io::{input_warnings, InputWarning};
/// // A cloth cast to integers: its vertices collapse onto two points.
/// let positions = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
/// let triangles = [[0, 1, 2], [1, 3, 2]];
/// let warnings = input_warnings(&positions, &triangles);
/// assert_eq!(warnings.len(), 3);
/// assert!(matches!(warnings[0], InputWarning::CoincidentVertices { duplicates: 2, .. }));
/// assert!(warnings[2].to_string().contains("cast to integers"));
/// // A proper unit triangle with integer corners gets none.
/// assert!(input_warnings(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[[0, 1, 2]]).is_empty());
/// ```
pub fn input_warnings(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<InputWarning> {
    let mut out = Vec::new();
    let groups = coincident_vertices(positions, triangles);
    if let Some(largest) = groups.iter().rev().max_by_key(|g| g.len()) {
        // (`rev` then `max_by_key`: the first of the largest groups.)
        out.push(InputWarning::CoincidentVertices {
            duplicates: groups.iter().map(|g| g.len() - 1).sum(),
            groups: groups.len(),
            largest: largest.iter().take(SHOWN).copied().collect(),
            largest_size: largest.len(),
        });
    }
    let at = |v: u32| positions.get(v as usize).copied();
    let mut flat = Vec::new();
    let mut flat_count = 0;
    for (t, tri) in triangles.iter().enumerate() {
        let (Some(a), Some(b), Some(c)) = (at(tri[0]), at(tri[1]), at(tri[2])) else {
            continue;
        };
        let (u, v) = (sub(b, a), sub(c, a));
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        if n == [0.0; 3] {
            flat_count += 1;
            if flat.len() < SHOWN {
                flat.push(t as u32);
            }
        }
    }
    if flat_count > 0 {
        out.push(InputWarning::ZeroAreaTriangles {
            count: flat_count,
            first: flat,
        });
    }
    if !out.is_empty() {
        let mut used = vec![false; positions.len()];
        for &v in triangles.iter().flatten() {
            if let Some(u) = used.get_mut(v as usize) {
                *u = true;
            }
        }
        let used: Vec<&[f64; 3]> = (positions.iter().zip(&used))
            .filter_map(|(p, &u)| u.then_some(p))
            .collect();
        let whole = |x: f64| x.is_finite() && x.fract() == 0.0;
        if !used.is_empty() && used.iter().all(|p| p.iter().all(|&x| whole(x))) {
            out.push(InputWarning::IntegralCoordinates {
                vertices: used.len(),
            });
        }
    }
    out
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
