//! Signed envelope factorisation `A = L Σ Lᵀ` of a symmetric indefinite matrix in the
//! envelope of [`EnvelopeCholesky`], without pivoting: `L` lower triangular with a
//! positive diagonal, `Σ` diagonal with entries ±1. Its pivots `σ_k l_kk²` are those of
//! the unpivoted scalar `LDLᵀ` in the natural order, so by Sylvester's law of inertia
//! the number of negative signs is the number of negative eigenvalues of `A`.
//!
//! Without pivoting the factorisation is only trustworthy while no pivot is tiny
//! compared with its row's diagonal entry; then it reports failure and the caller
//! counts the inertia another way.

use super::{Block, EnvelopeCholesky};

impl EnvelopeCholesky {
    /// Factorises `values` (upper triangle of the pattern) as `L Σ Lᵀ` and returns the
    /// number of negative pivots, or `None` if a pivot is not a number or its magnitude
    /// is at most `tiny` times the original diagonal entry of its row (the unpivoted
    /// factorisation would then be unreliable). Overwrites the factor that
    /// [`EnvelopeCholesky::solve_in_place`] uses; solve with
    /// [`EnvelopeCholesky::solve_signed_in_place`].
    pub(crate) fn factor_signed(&mut self, values: &[f64], tiny: f64) -> Option<usize> {
        self.load(values);
        self.signs.resize(self.first.len(), [1.0; 3]);
        let mut negative = 0;
        for i in 0..self.first.len() {
            let fi = self.first[i];
            let (done, rest) = self.blocks.split_at_mut(self.start[i]);
            let row = &mut rest[..i - fi + 1];
            // While row i is computed its blocks hold W_ik = L_ik Σ_k (Σ_k² = I), so
            // that Σ_k L_ik Σ_k L_jkᵀ = Σ_k W_ik L_jkᵀ needs no sign in the inner loop
            // (the recurrence is the Cholesky factor's); the signs are applied once per
            // block when the row is done.
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
            let original = [d[0], d[4], d[8]];
            // Σ_k L_ik Σ_k L_ikᵀ = Σ_k W_ik Σ_k W_ikᵀ.
            for (a, sign) in off.iter().zip(&self.signs[fi..i]) {
                subtract_signed_product(d, a, sign, a);
            }
            let (inverse, sign) = signed_cholesky_3x3(d, &original, tiny)?;
            // L_ik = W_ik Σ_k.
            for (a, sign) in off.iter_mut().zip(&self.signs[fi..i]) {
                for r in 0..3 {
                    for c in 0..3 {
                        a[3 * r + c] *= sign[c];
                    }
                }
            }
            negative += sign.iter().filter(|&&s| s < 0.0).count();
            self.inverse_diagonal[i] = inverse;
            self.signs[i] = sign;
        }
        Some(negative)
    }

    /// Solves `L Σ Lᵀ x = rhs` in place with the last successful
    /// [`EnvelopeCholesky::factor_signed`].
    pub(crate) fn solve_signed_in_place(&self, rhs: &mut [f64]) {
        self.forward(rhs);
        for (x, sign) in rhs.chunks_exact_mut(3).zip(&self.signs) {
            x.iter_mut().zip(sign).for_each(|(x, s)| *x *= s);
        }
        self.backward(rhs);
    }
}

/// `s −= a Σ bᵀ` for 3×3 blocks, `Σ = diag(sign)`.
fn subtract_signed_product(s: &mut Block, a: &Block, sign: &[f64; 3], b: &Block) {
    for r in 0..3 {
        let (a0, a1, a2) = (
            a[3 * r] * sign[0],
            a[3 * r + 1] * sign[1],
            a[3 * r + 2] * sign[2],
        );
        for c in 0..3 {
            s[3 * r + c] -= a0 * b[3 * c] + a1 * b[3 * c + 1] + a2 * b[3 * c + 2];
        }
    }
}

/// Signed factor `d = L Σ Lᵀ` of the symmetric 3×3 block `d` (lower triangle read and
/// written). Returns the reciprocals of `L`'s diagonal and the signs; `None` if a
/// pivot is not a number or at most `tiny` times the matching `original` diagonal
/// entry in magnitude.
fn signed_cholesky_3x3(
    d: &mut Block,
    original: &[f64; 3],
    tiny: f64,
) -> Option<([f64; 3], [f64; 3])> {
    let pivot = |p: f64, k: usize| -> Option<(f64, f64)> {
        let trusted = p.is_finite() && p.abs() > tiny * original[k].abs();
        trusted.then(|| (p.abs().sqrt(), p.signum()))
    };
    let (l00, s0) = pivot(d[0], 0)?;
    let i0 = 1.0 / l00;
    let l10 = d[3] * i0 * s0;
    let l20 = d[6] * i0 * s0;
    let (l11, s1) = pivot(d[4] - s0 * l10 * l10, 1)?;
    let i1 = 1.0 / l11;
    let l21 = (d[7] - s0 * l20 * l10) * i1 * s1;
    let (l22, s2) = pivot(d[8] - s0 * l20 * l20 - s1 * l21 * l21, 2)?;
    d[0] = l00;
    d[3] = l10;
    d[6] = l20;
    d[4] = l11;
    d[7] = l21;
    d[8] = l22;
    Some(([i0, i1, 1.0 / l22], [s0, s1, s2]))
}
