//! Exact design sensitivities of an equilibrium (implicit function theorem).
//!
//! At a converged equilibrium `x(p)` of a design with parameters `p` (lengths, support
//! positions, masses, gravity, …) the KKT conditions hold on the active rows `A`
//! (contacts pressing, joint stops carrying a moment):
//!
//! ```text
//!     Φ(δ, μ, p) = [ g(x ⊕ δ, p) − Σ μ_i a_i(x ⊕ δ, p) ]  = 0
//!                  [ c_A(x ⊕ δ, p)                    ]
//! ```
//!
//! with `δ` the increment in the solver's chart at `x` (positions added, frames
//! `q ⊗ exp(δθ)`; the gradient pulled back into that chart), `μ` the multipliers
//! (contact forces in N, stop moments in N·m) and `c_A` the active gaps (m, rad).
//! Differentiating at `δ = 0`:
//!
//! ```text
//!     [ K   −Aᵀ ] [ dδ/dp ]      [ ∂Φ_g/∂p ]
//!     [ A    0  ] [ dμ/dp ]  = − [ ∂c_A/∂p ]
//! ```
//!
//! `K` is the Hessian of the Lagrangian. It is solved with the sparse Cholesky factor
//! of the energy Hessian `H` at the equilibrium (the gauge held as in the solve,
//! [`crate::gauge`]: a round rod's free turn about its axis between pins, on which no
//! output depends) and a Schur complement on the few active rows — where `H` is
//! indefinite but definite on the directions the active rows leave free (a hose
//! pressed into a groove under axial compression), the factor of `H + ρ AᵀA`, the
//! same system since `A dδ/dp` is prescribed — then refined
//! against the exact directional derivative of `Φ` (the curvature of active contacts,
//! `Σ μ_i ∇² c_i`, is the only difference between `K` and `H`; with a curved active
//! row down to round-off): the result satisfies the linearised KKT system to the
//! accuracy of that directional derivative.
//!
//! **How `∂/∂p` is computed:** along a parameter that moves the model's real numbers
//! affinely ([`Design::model_line`]: lengths, support positions, masses, loads,
//! gravity, stiffnesses), in closed form: the derivative of each changed element's
//! gradient with respect to its reference data and held vertices
//! ([`Model::gradient_derivative`]), no design built
//! ([`SensitivitySettings::exact_right_hand_sides`]); the active rows' part is zero
//! where the line moves nothing they read ([`crate::Constraints::rows_may_differ`]),
//! else the differences of the base constraints' rows at the model moved along the
//! line. Otherwise by central differences of `Φ` in `p` at a fixed state
//! (a [`Design`] builds the model at `p ± h` and `p ± 2h` — a case design by moving its
//! base model along the parameter where the model's numbers are affine in it, see
//! `strand_case::CaseDesign`; the state keeps its unknowns, and the held vertices
//! follow their supports), extrapolated (Richardson; one central difference for a
//! parameter that [`Design::enters_linearly`]), with `h` from [`Design::step`] times
//! [`SensitivitySettings::relative_step`]. The truncation error is `O(h⁴)` and the
//! round-off `ε·C/h` (`C` the axial stiffness: the gradient's round-off): at the
//! default `h` (1e-4 of the parameter's scale) both are far below 1e-6 of the
//! derivatives (most parameters — loads, masses, gravity, support positions — enter
//! the gradient linearly at a fixed state, where the difference is exact). Outputs
//! (reactions, peaks, clearances, …) follow by the chain rule, evaluated the same
//! way: differences of the output along the first-order path
//! `(p ± h e_j, x ⊕ ±h dδ/dp_j, μ ± h dμ/dp_j)`
//! ([`Sensitivities::derivative`]); a peak or minimum whose arg changes between the
//! two sides is marked one-sided.
//!
//! Rows whose multiplier or gap is near zero are listed in
//! [`Sensitivities::flagged`]: there the active set is about to change and the
//! derivative holds on one side only.

mod kkt;
mod outputs;
mod schur;
mod settings;
mod solve;
#[cfg(test)]
mod tests;

use strand_system::Model;

use crate::constraints::{ConstraintError, Constraints, RowKey};

pub use outputs::{OutputDerivative, PathPlace, PathRows, Sample};
pub use settings::SensitivitySettings;
pub use solve::{Flag, FlaggedRow, ParameterSensitivity, Sensitivities};

/// A parameterised design: builds the model (and its inequality constraints) at given
/// offsets of its parameters from the base design.
///
/// The model must keep the base design's numbering of unknowns at every offset (the
/// same rods, segment counts, clips and bodies): a rod length changes its edges' rest
/// lengths, not their number.
pub trait Design {
    /// What [`Design::build`] returns: the model and its constraints.
    type Built: Designed;
    /// Why a design could not be built.
    type Error: std::error::Error + Send + Sync + 'static;

    /// Number of parameters.
    fn parameter_count(&self) -> usize;

    /// The typical size of parameter `parameter`, in its own unit: the difference
    /// step is [`SensitivitySettings::relative_step`] times this (e.g. 1000 for a
    /// length in mm, the mass for a mass in kg).
    fn step(&self, parameter: usize) -> f64;

    /// The design at `offsets` (one per parameter, in each parameter's unit) from the
    /// base design.
    fn build(&self, offsets: &[f64]) -> Result<Self::Built, Self::Error>;

    /// Whether parameter `parameter` enters the gradient linearly at a fixed state (a
    /// load, a mass, gravity, a stiffness): its difference is then exact at any step,
    /// and `∂Φ/∂p` takes one central difference instead of the extrapolated two
    /// ([`SensitivitySettings::richardson`]). Default: `false`.
    fn enters_linearly(&self, _parameter: usize) -> bool {
        false
    }

    /// Where parameter `parameter` moves the base design's model along a line of its
    /// real numbers ([`strand_system::System::reals`]: the model at offset `t` is the
    /// base's with the real numbers `reals + t · direction`, its constraints the
    /// base's), that line: `∂Φ/∂p` is then the closed-form derivative of the gradient
    /// along it ([`Model::gradient_derivative`],
    /// [`SensitivitySettings::exact_right_hand_sides`]), with no design built and no
    /// difference ladder. Default: `None` (every parameter through [`Design::build`]).
    fn model_line(&self, _parameter: usize) -> Result<Option<ModelLine<'_>>, Self::Error> {
        Ok(None)
    }
}

/// How one parameter moves a design's model ([`Design::model_line`]): affinely along
/// a line of its real numbers.
#[derive(Clone, Debug)]
pub struct ModelLine<'a> {
    /// The base model's real numbers ([`strand_system::System::reals`]: m, kg, N, …).
    pub reals: &'a [f64],
    /// Their change per unit of the parameter (real number's unit per parameter unit).
    pub direction: &'a [f64],
    /// The indices where `direction` is not zero (ascending).
    pub moved: Vec<usize>,
}

/// A built design: a model and the inequality constraints beyond joint limits.
pub trait Designed {
    /// The model.
    fn model(&self) -> &Model;
    /// Contact constraints, if any.
    fn constraints(&self) -> Option<&dyn Constraints>;
}

/// Why sensitivities could not be computed.
#[derive(Debug, thiserror::Error)]
pub enum SensitivityError {
    /// The base solution did not converge: there is no equilibrium to differentiate.
    #[error(
        "the base solve did not converge (residual {residual_n:.3e} N): no equilibrium to differentiate"
    )]
    NotConverged {
        /// Residual of the base solution, N.
        residual_n: f64,
    },
    /// The design could not be built at an offset.
    #[error("the design at a step of parameter {parameter}: {source}")]
    Design {
        /// The parameter stepped.
        parameter: usize,
        /// The design's error.
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// The built design does not have the base design's unknowns.
    #[error(
        "parameter {parameter} changes the model's unknowns ({given} instead of {expected}): keep segment counts fixed"
    )]
    Shape {
        /// The parameter stepped.
        parameter: usize,
        /// Unknowns of the stepped model.
        given: usize,
        /// Unknowns of the base model.
        expected: usize,
    },
    /// The Hessian at the equilibrium is not positive definite on the directions its
    /// active constraints leave free (an unstable state, or a neutral direction beyond
    /// the gauge freedoms held by construction): the derivative is not unique.
    #[error(
        "the Hessian at the equilibrium is not positive definite on the directions its active contacts and stops leave free: sensitivities need a stable equilibrium without neutral directions beyond the gauge (a round rod's turn about its axis between pins is held)"
    )]
    NotPositiveDefinite,
    /// An active row disappeared at a step of a parameter (the contact moved off its
    /// patch within the difference step).
    #[error(
        "active constraint {key:?} is lost at a step of parameter {parameter}: the active set changes there"
    )]
    RowLost {
        /// The parameter stepped.
        parameter: usize,
        /// The row.
        key: RowKey,
    },
    /// The contact rows could not be evaluated at a step.
    #[error("constraints at a step of parameter {parameter}: {source}")]
    Constraint {
        /// The parameter stepped.
        parameter: usize,
        /// The contact error (boxed: it names rods and obstacles).
        source: Box<ConstraintError>,
    },
    /// The settings are invalid.
    #[error(transparent)]
    Settings(#[from] crate::SettingsError),
    /// The sparse factorisation could not be set up.
    #[error(transparent)]
    Solve(#[from] crate::SolveError),
}
