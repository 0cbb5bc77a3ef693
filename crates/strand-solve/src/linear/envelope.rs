//! Block envelope (profile, skyline) Cholesky `A = L Lᵀ` for matrices whose 3×3
//! blocks lie in a narrow band around the diagonal, such as the Hessian of a rod
//! numbered along its length (positions and edge rotations interleaved: every element
//! couples blocks at most a few positions apart).
//!
//! Block row `I` of `L` is stored densely from its first nonzero block column
//! `first[I]` (the first block row of block column `I` of the upper-triangular
//! pattern) to the diagonal. Cholesky never fills outside this envelope, so the storage
//! is fixed once and needs no symbolic analysis; every update is a fixed-size 3×3
//! product with no index indirection. The pivots are those of the scalar Cholesky in
//! the same order, so positive definiteness is decided exactly as by a scalar
//! factorisation. For `B` blocks of row width `w` blocks (at most 4 for a rod) the
//! factorisation costs about `B·w²/2` block products of 27 multiply-adds.

use strand_system::HessianPattern;

mod signed;

/// A 3×3 block, row-major: entry `(i, j)` at `3 i + j`.
type Block = [f64; 9];

/// Numeric block envelope factorisation of matrices with one fixed pattern.
#[derive(Clone)]
pub(crate) struct EnvelopeCholesky {
    /// Per block row of `L`: its first stored block column.
    first: Vec<usize>,
    /// Per block row of `L`: the offset of its first stored block in `blocks` (length
    /// `B + 1`; the diagonal block of row `I` is at `start[I + 1] − 1`).
    start: Vec<usize>,
    /// Per stored value of the pattern (upper CSC order): where it goes in the lower
    /// triangle of `L`'s storage, as block offset times 9 plus the entry in the block.
    /// The upper triangles of the diagonal blocks are never read, so they get nothing.
    scatter: Vec<usize>,
    /// Blocks of the envelope that the pattern does not hold (zero in `A`, filled in
    /// by the factorisation): the only ones to clear before scattering.
    gaps: Vec<usize>,
    /// The block rows of `L` (after a factorisation; the upper triangles of the
    /// diagonal blocks hold scratch).
    blocks: Vec<Block>,
    /// Per block row: the reciprocals of the diagonal of `L_II`.
    inverse_diagonal: Vec<[f64; 3]>,
    /// Per block row: the signs (±1) of the pivots of the last signed factorisation
    /// ([`EnvelopeCholesky::factor_signed`]); empty until the first one.
    signs: Vec<[f64; 3]>,
}

impl EnvelopeCholesky {
    /// The block envelope of `pattern` (upper triangle, CSC, 3×3 blocks).
    pub(crate) fn new(pattern: &HessianPattern) -> Self {
        let (block_ptr, block_rows) = pattern.block_structure();
        let count = block_ptr.len() - 1;
        let first: Vec<usize> = (0..count)
            .map(|c| {
                block_rows[block_ptr[c]..block_ptr[c + 1]]
                    .first()
                    .map_or(c, |&r| r.min(c))
            })
            .collect();
        let mut start = Vec::with_capacity(count + 1);
        start.push(0);
        for (b, &f) in first.iter().enumerate() {
            start.push(start[b] + b - f + 1);
        }
        let mut scatter = Vec::with_capacity(pattern.nnz());
        for col in 0..pattern.dim() {
            for &row in &pattern.row_idx[pattern.col_ptr[col]..pattern.col_ptr[col + 1]] {
                // Upper entry (row, col) of A is entry (col, row) of block row col/3.
                let (block_row, block_col) = (col / 3, row / 3);
                let block = start[block_row] + block_col - first[block_row];
                scatter.push(9 * block + 3 * (col % 3) + row % 3);
            }
        }
        let mut held = vec![false; start[count]];
        for &lower in &scatter {
            held[lower / 9] = true;
        }
        let gaps = (0..start[count]).filter(|&b| !held[b]).collect();
        Self {
            blocks: vec![[0.0; 9]; start[count]],
            gaps,
            inverse_diagonal: vec![[0.0; 3]; count],
            signs: Vec::new(),
            first,
            start,
            scatter,
        }
    }

    /// Number of stored entries of `L` (the envelope, 9 per block).
    pub(crate) fn len(&self) -> usize {
        9 * self.blocks.len()
    }

    /// Number of stored entries of `L` for `pattern`, without building the envelope.
    pub(crate) fn size_of(pattern: &HessianPattern) -> usize {
        let (block_ptr, block_rows) = pattern.block_structure();
        (0..block_ptr.len() - 1)
            .map(|c| {
                let first = block_rows[block_ptr[c]..block_ptr[c + 1]]
                    .first()
                    .map_or(c, |&r| r.min(c));
                9 * (c - first + 1)
            })
            .sum()
    }

    /// The off-diagonal blocks of block row `i` in place: `S = A_ij − Σ_k X_ik L_jkᵀ`
    /// (`k` over the blocks both rows store), then `X_ij = S L_jj⁻ᵀ`, for `j` from
    /// `first[i]` to `i − 1`. `done` holds the finished rows before `i`, `row` row `i`
    /// from its first stored block. In [`EnvelopeCholesky::factor`] `X = L`; in
    /// `factor_signed` `X = W = L Σ` while the row is computed.
    /// (A function of the fields it reads, as `done` and `row` borrow `blocks`.)
    #[inline]
    fn eliminate_off_diagonal(
        first: &[usize],
        start: &[usize],
        inverse_diagonal: &[[f64; 3]],
        i: usize,
        done: &[Block],
        row: &mut [Block],
    ) {
        let fi = first[i];
        for j in fi..i {
            let fj = first[j];
            let k0 = fi.max(fj);
            let row_j = &done[start[j]..start[j + 1]];
            let (before, current) = row.split_at_mut(j - fi);
            let s = &mut current[0];
            for (a, b) in before[k0 - fi..].iter().zip(&row_j[k0 - fj..j - fj]) {
                subtract_product_transposed(s, a, b);
            }
            // X_ij = S L_jj⁻ᵀ: forward substitution on each row of S.
            let l = &row_j[j - fj];
            let inv = &inverse_diagonal[j];
            for r in 0..3 {
                let x0 = s[3 * r] * inv[0];
                let x1 = (s[3 * r + 1] - x0 * l[3]) * inv[1];
                let x2 = (s[3 * r + 2] - x0 * l[6] - x1 * l[7]) * inv[2];
                s[3 * r] = x0;
                s[3 * r + 1] = x1;
                s[3 * r + 2] = x2;
            }
        }
    }

    /// Factorises the matrix with the pattern's `values` (upper triangle). Returns
    /// `false` if a pivot is not positive (or not a number): the matrix is not
    /// positive definite.
    pub(crate) fn factor(&mut self, values: &[f64]) -> bool {
        // Every block the pattern holds is overwritten entirely where it is read: its
        // off-diagonal blocks are full, its diagonal blocks' lower triangles are (their
        // upper triangles are scratch, read by nothing).
        self.load(values);
        for i in 0..self.first.len() {
            let fi = self.first[i];
            let (done, rest) = self.blocks.split_at_mut(self.start[i]);
            let row = &mut rest[..i - fi + 1];
            Self::eliminate_off_diagonal(
                &self.first,
                &self.start,
                &self.inverse_diagonal,
                i,
                done,
                row,
            );
            let (off, diagonal) = row.split_at_mut(i - fi);
            let d = &mut diagonal[0];
            for a in off.iter() {
                subtract_product_transposed(d, a, a);
            }
            let Some(inverse) = cholesky_3x3(d) else {
                return false;
            };
            self.inverse_diagonal[i] = inverse;
        }
        true
    }

    /// Writes `values` (upper triangle of the pattern) into the envelope's blocks and
    /// clears the blocks the pattern does not hold.
    fn load(&mut self, values: &[f64]) {
        for &b in &self.gaps {
            self.blocks[b] = [0.0; 9];
        }
        let flat = self.blocks.as_flattened_mut();
        for (&lower, &v) in self.scatter.iter().zip(values) {
            flat[lower] = v;
        }
    }

    /// Solves `L Lᵀ x = rhs` in place with the last successful factorisation.
    pub(crate) fn solve_in_place(&self, rhs: &mut [f64]) {
        self.forward(rhs);
        self.backward(rhs);
    }

    /// `rhs ← L⁻¹ rhs`.
    fn forward(&self, rhs: &mut [f64]) {
        let count = self.first.len();
        for i in 0..count {
            let fi = self.first[i];
            let row = &self.blocks[self.start[i]..self.start[i + 1]];
            let mut s = [rhs[3 * i], rhs[3 * i + 1], rhs[3 * i + 2]];
            for (j, l) in (fi..i).zip(row) {
                let x = &rhs[3 * j..3 * j + 3];
                for r in 0..3 {
                    s[r] -= l[3 * r] * x[0] + l[3 * r + 1] * x[1] + l[3 * r + 2] * x[2];
                }
            }
            let (l, inv) = (&row[i - fi], &self.inverse_diagonal[i]);
            let y0 = s[0] * inv[0];
            let y1 = (s[1] - l[3] * y0) * inv[1];
            let y2 = (s[2] - l[6] * y0 - l[7] * y1) * inv[2];
            rhs[3 * i..3 * i + 3].copy_from_slice(&[y0, y1, y2]);
        }
    }

    /// `rhs ← L⁻ᵀ rhs`.
    fn backward(&self, rhs: &mut [f64]) {
        let count = self.first.len();
        for i in (0..count).rev() {
            let fi = self.first[i];
            let row = &self.blocks[self.start[i]..self.start[i + 1]];
            let (l, inv) = (&row[i - fi], &self.inverse_diagonal[i]);
            let x2 = rhs[3 * i + 2] * inv[2];
            let x1 = (rhs[3 * i + 1] - l[7] * x2) * inv[1];
            let x0 = (rhs[3 * i] - l[3] * x1 - l[6] * x2) * inv[0];
            rhs[3 * i..3 * i + 3].copy_from_slice(&[x0, x1, x2]);
            for (j, l) in (fi..i).zip(row) {
                let y = &mut rhs[3 * j..3 * j + 3];
                for c in 0..3 {
                    y[c] -= l[c] * x0 + l[3 + c] * x1 + l[6 + c] * x2;
                }
            }
        }
    }
}

/// `s −= a bᵀ` for 3×3 blocks.
fn subtract_product_transposed(s: &mut Block, a: &Block, b: &Block) {
    for r in 0..3 {
        for c in 0..3 {
            s[3 * r + c] -=
                a[3 * r] * b[3 * c] + a[3 * r + 1] * b[3 * c + 1] + a[3 * r + 2] * b[3 * c + 2];
        }
    }
}

/// Cholesky factor of the symmetric 3×3 block `d` (lower triangle read), in place
/// (lower triangle written). Returns the reciprocals of its diagonal; `None` if a
/// pivot is not positive.
fn cholesky_3x3(d: &mut Block) -> Option<[f64; 3]> {
    let p0 = d[0];
    if !is_positive(p0) {
        return None;
    }
    let l00 = p0.sqrt();
    let i0 = 1.0 / l00;
    let l10 = d[3] * i0;
    let l20 = d[6] * i0;
    let p1 = d[4] - l10 * l10;
    if !is_positive(p1) {
        return None;
    }
    let l11 = p1.sqrt();
    let i1 = 1.0 / l11;
    let l21 = (d[7] - l20 * l10) * i1;
    let p2 = d[8] - l20 * l20 - l21 * l21;
    if !is_positive(p2) {
        return None;
    }
    let l22 = p2.sqrt();
    d[0] = l00;
    d[3] = l10;
    d[6] = l20;
    d[4] = l11;
    d[7] = l21;
    d[8] = l22;
    Some([i0, i1, 1.0 / l22])
}

/// Whether a pivot is a positive number (`false` for zero, negative and NaN).
fn is_positive(pivot: f64) -> bool {
    pivot.partial_cmp(&0.0) == Some(std::cmp::Ordering::Greater)
}
