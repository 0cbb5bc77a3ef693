//! Newton's method with inertia correction and an Armijo line search.

use std::time::Instant;

use serde::Serialize;
use strand_system::{Model, Residual, SystemState};

use crate::constraints::{Constraints, Row, RowKey, limit_rows};
use crate::{SolveError, SolverSettings, SparseCholesky, continuation, nested, sqp};

/// Why the iteration stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Termination {
    /// The residual fell below the tolerance.
    Converged,
    /// The iteration limit was reached.
    MaxIterations,
    /// No step along the Newton direction decreased the energy (or the residual in the
    /// round-off regime).
    LineSearchFailed,
    /// A non-finite number appeared.
    NotFinite,
    /// The QP of a constrained step (joint limits, contact) could not be solved.
    SubproblemFailed,
}

/// What the solver did and how good the result is.
#[derive(Clone, Debug, Serialize)]
pub struct SolveReport {
    /// Whether the residual reached the tolerance.
    pub converged: bool,
    /// Why the iteration stopped.
    pub termination: Termination,
    /// Residual of the returned state (N, N·m).
    pub residual: Residual,
    /// Tolerance used, N.
    pub tolerance_n: f64,
    /// Newton iterations performed on the model.
    pub iterations: usize,
    /// Newton iterations of the coarse-model solve that produced the initial guess
    /// (nested iteration; 0 when not used).
    pub coarse_iterations: usize,
    /// Load steps of the continuation that produced this result (0: direct solve).
    pub continuation_steps: usize,
    /// Newton iterations spent in the continuation's load steps.
    pub continuation_iterations: usize,
    /// Iterations whose Hessian needed a diagonal shift to become positive definite.
    pub shifted_iterations: usize,
    /// Whether the Hessian at the returned state is positive definite (a stable
    /// equilibrium when converged).
    pub stable: bool,
    /// Total potential energy in J.
    pub energy_j: f64,
    /// Wall-clock time of the solve in s.
    pub solve_seconds: f64,
    /// Number of scalar unknowns.
    pub unknowns: usize,
}

/// An equilibrium (or the best state reached) with its report.
#[derive(Clone, Debug)]
pub struct Solution {
    /// The final configuration.
    pub state: SystemState,
    /// Convergence and stability report.
    pub report: SolveReport,
    /// The inequality constraints (joint limits, contact) at the final state with their
    /// multipliers: the force (N) or moment (N·m) each one exerts, zero when inactive.
    pub constraints: Vec<(Row, f64)>,
}

/// Solves for the equilibrium of `model` starting from `initial`: a fresh [`Solver`]
/// (symbolic analysis included) and one [`Solver::solve`].
///
/// Returns `Err` only when solving cannot start (bad settings, an initial state that
/// does not fit); a solve that does not converge returns a [`Solution`] whose report
/// says so.
pub fn solve(
    model: &Model,
    initial: SystemState,
    settings: &SolverSettings,
) -> Result<Solution, SolveError> {
    let started = Instant::now();
    let mut solution = Solver::try_new(model)?.solve(initial, settings)?;
    solution.report.solve_seconds = started.elapsed().as_secs_f64();
    Ok(solution)
}

/// [`solve`] with inequality constraints beyond joint limits (contact).
pub fn solve_constrained(
    model: &Model,
    constraints: &dyn Constraints,
    initial: SystemState,
    settings: &SolverSettings,
) -> Result<Solution, SolveError> {
    let started = Instant::now();
    let mut solution = Solver::try_new(model)?
        .with_constraints(constraints)
        .solve(initial, settings)?;
    solution.report.solve_seconds = started.elapsed().as_secs_f64();
    Ok(solution)
}

/// A Newton solver bound to one model: the symbolic factorisation and all work
/// buffers are set up once and reused by every [`Solver::solve`] (variants, load
/// steps, warm starts).
pub struct Solver<'m> {
    model: &'m Model,
    constraints: Option<&'m dyn Constraints>,
    cholesky: SparseCholesky,
    diagonal: Vec<usize>,
    eval: strand_system::Evaluation,
    trial_eval: strand_system::Evaluation,
    shifted_values: Vec<f64>,
    step: Vec<f64>,
}

impl<'m> Solver<'m> {
    /// Symbolic phase: analyses the model's Hessian pattern.
    pub fn try_new(model: &'m Model) -> Result<Self, SolveError> {
        Ok(Self {
            model,
            constraints: None,
            cholesky: SparseCholesky::try_new(model.pattern())?,
            diagonal: diagonal_positions(model),
            eval: model.new_evaluation(),
            trial_eval: model.new_evaluation(),
            shifted_values: vec![0.0; model.pattern().nnz()],
            step: vec![0.0; model.dofs().len()],
        })
    }

    /// Adds inequality constraints (contact) to every solve.
    pub fn with_constraints(mut self, constraints: &'m dyn Constraints) -> Self {
        self.constraints = Some(constraints);
        self
    }

    /// Solves from `initial`, first through a coarsened model when
    /// [`SolverSettings::nested_iteration`] is on and a rod is long.
    pub fn solve(
        &mut self,
        initial: SystemState,
        settings: &SolverSettings,
    ) -> Result<Solution, SolveError> {
        settings.validate()?;
        check_initial_state(self.model, &initial)?;
        if let Some(c) = self.constraints {
            let mut start = initial.clone();
            self.model.enforce_supports(&mut start);
            c.check_start(self.model, &start)
                .map_err(SolveError::StartsInside)?;
        }
        let started = Instant::now();
        let mut coarse_iterations = 0;
        // A start that is already an equilibrium (a warm start, a moulded rod in its
        // nominal shape) needs no coarse guess.
        let mut initial = initial;
        self.model.enforce_supports(&mut initial);
        self.model.evaluate(&initial, &mut self.eval, false);
        let already_converged =
            self.model.residual(&self.eval.gradient).combined_n <= settings.tolerance_n;
        if let Some((coarse_system, kept)) = nested::coarsen(self.model.system())
            .filter(|_| settings.nested_iteration && !already_converged)
        {
            let coarse_model = Model::try_new(coarse_system)
                .map_err(|e| SolveError::InitialState(e.to_string()))?;
            let coarse_settings = SolverSettings {
                nested_iteration: false,
                ..settings.clone()
            };
            let mut coarse_solver = Solver::try_new(&coarse_model)?;
            coarse_solver.constraints = self.constraints;
            let coarse =
                coarse_solver.solve(nested::restrict(&initial, &kept), &coarse_settings)?;
            coarse_iterations = coarse.report.iterations;
            if coarse.report.converged {
                initial = nested::prolong(self.model, &coarse_model, &coarse.state, &kept);
            }
        }
        let continuation_start = settings.load_continuation.then(|| initial.clone());
        let mut solution = self.newton(initial, settings);
        if let Some(start) = continuation_start.filter(|_| !solution.report.converged)
            && let Some((ramped, steps)) =
                continuation::ramp(self.model, self.constraints, start, settings)?
            && ramped.report.converged
        {
            solution = ramped;
            solution.report.continuation_steps = steps;
        }
        solution.report.coarse_iterations = coarse_iterations;
        solution.report.solve_seconds = started.elapsed().as_secs_f64();
        Ok(solution)
    }

    /// Newton's method from `initial` (no nested iteration).
    fn newton(&mut self, initial: SystemState, settings: &SolverSettings) -> Solution {
        let Self {
            model,
            constraints,
            cholesky,
            diagonal,
            eval,
            trial_eval,
            shifted_values,
            step,
        } = self;
        let model: &Model = model;
        let longest_rod = model
            .system()
            .rods
            .iter()
            .map(|r| r.rod.length())
            .fold(0.0, f64::max);
        let mut max_translation = settings.max_translation_step * longest_rod;
        let mut state = initial;
        model.enforce_supports(&mut state);
        model.evaluate(&state, eval, true);
        let mut trial = state.clone();
        let mut shift = 0.0f64;
        let mut iterations = 0;
        let mut shifted_iterations = 0;
        let mut termination = Termination::MaxIterations;
        let mut stable_at_current: Option<bool> = None;

        let constraints: Option<&dyn Constraints> = *constraints;
        if let Some(c) = constraints {
            max_translation = max_translation.min(c.max_translation_m());
        }
        // The rows at the current state and the multipliers of the last step by key.
        let mut rows: Vec<Row> = Vec::new();
        let collect_rows = |state: &SystemState, rows: &mut Vec<Row>| {
            rows.clear();
            limit_rows(model, state, rows);
            match constraints {
                Some(c) => c.rows(model, state, rows).is_ok(),
                None => true,
            }
        };
        collect_rows(&state, &mut rows);
        let mut multipliers: Vec<(RowKey, f64)> = Vec::new();
        let mut merit_weight = 0.0f64;
        // KKT residual `g − Σ λ_i a_i` (the multipliers of the last step, re-linearised
        // rows), and whether the constraints hold: feasible to the tolerance, and every
        // row with a multiplier closed (complementarity).
        let kkt = |rows: &[Row], multipliers: &[(RowKey, f64)], gradient: &[f64]| {
            let mut r = gradient.to_vec();
            let mut satisfied = true;
            for row in rows {
                let lambda = multipliers
                    .binary_search_by(|(k, _)| k.cmp(&row.key))
                    .map_or(0.0, |i| multipliers[i].1);
                if row.value < -settings.constraint_tolerance
                    || (lambda > 0.0 && row.value > settings.constraint_tolerance)
                {
                    satisfied = false;
                }
                for &(k, a) in &row.gradient {
                    r[k] -= lambda * a;
                }
            }
            (model.residual(&r), satisfied)
        };
        let violation = |rows: &[Row]| rows.iter().map(|r| (-r.value).max(0.0)).sum::<f64>();
        while iterations < settings.max_iterations {
            let (residual, satisfied) = kkt(&rows, &multipliers, &eval.gradient);
            if !residual.combined_n.is_finite() || !eval.energy.is_finite() {
                termination = Termination::NotFinite;
                break;
            }
            if residual.combined_n <= settings.tolerance_n && satisfied {
                termination = Termination::Converged;
                break;
            }
            iterations += 1;

            // Inertia correction: the smallest shift δ ∈ {0, δ0·10^k} with H + δI ≻ 0.
            let unshifted_ok = cholesky.factor(&eval.hessian);
            stable_at_current = Some(unshifted_ok);
            if !unshifted_ok {
                shifted_iterations += 1;
                let scale = diagonal
                    .iter()
                    .map(|&k| eval.hessian[k].abs())
                    .fold(0.0, f64::max)
                    .max(1e-300);
                shift = if shift == 0.0 {
                    1e-8 * scale
                } else {
                    (shift / 3.0).max(1e-8 * scale)
                };
                loop {
                    shifted_values.copy_from_slice(&eval.hessian);
                    for &k in diagonal.iter() {
                        shifted_values[k] += shift;
                    }
                    if cholesky.factor(shifted_values) {
                        break;
                    }
                    shift *= 10.0;
                    if !shift.is_finite() {
                        termination = Termination::NotFinite;
                        break;
                    }
                }
                if termination == Termination::NotFinite {
                    break;
                }
            } else {
                shift = 0.0;
            }
            for (s, g) in step.iter_mut().zip(&eval.gradient) {
                *s = -g;
            }
            cholesky.solve_in_place(step);
            // Inequalities (joint limits, contact): the step of the QP with the same
            // positive definite Hessian and the linearised rows.
            if !rows.is_empty() {
                let hint: Vec<usize> = (0..rows.len())
                    .filter(|&i| {
                        multipliers
                            .binary_search_by(|(k, _)| k.cmp(&rows[i].key))
                            .is_ok()
                    })
                    .collect();
                let values: &[f64] = if shift > 0.0 {
                    shifted_values
                } else {
                    &eval.hessian
                };
                match sqp::constrained_step(
                    model.pattern(),
                    values,
                    cholesky,
                    &eval.gradient,
                    &rows,
                    step,
                    &hint,
                ) {
                    Ok(constrained) => {
                        step.copy_from_slice(&constrained.step);
                        multipliers = rows
                            .iter()
                            .zip(&constrained.multipliers)
                            .filter(|(_, l)| **l > 0.0)
                            .map(|(r, l)| (r.key, *l))
                            .collect();
                        multipliers.sort_by_key(|a| a.0);
                        let largest = multipliers.iter().fold(0.0f64, |m, (_, l)| m.max(*l));
                        merit_weight = merit_weight.max(2.0 * largest);
                    }
                    Err(_) => {
                        termination = Termination::SubproblemFailed;
                        break;
                    }
                }
            }

            // Step-length limits keep the manifold retraction, the linearised contact
            // and the line search sane.
            let (rotation, translation) = model.step_size(step);
            let limit = (settings.max_rotation_step_rad / rotation.max(1e-300))
                .min(max_translation / translation.max(1e-300))
                .min(1.0);
            // Merit `E + μ Σ max(0, −gap)` (exact penalty) and its slope along the step.
            let current_violation = violation(&rows);
            let merit = eval.energy + merit_weight * current_violation;
            let slope_per_t: f64 = step
                .iter()
                .zip(&eval.gradient)
                .map(|(s, g)| s * g)
                .sum::<f64>()
                - merit_weight * current_violation;

            // The full step is tried with a complete evaluation (energy, gradient,
            // Hessian): it is accepted almost always, and its derivatives then serve the
            // next iteration. Backtracking trials need the energy only.
            let mut t = limit;
            let mut accepted = false;
            let mut evaluated = false;
            let mut trial_rows: Vec<Row> = Vec::new();
            for trial_number in 0..=settings.max_line_search_steps {
                model.retract_into(&state, step, t, &mut trial);
                evaluated = trial_number == 0;
                let energy = if evaluated {
                    model.evaluate(&trial, trial_eval, true);
                    trial_eval.energy
                } else {
                    model.energy(&trial)
                };
                // A trial whose centreline passes through an obstacle is rejected.
                let admissible = collect_rows(&trial, &mut trial_rows);
                let trial_merit = if admissible {
                    energy + merit_weight * violation(&trial_rows)
                } else {
                    f64::INFINITY
                };
                let noise = 1e-13 * eval.energy.abs().max(energy.abs()).max(1e-12);
                let armijo = trial_merit <= merit + 1e-4 * t * slope_per_t;
                if armijo && trial_merit.is_finite() {
                    accepted = true;
                    break;
                }
                // Round-off regime: merit differences are below their noise; accept the
                // step if it reduces the residual instead.
                if (trial_merit - merit).abs() <= noise && t * slope_per_t.abs() <= noise {
                    if !evaluated {
                        model.evaluate(&trial, trial_eval, true);
                        evaluated = true;
                    }
                    let (trial_residual, _) = kkt(&trial_rows, &multipliers, &trial_eval.gradient);
                    if trial_residual.combined_n < residual.combined_n {
                        accepted = true;
                        break;
                    }
                }
                t *= 0.5;
            }
            if !accepted {
                termination = Termination::LineSearchFailed;
                break;
            }
            std::mem::swap(&mut state, &mut trial);
            std::mem::swap(&mut rows, &mut trial_rows);
            stable_at_current = None;
            if evaluated {
                std::mem::swap(eval, trial_eval);
            } else {
                model.evaluate(&state, eval, true);
            }
        }

        let stable = match stable_at_current {
            Some(s) => s,
            None => cholesky.factor(&eval.hessian),
        };
        let (residual, _) = kkt(&rows, &multipliers, &eval.gradient);
        let constraints = rows
            .into_iter()
            .map(|row| {
                let lambda = multipliers
                    .binary_search_by(|(k, _)| k.cmp(&row.key))
                    .map_or(0.0, |i| multipliers[i].1);
                (row, lambda)
            })
            .collect();
        Solution {
            report: SolveReport {
                converged: termination == Termination::Converged,
                termination,
                residual,
                tolerance_n: settings.tolerance_n,
                iterations,
                coarse_iterations: 0,
                continuation_steps: 0,
                continuation_iterations: 0,
                shifted_iterations,
                stable,
                energy_j: eval.energy,
                solve_seconds: 0.0,
                unknowns: model.dofs().len(),
            },
            state,
            constraints,
        }
    }
}

/// Value offsets of the diagonal entries in the upper-triangular CSC pattern.
fn diagonal_positions(model: &Model) -> Vec<usize> {
    let p = model.pattern();
    (0..p.dim())
        .map(|c| {
            let rows = &p.row_idx[p.col_ptr[c]..p.col_ptr[c + 1]];
            p.col_ptr[c]
                + rows
                    .iter()
                    .position(|&r| r == c)
                    .expect("diagonal in pattern")
        })
        .collect()
}

fn check_initial_state(model: &Model, state: &SystemState) -> Result<(), SolveError> {
    let rods = &model.system().rods;
    if state.rods.len() != rods.len() {
        return Err(SolveError::InitialState(format!(
            "{} rod states for {} rods",
            state.rods.len(),
            rods.len()
        )));
    }
    for (spec, rod_state) in rods.iter().zip(&state.rods) {
        if rod_state.positions.len() != spec.rod.vertex_count()
            || rod_state.frames.len() != spec.rod.segments()
        {
            return Err(SolveError::InitialState(format!(
                "rod '{}' has {} vertices and {} frames; expected {} and {}",
                spec.name,
                rod_state.positions.len(),
                rod_state.frames.len(),
                spec.rod.vertex_count(),
                spec.rod.segments()
            )));
        }
        if !rod_state.is_finite() {
            return Err(SolveError::InitialState(format!(
                "rod '{}' has non-finite coordinates",
                spec.name
            )));
        }
    }
    Ok(())
}
