//! The step of the inequality-constrained problem (SQP, DESIGN §3):
//! `min ½ dᵀ H d + gᵀ d  s.t.  value_i + a_i · d ≥ 0` for the rows of joint limits and
//! contact. clarabel identifies the active set; the step on that set is then computed
//! exactly with the sparse Cholesky factor of `H` (a Schur complement on the few active
//! rows), so the multipliers — the contact forces and the stops' reactions — are exact
//! to round-off rather than to the interior-point tolerance ([`exact`], refined per
//! independent group of rows, [`groups`]).

mod exact;
mod groups;
mod kkt;
#[cfg(test)]
mod kkt_tests;
mod kkt_updates;
#[cfg(test)]
mod kkt_updates_tests;
#[cfg(test)]
mod scaling_tests;

pub(crate) use exact::{exact_step, exact_step_of_independent_rows};

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus};
use strand_system::HessianPattern;

use crate::constraints::Row;
use crate::{LinearError, SolveError, SparseCholesky};

/// A step and the multiplier of every row (≥ 0; in the row's force unit).
pub(crate) struct ConstrainedStep {
    /// The step.
    pub step: Vec<f64>,
    /// One multiplier per row, in the order of the rows.
    pub multipliers: Vec<f64>,
}

/// Largest violation of a linearised row accepted for the exact step, in the row's unit.
const FEASIBILITY: f64 = 1e-10;

/// Largest part of a step's approach along an open row (`−a·d`, in the row's unit) by
/// which the step may carry the row into violation (see [`violation_by`]).
const OVERSHOOT: f64 = 1e-3;

/// Smallest approach (m or rad) that [`OVERSHOOT`] judges: below it the approach is
/// round-off of the step.
const APPROACH_FLOOR: f64 = 1e-15;

/// The linearised value of `row` after `step` when the exact step does not tolerate it:
/// below `−FEASIBILITY`, or below 0 by more than [`OVERSHOOT`] of the step's approach
/// along the row. Near convergence a step of nanometres would otherwise cut a touching
/// row (a nearly tied ridge of a finely faceted drum) by 1e-12 m: the exact penalty
/// sees that, and with a merit weight of 100 N it outweighs the 1e-13 J the step gains,
/// so every trial was rejected whatever its length (the 94,500-facet drum's coarse
/// stage crept for 80 iterations at trust radii of 1e-8).
pub(crate) fn violation_by(row: &Row, step: &[f64]) -> Option<f64> {
    let after = row.linearised(step);
    let approach = row.value - after;
    let overshoot = after < 0.0 && approach > APPROACH_FLOOR && -after > OVERSHOOT * approach;
    (after < -FEASIBILITY || overshoot).then_some(after)
}

/// Solves the QP for the Hessian `values` (positive definite, already factorised in
/// `cholesky`), the gradient and the rows; `newton` is the unconstrained step `−H⁻¹g`.
/// A primal–dual active set started from `hint` (rows active at the previous iterate)
/// is tried first; clarabel's interior-point QP only when it does not settle. A `hint`
/// that is only `guessed` (the rows closed at a step without a last QP) that does not
/// settle is followed by the empty start before the QP: a guess can hold rows that
/// depend on each other inconsistently (consistent ones are held out by the exact
/// step; a hose on a bracket at 8000 segments held 194 closed rows with such a trio),
/// and the interior-point multipliers of the QP, small but positive on every open row,
/// once made the next step start from all 21,389 rows.
pub(crate) fn constrained_step(
    pattern: &HessianPattern,
    values: &[f64],
    cholesky: &mut SparseCholesky,
    gradient: &[f64],
    rows: &[Row],
    newton: &[f64],
    hint: &[usize],
    guessed: bool,
) -> Result<ConstrainedStep, SolveError> {
    if hint.is_empty() && rows.iter().all(|r| violation_by(r, newton).is_none()) {
        return Ok(ConstrainedStep {
            step: newton.to_vec(),
            multipliers: vec![0.0; rows.len()],
        });
    }
    // The primal–dual active set from the previous iterate's set usually settles in a
    // few Schur solves; the interior-point QP is the fallback.
    if let Some(exact) = exact_step(cholesky, rows, hint, newton) {
        return Ok(exact);
    }
    if guessed
        && !hint.is_empty()
        && let Some(exact) = exact_step(cholesky, rows, &[], newton)
    {
        return Ok(exact);
    }
    let (qp_step, qp_multipliers) = solve_qp(pattern, values, gradient, rows)?;
    let largest = qp_multipliers.iter().fold(0.0f64, |m, &z| m.max(z));
    // Active: a multiplier that counts and a row the QP step closes (interior-point
    // multipliers of open rows are small but not zero).
    let active: Vec<usize> = (0..rows.len())
        .filter(|&i| {
            qp_multipliers[i] > 1e-8 * largest.max(1e-12)
                && rows[i].linearised(&qp_step) <= 1e-6 * (1.0 + rows[i].value.abs())
        })
        .collect();
    if let Some(exact) = exact_step(cholesky, rows, &active, newton) {
        return Ok(exact);
    }
    // Only the rows the QP holds carry a multiplier: the next step starts its active
    // set from the rows with one, and the open rows' small interior-point values would
    // put every row in it.
    let mut multipliers = vec![0.0; rows.len()];
    for &i in &active {
        multipliers[i] = qp_multipliers[i];
    }
    Ok(ConstrainedStep {
        step: qp_step,
        multipliers,
    })
}

/// clarabel: `min ½ dᵀ P d + gᵀ d  s.t.  −A d + s = value, s ≥ 0`; returns the step and
/// the multipliers.
fn solve_qp(
    pattern: &HessianPattern,
    values: &[f64],
    gradient: &[f64],
    rows: &[Row],
) -> Result<(Vec<f64>, Vec<f64>), SolveError> {
    let n = pattern.dim();
    let p = CscMatrix::new(
        n,
        n,
        pattern.col_ptr.clone(),
        pattern.row_idx.clone(),
        values.to_vec(),
    );
    let mut entries: Vec<(usize, usize, f64)> = rows
        .iter()
        .enumerate()
        .flat_map(|(i, r)| r.gradient.iter().map(move |&(k, a)| (k, i, -a)))
        .collect();
    entries.sort_by_key(|&(k, i, _)| (k, i));
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::with_capacity(entries.len());
    let mut a_values = Vec::with_capacity(entries.len());
    let mut next = 0;
    for column in 0..n {
        col_ptr.push(row_idx.len());
        while next < entries.len() && entries[next].0 == column {
            let (_, i, a) = entries[next];
            // Merge duplicates (a row touching one unknown twice).
            if row_idx.len() > col_ptr[column] && row_idx.last() == Some(&i) {
                *a_values.last_mut().expect("entry") += a;
            } else {
                row_idx.push(i);
                a_values.push(a);
            }
            next += 1;
        }
    }
    col_ptr.push(row_idx.len());
    let a = CscMatrix::new(rows.len(), n, col_ptr, row_idx, a_values);
    let b: Vec<f64> = rows.iter().map(|r| r.value).collect();
    let cones = [NonnegativeConeT(rows.len())];
    let settings = DefaultSettings::<f64> {
        verbose: false,
        ..Default::default()
    };
    let mut solver = DefaultSolver::new(&p, gradient, &a, &b, &cones, settings).map_err(|e| {
        LinearError::Failed {
            stage: "QP set-up",
            detail: format!("{e:?}"),
        }
    })?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {}
        status => {
            return Err(LinearError::Subproblem {
                status: format!("{status:?}"),
            }
            .into());
        }
    }
    let multipliers = solver.solution.z.iter().map(|&z| z.max(0.0)).collect();
    Ok((solver.solution.x.clone(), multipliers))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::RowKey;

    /// One 3×3 block with `H = diag(2, 4, 1)`.
    fn diagonal_problem() -> (HessianPattern, Vec<f64>, SparseCholesky) {
        let structure: Vec<Vec<usize>> = vec![];
        let pattern = HessianPattern::new(1, structure.iter().map(|b| b.as_slice()));
        let mut values = vec![0.0; pattern.nnz()];
        let diag = [2.0, 4.0, 1.0];
        for c in 0..3 {
            let rows = &pattern.row_idx[pattern.col_ptr[c]..pattern.col_ptr[c + 1]];
            let at = rows.iter().position(|&r| r == c).unwrap();
            values[pattern.col_ptr[c] + at] = diag[c];
        }
        let mut cholesky = SparseCholesky::try_new(&pattern).unwrap();
        assert!(cholesky.factor(&values));
        (pattern, values, cholesky)
    }

    fn row(key: u64, value: f64, gradient: Vec<(usize, f64)>) -> Row {
        Row {
            key: RowKey::Contact(key),
            value,
            gradient,
            curvature: None,
        }
    }

    #[test]
    fn dependent_rows_in_a_start_are_held_out_and_the_step_is_exact() {
        // g = (−2, 8, −3), free minimiser (1, −2, 3); d0 ≤ 0.5 twice (the same row: an
        // edge's row on a face with its vertices' rows) and an open row 10 + d1 ≥ 0:
        // the solution is d0 = 0.5 with a force of 1, on either row.
        let (_, _, mut cholesky) = diagonal_problem();
        let newton = [1.0, -2.0, 3.0];
        let rows = [
            row(0, 0.5, vec![(0, -1.0)]),
            row(1, 0.5, vec![(0, -1.0)]),
            row(2, 10.0, vec![(1, 1.0)]),
        ];
        for start in [vec![0, 1], vec![0, 1, 2], vec![]] {
            let result = exact_step(&mut cholesky, &rows, &start, &newton)
                .unwrap_or_else(|| panic!("start {start:?}: the step settles"));
            assert_eq!(result.step, vec![0.5, -2.0, 3.0], "start {start:?}");
            let held: Vec<f64> = (result.multipliers.iter().copied())
                .filter(|&l| l > 0.0)
                .collect();
            assert!(
                held.len() == 1 && (held[0] - 1.0).abs() < 1e-14,
                "start {start:?}: {:?}",
                result.multipliers
            );
        }
        // A row held out must hold to round-off: one whose gap is 1e-11 m smaller
        // (within the 1e-10 m an open row may be cut by) comes back, and the start
        // fails; from the empty start the binding row alone is held.
        let rows = [
            row(0, 0.5, vec![(0, -1.0)]),
            row(1, 0.5 - 1e-11, vec![(0, -1.0)]),
            row(2, 10.0, vec![(1, 1.0)]),
        ];
        assert!(exact_step(&mut cholesky, &rows, &[0, 1], &newton).is_none());
        let result = exact_step(&mut cholesky, &rows, &[], &newton).unwrap();
        assert_eq!(result.step[0], 0.5 - 1e-11);
        assert!(result.multipliers[0] == 0.0 && result.multipliers[1] > 0.0);
    }

    #[test]
    fn a_failed_guess_starts_empty_and_the_qp_holds_no_open_row() {
        // As above, but the second row's gap is 1e-8 smaller: held out as dependent at
        // the start, it comes back violated, so the start fails (it depends on the
        // first row, but not consistently). The solution: d0 = 0.5 − 1e-8 on row 1.
        let (pattern, values, mut cholesky) = diagonal_problem();
        let gradient = [-2.0, 8.0, -3.0];
        let newton = [1.0, -2.0, 3.0];
        let rows = [
            row(0, 0.5, vec![(0, -1.0)]),
            row(1, 0.5 - 1e-8, vec![(0, -1.0)]),
            row(2, 10.0, vec![(1, 1.0)]),
        ];
        assert!(exact_step(&mut cholesky, &rows, &[0, 1], &newton).is_none());
        let solve = |cholesky: &mut SparseCholesky, guessed: bool| {
            constrained_step(
                &pattern,
                &values,
                cholesky,
                &gradient,
                &rows,
                &newton,
                &[0, 1],
                guessed,
            )
            .unwrap()
        };
        for guessed in [true, false] {
            let result = solve(&mut cholesky, guessed);
            assert!((result.step[0] - 0.5).abs() < 1e-7, "{:?}", result.step);
            let force = result.multipliers[0] + result.multipliers[1];
            assert!((force - 1.0).abs() < 1e-6, "{:?}", result.multipliers);
            // The open row carries no multiplier, not the QP's small interior value.
            assert_eq!(result.multipliers[2], 0.0, "guessed {guessed}");
        }
        // A guess is followed by the empty start: the exact step, one row held.
        let guessed = solve(&mut cholesky, true);
        assert_eq!(
            guessed.multipliers.iter().filter(|&&l| l > 0.0).count(),
            1,
            "{:?}",
            guessed.multipliers
        );
        assert!((guessed.step[0] - (0.5 - 1e-8)).abs() < 1e-14);
    }

    #[test]
    fn a_step_may_not_carry_a_touching_row_into_violation_by_a_fraction_of_its_approach() {
        let step = [1.0];
        // Touching, approached by 3e-12 m: cut by all of it (far below 1e-10 m).
        assert_eq!(
            violation_by(&row(0, 0.0, vec![(0, -3e-12)]), &step),
            Some(-3e-12)
        );
        // Open by 1e-12 m, approached by 2e-12 m: cut by half the approach.
        assert!(violation_by(&row(0, 1e-12, vec![(0, -2e-12)]), &step).is_some());
        // Approached by 1 m and cut by 1e-12 m (1e-12 of the approach): tolerated.
        assert_eq!(
            violation_by(&row(0, 1.0 - 1e-12, vec![(0, -1.0)]), &step),
            None
        );
        // Violated by 5e-11 m without approach (round-off of the value): tolerated.
        assert_eq!(violation_by(&row(0, -5e-11, vec![(0, 0.0)]), &step), None);
        // An approach of round-off (1e-16 m): not judged.
        assert_eq!(
            violation_by(&row(0, -5e-17, vec![(0, -1e-16)]), &step),
            None
        );
        // Beyond 1e-10 m: violated, however long the approach.
        assert!(violation_by(&row(0, 1.0, vec![(0, -1.0 - 2e-10)]), &step).is_some());
        // Opened: never.
        assert_eq!(violation_by(&row(0, 0.0, vec![(0, 1e-12)]), &step), None);
    }

    #[test]
    fn the_step_holds_a_touching_row_it_would_cut_by_a_picometre() {
        // g = (−2, 8, −3), free minimiser (1, −2, 3). The row 1e-12 − 2e-12 d0 ≥ 0 is cut
        // by 1e-12 at the Newton step (within 1e-10 m, which alone let it through):
        // held, d0 = 0.5.
        let (pattern, values, mut cholesky) = diagonal_problem();
        let gradient = [-2.0, 8.0, -3.0];
        let newton = [1.0, -2.0, 3.0];
        let rows = [row(0, 1e-12, vec![(0, -2e-12)])];
        let result = constrained_step(
            &pattern,
            &values,
            &mut cholesky,
            &gradient,
            &rows,
            &newton,
            &[],
            false,
        )
        .unwrap();
        assert!((result.step[0] - 0.5).abs() < 1e-12, "{:?}", result.step);
        assert!((result.step[1] + 2.0).abs() < 1e-12 && (result.step[2] - 3.0).abs() < 1e-12);
        assert!(rows[0].linearised(&result.step) >= -1e-24);
        assert!(result.multipliers[0] > 0.0);
    }

    #[test]
    fn active_rows_are_met_exactly_with_their_multipliers() {
        // g = (−2, 8, −3): the free minimiser is (1, −2, 3). Rows: 0.5 + d1 ≥ 0 (active:
        // 4 d1 + 8 = λ0 at d1 = −0.5, λ0 = 6), 1 − d0 − d2 ≥ 0 (active: 2 d0 − 2 = −λ1,
        // d2 − 3 = −λ1, d0 + d2 = 1, so λ1 = 2, d0 = 0, d2 = 1) and 10 + d0 ≥ 0 (open).
        let (pattern, values, mut cholesky) = diagonal_problem();
        let gradient = [-2.0, 8.0, -3.0];
        let newton = [1.0, -2.0, 3.0];
        let rows = [
            row(0, 0.5, vec![(1, 1.0)]),
            row(1, 1.0, vec![(0, -1.0), (2, -1.0)]),
            row(2, 10.0, vec![(0, 1.0)]),
        ];
        let result = constrained_step(
            &pattern,
            &values,
            &mut cholesky,
            &gradient,
            &rows,
            &newton,
            &[],
            false,
        )
        .unwrap();
        let lambda = 2.0;
        let expected = [0.0, -0.5, 1.0];
        for i in 0..3 {
            assert!(
                (result.step[i] - expected[i]).abs() < 1e-13,
                "{:?}",
                result.step
            );
        }
        assert!((result.multipliers[0] - 6.0).abs() < 1e-12);
        assert!((result.multipliers[1] - lambda).abs() < 1e-12);
        assert_eq!(result.multipliers[2], 0.0);
        // Stationarity of the QP: H d + g = Σ λ_i a_i.
        let h = [2.0, 4.0, 1.0];
        let mut r: Vec<f64> = (0..3)
            .map(|i| h[i] * result.step[i] + gradient[i])
            .collect();
        for (row, l) in rows.iter().zip(&result.multipliers) {
            for &(k, a) in &row.gradient {
                r[k] -= l * a;
            }
        }
        assert!(r.iter().all(|x| x.abs() < 1e-12), "{r:?}");
    }

    #[test]
    fn a_feasible_newton_step_is_kept_without_multipliers() {
        let (pattern, values, mut cholesky) = diagonal_problem();
        let rows = [row(0, 5.0, vec![(1, 1.0)])];
        let newton = [1.0, -2.0, 3.0];
        let result = constrained_step(
            &pattern,
            &values,
            &mut cholesky,
            &[-2.0, 8.0, -3.0],
            &rows,
            &newton,
            &[],
            false,
        )
        .unwrap();
        assert_eq!(result.step, newton);
        assert_eq!(result.multipliers, vec![0.0]);
    }
}
