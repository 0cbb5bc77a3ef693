//! The linearised KKT system `[H −Aᵀ; A 0] (v, w) = −(r, c)` solved with the sparse
//! Cholesky factor of the energy Hessian (gauge held) and a dense Schur complement on
//! the active rows.

use nalgebra::{DMatrix, DVector};
use strand_system::Model;

use super::SensitivityError;
use super::kkt::Kkt;
use crate::SparseCholesky;
use crate::constraints::Row;
use crate::gauge::Gauge;

/// Singular values of the Schur complement below this fraction of the largest are
/// dropped (dependent rows: one contact seen twice).
const SCHUR_CUTOFF: f64 = 1e-12;

/// The factorised linearised KKT system at the base equilibrium.
pub(crate) struct KktFactor {
    cholesky: SparseCholesky,
    /// The Hessian with the gauge held (values of the model's pattern).
    hessian: Vec<f64>,
    pattern: strand_system::HessianPattern,
    /// The active rows' gradients without the gauge-held unknowns.
    rows: Vec<Vec<(usize, f64)>>,
    /// `H⁻¹ a_i` per active row.
    columns: Vec<Vec<f64>>,
    /// SVD of the Schur complement `A H⁻¹ Aᵀ` (`None` without active rows).
    schur: Option<nalgebra::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>>,
    /// Whether dependent rows were found (their multipliers' split is not unique).
    pub dependent: bool,
}

impl KktFactor {
    /// Factorises `hessian` (values of the model's pattern at the equilibrium) with the
    /// gauge held, and the Schur complement of the `active` rows.
    pub(crate) fn new(
        model: &Model,
        hessian: &[f64],
        gauge: &Gauge,
        active: &[&Row],
    ) -> Result<Self, SensitivityError> {
        let mut cholesky = SparseCholesky::try_new(model.pattern())?;
        let mut values = hessian.to_vec();
        gauge.fix_matrix(&mut values);
        if !cholesky.factor(&values) {
            return Err(SensitivityError::NotPositiveDefinite);
        }
        let n = model.dofs().len();
        let held = gauge.held();
        let rows: Vec<Vec<(usize, f64)>> = active
            .iter()
            .map(|r| {
                r.gradient
                    .iter()
                    .copied()
                    .filter(|(k, _)| held.binary_search(k).is_err())
                    .collect()
            })
            .collect();
        let columns: Vec<Vec<f64>> = rows
            .iter()
            .map(|row| {
                let mut w = vec![0.0; n];
                for &(k, a) in row {
                    w[k] += a;
                }
                cholesky.solve_in_place(&mut w);
                w
            })
            .collect();
        let m = rows.len();
        let dot = |row: &[(usize, f64)], w: &[f64]| row.iter().map(|&(k, a)| a * w[k]).sum::<f64>();
        let mut dependent = false;
        let schur = (m > 0).then(|| {
            let s = DMatrix::from_fn(m, m, |i, j| {
                0.5 * (dot(&rows[i], &columns[j]) + dot(&rows[j], &columns[i]))
            });
            let svd = s.svd(true, true);
            let largest = svd.singular_values.max();
            dependent = svd
                .singular_values
                .iter()
                .any(|&x| x <= SCHUR_CUTOFF * largest);
            svd
        });
        Ok(Self {
            cholesky,
            hessian: values,
            pattern: model.pattern().clone(),
            rows,
            columns,
            schur,
            dependent,
        })
    }

    /// `H v` with the gauge held.
    pub(crate) fn hessian_product(&self, v: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; v.len()];
        crate::linear::symmetric_product(&self.pattern, &self.hessian, v, &mut out);
        out
    }

    /// `Aᵀ w` (the active rows, gauge entries dropped).
    pub(crate) fn transpose_product(&self, w: &[f64]) -> Vec<f64> {
        let n = self.hessian_dim();
        let mut out = vec![0.0; n];
        for (row, &wi) in self.rows.iter().zip(w) {
            for &(k, a) in row {
                out[k] += a * wi;
            }
        }
        out
    }

    /// `A v`.
    pub(crate) fn row_product(&self, v: &[f64]) -> Vec<f64> {
        self.rows
            .iter()
            .map(|row| row.iter().map(|&(k, a)| a * v[k]).sum())
            .collect()
    }

    fn hessian_dim(&self) -> usize {
        self.pattern.dim()
    }

    /// Solves `[H −Aᵀ; A 0] (v, w) = −(rhs.gradient, rhs.gaps)`: the state and
    /// multiplier changes `v` (chart units) and `w` (N, N·m).
    pub(crate) fn solve(&mut self, rhs: &Kkt) -> (Vec<f64>, Vec<f64>) {
        let mut y = rhs.gradient.clone();
        self.cholesky.solve_in_place(&mut y);
        let m = self.rows.len();
        let w: Vec<f64> = match &self.schur {
            None => Vec::new(),
            Some(svd) => {
                let b = DVector::from_fn(m, |i, _| {
                    -rhs.gaps[i] + self.rows[i].iter().map(|&(k, a)| a * y[k]).sum::<f64>()
                });
                let cutoff = SCHUR_CUTOFF * svd.singular_values.max();
                svd.solve(&b, cutoff)
                    .map(|x| x.iter().copied().collect())
                    .unwrap_or_else(|_| vec![0.0; m])
            }
        };
        let mut v: Vec<f64> = y.iter().map(|x| -x).collect();
        for (column, &wi) in self.columns.iter().zip(&w) {
            for (vk, ck) in v.iter_mut().zip(column) {
                *vk += wi * ck;
            }
        }
        (v, w)
    }
}
