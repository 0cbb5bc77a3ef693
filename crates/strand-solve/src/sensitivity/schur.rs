//! The linearised KKT system `[H −Aᵀ; A 0] (v, w) = −(r, c)` solved with the sparse
//! Cholesky factor of the energy Hessian (gauge held) and a dense Schur complement on
//! the active rows.

use nalgebra::{DMatrix, DVector};
use strand_system::Model;

use super::SensitivityError;
use super::kkt::Kkt;
use crate::constraints::Row;
use crate::gauge::Gauge;
use crate::{PatternAnalysis, SparseCholesky};

/// Singular values of the Schur complement below this fraction of the largest are
/// dropped (dependent rows: one contact seen twice).
const SCHUR_CUTOFF: f64 = 1e-12;

/// Factorises `H + ρ AᵀA` (`values`: `H` with the gauge held; `rows`: the active rows
/// `A`) for the smallest `ρ` of a ladder from 1e-2 to 1e6 times `H`'s largest diagonal
/// entry that makes it positive definite, and returns `ρ`. An equilibrium whose
/// Hessian is definite on the directions its active rows leave free (the null space
/// of `A`) has one (Finsler's lemma); one that is not (an unstable state, or a
/// neutral direction the rows do not hold), or whose rows couple unknowns the
/// Hessian's pattern does not, is [`SensitivityError::NotPositiveDefinite`].
fn augmented_factor(
    cholesky: &mut SparseCholesky,
    pattern: &strand_system::HessianPattern,
    values: &[f64],
    rows: &[Vec<(usize, f64)>],
) -> Result<f64, SensitivityError> {
    if rows.is_empty() {
        return Err(SensitivityError::NotPositiveDefinite);
    }
    // Where each product a_k a_l of every row goes in the upper triangle.
    let entry = |i: usize, j: usize| {
        let (r, c) = if i <= j { (i, j) } else { (j, i) };
        let range = pattern.col_ptr[c]..pattern.col_ptr[c + 1];
        pattern.row_idx[range.clone()]
            .binary_search(&r)
            .ok()
            .map(|p| range.start + p)
    };
    let mut products: Vec<(usize, f64)> = Vec::new();
    for row in rows {
        // One entry per unknown (a row may name one twice): a aᵀ, upper triangle.
        let mut merged: Vec<(usize, f64)> = Vec::with_capacity(row.len());
        let mut sorted = row.clone();
        sorted.sort_by_key(|&(k, _)| k);
        for (k, a) in sorted {
            match merged.last_mut() {
                Some((last, sum)) if *last == k => *sum += a,
                _ => merged.push((k, a)),
            }
        }
        for (x, &(k, a)) in merged.iter().enumerate() {
            for &(l, b) in &merged[x..] {
                let at = entry(k, l).ok_or(SensitivityError::NotPositiveDefinite)?;
                products.push((at, a * b));
            }
        }
    }
    let diagonal = (0..pattern.dim())
        .filter_map(|k| entry(k, k))
        .map(|at| values[at].abs())
        .fold(0.0f64, f64::max);
    let mut augmented = values.to_vec();
    for exponent in -2..=6 {
        let rho = diagonal * 10f64.powi(exponent);
        augmented.copy_from_slice(values);
        for &(at, product) in &products {
            augmented[at] += rho * product;
        }
        if cholesky.factor(&augmented) {
            return Ok(rho);
        }
    }
    Err(SensitivityError::NotPositiveDefinite)
}

/// The factorised linearised KKT system at the base equilibrium.
pub(crate) struct KktFactor {
    cholesky: SparseCholesky,
    /// The Hessian with the gauge held (values of the model's pattern).
    hessian: Vec<f64>,
    pattern: strand_system::HessianPattern,
    /// `ρ` of the factor `H + ρ AᵀA` (N/m or N·m/rad per unit row), 0 when `H` itself
    /// is positive definite: an equilibrium held only by its active rows (a hose
    /// pressed into a groove under axial compression) has an indefinite `H` but is
    /// stable on the directions the rows leave free, where `H + ρ AᵀA` is definite.
    penalty: f64,
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
    /// gauge held, and the Schur complement of the `active` rows. The pattern's
    /// symbolic analysis is taken from `analysis` where it is that pattern's (the
    /// solver's, handed on with its solution), else computed.
    pub(crate) fn new(
        model: &Model,
        hessian: &[f64],
        gauge: &Gauge,
        active: &[&Row],
        analysis: Option<&PatternAnalysis>,
    ) -> Result<Self, SensitivityError> {
        let mut cholesky = match analysis.filter(|a| a.is_of(model.pattern())) {
            Some(analysis) => SparseCholesky::from_analysis(analysis)?,
            None => SparseCholesky::try_new(model.pattern())?,
        };
        let mut values = hessian.to_vec();
        gauge.fix_matrix(&mut values);
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
        let penalty = if cholesky.factor(&values) {
            0.0
        } else {
            augmented_factor(&mut cholesky, model.pattern(), &values, &rows)?
        };
        let n = model.dofs().len();
        // `H⁻¹ a_i` of every row in one pass through the factor.
        let mut stacked = vec![0.0; n * rows.len()];
        for (i, row) in rows.iter().enumerate() {
            for &(k, a) in row {
                stacked[i * n + k] += a;
            }
        }
        cholesky.solve_columns_in_place(&mut stacked, rows.len());
        let columns: Vec<Vec<f64>> = (0..rows.len())
            .map(|i| stacked[i * n..(i + 1) * n].to_vec())
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
            penalty,
            rows,
            columns,
            schur,
            dependent,
        })
    }

    /// Whether the factor is of `H + ρ AᵀA` (`H` alone indefinite: the equilibrium is
    /// held by its active rows).
    pub(crate) fn augmented(&self) -> bool {
        self.penalty > 0.0
    }

    /// `H v` with the gauge held.
    pub(crate) fn hessian_product(&self, v: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; v.len()];
        crate::linear::symmetric_product(&self.pattern, &self.hessian, v, &mut out);
        out
    }

    /// `H v` with the gauge held for every vector of `vs`: the Hessian read once per
    /// eight vectors (the last group by the fewest of two, four or eight that holds
    /// it, [`crate::linear::symmetric_products`]); each result equals
    /// [`KktFactor::hessian_product`]'s bit for bit.
    pub(crate) fn hessian_products(&self, vs: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let mut out = Vec::with_capacity(vs.len());
        for group in vs.chunks(8) {
            match group.len() {
                1 => out.push(self.hessian_product(&group[0])),
                2 => self.grouped_products::<2>(group, &mut out),
                3 | 4 => self.grouped_products::<4>(group, &mut out),
                _ => self.grouped_products::<8>(group, &mut out),
            }
        }
        out
    }

    /// `H v` of the (at most `K`) vectors of `group`, interleaved for one pass over the
    /// Hessian, appended to `out`.
    fn grouped_products<const K: usize>(&self, group: &[Vec<f64>], out: &mut Vec<Vec<f64>>) {
        let n = self.hessian_dim();
        let x: Vec<[f64; K]> = (0..n)
            .map(|i| std::array::from_fn(|k| group.get(k).map_or(0.0, |v| v[i])))
            .collect();
        let mut y = vec![[0.0; K]; n];
        crate::linear::symmetric_products(&self.pattern, &self.hessian, &x, &mut y);
        for k in 0..group.len() {
            out.push(y.iter().map(|yi| yi[k]).collect());
        }
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
    ///
    /// With the factor of `H + ρ AᵀA` the first equation is solved as
    /// `(H + ρ AᵀA) v − Aᵀ w = −(rhs.gradient + ρ Aᵀ rhs.gaps)`, the same system, as
    /// `A v = −rhs.gaps`.
    pub(crate) fn solve(&mut self, rhs: &Kkt) -> (Vec<f64>, Vec<f64>) {
        self.solve_all(std::slice::from_ref(&rhs)).swap_remove(0)
    }

    /// [`KktFactor::solve`] for every right-hand side of `rhs`, with one pass through
    /// the factor for all of them ([`crate::SparseCholesky::solve_columns_in_place`]):
    /// each result is the one [`KktFactor::solve`] gives alone, bit for bit.
    pub(crate) fn solve_all(&mut self, rhs: &[&Kkt]) -> Vec<(Vec<f64>, Vec<f64>)> {
        let n = self.hessian_dim();
        let mut stacked = Vec::with_capacity(n * rhs.len());
        for side in rhs {
            let start = stacked.len();
            stacked.extend_from_slice(&side.gradient);
            let y = &mut stacked[start..];
            if self.penalty > 0.0 {
                for (row, &c) in self.rows.iter().zip(&side.gaps) {
                    for &(k, a) in row {
                        y[k] += self.penalty * a * c;
                    }
                }
            }
        }
        self.cholesky
            .solve_columns_in_place(&mut stacked, rhs.len());
        rhs.iter()
            .enumerate()
            .map(|(j, side)| self.multipliers_and_state(side, &stacked[j * n..(j + 1) * n]))
            .collect()
    }

    /// `(v, w)` from `y = (H + ρ AᵀA)⁻¹ (rhs.gradient + ρ Aᵀ rhs.gaps)`: the Schur
    /// complement's multipliers `w` and `v = −y + H⁻¹ Aᵀ w`.
    fn multipliers_and_state(&self, rhs: &Kkt, y: &[f64]) -> (Vec<f64>, Vec<f64>) {
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
