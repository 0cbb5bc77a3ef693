//! What a solve returns: the state, how it was reached and how good it is.

use serde::Serialize;
use strand_system::{Residual, SystemState};

use crate::constraints::Row;

/// Why the iteration stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Termination {
    /// The residual fell below the tolerance (or the stated round-off floor), or no
    /// step could reduce it further while it was within 4 times that floor.
    Converged,
    /// The iteration limit was reached.
    MaxIterations,
    /// No trial step decreased the merit function (energy plus constraint penalty) as
    /// predicted, even with the largest damping (or the residual in the round-off
    /// regime).
    LineSearchFailed,
    /// The residual stopped decreasing above the tolerance while the energy no longer
    /// changed beyond round-off: for [`crate::SolverSettings::stagnation_iterations`]
    /// iterations, or when no trial step was accepted after three such iterates. The
    /// returned residual is the floor the iteration reached; within 100 times
    /// [`SolveReport::residual_floor_n`] no continuation is tried after it.
    Stagnated,
    /// The direct attempt of a solve with contact crept: for
    /// [`crate::SolverSettings::stagnation_iterations`] iterations every step needed
    /// damping (the SQP model indefinite) and the residual did not fall by
    /// [`crate::SolverSettings::stagnation_reduction`] — a cable creeping along a
    /// groove under the held rows' pull, which converges linearly at the damping's
    /// rate. It stops there only where the release retry
    /// ([`crate::SolverSettings::release_retry`]) follows; should that retry fail, the
    /// direct attempt resumes where it stopped with the rest of its budget.
    Creeping,
    /// A non-finite number appeared.
    NotFinite,
    /// The QP of a constrained step (joint limits, contact) could not be solved.
    SubproblemFailed,
    /// The solve stopped short of the tolerance (at the round-off floor, or not) on a
    /// model whose round-off floor is not small against the applied loads (above
    /// [`crate::ROUND_OFF_RESOLVED`] of [`SolveReport::applied_load_n`]): stiffnesses
    /// this far apart (a huge `ea` or `ga` on a light cable) leave out-of-balance
    /// forces of the size of the loads that `f64` cannot resolve, so no state is an
    /// equilibrium of them, and no continuation is tried.
    FloorAboveLoads,
}

/// What the solver did and how good the result is.
#[derive(Clone, Debug, Serialize)]
pub struct SolveReport {
    /// Whether the residual reached the tolerance and every constraint holds.
    pub converged: bool,
    /// Why the iteration stopped.
    pub termination: Termination,
    /// Residual of the returned state (N, N·m).
    pub residual: Residual,
    /// Tolerance asked for, N.
    pub tolerance_n: f64,
    /// The round-off floor of the residual at this model's stiffnesses and coordinates,
    /// N (from its Hessian at the start, see `iteration/floor.rs`): a solve that can make
    /// no further progress within 4 × this floor is converged at round-off (its residual
    /// may then exceed `tolerance_n`, never 4 × the floor).
    pub residual_floor_n: f64,
    /// The size of the applied loads, N ([`strand_system::System::applied_load_n`]:
    /// weights and dead loads): a residual accepted at the round-off floor must be
    /// below [`crate::ROUND_OFF_RESOLVED`] of it ([`Termination::FloorAboveLoads`]).
    pub applied_load_n: f64,
    /// Every Newton iteration performed: the final solve, the coarse levels of nested
    /// iteration and the continuation steps.
    pub iterations: usize,
    /// Newton iterations of the final solve on the full model at full load.
    pub fine_iterations: usize,
    /// Newton iterations of the coarse-model solve that produced the initial guess
    /// (nested iteration; 0 when not used).
    pub coarse_iterations: usize,
    /// Steps of the continuation that produced this result (0: direct solve): load
    /// steps, or the softened and stiffening steps of the stiffness continuation
    /// ([`crate::stiffness`]); a release retry
    /// ([`crate::SolverSettings::release_retry`]) counts as one.
    pub continuation_steps: usize,
    /// Newton iterations spent in the continuation's steps (load or stiffness) and in
    /// a release retry that did not converge (a converged one is the final solve).
    pub continuation_iterations: usize,
    /// Newton iterations spent leaving unstable equilibria (part of `iterations`; see
    /// [`crate::SolverSettings::escape_saddles`]).
    pub escape_iterations: usize,
    /// Iterations whose Hessian needed damping to become positive definite or to give
    /// an acceptable step.
    pub shifted_iterations: usize,
    /// Whether the returned state is a stable equilibrium: converged, and no direction
    /// admissible under the supports, active contacts and active joint limits
    /// decreases the energy to second order (`negative_directions == 0`). Neutral
    /// directions (a symmetry, such as a buckled round rod turning about its chord)
    /// do not make it unstable.
    pub stable: bool,
    /// Number of directions of negative curvature of the reduced Hessian.
    pub negative_directions: usize,
    /// Number of neutral (zero-curvature, to the stated tolerance) directions of the
    /// reduced Hessian, not counting the gauge freedoms removed by construction.
    pub neutral_directions: usize,
    /// Gauge freedoms removed by construction (rods of round section free to turn
    /// about their own axis between pins).
    pub gauge_freedoms: usize,
    /// Total potential energy in J.
    pub energy_j: f64,
    /// Wall-clock time of the solve in s.
    pub solve_seconds: f64,
    /// Number of scalar unknowns.
    pub unknowns: usize,
}

impl SolveReport {
    /// A report for `unknowns` unknowns before any iteration.
    pub(crate) fn new(unknowns: usize, tolerance_n: f64) -> Self {
        Self {
            converged: false,
            termination: Termination::MaxIterations,
            residual: Residual::default(),
            tolerance_n,
            residual_floor_n: 0.0,
            applied_load_n: 0.0,
            iterations: 0,
            fine_iterations: 0,
            coarse_iterations: 0,
            continuation_steps: 0,
            continuation_iterations: 0,
            escape_iterations: 0,
            shifted_iterations: 0,
            stable: false,
            negative_directions: 0,
            neutral_directions: 0,
            gauge_freedoms: 0,
            energy_j: 0.0,
            solve_seconds: 0.0,
            unknowns,
        }
    }
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
    /// The solver's symbolic analysis of the model's Hessian pattern, handed on so that
    /// the sensitivities of this equilibrium ([`crate::sensitivity`]) factor the
    /// Hessian without analysing the pattern again; `None` where no solver made it.
    pub analysis: Option<crate::PatternAnalysis>,
    /// The Hessian's values at the returned state (the model's pattern, upper
    /// triangle, the gauge not held), kept when [`crate::SolverSettings::keep_hessian`]
    /// is set and the solve converged: the sensitivities of the equilibrium
    /// ([`crate::sensitivity`]) then factorise it without evaluating it again (the
    /// same values bit for bit). `None` otherwise.
    pub hessian: Option<std::sync::Arc<[f64]>>,
}
