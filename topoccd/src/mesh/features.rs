//! The features of one step (vertices, edges, faces), their swept boxes, and which triangle
//! owns each vertex and edge. Computed anew every step in linear time after the edge sort.
//!
//! # Ownership: each feature pair tested at most once
//! Every referenced vertex and every edge is *owned* by exactly one incident triangle, the one
//! of lowest index. When a traversal reports an overlapping triangle pair `{A, B}`, only the
//! pairs `(v owned by A, face B)`, `(v owned by B, face A)` and `(e owned by A, e' owned by B)`
//! are candidates ([`Features::triangle_pair`]). A vertex-face pair `(v, f)` can therefore only
//! come from the triangle pair `{owner(v), f}`, and an edge-edge pair `{e, e'}` only from
//! `{owner(e), owner(e')}` (pairs with equal owners share a vertex and are skipped). Since a
//! traversal visits each unordered triangle pair once, each feature pair is a candidate at most
//! once. Nothing is lost: a feature lies inside its owner triangle's swept volume.

use rayon::prelude::*;

use super::filter::{shared_corners, PairFilter};
use super::{Step, Topology};
use crate::math::{lerp, DVec3, UNIT_ROUNDOFF};

/// An axis-aligned box swept by a feature (or a set of triangles) over the step: a point
/// moving linearly stays in the box of its two end positions. Exact: min and max do not round.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweptBox {
    /// Smallest coordinates.
    pub lo: DVec3,
    /// Largest coordinates.
    pub hi: DVec3,
}

impl SweptBox {
    /// The empty box, which overlaps nothing.
    pub const EMPTY: Self = Self {
        lo: DVec3::INFINITY,
        hi: DVec3::NEG_INFINITY,
    };

    /// Grows the box to hold `p`.
    #[inline]
    pub fn add(&mut self, p: DVec3) {
        self.lo = self.lo.min(p);
        self.hi = self.hi.max(p);
    }

    /// Whether the closed boxes share a point (touching counts).
    #[inline]
    pub fn overlaps(&self, other: &Self) -> bool {
        self.lo.cmple(other.hi).all() && other.lo.cmple(self.hi).all()
    }

    #[inline]
    pub fn merge(&self, other: &Self) -> Self {
        Self {
            lo: self.lo.min(other.lo),
            hi: self.hi.max(other.hi),
        }
    }

    /// The box of a vertex moving from `a` to `b`, over `[0, tmax]` (the whole step for
    /// `tmax >= 1`), as [`FeatureBoxes::sweep`] computes it: see there.
    #[inline]
    pub fn vertex_until(a: DVec3, b: DVec3, tmax: f64) -> Self {
        if tmax.is_nan() || tmax >= 1.0 {
            return Self {
                lo: a.min(b),
                hi: a.max(b),
            };
        }
        let c = lerp(a, b, tmax.max(0.0));
        let pad = 8.0 * UNIT_ROUNDOFF * a.abs().max(b.abs());
        Self {
            lo: a.min(c) - pad,
            hi: a.max(c) + pad,
        }
    }

    /// Whether the boxes come within `sep` of each other along every axis (a necessary
    /// condition for the features to come within `sep`). Exact: no rounding is involved.
    #[inline]
    pub fn near(&self, other: &Self, sep: f64) -> bool {
        self.lo.x <= other.hi.x + sep
            && other.lo.x <= self.hi.x + sep
            && self.lo.y <= other.hi.y + sep
            && other.lo.y <= self.hi.y + sep
            && self.lo.z <= other.hi.z + sep
            && other.lo.z <= self.hi.z + sep
    }
}

/// Items per piece of the parallel loops (on the current rayon pool; the results do not
/// depend on the thread count).
const PAR_LEN: usize = 1 << 13;

/// The boxes swept by the vertices and the faces over `[0, tmax]`, the whole step or its
/// start. An edge's box is the union of its vertices' ([`FeatureBoxes::edge`]), computed where
/// it is needed rather than stored (edges are the most numerous features).
#[derive(Clone, Debug, Default)]
pub struct FeatureBoxes {
    /// Swept box of each vertex (unreferenced ones included, though never used).
    pub vertex: Vec<SweptBox>,
    /// Swept box of each triangle: the union of its vertices'.
    pub face: Vec<SweptBox>,
}

impl FeatureBoxes {
    /// Recomputes the boxes swept over `[0, tmax]` (the whole step for `tmax >= 1` or NaN).
    /// Over the whole step a box is exact (min and max do not round). Over `[0, tmax]` it
    /// holds the positions at 0 and at `tmax`, the latter interpolated as `a + (b - a) tmax`
    /// with three roundings, at most `5 u max(|a|, |b|)` per coordinate, so it is padded by
    /// `8 u max(|a|, |b|)`.
    pub fn sweep(&mut self, step: &Step, tmax: f64) {
        let (x0, x1) = (step.pos0(), step.pos1());
        let ends = x0.par_iter().zip(x1).with_min_len(PAR_LEN);
        self.vertex.clear();
        self.vertex
            .par_extend(ends.map(|(&a, &b)| SweptBox::vertex_until(a, b, tmax)));
        let vb = &self.vertex;
        self.face.clear();
        self.face
            .par_extend(step.triangles().par_iter().with_min_len(PAR_LEN).map(|t| {
                t.iter()
                    .fold(SweptBox::EMPTY, |b, &v| b.merge(&vb[v as usize]))
            }));
    }

    /// The box swept by the edge `[i, j]`: the union of its vertices' (exact).
    #[inline]
    pub fn edge(&self, [i, j]: [u32; 2]) -> SweptBox {
        self.vertex[i as usize].merge(&self.vertex[j as usize])
    }
}

/// What [`Features::triangle_pair`] reads of one triangle, two to a cache line: its vertices,
/// its edges, and which of them it owns.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(align(32))]
pub struct OwnedFeatures {
    /// The triangle's vertices `[a, b, c]`.
    pub vertices: [u32; 3],
    /// Its edges `ab`, `bc`, `ca` (indices into `topo.edges`).
    pub edges: [u32; 3],
    /// Bit `i` set: it owns `vertices[i]`.
    pub vertex_mask: u8,
    /// Bit `k` set: it owns `edges[k]`, from `vertices[k]` to `vertices[(k + 1) % 3]`.
    pub edge_mask: u8,
}

/// The set bits of a 3-bit mask, in increasing order.
#[inline]
fn bits(mask: u8) -> impl Iterator<Item = usize> {
    (0..3).filter(move |&i| mask >> i & 1 == 1)
}

/// Per-step feature data, with buffers reused across steps.
#[derive(Clone, Debug, Default)]
pub struct Features {
    /// Edges and incidences.
    pub topo: Topology,
    /// Per triangle: its vertices and the features it owns.
    pub owned: Vec<OwnedFeatures>,
    /// The features' boxes, swept over the whole step (over its start only for the first pass
    /// of an Earliest query).
    pub boxes: FeatureBoxes,
    /// The triangles and vertex count that `topo` and `owned` were derived from, once derived.
    derived_from: Option<(Vec<[u32; 3]>, usize)>,
}

impl Features {
    /// Whether `step` has the very triangles (same indices, same order) and vertex count that
    /// the topology was last derived from: then [`Features::update`] keeps it.
    pub fn same_topology(&self, step: &Step) -> bool {
        self.derived_from
            .as_ref()
            .is_some_and(|(t, n)| *n == step.vertex_count() && t[..] == *step.triangles())
    }

    /// Recomputes everything for `step`: the boxes always (swept over `[0, tmax]`, the whole
    /// step for `tmax >= 1`), the topology and the ownership only when `same_topology` is
    /// false (the caller's [`Features::same_topology`]; a simulator's everyday step keeps its
    /// triangles, and an exact comparison of them costs far less than the edges' derivation).
    pub fn update(&mut self, step: &Step, same_topology: bool, tmax: f64) {
        let tris = step.triangles();
        self.boxes.sweep(step, tmax);
        if same_topology {
            debug_assert!(self.same_topology(step));
            return;
        }
        self.topo = Topology::new(tris, step.vertex_count());
        let (from, count) = self.derived_from.get_or_insert_with(Default::default);
        from.clear();
        from.extend_from_slice(tris);
        *count = step.vertex_count();

        // A triangle owns a vertex or an edge when it is the lowest-numbered incident one.
        let topo = &self.topo;
        self.owned.clear();
        self.owned.par_extend(
            tris.par_iter()
                .zip(&topo.triangle_edges)
                .enumerate()
                .with_min_len(PAR_LEN)
                .map(|(t, (&vertices, &edges))| {
                    let t = t as u32;
                    let mut o = OwnedFeatures {
                        vertices,
                        edges,
                        ..OwnedFeatures::default()
                    };
                    for i in 0..3 {
                        if topo.triangles_of(vertices[i])[0] == t {
                            o.vertex_mask |= 1 << i;
                        }
                        if topo.edge_owner[edges[i] as usize] == t {
                            o.edge_mask |= 1 << i;
                        }
                    }
                    o
                }),
        );
    }

    /// Appends the candidate feature pairs of the overlapping triangle pair `[a, b]` (`a != b`)
    /// whose swept boxes (from `boxes`, usually [`Features::boxes`]) come within `sep`:
    /// `(vertex, face)` to `vf`, `(edge, edge)` (indices into `topo.edges`, smaller first) to
    /// `ee`. See the module documentation. Two triangles that share no vertex and that the
    /// filter finds apart ([`PairFilter::unshared_apart`]), or that share a vertex whose star
    /// is certified ([`PairFilter::shared_star`]), give none.
    ///
    /// Which vertices the two triangles share decides, through [`SHARED`], which of their
    /// owned feature pairs share no vertex; only those are looked at, in a fixed order: the
    /// first triangle's vertices against the second face, the second's against the first face,
    /// then the edge pairs, the first triangle's edge slowest. (Most overlapping triangle pairs
    /// of a mesh are neighbours, with few or none of those.)
    #[inline]
    pub fn triangle_pair(
        &self,
        boxes: &FeatureBoxes,
        [a, b]: [u32; 2],
        filter: &PairFilter<'_>,
        vf: &mut Vec<[u32; 2]>,
        ee: &mut Vec<[u32; 2]>,
    ) {
        debug_assert_ne!(a, b);
        let (oa, ob) = (&self.owned[a as usize], &self.owned[b as usize]);
        let (va, vb) = (oa.vertices, ob.vertices);
        let equal = shared_corners(va, vb);
        if equal == 0 {
            // Rule 5 only where some feature pair is left to drop.
            let nothing = oa.vertex_mask | ob.vertex_mask == 0 && edge_pairs(oa, ob, 0) == 0;
            if nothing || filter.unshared_apart(va, vb) {
                return;
            }
        } else if filter.shared_star(va, equal) {
            return;
        }
        let shared = SHARED[equal];
        let (a_vertices, b_vertices) = (
            oa.vertex_mask & !(shared >> 9) as u8 & 7,
            ob.vertex_mask & !(shared >> 12) as u8 & 7,
        );
        let sep = filter.sep;
        Self::vertices_face(boxes, a_vertices, va, b, vb, filter, vf);
        Self::vertices_face(boxes, b_vertices, vb, a, va, filter, vf);
        let mut pairs = edge_pairs(oa, ob, shared);
        while pairs != 0 {
            let bit = pairs.trailing_zeros() as usize;
            pairs &= pairs - 1;
            let (k, l) = (bit / 3, bit % 3);
            let (e0, e1) = (va[k], va[(k + 1) % 3]);
            let (f0, f1) = (vb[l], vb[(l + 1) % 3]);
            if boxes.edge([e0, e1]).near(&boxes.edge([f0, f1]), sep)
                && filter.edge_edge([e0, e1], [f0, f1])
            {
                let (e, f) = (oa.edges[k], ob.edges[l]);
                ee.push([e.min(f), e.max(f)]);
            }
        }
    }

    /// The vertices `tv[i]` for the bits `i` of `mask` against face `face` (vertices `tf`).
    #[inline(always)]
    fn vertices_face(
        boxes: &FeatureBoxes,
        mask: u8,
        tv: [u32; 3],
        face: u32,
        tf: [u32; 3],
        filter: &PairFilter<'_>,
        vf: &mut Vec<[u32; 2]>,
    ) {
        if mask == 0 {
            return;
        }
        let f_box = &boxes.face[face as usize];
        for i in bits(mask) {
            let v = tv[i];
            if boxes.vertex[v as usize].near(f_box, filter.sep) && filter.vertex_face(v, tf) {
                vf.push([v, face]);
            }
        }
    }
}

/// The owned edge pairs of two triangles that share no vertex, `shared` being [`SHARED`] of
/// their shared corners: bit `3 k + l` for edge `k` of the first and edge `l` of the second.
#[inline(always)]
fn edge_pairs(oa: &OwnedFeatures, ob: &OwnedFeatures, shared: u16) -> u16 {
    SPREAD[oa.edge_mask as usize] & (ob.edge_mask as u16 * 0b001_001_001) & !shared & 0x1ff
}

/// `SPREAD[m]`: bits `3 k .. 3 k + 3` set for each bit `k` of the 3-bit mask `m` (with a
/// mask `n` repeated in each group of three, the bits `3 k + l` of the pairs `(k in m, l in n)`).
const SPREAD: [u16; 8] = {
    let mut t = [0u16; 8];
    let mut m = 0;
    while m < 8 {
        let mut k = 0;
        while k < 3 {
            if m >> k & 1 == 1 {
                t[m] |= 0b111 << (3 * k);
            }
            k += 1;
        }
        m += 1;
    }
    t
};

/// For the mask `equal` of which vertices of two triangles coincide (bit `3 i + j`: vertex
/// `i` of the first is vertex `j` of the second), `SHARED[equal]` has bit `3 k + l` set when
/// edge `k` of the first (from vertex `k` to `k + 1`) and edge `l` of the second share a
/// vertex, bit `9 + i` when vertex `i` of the first is one of the second's, and bit `12 + j`
/// when vertex `j` of the second is one of the first's.
const SHARED: [u16; 512] = {
    const fn equal(mask: usize, i: usize, j: usize) -> bool {
        mask >> (3 * (i % 3) + j % 3) & 1 == 1
    }
    let mut t = [0u16; 512];
    let mut mask = 0;
    while mask < 512 {
        let mut i = 0;
        while i < 3 {
            let mut j = 0;
            while j < 3 {
                if equal(mask, i, j) || equal(mask, i, j + 1) || equal(mask, i + 1, j) || equal(mask, i + 1, j + 1) {
                    t[mask] |= 1 << (3 * i + j);
                }
                if equal(mask, i, j) {
                    t[mask] |= 1 << (9 + i) | 1 << (12 + j);
                }
                j += 1;
            }
            i += 1;
        }
        mask += 1;
    }
    t
};
