//! Settings of the optimiser.

use serde::{Deserialize, Serialize};
use strand_solve::SettingsError;
use strand_solve::sensitivity::SensitivitySettings;

/// Settings of [`super::optimize`]. Distances in the variables are fractions of each
/// variable's bounds' width.
///
/// ```
/// use strand_study::optimize::OptimizeSettings;
/// assert!(OptimizeSettings::default().validate().is_ok());
/// let bad = OptimizeSettings { step_tolerance: 0.0, ..OptimizeSettings::default() };
/// assert_eq!(bad.validate().unwrap_err().field, "step_tolerance");
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OptimizeSettings {
    /// Most iterations (trial points).
    pub max_iterations: usize,
    /// Most equilibrium solves.
    pub max_solves: usize,
    /// The first trust radius (fraction of the widths).
    pub initial_radius: f64,
    /// The largest trust radius.
    pub max_radius: f64,
    /// Converged when the subproblem's step is below this (fraction of the widths)
    /// at a feasible point.
    pub step_tolerance: f64,
    /// A constraint row counts as satisfied down to this fraction of its bound below it.
    pub feasibility_tolerance: f64,
    /// A constraint row is reported active when within this fraction of its bound, or
    /// when its multiplier is positive.
    pub active_tolerance: f64,
    /// The first penalty on constraint violation in the merit (per normalised unit of
    /// the objective); raised tenfold when the subproblem needs it.
    pub penalty: f64,
    /// A trial point is accepted when its merit falls by at least this fraction of the
    /// model's predicted fall.
    pub accept_ratio: f64,
    /// The first curvature model `B = b₀ I` (normalised objective per scaled variable²).
    pub initial_curvature: f64,
    /// The sensitivities of every point.
    pub sensitivity: SensitivitySettings,
}

impl Default for OptimizeSettings {
    fn default() -> Self {
        Self {
            max_iterations: 40,
            max_solves: 80,
            initial_radius: 0.25,
            max_radius: 1.0,
            step_tolerance: 2e-4,
            feasibility_tolerance: 1e-4,
            active_tolerance: 1e-3,
            penalty: 10.0,
            accept_ratio: 0.1,
            initial_curvature: 1e-2,
            sensitivity: SensitivitySettings::default(),
        }
    }
}

impl OptimizeSettings {
    /// Checks every setting.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let positive = SettingsError::require_positive;
        positive("max_iterations", self.max_iterations as f64)?;
        positive("max_solves", self.max_solves as f64)?;
        positive("initial_radius", self.initial_radius)?;
        positive("max_radius", self.max_radius)?;
        positive("step_tolerance", self.step_tolerance)?;
        positive("feasibility_tolerance", self.feasibility_tolerance)?;
        positive("active_tolerance", self.active_tolerance)?;
        positive("penalty", self.penalty)?;
        positive("initial_curvature", self.initial_curvature)?;
        if !(self.accept_ratio > 0.0 && self.accept_ratio < 1.0) {
            return Err(SettingsError {
                field: "accept_ratio",
                value: self.accept_ratio,
                requirement: "must be in (0, 1)",
            });
        }
        self.sensitivity.validate()
    }
}
