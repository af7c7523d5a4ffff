//! What a file holds besides its triangles, by one rule that every reader and command uses:
//! its free edges (rods, hair) and its free points (particles).
//!
//! The rule is the IPC toolkit's: a vertex in no triangle and no edge (a *loose* vertex) is a
//! free point, whether or not the file has edges. A file whose loose vertices are leftovers
//! (vertices a modelling tool kept after deleting their faces) says otherwise with
//! [`LooseVertices::Ignore`]; its free edges stay.

use std::fmt;
use std::str::FromStr;

use crate::mesh::{Step, StepError};

use super::Mesh;

/// What the loose vertices of a file are: vertices in no triangle and no edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LooseVertices {
    /// Free points (particles), tested against every face, free edge and other free point:
    /// the IPC toolkit's rule, the default.
    #[default]
    Points,
    /// Leftovers, in no pair at all.
    Ignore,
}

impl LooseVertices {
    /// The names [`FromStr`] takes and [`Display`](fmt::Display) gives.
    pub const NAMES: [&'static str; 2] = ["points", "ignore"];

    /// Whether loose vertices are free points.
    pub fn are_points(self) -> bool {
        self == LooseVertices::Points
    }
}

impl fmt::Display for LooseVertices {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            LooseVertices::Points => "points",
            LooseVertices::Ignore => "ignore",
        })
    }
}

/// A name other than `points` and `ignore`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("loose vertices are `points` or `ignore`, not `{0}`")]
pub struct UnknownLooseVertices(pub String);

impl FromStr for LooseVertices {
    type Err = UnknownLooseVertices;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "points" => Ok(LooseVertices::Points),
            "ignore" => Ok(LooseVertices::Ignore),
            other => Err(UnknownLooseVertices(other.to_string())),
        }
    }
}

/// The loose vertices of a mesh of `vertex_count` vertices: those in no triangle and no edge,
/// increasing. Indices out of range are skipped (the step's checks name them).
///
/// ```
/// use topoccd::io::loose_vertices;
/// // A triangle, a rod 3-4 and two particles, 5 and 6.
/// assert_eq!(loose_vertices(7, &[[0, 1, 2]], &[[3, 4]]), vec![5, 6]);
/// ```
pub fn loose_vertices(vertex_count: usize, triangles: &[[u32; 3]], edges: &[[u32; 2]]) -> Vec<u32> {
    let mut used = vec![false; vertex_count];
    let corners = triangles.iter().flatten().chain(edges.iter().flatten());
    for &v in corners {
        if let Some(u) = used.get_mut(v as usize) {
            *u = true;
        }
    }
    (0..vertex_count as u32)
        .filter(|&v| !used[v as usize])
        .collect()
}

impl Mesh {
    /// The mesh's loose vertices (see [`loose_vertices`]).
    pub fn loose_vertices(&self) -> Vec<u32> {
        loose_vertices(self.positions.len(), &self.triangles, &self.edges)
    }
}

/// `step` with what a file holds besides its triangles: its free `edges` ([`Mesh::edges`] of
/// the step's second frame) and, as `loose` says, its loose vertices as free points. The one
/// rule of every reader: the CLI's commands, [`sequence`](super::sequence), the Python and C
/// readers.
///
/// A step with neither free edges nor free points is left a triangle mesh.
///
/// ```
/// use topoccd::io::{with_file_primitives, LooseVertices};
/// use topoccd::Step;
/// // Particles only, no edge in the file: they are free points all the same.
/// let x = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.2, 1.0]];
/// let step = Step::new(x.clone(), x.clone(), vec![[0u32, 1, 2]])?;
/// let step = with_file_primitives(step, &[], LooseVertices::Points)?;
/// assert_eq!(step.edges(), Some(&[][..]));
/// let step = Step::new(x.clone(), x, vec![[0u32, 1, 2]])?;
/// let step = with_file_primitives(step, &[], LooseVertices::Ignore)?;
/// assert_eq!(step.edges(), None);
/// # Ok::<(), topoccd::StepError>(())
/// ```
pub fn with_file_primitives(
    step: Step<'static>,
    edges: &[[u32; 2]],
    loose: LooseVertices,
) -> Result<Step<'static>, StepError> {
    let points = loose.are_points()
        && !loose_vertices(step.vertex_count(), step.triangles(), edges).is_empty();
    if edges.is_empty() && !points {
        return Ok(step);
    }
    Ok(step
        .with_edges_owned(edges.to_vec())?
        .with_free_points(loose.are_points()))
}

/// The primitives a step or a configuration holds besides its triangles: its free edges (in
/// no triangle, each once, `[i, j]` with `i < j`, sorted) and its free points (increasing).
/// Every command reports them (`--json`), so that one file can be seen to give every reader
/// the same primitives.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FilePrimitives {
    /// The triangles.
    pub triangles: usize,
    /// The free edges.
    pub free_edges: Vec<[u32; 2]>,
    /// The free points.
    pub free_points: Vec<u32>,
}

impl FilePrimitives {
    /// The primitives of a mesh of `vertex_count` vertices with these `triangles` and file
    /// `edges`, its loose vertices read as `loose` says.
    ///
    /// ```
    /// use topoccd::io::{FilePrimitives, LooseVertices};
    /// // A triangle whose side 1-2 the file lists as an edge too, a rod 4-3, a particle 5.
    /// let p = FilePrimitives::new(6, &[[0, 1, 2]], &[[2, 1], [4, 3]], LooseVertices::Points);
    /// assert_eq!((p.free_edges, p.free_points), (vec![[3, 4]], vec![5]));
    /// let p = FilePrimitives::new(6, &[[0, 1, 2]], &[[4, 3]], LooseVertices::Ignore);
    /// assert!(p.free_points.is_empty());
    /// ```
    pub fn new(
        vertex_count: usize,
        triangles: &[[u32; 3]],
        edges: &[[u32; 2]],
        loose: LooseVertices,
    ) -> Self {
        let mut sides: Vec<[u32; 2]> = triangles
            .iter()
            .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
            .map(|[i, j]| [i.min(j), i.max(j)])
            .collect();
        sides.sort_unstable();
        sides.dedup();
        let mut free_edges: Vec<[u32; 2]> = edges
            .iter()
            .map(|&[i, j]| [i.min(j), i.max(j)])
            .filter(|e| sides.binary_search(e).is_err())
            .collect();
        free_edges.sort_unstable();
        free_edges.dedup();
        let free_points = if loose.are_points() {
            loose_vertices(vertex_count, triangles, edges)
        } else {
            Vec::new()
        };
        Self {
            triangles: triangles.len(),
            free_edges,
            free_points,
        }
    }

    /// The primitives that `step` is queried with: none besides its triangles without edges
    /// set, else its free edges and (unless [`Step::free_points`] is off) its loose vertices.
    pub fn of_step(step: &Step<'_>) -> Self {
        match step.edges() {
            None => Self {
                triangles: step.triangles().len(),
                ..Self::default()
            },
            Some(edges) => Self::new(
                step.vertex_count(),
                step.triangles(),
                edges,
                if step.free_points() {
                    LooseVertices::Points
                } else {
                    LooseVertices::Ignore
                },
            ),
        }
    }

    /// The primitives a proximity query sees in `config`.
    pub fn of_configuration(config: &crate::Configuration<'_>) -> Self {
        let loose = if config.free_points() {
            LooseVertices::Points
        } else {
            LooseVertices::Ignore
        };
        Self::new(
            config.vertex_count(),
            config.triangles(),
            config.edges(),
            loose,
        )
    }

    /// The primitives of `mesh` (a file read), its loose vertices read as `loose` says: the
    /// same as [`FilePrimitives::of_step`] of the step [`with_file_primitives`] builds.
    pub fn of_mesh(mesh: &Mesh, loose: LooseVertices) -> Self {
        Self::new(mesh.positions.len(), &mesh.triangles, &mesh.edges, loose)
    }
}
