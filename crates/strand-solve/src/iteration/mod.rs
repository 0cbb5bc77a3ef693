//! One Newton/SQP solve on one model, in named phases:
//!
//! 1. **convergence test** ([`Iteration::kkt`]): the KKT residual `g − Σ λ_i a_i` in
//!    newtons, feasibility and complementarity of the rows, and stagnation;
//! 2. **model step** ([`Iteration::factor_damped`]): the Hessian with the gauge held
//!    and a Levenberg–Marquardt damping `λ·D`, `D` scaled per block ([`damping_scale`]:
//!    an edge rotation by its `EI/h`, a position barely, a joint by its own stiffness),
//!    raised from the last accepted value until the factorisation is positive definite
//!    (the undamped Hessian is tried first after an exact step);
//! 3. **direction** ([`Iteration::direction`]): the damped Newton step, projected by the
//!    QP of the linearised inequalities (contact, joint limits);
//! 4. **globalisation** ([`Iteration::globalise`]): a trust region in physical units
//!    (largest rotation in rad, largest translation in m), shrunk on rejection, grown on
//!    success; a first trial that the model mispredicted (without constraint rows) gets
//!    a second-order correction (the gradient's remainder at the trial, solved with the
//!    same factor: the step bends along a curved valley) and then a positions-only
//!    correction (the positions follow the frames), which a stiff rod (`C·h²/EI` above
//!    100) also gets whenever a trial turns its frames by more than a tenth of the
//!    valley turn `√(8 EI/(C h²))`; with contact rows the positions follow under the
//!    trial's rows ([`follow`]); an exact step is extended, and a short step of an
//!    indefinite iteration is
//!    tried together with a direction of negative curvature (from the whole region
//!    down, a quarter at a time);
//! 5. **acceptance** (inside `globalise`): the ratio of achieved to predicted decrease of
//!    the exact-penalty merit `E + μ max(0, −gap)` (ℓ∞); in the round-off regime, a
//!    decrease of the residual instead;
//!    A line search that fails, or a stagnation, within 4 times the round-off floor of
//!    the residual counts as convergence to round-off;
//! 6. **finish** ([`Iteration::finish`]): residual, multipliers and the stability
//!    classification of the returned state.

mod curvature;
mod far;
mod floor;
mod follow;
mod globalise;
mod stall;
mod tangent;

pub use floor::ROUND_OFF_RESOLVED;
pub(crate) use floor::strain_floor;
use floor::{ROUND_OFF_SPREAD, residual_floor};
pub use stall::ROUND_OFF_STALL;
pub(crate) use stall::stalled_at_floor;

use strand_system::{EdgeStresses, Evaluation, HessianPattern, Model, Residual, SystemState};

use crate::constraints::{Constraints, FarVertex, Row, RowKey, limit_rows};
use crate::gauge::Gauge;
use crate::linear::symmetric_product;
use crate::report::{Solution, SolveReport, Termination};
use crate::stability::reduced_inertia;
use crate::{SolverSettings, SparseCholesky};

/// Inverse-iteration steps per iteration for the direction of negative curvature.
const NEGATIVE_CURVATURE_ITERATIONS: usize = 6;

/// Ratio of achieved to predicted decrease above which a step counts as exact.
const EXACT_RATIO: f64 = 0.99;

/// Relative damping above which the step is mostly damping: after an exact step there,
/// [`Iteration::factor_damped`] tries [`LARGE_DAMPING_JUMP`] times it before the
/// damping itself. A contact row's curvature can make one iteration's Hessian need
/// 1e6 (everyday_s3_027, a cable along a 60° groove over the groove's end); decayed
/// by 3 per exact step, each such spike cost 20 iterations of steps of 1e-9 m.
const LARGE_DAMPING: f64 = 1.0;

/// Factor on a [`LARGE_DAMPING`] tried first after an exact step.
const LARGE_DAMPING_JUMP: f64 = 1e-3;

/// Smallest damping scale of a body rotation or joint unknown relative to the largest
/// rotation diagonal entry.
const DAMPING_FLOOR: f64 = 1e-4;

/// Damping scale of a position unknown relative to its own diagonal entry.
const POSITION_DAMPING: f64 = 1e-12;

/// The damping scale `D` of every unknown (in the order of `diagonal`, the value
/// offsets of the Hessian's diagonal), per block of the model's natural scaling:
/// * an edge rotation of a rod: the bending stiffness of the edge, `EI/h` (N·m per
///   rad²), not its Hessian diagonal, which the shear stiffness `GA·h` dominates: the
///   soft modes of a cable turn an edge's frame together with the edge, and a damping
///   scaled by `GA·h` would stop them (measured over the convergence map: 7 200 instead
///   of 13 500 iterations, 199 instead of 197 of 200 cases converged);
/// * a body rotation or joint unknown: its own diagonal entry, but at least
///   [`DAMPING_FLOOR`] of the largest rotation entry;
/// * a position unknown: [`POSITION_DAMPING`] of its own entry (`EA/h`): positions
///   follow the frames undamped, so the damped step is close to the step of the energy
///   minimised over the positions at given frames (the stiff axial and shear strains
///   never limit the step of the soft bending and twisting), yet a position that
///   nothing holds is still regularised at large damping.
pub(crate) fn damping_scale(
    hessian: &[f64],
    diagonal: &[usize],
    rotation: &[bool],
    bending: &[f64],
) -> Vec<f64> {
    let largest = diagonal
        .iter()
        .zip(rotation)
        .filter(|(_, r)| **r)
        .map(|(&k, _)| hessian[k].abs())
        .fold(f64::MIN_POSITIVE, f64::max);
    diagonal
        .iter()
        .zip(rotation)
        .zip(bending)
        .map(|((&k, &r), &b)| {
            if !r {
                POSITION_DAMPING * hessian[k].abs().max(f64::MIN_POSITIVE)
            } else if b > 0.0 {
                b
            } else {
                hessian[k].abs().max(DAMPING_FLOOR * largest)
            }
        })
        .collect()
}

/// Buffers reused by every solve of one model.
pub(crate) struct Workspace {
    pub cholesky: SparseCholesky,
    pub diagonal: Vec<usize>,
    /// Per unknown: whether it is a rotation or joint angle (not a position).
    pub rotation: Vec<bool>,
    /// Per unknown: `EI/h` of an edge rotation (N·m), 0 for other unknowns.
    pub bending_scale: Vec<f64>,
    pub gauge: Gauge,
    /// Every rotation (and gauge) unknown held: the positions-only correction. Built
    /// on first use ([`Workspace::rotations`]) from `rotation_unknowns`: most solves
    /// never take that correction, and building it walks the whole pattern (about 3 %
    /// of a 999-edge solve's time).
    pub rotations: Option<Gauge>,
    /// The unknowns [`Workspace::rotations`] holds, until it is built.
    pub rotation_unknowns: Vec<usize>,
    pub eval: Evaluation,
    pub trial_eval: Evaluation,
    /// A third evaluation: the trial's, kept while a corrected step is evaluated.
    pub spare_eval: Evaluation,
    pub damped: Vec<f64>,
    pub step: Vec<f64>,
    pub product: Vec<f64>,
    pub rhs: Vec<f64>,
    /// The SQP model's gradient where it is not the energy's (the augmented-Lagrangian
    /// term of the active rows, [`add_row_penalty`]), J per unknown.
    pub model_gradient: Option<Vec<f64>>,
}

impl Workspace {
    /// Writes the damped matrix `H + damping·D` into `damped`, gauge held: `H` the SQP
    /// model's Hessian (`model_hessian`, or the energy's when `None`), `D` the
    /// [`damping_scale`] of the energy Hessian.
    pub fn set_damped(&mut self, model_hessian: Option<&[f64]>, damping: f64) {
        self.damped
            .copy_from_slice(model_hessian.unwrap_or(&self.eval.hessian));
        if damping > 0.0 {
            let scale = damping_scale(
                &self.eval.hessian,
                &self.diagonal,
                &self.rotation,
                &self.bending_scale,
            );
            for (&k, d) in self.diagonal.iter().zip(&scale) {
                self.damped[k] += damping * d;
            }
        }
        self.gauge.fix_matrix(&mut self.damped);
    }

    /// The positions-only Newton step at `trial_eval` (every rotation held), left in
    /// `rhs` with its factor in `cholesky` (this iteration's factor is overwritten).
    /// `false` when that block is not positive definite (a body or clip couples
    /// positions to rotations).
    pub fn positions_only_step(&mut self, pattern: &HessianPattern) -> bool {
        let rotations = built_rotations(&mut self.rotations, &mut self.rotation_unknowns, pattern);
        self.damped.copy_from_slice(&self.trial_eval.hessian);
        rotations.fix_matrix(&mut self.damped);
        for (c, g) in self.rhs.iter_mut().zip(&self.trial_eval.gradient) {
            *c = -g;
        }
        rotations.fix_vector(&mut self.rhs);
        if !self.cholesky.factor(&self.damped) {
            return false;
        }
        self.cholesky.solve_in_place(&mut self.rhs);
        true
    }

    /// The gauge holding every rotation unknown (and the gauge's): the unknowns the
    /// positions-only correction keeps fixed. Built from `pattern` on first use.
    pub fn rotations(&mut self, pattern: &HessianPattern) -> &Gauge {
        built_rotations(&mut self.rotations, &mut self.rotation_unknowns, pattern)
    }
}

/// The gauge in `slot`, built holding `unknowns` (taken) in `pattern` if not yet.
fn built_rotations<'g>(
    slot: &'g mut Option<Gauge>,
    unknowns: &mut Vec<usize>,
    pattern: &HessianPattern,
) -> &'g Gauge {
    slot.get_or_insert_with(|| Gauge::holding_in(pattern, std::mem::take(unknowns)))
}

/// The SQP model of one step where it differs from the energy's (see
/// [`Iteration::sqp_model`]).
struct SqpModel {
    /// Upper-triangular Hessian values in the model's pattern, J per unknown².
    hessian: Vec<f64>,
    /// Gradient, J per unknown.
    gradient: Vec<f64>,
    /// Per row: the shortfall of [`add_row_penalty`], added back to the row's QP
    /// multiplier when held.
    penalty_shifts: Vec<f64>,
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
    /// The vertices of the features far from the meshes whose rows `rows` leaves out
    /// (see `far.rs`): empty when `rows` holds every row.
    far: Vec<FarVertex>,
    /// Multipliers of the last step by key (sorted).
    multipliers: Vec<(RowKey, f64)>,
    /// Per row of the SQP model being stepped: the amount (N, or N·m for an angular
    /// limit) by which the QP's multiplier of that row falls short of the true one when
    /// the row is held (see [`add_row_penalty`]); empty without the augmented-Lagrangian
    /// term.
    penalty_shifts: Vec<f64>,
    merit_weight: f64,
    /// Relative Levenberg–Marquardt damping of the last accepted step (0: pure Newton).
    damping: f64,
    /// Trust radius as a fraction of the settings' step limits.
    radius: f64,
    /// Largest translation of a vertex in one step, m, along a direction whose
    /// clearance is not measured (the settings' limit and the contact's blind limit).
    max_translation: f64,
    /// Largest translation of a vertex in one step by the settings alone, m (the
    /// Newton step's clearance is measured: [`Constraints::advancement`]).
    free_translation: f64,
    /// The tolerance applied: the larger of the setting and the round-off floor, N.
    tolerance: f64,
    report: SolveReport,
    history: Vec<(f64, f64)>,
    /// Whether this iteration's Hessian needed damping to be positive definite.
    indefinite: bool,
    /// Whether the last accepted step matched its quadratic model (ratio at least
    /// [`EXACT_RATIO`]): the next iteration tries the undamped Hessian first.
    try_undamped: bool,
    /// The last direction of negative curvature (warm start of inverse iteration).
    curvature_direction: Vec<f64>,
    /// Whether some rod's axial and shear stiffness dwarfs its bending stiffness at the
    /// scale of its edges (`C·h²/EI` above [`FOLLOW_RATIO`]): a finite turn of its frames
    /// then strains it at second order, so trial steps let the positions follow.
    stiff: bool,
    /// The turn (rad) beyond which a straight-line step strains a stiff rod more than
    /// it bends it ([`valley_turn`]).
    valley_turn: f64,
    /// Print every trial step to stderr (environment variable `STRAND_TRACE` set).
    trace: bool,
    /// Whether `work.eval.hessian` was assembled with predicted edge stresses (mixed
    /// Newton) rather than the state's own.
    mixed_hessian: bool,
    /// Whether the last direction, from the augmented SQP model ([`Iteration::sqp_model`]),
    /// failed to descend the merit function (its predicted decrease not positive): the
    /// iteration is then stepped again with the plain model.
    ascent: bool,
    /// Step with the energy's own Hessian and gradient, without the contact rows'
    /// curvature and augmented-Lagrangian terms (see [`Iteration::ascent`]).
    plain_model: bool,
    /// Whether the trial being accepted is the first one and was as long as the
    /// translation limits allow (see [`Iteration::globalise`]).
    step_at_limit: bool,
    /// Stop as [`Termination::Creeping`] (see [`Iteration::stopping_on_creep`]).
    stop_on_creep: bool,
    /// Consecutive iterations, up to this one, that followed an exact step (see
    /// [`Iteration::try_undamped`]) and still needed damping: the undamped Hessian
    /// not positive definite where the quadratic model was accurate.
    damped_exact_steps: usize,
}

impl<'a> Iteration<'a> {
    pub(crate) fn new(
        model: &'a Model,
        constraints: Option<&'a dyn Constraints>,
        settings: &'a SolverSettings,
        work: &'a mut Workspace,
        mut state: SystemState,
        stresses: Option<EdgeStresses>,
    ) -> Self {
        model.enforce_supports(&mut state);
        let stresses = stresses.filter(|_| settings.mixed_newton);
        match &stresses {
            Some(s) => model.evaluate_mixed(&state, &mut work.eval, s),
            None => model.evaluate(&state, &mut work.eval, true),
        }
        let longest_rod = model
            .system()
            .rods
            .iter()
            .map(|r| r.rod.length())
            .fold(0.0, f64::max);
        let free_translation = settings.max_translation_step * longest_rod;
        let mut max_translation = free_translation;
        if let Some(c) = constraints {
            max_translation = max_translation.min(c.max_translation_m());
        }
        let floor = if work.eval.has_hessian {
            residual_floor(model, &state, &work.eval.hessian)
        } else {
            strain_floor(model)
        };
        let valley_turn = valley_turn(model);
        let mut report = SolveReport::new(model.dofs().len(), settings.tolerance_n);
        report.residual_floor_n = floor;
        report.applied_load_n = model.system().applied_load_n();
        report.gauge_freedoms = work.gauge.held().len();
        let mut iteration = Self {
            model,
            constraints,
            settings,
            work,
            state,
            rows: Vec::new(),
            far: Vec::new(),
            multipliers: Vec::new(),
            penalty_shifts: Vec::new(),
            merit_weight: 0.0,
            damping: 0.0,
            radius: 1.0,
            max_translation,
            free_translation,
            // The least the residual is resolved to, not the floor's estimate: the iteration
            // goes on while it still gains (a stall counts within its spread of the floor),
            // for a residual at the floor leaves errors along the soft directions (5e-9 m
            // across a stiff cantilever, EA 1e8 N, when it stopped there).
            tolerance: settings.tolerance_n.max(strain_floor(model)),
            report,
            history: Vec::new(),
            trace: std::env::var_os("STRAND_TRACE").is_some(),
            valley_turn,
            stiff: valley_turn < (8.0 / FOLLOW_RATIO).sqrt(),
            indefinite: false,
            try_undamped: false,
            curvature_direction: Vec::new(),
            mixed_hessian: stresses.is_some(),
            step_at_limit: false,
            ascent: false,
            plain_model: false,
            stop_on_creep: false,
            damped_exact_steps: 0,
        };
        let (mut rows, mut far) = (Vec::new(), Vec::new());
        iteration.collect_rows(&iteration.state.clone(), &mut rows, &mut far);
        iteration.rows = rows;
        iteration.far = far;
        iteration
    }

    /// Whether to stop as [`Termination::Creeping`] when the iteration creeps (the
    /// direct attempt of a solve that a release retry follows).
    pub(crate) fn stopping_on_creep(mut self, stop: bool) -> Self {
        self.stop_on_creep = stop;
        self
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
                if residual.combined_n <= ROUND_OFF_SPREAD * self.report.residual_floor_n
                    && satisfied
                {
                    break Termination::Converged;
                }
                break Termination::Stagnated;
            }
            if self.creeping(residual.combined_n) {
                break Termination::Creeping;
            }
            if self.report.iterations >= self.settings.max_iterations {
                break Termination::MaxIterations;
            }
            self.report.iterations += 1;
            crate::activity::record(residual.combined_n);
            let (damping_before, damped_before) = (self.damping, self.damped_exact_steps);
            // The multipliers `residual` was measured with: a step that is then not
            // taken leaves the state as it was but its QP's multipliers in place.
            let multipliers_before = self.multipliers.clone();
            let mut stepped = self.step(residual.combined_n);
            if self.ascent {
                // The augmented SQP model's step does not descend the merit (the
                // penalty pulls open rows held in the last QP shut, uphill in energy):
                // this iteration takes the plain step instead.
                self.ascent = false;
                // The plain Hessian searches its own damping from where this
                // iteration started: the rows' curvature (`−λ∇²g` of a cable pressed
                // over a mesh edge) can make the augmented one need far more
                // (everyday_s3_027, a cable along a 60° groove: 1.2e6 where the last
                // step had none; the plain step inherited it, and every such step cost
                // 20 iterations of damping decay).
                self.damping = damping_before;
                self.damped_exact_steps = damped_before;
                self.plain_model = true;
                stepped = self.step(residual.combined_n);
                self.plain_model = false;
            }
            if let Err((stop, searched)) = stepped {
                if !searched {
                    break stop;
                }
                // No step improves the merit any more: at a residual within
                // [`ROUND_OFF_SPREAD`] times the floor that is round-off, not failure.
                // The residual judged is the one reported: with the multipliers it was
                // measured with, not those of the step's QP (`g − Aᵀλ = −H d` for the
                // step `d` not taken: on a stiff cable in a groove 4.6e-8 N where the
                // state's own was 3.9e-9 N, everyday_s21_025).
                if residual.combined_n <= ROUND_OFF_SPREAD * self.report.residual_floor_n
                    && satisfied
                {
                    self.multipliers = multipliers_before;
                    break Termination::Converged;
                }
                break self.stall_or(stop);
            }
        };
        self.finish(termination)
    }

    /// One step: model, direction, globalisation. `Err((stop, searched))`, `searched`
    /// when the line search (not the model or the direction) failed.
    fn step(&mut self, residual: f64) -> Result<(), (Termination, bool)> {
        self.factor_damped().map_err(|stop| (stop, false))?;
        self.direction().map_err(|stop| (stop, false))?;
        self.globalise(residual).map_err(|stop| (stop, true))
    }

    /// Convergence test: the KKT residual `g − Σ λ_i a_i` with the multipliers of the
    /// last step on the current rows, and whether every row is feasible and every row
    /// with a multiplier closed (complementarity).
    fn kkt(&self, rows: &[Row], gradient: &[f64]) -> (Residual, bool) {
        if rows.is_empty() {
            return (self.model.residual(gradient), true);
        }
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
    /// window while the energy no longer changes beyond round-off. Within
    /// [`ROUND_OFF_SPREAD`] times the floor the window is [`stall::STALL_ITERATIONS`]:
    /// there trials are accepted on round-off noise of the residual (ratios of ±1e9,
    /// energies equal to every digit) and a longer window only spends iterations (the
    /// convergence map's case #103: 12 iterations at 1.7 to 2.4 times the floor).
    fn stagnated(&mut self, residual: f64) -> bool {
        let energy = self.work.eval.energy;
        self.history.push((residual, energy));
        let window = if residual <= ROUND_OFF_SPREAD * self.report.residual_floor_n {
            self.settings
                .stagnation_iterations
                .min(stall::STALL_ITERATIONS)
        } else {
            self.settings.stagnation_iterations
        };
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

    /// Creeping ([`Termination::Creeping`], where asked for): rows held, each of the
    /// last [`crate::SolverSettings::stagnation_iterations`] steps an exact one (full,
    /// as predicted) whose successor still needed damping, and the best residual of
    /// that window not below [`crate::SolverSettings::stagnation_reduction`] times the
    /// best before it, away from the round-off floor (where [`Iteration::stagnated`]
    /// judges): linear convergence at the damping's rate. Measured on
    /// `everyday_s74_001` (a 12 mm cable of 3233 segments in a 90° groove): the
    /// residual fell from 2.5e-8 to 2.0e-9 N in 160 such iterations at a damping of
    /// 5e-5 to 3e-4, and the release retry from there converged in 2. Of the 159
    /// other everyday cases of seeds 3, 9, 39, 51, 55, 64, 69 and 74, two stop by this
    /// test (`everyday_s69_001` 26 → 24 iterations, `everyday_s69_002` 151 → 148);
    /// counting damped steps alone, six stopped early in their settling, two at a
    /// cost. A test over any steps (the best residual not halved in four windows)
    /// caught the creep of `everyday_s39_013` and `everyday_s76_008` (200 iterations
    /// each before the retry converged in 10 and 18) but gained little: the retry
    /// from an earlier state needs more (249 → 196 and 231 → 221 iterations; with
    /// three windows 244 for the second), so it is not used.
    fn creeping(&self, residual: f64) -> bool {
        let window = self.settings.stagnation_iterations;
        let n = self.history.len();
        if !self.stop_on_creep
            || self.multipliers.is_empty()
            || self.damped_exact_steps < window
            || n <= window
            || residual <= ROUND_OFF_SPREAD * self.report.residual_floor_n
        {
            return false;
        }
        let least = |h: &[(f64, f64)]| h.iter().map(|h| h.0).fold(f64::INFINITY, f64::min);
        least(&self.history[n - window..])
            > self.settings.stagnation_reduction * least(&self.history[..n - window])
    }

    /// Model step: factorises `H + λ·diag|H|` (gauge held), with the smallest damping
    /// from the last accepted one down (or up) that is positive definite.
    fn factor_damped(&mut self) -> Result<(), Termination> {
        let settings = self.settings;
        let mut damping = self.damping;
        let mut failed = false;
        let model = self.sqp_model();
        self.penalty_shifts = model
            .as_ref()
            .map(|m| m.penalty_shifts.clone())
            .unwrap_or_default();
        let work = &mut *self.work;
        work.model_gradient = model.as_ref().map(|m| m.gradient.clone());
        let hessian = model.as_ref().map(|m| &m.hessian[..]);
        if self.try_undamped && damping > 0.0 {
            // The last step was exact: the undamped Newton step may be positive definite
            // already (one factorisation to find out, instead of an eighth per step).
            work.set_damped(hessian, 0.0);
            if work.cholesky.factor(&work.damped) {
                self.damping = 0.0;
                self.indefinite = false;
                self.damped_exact_steps = 0;
                return Ok(());
            }
            failed = true;
            if damping > LARGE_DAMPING {
                // Still indefinite, but the damping of a passing spike (a contact row's
                // curvature at one iteration) need not be decayed one
                // `contact_damping_decrease` per exact step: try far less first.
                let smaller = damping * LARGE_DAMPING_JUMP;
                work.set_damped(hessian, smaller);
                if work.cholesky.factor(&work.damped) {
                    self.report.shifted_iterations += 1;
                    self.damping = smaller;
                    self.indefinite = true;
                    self.damped_exact_steps += 1;
                    return Ok(());
                }
            }
        }
        loop {
            work.set_damped(hessian, damping);
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
        self.damped_exact_steps = if self.try_undamped && damping > 0.0 {
            self.damped_exact_steps + 1
        } else {
            0
        };
        self.damping = damping;
        self.indefinite = failed;
        Ok(())
    }

    /// The SQP model's Hessian and gradient when they differ from the energy's: the
    /// Lagrangian's `H − Σ λ_i ∇²g_i` over the rows with a positive multiplier of the
    /// last QP and a curvature (a contact held across a ridge, a mesh vertex or another
    /// rod: the constraint's curvature, about `λ/r`, can dwarf a limp rod's own
    /// stiffness; setting `constraint_curvature`), plus the augmented-Lagrangian term
    /// `½ Σ ρ_i (value_i + a_i·d)²` of those rows (setting `active_row_penalty`, see
    /// [`add_row_penalty`]). `None` when neither applies.
    fn sqp_model(&self) -> Option<SqpModel> {
        let settings = self.settings;
        if self.multipliers.is_empty()
            || self.plain_model
            || !(settings.constraint_curvature || settings.active_row_penalty)
        {
            return None;
        }
        let pattern = self.model.pattern();
        let energy = &self.work.eval;
        let mut hessian = energy.hessian.clone();
        let mut gradient = energy.gradient.clone();
        let mut changed = false;
        let mut penalty_shifts = vec![0.0; self.rows.len()];
        for (row, shift) in self.rows.iter().zip(&mut penalty_shifts) {
            let lambda = self.multiplier(row.key);
            if lambda <= 0.0 {
                continue;
            }
            if settings.constraint_curvature
                && let Some(curvature) = &row.curvature
            {
                curvature.add_into(pattern, &mut hessian, -lambda);
                changed = true;
            }
            if settings.active_row_penalty
                && let Some(shortfall) = add_row_penalty(
                    pattern,
                    &self.work.diagonal,
                    &energy.hessian,
                    row,
                    settings.release_open_rows.then_some(lambda),
                    settings.constraint_tolerance,
                    &mut hessian,
                    &mut gradient,
                )
            {
                *shift = shortfall;
                changed = true;
            }
        }
        changed.then_some(SqpModel {
            hessian,
            gradient,
            penalty_shifts,
        })
    }

    /// A direction of negative curvature of the Hessian (the generalised eigenvector of
    /// `(H, D)` with the most negative eigenvalue), from a few steps of inverse
    /// iteration with the current damped factor, warm-started from the last one.
    /// With rows, of the SQP model's Hessian on the directions that keep the rows held
    /// in the last step (projected inverse iteration, [`tangent`]; none when more than
    /// [`tangent::MAX_TANGENT_ROWS`] are held). `None` unless the Hessian was found
    /// indefinite and the direction's Rayleigh quotient is negative.
    fn negative_curvature(&mut self) -> Option<Vec<f64>> {
        if !self.indefinite {
            return None;
        }
        let held: Vec<&Row> = self
            .rows
            .iter()
            .filter(|r| self.multiplier(r.key) > 0.0)
            .collect();
        let work = &mut *self.work;
        let n = work.step.len();
        let projector = if self.rows.is_empty() {
            None
        } else {
            Some(tangent::TangentProjector::new(
                &mut work.cholesky,
                &work.gauge,
                n,
                &held,
            )?)
        };
        let scale = damping_scale(
            &work.eval.hessian,
            &work.diagonal,
            &work.rotation,
            &work.bending_scale,
        );
        if self.curvature_direction.len() != n {
            self.curvature_direction = crate::saddle::generic_start(n);
        }
        let x = &mut self.curvature_direction;
        match &projector {
            None => {
                crate::saddle::inverse_iteration(work, &scale, x, NEGATIVE_CURVATURE_ITERATIONS)?
            }
            Some(projector) => {
                projector.project(x);
                for _ in 0..NEGATIVE_CURVATURE_ITERATIONS {
                    crate::saddle::inverse_iteration(work, &scale, x, 1)?;
                    projector.project(x);
                }
            }
        }
        // The energy's curvature without rows; with rows the model's (the rows'
        // curvature is what makes it negative), `damped` less its damping.
        let curvature: f64 = if projector.is_none() {
            symmetric_product(
                self.model.pattern(),
                &work.eval.hessian,
                x,
                &mut work.product,
            );
            x.iter().zip(&work.product).map(|(a, b)| a * b).sum()
        } else {
            symmetric_product(self.model.pattern(), &work.damped, x, &mut work.product);
            let damped: f64 = x.iter().zip(&work.product).map(|(a, b)| a * b).sum();
            let damping: f64 = x.iter().zip(&scale).map(|(xi, d)| d * xi * xi).sum();
            damped - self.damping * damping
        };
        (curvature < 0.0).then(|| x.clone())
    }

    /// Direction: the damped Newton step `−(H + λD)⁻¹ g`, then the QP of the
    /// linearised inequalities with the same matrix.
    fn direction(&mut self) -> Result<(), Termination> {
        let work = &mut *self.work;
        let gradient = work.model_gradient.as_ref().unwrap_or(&work.eval.gradient);
        for (s, g) in work.step.iter_mut().zip(gradient) {
            *s = -g;
        }
        work.gauge.fix_vector(&mut work.step);
        work.cholesky.solve_in_place(&mut work.step);
        // No rows: none left out either (see `collect_rows`).
        if self.rows.is_empty() {
            return Ok(());
        }
        // Rows left out for far features hold if the step keeps their vertices within
        // their clearances (see `far.rs`); else those vertices' rows are brought in and
        // the QP solved again.
        let mut constrained = self.constrained_step()?;
        loop {
            let moved = self.far_moved(&constrained.step);
            if moved.is_empty() {
                break;
            }
            self.include_far_rows(&moved)?;
            constrained = self.constrained_step()?;
        }
        self.work.step.copy_from_slice(&constrained.step);
        // A held row's multiplier in the penalised model falls short of the true one
        // by the pull the model leaves out (see `add_row_penalty`).
        let shifts = &self.penalty_shifts;
        self.multipliers = self
            .rows
            .iter()
            .zip(&constrained.multipliers)
            .enumerate()
            .filter(|(_, (_, l))| **l > 0.0)
            .map(|(i, (r, l))| (r.key, *l + shifts.get(i).copied().unwrap_or(0.0)))
            .collect();
        self.multipliers.sort_by_key(|a| a.0);
        // The ℓ∞ penalty is exact above the sum of the multipliers.
        let total: f64 = self.multipliers.iter().map(|(_, l)| l).sum();
        self.merit_weight = self.merit_weight.max(2.0 * total);
        Ok(())
    }

    /// The QP of the linearised rows with the damped model's factor, from the Newton
    /// step in `work.step` (left as it is).
    fn constrained_step(&mut self) -> Result<crate::sqp::ConstrainedStep, Termination> {
        let (hint, guessed) = start_of_active_set(&self.rows, &self.multipliers);
        let work = &mut *self.work;
        let gradient = work.model_gradient.as_ref().unwrap_or(&work.eval.gradient);
        work.rhs.copy_from_slice(gradient);
        work.gauge.fix_vector(&mut work.rhs);
        crate::sqp::constrained_step(
            self.model.pattern(),
            &work.damped,
            &mut work.cholesky,
            &work.rhs,
            &self.rows,
            &work.step,
            &hint,
            guessed,
        )
        .map_err(|_| Termination::SubproblemFailed)
    }

    /// Rows at `state`: joint limits and (if any) contact, less the rows of features
    /// far from the meshes, whose vertices go to `far` (see `far.rs`). `false` when
    /// the state is not admissible (a centreline through an obstacle).
    fn collect_rows(
        &self,
        state: &SystemState,
        rows: &mut Vec<Row>,
        far: &mut Vec<FarVertex>,
    ) -> bool {
        rows.clear();
        far.clear();
        limit_rows(self.model, state, rows);
        let Some(c) = self.constraints else {
            return true;
        };
        if c.rows_leaving_far(self.model, state, rows, far).is_err() {
            return false;
        }
        // Whether there are rows at all decides the unconstrained paths: with only
        // far features, every row is made (the left-out features may make none).
        if rows.is_empty() && !far.is_empty() {
            far.clear();
            return c.rows(self.model, state, rows).is_ok();
        }
        true
    }

    /// Every row at `state` ([`Iteration::collect_rows`] leaving nothing out).
    fn collect_all_rows(&self, state: &SystemState, rows: &mut Vec<Row>) -> bool {
        rows.clear();
        limit_rows(self.model, state, rows);
        match self.constraints {
            Some(c) => c.rows(self.model, state, rows).is_ok(),
            None => true,
        }
    }

    /// Finish: residual, multipliers per row and the stability of the returned state.
    fn finish(mut self, termination: Termination) -> Solution {
        if self.trace && termination != Termination::Converged {
            let g = &self.work.eval.gradient;
            let (k, v) = g.iter().enumerate().fold((0, 0.0f64), |(bk, bv), (k, v)| {
                if v.abs() > bv { (k, v.abs()) } else { (bk, bv) }
            });
            eprintln!(
                "strand-solve: stopped ({termination:?}): largest gradient component {k} (block {}, {:?}) = {v:.3e}",
                k / 3,
                self.model.dofs().kind(k / 3)
            );
        }
        if self.mixed_hessian {
            // Stability is a property of the true Hessian.
            self.model.evaluate(&self.state, &mut self.work.eval, true);
        }
        let (residual, satisfied) = self.kkt(&self.rows, &self.work.eval.gradient);
        // Converged only if the residual reported meets what convergence means (the
        // tolerance, or round-off within [`ROUND_OFF_SPREAD`] times the floor), every
        // row holding: a guard that the residual judged and the one reported are one.
        let meets = residual.combined_n <= self.tolerance
            || residual.combined_n <= ROUND_OFF_SPREAD * self.report.residual_floor_n;
        // A residual accepted at round-off must also be small against the loads: a
        // floor of the size of the loads resolves no equilibrium of them.
        let load = self.report.applied_load_n;
        let resolved = residual.combined_n <= self.settings.tolerance_n
            || load <= 0.0
            || residual.combined_n <= ROUND_OFF_RESOLVED * load;
        // A floor above that fraction of the loads resolves no equilibrium at all:
        // any stop short of the tolerance (but a failed subproblem or a non-finite
        // number) is that, and no continuation can do better.
        let unresolvable = load > 0.0
            && self.report.residual_floor_n > ROUND_OFF_RESOLVED * load
            && residual.combined_n > self.settings.tolerance_n;
        let termination = match termination {
            Termination::Converged if !(meets && satisfied) => Termination::Stagnated,
            Termination::Converged if !resolved => Termination::FloorAboveLoads,
            Termination::MaxIterations | Termination::LineSearchFailed | Termination::Stagnated
                if unresolvable =>
            {
                Termination::FloorAboveLoads
            }
            other => other,
        };
        let converged = termination == Termination::Converged;
        let active: Vec<&Row> = self
            .rows
            .iter()
            .filter(|r| self.multiplier(r.key) > 0.0)
            .collect();
        // Fast path: without active rows, `H − τD` positive definite (one Cholesky with
        // the analysis already done) means no negative and no neutral direction. The
        // envelope's count tries that Cholesky first itself (with rows too).
        let tau = self.settings.neutral_tolerance;
        let work = &mut *self.work;
        let clearly_stable = active.is_empty() && !work.cholesky.is_envelope() && {
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
                &mut work.cholesky,
                &mut work.damped,
            )
        };
        // The Hessian at the converged state (the true one: see above), handed on
        // for the sensitivities when asked for.
        let hessian = (self.settings.keep_hessian && converged)
            .then(|| std::sync::Arc::from(work.eval.hessian.as_slice()));
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
            analysis: Some(self.work.cholesky.analysis()),
            hessian,
        }
    }
}

/// `C·h²/EI` above which a rod counts as stiff (see [`Iteration`]'s `stiff`): the
/// quadratic model of a step turning its frames by `θ` fails beyond
/// `θ ≈ √(8 EI / (C h²))`, i.e. below 0.3 rad.
const FOLLOW_RATIO: f64 = 100.0;

/// The smallest turn `√(8 EI / (C h²))` (rad) of any rod beyond which the axial and
/// shear strain of a straight-line step (`C θ⁴ h / 8` per edge) exceeds the change of
/// bending energy it makes (`EI θ² / h`): `C` the stiffest strain stiffness, `EI` the
/// softest bending or twisting one, `h` the shortest edge.
fn valley_turn(model: &Model) -> f64 {
    (8.0 / crate::stiffness::stiffness_ratio(model.system())).sqrt()
}

/// Largest violation `max(0, −value)` of the rows (m or rad): the ℓ∞ exact penalty.
/// Unlike the sum, it does not jump when one contact becomes two rows of equal value
/// (an edge whose nearest points become a stretch gives a row at each end; a vertex
/// near a crease gets one row per flank), which would make the merit discontinuous
/// along a step and reject every trial however short.
fn violation_of(rows: &[Row]) -> f64 {
    rows.iter().map(|r| (-r.value).max(0.0)).fold(0.0, f64::max)
}

/// The rows the primal–dual active set of a step starts from: those the last QP held
/// (by key); without a last QP's multipliers (a solve's first step, a prolonged coarse
/// equilibrium's contacts), the rows closed to within [`CLOSED_AT_START`].
///
/// The set is only a start (rows of negative multiplier leave, violated ones join), but
/// a good one saves passes: a 2831-segment cable lying in a groove started empty took
/// 528 passes (each a substitution over the whole band) to hold its 1862 contacts,
/// 1.4 s of a 1.8 s solve, from the closed rows 21. Whether the start is such a guess
/// is returned with it (see [`crate::sqp::constrained_step`]).
fn start_of_active_set(rows: &[Row], multipliers: &[(RowKey, f64)]) -> (Vec<usize>, bool) {
    if multipliers.is_empty() {
        let closed = (0..rows.len())
            .filter(|&i| rows[i].value <= CLOSED_AT_START)
            .collect();
        return (closed, true);
    }
    let held = (0..rows.len())
        .filter(|&i| {
            multipliers
                .binary_search_by(|(k, _)| k.cmp(&rows[i].key))
                .is_ok()
        })
        .collect();
    (held, false)
}

/// A row whose value (a gap in m, a joint's distance to its stop in rad or m) is at
/// most this at a step without a last QP starts its active set (a coarse level's
/// contacts carried to the fine rod are closed to well within it).
const CLOSED_AT_START: f64 = 1e-6;

/// Adds the augmented-Lagrangian term `½ ρ (pulled + a·d)²` of an active `row` to the
/// SQP model (`ρ a aᵀ` to `hessian`, `ρ·pulled·a` to `gradient`), `ρ` the energy
/// Hessian's stiffness along the row (`Σ a_k² H_kk / Σ a_k²`, N/m for a gap). It makes
/// the model positive definite wherever only the tangent space of the contacts is (a
/// hose draped over a pipe, whose energy alone is indefinite along the normals), so the
/// Newton step needs no Levenberg–Marquardt damping there. `pulled` is the row's whole
/// value, unless `released_multiplier` (setting `release_open_rows`: the row's last
/// multiplier λ, N) is given: then only while the row is open by less than
/// `max(tolerance, λ/ρ)`, none beyond twice that ([`pulled_value`]): a row the rod
/// lifted off since the QP held it gets the curvature but is not pulled shut, which
/// lets cables creeping along a groove converge (see the setting). On a row held by
/// the QP (`value + a·d = 0`) the term's gradient is `ρ·(pulled − value)·a`: the step
/// is that of the unpenalised QP and the QP's multiplier falls short of the true one by
/// `ρ·(value − pulled)` (zero without the release), which is returned for the caller
/// to add back. Returns `None` (and adds nothing) when the pattern does not couple the
/// row's unknowns (two rods in contact).
pub(crate) fn add_row_penalty(
    pattern: &strand_system::HessianPattern,
    diagonal: &[usize],
    energy_hessian: &[f64],
    row: &Row,
    released_multiplier: Option<f64>,
    tolerance: f64,
    hessian: &mut [f64],
    gradient: &mut [f64],
) -> Option<f64> {
    // The stored offset of entry (p, q) of the upper triangle (block-wise CSC).
    let offset = |p: usize, q: usize| -> Option<usize> {
        let (p, q) = if p <= q { (p, q) } else { (q, p) };
        pattern
            .find_offsets(p / 3, q / 3)
            .map(|offsets| offsets[q % 3] + p % 3)
    };
    // The row's gradient with repeated unknowns merged.
    let mut entries: Vec<(usize, f64)> = Vec::with_capacity(row.gradient.len());
    for &(k, a) in &row.gradient {
        match entries.iter_mut().find(|e| e.0 == k) {
            Some(e) => e.1 += a,
            None => entries.push((k, a)),
        }
    }
    if entries
        .iter()
        .any(|&(p, _)| entries.iter().any(|&(q, _)| offset(p, q).is_none()))
    {
        return None;
    }
    let norm: f64 = entries.iter().map(|(_, a)| a * a).sum();
    if norm == 0.0 {
        return None;
    }
    let rho = entries
        .iter()
        .map(|&(k, a)| a * a * energy_hessian[diagonal[k]].abs())
        .sum::<f64>()
        / norm;
    let pulled = match released_multiplier {
        // Released beyond the gap the row's last force opens in the rod's own
        // stiffness along it (`λ/ρ`, m).
        Some(multiplier) => pulled_value(row.value, tolerance.max(multiplier / rho)),
        None => row.value,
    };
    for (i, &(p, a)) in entries.iter().enumerate() {
        gradient[p] += rho * pulled * a;
        for &(q, b) in &entries[i..] {
            // One stored value stands for both (p, q) and (q, p).
            if let Some(at) = offset(p, q) {
                hessian[at] += rho * a * b;
            }
        }
    }
    Some(rho * (row.value - pulled))
}

/// The part of a released held row's `value` that [`add_row_penalty`] pulls shut: all
/// of it while the row is closed to within `reach` (or violated), none once it is open
/// by `2·reach`, linear in between (continuous, so the model does not jump).
pub(crate) fn pulled_value(value: f64, reach: f64) -> f64 {
    if value <= reach {
        value
    } else {
        (2.0 * reach - value).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::{CLOSED_AT_START, Row, RowKey, pulled_value, start_of_active_set};

    #[test]
    fn a_step_without_a_last_qp_starts_from_the_closed_rows() {
        let row = |key: u64, value: f64| Row {
            key: RowKey::Contact(key),
            value,
            gradient: vec![(0, 1.0)],
            curvature: None,
        };
        let rows = [
            row(7, 0.3e-6),
            row(3, 2.0 * CLOSED_AT_START),
            row(9, -1e-4),
            row(5, 1e-2),
        ];
        // First step: the rows closed (or violated) to within a micrometre.
        assert_eq!(start_of_active_set(&rows, &[]), (vec![0, 2], true));
        // After a QP: the rows it held, by key, whatever their value now.
        let held = [(RowKey::Contact(3), 0.5), (RowKey::Contact(5), 0.1)];
        assert_eq!(start_of_active_set(&rows, &held), (vec![1, 3], false));
    }

    #[test]
    fn a_held_row_is_pulled_shut_while_closed_and_let_go_once_open() {
        let tolerance = 1e-9;
        // Closed, touching within the tolerance or violated: the whole value is pulled.
        for value in [-1e-3, -1e-9, 0.0, 5e-10, 1e-9] {
            assert_eq!(pulled_value(value, tolerance), value);
        }
        // Open by twice the tolerance or more (lifted off since the QP held it): none.
        for value in [2e-9, 1e-6, 1e-2] {
            assert_eq!(pulled_value(value, tolerance), 0.0);
        }
        // Continuous between (the model does not jump when a gap crosses the
        // tolerance) and never more than the value itself.
        let mut last = pulled_value(0.0, tolerance);
        for k in 1..=3000 {
            let value = k as f64 * 1e-12;
            let pulled = pulled_value(value, tolerance);
            assert!(
                (pulled - last).abs() <= 1.0000001e-12,
                "{value}: {last} -> {pulled}"
            );
            assert!((0.0..=value).contains(&pulled));
            last = pulled;
        }
    }
}
