//! The positions-only correction of a trial step that has contact rows: the positions
//! follow the frames (as [`Iteration::follow`] does without rows) while the contacts
//! held in this step stay closed and no other row is violated to first order.
//!
//! A straight-line step that turns a stiff rod's frames moves its vertices along the
//! tangent lines and strains the rod at second order (`C θ⁴ h / 8` per edge); without
//! rows the positions-only Newton step removes that strain, but with contact rows it
//! could push a vertex into an obstacle, so it was skipped there and every long step of
//! a hose sliding over the scene was mispredicted (ratios of −1 to −50 on the drop
//! family of `tests/validation/drop.rs`), the damping alternating between two levels.
//! Here the correction is the positions-only step constrained by the trial's rows
//! (the exact active-set step of [`crate::sqp`] with the rotations held), kept only when
//! it lowers the exact-penalty merit.

use strand_system::SystemState;

use super::{Iteration, violation_of};
use crate::constraints::Row;

impl Iteration<'_> {
    /// Lets the positions of `trial` follow its frames under its contact rows: replaces
    /// it by the rows-constrained positions-only correction when that lowers the merit
    /// `E + μ max(0, −gap)`. Returns the energy of `trial` (J); `evaluated` as in
    /// [`Iteration::follow`]. Overwrites this iteration's factor (see
    /// [`Iteration::refactor`]).
    pub(super) fn follow_on_rows(&mut self, trial: &mut SystemState, evaluated: &mut bool) -> f64 {
        if !*evaluated || !self.work.trial_eval.has_hessian {
            self.model.evaluate(trial, &mut self.work.trial_eval, true);
            *evaluated = true;
        }
        let energy = self.work.trial_eval.energy;
        // Every row: the correction's QP is not checked against left-out ones.
        let mut rows = Vec::new();
        if !self.collect_all_rows(trial, &mut rows) {
            return energy;
        }
        let merit = energy + self.merit_weight * violation_of(&rows);
        let Some(relaxed) = self.relax_positions_on_rows(trial, &rows) else {
            return energy;
        };
        let (mut relaxed_rows, mut far) = (Vec::new(), Vec::new());
        if !self.collect_rows(&relaxed, &mut relaxed_rows, &mut far) {
            return energy;
        }
        let relaxed_energy = self.model.energy(&relaxed);
        let relaxed_merit = relaxed_energy + self.merit_weight * violation_of(&relaxed_rows);
        if self.trace {
            eprintln!(
                "strand-solve:   positions follow on the rows: merit {relaxed_merit:.9e} J (straight trial {merit:.9e} J)"
            );
        }
        if relaxed_merit < merit {
            *trial = relaxed;
            self.model.evaluate(trial, &mut self.work.trial_eval, false);
            return self.work.trial_eval.energy;
        }
        energy
    }

    /// The positions-only Newton step at `trial` (Hessian and gradient in
    /// `work.trial_eval`, every rotation held) constrained by `rows` (the trial's):
    /// the rows held with a force in this step, and any the trial violates, closed to
    /// first order, every other row kept open. `None` when the positions block is not
    /// positive definite or the active set does not settle.
    fn relax_positions_on_rows(
        &mut self,
        trial: &SystemState,
        rows: &[Row],
    ) -> Option<SystemState> {
        // The rows as functions of the positions alone (a row on rotations only, a joint
        // limit, does not move).
        let held = self.work.rotations(self.model.pattern()).held().to_vec();
        let mut position_rows = Vec::with_capacity(rows.len());
        let mut hint = Vec::new();
        for row in rows {
            let gradient: Vec<(usize, f64)> = row
                .gradient
                .iter()
                .filter(|(k, _)| held.binary_search(k).is_err())
                .copied()
                .collect();
            if gradient.is_empty() {
                continue;
            }
            if self.multiplier(row.key) > 0.0 || row.value < 0.0 {
                hint.push(position_rows.len());
            }
            position_rows.push(Row {
                key: row.key,
                value: row.value,
                gradient,
                curvature: None,
            });
        }
        let work = &mut *self.work;
        if !work.positions_only_step(self.model.pattern()) {
            return None;
        }
        let free = hint.is_empty() && position_rows.iter().all(|r| r.linearised(&work.rhs) >= 0.0);
        let step = if free {
            work.rhs.clone()
        } else {
            crate::sqp::exact_step_of_independent_rows(
                &mut work.cholesky,
                &position_rows,
                &hint,
                &work.rhs,
            )?
            .step
        };
        Some(self.model.retract(trial, &step))
    }

    /// Factorises this iteration's damped matrix again (the SQP model's Hessian plus
    /// the accepted damping `λ·D`, gauge held), after a correction overwrote the
    /// factor. `false` if it is not positive definite (it was when the step was
    /// computed, so only on round-off).
    pub(super) fn refactor(&mut self) -> bool {
        let model = self.sqp_model();
        let damping = self.damping;
        let work = &mut *self.work;
        work.set_damped(model.as_ref().map(|m| &m.hessian[..]), damping);
        work.cholesky.factor(&work.damped)
    }
}
