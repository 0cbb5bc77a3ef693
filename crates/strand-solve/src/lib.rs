//! # strand-solve
//!
//! Newton's method on the rod manifold for the equilibrium of a
//! [`strand_system::Model`]: unknowns are position increments and right rotation
//! increments (no unit-norm constraints), the sparse Hessian is factorised with faer
//! (symbolic analysis once per model, [`SparseCholesky`]), indefinite Hessians are
//! shifted until positive definite (inertia correction), and steps are globalised by an
//! Armijo line search on the energy. Convergence is declared on the force residual in
//! newtons ([`strand_system::Residual`]); every [`Solution`] says whether it converged
//! and whether the equilibrium is stable.

mod constraints;
pub mod contact;
pub mod continuation;
mod linear;
mod nested;
mod newton;
mod settings;
mod sqp;

pub use constraints::{Constraints, Row, RowKey, limit_rows};
pub use linear::SparseCholesky;
pub use newton::{Solution, SolveReport, Solver, Termination, solve, solve_constrained};
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
    /// an obstacle); the message says where.
    #[error("{0}")]
    StartsInside(String),
}
