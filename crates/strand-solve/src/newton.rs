//! The solver bound to one model: symbolic analysis once, then solves that chain nested
//! iteration (a coarse start), the direct Newton/SQP iteration ([`crate::iteration`])
//! and, when that fails, adaptive load continuation ([`crate::continuation`]).

use std::time::Instant;

use strand_system::{EdgeStresses, Model, SystemState};

use crate::constraints::Constraints;
use crate::gauge::Gauge;
use crate::iteration::{Iteration, Workspace, stalled_at_floor};
use crate::report::{Solution, Termination};
use crate::{
    InitialStateError, SolveError, SolverSettings, SparseCholesky, continuation, nested, saddle,
    stiffness,
};

/// Systems whose held points centre farther than this from the origin (m) are solved in
/// local coordinates (the round-off of 10 m coordinates is 2e-15 m, harmless).
pub const LOCAL_ORIGIN_DISTANCE_M: f64 = 10.0;

/// A start whose clamped or pinned ends (or fixed bodies) lie farther than this (m)
/// from their supports is kept for a support ramp ([`continuation::ramp_supports`]),
/// the last fallback when the direct solve and load continuation fail.
pub const SUPPORT_RAMP_DISTANCE_M: f64 = 1e-6;

/// The same for a clamped end's first or last edge frame (or a fixed body) turned by
/// more than this (rad) from the prescribed frame: more than an end edge bends at a
/// clamp (the boundary frame is a virtual edge of its own), i.e. a turned connector.
pub const SUPPORT_RAMP_ANGLE_RAD: f64 = 0.5;

/// Largest number of escapes from unstable equilibria in one solve.
pub const MAX_SADDLE_ESCAPES: usize = 3;

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

/// A Newton solver bound to one model: the symbolic factorisation, the gauge analysis
/// and all work buffers are set up once and reused by every [`Solver::solve`]
/// (variants, load steps, warm starts).
pub struct Solver<'m> {
    model: &'m Model,
    constraints: Option<&'m dyn Constraints>,
    pub(crate) work: Workspace,
    /// Edge stresses of the start's first Hessian (mixed Newton), used once.
    initial_stresses: Option<EdgeStresses>,
    /// The finest level when this solver is a coarse level of nested iteration (its
    /// budget is counted in that level's work, [`nested::level_budget`]).
    finest: Option<nested::Finest>,
}

impl<'m> Solver<'m> {
    /// Symbolic phase: analyses the model's Hessian pattern and its gauge freedoms.
    pub fn try_new(model: &'m Model) -> Result<Self, SolveError> {
        let n = model.dofs().len();
        let gauge = Gauge::of(model);
        Ok(Self {
            model,
            constraints: None,
            initial_stresses: None,
            finest: None,
            work: Workspace {
                cholesky: SparseCholesky::try_new(model.pattern())?,
                diagonal: diagonal_positions(model),
                rotation: rotation_flags(model),
                bending_scale: bending_scales(model),
                rotations: None,
                rotation_unknowns: rotation_unknowns(model, &gauge),
                gauge,
                eval: model.new_evaluation(),
                trial_eval: model.new_evaluation(),
                spare_eval: model.new_evaluation(),
                damped: vec![0.0; model.pattern().nnz()],
                step: vec![0.0; n],
                product: vec![0.0; n],
                rhs: vec![0.0; n],
                model_gradient: None,
            },
        })
    }

    /// Adds inequality constraints (contact) to every solve.
    pub fn with_constraints(mut self, constraints: &'m dyn Constraints) -> Self {
        self.constraints = Some(constraints);
        self
    }

    /// The first Newton step takes the Hessian's stress terms from `stresses`
    /// (material edge forces, N; see `strand_system::Model::evaluate_mixed`) instead
    /// of the start's own: a start whose stiffness was just raised (a stiffness
    /// continuation step) carries the force of the last step, not its strain times the
    /// new stiffness. Ignored without [`SolverSettings::mixed_newton`].
    pub fn with_initial_stresses(mut self, stresses: EdgeStresses) -> Self {
        self.initial_stresses = Some(stresses);
        self
    }

    /// Solves from `initial`: first through a coarsened model when
    /// [`SolverSettings::nested_iteration`] is on and a rod is long, then directly,
    /// then by load continuation when [`SolverSettings::load_continuation`] is on and
    /// the direct solve failed, and last, when `initial` holds its ends away from the
    /// supports (a warm start from another design), by a support ramp from where it
    /// holds them. `iterations` in the report counts all of them.
    pub fn solve(
        &mut self,
        initial: SystemState,
        settings: &SolverSettings,
    ) -> Result<Solution, SolveError> {
        settings.validate()?;
        check_initial_state(self.model, &initial)?;
        // A start whose ends sit away from the supports (a warm start from another
        // design) is kept as it is for a support ramp, should the direct solve fail.
        let (offset_m, offset_rad) = self.model.system().support_offset(&initial);
        let mut unsupported = (offset_m > SUPPORT_RAMP_DISTANCE_M
            || offset_rad > SUPPORT_RAMP_ANGLE_RAD)
            .then(|| initial.clone());
        let mut initial = initial;
        self.model.enforce_supports(&mut initial);
        if let Some(c) = self.constraints {
            c.check_start(self.model, &initial)
                .map_err(SolveError::StartsInside)?;
        }
        let started = Instant::now();
        // Local coordinates: a system far from the origin is solved moved next to it
        // (round-off of the coordinates would otherwise set the residual floor), then
        // moved back. Contact meshes stay where they are, so only without contact.
        let origin = self.model.system().local_origin();
        if self.constraints.is_none() && origin.norm() > LOCAL_ORIGIN_DISTANCE_M {
            let local = Model::try_new(self.model.system().translated(&-origin))
                .map_err(InitialStateError::from)?;
            let mut local_initial = initial;
            local_initial.translate(&-origin);
            if let Some(start) = &mut unsupported {
                start.translate(&-origin);
            }
            let mut solution =
                Solver::try_new(&local)?.solve_here(local_initial, unsupported, settings)?;
            solution.state.translate(&origin);
            solution.report.solve_seconds = started.elapsed().as_secs_f64();
            return Ok(solution);
        }
        self.solve_here(initial, unsupported, settings)
    }

    /// [`Solver::solve`] in the model's own coordinates (after the checks);
    /// `unsupported` is the start before its ends were put onto the supports, when they
    /// were away from them.
    fn solve_here(
        &mut self,
        initial: SystemState,
        unsupported: Option<SystemState>,
        settings: &SolverSettings,
    ) -> Result<Solution, SolveError> {
        let started = Instant::now();
        // Newton iterations of a stiffness continuation that did not converge (they
        // count in `iterations` like every other attempt).
        let mut failed_stiffening = 0;
        // A start that is already an equilibrium (a warm start, a moulded rod in its
        // nominal shape) needs no coarse guess and no continuation: tested (one
        // gradient evaluation) only where one of them would run.
        let model = self.model;
        let mut start_converged = None;
        let mut already_converged = || {
            *start_converged.get_or_insert_with(|| {
                let mut eval = model.new_evaluation();
                model.evaluate(&initial, &mut eval, false);
                model.residual(&eval.gradient).combined_n <= settings.tolerance_n
            })
        };
        // A rod far stiffer in stretch than in bending: stiffness continuation first;
        // the direct path below is the fallback. Not with contact: a softened hose
        // would settle into a different contact set.
        if settings.stiffness_continuation
            && self.constraints.is_none()
            && stiffness::stiffness_ratio(self.model.system()) > settings.stiffness_threshold
            && !already_converged()
        {
            let stiffened =
                stiffness::stiffen(self.model, self.constraints, initial.clone(), settings)?;
            failed_stiffening = stiffened.spent();
            if let Some(mut solution) = stiffened.solution.filter(|s| s.report.converged) {
                let escape_iterations = if settings.escape_saddles {
                    self.escape_saddle(&mut solution, settings)
                } else {
                    0
                };
                let report = &mut solution.report;
                report.fine_iterations = report.iterations;
                report.escape_iterations = escape_iterations;
                report.continuation_steps = stiffened.steps;
                report.continuation_iterations = stiffened.iterations;
                report.iterations += stiffened.iterations + escape_iterations;
                report.solve_seconds = started.elapsed().as_secs_f64();
                return Ok(solution);
            }
        }
        let mut coarse_iterations = 0;
        let mut start = initial.clone();
        // Levels of a quarter each under long rods with contact (see
        // [`nested::LEVEL_RATIO`]); without contact the fine level corrects a single
        // coarse level's start in a few Newton steps, and an extra level only costs
        // (the convergence map's 1000-segment rods: 25 % more instructions).
        let finest = self.finest.unwrap_or(nested::Finest {
            unknowns: self.model.dofs().len(),
            levels: self.constraints.is_some() && nested::has_levels(self.model.system()),
        });
        if let Some((coarse_system, kept)) = nested::coarsen(self.model.system(), finest.levels)
            .filter(|_| settings.nested_iteration && !already_converged())
        {
            let coarse_model = Model::try_new(coarse_system).map_err(InitialStateError::from)?;
            // A coarse level only proposes a start: it gets no continuation and no
            // release retry, and a budget in work of the finest level
            // ([`nested::level_budget`]), so a hard coarse problem cannot cost more
            // than it saves. It is itself started from a coarser level when it is
            // long enough ([`nested::coarsen`]: every level a quarter of the last).
            let coarse_settings = SolverSettings {
                nested_iteration: true,
                load_continuation: false,
                support_continuation: false,
                release_retry: false,
                max_iterations: nested::level_budget(settings, coarse_model.dofs().len(), finest),
                ..settings.clone()
            };
            let mut coarse_solver = Solver::try_new(&coarse_model)?;
            coarse_solver.constraints = self.constraints;
            coarse_solver.finest = Some(finest);
            // A start that clears the parts may not once coarsened: a coarse edge
            // joins vertices the fine polyline bent around a part's corner (a cable
            // draped off the end of a groove). The fine level then starts as given.
            let coarse = match coarse_solver
                .solve(nested::restrict(&initial, &kept), &coarse_settings)
            {
                Err(SolveError::StartsInside(e)) => {
                    if std::env::var_os("STRAND_TRACE").is_some() {
                        eprintln!(
                            "strand-solve: coarse level of {} unknowns not solved: its start {e}",
                            coarse_model.dofs().len()
                        );
                    }
                    None
                }
                other => Some(other?),
            };
            if let Some(coarse) = coarse {
                coarse_iterations = coarse.report.iterations;
                if std::env::var_os("STRAND_TRACE").is_some() {
                    eprintln!(
                        "strand-solve: coarse level of {} unknowns (budget {}): {} iterations, converged {}, stable {} at {:.3} s",
                        coarse_model.dofs().len(),
                        coarse_settings.max_iterations,
                        coarse.report.iterations,
                        coarse.report.converged,
                        coarse.report.stable,
                        started.elapsed().as_secs_f64()
                    );
                }
                // A prolonged state is a start only where the fine iteration can move from
                // it: its new vertices interpolate the coarse ones, and with contact they
                // can put a fine edge's centreline through a mesh the coarse capsules
                // cleared. The fine iteration would then reject every trial and end on
                // that state (everyday_s1_017: a cable over a floor, reported as exit 1
                // because its contacts could not be evaluated).
                let admissible = |state: &SystemState| {
                    self.constraints.is_none_or(|c| {
                        let mut rows = Vec::new();
                        c.rows(self.model, state, &mut rows).is_ok()
                    })
                };
                let prolonged = nested::prolong(self.model, &coarse_model, &coarse.state, &kept);
                // Only a stable coarse equilibrium is a good start (an unstable branch, a
                // straight rod beyond buckling, would be carried into the fine solve).
                // A coarse level that ran out of budget may still have come most of the
                // way: its state is the better start when its energy on the fine model is
                // lower than the initial state's.
                let better = coarse.report.stable
                    || (!coarse.report.converged
                        && self.model.energy(&prolonged) < self.model.energy(&initial));
                if better && admissible(&prolonged) {
                    start = prolonged;
                }
            }
        }
        let release_retry = settings.release_retry
            && self.constraints.is_some()
            && settings.active_row_penalty
            && !settings.release_open_rows;
        // The direct attempt stops where it creeps when the release retry follows.
        let mut solution = self.iterate_stopping_on_creep(start, settings, release_retry);
        // Stalled at the round-off floor: final (a continuation reaches the same floor).
        let at_floor = stalled_at_floor(&solution.report);
        // Iterations of a direct attempt that continuation replaced still count.
        let mut replaced_iterations = 0;
        let mut continuation_iterations = 0;
        let mut continuation_steps = 0;
        if release_retry && !solution.report.converged && !at_floor {
            // A cable creeping along a groove under the held rows' pull: go on from
            // where the direct attempt stopped with the open rows released.
            let released = SolverSettings {
                release_open_rows: true,
                ..settings.clone()
            };
            let retry = self.iterate(solution.state.clone(), &released);
            continuation_steps += 1;
            if retry.report.converged {
                replaced_iterations += solution.report.fine_iterations;
                solution = retry;
            } else {
                continuation_iterations += retry.report.iterations;
                if solution.report.termination == Termination::Creeping {
                    // The direct attempt goes on where it stopped, with the rest of its
                    // budget: the path it would have taken without the retry.
                    let rest = SolverSettings {
                        max_iterations: settings
                            .max_iterations
                            .saturating_sub(solution.report.fine_iterations),
                        ..settings.clone()
                    };
                    let resumed = self.iterate(solution.state.clone(), &rest);
                    replaced_iterations += solution.report.fine_iterations;
                    solution = resumed;
                }
            }
        }
        if settings.load_continuation && !solution.report.converged && !at_floor {
            let ramped =
                continuation::ramp(self.model, self.constraints, initial.clone(), settings)?;
            ramped.adopt_into(
                &mut solution,
                &mut replaced_iterations,
                &mut continuation_iterations,
                &mut continuation_steps,
            );
        }
        if let Some(start) = unsupported
            .filter(|_| settings.support_continuation && !solution.report.converged && !at_floor)
        {
            // The start came from another design: move the supports there and back.
            let ramped =
                continuation::ramp_supports(self.model, self.constraints, start, settings)?;
            ramped.adopt_into(
                &mut solution,
                &mut replaced_iterations,
                &mut continuation_iterations,
                &mut continuation_steps,
            );
        }
        // With contact, stiffness continuation is the last resort (a softened hose may
        // settle into another contact set, but any converged state of the true system
        // beats none): a limp cable draped over an edge (C·h²/EI of 1e7) otherwise
        // crawls. Not on a coarse level of nested iteration, which only proposes a
        // start within its budget: there it doubled the level's cost
        // (`everyday_s69_002`: 40 iterations of a failed stiffening step after its 40).
        if settings.stiffness_continuation
            && self.finest.is_none()
            && self.constraints.is_some()
            && !solution.report.converged
            && !at_floor
            && stiffness::stiffness_ratio(self.model.system()) > settings.stiffness_threshold
        {
            let stiffened =
                stiffness::stiffen(self.model, self.constraints, initial.clone(), settings)?;
            stiffened.adopt_into(
                &mut solution,
                &mut replaced_iterations,
                &mut continuation_iterations,
                &mut continuation_steps,
            );
        }
        let escape_iterations = if settings.escape_saddles {
            self.escape_saddle(&mut solution, settings)
        } else {
            0
        };
        let report = &mut solution.report;
        report.escape_iterations = escape_iterations;
        report.coarse_iterations = coarse_iterations;
        report.continuation_steps = continuation_steps;
        report.continuation_iterations = continuation_iterations;
        report.iterations = report.fine_iterations
            + coarse_iterations
            + continuation_iterations
            + replaced_iterations
            + failed_stiffening
            + escape_iterations;
        report.solve_seconds = started.elapsed().as_secs_f64();
        Ok(solution)
    }

    /// Leaves an unstable converged state along its direction of most negative
    /// curvature (both senses tried, the lower energy kept) for a converged state of
    /// lower energy, at most [`MAX_SADDLE_ESCAPES`] times. Returns the Newton
    /// iterations spent; `solution` is replaced only by a converged state of lower
    /// energy.
    fn escape_saddle(&mut self, solution: &mut Solution, settings: &SolverSettings) -> usize {
        let mut spent = 0;
        for _ in 0..MAX_SADDLE_ESCAPES {
            if !solution.report.converged || solution.report.negative_directions == 0 {
                break;
            }
            let Some(direction) = saddle::negative_direction(
                self.model,
                &mut self.work,
                &solution.state,
                settings.escape_min_shift,
            ) else {
                break;
            };
            let mut best: Option<Solution> = None;
            for sense in [1.0, -1.0] {
                let step: Vec<f64> = direction.iter().map(|d| sense * d).collect();
                let start = self.model.retract(&solution.state, &step);
                let candidate = self.iterate(start, settings);
                spent += candidate.report.iterations;
                let lower = candidate.report.energy_j
                    < solution.report.energy_j - 1e-12 * solution.report.energy_j.abs();
                let better = best
                    .as_ref()
                    .is_none_or(|b| candidate.report.energy_j < b.report.energy_j);
                if candidate.report.converged && lower && better {
                    best = Some(candidate);
                }
            }
            match best {
                Some(found) => *solution = found,
                None => break,
            }
        }
        spent
    }

    /// One Newton/SQP iteration sequence from `initial` on this model (no nested
    /// iteration, no continuation).
    pub(crate) fn iterate(&mut self, initial: SystemState, settings: &SolverSettings) -> Solution {
        self.iterate_stopping_on_creep(initial, settings, false)
    }

    /// [`Solver::iterate`], stopping as [`Termination::Creeping`] where it creeps when
    /// `stop_on_creep`.
    fn iterate_stopping_on_creep(
        &mut self,
        initial: SystemState,
        settings: &SolverSettings,
        stop_on_creep: bool,
    ) -> Solution {
        Iteration::new(
            self.model,
            self.constraints,
            settings,
            &mut self.work,
            initial,
            self.initial_stresses.take(),
        )
        .stopping_on_creep(stop_on_creep)
        .run()
    }
}

/// Every rotation unknown and every gauge-held unknown.
fn rotation_unknowns(model: &Model, gauge: &Gauge) -> Vec<usize> {
    let dofs = model.dofs();
    let mut held: Vec<usize> = (0..dofs.block_count())
        .filter(|&b| dofs.kind(b) == strand_system::BlockKind::Rotation)
        .flat_map(|b| [3 * b, 3 * b + 1, 3 * b + 2])
        .collect();
    held.extend_from_slice(gauge.held());
    held
}

/// Per unknown: `true` unless it is a position (a rod vertex or a body's origin).
fn rotation_flags(model: &Model) -> Vec<bool> {
    let dofs = model.dofs();
    (0..dofs.len())
        .map(|i| dofs.kind(i / 3) != strand_system::BlockKind::Position)
        .collect()
}

/// Per unknown: the bending stiffness of its edge `EI/h` (N·m) for an edge rotation of
/// a rod, 0 for every other unknown.
fn bending_scales(model: &Model) -> Vec<f64> {
    let dofs = model.dofs();
    let mut scales = vec![0.0; dofs.len()];
    for (r, spec) in model.system().rods.iter().enumerate() {
        let bending = spec.rod.section().curvature_stiffness().max();
        for e in 0..spec.rod.segments() {
            let b = dofs.edge(r, e);
            for k in 0..3 {
                scales[3 * b + k] = bending / spec.rod.edge_length(e);
            }
        }
    }
    scales
}

/// Value offsets of the diagonal entries in the upper-triangular CSC pattern (the
/// last entry of a column whose rows are sorted; searched for otherwise).
fn diagonal_positions(model: &Model) -> Vec<usize> {
    let p = model.pattern();
    (0..p.dim())
        .map(|c| {
            let (begin, end) = (p.col_ptr[c], p.col_ptr[c + 1]);
            if end > begin && p.row_idx[end - 1] == c {
                return end - 1;
            }
            let rows = &p.row_idx[begin..end];
            begin
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
        return Err(InitialStateError::RodCount {
            given: state.rods.len(),
            expected: rods.len(),
        }
        .into());
    }
    for (spec, rod_state) in rods.iter().zip(&state.rods) {
        if rod_state.positions.len() != spec.rod.vertex_count()
            || rod_state.frames.len() != spec.rod.segments()
        {
            return Err(InitialStateError::Shape {
                rod: spec.name.clone(),
                vertices: rod_state.positions.len(),
                frames: rod_state.frames.len(),
                expected_vertices: spec.rod.vertex_count(),
                expected_frames: spec.rod.segments(),
            }
            .into());
        }
        if !rod_state.is_finite() {
            return Err(InitialStateError::NotFinite {
                rod: spec.name.clone(),
            }
            .into());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use nalgebra::{UnitQuaternion, Vector3};
    use strand_rod::Section;
    use strand_system::{End, Model, initial_state};

    use crate::gauge::tests::rod_between;
    use crate::{InitialStateError, SolveError, SolverSettings, solve};

    fn cantilever() -> Model {
        let section = Section::try_explicit(1e4, 1e4, 1.0, 1.0, 0.5, 0.005).unwrap();
        let along_x =
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
        rod_between(
            End::clamped(Vector3::zeros(), along_x),
            End::free(),
            section,
        )
    }

    #[test]
    fn a_state_that_does_not_fit_the_model_is_a_typed_error_naming_the_rod() {
        let model = cantilever();
        let settings = SolverSettings::default();
        let good = initial_state(model.system());

        let mut nan = good.clone();
        nan.rods[0].set_position(3, Vector3::new(f64::NAN, 0.0, 0.0));
        assert_eq!(
            solve(&model, nan, &settings).unwrap_err(),
            SolveError::InitialState(InitialStateError::NotFinite { rod: "r".into() })
        );

        let mut short = good.clone();
        short.rods[0].frames.pop();
        assert!(matches!(
            solve(&model, short, &settings).unwrap_err(),
            SolveError::InitialState(InitialStateError::Shape {
                frames: 7,
                expected_frames: 8,
                ..
            })
        ));

        let mut none = good;
        none.rods.clear();
        assert_eq!(
            solve(&model, none, &settings).unwrap_err(),
            SolveError::InitialState(InitialStateError::RodCount {
                given: 0,
                expected: 1
            })
        );
    }
}
