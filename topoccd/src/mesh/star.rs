//! Rule 6 of the pair filter: vertex stars proved free of self-contact over the step.
//!
//! The *star* of a vertex `v` is the set of its incident triangles. When it is a certified disk
//! (the disk theorem of the cluster method, [`broad::cluster`](crate::broad::cluster), applied
//! to the star with the centre `c = v`), no two of its features that share no vertex touch at
//! any time of the step, so two triangles that share `v` give no candidate pair at all: every
//! feature of either lies in the star. Most overlapping triangle pairs of a mesh are such
//! neighbours, and their feature pairs, though they never touch, come close enough for their
//! boxes to overlap.
//!
//! # The certificate
//! For the star of `v`, with triangles `(v, a_i, b_i)` (each rotated to start at `v`, keeping
//! its orientation), and the direction `V` = the sum of their normals at t=0 and t=1:
//! 1. the link edges `a_i -> b_i` (`k >= 3` of them) have distinct starts, and every end is the
//!    start of exactly one of them: the directed link splits into cycles through `k` distinct
//!    vertices, every spoke `v a` lies in exactly two triangles of the star, in opposite
//!    directions (the mesh is consistently oriented around `v`), every link edge in one (the
//!    two triangles `(v, a, b)` and `(v, b, a)` cannot both pass 2), and
//!    `V - E + F = (k + 1) - 2k + k = 1`;
//! 2. every triangle has `n(t)·V > 0` on `[0, 1]`: the three Bernstein coefficients of the
//!    quadratic, computed from the triangle's control normals, exceed their rounding bound.
//!    With the centre `c = v`, this is also the star test of every link edge (hypothesis 4:
//!    `V·((a - v) x (b - v)) = n·V`);
//! 3. the link's projected angles around `v` at t=0 sum to less than `4 pi`: each is in
//!    `(0, pi)` by 2, so each cycle of the link winds at least once around `v` and the sum is
//!    `2 pi` times the total winding number, which is then one: the link is one cycle, and it
//!    winds once (hypothesis 5). Each angle is bounded by `pi / 3`, `pi / 2` or `pi` from
//!    rigorous comparisons of its cosine, and the bounds must add up to less than `4 pi`.
//!
//! By the disk theorem the star's projection along `V` is then injective at every time of the
//! step. Certifying over the whole step covers any `[0, tmax]`. The certificate says nothing
//! about distances, so the rule applies only without a minimum separation.

use std::sync::atomic::{AtomicU8, Ordering};

use rayon::prelude::*;

use super::{Step, Topology};
use crate::math::{max_abs, DVec3, UNDERFLOW_ERROR, UNIT_ROUNDOFF};

/// Rounding bound of a coefficient `N_j·V` of `n(t)·V`, in units of `u |V|_1 P Q` (`P`, `Q`
/// the largest coordinates of the triangle's two edge vectors over the step). Analysis: the
/// edge vectors' own rounding moves each cross product's component by `4 u P Q`, its products
/// and difference by `6 u P Q`, the mean of two by `2 u P Q` more, and the dot product with
/// `V` adds `6 u |V|_1 P Q`: at most 20.
const NORMAL_ERROR: f64 = 64.0;
/// Rounding bound of the projected dot product and squared lengths of the winding test, in
/// units of `u |V|_inf^2 A B` (`A`, `B` the largest coordinates of the two arms). Analysis:
/// each of the two products is at most `9 |V|_inf^2 A B` and is computed within 7 units of
/// rounding of that, the difference adds 18, the arms' own rounding 72: at most 220.
const ANGLE_ERROR: f64 = 512.0;
/// Meshes with at least this many vertices have all their stars certified in parallel chunks.
const PAR_LEN: usize = 4096;
/// Stars of more triangles than this are not certified (the link test is quadratic in it).
const MAX_VALENCE: usize = 16;

/// Which vertex stars of one step are certified, each found out when first asked
/// ([`StarView::certified`]): the method that skips most neighbouring triangle pairs before
/// looking at them (the cluster method) asks about few stars. Kept by the caller across steps.
#[derive(Debug, Default)]
pub(crate) struct Stars {
    /// Per vertex: [`UNKNOWN`], [`CERTIFIED`] or [`REFUSED`].
    state: Vec<AtomicU8>,
    /// Condition 1 of every star (it depends on the topology only), for [`Stars::certify_all`]
    /// over the topology it was derived for.
    links: Links,
    /// The triangles' normals of the step, kept for the next.
    normals: Normals,
}

/// The control normals of every triangle over one step ([`TriangleNormals`]), computed once
/// for the three stars it lies in, and what [`Stars::certify_all`] keeps of them for the next
/// step: a simulator's step starts where the last one ended, so a triangle's normal at its
/// start is the last step's at its end, the same floating-point vector when its three
/// vertices' positions are the same (compared exactly). The certificate is then computed
/// exactly as afresh, with one cross product of four per triangle.
#[derive(Debug, Default)]
struct Normals {
    /// Per triangle, this step's.
    tri: Vec<TriangleNormals>,
    /// The last step's positions at t=1.
    x1: Vec<DVec3>,
    /// Whether `tri` and `x1` are those of the last query's [`Stars::certify_all`], over the
    /// same triangles: set then, and passed on by [`Stars::reset`] to `usable`.
    fresh: bool,
    usable: bool,
    /// Triangles whose normal at the start the last [`Stars::certify_all`] took from the
    /// step before (for the tests).
    reused: usize,
}

/// The Bernstein control normals of `n(t) = (a - v) x (b - v)` over the step for a triangle
/// `(v, a, b)` (the same vector for each rotation of it, so computed from its first vertex),
/// and the product `P Q` of its two edge vectors' largest coordinates over the step (the
/// rounding bound's scale, [`NORMAL_ERROR`]).
#[derive(Clone, Copy, Debug, Default)]
struct TriangleNormals {
    start: DVec3,
    middle: DVec3,
    end: DVec3,
    size: f64,
}

impl TriangleNormals {
    /// The normals of `tri` on the step's positions; with `start`, the one at t=0 as given
    /// (the last step's at its end, over the same positions: bitwise what this computes).
    #[inline]
    fn new(tri: &[u32; 3], (x0, x1): (&[DVec3], &[DVec3]), start: Option<DVec3>) -> Self {
        let [c, a, b] = tri.map(|v| v as usize);
        let (p0, p1) = (x0[a] - x0[c], x1[a] - x1[c]);
        let (q0, q1) = (x0[b] - x0[c], x1[b] - x1[c]);
        Self {
            start: start.unwrap_or_else(|| p0.cross(q0)),
            middle: (p0.cross(q1) + p1.cross(q0)) * 0.5,
            end: p1.cross(q1),
            size: max_abs(p0).max(max_abs(p1)) * max_abs(q0).max(max_abs(q1)),
        }
    }
}

/// Condition 1 of every star of one topology ([`link`]), kept while the topology is: the
/// per-step certificate then checks conditions 2 and 3 only, on the step's positions.
#[derive(Debug, Default)]
struct Links {
    /// Per vertex: whether its link passes.
    passes: Vec<bool>,
    /// Beside `topo.vertex_triangles`: the link edges' starts and `next` of each star.
    start: Vec<u32>,
    next: Vec<u8>,
    /// Whether these are the links of the topology last given to [`Stars::certify_all`].
    valid: bool,
}

impl Clone for Stars {
    /// A fresh, empty one (the states are scratch memory, valid for one step).
    fn clone(&self) -> Self {
        Self::default()
    }
}

const UNKNOWN: u8 = 0;
const CERTIFIED: u8 = 1;
const REFUSED: u8 = 2;

impl Stars {
    /// Forgets every star, for a step with `n` vertices; without `same_topology` (the step's
    /// triangles and vertex count are those of the last reset's), the links too.
    pub fn reset(&mut self, n: usize, same_topology: bool) {
        self.links.valid &= same_topology;
        self.normals.usable = std::mem::take(&mut self.normals.fresh) && same_topology;
        self.state.truncate(n);
        for s in &mut self.state {
            *s.get_mut() = UNKNOWN;
        }
        self.state.resize_with(n, || AtomicU8::new(UNKNOWN));
    }

    /// Certifies every star of `step` (topology `topo`) at once, in parallel, after a
    /// [`Stars::reset`]: cheaper than one by one when nearly all will be asked about (the
    /// per-step hierarchy and the oracle ask about every vertex of a mesh). The links derived
    /// for the topology serve while the resets say it is the same: only the conditions on the
    /// positions are checked then.
    pub fn certify_all(&mut self, step: &Step, topo: &Topology) {
        let n = self.state.len();
        if !(self.links.valid && self.links.passes.len() == n) {
            self.links.derive(topo, step.triangles());
        }
        let positions = (step.pos0(), step.pos1());
        let tris = step.triangles();
        let par = n >= PAR_LEN;
        // Every triangle's normals once, the one at the start kept from the last step where
        // the triangle starts where it ended.
        let normals = &mut self.normals;
        if !normals.usable {
            normals.x1.clear();
        }
        normals.tri.resize(tris.len(), TriangleNormals::default());
        let kept_x1 = &normals.x1[..];
        let usable = normals.usable && normals.tri.len() == tris.len();
        let same = |v: u32| kept_x1.get(v as usize) == Some(&positions.0[v as usize]);
        let fit = |(tri, kept): (&[u32; 3], &mut TriangleNormals)| -> usize {
            let again = usable && tri.iter().all(|&v| same(v));
            *kept = TriangleNormals::new(tri, positions, again.then_some(kept.end));
            usize::from(again)
        };
        normals.reused = if par {
            tris.par_iter()
                .zip(normals.tri.par_iter_mut())
                .with_min_len(PAR_LEN / 4)
                .map(fit)
                .sum()
        } else {
            tris.iter().zip(normals.tri.iter_mut()).map(fit).sum()
        };
        let (links, state, tri) = (&self.links, &self.state, &normals.tri[..]);
        let offsets = &topo.vertex_offsets;
        let certify = |v: usize| {
            let (lo, hi) = (offsets[v] as usize, offsets[v + 1] as usize);
            let fan = &topo.vertex_triangles[lo..hi];
            let c = links.passes[v]
                && star_geometry(
                    v as u32,
                    (&links.start[lo..hi], &links.next[lo..hi]),
                    |i| tri[fan[i] as usize],
                    positions.0,
                );
            state[v].store(if c { CERTIFIED } else { REFUSED }, Ordering::Relaxed);
        };
        if par {
            (0..n).into_par_iter().with_min_len(PAR_LEN / 4).for_each(certify);
        } else {
            (0..n).for_each(certify);
        }
        normals.x1.clear();
        normals.x1.extend_from_slice(positions.1);
        normals.fresh = true;
    }

    /// How many triangles' normals at the start the last [`Stars::certify_all`] took from the
    /// step before.
    #[cfg(test)]
    fn reused(&self) -> usize {
        self.normals.reused
    }

    /// The view of `step` (topology `topo`) that tells which stars are certified, certifying
    /// those not known yet on demand.
    pub fn view<'s>(&'s self, step: &'s Step, topo: &'s Topology) -> StarView<'s> {
        debug_assert_eq!(self.state.len(), step.vertex_count());
        StarView {
            state: &self.state,
            topo,
            tris: step.triangles(),
            positions: (step.pos0(), step.pos1()),
        }
    }
}

impl Links {
    /// Condition 1 of every star of `topo` (triangles `tris`).
    fn derive(&mut self, topo: &Topology, tris: &[[u32; 3]]) {
        let n = topo.vertex_offsets.len().saturating_sub(1);
        let total = topo.vertex_triangles.len();
        self.start.clear();
        self.start.resize(total, 0);
        self.next.clear();
        self.next.resize(total, 0);
        self.passes.clear();
        self.passes.resize(n, false);
        for v in 0..n {
            let (lo, hi) = (topo.vertex_offsets[v] as usize, topo.vertex_offsets[v + 1] as usize);
            self.passes[v] = hi - lo <= MAX_VALENCE
                && link(v as u32, topo, tris, &mut self.start[lo..hi], &mut self.next[lo..hi]);
        }
        self.valid = true;
    }
}

/// The stars of one step, certified when first asked about, from any thread.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StarView<'s> {
    state: &'s [AtomicU8],
    topo: &'s Topology,
    tris: &'s [[u32; 3]],
    positions: (&'s [DVec3], &'s [DVec3]),
}

impl StarView<'_> {
    /// Whether the star of vertex `v` is certified. The answer is a function of the step
    /// alone: threads that ask at once may both compute it, and store the same value.
    #[inline]
    pub fn certified(&self, v: u32) -> bool {
        let state = &self.state[v as usize];
        match state.load(Ordering::Relaxed) {
            CERTIFIED => true,
            REFUSED => false,
            _ => {
                let c = star_certified(v, self.topo, self.tris, self.positions);
                state.store(if c { CERTIFIED } else { REFUSED }, Ordering::Relaxed);
                c
            }
        }
    }
}

/// Whether the star of `v` passes the certificate of the module documentation.
fn star_certified(
    v: u32,
    topo: &Topology,
    tris: &[[u32; 3]],
    positions: (&[DVec3], &[DVec3]),
) -> bool {
    let mut start = [0u32; MAX_VALENCE];
    let mut next = [0u8; MAX_VALENCE];
    let fan = topo.triangles_of(v);
    let k = fan.len();
    link(v, topo, tris, &mut start, &mut next)
        && star_geometry(
            v,
            (&start[..k], &next[..k]),
            |i| TriangleNormals::new(&tris[fan[i] as usize], positions, None),
            positions.0,
        )
}

/// Condition 1 of the certificate, which depends on the topology only: writes the link edges'
/// starts (`start[i]`, of the `i`-th triangle around `v`) and where each edge's end starts one
/// (`next[i]`), and says whether the link passes.
fn link(v: u32, topo: &Topology, tris: &[[u32; 3]], start: &mut [u32], next: &mut [u8]) -> bool {
    let fan = topo.triangles_of(v);
    let k = fan.len();
    if !(3..=MAX_VALENCE).contains(&k) {
        return false;
    }
    // Link edges a_i -> b_i.
    let mut end = [0u32; MAX_VALENCE];
    for (i, &t) in fan.iter().enumerate() {
        let tri = tris[t as usize];
        let r = usize::from(tri[1] == v) + 2 * usize::from(tri[2] == v);
        start[i] = tri[(r + 1) % 3];
        end[i] = tri[(r + 2) % 3];
    }
    // 1. The link edges' starts are distinct, and every end is the start of exactly one edge
    // (`next[i]`, then also distinct): the directed link splits into cycles (the winding test
    // below admits only one).
    let mut bad = 0;
    for i in 0..k {
        let mut found = 0;
        next[i] = 0;
        for j in 0..k {
            let hit = end[i] == start[j];
            found += usize::from(hit);
            next[i] = if hit { j as u8 } else { next[i] };
            bad += usize::from(j > i && start[i] == start[j]);
        }
        bad += usize::from(found != 1);
    }
    bad == 0
}

/// Conditions 2 and 3 of the certificate for the star of `v` whose link passed condition 1
/// ([`link`], its edges' `start` and `next`), on the step's positions: `normals(i)` are those
/// of the star's `i`-th triangle ([`TriangleNormals`]), `x0` the positions at t=0.
fn star_geometry(
    v: u32,
    (start, next): (&[u32], &[u8]),
    normals: impl Fn(usize) -> TriangleNormals,
    x0: &[DVec3],
) -> bool {
    let k = start.len();
    let next = |i: usize| next[i] as usize;
    // (Each triangle's normals asked for twice rather than copied: an index into the step's
    // normals, or a fresh computation for a star asked about alone.)
    let mut direction = DVec3::ZERO;
    for i in 0..k {
        let n = normals(i);
        direction += n.start + n.end;
    }
    // 2. n(t)·V > 0 on [0, 1] for every triangle (v, a, b), n = (a - v) x (b - v): its control
    // coefficients exceed their rounding bound.
    let v1 = direction.abs().element_sum();
    let scale = NORMAL_ERROR * UNIT_ROUNDOFF * v1;
    for i in 0..k {
        let n = normals(i);
        let error = scale * n.size + UNDERFLOW_ERROR;
        let b0 = direction.dot(n.start);
        let b1 = direction.dot(n.middle);
        let b2 = direction.dot(n.end);
        if !(b0 > error && b1 > error && b2 > error) {
            return false;
        }
    }
    // The arms from v to the link vertices at t=0.
    let c0 = x0[v as usize];
    let mut arm0 = [DVec3::ZERO; MAX_VALENCE];
    for i in 0..k {
        arm0[i] = x0[start[i] as usize] - c0;
    }
    // 3. Winding number one at t=0: the angles' bounds, in units of pi / 6, add up to less
    // than 4 pi. (Several cycles would each wind at least once.) Each angle is at most pi / 2
    // when its projected cosine is certainly positive, else less than pi; if that is not
    // enough, the acute ones are looked at again for pi / 3.
    let vv = direction.dot(direction);
    let unit = ANGLE_ERROR * UNIT_ROUNDOFF * max_abs(direction).powi(2);
    let mut along = [0.0; MAX_VALENCE];
    for i in 0..k {
        along[i] = arm0[i].dot(direction);
    }
    // |V|^2 times the projected cosine's numerator of link edge i, less its rounding bound.
    let mut low = [0.0; MAX_VALENCE];
    let mut acute = 0;
    for i in 0..k {
        let j = next(i);
        let (pa, pb) = (arm0[i], arm0[j]);
        low[i] = pa.dot(pb) * vv - along[i] * along[j] - unit * max_abs(pa) * max_abs(pb);
        acute += usize::from(low[i] > 0.0);
    }
    if 3 * acute + 6 * (k - acute) < 24 {
        return true;
    }
    // |V|^2 times the projected squared lengths, plus their rounding bounds.
    let length = |i: usize| {
        let p = arm0[i];
        p.dot(p) * vv - along[i] * along[i] + unit * max_abs(p).powi(2)
    };
    let mut total = 0;
    for (i, &l) in low[..k].iter().enumerate() {
        total += if l <= 0.0 {
            6
        } else if 4.0 * l * l * (1.0 - 1e-9) >= length(i) * length(next(i)) * (1.0 + 1e-9) {
            2
        } else {
            3
        };
    }
    total < 24
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::narrow::{edge_edge, vertex_face, EdgeEdge, NarrowOptions, VertexFace};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A fan of `k` triangles around vertex 0, its rim vertices `1..=k` at the given
    /// positions, oriented counter-clockwise seen from +z.
    fn fan(k: u32) -> Vec<[u32; 3]> {
        (0..k).map(|i| [0, 1 + i, 1 + (i + 1) % k]).collect()
    }

    fn certified(x0: &[DVec3], x1: &[DVec3], tris: &[[u32; 3]]) -> Vec<bool> {
        // As arrays: `From<&[DVec3]>` needs the feature `glam`, off in the published crate.
        let arrays = |x: &[DVec3]| x.iter().map(|p| p.to_array()).collect::<Vec<_>>();
        let step = Step::new(arrays(x0), arrays(x1), tris).expect("a valid step");
        let topo = Topology::new(tris, x0.len());
        let mut stars = Stars::default();
        stars.reset(x0.len(), false);
        let view = stars.view(&step, &topo);
        let lazy: Vec<bool> = (0..x0.len() as u32).map(|v| view.certified(v)).collect();
        stars.reset(x0.len(), false);
        stars.certify_all(&step, &topo);
        let view = stars.view(&step, &topo);
        let all: Vec<bool> = (0..x0.len() as u32).map(|v| view.certified(v)).collect();
        assert_eq!(lazy, all);
        // Again, with the links kept from the call before.
        stars.reset(x0.len(), true);
        stars.certify_all(&step, &topo);
        let view = stars.view(&step, &topo);
        let kept: Vec<bool> = (0..x0.len() as u32).map(|v| view.certified(v)).collect();
        assert_eq!(kept, all);
        all
    }

    fn rim(k: u32, z: impl Fn(f64) -> f64) -> Vec<DVec3> {
        let mut x = vec![DVec3::ZERO];
        for i in 0..k {
            let a = std::f64::consts::TAU * i as f64 / k as f64;
            x.push(DVec3::new(a.cos(), a.sin(), z(a)));
        }
        x
    }

    #[test]
    fn a_flat_or_gently_bent_fan_is_certified_and_a_boundary_vertex_is_not() {
        for k in [3, 5, 6, 8, 10] {
            let x0 = rim(k, |_| 0.0);
            let x1 = rim(k, |a| 0.3 * a.cos());
            assert!(certified(&x0, &x1, &fan(k))[0], "k {k}");
            // Rim vertices lie on the boundary: not certified.
            assert!(certified(&x0, &x1, &fan(k))[1..].iter().all(|&c| !c));
            // An open fan (one triangle removed): the centre is a boundary vertex.
            let open: Vec<_> = fan(k).into_iter().skip(1).collect();
            assert!(!certified(&x0, &x1, &open)[0], "k {k}");
        }
    }

    #[test]
    fn a_folding_flipped_or_doubly_wound_fan_is_not_certified() {
        let k = 6;
        let x0 = rim(k, |_| 0.0);
        // One rim vertex folds through the centre's other side: a triangle's normal turns over.
        let mut x1 = x0.clone();
        x1[1] = DVec3::new(-0.5, 0.1, 0.05);
        assert!(!certified(&x0, &x1, &fan(k))[0]);
        // One triangle flipped: inconsistent orientation.
        let mut tris = fan(k);
        tris[2].swap(1, 2);
        assert!(!certified(&x0, &x0, &tris)[0]);
        // Twelve triangles winding twice around the centre (each spans 60 degrees).
        let mut x = vec![DVec3::ZERO];
        for i in 0..12 {
            let a = std::f64::consts::TAU * i as f64 / 6.0;
            x.push(DVec3::new(a.cos(), a.sin(), 0.01 * i as f64));
        }
        assert!(!certified(&x, &x, &fan(12))[0]);
    }

    /// For random moving fans, every certified star has no pair of features sharing no vertex
    /// in contact: the elementary tests find none.
    #[test]
    fn certified_stars_have_no_feature_pair_in_contact() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let options = NarrowOptions::default();
        let (mut stars, mut checked) = (0, 0);
        for _ in 0..3000 {
            let k = rng.random_range(3..=9u32);
            let jitter = rng.random_range(0.0..1.0);
            let mut x0 = rim(k, |_| 0.0);
            let mut x1 = x0.clone();
            for p in x0.iter_mut().chain(x1.iter_mut()) {
                *p += jitter * DVec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
            }
            let tris = fan(k);
            if !certified(&x0, &x1, &tris)[0] {
                continue;
            }
            stars += 1;
            let topo = Topology::new(&tris, x0.len());
            let points = |ids: [u32; 4]| -> [DVec3; 8] {
                std::array::from_fn(|i| {
                    let x = if i < 4 { &x0 } else { &x1 };
                    x[ids[i % 4] as usize]
                })
            };
            for tri in &tris {
                for v in (0..=k).filter(|v| !tri.contains(v)) {
                    checked += 1;
                    let q = VertexFace::from_points(points([v, tri[0], tri[1], tri[2]]));
                    assert!(!vertex_face(&q, &options).is_contact(), "{q:?}");
                }
            }
            for (i, e) in topo.edges.iter().enumerate() {
                for f in &topo.edges[i + 1..] {
                    if e.iter().any(|x| f.contains(x)) {
                        continue;
                    }
                    checked += 1;
                    let q = EdgeEdge::from_points(points([e[0], e[1], f[0], f[1]]));
                    assert!(!edge_edge(&q, &options).is_contact(), "{q:?}");
                }
            }
        }
        assert!(stars > 300 && checked > 10_000, "{stars} stars, {checked} pairs");
    }

    /// A grid of `n x n` vertices in the plane z = 0, two triangles per cell.
    fn grid(n: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let x = (0..n * n)
            .map(|i| DVec3::new(f64::from(i % n), f64::from(i / n), 0.0))
            .collect();
        let mut tris = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let a = j * n + i;
                tris.push([a, a + 1, a + n + 1]);
                tris.push([a, a + n + 1, a + n]);
            }
        }
        (x, tris)
    }

    /// Over seeded random deformations that chain (each step starts where the last ended), with
    /// jumps, topology changes and folds: [`Stars::certify_all`] with the normals kept from the
    /// step before certifies exactly the stars a fresh `Stars` does, and every certified star
    /// has no pair of features sharing no vertex in contact (the elementary tests, brute force
    /// over the star).
    #[test]
    fn kept_normals_certify_as_afresh_and_soundly_over_random_deformations() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let options = NarrowOptions::default();
        let arrays = |x: &[DVec3]| x.iter().map(|p| p.to_array()).collect::<Vec<_>>();
        let (mut reused, mut checked) = (0, 0);
        for _ in 0..40 {
            let (mut x, mut tris) = grid(7);
            let mut stars = Stars::default();
            let mut same = false;
            let amplitude = rng.random_range(0.05..0.6);
            for _ in 0..8 {
                // A step of random size; sometimes a jump (the start moved), a topology change
                // (one triangle flipped or removed) or a fold of one vertex.
                let mut x0 = x.clone();
                if rng.random_bool(0.15) {
                    let v = rng.random_range(0..x0.len());
                    x0[v] += DVec3::new(0.0, 0.0, 1e-9);
                }
                if rng.random_bool(0.2) {
                    let t = rng.random_range(0..tris.len());
                    if rng.random_bool(0.5) {
                        tris[t].swap(1, 2);
                    } else {
                        tris.remove(t);
                    }
                    same = false;
                }
                let mut x1: Vec<DVec3> = x0
                    .iter()
                    .map(|p| {
                        *p + amplitude
                            * DVec3::new(
                                rng.random_range(-0.2..0.2),
                                rng.random_range(-0.2..0.2),
                                rng.random_range(-1.0..1.0),
                            )
                    })
                    .collect();
                if rng.random_bool(0.2) {
                    let v = rng.random_range(0..x1.len());
                    x1[v].z -= 3.0 * x1[v].z.signum() + 1.0;
                }
                let step = Step::new(arrays(&x0), arrays(&x1), &tris).expect("a valid step");
                let topo = Topology::new(&tris, x0.len());
                stars.reset(x0.len(), same);
                stars.certify_all(&step, &topo);
                reused += stars.reused();
                let mut fresh = Stars::default();
                fresh.reset(x0.len(), false);
                fresh.certify_all(&step, &topo);
                let (kept, new) = (stars.view(&step, &topo), fresh.view(&step, &topo));
                let points = |ids: [u32; 4]| -> [DVec3; 8] {
                    std::array::from_fn(|i| {
                        let x = if i < 4 { &x0 } else { &x1 };
                        x[ids[i % 4] as usize]
                    })
                };
                for v in 0..x0.len() as u32 {
                    assert_eq!(new.certified(v), kept.certified(v), "vertex {v}");
                    if !kept.certified(v) {
                        continue;
                    }
                    let fan: Vec<[u32; 3]> =
                        topo.triangles_of(v).iter().map(|&t| tris[t as usize]).collect();
                    let mut edges: Vec<[u32; 2]> = fan
                        .iter()
                        .flat_map(|t| (0..3).map(move |i| [t[i].min(t[(i + 1) % 3]), t[i].max(t[(i + 1) % 3])]))
                        .collect();
                    edges.sort_unstable();
                    edges.dedup();
                    let mut vertices: Vec<u32> = fan.iter().flatten().copied().collect();
                    vertices.sort_unstable();
                    vertices.dedup();
                    for tri in &fan {
                        for &u in vertices.iter().filter(|u| !tri.contains(u)) {
                            checked += 1;
                            let q = VertexFace::from_points(points([u, tri[0], tri[1], tri[2]]));
                            assert!(!vertex_face(&q, &options).is_contact(), "{q:?}");
                        }
                    }
                    for (i, e) in edges.iter().enumerate() {
                        for f in edges[i + 1..].iter().filter(|f| !e.iter().any(|u| f.contains(u))) {
                            checked += 1;
                            let q = EdgeEdge::from_points(points([e[0], e[1], f[0], f[1]]));
                            assert!(!edge_edge(&q, &options).is_contact(), "{q:?}");
                        }
                    }
                }
                x = x1;
                same = true;
            }
        }
        assert!(reused > 10_000 && checked > 100_000, "{reused} reused, {checked} pairs");
    }
}
