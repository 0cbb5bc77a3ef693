//! One Newton/SQP solve on one model, in named phases:
//!
//! 1. **convergence test** ([`Iteration::kkt`]): the KKT residual `g − Σ λ_i a_i` in
//!    newtons, feasibility and complementarity of the rows, and stagnation;
//! 2. **model step** ([`Iteration::factor_damped`]): the Hessian with the gauge held
//!    and a Levenberg–Marquardt damping `λ·D`, `D` the Hessian's own diagonal floored
//!    at 1e-4 of its largest entry, i.e. scaled per unknown (a
//!    position's own `EA/h`, a rotation's own `EI/h`, a joint's own stiffness), raised
//!    from the last accepted value until the factorisation is positive definite;
//! 3. **direction** ([`Iteration::direction`]): the damped Newton step, projected by the
//!    QP of the linearised inequalities (contact, joint limits);
//! 4. **globalisation** ([`Iteration::globalise`]): a trust region in physical units
//!    (largest rotation in rad, largest translation in m), shrunk on rejection, grown on
//!    success; a mispredicted step first gets a positions-only correction, an exact one
//!    is extended, and a short step of an indefinite iteration is tried together with a
//!    direction of negative curvature scaled to the region;
//! 5. **acceptance** (inside `globalise`): the ratio of achieved to predicted decrease of
//!    the exact-penalty merit `E + μ Σ max(0, −gap)`; in the round-off regime, a
//!    decrease of the residual instead;
//! 6. **finish** ([`Iteration::finish`]): residual, multipliers and the stability
//!    classification of the returned state.

mod globalise;

use strand_system::{Evaluation, Model, Residual, SystemState};

use crate::constraints::{Constraints, Row, RowKey, limit_rows};
use crate::gauge::Gauge;
use crate::linear::symmetric_product;
use crate::report::{Solution, SolveReport, Termination};
use crate::stability::reduced_inertia;
use crate::{SolverSettings, SparseCholesky};

/// Inverse-iteration steps per iteration for the direction of negative curvature.
const NEGATIVE_CURVATURE_ITERATIONS: usize = 6;

/// Smallest damping scale of an unknown relative to the largest Hessian diagonal.
const DAMPING_FLOOR: f64 = 1e-4;

/// The damping scale of every unknown (in the order of `diagonal`, the value offsets
/// of the Hessian's diagonal): its own diagonal entry, but at least [`DAMPING_FLOOR`]
/// of the largest one, so that soft directions are not damped away entirely while stiff
/// ones relax (measured: pure Marquardt scaling lets a strained start drift to another
/// equilibrium).
pub(crate) fn damping_scale(hessian: &[f64], diagonal: &[usize]) -> Vec<f64> {
    let largest = diagonal
        .iter()
        .map(|&k| hessian[k].abs())
        .fold(f64::MIN_POSITIVE, f64::max);
    diagonal
        .iter()
        .map(|&k| hessian[k].abs().max(DAMPING_FLOOR * largest))
        .collect()
}

/// Buffers reused by every solve of one model.
pub(crate) struct Workspace {
    pub cholesky: SparseCholesky,
    pub diagonal: Vec<usize>,
    pub gauge: Gauge,
    /// Every rotation (and gauge) unknown held: the positions-only correction.
    pub rotations: Gauge,
    pub eval: Evaluation,
    pub trial_eval: Evaluation,
    pub damped: Vec<f64>,
    pub step: Vec<f64>,
    pub product: Vec<f64>,
    pub rhs: Vec<f64>,
}

/// The state of one Newton/SQP iteration sequence.
pub(crate) struct Iteration<'a> {
    model: &'a Model,
    constraints: Option<&'a dyn Constraints>,
    settings: &'a SolverSettings,
    work: &'a mut Workspace,
    /// Current iterate and its rows.
    state: SystemState,
    rows: Vec<Row>,
    /// Multipliers of the last step by key (sorted).
    multipliers: Vec<(RowKey, f64)>,
    merit_weight: f64,
    /// Relative Levenberg–Marquardt damping of the last accepted step (0: pure Newton).
    damping: f64,
    /// Trust radius as a fraction of the settings' step limits.
    radius: f64,
    /// Largest translation of a vertex in one step, m.
    max_translation: f64,
    /// The tolerance applied: the larger of the setting and the round-off floor, N.
    tolerance: f64,
    report: SolveReport,
    history: Vec<(f64, f64)>,
    /// Whether this iteration's Hessian needed damping to be positive definite.
    indefinite: bool,
    /// The last direction of negative curvature (warm start of inverse iteration).
    curvature_direction: Vec<f64>,
    /// Print every trial step to stderr (environment variable `STRAND_TRACE` set).
    trace: bool,
}

impl<'a> Iteration<'a> {
    pub(crate) fn new(
        model: &'a Model,
        constraints: Option<&'a dyn Constraints>,
        settings: &'a SolverSettings,
        work: &'a mut Workspace,
        mut state: SystemState,
    ) -> Self {
        model.enforce_supports(&mut state);
        model.evaluate(&state, &mut work.eval, true);
        let longest_rod = model
            .system()
            .rods
            .iter()
            .map(|r| r.rod.length())
            .fold(0.0, f64::max);
        let mut max_translation = settings.max_translation_step * longest_rod;
        if let Some(c) = constraints {
            max_translation = max_translation.min(c.max_translation_m());
        }
        let floor = residual_floor(model);
        let mut report = SolveReport::new(model.dofs().len(), settings.tolerance_n);
        report.residual_floor_n = floor;
        report.gauge_freedoms = work.gauge.held().len();
        let mut iteration = Self {
            model,
            constraints,
            settings,
            work,
            state,
            rows: Vec::new(),
            multipliers: Vec::new(),
            merit_weight: 0.0,
            damping: 0.0,
            radius: 1.0,
            max_translation,
            tolerance: settings.tolerance_n.max(floor),
            report,
            history: Vec::new(),
            trace: std::env::var_os("STRAND_TRACE").is_some(),
            indefinite: false,
            curvature_direction: Vec::new(),
        };
        let mut rows = Vec::new();
        iteration.collect_rows(&iteration.state.clone(), &mut rows);
        iteration.rows = rows;
        iteration
    }

    /// Runs the iteration to convergence or failure.
    pub(crate) fn run(mut self) -> Solution {
        let termination = loop {
            let (residual, satisfied) = self.kkt(&self.rows, &self.work.eval.gradient);
            if !residual.combined_n.is_finite() || !self.work.eval.energy.is_finite() {
                break Termination::NotFinite;
            }
            if residual.combined_n <= self.tolerance && satisfied {
                break Termination::Converged;
            }
            if self.stagnated(residual.combined_n) {
                break Termination::Stagnated;
            }
            if self.report.iterations >= self.settings.max_iterations {
                break Termination::MaxIterations;
            }
            self.report.iterations += 1;
            if let Err(stop) = self.factor_damped() {
                break stop;
            }
            if let Err(stop) = self.direction() {
                break stop;
            }
            if let Err(stop) = self.globalise(residual.combined_n) {
                break stop;
            }
        };
        self.finish(termination)
    }

    /// Convergence test: the KKT residual `g − Σ λ_i a_i` with the multipliers of the
    /// last step on the current rows, and whether every row is feasible and every row
    /// with a multiplier closed (complementarity).
    fn kkt(&self, rows: &[Row], gradient: &[f64]) -> (Residual, bool) {
        let mut r = gradient.to_vec();
        let mut satisfied = true;
        let tolerance = self.settings.constraint_tolerance;
        for row in rows {
            let lambda = self.multiplier(row.key);
            if row.value < -tolerance || (lambda > 0.0 && row.value > tolerance) {
                satisfied = false;
            }
            for &(k, a) in &row.gradient {
                r[k] -= lambda * a;
            }
        }
        (self.model.residual(&r), satisfied)
    }

    fn multiplier(&self, key: RowKey) -> f64 {
        self.multipliers
            .binary_search_by(|(k, _)| k.cmp(&key))
            .map_or(0.0, |i| self.multipliers[i].1)
    }

    /// Stagnation: the best residual has not dropped by the required factor within the
    /// window while the energy no longer changes beyond round-off.
    fn stagnated(&mut self, residual: f64) -> bool {
        let energy = self.work.eval.energy;
        self.history.push((residual, energy));
        let window = self.settings.stagnation_iterations;
        if self.history.len() <= window {
            return false;
        }
        let (old_residual, old_energy) = self.history[self.history.len() - 1 - window];
        let best_recent = self.history[self.history.len() - window..]
            .iter()
            .map(|h| h.0)
            .fold(f64::INFINITY, f64::min);
        let best_before = self.history[..self.history.len() - window]
            .iter()
            .map(|h| h.0)
            .fold(f64::INFINITY, f64::min)
            .min(old_residual);
        let noise = 1e-12 * energy.abs().max(old_energy.abs()).max(1e-300);
        best_recent > self.settings.stagnation_reduction * best_before
            && (old_energy - energy).abs() <= noise
    }

    /// Model step: factorises `H + λ·diag|H|` (gauge held), with the smallest damping
    /// from the last accepted one down (or up) that is positive definite.
    fn factor_damped(&mut self) -> Result<(), Termination> {
        let settings = self.settings;
        let work = &mut *self.work;
        let mut damping = self.damping;
        let mut failed = false;
        loop {
            work.damped.copy_from_slice(&work.eval.hessian);
            if damping > 0.0 {
                let scale = damping_scale(&work.eval.hessian, &work.diagonal);
                for (&k, d) in work.diagonal.iter().zip(&scale) {
                    work.damped[k] += damping * d;
                }
            }
            work.gauge.fix_matrix(&mut work.damped);
            if work.cholesky.factor(&work.damped) {
                break;
            }
            failed = true;
            damping = if damping == 0.0 {
                settings.min_damping
            } else {
                damping * settings.damping_increase
            };
            if damping > settings.max_damping {
                return Err(Termination::LineSearchFailed);
            }
        }
        if damping > 0.0 {
            self.report.shifted_iterations += 1;
        }
        self.damping = damping;
        self.indefinite = failed;
        Ok(())
    }

    /// A direction of negative curvature of the Hessian (the generalised eigenvector of
    /// `(H, D)` with the most negative eigenvalue), from a few steps of inverse
    /// iteration with the current damped factor, warm-started from the last one.
    /// `None` unless the Hessian was found indefinite and the direction's Rayleigh
    /// quotient is negative.
    fn negative_curvature(&mut self) -> Option<Vec<f64>> {
        if !self.indefinite || !self.rows.is_empty() {
            return None;
        }
        let work = &mut *self.work;
        let scale = damping_scale(&work.eval.hessian, &work.diagonal);
        let n = work.step.len();
        if self.curvature_direction.len() != n {
            self.curvature_direction = crate::saddle::generic_start(n);
        }
        let x = &mut self.curvature_direction;
        crate::saddle::inverse_iteration(work, &scale, x, NEGATIVE_CURVATURE_ITERATIONS)?;
        symmetric_product(
            self.model.pattern(),
            &work.eval.hessian,
            x,
            &mut work.product,
        );
        let curvature: f64 = x.iter().zip(&work.product).map(|(a, b)| a * b).sum();
        (curvature < 0.0).then(|| x.clone())
    }

    /// Direction: the damped Newton step `−(H + λD)⁻¹ g`, then the QP of the
    /// linearised inequalities with the same matrix.
    fn direction(&mut self) -> Result<(), Termination> {
        let work = &mut *self.work;
        for (s, g) in work.step.iter_mut().zip(&work.eval.gradient) {
            *s = -g;
        }
        work.gauge.fix_vector(&mut work.step);
        work.cholesky.solve_in_place(&mut work.step);
        if self.rows.is_empty() {
            return Ok(());
        }
        let hint: Vec<usize> = (0..self.rows.len())
            .filter(|&i| {
                self.multipliers
                    .binary_search_by(|(k, _)| k.cmp(&self.rows[i].key))
                    .is_ok()
            })
            .collect();
        work.rhs.copy_from_slice(&work.eval.gradient);
        work.gauge.fix_vector(&mut work.rhs);
        let constrained = crate::sqp::constrained_step(
            self.model.pattern(),
            &work.damped,
            &mut work.cholesky,
            &work.rhs,
            &self.rows,
            &work.step,
            &hint,
        )
        .map_err(|_| Termination::SubproblemFailed)?;
        work.step.copy_from_slice(&constrained.step);
        self.multipliers = self
            .rows
            .iter()
            .zip(&constrained.multipliers)
            .filter(|(_, l)| **l > 0.0)
            .map(|(r, l)| (r.key, *l))
            .collect();
        self.multipliers.sort_by_key(|a| a.0);
        let largest = self.multipliers.iter().fold(0.0f64, |m, (_, l)| m.max(*l));
        self.merit_weight = self.merit_weight.max(2.0 * largest);
        Ok(())
    }

    /// Rows at `state`: joint limits and (if any) contact. `false` when the state is not
    /// admissible (a centreline through an obstacle).
    fn collect_rows(&self, state: &SystemState, rows: &mut Vec<Row>) -> bool {
        rows.clear();
        limit_rows(self.model, state, rows);
        match self.constraints {
            Some(c) => c.rows(self.model, state, rows).is_ok(),
            None => true,
        }
    }

    /// Finish: residual, multipliers per row and the stability of the returned state.
    fn finish(mut self, termination: Termination) -> Solution {
        let (residual, _) = self.kkt(&self.rows, &self.work.eval.gradient);
        let converged = termination == Termination::Converged;
        let active: Vec<&Row> = self
            .rows
            .iter()
            .filter(|r| self.multiplier(r.key) > 0.0)
            .collect();
        // Fast path: without active rows, `H − τD` positive definite (one Cholesky with
        // the analysis already done) means no negative and no neutral direction.
        let tau = self.settings.neutral_tolerance;
        let work = &mut *self.work;
        let clearly_stable = active.is_empty() && {
            work.damped.copy_from_slice(&work.eval.hessian);
            for &k in &work.diagonal {
                work.damped[k] -= tau * work.eval.hessian[k].abs();
            }
            work.gauge.fix_matrix(&mut work.damped);
            work.cholesky.factor(&work.damped)
        };
        let inertia = if clearly_stable {
            Ok(crate::stability::Inertia {
                negative: 0,
                neutral: 0,
            })
        } else {
            reduced_inertia(
                self.model.pattern(),
                &work.eval.hessian,
                &work.gauge,
                &active,
                tau,
            )
        };
        let report = &mut self.report;
        match inertia {
            Ok(inertia) => {
                report.negative_directions = inertia.negative;
                report.neutral_directions = inertia.neutral;
                report.stable = converged && inertia.negative == 0;
            }
            Err(_) => report.stable = false,
        }
        report.converged = converged;
        report.termination = termination;
        report.residual = residual;
        report.energy_j = self.work.eval.energy;
        report.fine_iterations = report.iterations;
        let constraints = self
            .rows
            .iter()
            .map(|row| (row.clone(), self.multiplier(row.key)))
            .collect();
        Solution {
            report: self.report,
            state: self.state,
            constraints,
        }
    }
}

/// Total violation `Σ max(0, −value)` of the rows.
fn violation_of(rows: &[Row]) -> f64 {
    rows.iter().map(|r| (-r.value).max(0.0)).sum()
}

/// The round-off floor of the residual in N: a strain computed to one ulp times the
/// largest axial or shear stiffness (positions are stored compensated, so it does not
/// grow with the distance from the origin).
fn residual_floor(model: &Model) -> f64 {
    let stiffest = model
        .system()
        .rods
        .iter()
        .map(|r| {
            let s = r.rod.section().strain_stiffness();
            s.max()
        })
        .fold(0.0, f64::max);
    2.0 * f64::EPSILON * stiffest
}
