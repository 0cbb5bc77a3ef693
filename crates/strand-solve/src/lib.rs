//! # strand-solve
//!
//! Newton's method on the rod manifold for the equilibrium of a
//! [`strand_system::Model`]: unknowns are position increments and right rotation
//! increments (no unit-norm constraints), the sparse Hessian is factorised with faer
//! (symbolic analysis once per model, [`SparseCholesky`]), gauge freedoms are held
//! ([`gauge`]), indefinite or untrustworthy models are damped per unknown
//! (Levenberg–Marquardt scaled by the Hessian's own diagonal) inside a trust region in
//! physical units, and inequalities (contact, joint limits) enter as SQP rows. When a
//! direct solve fails, the loads are ramped by adaptive continuation. Convergence is
//! declared on the force residual in newtons ([`strand_system::Residual`]); every
//! [`Solution`] says whether it converged and classifies its stability from the inertia
//! of the reduced Hessian ([`stability`]).

mod activity;
mod constraints;
pub mod contact;
pub mod continuation;
pub mod gauge;
mod iteration;
mod linear;
mod nested;
mod newton;
mod report;
mod saddle;
pub mod sensitivity;
mod settings;
mod sqp;
pub mod stability;
pub mod stiffness;

pub use activity::{Activity, activity};
pub use constraints::{
    ConstraintError, Constraints, FarVertex, Row, RowKey, StartHint, WayAround, limit_rows,
};
pub use iteration::{ROUND_OFF_RESOLVED, ROUND_OFF_STALL};
pub use linear::{PatternAnalysis, SparseCholesky};
pub use newton::{Solver, solve, solve_constrained};
pub use report::{Solution, SolveReport, Termination};
pub use settings::{SettingsError, SolverSettings};

/// Why the linear algebra of a solve could not run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LinearError {
    /// Memory ran out in `stage` (ordering, factorisation, solve, stability test).
    #[error("out of memory for the {stage}")]
    OutOfMemory {
        /// What was being set up.
        stage: &'static str,
    },
    /// faer or clarabel rejected the problem in `stage`; `detail` is their message.
    #[error("{stage} failed: {detail}")]
    Failed {
        /// What was being set up (symbolic analysis, ordering, QP set-up, …).
        stage: &'static str,
        /// The library's own description.
        detail: String,
    },
    /// The QP of a constrained step ended without a solution.
    #[error("the constrained step QP ended with {status}")]
    Subproblem {
        /// Clarabel's status.
        status: String,
    },
}

/// Why an initial state cannot start a solve.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InitialStateError {
    /// The state has a different number of rods than the model.
    #[error("{given} rod states for {expected} rods")]
    RodCount {
        /// Rod states given.
        given: usize,
        /// Rods of the model.
        expected: usize,
    },
    /// A rod's state has the wrong number of vertices or frames.
    #[error(
        "rod '{rod}' has {vertices} vertices and {frames} frames; expected {expected_vertices} and {expected_frames}"
    )]
    Shape {
        /// The rod's name.
        rod: String,
        /// Vertices given.
        vertices: usize,
        /// Frames given.
        frames: usize,
        /// Vertices of the rod.
        expected_vertices: usize,
        /// Frames (edges) of the rod.
        expected_frames: usize,
    },
    /// A rod's state has a NaN or infinite coordinate.
    #[error("rod '{rod}' has non-finite coordinates")]
    NotFinite {
        /// The rod's name.
        rod: String,
    },
    /// A derived model (coarsened, softened, moved to local coordinates, with scaled
    /// loads) could not be built from the model's system.
    #[error("derived model: {0}")]
    DerivedModel(#[from] strand_system::SystemError),
}

/// A failure that prevents solving at all (not a mere lack of convergence, which is
/// reported in [`SolveReport`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// The sparse linear algebra (ordering, factorisation, the QP of a constrained
    /// step, the stability test) could not run.
    #[error("linear algebra: {0}")]
    Linear(#[from] LinearError),
    /// The initial state does not fit the model or is not finite.
    #[error("initial state: {0}")]
    InitialState(#[from] InitialStateError),
    /// The settings are invalid.
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// The starting configuration violates a contact constraint (a hose starts inside
    /// an obstacle); the error says where.
    #[error(transparent)]
    StartsInside(ConstraintError),
}
