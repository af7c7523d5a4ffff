//! What the broad phases hand down to the narrow phase: buffers of candidate feature pairs,
//! and the swept volumes of the owner triangles that every method tests them with.

use crate::kdop::Kdop;
use crate::mesh::Step;

/// Candidate feature pairs: `[vertex, face]` and `[e, f]` (indices into the step's sorted
/// edges, `e < f`).
#[derive(Clone, Debug, Default)]
pub(crate) struct Candidates {
    pub vf: Vec<[u32; 2]>,
    pub ee: Vec<[u32; 2]>,
}

impl Candidates {
    pub fn clear(&mut self) {
        self.vf.clear();
        self.ee.clear();
    }

    pub fn len(&self) -> usize {
        self.vf.len() + self.ee.len()
    }

    /// Makes room, fallibly, for `more`'s candidates (a buffer that records them all).
    pub fn grow_for(&mut self, more: &Candidates) -> Result<(), crate::alloc::AllocError> {
        crate::alloc::grow(&mut self.vf, more.vf.len(), "recorded candidates")?;
        crate::alloc::grow(&mut self.ee, more.ee.len(), "recorded candidates")
    }
}

/// The k-DOP swept by triangle `t` over `[0, tmax]` (the whole step for `tmax >= 1`),
/// inflated by `inflation`, as a function of `t`.
pub(crate) fn triangle_volume<'a, const H: usize>(
    step: &'a Step<'_>,
    tmax: f64,
    inflation: f64,
) -> impl Fn(u32) -> Kdop<H> + Sync + Send + Copy + 'a {
    let (x0, x1, tris) = (step.pos0(), step.pos1(), step.triangles());
    move |t| {
        let [a, b, c] = tris[t as usize].map(|i| i as usize);
        let (t0, t1) = ([x0[a], x0[b], x0[c]], [x1[a], x1[b], x1[c]]);
        Kdop::swept_triangle_until(&t0, &t1, tmax, inflation)
    }
}
