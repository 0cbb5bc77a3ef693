//! Stability of an equilibrium from the inertia of the reduced Hessian.
//!
//! The admissible directions at an equilibrium are those that keep the supports
//! (eliminated by construction), the gauge (held, see [`crate::gauge`]) and every
//! active inequality (contact, joint stop carrying a force): `a_i · d = 0`. The
//! equilibrium is stable when the Hessian restricted to them, `Zᵀ H Z`, has no negative
//! eigenvalue. Its inertia is read, without forming `Z`, from the bordered matrix
//!
//! ```text
//!     K(σ) = [ H + σD   Aᵀ  ]
//!            [ A       −δ I ]
//! ```
//!
//! whose sparse `LDLᵀ` factorisation has `neg(K) = neg(H + σD + AᵀA/δ) + m` negative
//! pivots (Sylvester's law of inertia; a tiny `δ` makes the penalty `AᵀA/δ` exclude the
//! constrained directions). Rows in the span of others are left out first
//! ([`independent_rows`]): in the natural order they would leave a border pivot of the
//! size of `δ` whose sign round-off decides. `D` is the Hessian's own
//! diagonal, so `σ` is a relative eigenvalue threshold, the same for positions,
//! rotations and joints. Two factorisations classify every eigenvalue:
//! `neg(K(+τ)) − m` directions are negative beyond round-off and
//! `neg(K(−τ)) − neg(K(+τ))` are neutral (`|λ| ≤ τ`, e.g. a buckled round rod that can
//! turn its buckling plane about the chord). Neither depends on the sign round-off
//! gives an exactly neutral direction.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Par, Side};
use strand_system::HessianPattern;

use crate::constraints::Row;
use crate::gauge::Gauge;
use crate::{LinearError, SolveError, SparseCholesky};

mod envelope;
mod independent_rows;
#[cfg(test)]
mod random_tests;

pub use independent_rows::{DEPENDENCE_TOLERANCE, independent_rows};

#[cfg(test)]
thread_local! {
    /// Bordered matrices factorised by faer on this thread (tests only: the work a
    /// definite Hessian must not cause).
    static BORDERED_FACTORISATIONS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Curvature counts of the reduced Hessian.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Inertia {
    /// Directions with a relative eigenvalue below `−τ`.
    pub negative: usize,
    /// Directions with `|λ| ≤ τ`.
    pub neutral: usize,
}

/// Classifies the Hessian `hessian` (values of `pattern`, upper triangle) reduced to the
/// directions that keep `gauge` and the `active` rows, with relative threshold `tau`.
///
/// First, whatever the active rows: when `H − τD` is positive definite (one Cholesky
/// with `cholesky`, the model's factorisation, whose factor this overwrites) nothing
/// lies below `−τ`, so nothing below `+τ` either (the Schur complement of the rows,
/// `−δI − A H'⁻¹ Aᵀ`, is then negative definite: Haynsworth), and the count is 0
/// without the bordered matrix. Otherwise, when `cholesky` works in the envelope, the inertia
/// is counted there ([`envelope`]: the Hessian block by an
/// unpivoted signed factorisation, the rows by their Schur complement); otherwise, or
/// when a pivot there is too small to trust, by faer's sparse `LDLᵀ` of `K(σ)`.
/// `scratch` holds one value per pattern entry. Active rows in the span of others are
/// left out first ([`independent_rows`]): they constrain nothing more, and in the
/// bordered matrix they would leave a pivot whose sign round-off decides.
pub fn reduced_inertia(
    pattern: &HessianPattern,
    hessian: &[f64],
    gauge: &Gauge,
    active: &[&Row],
    tau: f64,
    cholesky: &mut SparseCholesky,
    scratch: &mut [f64],
) -> Result<Inertia, SolveError> {
    fill_shifted(pattern, hessian, gauge, -tau, scratch);
    if cholesky.factor(scratch) {
        return Ok(Inertia {
            negative: 0,
            neutral: 0,
        });
    }
    let independent = independent_rows(active);
    let active = independent.as_slice();
    let counted =
        envelope::reduced_inertia(pattern, hessian, gauge, active, tau, cholesky, scratch);
    match counted {
        Some(inertia) => Ok(inertia),
        None => faer_reduced_inertia(pattern, hessian, gauge, active, tau),
    }
}

/// [`reduced_inertia`] by faer's simplicial `LDLᵀ` of the bordered matrix `K(±τ)`,
/// each row right after its last unknown ([`rows_after_their_unknowns`]: the factor
/// stays in the band however many rows are active), with the rows as given
/// (independent rows: see [`independent_rows`]).
pub fn faer_reduced_inertia(
    pattern: &HessianPattern,
    hessian: &[f64],
    gauge: &Gauge,
    active: &[&Row],
    tau: f64,
) -> Result<Inertia, SolveError> {
    let bordered = Bordered::new(pattern, active);
    let mut values = vec![0.0; bordered.nnz()];
    let mut count = |sigma: f64| -> Result<usize, SolveError> {
        bordered.fill(hessian, gauge, active, sigma, &mut values);
        let negative = bordered.negative_pivots(&values)?;
        Ok(negative.saturating_sub(active.len()))
    };
    let below_plus = count(tau)?;
    let below_minus = count(-tau)?;
    Ok(Inertia {
        negative: below_plus,
        neutral: below_minus.saturating_sub(below_plus),
    })
}

/// Writes `H + σD` with the gauge held (the Hessian block of `K(σ)`) into `out` and
/// returns the largest diagonal magnitude of `H`.
fn fill_shifted(
    pattern: &HessianPattern,
    hessian: &[f64],
    gauge: &Gauge,
    sigma: f64,
    out: &mut [f64],
) -> f64 {
    out.copy_from_slice(hessian);
    let mut largest_diagonal = f64::MIN_POSITIVE;
    for col in 0..pattern.dim() {
        let end = pattern.col_ptr[col + 1];
        // The diagonal is the last entry of each upper-triangular column.
        let d = hessian[end - 1].abs().max(f64::MIN_POSITIVE);
        largest_diagonal = largest_diagonal.max(d);
        out[end - 1] += sigma * d;
    }
    gauge.fix_matrix(out);
    largest_diagonal
}

/// The diagonal entry `−δ` of an active row with gradient norm² `norm_squared`: `δ`
/// such that the penalty `aᵀa/δ` exceeds every diagonal (largest `largest_diagonal`)
/// by 1e10.
fn row_diagonal(norm_squared: f64, largest_diagonal: f64) -> f64 {
    -1e-10 * norm_squared.max(f64::MIN_POSITIVE) / largest_diagonal
}

/// The bordered pattern `[H Aᵀ; A −δI]` (upper triangle, CSC) with a simplicial
/// symbolic analysis in the unknowns' natural order with each active row right after
/// the last unknown it moves ([`rows_after_their_unknowns`]).
struct Bordered<'p> {
    pattern: &'p HessianPattern,
    structure: SymbolicSparseColMat<usize>,
    symbolic: SymbolicCholesky<usize>,
    /// Per active row: value offsets of its entries and of its diagonal.
    row_offsets: Vec<(Vec<usize>, usize)>,
}

impl<'p> Bordered<'p> {
    fn new(pattern: &'p HessianPattern, active: &[&Row]) -> Self {
        let n = pattern.dim();
        let mut col_ptr = pattern.col_ptr.clone();
        let mut row_idx = pattern.row_idx.clone();
        let mut row_offsets = Vec::with_capacity(active.len());
        for (i, row) in active.iter().enumerate() {
            let mut entries: Vec<usize> = row.gradient.iter().map(|&(k, _)| k).collect();
            entries.sort_unstable();
            entries.dedup();
            let start = row_idx.len();
            row_idx.extend_from_slice(&entries);
            row_idx.push(n + i);
            col_ptr.push(row_idx.len());
            let offsets = (start..start + entries.len()).collect();
            row_offsets.push((offsets, row_idx.len() - 1));
        }
        let dim = n + active.len();
        let structure = SymbolicSparseColMat::new_checked(dim, dim, col_ptr, None, row_idx);
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
            ..Default::default()
        };
        let (forward, inverse) = rows_after_their_unknowns(n, active);
        let symbolic = factorize_symbolic_cholesky(
            structure.as_ref(),
            Side::Upper,
            SymmetricOrdering::Custom(PermRef::new_checked(&forward, &inverse, dim)),
            params,
        )
        .expect("the bordered pattern is square and sorted");
        Self {
            pattern,
            structure,
            symbolic,
            row_offsets,
        }
    }

    fn nnz(&self) -> usize {
        self.structure.row_idx().len()
    }

    /// Entries of the `LDLᵀ` factor (tests: the work of the factorisation).
    #[cfg(test)]
    fn factor_entries(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Values of `K(σ)`.
    fn fill(&self, hessian: &[f64], gauge: &Gauge, active: &[&Row], sigma: f64, out: &mut [f64]) {
        let h_nnz = hessian.len();
        let largest_diagonal = fill_shifted(self.pattern, hessian, gauge, sigma, &mut out[..h_nnz]);
        for ((offsets, diagonal), row) in self.row_offsets.iter().zip(active) {
            for slot in offsets {
                out[*slot] = 0.0;
            }
            let mut norm_squared = 0.0;
            for &(k, a) in &row.gradient {
                let slot = offsets
                    .iter()
                    .find(|&&s| self.structure.row_idx()[s] == k)
                    .expect("entry in bordered column");
                out[*slot] += a;
                norm_squared += a * a;
            }
            out[*diagonal] = row_diagonal(norm_squared, largest_diagonal);
        }
    }

    /// Number of negative pivots of the `LDLᵀ` factorisation of `values`.
    fn negative_pivots(&self, values: &[f64]) -> Result<usize, SolveError> {
        #[cfg(test)]
        BORDERED_FACTORISATIONS.with(|c| c.set(c.get() + 1));
        let mut factor = vec![0.0; self.symbolic.len_val()];
        let mut buffer = MemBuffer::try_new(
            self.symbolic
                .factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default()),
        )
        .map_err(|_| LinearError::OutOfMemory {
            stage: "stability test",
        })?;
        let matrix = SparseColMatRef::new(self.structure.as_ref(), values);
        self.symbolic
            .factorize_numeric_ldlt::<f64>(
                &mut factor,
                matrix,
                Side::Upper,
                LdltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut buffer),
                Default::default(),
            )
            .map_err(|e| LinearError::Failed {
                stage: "stability test",
                detail: format!("{e:?}"),
            })?;
        let SymbolicCholeskyRaw::Simplicial(simplicial) = self.symbolic.raw() else {
            unreachable!("simplicial analysis was forced");
        };
        let col_ptr = simplicial.col_ptr();
        Ok((0..self.structure.ncols())
            .filter(|&k| factor[col_ptr[k]] < 0.0)
            .count())
    }
}

/// The order of the bordered matrix's `n + m` unknowns (`forward[new] = old`, and its
/// inverse): the Hessian's `n` in their natural order, each active row (`n + i`) right
/// after the last unknown it moves. Rows last would leave their Schur complement
/// `A H'⁻¹ Aᵀ` dense (`m²` entries, `m³` work: a cable lying on a floor along
/// thousands of contacts); next to their unknowns they fill only the band. Each row
/// still comes after all its unknowns, so its pivot is `−δ` less the Schur complement
/// of those unknowns (of the size of `aᵀa / d`, not of `δ`) and the penalty `aᵀa/δ` is
/// never added to an unknown not yet eliminated. The count of negative pivots is the
/// same in any order (Sylvester's law of inertia).
fn rows_after_their_unknowns(n: usize, active: &[&Row]) -> (Vec<usize>, Vec<usize>) {
    // Rows by their last unknown (a row without entries at the end).
    let mut by_last: Vec<(usize, usize)> = active
        .iter()
        .enumerate()
        .map(|(i, row)| {
            let last = row.gradient.iter().map(|&(k, _)| k).max().unwrap_or(n);
            (last, n + i)
        })
        .collect();
    by_last.sort_unstable();
    let mut forward = Vec::with_capacity(n + active.len());
    let mut rows = by_last.iter().peekable();
    for k in 0..n {
        forward.push(k);
        while let Some(&(_, row)) = rows.next_if(|(last, _)| *last == k) {
            forward.push(row);
        }
    }
    forward.extend(rows.map(|&(_, row)| row));
    let mut inverse = vec![0; forward.len()];
    for (new, &old) in forward.iter().enumerate() {
        inverse[old] = new;
    }
    (forward, inverse)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::RowKey;

    /// Two 3-blocks: `[[1, 2], [2, 1]]` on unknowns 0, 1 (eigenvalues −1 and 3),
    /// `[[1, 1], [1, 1]]` on unknowns 3, 4 (eigenvalues 0 and 2), 1 on 2 and 5.
    fn toy() -> (HessianPattern, Vec<f64>) {
        let coupling = [vec![0usize, 1]];
        let pattern = HessianPattern::new(2, coupling.iter().map(|b| b.as_slice()));
        let mut values = vec![0.0; pattern.nnz()];
        let mut set = |row: usize, col: usize, value: f64| {
            let rows = &pattern.row_idx[pattern.col_ptr[col]..pattern.col_ptr[col + 1]];
            let at = rows.iter().position(|&r| r == row).unwrap();
            values[pattern.col_ptr[col] + at] = value;
        };
        for k in 0..6 {
            set(k, k, 1.0);
        }
        set(0, 1, 2.0);
        set(3, 4, 1.0);
        (pattern, values)
    }

    /// The inertia by the envelope count, asserted equal to faer's.
    fn inertia(
        pattern: &HessianPattern,
        values: &[f64],
        gauge: &Gauge,
        active: &[&Row],
        tau: f64,
    ) -> Inertia {
        let mut cholesky = SparseCholesky::try_new(pattern).unwrap();
        let mut scratch = vec![0.0; pattern.nnz()];
        let counted = envelope::reduced_inertia(
            pattern,
            values,
            gauge,
            active,
            tau,
            &mut cholesky,
            &mut scratch,
        )
        .expect("counted in the envelope");
        let faer = faer_reduced_inertia(pattern, values, gauge, active, tau).unwrap();
        assert_eq!(counted, faer);
        counted
    }

    #[test]
    fn counts_negative_and_neutral_directions() {
        let (pattern, values) = toy();
        let inertia = inertia(&pattern, &values, &Gauge::default(), &[], 1e-9);
        assert_eq!(
            inertia,
            Inertia {
                negative: 1,
                neutral: 1
            }
        );
    }

    #[test]
    fn an_active_row_along_the_negative_direction_removes_it() {
        let (pattern, values) = toy();
        let row = Row {
            key: RowKey::Contact(0),
            value: 0.0,
            gradient: vec![(0, 1.0), (1, -1.0)],
            curvature: None,
        };
        let inertia = inertia(&pattern, &values, &Gauge::default(), &[&row], 1e-9);
        assert_eq!(inertia.negative, 0);
        assert_eq!(inertia.neutral, 1);
    }

    #[test]
    fn a_held_unknown_removes_the_neutral_direction_it_spans() {
        let (pattern, values) = toy();
        let gauge = Gauge::holding_in(&pattern, vec![3]);
        let inertia = inertia(&pattern, &values, &gauge, &[], 1e-9);
        assert_eq!(
            inertia,
            Inertia {
                negative: 1,
                neutral: 0
            }
        );
    }

    /// A chain of `blocks` 3-blocks, each coupled to the next, with 100 on the diagonal
    /// and 1 elsewhere in the pattern (positive definite by dominance), and one active
    /// row per unknown of every other block.
    fn chain(blocks: usize) -> (HessianPattern, Vec<f64>, Vec<Row>) {
        let couplings: Vec<Vec<usize>> = (0..blocks - 1).map(|b| vec![b, b + 1]).collect();
        let pattern = HessianPattern::new(blocks, couplings.iter().map(|c| c.as_slice()));
        let mut values = vec![1.0; pattern.nnz()];
        for col in 0..pattern.dim() {
            values[pattern.col_ptr[col + 1] - 1] = 100.0;
        }
        let rows = (0..pattern.dim())
            .filter(|k| (k / 3) % 2 == 0)
            .map(|k| Row {
                key: RowKey::Contact(k as u64),
                value: 0.0,
                gradient: vec![(k, 1.0)],
                curvature: None,
            })
            .collect();
        (pattern, values, rows)
    }

    #[test]
    fn a_definite_hessian_is_stable_under_any_rows_without_the_bordered_matrix() {
        // 150 active rows: beyond the envelope's Schur complement, so the bordered
        // matrix was factorised (dense in its rows) before the definite test.
        let (pattern, values, rows) = chain(100);
        let active: Vec<&Row> = rows.iter().collect();
        assert!(active.len() > 100);
        let mut cholesky = SparseCholesky::try_new(&pattern).unwrap();
        let mut scratch = vec![0.0; pattern.nnz()];
        let gauge = Gauge::default();
        // The count and the bordered matrices it factorised.
        let mut classify = |values: &[f64]| {
            let before = BORDERED_FACTORISATIONS.with(|c| c.get());
            let inertia = reduced_inertia(
                &pattern,
                values,
                &gauge,
                &active,
                1e-9,
                &mut cholesky,
                &mut scratch,
            )
            .unwrap();
            (inertia, BORDERED_FACTORISATIONS.with(|c| c.get()) - before)
        };
        let (inertia, bordered) = classify(&values);
        assert_eq!(bordered, 0);
        assert_eq!(
            inertia,
            faer_reduced_inertia(&pattern, &values, &gauge, &active, 1e-9).unwrap()
        );
        assert_eq!(
            inertia,
            Inertia {
                negative: 0,
                neutral: 0
            }
        );
        // An indefinite Hessian still goes to the bordered count: a negative diagonal
        // on a constrained unknown is removed by its row, one on a free unknown is not.
        for (unknown, negative) in [(0, 0), (3, 1)] {
            let mut indefinite = values.clone();
            indefinite[pattern.col_ptr[unknown + 1] - 1] = -50.0;
            let (inertia, bordered) = classify(&indefinite);
            assert!(bordered > 0);
            assert_eq!(
                inertia,
                Inertia {
                    negative,
                    neutral: 0
                }
            );
        }
    }
}
