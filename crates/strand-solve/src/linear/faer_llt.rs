//! The general backend of [`super::SparseCholesky`]: faer's sparse Cholesky with the
//! symbolic analysis (fill-reducing ordering, elimination tree, supernodes) done once
//! per pattern and reused by every numeric factorisation; workspaces allocated once.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use std::sync::Arc;

use faer::{Conj, MatMut, Par, Side};
use strand_system::HessianPattern;

use crate::{LinearError, SolveError};

/// The pattern and faer's symbolic analysis of it (ordering, elimination tree).
#[derive(Clone)]
pub(crate) struct FaerAnalysis {
    structure: Arc<SymbolicSparseColMat<usize>>,
    symbolic: Arc<SymbolicCholesky<usize>>,
}

/// faer's sparse `LLᵀ` factorisation of matrices with one fixed pattern.
pub(crate) struct FaerCholesky {
    /// The pattern and its symbolic analysis, shared by the factorisers of one pattern
    /// ([`FaerCholesky::sharing_analysis`]).
    structure: Arc<SymbolicSparseColMat<usize>>,
    symbolic: Arc<SymbolicCholesky<usize>>,
    factor_values: Vec<f64>,
    factor_buffer: MemBuffer,
    solve_buffer: MemBuffer,
    /// The number of right-hand sides `solve_buffer` holds the workspace of.
    solve_columns: usize,
}

impl FaerCholesky {
    /// Symbolic analysis of the upper-triangular pattern: the natural numbering (along
    /// each rod) and, unless the pattern is banded (then the natural numbering is
    /// fill-free), the block AMD ordering are analysed, and the one with the sparser
    /// factor is kept.
    pub(crate) fn try_new(pattern: &HessianPattern) -> Result<Self, SolveError> {
        let n = pattern.dim();
        let structure = SymbolicSparseColMat::new_checked(
            n,
            n,
            pattern.col_ptr.clone(),
            None,
            pattern.row_idx.clone(),
        );
        let analyse = |ordering: SymmetricOrdering<'_, usize>| {
            factorize_symbolic_cholesky(
                structure.as_ref(),
                Side::Upper,
                ordering,
                CholeskySymbolicParams::default(),
            )
            .map_err(|e| LinearError::Failed {
                stage: "symbolic analysis",
                detail: format!("{e:?}"),
            })
        };
        let mut symbolic = analyse(SymmetricOrdering::Identity)?;
        if !pattern.is_banded() {
            let (forward, inverse) = block_amd_ordering(pattern)?;
            let amd = analyse(SymmetricOrdering::Custom(PermRef::new_checked(
                &forward, &inverse, n,
            )))?;
            if amd.len_val() < symbolic.len_val() {
                symbolic = amd;
            }
        }
        Self::with_analysis(&FaerAnalysis {
            structure: Arc::new(structure),
            symbolic: Arc::new(symbolic),
        })
    }

    /// The pattern and its symbolic analysis, shared ([`FaerCholesky::with_analysis`]
    /// makes a factoriser of them without ordering or analysing again).
    pub(crate) fn analysis(&self) -> FaerAnalysis {
        FaerAnalysis {
            structure: Arc::clone(&self.structure),
            symbolic: Arc::clone(&self.symbolic),
        }
    }

    /// A factoriser of an analysed pattern: its own numeric storage and workspaces.
    pub(crate) fn with_analysis(analysis: &FaerAnalysis) -> Result<Self, SolveError> {
        let structure = Arc::clone(&analysis.structure);
        let symbolic = Arc::clone(&analysis.symbolic);
        let factor_req =
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default());
        let solve_req = symbolic.solve_in_place_scratch::<f64>(1, Par::Seq);
        let factor_buffer =
            MemBuffer::try_new(factor_req).map_err(|_| LinearError::OutOfMemory {
                stage: "factorisation",
            })?;
        let solve_buffer = MemBuffer::try_new(solve_req)
            .map_err(|_| LinearError::OutOfMemory { stage: "solve" })?;
        let factor_values = vec![0.0; symbolic.len_val()];
        Ok(Self {
            structure,
            symbolic,
            factor_values,
            factor_buffer,
            solve_buffer,
            solve_columns: 1,
        })
    }

    /// Whether faer chose its supernodal factorisation (dense blocks of columns) rather
    /// than the simplicial one for this pattern.
    #[cfg(test)]
    pub(crate) fn is_supernodal(&self) -> bool {
        matches!(self.symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_))
    }

    /// Number of nonzeros of the factor `L`.
    pub(crate) fn factor_nnz(&self) -> usize {
        self.factor_values.len()
    }

    /// Numeric factorisation of the matrix with the model's pattern and `values`
    /// (upper triangle). Returns `false` if the matrix is not positive definite.
    pub(crate) fn factor(&mut self, values: &[f64]) -> bool {
        let matrix = SparseColMatRef::new((*self.structure).as_ref(), values);
        let result = self.symbolic.factorize_numeric_llt::<f64>(
            &mut self.factor_values,
            matrix,
            Side::Upper,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut self.factor_buffer),
            Default::default(),
        );
        result.is_ok()
    }

    /// Solves `A x = rhs` in place with the last successful factorisation.
    pub(crate) fn solve_in_place(&mut self, rhs: &mut [f64]) {
        self.solve_columns_in_place(rhs, 1);
    }

    /// Solves `A X = B` in place for `columns` right-hand sides stored one after
    /// another in `rhs` (column-major, `columns` times the dimension). With faer's
    /// simplicial factor the ordering's permutation is applied once to all of them and
    /// each column of the factor is read once per four right-hand sides: its
    /// triangular solves do the same operations in the same order for each right-hand
    /// side whether it is solved alone or with others, so every column is
    /// [`FaerCholesky::solve_in_place`]'s bit for bit (tested). The supernodal
    /// factor's dense kernels group the operations differently for several columns,
    /// so there each column is solved alone (the same bits again).
    pub(crate) fn solve_columns_in_place(&mut self, rhs: &mut [f64], columns: usize) {
        if columns == 0 {
            return;
        }
        let n = rhs.len() / columns;
        assert_eq!(n * columns, rhs.len(), "whole columns of the dimension");
        let simplicial = matches!(self.symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_));
        if columns > 1 && !simplicial {
            for column in rhs.chunks_exact_mut(n) {
                self.solve_columns_in_place(column, 1);
            }
            return;
        }
        if columns > self.solve_columns {
            let req = self
                .symbolic
                .solve_in_place_scratch::<f64>(columns, Par::Seq);
            // The workspace of fewer columns stays usable where this one cannot be had.
            if let Ok(buffer) = MemBuffer::try_new(req) {
                self.solve_buffer = buffer;
                self.solve_columns = columns;
            } else {
                for column in rhs.chunks_exact_mut(n) {
                    self.solve_columns_in_place(column, 1);
                }
                return;
            }
        }
        let llt = LltRef::<'_, usize, f64>::new(&self.symbolic, &self.factor_values);
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, columns),
            Par::Seq,
            MemStack::new(&mut self.solve_buffer),
        );
    }
}

/// Approximate minimum degree on the graph of 3×3 blocks, expanded to scalars (keeps
/// each block's three unknowns together and is 9× cheaper than scalar AMD).
fn block_amd_ordering(pattern: &HessianPattern) -> Result<(Vec<usize>, Vec<usize>), SolveError> {
    let (col_ptr, row_idx) = pattern.block_structure();
    let blocks = col_ptr.len() - 1;
    let structure = SymbolicSparseColMatRef::new_checked(blocks, blocks, &col_ptr, None, &row_idx);
    let mut block_forward = vec![0usize; blocks];
    let mut block_inverse = vec![0usize; blocks];
    let mut buffer = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(
        blocks,
        row_idx.len(),
    ))
    .map_err(|_| LinearError::OutOfMemory { stage: "ordering" })?;
    amd::order_maybe_unsorted(
        &mut block_forward,
        &mut block_inverse,
        structure,
        amd::Control::default(),
        MemStack::new(&mut buffer),
    )
    .map_err(|e| LinearError::Failed {
        stage: "ordering",
        detail: format!("{e:?}"),
    })?;
    let forward: Vec<usize> = block_forward
        .iter()
        .flat_map(|&b| [3 * b, 3 * b + 1, 3 * b + 2])
        .collect();
    let mut inverse = vec![0usize; forward.len()];
    for (new, &old) in forward.iter().enumerate() {
        inverse[old] = new;
    }
    Ok((forward, inverse))
}
