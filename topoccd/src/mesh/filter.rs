//! Which feature pairs may collide at all: the pair filter that every broad phase applies
//! before a pair becomes a candidate, so that all methods report the same pairs.
//!
//! A pair is dropped when
//! 1. the two features share a vertex (always);
//! 2. with the crack filter on and a topology change in the step, they share a vertex once
//!    every new vertex is identified with its parent ([`Step::with_parents`]): the two sides of
//!    a fresh crack start at the same place and would otherwise all "touch" at t=0;
//! 3. with group ids, every vertex of one feature is in the group of every vertex of the other;
//! 4. with a user predicate, it is false for every vertex of one feature against every vertex
//!    of the other;
//! 5. the features' owner triangles (see `features`) share no vertex and stay farther apart
//!    than the minimum separation along the direction between their mean points, over the
//!    times searched `[0, tmax]` ([`PairFilter::unshared_apart`]). Each feature lies in its
//!    owner, so no pair of their features can come that close either: the rule drops no
//!    contact, and it drops at once every pair of two triangles that merely pass near each
//!    other, before their features are looked at;
//! 6. without a minimum separation, the owner triangles share a vertex whose star (its
//!    incident triangles) is certified free of self-contact over the step (`star`): every
//!    feature of either lies in that star, so no pair of them can touch. Most overlapping
//!    triangle pairs of a mesh are neighbours whose feature pairs come close without touching;
//!    the rule drops them all at once.
//!
//! Rules 3 and 4 follow the IPC toolkit's `can_collide`: a pair is kept when *some* vertex
//! pair across the features may collide.

use super::star::StarView;
use super::Step;
use crate::math::{max_abs, DVec3};
use crate::narrow::prefilter::triangles_separated;

/// The pair filter of one query. Cheap to build: the parent map is written into a buffer the
/// caller keeps across steps.
pub(crate) struct PairFilter<'s> {
    /// Minimum separation (`>= 0`): feature boxes farther apart than this are not candidates.
    pub sep: f64,
    /// Rule 5: the end of the times searched, the positions at t=0 and t=1, and the largest
    /// absolute coordinate among them.
    tmax: f64,
    positions: (&'s [DVec3], &'s [DVec3]),
    coord: f64,
    /// Each vertex's representative (its parent for a new vertex of the step, else itself);
    /// `None` when no vertex has a parent or the crack filter is off.
    canon: Option<&'s [u32]>,
    /// Rule 6: the step's vertex stars; `None` with a minimum separation.
    stars: Option<StarView<'s>>,
    groups: Option<&'s [u32]>,
    can_collide: Option<super::step::CanCollide<'s>>,
}

/// Which corners two triangles share: bit `3 i + j` is set when `a[i] == b[j]`.
#[inline]
pub(crate) fn shared_corners(a: [u32; 3], b: [u32; 3]) -> usize {
    let mut equal = 0;
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            equal |= usize::from(x == y) << (3 * i + j);
        }
    }
    equal
}

impl<'s> PairFilter<'s> {
    /// The filter of `step`; `canon` is scratch memory for the parent map, `stars` the
    /// certified stars of rule 6 (ignored with a minimum separation).
    pub fn new(
        step: &'s Step<'_>,
        sep: f64,
        tmax: f64,
        crack_filter: bool,
        canon: &'s mut Vec<u32>,
        stars: Option<StarView<'s>>,
    ) -> Self {
        let parents = step.parents();
        let canon = if crack_filter && !parents.is_empty() {
            canon.clear();
            canon.extend(0..step.vertex_count() as u32);
            for &[child, parent] in parents {
                canon[child as usize] = parent;
            }
            Some(&canon[..])
        } else {
            None
        };
        Self {
            sep,
            tmax,
            positions: (step.pos0(), step.pos1()),
            coord: (step.pos0().iter().chain(step.pos1())).fold(0.0, |m, &p| m.max(max_abs(p))),
            canon,
            stars: stars.filter(|_| sep == 0.0),
            groups: step.groups(),
            can_collide: step.can_collide(),
        }
    }

    /// The end of the times searched.
    #[inline]
    pub fn tmax(&self) -> f64 {
        self.tmax
    }

    /// The largest absolute coordinate of the step's positions at t=0 and t=1.
    #[inline]
    pub fn coord(&self) -> f64 {
        self.coord
    }

    /// `true` when only shared vertices are filtered (the common case, checked once per pair).
    #[inline]
    fn only_shared(&self) -> bool {
        self.canon.is_none() && self.groups.is_none() && self.can_collide.is_none()
    }

    /// Whether vertex `v` and the face with vertices `f` may collide. `v` not in `f` is
    /// checked by the caller.
    #[inline]
    pub fn vertex_face(&self, v: u32, f: [u32; 3]) -> bool {
        self.only_shared() || self.check(&[v], &f)
    }

    /// Whether two edges that share no vertex may collide.
    #[inline]
    pub fn edge_edge(&self, a: [u32; 2], b: [u32; 2]) -> bool {
        self.only_shared() || self.check(&a, &b)
    }

    /// Rules 5 and 6: whether no feature of the triangle with corners `a` is a candidate
    /// against a feature of the triangle with corners `b`, because they share no vertex and
    /// stay apart along the direction between their mean points during `[0, tmax]`, or share
    /// a vertex whose star is certified.
    #[inline]
    pub fn owners_dropped(&self, a: [u32; 3], b: [u32; 3]) -> bool {
        let equal = shared_corners(a, b);
        if equal == 0 {
            self.unshared_apart(a, b)
        } else {
            self.shared_star(a, equal)
        }
    }

    /// Rule 6 for triangles `a` and `b` that share the vertices given by `equal`
    /// ([`shared_corners`]): whether one of them has a certified star.
    #[inline]
    pub fn shared_star(&self, a: [u32; 3], equal: usize) -> bool {
        let Some(stars) = self.stars else {
            return false;
        };
        (0..3).any(|i| equal >> (3 * i) & 7 != 0 && stars.certified(a[i]))
    }

    /// Rule 5 for triangles known to share no vertex: whether they stay apart along the
    /// direction between their mean points during `[0, tmax]`.
    #[inline]
    pub fn unshared_apart(&self, a: [u32; 3], b: [u32; 3]) -> bool {
        triangles_separated(self.positions, a, b, self.sep, self.tmax, self.coord)
    }

    fn check(&self, a: &[u32], b: &[u32]) -> bool {
        if let Some(canon) = self.canon {
            let c = |v: u32| canon[v as usize];
            if a.iter().any(|&x| b.iter().any(|&y| c(x) == c(y))) {
                return false;
            }
        }
        if let Some(groups) = self.groups {
            let g = |v: u32| groups[v as usize];
            if !a.iter().any(|&x| b.iter().any(|&y| g(x) != g(y))) {
                return false;
            }
        }
        if let Some(can) = self.can_collide {
            if !a.iter().any(|&x| b.iter().any(|&y| can(x, y))) {
                return false;
            }
        }
        true
    }
}
