//! The exact step on an active set: `d = d_N + Σ λ_j H⁻¹ a_j` with
//! `(A H⁻¹ Aᵀ) λ = −value − A d_N` for the rows held at zero, refined as a primal–dual
//! active set (a row with a negative multiplier leaves the set, the most violated other
//! row joins it).
//!
//! The rows are split into independent groups ([`RowGroups`]: rows reaching different
//! independent blocks of the Hessian never couple), and every group is refined on its
//! own, by one of two methods ([`GroupMethod`]):
//!
//! * a group of many rows on a narrow band (one rod with many contacts) solves the KKT
//!   system of its active rows in profile form ([`super::kkt`]): a factorisation costs
//!   `O((unknowns + rows) · width²)`, without a solve per row or a dense Schur matrix,
//!   and later passes that change a few rows border it instead of factorising again
//!   ([`super::kkt_updates`]: a substitution per changed row and a dense solve over the
//!   changes);
//!   While no row it dropped wants back in, such a group changes its active set by
//!   whole batches (every violated row joins, every row of negative multiplier leaves,
//!   as a primal–dual active set method does): a cable landing on a floor along
//!   hundreds of contacts settles in a few passes instead of one pass per contact
//!   (each a factorisation of the whole band). A dropped row that is violated again
//!   ends the batches: from then on one row changes per pass, the method that cannot
//!   cycle. The settled step is the same (the QP's solution is unique).
//!
//! * other groups keep the columns `H⁻¹ a_i` on their own unknowns, and one sparse solve
//!   serves one new row of every such group at once (their right-hand sides do not
//!   overlap and neither do their solutions, so each is exactly what a solve of its own
//!   gives). With `G` groups of `m` rows each, one call costs about `m` solves instead
//!   of `G·m`, and each step rebuild touches a group's unknowns instead of all `n`.
//!
//! A held row that depends on the other held rows (its pivot has the wrong sign) is held
//! out of the set, once: the others hold it, to round-off, or it comes back and the
//! step falls back as before. Only the main step does so ([`exact_step`]); the
//! solver's optional corrections fail on it instead ([`exact_step_of_independent_rows`]).

use nalgebra::{DMatrix, DVector};

use super::groups::RowGroups;
use super::kkt::{KktFailure, KktInput};
use super::kkt_updates::KktUpdates;
use super::{ConstrainedStep, violation_by};
use crate::SparseCholesky;
use crate::constraints::Row;

/// How the step of each group of rows is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
// The solver always chooses automatically; the tests force each method.
#[cfg_attr(not(test), allow(dead_code))]
pub(crate) enum GroupMethod {
    /// The kept columns, until their passes so far would cost more than one pass with
    /// the KKT system (estimated by [`KktInput::costs`], on a narrow band only): from
    /// then on the KKT system. The columns' pass costs a solve per missing row, the step
    /// rebuild (rows × unknowns) and the Schur matrix's factorisation (rows³ / 3), so a
    /// few rows keep their columns and many rows switch. Counting the passes so far,
    /// not only the next one, bounds the columns' work at about one KKT pass: from an
    /// empty start the columns add one row per pass, each pass cheaper than a KKT
    /// pass, and a hose landing on a bracket along 164 contacts (8000 segments per
    /// hose) took 4.7 s of them before the rebuilds alone outgrew the KKT pass.
    Automatic,
    /// Always the kept columns `H⁻¹ a_i` and the Schur complement.
    Columns,
    /// Always the KKT system in profile form (whatever its width).
    Kkt,
}

/// The work of one exact step, counted (not timed) for the complexity tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct ExactStepWork {
    /// Sparse solves with the Hessian's factor (each costs about the factor's size).
    pub solves: usize,
    /// Entries written to the kept columns `H⁻¹ a_i` and to the rebuilt steps.
    pub entries: usize,
    /// Multiply–adds of the KKT factorisations and solves.
    pub products: usize,
    /// Refinement passes, summed over the groups.
    pub passes: usize,
}

/// The refinement state of one group.
#[derive(Default)]
struct GroupState {
    /// Whether the group solves its KKT system (else it keeps columns).
    kkt: bool,
    /// The estimated costs of its passes when it may switch to the KKT system.
    switch: Option<super::kkt::PassCosts>,
    /// The estimated cost of its passes with the kept columns so far, this one
    /// included: the group switches to the KKT system once it exceeds one KKT pass.
    columns_work: usize,
    /// The rows held at zero, ascending after a pass.
    active: Vec<usize>,
    /// `(row, H⁻¹ a_row on the group's unknowns)`, for the rows of `active`.
    columns: Vec<(usize, Vec<f64>)>,
    /// Passes made (bounded by `2 rows + 4`, counted again once batches end).
    passes: usize,
    /// Whether batches have ended (see the module documentation): a row dropped in a
    /// batch was violated again, or the batches took as many passes as the bound.
    single: bool,
    /// The rows dropped by batches, ascending.
    dropped: Vec<usize>,
    /// The rows held out of the set because they depended on the held rows (see
    /// [`GroupState::hold_out`]).
    dependent: Vec<usize>,
    /// Whether a dependent row may be held out (else the step fails on it).
    may_hold_out: bool,
    /// The active rows before the last batch joined, to go back to should the batch
    /// make the held rows dependent.
    before_batch: Option<Vec<usize>>,
    /// Whether the group's step meets all its rows with non-negative multipliers.
    settled: bool,
    /// Hashes of the active sets its passes one row at a time started from: a set
    /// seen again is a cycle (see [`GroupState::repeats`]).
    seen: std::collections::HashSet<u64>,
    /// The group's KKT factorisation, kept for the next pass's changes.
    kkt_factor: Option<KktUpdates>,
}

impl GroupState {
    /// Holds out of the set a row whose pivot showed it depends on the other held rows
    /// (an edge's row on a flat face with the rows of both its vertices, whose gaps it
    /// interpolates): the others hold it too, to round-off, so the step goes on without
    /// it. `false` if it was held out before: it came back, violated or cut by more
    /// than round-off ([`cut`]), so it does not depend on them consistently, and the
    /// caller falls back as for dependent rows.
    /// Without this a guessed start holding such a trio failed whole, and the empty
    /// start after it met the trio again in a batch and went on one row per pass (a
    /// hose on a bracket at 8000 segments per hose: 173 passes, 3.9 s).
    fn hold_out(&mut self, row: usize) -> bool {
        if !self.may_hold_out || self.dependent.contains(&row) {
            return false;
        }
        self.dependent.push(row);
        self.active.retain(|&i| i != row);
        true
    }

    /// From now on one row changes per pass (see the module documentation); the pass
    /// bound counts again from this one.
    fn end_batches(&mut self) {
        self.single = true;
        self.passes = 1;
    }

    /// Whether a pass one row at a time (with kept columns, or with the KKT system once
    /// batches ended) starts from an active set it started from before. Such a pass
    /// is a function of its set, so the passes cycle and would run to the bound of
    /// `2 rows + 4` before the step fails (a 2970-segment cable over a box's edges,
    /// `everyday_s30_003`: 23 steps cycling through one to three rows for 6,000 passes
    /// each, 49 s of a 74 s solve); the step fails now instead, as it would have there
    /// (the QP falls back to the interior-point solver).
    fn repeats(&mut self) -> bool {
        use std::hash::{Hash, Hasher};
        if self.kkt && !self.single {
            return false;
        }
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        self.active.hash(&mut hasher);
        !self.seen.insert(hasher.finish())
    }
}

/// The step with the `active` rows held at zero (see the module documentation); a row
/// that depends on the rows held with it is held out of the set ([`GroupState::hold_out`]).
/// `None` if a group's rows are dependent otherwise or its refinement does not settle.
pub(crate) fn exact_step(
    cholesky: &mut SparseCholesky,
    rows: &[Row],
    active: &[usize],
    newton: &[f64],
) -> Option<ConstrainedStep> {
    exact_step_counted(cholesky, rows, active, newton, GroupMethod::Automatic).map(|(s, _)| s)
}

/// [`exact_step`] for the solver's optional corrections (a trial's positions followed on
/// its rows, a rejected trial's rows closed): `None` as soon as the held rows depend on
/// each other, so that such a correction is skipped rather than made on a set the
/// main step did not choose (made with dependent rows held out, they took the hose over
/// the 94,500-facet drum from 21 to 27 iterations).
pub(crate) fn exact_step_of_independent_rows(
    cholesky: &mut SparseCholesky,
    rows: &[Row],
    active: &[usize],
    newton: &[f64],
) -> Option<ConstrainedStep> {
    let method = GroupMethod::Automatic;
    exact_step_with(cholesky, rows, active, newton, method, false).map(|(s, _)| s)
}

/// [`exact_step`] with the `method` of every group, and the work it did.
pub(crate) fn exact_step_counted(
    cholesky: &mut SparseCholesky,
    rows: &[Row],
    active: &[usize],
    newton: &[f64],
    method: GroupMethod,
) -> Option<(ConstrainedStep, ExactStepWork)> {
    exact_step_with(cholesky, rows, active, newton, method, true)
}

/// [`exact_step_counted`], holding out dependent rows when `hold_out` is set.
fn exact_step_with(
    cholesky: &mut SparseCholesky,
    rows: &[Row],
    active: &[usize],
    newton: &[f64],
    method: GroupMethod,
    hold_out: bool,
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
    for (g, state) in states.iter_mut().enumerate() {
        state.kkt = method == GroupMethod::Kkt;
        state.may_hold_out = hold_out;
        if method == GroupMethod::Automatic && groups.rows[g].len() > 1 {
            state.switch = kkt_input(cholesky.matrix(), rows, &groups.unknowns[g], &local).costs();
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
        // The missing columns, one row of every column group per shared solve.
        let mut missing: Vec<Vec<usize>> = Vec::with_capacity(live.len());
        for &g in &live {
            let state = &mut states[g];
            if state.kkt {
                missing.push(Vec::new());
                continue;
            }
            let held = &state.active;
            state.columns.retain(|(i, _)| held.binary_search(i).is_ok());
            let have = &state.columns;
            let new: Vec<usize> = (state.active.iter().copied())
                .filter(|i| have.iter().all(|(j, _)| j != i))
                .collect();
            if let Some(costs) = state.switch {
                let (m, n_g) = (state.active.len(), groups.unknowns[g].len());
                let columns_pass = new.len() * costs.solve + m * n_g + m * m * m / 3;
                state.columns_work += columns_pass;
                if state.columns_work > costs.kkt_pass {
                    state.kkt = true;
                    state.columns.clear();
                    // Another method from here on: its passes are not the ones seen.
                    state.seen.clear();
                    missing.push(Vec::new());
                    continue;
                }
            }
            missing.push(new);
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
        let matrix = cholesky.matrix();
        for &g in &live {
            let state = &mut states[g];
            state.passes += 1;
            work.passes += 1;
            if state.passes > 2 * groups.rows[g].len() + 4 {
                if state.single {
                    return None;
                }
                state.end_batches();
            }
            if state.repeats() {
                return None;
            }
            let context = Pass {
                rows,
                group_rows: &groups.rows[g],
                unknowns: &groups.unknowns[g],
                local: &local,
                newton,
                kkt: kkt_input(matrix, rows, &groups.unknowns[g], &local),
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

/// The KKT system of the group with `unknowns`, on the factorised `matrix`.
fn kkt_input<'a>(
    matrix: (&'a [usize], &'a [usize], &'a [f64]),
    rows: &'a [Row],
    unknowns: &'a [usize],
    local: &'a [usize],
) -> KktInput<'a> {
    KktInput {
        col_ptr: matrix.0,
        row_idx: matrix.1,
        values: matrix.2,
        rows,
        unknowns,
        local,
    }
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
    /// The group's KKT system (used when the state says so).
    kkt: KktInput<'a>,
}

impl Pass<'_> {
    /// One primal–dual pass on `state` (its columns complete, or its KKT system): the
    /// multipliers of the held rows; the most negative one leaves the set, or else the
    /// group's step is rebuilt in `step` and its most violated open row joins the set.
    /// Returns the multipliers when neither happens (the group is settled); `None`
    /// outside when the held rows are dependent (the Schur complement is not positive
    /// definite, or a KKT pivot has the wrong sign).
    fn refine(
        &self,
        state: &mut GroupState,
        step: &mut [f64],
        work: &mut ExactStepWork,
    ) -> Option<Option<DVector<f64>>> {
        let rows = self.rows;
        let m = state.active.len();
        let rhs = DVector::from_fn(m, |r, _| -rows[state.active[r]].linearised(self.newton));
        let (multipliers, correction) = if m == 0 {
            (DVector::zeros(0), None)
        } else if state.kkt {
            let solved = self.kkt.solve_updating(
                &mut state.kkt_factor,
                &state.active,
                rhs.as_slice(),
                &mut work.products,
            );
            let solution = match solved {
                Ok(solution) => solution,
                Err(KktFailure::DependentRow(i)) if state.hold_out(i) => return Some(None),
                Err(_) => {
                    // Rows that joined together made the held rows dependent (nearly
                    // tied ridges): back to the set before them, one row per pass from
                    // now on.
                    let before = state.before_batch.take()?;
                    state.active = before;
                    state.end_batches();
                    return Some(None);
                }
            };
            state.before_batch = None;
            (
                DVector::from_vec(solution.multipliers),
                Some(solution.correction),
            )
        } else {
            state.columns.sort_by_key(|(i, _)| *i);
            let dot = |i: usize, w: &[f64]| {
                (rows[i].gradient.iter())
                    .map(|&(k, a)| a * w[self.local[k]])
                    .sum::<f64>()
            };
            let (active, columns) = (&state.active, &state.columns);
            let schur = DMatrix::from_fn(m, m, |r, c| dot(active[r], &columns[c].1));
            match schur.clone().cholesky() {
                Some(factor) => (factor.solve(&rhs), None),
                None => {
                    let row = state.active[first_dependent(schur)?];
                    return state.hold_out(row).then_some(None);
                }
            }
        };
        let batches = state.kkt && !state.single;
        let negative = |l: &f64| l.is_nan() || *l < 0.0;
        if batches && multipliers.iter().any(negative) {
            let held = std::mem::take(&mut state.active);
            for (i, l) in held.into_iter().zip(multipliers.iter()) {
                if negative(l) {
                    state.dropped.push(i);
                } else {
                    state.active.push(i);
                }
            }
            state.dropped.sort_unstable();
            return Some(None);
        }
        if let Some((r, _)) = multipliers
            .iter()
            .enumerate()
            .filter(|(_, l)| negative(l))
            .min_by(|a, b| a.1.total_cmp(b.1))
        {
            state.active.remove(r);
            return Some(None);
        }
        for (p, &u) in self.unknowns.iter().enumerate() {
            let mut s = self.newton[u];
            match &correction {
                Some(delta) => s += delta[p],
                None => {
                    for ((_, w), &l) in state.columns.iter().zip(multipliers.iter()) {
                        s += l * w[p];
                    }
                }
            }
            step[u] = s;
        }
        work.entries += self.unknowns.len();
        let active = &state.active;
        let violated: Vec<(usize, f64)> = (self.group_rows.iter().copied())
            .filter(|i| active.binary_search(i).is_err())
            .filter_map(|i| {
                violation_by(&rows[i], step)
                    .or_else(|| state.dependent.contains(&i).then(|| cut(&rows[i], step))?)
                    .map(|v| (i, v))
            })
            .collect();
        if batches && !violated.is_empty() {
            if violated
                .iter()
                .all(|(i, _)| state.dropped.binary_search(i).is_err())
            {
                state.before_batch = Some(state.active.clone());
                state.active.extend(violated.iter().map(|&(i, _)| i));
                state.active.sort_unstable();
                return Some(None);
            }
            // A dropped row wants back in: one row per pass from now on.
            state.end_batches();
        }
        let violated = violated.into_iter().min_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((i, _)) = violated {
            let at = state.active.binary_search(&i).unwrap_err();
            state.active.insert(at, i);
            return Some(None);
        }
        Some(Some(multipliers))
    }
}

/// Largest cut of a held-out row by the step, relative to the size of its terms
/// (value and `a·d`), that counts as round-off (see [`cut`]).
const HELD_OUT_ROUND_OFF: f64 = 1e-12;

/// A held-out row's linearised value after `step` if the step cuts it by more than
/// round-off of its terms ([`HELD_OUT_ROUND_OFF`] of their size): such a row does not depend on the
/// held rows consistently (nearly tied ridges of a finely faceted drum: cuts of
/// 1e-12 m, far below the 1e-10 m an open row may be cut by, turned every trial of the
/// exact penalty back).
fn cut(row: &Row, step: &[f64]) -> Option<f64> {
    let terms: f64 = row.value.abs()
        + (row.gradient.iter())
            .map(|&(k, a)| (a * step[k]).abs())
            .sum::<f64>();
    let after = row.linearised(step);
    (after < -HELD_OUT_ROUND_OFF * terms).then_some(after)
}

/// The first of the held rows whose pivot in the Cholesky factor of their Schur matrix
/// `S = A H⁻¹ Aᵀ` is not positive (it depends on the rows before it); `None` if every
/// pivot is.
fn first_dependent(mut s: DMatrix<f64>) -> Option<usize> {
    let m = s.nrows();
    for c in 0..m {
        let pivot = s[(c, c)] - (0..c).map(|t| s[(c, t)] * s[(c, t)]).sum::<f64>();
        if pivot.is_nan() || pivot <= 0.0 {
            return Some(c);
        }
        let root = pivot.sqrt();
        for r in c + 1..m {
            let dot: f64 = (0..c).map(|t| s[(r, t)] * s[(c, t)]).sum();
            s[(r, c)] = (s[(r, c)] - dot) / root;
        }
        s[(c, c)] = root;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::GroupState;

    /// A pass one row at a time that starts from a set seen before is a cycle; in
    /// batches (the KKT system before they end) the next set also depends on the rows
    /// dropped, so a repeat there is not one.
    #[test]
    fn an_active_set_seen_again_one_row_at_a_time_is_a_cycle() {
        let mut columns = GroupState::default();
        for active in [vec![3], vec![3, 7], vec![7], vec![3, 7, 9]] {
            columns.active = active;
            assert!(!columns.repeats(), "{:?} seen first", columns.active);
        }
        columns.active = vec![3, 7];
        assert!(columns.repeats());
        let mut batches = GroupState {
            kkt: true,
            ..GroupState::default()
        };
        for _ in 0..2 {
            batches.active = vec![1, 2];
            assert!(!batches.repeats());
        }
        batches.end_batches();
        assert!(!batches.repeats());
        assert!(batches.repeats());
    }
}
