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
mod settings;
mod sqp;
pub mod stability;
pub mod stiffness;

pub use constraints::{ConstraintError, Constraints, Row, RowKey, limit_rows};
pub use linear::SparseCholesky;
pub use newton::{Solver, solve, solve_constrained};
pub use report::{Solution, SolveReport, Termination};
pub use settings::{SettingsError, SolverSettings};

/// A failure that prevents solving at all (not a mere lack of convergence, which is
/// reported in [`SolveReport`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// The sparse linear algebra could not be set up.
    #[error("linear algebra: {0}")]
    Linear(String),
    /// The initial state does not fit the model or is not finite.
    #[error("initial state: {0}")]
    InitialState(String),
    /// The settings are invalid.
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// The starting configuration violates a contact constraint (a hose starts inside
    /// an obstacle); the error says where.
    #[error(transparent)]
    StartsInside(ConstraintError),
}
