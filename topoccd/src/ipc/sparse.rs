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
    /// the union of the stencils' 3x3 vertex blocks, found by sorting the vertex pairs once.
    pub(crate) fn from_vertex_blocks(
        n_vertices: usize,
        ids: &[u32],
        offsets: &[usize],
        vals: &[f64],
    ) -> Self {
        let mut keys: Vec<u64> = Vec::new();
        for w in offsets.windows(2) {
            let s = &ids[w[0]..w[1]];
            for &a in s {
                for &b in s {
                    keys.push((u64::from(a) << 32) | u64::from(b));
                }
            }
        }
        keys.sort_unstable();
        keys.dedup();
        // Blocks per vertex row and their columns.
        let mut row_start = vec![0usize; n_vertices + 1];
        let cols: Vec<u32> = keys.iter().map(|&k| k as u32).collect();
        for &k in &keys {
            row_start[(k >> 32) as usize + 1] += 1;
        }
        for v in 0..n_vertices {
            row_start[v + 1] += row_start[v];
        }
        let n = 3 * n_vertices;
        let mut indptr = vec![0usize; n + 1];
        let mut indices = vec![0usize; 9 * keys.len()];
        for v in 0..n_vertices {
            let (s, e) = (row_start[v], row_start[v + 1]);
            let len = e - s;
            for a in 0..3 {
                let base = 9 * s + a * 3 * len;
                indptr[3 * v + a + 1] = base + 3 * len;
                for (ci, &c) in cols[s..e].iter().enumerate() {
                    for b in 0..3 {
                        indices[base + 3 * ci + b] = 3 * c as usize + b;
                    }
                }
            }
        }
        let mut data = vec![0.0f64; 9 * keys.len()];
        let mut off = 0usize;
        for w in offsets.windows(2) {
            let s = &ids[w[0]..w[1]];
            let m = 3 * s.len();
            for (k, &a) in s.iter().enumerate() {
                let (rs, re) = (row_start[a as usize], row_start[a as usize + 1]);
                let len = re - rs;
                for (l, &b) in s.iter().enumerate() {
                    let ci = rs
                        + cols[rs..re]
                            .binary_search(&b)
                            .expect("a block of the pattern")
                        - rs;
                    for i in 0..3 {
                        let base = 9 * rs + i * 3 * len + 3 * ci;
                        let row = &vals[off + (3 * k + i) * m + 3 * l..][..3];
                        for j in 0..3 {
                            data[base + j] += row[j];
                        }
                    }
                }
            }
            off += m * m;
        }
        Self {
            n,
            indptr,
            indices,
            data,
        }
    }
}
