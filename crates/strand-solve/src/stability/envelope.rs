//! The inertia of `K(σ)` counted in the Hessian's envelope (a single rod), without
//! faer's symbolic analysis of the bordered pattern.
//!
//! The envelope counts the pivots of `K(σ) = [H' Aᵀ; A −δI]` (`H' = H + σD`, gauge
//! held) in the natural order: first those of `H'` (the envelope's unpivoted signed
//! factorisation), then those of the Schur complement `S = −δI − A H'⁻¹ Aᵀ` (a dense
//! unpivoted `LDLᵀ`, one envelope solve per active row, so only for a few rows). By
//! Haynsworth's inertia additivity `neg(K) = neg(H') + neg(S)`, the count of faer's
//! factorisation with each row after its unknowns (Sylvester's law: any order). A positive definite `H'` (tried
//! first, by Cholesky) makes `S` negative definite: then the count is 0.

use strand_system::HessianPattern;

use super::{Inertia, fill_shifted, row_diagonal};
use crate::SparseCholesky;
use crate::constraints::Row;
use crate::gauge::Gauge;

/// Active rows above which the Schur complement (one solve per row, dense `m × m`)
/// is left to faer.
const MAX_SCHUR_ROWS: usize = 64;

/// A pivot is trusted when its magnitude exceeds this fraction of `τ` times its row's
/// diagonal: far below the smallest shifted eigenvalue `τ·d` the test resolves.
const TINY_PER_TAU: f64 = 1e-2;

/// [`super::reduced_inertia`] in the envelope of `cholesky`; `None` when `cholesky`
/// does not factorise in the envelope, there are more than [`MAX_SCHUR_ROWS`] active
/// rows, or a pivot is too small to trust.
pub(super) fn reduced_inertia(
    pattern: &HessianPattern,
    hessian: &[f64],
    gauge: &Gauge,
    active: &[&Row],
    tau: f64,
    cholesky: &mut SparseCholesky,
    scratch: &mut [f64],
) -> Option<Inertia> {
    if !cholesky.is_envelope() || active.len() > MAX_SCHUR_ROWS {
        return None;
    }
    let tiny = TINY_PER_TAU * tau;
    let mut count = |sigma: f64| -> Option<usize> {
        let largest_diagonal = fill_shifted(pattern, hessian, gauge, sigma, scratch);
        // `H'` positive definite (one Cholesky, cheaper than the signed factorisation)
        // makes `S` negative definite: no direction below the threshold.
        if cholesky.factor(scratch) {
            return Some(0);
        }
        let hessian_block = cholesky.negative_eigenvalues(scratch, tiny)?;
        let schur = schur_complement(cholesky, pattern.dim(), active, largest_diagonal);
        // Every active row adds one negative direction of the border (−δ).
        Some(
            (hessian_block + negative_pivots(schur, active.len(), tiny)?)
                .saturating_sub(active.len()),
        )
    };
    // `H − τD ≤ H + τD`: nothing below −τ leaves nothing below +τ either.
    let below_minus = count(-tau)?;
    let below_plus = if below_minus == 0 { 0 } else { count(tau)? };
    Some(Inertia {
        negative: below_plus,
        neutral: below_minus.saturating_sub(below_plus),
    })
}

/// `S = −δI − A H'⁻¹ Aᵀ` (row-major `m × m`) with `H'` factorised (signed) in
/// `cholesky`, of dimension `n`.
fn schur_complement(
    cholesky: &SparseCholesky,
    n: usize,
    active: &[&Row],
    largest_diagonal: f64,
) -> Vec<f64> {
    let m = active.len();
    let mut schur = vec![0.0; m * m];
    let mut column = vec![0.0; if m == 0 { 0 } else { n }];
    for (j, row_j) in active.iter().enumerate() {
        column.iter_mut().for_each(|x| *x = 0.0);
        let mut norm_squared = 0.0;
        for &(k, a) in &row_j.gradient {
            column[k] += a;
            norm_squared += a * a;
        }
        cholesky.solve_signed_in_place(&mut column);
        for (i, row_i) in active.iter().enumerate() {
            let product: f64 = row_i.gradient.iter().map(|&(k, a)| a * column[k]).sum();
            schur[i * m + j] = -product;
        }
        schur[j * m + j] += row_diagonal(norm_squared, largest_diagonal);
    }
    schur
}

/// Negative pivots of the unpivoted `LDLᵀ` of the symmetric `m × m` matrix `a`
/// (row-major, lower triangle read, overwritten); `None` if a pivot is not a number
/// or at most `tiny` times its original diagonal entry in magnitude.
fn negative_pivots(mut a: Vec<f64>, m: usize, tiny: f64) -> Option<usize> {
    let mut negative = 0;
    for k in 0..m {
        let original = a[k * m + k];
        let pivot = original
            - (0..k)
                .map(|p| a[k * m + p] * a[k * m + p] * a[p * m + p])
                .sum::<f64>();
        if !pivot.is_finite() || pivot.abs() <= tiny * original.abs() {
            return None;
        }
        a[k * m + k] = pivot;
        negative += usize::from(pivot < 0.0);
        // Column k of the unit lower factor: l_ik = (a_ik − Σ_p l_ip d_p l_kp) / d_k.
        for i in k + 1..m {
            let sum: f64 = (0..k)
                .map(|p| a[i * m + p] * a[p * m + p] * a[k * m + p])
                .sum();
            a[i * m + k] = (a[i * m + k] - sum) / pivot;
        }
    }
    Some(negative)
}
