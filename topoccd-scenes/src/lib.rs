//! Seeded scene generators used by the tests, the benchmarks and the command line.
//!
//! Each returns one [`Step`] (positions at t=0 and t=1 and the triangles) built from a size
//! parameter and a seed; the same arguments give the same step on every machine (the random
//! numbers come from [`ChaCha8Rng`](rand_chacha::ChaCha8Rng)). Every scene is made to collide:
//!
//! - [`crumpled_sheet`]: a square sheet whose smooth random displacement folds it onto itself;
//! - [`folded_sheet`]: a sheet whose right half folds over and through its left half;
//! - [`small_objects`]: small closed meshes (icospheres and cubes) moving into each other;
//! - [`torn_sheet`]: a sheet torn into disconnected strips (vertices duplicated along the cuts)
//!   that slide across and through each other.
//!
//! ```
//! use topoccd_scenes::{self as scene, SceneKind};
//! let step = scene::crumpled_sheet(16, 7);
//! assert_eq!(step.vertex_count(), 16 * 16);
//! assert_eq!(step.triangles().len(), 2 * 15 * 15);
//! let same = SceneKind::CrumpledSheet.generate(16, 7);
//! assert_eq!(same.x1(), step.x1());
//! ```

pub mod codim;
mod objects;
pub mod paper;
mod sheets;

pub use objects::small_objects;
pub use sheets::{crumpled_sheet, folded_sheet, torn_sheet};

use glam::DVec3;
use topoccd::Step;

/// The scene generators, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SceneKind {
    /// [`crumpled_sheet`].
    CrumpledSheet,
    /// [`folded_sheet`].
    FoldedSheet,
    /// [`small_objects`].
    SmallObjects,
    /// [`torn_sheet`].
    TornSheet,
}

impl SceneKind {
    /// All kinds.
    pub const ALL: [SceneKind; 4] = [
        SceneKind::CrumpledSheet,
        SceneKind::FoldedSheet,
        SceneKind::SmallObjects,
        SceneKind::TornSheet,
    ];

    /// The kind's name: `crumpled`, `folded`, `objects` or `torn`.
    pub fn name(self) -> &'static str {
        match self {
            SceneKind::CrumpledSheet => "crumpled",
            SceneKind::FoldedSheet => "folded",
            SceneKind::SmallObjects => "objects",
            SceneKind::TornSheet => "torn",
        }
    }

    /// The kind named `name` (see [`SceneKind::name`]).
    ///
    /// ```
    /// use topoccd_scenes::SceneKind;
    /// assert_eq!(SceneKind::from_name("torn"), Some(SceneKind::TornSheet));
    /// ```
    pub fn from_name(name: &str) -> Option<Self> {
        SceneKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Generates the scene: `size` is the sheet's vertices per side (for the sheets) or the
    /// number of objects (for [`small_objects`]); see each generator.
    pub fn generate(self, size: usize, seed: u64) -> Step<'static> {
        match self {
            SceneKind::CrumpledSheet => crumpled_sheet(size, seed),
            SceneKind::FoldedSheet => folded_sheet(size, seed),
            SceneKind::SmallObjects => small_objects(size, seed),
            SceneKind::TornSheet => torn_sheet(size, seed),
        }
    }
}

/// Assembles a step from generated data, which is valid by construction.
fn assemble(x0: Vec<DVec3>, x1: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Step<'static> {
    match Step::new(x0, x1, triangles) {
        Ok(step) => step,
        Err(e) => unreachable!("a generated scene is valid: {e}"),
    }
}

/// The triangles of a regular grid of `nx * ny` vertices numbered `offset + i * ny + j`
/// (column `i`, row `j`), two per cell.
fn grid_triangles(nx: usize, ny: usize, offset: u32, out: &mut Vec<[u32; 3]>) {
    let id = |i: usize, j: usize| offset + (i * ny + j) as u32;
    for i in 0..nx.saturating_sub(1) {
        for j in 0..ny.saturating_sub(1) {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            // Alternate the diagonal so the sheet has no preferred direction.
            if (i + j) % 2 == 0 {
                out.push([a, b, c]);
                out.push([a, c, d]);
            } else {
                out.push([a, b, d]);
                out.push([b, c, d]);
            }
        }
    }
}

/// A random unit vector, uniform on the sphere (rejection sampling in the unit ball).
pub(crate) fn random_unit(rng: &mut rand_chacha::ChaCha8Rng) -> glam::DVec3 {
    use rand::Rng;
    loop {
        let p = glam::DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let len = p.length();
        if len > 0.1 && len <= 1.0 {
            return p / len;
        }
    }
}
