//! The exact tangent of the path: `d(state)/d(parameter)` at a converged pose by the
//! implicit function theorem ([`strand_solve::sensitivity`]), with the motion
//! parameter as the one design parameter (the moving parts' positions, and so the
//! held ends and the moving meshes, are its functions).

use strand_solve::Solution;
use strand_solve::sensitivity::{Design, Sensitivities, SensitivitySettings};
use strand_system::{Model, SystemState};

use crate::design::DesignedCase;
use crate::units::LengthUnit;
use crate::{Case, CaseError};

/// A case at pose `value` of `motion`, as a design whose one parameter is the offset
/// of the motion parameter (its unit) from `value`.
struct PoseDesign<'a> {
    case: &'a Case,
    motion: &'a str,
    value: f64,
    segments: Option<usize>,
    /// The equilibrium at `value` (the builds' warm state: no guesses are made).
    state: &'a SystemState,
    /// The parameter's typical size, in its unit.
    scale: f64,
}

impl Design for PoseDesign<'_> {
    type Built = DesignedCase;
    type Error = CaseError;

    fn parameter_count(&self) -> usize {
        1
    }

    fn step(&self, _: usize) -> f64 {
        self.scale
    }

    fn build(&self, offsets: &[f64]) -> Result<DesignedCase, CaseError> {
        let value = self.value + offsets[0];
        let built = self
            .case
            .build_motion_from(self.motion, value, self.segments, self.state)?;
        Ok(DesignedCase::new(built))
    }
}

/// The typical size of a motion parameter in `unit`: 10° for an angle, 1 m for a
/// length (the difference steps of the tangent are 1e-4 of it by default).
pub fn parameter_scale(unit: &str) -> f64 {
    match LengthUnit::parse(unit) {
        Some(length) => 1.0 / length.metres(),
        None => 10.0,
    }
}

/// The tangent `dδ/dp` of the path at the converged `solution` of pose `value` (in
/// the solver's chart at `solution.state`, per unit of the parameter), with the
/// contacts and stops that carry a force held active; `None` where it cannot be
/// computed (an unstable or only constraint-held equilibrium, an active contact lost
/// within the difference step): the caller falls back to the secant.
pub fn tangent(
    case: &Case,
    motion: &str,
    unit: &str,
    value: f64,
    segments: Option<usize>,
    solution: &Solution,
) -> Option<Vec<f64>> {
    let design = PoseDesign {
        case,
        motion,
        value,
        segments,
        state: &solution.state,
        scale: parameter_scale(unit),
    };
    // A predictor needs no more than a few digits: one central difference, no
    // refinement (the derivative is still checked once against the KKT conditions).
    let settings = SensitivitySettings {
        richardson: false,
        max_refinements: 0,
        ..SensitivitySettings::default()
    };
    let sensitivities = Sensitivities::compute(&design, solution, &settings).ok()?;
    sensitivities.parameters.into_iter().next().map(|p| p.state)
}

/// `state` moved along the tangent by `change` parameter units (the first-order
/// prediction of the next pose).
pub fn along(model: &Model, state: &SystemState, tangent: &[f64], change: f64) -> SystemState {
    let step: Vec<f64> = tangent.iter().map(|t| t * change).collect();
    model.retract(state, &step)
}
