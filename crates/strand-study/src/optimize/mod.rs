//! Design optimisation with exact gradients (`strand optimize`).
//!
//! The design variables are parameters of the case (named as in `batch --vary`) with
//! bounds; the objective is the largest of a few smooth pieces (`peak_force`: the
//! peak |f| of every rod, a min–max; `peak_moment`: the same of |m|; `max_reaction`:
//! every support's reaction; or one output: `peak_force:<rod>`, `peak_moment:<rod>`,
//! `energy`, any output of `sensitivity.json`); the
//! constraints bound outputs (`clearance>=10mm`: every rod to every obstacle;
//! `bend_radius>=min`: each rod's smallest bend radius against its section's
//! `min_bend_radius`; any output by name).
//!
//! Every point costs one equilibrium solve, warm-started from the last accepted
//! point moved along its first-order path, and one sensitivity computation
//! ([`strand_solve::sensitivity`]), which gives the gradient of every piece and row.
//! The loop ([`run`]) is a trust-region SQP in the epigraph form of the min–max:
//! one subproblem row per piece, solved by clarabel ([`step`]). A clearance row
//! whose rod presses on the obstacle is replaced by the contact force there
//! ([`pieces::Row::in_contact`]). Where the model fails (a peak's location jumps, a
//! contact opens) steps are rejected and the history says why; a run that cannot
//! converge there ends as `non_smooth`, not converged.
//!
//! [`Optimum`] is the result: the optimum's values, objective, active constraints
//! with their multipliers (`d_objective_d_bound`: how much the optimum's objective
//! rises per unit the bound is tightened), every output, the history, and the variant
//! changes that make the optimal case ([`optimum::document`] makes `optimum.json`,
//! [`strand_report::OptimumDoc`] and [`strand_report::optimum_svg`] the history's CSV
//! and SVG).

pub mod evaluate;
pub mod of_case;
pub mod optimum;
pub mod options;
pub mod pieces;
pub mod problem;
pub mod run;
pub mod settings;
pub mod step;
pub mod write;

use strand_case::CaseError;
use strand_case::schema::VariantChange;
use strand_report::OutputValue;
pub use strand_report::{OptimumConstraint, OptimumIterate};
use strand_solve::SettingsError;

use crate::error::{ErrorKind, StudyError};

pub use of_case::{OptimizeProgress, OptimizeRun, optimize_case};
pub use optimum::document;
pub use problem::{Bound, Bounded, Limit, Objective, Problem, Variable};
pub use run::optimize;
pub use settings::OptimizeSettings;
pub use write::{OptimumOutputs, optimal_case, optimum_outputs, write_optimum};

/// Why an optimisation could not run.
#[derive(Debug, thiserror::Error)]
pub enum OptimizeError {
    /// A command-line input is wrong.
    #[error("{option} {text}: {message} (hint: {hint})")]
    Input {
        /// The option (`--minimize`, `--subject-to`, `--vary`).
        option: String,
        /// Its value as given.
        text: String,
        /// What is wrong.
        message: String,
        /// How to fix it.
        hint: String,
    },
    /// The case cannot be built.
    #[error(transparent)]
    Case(Box<CaseError>),
    /// The starting design has no differentiable equilibrium.
    #[error("the starting design: {0}")]
    Start(String),
    /// The outputs or their sensitivities at a point could not be computed
    /// ([`crate::sensitivity::output_table`]).
    #[error(transparent)]
    Study(Box<StudyError>),
    /// The subproblem failed.
    #[error("the optimisation subproblem failed: {0}")]
    Subproblem(String),
    /// The settings are invalid.
    #[error("optimisation settings: {0}")]
    Settings(#[from] SettingsError),
}

impl From<CaseError> for OptimizeError {
    fn from(e: CaseError) -> Self {
        Self::Case(Box::new(e))
    }
}

impl From<StudyError> for OptimizeError {
    fn from(e: StudyError) -> Self {
        Self::Study(Box::new(e))
    }
}

impl OptimizeError {
    /// An input error of `option` `text`.
    pub fn input(option: &str, text: &str, message: &str, hint: &str) -> Self {
        Self::Input {
            option: option.to_string(),
            text: text.to_string(),
            message: message.to_string(),
            hint: hint.to_string(),
        }
    }

    /// Whether the error is the user's input (exit 2) rather than the computation's.
    pub fn is_input(&self) -> bool {
        self.kind() == ErrorKind::Input
    }

    /// The kind of the failure (the exit status of `strand optimize`): input for the
    /// options and the case, not converged for a starting design without an
    /// equilibrium, I/O (internal) for the rest.
    pub fn kind(&self) -> ErrorKind {
        match self {
            Self::Input { .. } | Self::Case(_) | Self::Settings(_) => ErrorKind::Input,
            Self::Start(_) => ErrorKind::NotConverged,
            Self::Study(e) => e.kind(),
            Self::Subproblem(_) => ErrorKind::Io,
        }
    }
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Termination {
    /// The step fell below the tolerance at a feasible point.
    Converged,
    /// The step fell below the tolerance with a constraint still violated.
    Infeasible,
    /// The trust region collapsed: the gradient model does not predict the change.
    NonSmooth,
    /// The iteration limit.
    MaxIterations,
    /// The solve limit.
    MaxSolves,
}

/// The result of [`optimize`].
#[derive(Clone, Debug)]
pub struct Optimum {
    /// Whether the run met its convergence test (see [`Optimum::termination`]).
    pub converged: bool,
    /// How it ended.
    pub termination: Termination,
    /// The ending in words.
    pub message: String,
    /// The variables' offsets from the case (item units).
    pub offsets: Vec<f64>,
    /// The variables' values (see [`Variable::value`]).
    pub values: Vec<f64>,
    /// The objective at the optimum.
    pub objective: f64,
    /// The pieces that attain it (several at a kink of the min–max).
    pub attained_by: Vec<String>,
    /// Every constraint row at the optimum, then the variables on their bounds
    /// (`kind` `lower_bound` / `upper_bound`).
    pub constraints: Vec<OptimumConstraint>,
    /// Every output at the optimum.
    pub outputs: Vec<OutputValue>,
    /// The optimum's equilibrium.
    pub solution: strand_solve::Solution,
    /// Equilibrium solves in all.
    pub solves: usize,
    /// Trial points.
    pub iterations: usize,
    /// Newton iterations of all solves.
    pub newton_iterations: usize,
    /// The optimum's equilibrium residual, N.
    pub residual_n: f64,
    /// Where the gradient model failed.
    pub non_smooth: Vec<String>,
    /// Every trial point.
    pub history: Vec<OptimumIterate>,
    /// The variant changes that make the optimal case from the case.
    pub changes: Vec<VariantChange>,
}
