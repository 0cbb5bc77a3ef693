//! The bound-constrained Newton step as a clarabel QP (the SQP path of DESIGN §3):
//! `min ½ dᵀ H d + gᵀ d  s.t.  lower_i ≤ d_i ≤ upper_i` for the bounded unknowns (joint
//! limits). The multipliers are the forces or moments of the stops.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus};
use strand_system::HessianPattern;

use crate::SolveError;

/// The QP step and the bounds it ends on.
pub(crate) struct BoundedStep {
    /// The step.
    pub step: Vec<f64>,
    /// `(unknown index, value)` of every bound the step lies on.
    pub active: Vec<(usize, f64)>,
}

/// Solves the QP with the (positive definite) Hessian `values` in `pattern`.
pub(crate) fn bounded_step(
    pattern: &HessianPattern,
    values: &[f64],
    gradient: &[f64],
    bounds: &[(usize, f64, f64)],
) -> Result<BoundedStep, SolveError> {
    let n = pattern.dim();
    let p = CscMatrix::new(
        n,
        n,
        pattern.col_ptr.clone(),
        pattern.row_idx.clone(),
        values.to_vec(),
    );
    // Rows 2k (d_i ≤ upper) and 2k+1 (−d_i ≤ −lower) of bound k, as `A d + s = b, s ≥ 0`.
    let mut order: Vec<usize> = (0..bounds.len()).collect();
    order.sort_by_key(|&k| bounds[k].0);
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::with_capacity(2 * bounds.len());
    let mut a_values = Vec::with_capacity(2 * bounds.len());
    let mut next = 0;
    for column in 0..n {
        col_ptr.push(row_idx.len());
        while next < order.len() && bounds[order[next]].0 == column {
            let k = order[next];
            row_idx.extend([2 * k, 2 * k + 1]);
            a_values.extend([1.0, -1.0]);
            next += 1;
        }
    }
    col_ptr.push(row_idx.len());
    let a = CscMatrix::new(2 * bounds.len(), n, col_ptr, row_idx, a_values);
    let b: Vec<f64> = bounds
        .iter()
        .flat_map(|&(_, lower, upper)| [upper, -lower])
        .collect();
    let cones = [NonnegativeConeT(2 * bounds.len())];
    // Moderate accuracy: the QP only has to find which stops are active; the exact step
    // on that active set is then computed with the sparse Cholesky ([`fix_active`]).
    let settings = DefaultSettings::<f64> {
        verbose: false,
        ..Default::default()
    };
    let mut solver = DefaultSolver::new(&p, gradient, &a, &b, &cones, settings)
        .map_err(|e| SolveError::Linear(format!("QP set-up failed: {e:?}")))?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {}
        status => {
            return Err(SolveError::Linear(format!(
                "the bound-constrained step QP ended with {status:?}"
            )));
        }
    }
    let mut step = solver.solution.x.clone();
    let mut active = Vec::new();
    for &(index, lower, upper) in bounds {
        let tolerance = 1e-7 * (1.0 + lower.abs().max(upper.abs()));
        step[index] = step[index].clamp(lower, upper);
        if step[index] - lower <= tolerance {
            active.push((index, lower));
        } else if upper - step[index] <= tolerance {
            active.push((index, upper));
        }
    }
    Ok(BoundedStep { step, active })
}

/// The Hessian and right-hand side of the Newton step with the `active` unknowns fixed
/// at their values: their rows and columns become unit rows, their known values move to
/// the right-hand side `rhs` (which holds `−g` on entry).
pub(crate) fn fix_active(
    pattern: &HessianPattern,
    values: &mut [f64],
    rhs: &mut [f64],
    active: &[(usize, f64)],
) {
    let fixed = |i: usize| {
        active
            .iter()
            .find(|&&(index, _)| index == i)
            .map(|&(_, v)| v)
    };
    for column in 0..pattern.dim() {
        for k in pattern.col_ptr[column]..pattern.col_ptr[column + 1] {
            let row = pattern.row_idx[k];
            match (fixed(row), fixed(column)) {
                (None, None) => {}
                (Some(_), Some(_)) if row == column => values[k] = 1.0,
                (row_value, column_value) => {
                    if let (None, Some(v)) = (row_value, column_value) {
                        rhs[row] -= values[k] * v;
                    }
                    if let (Some(v), None) = (row_value, column_value) {
                        rhs[column] -= values[k] * v;
                    }
                    values[k] = 0.0;
                }
            }
        }
    }
    for &(index, value) in active {
        rhs[index] = value;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bound_cuts_a_diagonal_quadratic_exactly() {
        // Three unknowns, diagonal H = diag(2, 4, 1), g = (−2, 8, −3): the free minimiser
        // is (1, −2, 3); bounding d_1 ≥ −0.5 and d_2 ≤ 1 moves those onto the bounds.
        let structure: Vec<Vec<usize>> = vec![];
        let pattern = HessianPattern::new(1, structure.iter().map(|b| b.as_slice()));
        // One 3×3 diagonal block: upper-triangular values column by column.
        let mut values = vec![0.0; pattern.nnz()];
        let diag = [2.0, 4.0, 1.0];
        for c in 0..3 {
            let rows = &pattern.row_idx[pattern.col_ptr[c]..pattern.col_ptr[c + 1]];
            let at = rows.iter().position(|&r| r == c).unwrap();
            values[pattern.col_ptr[c] + at] = diag[c];
        }
        let gradient = [-2.0, 8.0, -3.0];
        let result = bounded_step(
            &pattern,
            &values,
            &gradient,
            &[(1, -0.5, 10.0), (2, -10.0, 1.0)],
        )
        .unwrap();
        let expected = [1.0, -0.5, 1.0];
        for i in 0..3 {
            assert!(
                (result.step[i] - expected[i]).abs() < 1e-9,
                "{:?}",
                result.step
            );
        }
    }
}
