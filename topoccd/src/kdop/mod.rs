//! Discrete oriented polytopes (k-DOPs): bounding volumes with k/2 fixed slab directions.
//!
//! A k-DOP is the intersection of `k/2` slabs `lo[i] <= n_i . x <= hi[i]`, one per direction
//! `n_i` of a fixed set. The directions have small integer coordinates (not unit length), so a
//! projection is a handful of additions; [`DopKind`] names the four standard sets:
//!
//! | k  | directions                                                        |
//! |----|-------------------------------------------------------------------|
//! | 6  | the axes `x, y, z` (an axis-aligned box)                          |
//! | 14 | the axes and the 4 cube diagonals `(1, ±1, ±1)`                   |
//! | 18 | the axes and the 6 edge diagonals `x±y, x±z, y±z`                 |
//! | 26 | all 13 of them                                                    |
//!
//! [`Kdop<H>`] holds `H = k/2` slabs; it is monomorphised for `H` = 3, 7, 9 and 13, and a query
//! dispatches on [`DopKind`] once, at the top.

mod compact;
mod volume;

pub use compact::CompactKdop;
pub use volume::Kdop;

/// The 13 directions used by the k-DOPs, grouped: axes, cube diagonals, edge diagonals.
const AXES: [[i8; 3]; 3] = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
const CUBE_DIAGONALS: [[i8; 3]; 4] = [[1, 1, 1], [1, -1, 1], [1, 1, -1], [1, -1, -1]];
const EDGE_DIAGONALS: [[i8; 3]; 6] = [
    [1, 1, 0],
    [1, 0, 1],
    [0, 1, 1],
    [1, -1, 0],
    [1, 0, -1],
    [0, 1, -1],
];

/// Which of the four standard k-DOPs to use. The number is `k`, the count of bounding planes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum DopKind {
    /// 6-DOP: an axis-aligned box.
    K6,
    /// 14-DOP: axes and cube diagonals.
    K14,
    /// 18-DOP: axes and edge diagonals (the paper's choice; the default).
    #[default]
    K18,
    /// 26-DOP: axes, cube diagonals and edge diagonals.
    K26,
}

impl DopKind {
    /// All four kinds, in increasing `k`.
    pub const ALL: [DopKind; 4] = [DopKind::K6, DopKind::K14, DopKind::K18, DopKind::K26];

    /// The number of bounding planes `k` (6, 14, 18 or 26).
    pub fn k(self) -> usize {
        2 * self.slabs()
    }

    /// The number of slabs `k/2` (3, 7, 9 or 13), the `H` of `Kdop<H>`.
    pub fn slabs(self) -> usize {
        match self {
            DopKind::K6 => 3,
            DopKind::K14 => 7,
            DopKind::K18 => 9,
            DopKind::K26 => 13,
        }
    }

    /// The kind with `k` bounding planes, if `k` is 6, 14, 18 or 26.
    ///
    /// ```
    /// use topoccd::kdop::DopKind;
    /// assert_eq!(DopKind::from_k(18), Some(DopKind::K18));
    /// assert_eq!(DopKind::from_k(8), None);
    /// ```
    pub fn from_k(k: usize) -> Option<Self> {
        DopKind::ALL.into_iter().find(|kind| kind.k() == k)
    }

    /// The slab directions, in the order of the slabs of `Kdop`: the axes first, then the
    /// cube diagonals (k = 14, 26), then the edge diagonals (k = 18, 26).
    ///
    /// ```
    /// use topoccd::kdop::DopKind;
    /// assert_eq!(DopKind::K18.directions().len(), 9);
    /// assert_eq!(DopKind::K6.directions()[2], [0, 0, 1]);
    /// ```
    pub fn directions(self) -> Vec<[i8; 3]> {
        let mut dirs = AXES.to_vec();
        if matches!(self, DopKind::K14 | DopKind::K26) {
            dirs.extend_from_slice(&CUBE_DIAGONALS);
        }
        if matches!(self, DopKind::K18 | DopKind::K26) {
            dirs.extend_from_slice(&EDGE_DIAGONALS);
        }
        dirs
    }
}

impl std::fmt::Display for DopKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.k())
    }
}

/// The Euclidean norm of each slab direction of a `Kdop<H>`: 1 for axes, `sqrt(3)` for cube
/// diagonals, `sqrt(2)` for edge diagonals. Inflating a k-DOP by a distance `d` moves slab `i`
/// by `d * norms[i]`.
pub(crate) fn norms<const H: usize>() -> [f64; H] {
    let mut out = [1.0; H];
    let (s2, s3) = (std::f64::consts::SQRT_2, 3f64.sqrt());
    match H {
        3 => {}
        7 => out[3..7].fill(s3),
        9 => out[3..9].fill(s2),
        13 => {
            out[3..7].fill(s3);
            out[7..13].fill(s2);
        }
        _ => unreachable!("a k-DOP has 3, 7, 9 or 13 slabs, not {H}"),
    }
    out
}
