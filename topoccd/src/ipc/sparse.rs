//! A sparse symmetric matrix as triplets and as CSR, for any Rust sparse solver.

// Index loops over small fixed-size arrays read as the formulas do.
#![allow(clippy::needless_range_loop)]

/// A square sparse matrix of size `n x n`, kept both as triplets (row, column, value; one
/// per nonzero, sorted by row then column, duplicates summed) and as compressed sparse rows.
///
/// - faer: `SparseColMat::try_new_from_triplets(n, n, &triplets)` with
///   `Triplet::new(row, col, val)` from [`triplets`](Self::triplets) (the matrix is
///   symmetric, so the CSR arrays read as CSC too);
/// - sprs: `CsMat::new((n, n), indptr, indices, data)` from [`csr`](Self::csr), or a
///   `TriMat` filled from the triplets.
///
/// ```
/// use topoccd::ipc::SparseMatrix;
/// let m = SparseMatrix::from_triplets(2, vec![(1, 1, 2.0), (0, 1, 1.0), (1, 1, 3.0), (1, 0, 1.0)]);
/// assert_eq!(m.triplets().collect::<Vec<_>>(), [(0, 1, 1.0), (1, 0, 1.0), (1, 1, 5.0)]);
/// let (indptr, indices, data) = m.csr();
/// assert_eq!((indptr, indices, data), (&[0, 1, 3][..], &[1, 0, 1][..], &[1.0, 1.0, 5.0][..]));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SparseMatrix {
    n: usize,
    indptr: Vec<usize>,
    indices: Vec<usize>,
    data: Vec<f64>,
}

impl SparseMatrix {
    /// Sums the triplets into CSR (duplicates added; explicit zeros kept). Entries out of
    /// range are a bug of the caller and panic in debug builds.
    pub fn from_triplets(n: usize, mut triplets: Vec<(usize, usize, f64)>) -> Self {
        triplets.sort_unstable_by_key(|&(r, c, _)| (r, c));
        let mut indptr = vec![0usize; n + 1];
        let mut indices = Vec::with_capacity(triplets.len());
        let mut data: Vec<f64> = Vec::with_capacity(triplets.len());
        let mut last = (usize::MAX, usize::MAX);
        for (r, c, v) in triplets {
            debug_assert!(r < n && c < n);
            if (r, c) == last {
                *data.last_mut().expect("a previous entry") += v;
            } else {
                indices.push(c);
                data.push(v);
                indptr[r + 1] += 1;
                last = (r, c);
            }
        }
        for i in 0..n {
            indptr[i + 1] += indptr[i];
        }
        Self {
            n,
            indptr,
            indices,
            data,
        }
    }

    /// The size `n` (rows and columns).
    pub fn size(&self) -> usize {
        self.n
    }

    /// The number of stored entries.
    pub fn nnz(&self) -> usize {
        self.data.len()
    }

    /// The CSR arrays: `indptr` (length `n + 1`), `indices` (column of each entry, sorted in
    /// each row) and `data`.
    pub fn csr(&self) -> (&[usize], &[usize], &[f64]) {
        (&self.indptr, &self.indices, &self.data)
    }

    /// The entries as `(row, column, value)`, sorted by row then column.
    pub fn triplets(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        (0..self.n).flat_map(move |r| {
            (self.indptr[r]..self.indptr[r + 1]).map(move |k| (r, self.indices[k], self.data[k]))
        })
    }

    /// `y = A x` (`x` of length `n`).
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        (0..self.n)
            .map(|r| {
                (self.indptr[r]..self.indptr[r + 1])
                    .map(|k| self.data[k] * x[self.indices[k]])
                    .sum()
            })
            .collect()
    }

    /// The entry at `(row, col)` (0 if not stored).
    pub fn get(&self, row: usize, col: usize) -> f64 {
        let (s, e) = (self.indptr[row], self.indptr[row + 1]);
        match self.indices[s..e].binary_search(&col) {
            Ok(k) => self.data[s + k],
            Err(_) => 0.0,
        }
    }

    /// The sum of dense local Hessians over vertex stencils, as a `3 n x 3 n` matrix: the
    /// collision `c` names the vertices `ids[offsets[c]..offsets[c + 1]]` and holds the
    /// `3 k x 3 k` row-major block `vals[...]` (the blocks laid end to end). The pattern is
    /// the union of the stencils' 3x3 vertex blocks.
    pub(crate) fn from_vertex_blocks(
        n_vertices: usize,
        ids: &[u32],
        offsets: &[usize],
        vals: &[f64],
    ) -> Self {
        let pattern = BlockPattern::new(n_vertices, FlatStencils { ids, offsets });
        let mut data = vec![0.0f64; pattern.nnz()];
        let mut off = 0usize;
        for (c, w) in offsets.windows(2).enumerate() {
            let s = &ids[w[0]..w[1]];
            let m = 3 * s.len();
            pattern.add(c, s, &vals[off..off + m * m], &mut data);
            off += m * m;
        }
        pattern.into_matrix(data)
    }
}

/// A sequence of vertex stencils (the vertices of each collision, at most 4), visited in a
/// fixed order.
pub(crate) trait StencilSource {
    /// Calls `f` on each stencil in order.
    fn for_each(&self, f: impl FnMut(&[u32]));
}

/// Stencils laid end to end: stencil `c` is `ids[offsets[c]..offsets[c + 1]]`.
struct FlatStencils<'a> {
    ids: &'a [u32],
    offsets: &'a [usize],
}

impl StencilSource for FlatStencils<'_> {
    fn for_each(&self, mut f: impl FnMut(&[u32])) {
        for w in self.offsets.windows(2) {
            f(&self.ids[w[0]..w[1]]);
        }
    }
}

/// The block pattern of a sum of local Hessians over vertex stencils, built from the
/// vertex indices alone, with the place of every local block in the CSR data: local
/// Hessians are then added straight into the matrix, in any order, with no search.
///
/// Vertex row `a` holds the blocks `row_start[a]..row_start[a + 1]`, sorted by column
/// vertex (`cols`). The local Hessians are summed block by block (each block's 9 entries
/// side by side, so that adding one touches one or two cache lines, not three rows), and
/// [`into_matrix`](Self::into_matrix) lays the blocks out as CSR rows in one pass.
pub(crate) struct BlockPattern {
    n_vertices: usize,
    /// Per vertex row, its first block (`n_vertices + 1` entries).
    row_start: Vec<usize>,
    /// The column vertex of each block.
    cols: Vec<u32>,
    /// Per stencil, its first entry in `slots`.
    first: Vec<usize>,
    /// Per stencil entry `(k, l)` (row-major over the stencil's vertices), the block's index
    /// within row `ids[k]`.
    slots: Vec<u32>,
}

impl BlockPattern {
    /// The pattern of the stencils of `source` over `n_vertices` vertices. Stencils name
    /// vertices below `n_vertices` (checked in debug builds).
    pub(crate) fn new(n_vertices: usize, source: impl StencilSource) -> Self {
        // Entries per vertex row, and per stencil its first entry.
        let mut row_count = vec![0usize; n_vertices + 1];
        let mut first = Vec::new();
        let mut total = 0usize;
        source.for_each(|s| {
            first.push(total);
            total += s.len() * s.len();
            for &a in s {
                debug_assert!((a as usize) < n_vertices);
                row_count[a as usize + 1] += s.len();
            }
        });
        first.push(total);
        assert!(
            total <= u32::MAX as usize,
            "BlockPattern: more than 2^32 stencil entries"
        );
        for v in 0..n_vertices {
            row_count[v + 1] += row_count[v];
        }
        // Bucket the entries by row: (column << 32 | entry).
        let mut cursor = row_count.clone();
        let mut keys = vec![0u64; total];
        let mut e = 0usize;
        source.for_each(|s| {
            for &a in s {
                let at = &mut cursor[a as usize];
                for &b in s {
                    keys[*at] = (u64::from(b) << 32) | e as u64;
                    *at += 1;
                    e += 1;
                }
            }
        });
        let mut row_start = vec![0usize; n_vertices + 1];
        let mut cols = Vec::with_capacity(total / 2);
        let mut slots = vec![0u32; total];
        for a in 0..n_vertices {
            let row = &mut keys[row_count[a]..row_count[a + 1]];
            row.sort_unstable();
            let start = cols.len();
            let mut last = u64::MAX;
            for &k in row.iter() {
                let col = k >> 32;
                if col != last {
                    cols.push(col as u32);
                    last = col;
                }
                slots[(k & 0xffff_ffff) as usize] = (cols.len() - 1 - start) as u32;
            }
            row_start[a + 1] = cols.len();
        }
        Self {
            n_vertices,
            row_start,
            cols,
            first,
            slots,
        }
    }

    /// The number of stored entries (9 per block).
    pub(crate) fn nnz(&self) -> usize {
        9 * self.cols.len()
    }

    /// Adds the `3 k x 3 k` row-major local Hessian `h` of stencil number `stencil`, whose
    /// vertices are `ids` (as the source gave them), into the blocks `data` (`nnz` entries,
    /// block by block).
    #[inline]
    pub(crate) fn add(&self, stencil: usize, ids: &[u32], h: &[f64], data: &mut [f64]) {
        let k = ids.len();
        let m = 3 * k;
        debug_assert_eq!(h.len(), m * m);
        let slots = &self.slots[self.first[stencil]..][..k * k];
        for (ka, &a) in ids.iter().enumerate() {
            let rs = self.row_start[a as usize];
            for lb in 0..k {
                let block = &mut data[9 * (rs + slots[ka * k + lb] as usize)..][..9];
                for i in 0..3 {
                    let src = &h[(3 * ka + i) * m + 3 * lb..][..3];
                    for j in 0..3 {
                        block[3 * i + j] += src[j];
                    }
                }
            }
        }
    }

    /// The matrix of the summed blocks `blocks` (as [`add`](Self::add) fills them) in CSR:
    /// the entry `(3 a + i, 3 b + j)` of the `k`-th block of row `a` goes to
    /// `9 row_start[a] + 3 i len_a + 3 k + j`, `len_a` the row's number of blocks.
    pub(crate) fn into_matrix(self, blocks: Vec<f64>) -> SparseMatrix {
        debug_assert_eq!(blocks.len(), self.nnz());
        let n = 3 * self.n_vertices;
        let mut indptr = vec![0usize; n + 1];
        let mut indices = vec![0usize; self.nnz()];
        let mut data = vec![0.0f64; self.nnz()];
        for v in 0..self.n_vertices {
            let (s, e) = (self.row_start[v], self.row_start[v + 1]);
            let len = e - s;
            for a in 0..3 {
                let base = 9 * s + a * 3 * len;
                indptr[3 * v + a + 1] = base + 3 * len;
                for (ci, &c) in self.cols[s..e].iter().enumerate() {
                    let block = &blocks[9 * (s + ci) + 3 * a..][..3];
                    for b in 0..3 {
                        indices[base + 3 * ci + b] = 3 * c as usize + b;
                        data[base + 3 * ci + b] = block[b];
                    }
                }
            }
        }
        SparseMatrix {
            n,
            indptr,
            indices,
            data,
        }
    }
}
