//! The fixed sparsity pattern of the Hessian (upper triangle, compressed sparse
//! columns) and the scatter map that places element blocks into it.

use std::collections::BTreeSet;

/// Upper-triangular CSC pattern of a block-sparse symmetric matrix with 3×3 blocks.
#[derive(Clone, Debug)]
pub struct HessianPattern {
    /// Column pointers (length `n + 1`).
    pub col_ptr: Vec<usize>,
    /// Row indices, sorted within each column.
    pub row_idx: Vec<usize>,
    /// Per block column: the sorted block rows (≤ column) present.
    block_rows: Vec<Vec<usize>>,
    /// Per block column, per present block row: value offsets of the 3 scalar columns.
    block_offsets: Vec<Vec<[usize; 3]>>,
}

/// Where one local 3×3 block of an element Hessian goes.
#[derive(Clone, Copy, Debug)]
pub struct ScatterBlock {
    /// Local block index of the rows (global row block ≤ global column block).
    pub local_row: usize,
    /// Local block index of the columns.
    pub local_col: usize,
    /// Value offsets of the three scalar columns of the global block.
    pub offsets: [usize; 3],
    /// Whether the block is on the diagonal (only its upper triangle is stored).
    pub diagonal: bool,
}

impl HessianPattern {
    /// The pattern of `block_count` blocks coupled by the given elements (each a list of
    /// global blocks).
    pub fn new<'a>(block_count: usize, elements: impl Iterator<Item = &'a [usize]>) -> Self {
        let mut sets: Vec<BTreeSet<usize>> =
            (0..block_count).map(|b| BTreeSet::from([b])).collect();
        for blocks in elements {
            for &a in blocks {
                for &b in blocks {
                    if a <= b {
                        sets[b].insert(a);
                    }
                }
            }
        }
        let block_rows: Vec<Vec<usize>> =
            sets.into_iter().map(|s| s.into_iter().collect()).collect();
        let n = 3 * block_count;
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        let mut block_offsets: Vec<Vec<[usize; 3]>> = block_rows
            .iter()
            .map(|rows| vec![[0; 3]; rows.len()])
            .collect();
        col_ptr.push(0);
        for (col_block, rows) in block_rows.iter().enumerate() {
            for k in 0..3 {
                for (slot, &row_block) in rows.iter().enumerate() {
                    block_offsets[col_block][slot][k] = row_idx.len();
                    let last = if row_block == col_block { k } else { 2 };
                    for i in 0..=last {
                        row_idx.push(3 * row_block + i);
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        Self {
            col_ptr,
            row_idx,
            block_rows,
            block_offsets,
        }
    }

    /// Number of stored values.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Dimension of the matrix.
    pub fn dim(&self) -> usize {
        self.col_ptr.len() - 1
    }

    /// Whether every block couples only to blocks at most 3 positions before it (the
    /// natural numbering of a single rod): then the identity is a fill-free ordering.
    pub fn is_banded(&self) -> bool {
        self.block_rows
            .iter()
            .enumerate()
            .all(|(col, rows)| rows.first().is_none_or(|&first| col - first <= 3))
    }

    /// The block-level structure (upper triangle with diagonal) as CSC column pointers
    /// and row indices, one entry per 3×3 block: the graph a fill-reducing ordering
    /// needs, 9× smaller than the scalar pattern.
    pub fn block_structure(&self) -> (Vec<usize>, Vec<usize>) {
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        for rows in &self.block_rows {
            row_idx.extend_from_slice(rows);
            col_ptr.push(row_idx.len());
        }
        (col_ptr, row_idx)
    }

    /// Value offsets of global block `(row_block, col_block)`, `row_block ≤ col_block`.
    pub fn offsets(&self, row_block: usize, col_block: usize) -> [usize; 3] {
        self.find_offsets(row_block, col_block)
            .expect("block in pattern")
    }

    /// [`HessianPattern::offsets`], or `None` if the pattern does not hold the block.
    pub fn find_offsets(&self, row_block: usize, col_block: usize) -> Option<[usize; 3]> {
        let slot = self.block_rows[col_block].binary_search(&row_block).ok()?;
        Some(self.block_offsets[col_block][slot])
    }

    /// The scatter map of an element whose local blocks map to `blocks` (`None` for an
    /// eliminated block).
    pub fn scatter(&self, blocks: &[Option<usize>]) -> Vec<ScatterBlock> {
        let mut out = Vec::new();
        for (a, ga) in blocks.iter().enumerate() {
            for (b, gb) in blocks.iter().enumerate() {
                if let (Some(ga), Some(gb)) = (ga, gb)
                    && (ga < gb || (ga == gb && a == b))
                {
                    out.push(ScatterBlock {
                        local_row: a,
                        local_col: b,
                        offsets: self.offsets(*ga, *gb),
                        diagonal: ga == gb,
                    });
                }
            }
        }
        out
    }
}

/// Adds the local Hessian `local` (square, `dim` × `dim` with `dim` a multiple of 3,
/// column-major as nalgebra stores it) into `values` by `scatter`: each scalar column
/// of a block is a contiguous run in both, added as one slice.
pub fn add_blocks(values: &mut [f64], scatter: &[ScatterBlock], local: &[f64], dim: usize) {
    for s in scatter {
        let (r0, c0) = (3 * s.local_row, 3 * s.local_col);
        for (k, &base) in s.offsets.iter().enumerate() {
            let rows = if s.diagonal { k + 1 } else { 3 };
            let column = &local[(c0 + k) * dim + r0..][..rows];
            for (value, &add) in values[base..base + rows].iter_mut().zip(column) {
                *value += add;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pattern_of_a_chain_is_upper_block_tridiagonal() {
        let elements: Vec<Vec<usize>> = vec![vec![0, 1], vec![1, 2]];
        let p = HessianPattern::new(3, elements.iter().map(|e| e.as_slice()));
        assert_eq!(p.dim(), 9);
        // Diagonal blocks 6 each, two off-diagonal blocks 9 each.
        assert_eq!(p.nnz(), 3 * 6 + 2 * 9);
        let off = p.offsets(1, 2);
        assert_eq!(p.row_idx[off[0]], 3);
        assert_eq!(p.row_idx[off[2] + 2], 5);
        for c in 0..9 {
            let rows = &p.row_idx[p.col_ptr[c]..p.col_ptr[c + 1]];
            assert!(rows.windows(2).all(|w| w[0] < w[1]) && rows.iter().all(|&r| r <= c));
        }
    }
}
