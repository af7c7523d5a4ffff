//! Proximity: at one configuration, every primitive pair closer than a distance `dhat` (plus
//! an offset `dmin`), with its distance and closest-feature type, for the barrier or repulsion
//! forces of a contact solver (the IPC toolkit's `Candidates` kept where the distance is
//! below `dhat`).
//!
//! - [`Configuration`]: positions, triangles, free edges (free points are the vertices in no
//!   triangle and no edge), with the pair filter's groups and `can_collide`;
//! - [`ProximityOptions`]: `dhat`, `dmin`, `max_contacts`, `deadline`, the method;
//! - [`Ccd::proximity`](crate::Ccd::proximity) (the hierarchy kept and refitted across a
//!   solver's iterations) and the one-shot [`proximity`];
//! - [`ProximityReport`]: `vf`, `ee`, `ve`, `vv`, each sorted by its indices.
//!
//! Inside: `primitives` (leaves and feature ownership) → `tree` (a hierarchy over the leaves'
//! boxes inflated by half the threshold) → `pairs` (the feature pairs of a leaf pair and the
//! distance test, with the [`distance`](crate::distance) kernels) → `run`; `brute` is the
//! oracle (every pair, no tree). The CCD's hierarchy holds swept volumes of triangles only;
//! this one holds static boxes of every primitive kind, so the two are separate trees in one
//! [`Ccd`](crate::Ccd).
//!
//! **Rounding.** A pair is kept when its computed distance is below `dhat + dmin + eps`,
//! `eps` the bound of [`rounding_bound`](crate::distance::rounding_bound) for the pair (about
//! `1.2e-14` times the pair's extent, its largest coordinate difference; more for nearly
//! parallel edges). So no pair closer than `dhat + dmin` is missed, and a pair reported is
//! closer than `dhat + dmin + 2 eps`.

mod boxes;
mod brute;
mod cache;
mod features;
#[cfg(feature = "internals")]
pub mod floor;
mod input;
mod options;
mod pairs;
mod primitives;
mod report;
mod run;
mod slots;
mod tree;

pub use input::{Configuration, ProximityError};
pub use options::{ProximityMethod, ProximityOptions};
pub use report::{
    EeProximity, ProximityReport, ProximityStats, VeProximity, VfProximity, VvProximity,
};
pub use run::proximity;
pub(crate) use run::State;

#[cfg(test)]
mod tests;
