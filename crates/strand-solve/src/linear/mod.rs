//! Sparse Cholesky factorisation `A = L Lᵀ` of the Hessian, with its pattern analysed
//! once per model and reused by every numeric factorisation (workspaces allocated
//! once). Two backends behind one type:
//!
//! * [`envelope`]: a dense-profile factorisation for matrices whose nonzeros hug the
//!   diagonal, a single rod numbered along its length (no symbolic analysis, contiguous
//!   inner loops);
//! * [`faer_llt`]: faer's sparse Cholesky with a fill-reducing ordering, for systems of
//!   several rods coupled by junctions, clips and bodies.
//!
//! The pattern's independent blocks ([`Components`]) are found once with it, so that
//! solves for right-hand sides local to one block can be shared (see `sqp::exact`).

mod components;
mod envelope;
mod faer_llt;

use std::sync::Arc;

use strand_system::HessianPattern;

use crate::SolveError;
pub(crate) use components::{Components, union_find_root};
use envelope::EnvelopeCholesky;
use faer_llt::{FaerAnalysis, FaerCholesky};

/// A reusable sparse `LLᵀ` factorisation of matrices with one fixed pattern.
pub struct SparseCholesky {
    backend: Backend,
    factored: bool,
    /// Whether the envelope holds a signed factorisation
    /// ([`SparseCholesky::negative_eigenvalues`]) rather than a Cholesky one.
    signed: bool,
    components: Arc<Components>,
    /// The pattern's upper-triangular CSC column pointers and row indices.
    col_ptr: Arc<[usize]>,
    row_idx: Arc<[usize]>,
    /// The values of the last successful factorisation (upper triangle, in the
    /// pattern's order): the matrix the factor stands for, read by the active set's
    /// KKT system (`sqp::kkt`).
    values: Vec<f64>,
}

enum Backend {
    Envelope(EnvelopeCholesky),
    Faer(Box<FaerCholesky>),
}

/// The symbolic analysis of one Hessian pattern by a [`SparseCholesky`] (the backend
/// chosen, faer's fill-reducing ordering and elimination tree, the independent
/// blocks): what a factoriser of the same pattern needs besides its numeric storage.
/// A solver hands its analysis on with its [`crate::Solution`], so that the
/// sensitivities of the equilibrium factor its Hessian without analysing the pattern
/// again ([`SparseCholesky::from_analysis`]).
#[derive(Clone)]
pub struct PatternAnalysis {
    backend: AnalysedBackend,
    components: Arc<Components>,
    col_ptr: Arc<[usize]>,
    row_idx: Arc<[usize]>,
}

#[derive(Clone)]
enum AnalysedBackend {
    /// The envelope's layout (its numeric blocks are overwritten by every factorisation).
    Envelope(Box<EnvelopeCholesky>),
    /// faer's pattern and symbolic analysis.
    Faer(FaerAnalysis),
}

impl std::fmt::Debug for PatternAnalysis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PatternAnalysis")
            .field("unknowns", &(self.col_ptr.len() - 1))
            .field("entries", &self.row_idx.len())
            .field(
                "backend",
                &match self.backend {
                    AnalysedBackend::Envelope(_) => "envelope",
                    AnalysedBackend::Faer(_) => "faer",
                },
            )
            .finish()
    }
}

impl PatternAnalysis {
    /// Whether this is the analysis of `pattern` (the same upper-triangular CSC
    /// structure).
    pub fn is_of(&self, pattern: &HessianPattern) -> bool {
        *self.col_ptr == *pattern.col_ptr && *self.row_idx == *pattern.row_idx
    }
}

impl SparseCholesky {
    /// Analysis of the upper-triangular pattern.
    ///
    /// The model numbers unknowns along each rod (a narrow band): a pattern whose
    /// blocks couple only to blocks at most 3 positions before them
    /// ([`HessianPattern::is_banded`], a single rod) is factorised in its envelope
    /// directly. Otherwise faer analyses the natural and the block AMD ordering, and
    /// the envelope is still used when it holds no more entries than faer's sparser
    /// factor.
    pub fn try_new(pattern: &HessianPattern) -> Result<Self, SolveError> {
        let backend = if pattern.is_banded() {
            Backend::Envelope(EnvelopeCholesky::new(pattern))
        } else {
            let faer = FaerCholesky::try_new(pattern)?;
            if EnvelopeCholesky::size_of(pattern) <= faer.factor_nnz() {
                Backend::Envelope(EnvelopeCholesky::new(pattern))
            } else {
                Backend::Faer(Box::new(faer))
            }
        };
        Ok(Self {
            backend,
            factored: false,
            signed: false,
            components: Arc::new(Components::of_pattern(pattern)),
            col_ptr: pattern.col_ptr.as_slice().into(),
            row_idx: pattern.row_idx.as_slice().into(),
            values: vec![0.0; pattern.nnz()],
        })
    }

    /// This factoriser's symbolic analysis, to hand on ([`PatternAnalysis`]).
    pub fn analysis(&self) -> PatternAnalysis {
        PatternAnalysis {
            backend: match &self.backend {
                Backend::Envelope(e) => AnalysedBackend::Envelope(Box::new(e.clone())),
                Backend::Faer(f) => AnalysedBackend::Faer(f.analysis()),
            },
            components: Arc::clone(&self.components),
            col_ptr: Arc::clone(&self.col_ptr),
            row_idx: Arc::clone(&self.row_idx),
        }
    }

    /// A factoriser from a pattern's `analysis` ([`SparseCholesky::analysis`]): the one
    /// [`SparseCholesky::try_new`] makes of that pattern, without analysing it again.
    pub fn from_analysis(analysis: &PatternAnalysis) -> Result<Self, SolveError> {
        Ok(Self {
            backend: match &analysis.backend {
                AnalysedBackend::Envelope(e) => Backend::Envelope((**e).clone()),
                AnalysedBackend::Faer(f) => {
                    Backend::Faer(Box::new(FaerCholesky::with_analysis(f)?))
                }
            },
            factored: false,
            signed: false,
            components: Arc::clone(&analysis.components),
            col_ptr: Arc::clone(&analysis.col_ptr),
            row_idx: Arc::clone(&analysis.row_idx),
            values: vec![0.0; analysis.row_idx.len()],
        })
    }

    /// The independent blocks of the pattern (connected components of its block graph).
    pub(crate) fn components(&self) -> &Components {
        &self.components
    }

    /// Number of stored entries of the factor `L`.
    pub fn factor_nnz(&self) -> usize {
        match &self.backend {
            Backend::Envelope(e) => e.len(),
            Backend::Faer(f) => f.factor_nnz(),
        }
    }

    /// Whether the factorisation runs in the matrix's envelope (a single rod) rather
    /// than through faer's sparse Cholesky.
    pub fn is_envelope(&self) -> bool {
        matches!(self.backend, Backend::Envelope(_))
    }

    /// Numeric factorisation of the matrix with the model's pattern and `values`
    /// (upper triangle). Returns `false` if the matrix is not positive definite.
    pub fn factor(&mut self, values: &[f64]) -> bool {
        self.signed = false;
        self.factored = match &mut self.backend {
            Backend::Envelope(e) => e.factor(values),
            Backend::Faer(f) => f.factor(values),
        };
        if self.factored {
            self.values.copy_from_slice(values);
        }
        self.factored
    }

    /// The factorised matrix: the pattern's upper-triangular CSC column pointers, row
    /// indices and the values of the last successful factorisation.
    pub(crate) fn matrix(&self) -> (&[usize], &[usize], &[f64]) {
        assert!(self.factored, "matrix before a successful factorisation");
        (&self.col_ptr, &self.row_idx, &self.values)
    }

    /// The number of negative eigenvalues of the symmetric (possibly indefinite)
    /// matrix with the pattern's `values`, from an unpivoted `L Σ Lᵀ` factorisation in
    /// the envelope (Sylvester's law of inertia). `None` for the faer backend, or when
    /// a pivot is not a number or at most `tiny` times its row's diagonal entry in
    /// magnitude. Replaces the Cholesky factor: [`SparseCholesky::solve_in_place`]
    /// needs a new [`SparseCholesky::factor`], [`SparseCholesky::solve_signed_in_place`]
    /// solves with this factor.
    pub(crate) fn negative_eigenvalues(&mut self, values: &[f64], tiny: f64) -> Option<usize> {
        self.factored = false;
        let Backend::Envelope(e) = &mut self.backend else {
            return None;
        };
        let negative = e.factor_signed(values, tiny);
        self.signed = negative.is_some();
        negative
    }

    /// Solves `A x = rhs` in place with the last successful
    /// [`SparseCholesky::negative_eigenvalues`] factorisation.
    pub(crate) fn solve_signed_in_place(&self, rhs: &mut [f64]) {
        assert!(
            self.signed,
            "solve before a successful signed factorisation"
        );
        let Backend::Envelope(e) = &self.backend else {
            unreachable!("a signed factorisation is an envelope one");
        };
        e.solve_signed_in_place(rhs);
    }

    /// Solves `A x = rhs` in place with the last successful factorisation.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        assert!(self.factored, "solve before a successful factorisation");
        match &mut self.backend {
            Backend::Envelope(e) => e.solve_in_place(rhs),
            Backend::Faer(f) => f.solve_in_place(rhs),
        }
    }

    /// Solves `A X = B` in place with the last successful factorisation for
    /// `columns` right-hand sides stored one after another in `rhs` (column-major:
    /// column `k` is `rhs[k n..(k + 1) n]`, `n` the dimension). Each column's result is
    /// [`SparseCholesky::solve_in_place`]'s bit for bit; through faer's simplicial
    /// factor the permutations are applied once and the factor is read once per four
    /// columns, the envelope and faer's supernodal factor solve one column after
    /// another.
    ///
    /// # Panics
    ///
    /// Before a successful factorisation, or if `rhs.len()` is not `columns` times the
    /// dimension.
    pub fn solve_columns_in_place(&mut self, rhs: &mut [f64], columns: usize) {
        assert!(self.factored, "solve before a successful factorisation");
        let n = self.col_ptr.len() - 1;
        assert_eq!(rhs.len(), n * columns, "columns of the factor's dimension");
        match &mut self.backend {
            Backend::Envelope(e) => {
                for column in rhs.chunks_exact_mut(n.max(1)) {
                    e.solve_in_place(column);
                }
            }
            Backend::Faer(f) => f.solve_columns_in_place(rhs, columns),
        }
    }
}

/// `out = A x` for the symmetric matrix `A` given by its upper triangle (`values` in
/// `pattern`).
pub(crate) fn symmetric_product(
    pattern: &HessianPattern,
    values: &[f64],
    x: &[f64],
    out: &mut [f64],
) {
    out.iter_mut().for_each(|o| *o = 0.0);
    for col in 0..pattern.dim() {
        let range = pattern.col_ptr[col]..pattern.col_ptr[col + 1];
        let (rows, column) = (&pattern.row_idx[range.clone()], &values[range]);
        let x_col = x[col];
        // Rows are sorted and at most `col`: the diagonal, where held, is the last entry;
        // the loop over the others needs no test for it.
        let (rows, column, diagonal) = match rows.split_last() {
            Some((&last, above)) if last == col => {
                (above, &column[..above.len()], column.last().copied())
            }
            _ => (rows, column, None),
        };
        // The transposed part of column `col` (its rows above the diagonal).
        let mut transposed = 0.0;
        for (&row, &value) in rows.iter().zip(column) {
            out[row] += value * x_col;
            transposed += value * x[row];
        }
        if let Some(d) = diagonal {
            out[col] += d * x_col;
        }
        out[col] += transposed;
    }
}

/// `out[k] = A x[k]` for `K` vectors at once, interleaved (`x[i][k]` is entry `i` of
/// vector `k`), for the symmetric matrix `A` given by its upper triangle (`values` in
/// `pattern`): each entry of `A` is read once for all `K` vectors. Every vector's
/// result is that of [`symmetric_product`] bit for bit (the same operations in the
/// same order).
pub(crate) fn symmetric_products<const K: usize>(
    pattern: &HessianPattern,
    values: &[f64],
    x: &[[f64; K]],
    out: &mut [[f64; K]],
) {
    out.iter_mut().for_each(|o| *o = [0.0; K]);
    for col in 0..pattern.dim() {
        let range = pattern.col_ptr[col]..pattern.col_ptr[col + 1];
        let (rows, column) = (&pattern.row_idx[range.clone()], &values[range]);
        let x_col = x[col];
        let (rows, column, diagonal) = match rows.split_last() {
            Some((&last, above)) if last == col => {
                (above, &column[..above.len()], column.last().copied())
            }
            _ => (rows, column, None),
        };
        let mut transposed = [0.0; K];
        for (&row, &value) in rows.iter().zip(column) {
            let (o, xr) = (&mut out[row], &x[row]);
            for k in 0..K {
                o[k] += value * x_col[k];
                transposed[k] += value * xr[k];
            }
        }
        let o = &mut out[col];
        if let Some(d) = diagonal {
            for k in 0..K {
                o[k] += d * x_col[k];
            }
        }
        for k in 0..K {
            o[k] += transposed[k];
        }
    }
}

#[cfg(test)]
pub(crate) mod tests;
