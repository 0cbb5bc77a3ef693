//! The exact step on an active set: `d = d_N + Σ λ_j H⁻¹ a_j` with
//! `(A H⁻¹ Aᵀ) λ = −value − A d_N` for the rows held at zero, refined as a primal–dual
//! active set (a row with a negative multiplier leaves the set, the most violated other
//! row joins it).
//!
//! The rows are split into independent groups ([`RowGroups`]: rows reaching different
//! independent blocks of the Hessian never couple), and every group is refined on its
//! own. A column `H⁻¹ a_i` is kept only on its group's unknowns, and one sparse solve
//! serves one new row of every group at once (their right-hand sides do not overlap and
//! neither do their solutions, so each is exactly what a solve of its own gives). With
//! `G` groups of `m` rows each, one call costs about `m` solves instead of `G·m`, and
//! each step rebuild touches a group's unknowns instead of all `n`.

use nalgebra::{DMatrix, DVector};

use super::groups::RowGroups;
use super::{ConstrainedStep, FEASIBILITY};
use crate::SparseCholesky;
use crate::constraints::Row;

/// The work of one exact step, counted (not timed) for the complexity tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct ExactStepWork {
    /// Sparse solves with the Hessian's factor (each costs about the factor's size).
    pub solves: usize,
    /// Entries written to the kept columns `H⁻¹ a_i` and to the rebuilt steps.
    pub entries: usize,
}

/// The refinement state of one group.
#[derive(Default)]
struct GroupState {
    /// The rows held at zero, ascending after a pass.
    active: Vec<usize>,
    /// `(row, H⁻¹ a_row on the group's unknowns)`, for the rows of `active`.
    columns: Vec<(usize, Vec<f64>)>,
    /// Passes made (bounded by `2 rows + 4`).
    passes: usize,
    /// Whether the group's step meets all its rows with non-negative multipliers.
    settled: bool,
}

/// The step with the `active` rows held at zero (see the module documentation). `None`
/// if a group's Schur complement is singular or its refinement does not settle.
pub(crate) fn exact_step(
    cholesky: &mut SparseCholesky,
    rows: &[Row],
    active: &[usize],
    newton: &[f64],
) -> Option<ConstrainedStep> {
    exact_step_counted(cholesky, rows, active, newton).map(|(step, _)| step)
}

/// [`exact_step`] and the work it did.
pub(crate) fn exact_step_counted(
    cholesky: &mut SparseCholesky,
    rows: &[Row],
    active: &[usize],
    newton: &[f64],
) -> Option<(ConstrainedStep, ExactStepWork)> {
    let n = newton.len();
    let groups = RowGroups::new(cholesky.components(), rows);
    let mut states: Vec<GroupState> = (0..groups.count()).map(|_| GroupState::default()).collect();
    for &i in active {
        states[groups.of_row[i]].active.push(i);
    }
    for state in &mut states {
        state.active.sort_unstable();
        state.active.dedup();
    }
    // Per unknown of a group: its position in the group's columns.
    let mut local = vec![usize::MAX; n];
    for unknowns in &groups.unknowns {
        for (p, &u) in unknowns.iter().enumerate() {
            local[u] = p;
        }
    }
    let mut work = ExactStepWork::default();
    let mut step = newton.to_vec();
    let mut multipliers = vec![0.0; rows.len()];
    let mut rhs = vec![0.0; n];
    loop {
        let live: Vec<usize> = (0..groups.count())
            .filter(|&g| !states[g].settled)
            .collect();
        if live.is_empty() {
            break;
        }
        // The missing columns, one row of every group per shared solve.
        let mut missing: Vec<Vec<usize>> = Vec::with_capacity(live.len());
        for &g in &live {
            let state = &mut states[g];
            let held = &state.active;
            state.columns.retain(|(i, _)| held.binary_search(i).is_ok());
            let have = &state.columns;
            missing.push(
                (state.active.iter().copied())
                    .filter(|i| have.iter().all(|(j, _)| j != i))
                    .collect(),
            );
        }
        let depth = missing.iter().map(Vec::len).max().unwrap_or(0);
        for k in 0..depth {
            rhs.iter_mut().for_each(|x| *x = 0.0);
            for (&g, new) in live.iter().zip(&missing) {
                if let Some(&i) = new.get(k) {
                    debug_assert_eq!(groups.of_row[i], g);
                    for &(u, a) in &rows[i].gradient {
                        rhs[u] += a;
                    }
                }
            }
            cholesky.solve_in_place(&mut rhs);
            work.solves += 1;
            for (&g, new) in live.iter().zip(&missing) {
                if let Some(&i) = new.get(k) {
                    let column: Vec<f64> = groups.unknowns[g].iter().map(|&u| rhs[u]).collect();
                    work.entries += column.len();
                    states[g].columns.push((i, column));
                }
            }
        }
        for &g in &live {
            let state = &mut states[g];
            state.passes += 1;
            if state.passes > 2 * groups.rows[g].len() + 4 {
                return None;
            }
            let context = Pass {
                rows,
                group_rows: &groups.rows[g],
                unknowns: &groups.unknowns[g],
                local: &local,
                newton,
            };
            if let Some(settled) = context.refine(state, &mut step, &mut work)? {
                state.settled = true;
                for (&i, &l) in state.active.iter().zip(settled.iter()) {
                    multipliers[i] = l;
                }
            }
        }
    }
    Some((ConstrainedStep { step, multipliers }, work))
}

/// What one refinement pass of a group reads.
struct Pass<'a> {
    rows: &'a [Row],
    /// The group's rows.
    group_rows: &'a [usize],
    /// The group's unknowns (the support of its columns).
    unknowns: &'a [usize],
    /// Per unknown: its position among its group's unknowns.
    local: &'a [usize],
    newton: &'a [f64],
}

impl Pass<'_> {
    /// One primal–dual pass on `state` (its columns complete): the multipliers of the
    /// held rows from their Schur complement; the most negative one leaves the set, or
    /// else the group's step is rebuilt in `step` and its most violated open row joins
    /// the set. Returns the multipliers when neither happens (the group is settled);
    /// `None` outside when the Schur complement is not positive definite.
    fn refine(
        &self,
        state: &mut GroupState,
        step: &mut [f64],
        work: &mut ExactStepWork,
    ) -> Option<Option<DVector<f64>>> {
        let rows = self.rows;
        state.columns.sort_by_key(|(i, _)| *i);
        let m = state.active.len();
        let dot = |i: usize, w: &[f64]| {
            (rows[i].gradient.iter())
                .map(|&(k, a)| a * w[self.local[k]])
                .sum::<f64>()
        };
        let active = &state.active;
        let columns = &state.columns;
        let schur = DMatrix::from_fn(m, m, |r, c| dot(active[r], &columns[c].1));
        let rhs = DVector::from_fn(m, |r, _| -rows[active[r]].linearised(self.newton));
        let multipliers = if m == 0 {
            DVector::zeros(0)
        } else {
            schur.cholesky()?.solve(&rhs)
        };
        if let Some((r, _)) = multipliers
            .iter()
            .enumerate()
            .filter(|(_, l)| l.is_nan() || **l < 0.0)
            .min_by(|a, b| a.1.total_cmp(b.1))
        {
            state.active.remove(r);
            return Some(None);
        }
        for (p, &u) in self.unknowns.iter().enumerate() {
            let mut s = self.newton[u];
            for ((_, w), &l) in columns.iter().zip(multipliers.iter()) {
                s += l * w[p];
            }
            step[u] = s;
        }
        work.entries += self.unknowns.len();
        let violated = (self.group_rows.iter().copied())
            .filter(|i| active.binary_search(i).is_err())
            .map(|i| (i, rows[i].linearised(step)))
            .filter(|(_, v)| *v < -FEASIBILITY)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((i, _)) = violated {
            let at = state.active.binary_search(&i).unwrap_err();
            state.active.insert(at, i);
            return Some(None);
        }
        Some(Some(multipliers))
    }
}
