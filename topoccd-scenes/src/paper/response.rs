//! The collision response of the generators, driven by topoccd's own query.
//!
//! After each proposed step the generator runs [`Ccd::query`](topoccd::Ccd::query) in
//! [`Mode::All`](topoccd::Mode::All) on it and keeps the step as proposed (so the stored
//! step contains its contacts), then changes the motion of the *following* steps:
//!
//! - every soft vertex of a colliding feature is pinned: it stops for good (a sticky contact),
//!   so a soft surface enters another by at most one step's motion and no further;
//! - a rigid piece receives, per colliding pair of pieces, an impulse with restitution
//!   [`RESTITUTION`] along the contact normal at the pair's earliest contact (static and soft
//!   pieces count as infinitely heavy), resolved by a few Gauss-Seidel sweeps so that no pair
//!   still approaches; the pieces then move apart and the penetration shrinks;
//! - an impact on a breakable static piece faster than [`World::break_speed`] does not
//!   bounce: it is returned as a [`Break`] and the scene breaks the touched fragment off.
//!
//! Contacts between features that share an origin vertex (the two sides of a fresh crack, which
//! coincide at the start of the step) are part of the topology change, not collisions: they
//! are counted in the step but get no response.

use super::world::{Motion, World, NO_FRAGMENT};
use glam::DVec3;
use topoccd::{Report, Step};

/// Coefficient of restitution of the rigid impulses, in `[0, 1]`.
pub(crate) const RESTITUTION: f64 = 0.4;

/// Gauss-Seidel sweeps over the colliding pairs.
const SWEEPS: usize = 4;

/// One collision between two features, with the geometry the response needs.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hit {
    /// Vertices of feature A (the vertex of a vertex-face pair, the first edge), then of B.
    pub vertices: [u32; 4],
    /// How many of `vertices` belong to A (1 or 2).
    pub split: usize,
    /// The face of a vertex-face pair (`u32::MAX` for an edge-edge pair).
    pub face: u32,
    /// Time of impact.
    pub toi: f64,
    /// Contact normal, unit, pointing from B's side towards A's side (zero if degenerate).
    pub normal: DVec3,
    /// Whether A started clearly on one side of B (farther than a thousandth of B's size from
    /// its plane), which is what orients `normal`; features on a crack's lips do not.
    pub sided: bool,
    /// A point of A at the end of the step.
    pub point: DVec3,
    /// Piece of A.
    pub piece_a: u32,
    /// Piece of B.
    pub piece_b: u32,
}

/// An impact that breaks a fragment off a breakable piece.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Break {
    /// The fragment hit.
    pub fragment: u32,
    /// Velocity of the impactor at the contact (per step).
    pub velocity: DVec3,
    /// Where it was hit.
    pub point: DVec3,
}

/// The collisions of a report, without the contacts along fresh cracks.
pub(crate) fn hits(world: &World, step: &Step, report: &Report) -> Vec<Hit> {
    let vectors = |xs: &[[f64; 3]]| xs.iter().map(|&p| DVec3::from(p)).collect::<Vec<_>>();
    let (x0, x1) = (vectors(step.x0()), vectors(step.x1()));
    let at = |v: u32, t: f64| {
        let i = v as usize;
        x0[i] + (x1[i] - x0[i]) * t
    };
    let crack = |a: &[u32], b: &[u32]| {
        a.iter().any(|&i| {
            b.iter()
                .any(|&j| world.origin[i as usize] == world.origin[j as usize])
        })
    };
    let mut out = Vec::with_capacity(report.vf.len() + report.ee.len());
    for c in &report.vf {
        let face = step.triangles()[c.face as usize];
        if crack(&[c.vertex], &face) {
            continue;
        }
        let [q0, q1, q2] = face.map(|i| at(i, c.toi));
        let n = (q1 - q0).cross(q2 - q0).normalize_or_zero();
        let side = (x0[c.vertex as usize] - face.map(|i| x0[i as usize])[0]).dot(n);
        let rel = (x1[c.vertex as usize] - x0[c.vertex as usize])
            - face
                .iter()
                .map(|&i| x1[i as usize] - x0[i as usize])
                .sum::<DVec3>()
                / 3.0;
        let sign = orientation(side, rel.dot(n));
        let size = (q1 - q0).length().max((q2 - q0).length());
        out.push(Hit {
            sided: side.abs() > 1e-3 * size,
            vertices: [c.vertex, face[0], face[1], face[2]],
            split: 1,
            face: c.face,
            toi: c.toi,
            normal: n * sign,
            point: x1[c.vertex as usize],
            piece_a: world.piece[c.vertex as usize],
            piece_b: world.piece[face[0] as usize],
        });
    }
    for c in &report.ee {
        if crack(&c.a, &c.b) {
            continue;
        }
        let (a0, a1) = (at(c.a[0], c.toi), at(c.a[1], c.toi));
        let (b0, b1) = (at(c.b[0], c.toi), at(c.b[1], c.toi));
        let (s, t) = topoccd::narrow::closest::segment_segment_parameters(a0, a1, b0, b1);
        let mut n = (a1 - a0).cross(b1 - b0).normalize_or_zero();
        if n == DVec3::ZERO {
            n = ((a0 + (a1 - a0) * s) - (b0 + (b1 - b0) * t)).normalize_or_zero();
        }
        let lerp0 = |e: [u32; 2], u: f64| {
            let (p, q) = (x0[e[0] as usize], x0[e[1] as usize]);
            p + (q - p) * u
        };
        let lerp1 = |e: [u32; 2], u: f64| {
            let (p, q) = (x1[e[0] as usize], x1[e[1] as usize]);
            p + (q - p) * u
        };
        let side = (lerp0(c.a, s) - lerp0(c.b, t)).dot(n);
        let rel = (lerp1(c.a, s) - lerp0(c.a, s)) - (lerp1(c.b, t) - lerp0(c.b, t));
        let sign = orientation(side, rel.dot(n));
        let size = (a1 - a0).length().max((b1 - b0).length());
        out.push(Hit {
            sided: side.abs() > 1e-3 * size,
            vertices: [c.a[0], c.a[1], c.b[0], c.b[1]],
            split: 2,
            face: u32::MAX,
            toi: c.toi,
            normal: n * sign,
            point: lerp1(c.a, s),
            piece_a: world.piece[c.a[0] as usize],
            piece_b: world.piece[c.b[0] as usize],
        });
    }
    out
}

/// The sign that orients a normal from B to A: by the side A started on, or failing that
/// (A started on B's plane) against the relative motion.
fn orientation(side: f64, approach: f64) -> f64 {
    if side.abs() > 1e-12 {
        side.signum()
    } else if approach != 0.0 {
        -approach.signum()
    } else {
        0.0
    }
}

/// Applies the response to the hits of a step (see the module docs), after the rigid centres
/// have moved to the end of the step. Returns the impacts that break breakable pieces.
pub(crate) fn respond(world: &mut World, hits: &[Hit]) -> Vec<Break> {
    // Soft vertices stop.
    for h in hits {
        for &v in &h.vertices {
            let p = world.piece[v as usize] as usize;
            if matches!(world.pieces[p].motion, Motion::Soft) {
                world.pinned[v as usize] = true;
            }
        }
    }
    // One contact per pair of pieces with a rigid side: the earliest.
    let mut pairs: Vec<((u32, u32), usize)> = Vec::new();
    for (i, h) in hits.iter().enumerate() {
        let rigid = |p: u32| matches!(world.pieces[p as usize].motion, Motion::Rigid { .. });
        if h.normal == DVec3::ZERO
            || h.piece_a == h.piece_b
            || !(rigid(h.piece_a) || rigid(h.piece_b))
        {
            continue;
        }
        pairs.push(((h.piece_a.min(h.piece_b), h.piece_a.max(h.piece_b)), i));
    }
    pairs.sort_by(|x, y| {
        x.0.cmp(&y.0)
            .then(hits[x.1].toi.total_cmp(&hits[y.1].toi))
            .then(x.1.cmp(&y.1))
    });
    pairs.dedup_by_key(|p| p.0);
    let mut breaks = Vec::new();
    let mut broken = vec![false; pairs.len()];
    for _ in 0..SWEEPS {
        for (k, &(_, i)) in pairs.iter().enumerate() {
            if broken[k] {
                continue;
            }
            let mut h = hits[i];
            if !h.sided {
                // On a crack's lips the side is unknown: push the pieces apart centre to
                // centre instead.
                let centre = |p: u32| match world.pieces[p as usize].motion {
                    Motion::Rigid { centre, .. } => Some(centre),
                    _ => None,
                };
                if let (Some(ca), Some(cb)) = (centre(h.piece_a), centre(h.piece_b)) {
                    h.normal = (ca - cb).normalize_or(h.normal);
                }
            }
            let h = &h;
            let rel = world.velocity_at(h.piece_a, h.point) - world.velocity_at(h.piece_b, h.point);
            let approach = rel.dot(h.normal);
            if approach >= 0.0 {
                continue;
            }
            // A fast impact on a breakable static piece breaks it instead of bouncing.
            let breaks_b = world.pieces[h.piece_b as usize].breakable;
            let breaks_a = world.pieces[h.piece_a as usize].breakable;
            if (breaks_a || breaks_b) && -approach > world.break_speed {
                let (body, impactor, at) = if breaks_b {
                    (&h.vertices[h.split..], h.piece_a, h.vertices[0])
                } else {
                    (&h.vertices[..h.split], h.piece_b, h.vertices[h.split])
                };
                // The fragments of the touched feature: the face's, or those next to its
                // vertices.
                let mut fragments: Vec<u32> = if breaks_b && h.face != u32::MAX {
                    vec![world.triangle_fragment[h.face as usize]]
                } else {
                    body.iter()
                        .map(|&v| world.vertex_fragment[v as usize])
                        .collect()
                };
                fragments.retain(|&f| f != NO_FRAGMENT);
                fragments.sort_unstable();
                fragments.dedup();
                if !fragments.is_empty() {
                    broken[k] = true;
                    let velocity = world.velocity_at(impactor, world.x(at));
                    breaks.extend(fragments.into_iter().map(|fragment| Break {
                        fragment,
                        velocity,
                        point: h.point,
                    }));
                    continue;
                }
            }
            impulse(world, h, approach);
        }
    }
    // Pieces that collided lose half their spin, which otherwise turns them into their
    // neighbours along the cracks they broke off at.
    let mut damped: Vec<u32> = pairs.iter().flat_map(|&(p, _)| [p.0, p.1]).collect();
    damped.sort_unstable();
    damped.dedup();
    for p in damped {
        if let Motion::Rigid { spin, .. } = &mut world.pieces[p as usize].motion {
            *spin *= 0.5;
        }
    }
    breaks
}

/// Applies the impulse that turns the approach speed `approach < 0` along the hit's normal
/// into a separation speed `-RESTITUTION * approach`.
fn impulse(world: &mut World, h: &Hit, approach: f64) {
    let n = h.normal;
    let weight = |world: &World, p: u32| match world.pieces[p as usize].motion {
        Motion::Rigid {
            centre,
            inv_mass,
            inv_inertia,
            ..
        } => inv_mass + inv_inertia * (h.point - centre).cross(n).length_squared(),
        _ => 0.0,
    };
    let w = weight(world, h.piece_a) + weight(world, h.piece_b);
    if w <= 0.0 {
        return;
    }
    let j = -(1.0 + RESTITUTION) * approach / w;
    for (p, sign) in [(h.piece_a, 1.0), (h.piece_b, -1.0)] {
        if let Motion::Rigid {
            centre,
            velocity,
            spin,
            inv_mass,
            inv_inertia,
        } = &mut world.pieces[p as usize].motion
        {
            *velocity += n * (sign * j * *inv_mass);
            *spin += (h.point - *centre).cross(n) * (sign * j * *inv_inertia);
        }
    }
}
