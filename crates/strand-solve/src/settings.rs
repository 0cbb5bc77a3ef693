//! Solver settings: one plain struct with serde defaults and `validate()`, so the same
//! struct loads from a case file and builds in code.

use serde::{Deserialize, Serialize};

/// Settings of the Newton solver.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SolverSettings {
    /// Convergence threshold on the residual (largest out-of-balance vertex force, and
    /// edge moment per edge length) in N.
    pub tolerance_n: f64,
    /// Maximum number of Newton iterations.
    pub max_iterations: usize,
    /// Largest rotation increment of any edge in one step, rad.
    pub max_rotation_step_rad: f64,
    /// Largest translation of any vertex in one step, as a fraction of the longest rod.
    pub max_translation_step: f64,
    /// Maximum number of step halvings in the line search.
    pub max_line_search_steps: usize,
    /// Start rods of more than 64 segments from the solution of a coarsened copy of the
    /// system (nested iteration). Turn off when warm-starting from a nearby solution.
    pub nested_iteration: bool,
    /// When a solve does not converge, ramp gravity and dead loads up in steps
    /// (1/8, 1/4, 1/2, 3/4, 1), each warm-started, and report that result instead.
    pub load_continuation: bool,
    /// Inequality constraints (contact gaps in m, joint limits in rad or m): a converged
    /// state violates none by more than this, and every constraint that carries a force
    /// is closed to within it.
    pub constraint_tolerance: f64,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            tolerance_n: 1e-9,
            max_iterations: 200,
            max_rotation_step_rad: 0.5,
            max_translation_step: 0.25,
            max_line_search_steps: 40,
            nested_iteration: true,
            load_continuation: true,
            constraint_tolerance: 1e-9,
        }
    }
}

/// An invalid setting.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("solver setting '{field}' = {value}: {requirement}")]
pub struct SettingsError {
    /// The setting's name as in the case file.
    pub field: &'static str,
    /// The given value.
    pub value: f64,
    /// What it must satisfy.
    pub requirement: &'static str,
}

impl SolverSettings {
    /// Checks every setting.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let positive = |field, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(SettingsError {
                    field,
                    value,
                    requirement: "must be a finite number > 0",
                })
            }
        };
        positive("tolerance_n", self.tolerance_n)?;
        positive("max_rotation_step_rad", self.max_rotation_step_rad)?;
        positive("max_translation_step", self.max_translation_step)?;
        positive("constraint_tolerance", self.constraint_tolerance)?;
        if self.max_iterations == 0 {
            return Err(SettingsError {
                field: "max_iterations",
                value: 0.0,
                requirement: "must be ≥ 1",
            });
        }
        Ok(())
    }
}
