//! The tangent space of the held rows: a direction of negative curvature that keeps
//! them.
//!
//! A cable held over a convex mesh edge (a groove's rim) by one contact is an unstable
//! equilibrium of the Lagrangian `H − Σ λ_i ∇²g_i` on the directions the held rows leave
//! free (the cable slides along the rim and off it), so the damping that makes the
//! model positive definite keeps every step short: `everyday_s52_010` at 60 segments
//! took 198 iterations, most of them with a relative damping of 0.1 to 4.6 and steps of
//! 0.5 to 3 mm. Along that direction the trust region can be used whole, as it is
//! without rows ([`super::Iteration::negative_curvature`]); the direction must keep the
//! held rows (`A v = 0`), so inverse iteration is projected onto their null space in
//! the metric of the damped factor `K`: `P w = w − K⁻¹Aᵀ (A K⁻¹ Aᵀ)⁺ A w`.

use nalgebra::{DMatrix, DVector};

use crate::SparseCholesky;
use crate::constraints::Row;
use crate::gauge::Gauge;

/// Most held rows the projection is built for: each costs a solve with the factor
/// and the pseudo-inverse is dense. A cable lying along a floor or a groove holds
/// hundreds, and there the damped model is positive definite in practice.
pub(crate) const MAX_TANGENT_ROWS: usize = 32;

/// Relative size below which a singular value of `A K⁻¹ Aᵀ` is dependence (two rows
/// of one contact, a row in the span of others).
const DEPENDENCE: f64 = 1e-10;

/// The `K`-orthogonal projection onto the null space of some rows.
pub(crate) struct TangentProjector<'r> {
    /// The rows.
    rows: &'r [&'r Row],
    /// `K⁻¹ a_i` per row.
    columns: Vec<Vec<f64>>,
    /// `(A K⁻¹ Aᵀ)⁺`.
    inverse: DMatrix<f64>,
}

impl<'r> TangentProjector<'r> {
    /// The projection for `rows` with the factor `K` in `cholesky` (gauge held), or
    /// `None` when there are more than [`MAX_TANGENT_ROWS`].
    pub(crate) fn new(
        cholesky: &mut SparseCholesky,
        gauge: &Gauge,
        n: usize,
        rows: &'r [&'r Row],
    ) -> Option<Self> {
        if rows.len() > MAX_TANGENT_ROWS {
            return None;
        }
        if rows.is_empty() {
            // Nothing held: the projection is the identity (and the pseudo-inverse of
            // an empty matrix would panic).
            return Some(Self {
                rows,
                columns: Vec::new(),
                inverse: DMatrix::zeros(0, 0),
            });
        }
        let columns: Vec<Vec<f64>> = rows
            .iter()
            .map(|row| {
                let mut column = vec![0.0; n];
                for &(k, a) in &row.gradient {
                    column[k] += a;
                }
                gauge.fix_vector(&mut column);
                cholesky.solve_in_place(&mut column);
                column
            })
            .collect();
        let m = rows.len();
        let schur = DMatrix::from_fn(m, m, |i, j| dot_sparse(&rows[i].gradient, &columns[j]));
        let largest = schur.diagonal().amax();
        if !(largest.is_finite() && largest > 0.0) {
            return None;
        }
        let inverse = schur.pseudo_inverse(DEPENDENCE * largest).ok()?;
        Some(Self {
            rows,
            columns,
            inverse,
        })
    }

    /// Projects `w` onto the rows' null space in place.
    pub(crate) fn project(&self, w: &mut [f64]) {
        if self.rows.is_empty() {
            return;
        }
        let along = DVector::from_iterator(
            self.rows.len(),
            self.rows.iter().map(|row| dot_sparse(&row.gradient, w)),
        );
        let weights = &self.inverse * along;
        for (column, weight) in self.columns.iter().zip(weights.iter()) {
            for (wi, c) in w.iter_mut().zip(column) {
                *wi -= weight * c;
            }
        }
    }
}

fn dot_sparse(sparse: &[(usize, f64)], dense: &[f64]) -> f64 {
    sparse.iter().map(|&(k, a)| a * dense[k]).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::RowKey;
    use crate::linear::symmetric_product;
    use strand_system::HessianPattern;

    /// A block chain, 100 on the diagonal and 1 elsewhere (positive definite), and
    /// three rows: two on overlapping unknowns and the first again, scaled (dependent).
    fn chain() -> (HessianPattern, Vec<f64>, Vec<Row>) {
        let couplings: Vec<Vec<usize>> = (0..5).map(|b| vec![b, b + 1]).collect();
        let pattern = HessianPattern::new(6, couplings.iter().map(|c| c.as_slice()));
        let mut values = vec![1.0; pattern.nnz()];
        for col in 0..pattern.dim() {
            values[pattern.col_ptr[col + 1] - 1] = 100.0;
        }
        let row = |key: u64, gradient: Vec<(usize, f64)>| Row {
            key: RowKey::Contact(key),
            value: 0.0,
            gradient,
            curvature: None,
        };
        let rows = vec![
            row(0, vec![(3, 0.6), (4, -0.8), (7, 0.3)]),
            row(1, vec![(7, 1.0), (8, 0.5), (12, -0.2)]),
            row(2, vec![(3, 1.2), (4, -1.6), (7, 0.6)]),
        ];
        (pattern, values, rows)
    }

    fn dot(a: &[f64], b: &[f64]) -> f64 {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    }

    #[test]
    fn the_projection_keeps_the_rows_and_is_orthogonal_in_the_factor_metric() {
        let (pattern, values, rows) = chain();
        let n = pattern.dim();
        let mut cholesky = SparseCholesky::try_new(&pattern).unwrap();
        assert!(cholesky.factor(&values));
        let held: Vec<&Row> = rows.iter().collect();
        let projector =
            TangentProjector::new(&mut cholesky, &Gauge::default(), n, &held).expect("three rows");
        let generic = |phase: f64| -> Vec<f64> {
            (0..n)
                .map(|i| ((i as f64 + phase) * 0.618_034).fract() - 0.5)
                .collect()
        };
        let w = generic(1.0);
        let mut p = w.clone();
        projector.project(&mut p);
        // Every row (the dependent one too) is kept: a·Pw = 0.
        for row in &rows {
            let along: f64 = row.gradient.iter().map(|&(k, a)| a * p[k]).sum();
            assert!(along.abs() < 1e-13, "{along:e}");
        }
        // A projection: P(Pw) = Pw.
        let mut twice = p.clone();
        projector.project(&mut twice);
        let moved = twice
            .iter()
            .zip(&p)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(moved < 1e-14, "{moved:e}");
        // In the metric of K: the removed part is K-orthogonal to every direction that
        // keeps the rows (Pv for another v), so vᵀK(w − Pw) = 0, which the Euclidean
        // projection would not give.
        let mut v = generic(2.5);
        projector.project(&mut v);
        let removed: Vec<f64> = w.iter().zip(&p).map(|(a, b)| a - b).collect();
        let mut k_removed = vec![0.0; n];
        symmetric_product(&pattern, &values, &removed, &mut k_removed);
        let scale = dot(&v, &v).sqrt() * dot(&k_removed, &k_removed).sqrt();
        assert!(dot(&v, &k_removed).abs() < 1e-12 * scale);
        assert!(dot(&removed, &removed) > 1e-6, "the rows removed something");
        // No row held: the identity.
        let none = TangentProjector::new(&mut cholesky, &Gauge::default(), n, &[]).unwrap();
        let mut same = w.clone();
        none.project(&mut same);
        assert_eq!(same, w);
        // Too many rows: no projector.
        let many: Vec<&Row> = (0..=MAX_TANGENT_ROWS).map(|_| &rows[0]).collect();
        assert!(TangentProjector::new(&mut cholesky, &Gauge::default(), n, &many).is_none());
    }
}
