//! Load continuation: when a direct solve fails, the loads (gravity, dead end loads)
//! are ramped up in steps, each solve warm-started from the previous equilibrium, and
//! the full model is finally solved from the last step (DESIGN §3, robustness).

use strand_system::{Model, System, SystemState};

use crate::constraints::Constraints;
use crate::newton::{Solution, Solver};
use crate::{SolveError, SolverSettings};

/// Load factors of the ramp before the full load.
pub const LOAD_STEPS: [f64; 4] = [0.125, 0.25, 0.5, 0.75];

/// The system with gravity and every dead end load scaled by `factor`.
pub fn scaled_loads(system: &System, factor: f64) -> System {
    let mut scaled = system.clone();
    scaled.gravity *= factor;
    for spec in &mut scaled.rods {
        for end in [&mut spec.start, &mut spec.end] {
            end.load.force *= factor;
            end.load.moment *= factor;
        }
    }
    scaled
}

/// Ramps the loads from `initial` and solves `model` from the last ramp step. Returns
/// the final solution with the number of ramp steps taken, or `None` if a ramp step did
/// not converge.
pub(crate) fn ramp(
    model: &Model,
    constraints: Option<&dyn Constraints>,
    initial: SystemState,
    settings: &SolverSettings,
) -> Result<Option<(Solution, usize)>, SolveError> {
    let step_settings = SolverSettings {
        nested_iteration: false,
        load_continuation: false,
        ..settings.clone()
    };
    let mut state = initial;
    let mut iterations = 0;
    for &factor in &LOAD_STEPS {
        let scaled = Model::try_new(scaled_loads(model.system(), factor))
            .map_err(|e| SolveError::InitialState(e.to_string()))?;
        let mut solver = Solver::try_new(&scaled)?;
        if let Some(c) = constraints {
            solver = solver.with_constraints(c);
        }
        let solution = solver.solve(state, &step_settings)?;
        iterations += solution.report.iterations;
        if !solution.report.converged {
            return Ok(None);
        }
        state = solution.state;
    }
    let mut solver = Solver::try_new(model)?;
    if let Some(c) = constraints {
        solver = solver.with_constraints(c);
    }
    let mut solution = solver.solve(state, &step_settings)?;
    solution.report.continuation_iterations = iterations;
    Ok(Some((solution, LOAD_STEPS.len())))
}

#[cfg(test)]
mod tests {
    use nalgebra::{UnitQuaternion, Vector3};
    use strand_rod::{Rod, Section};
    use strand_system::{End, RodSpec};

    use super::*;

    #[test]
    fn scaled_loads_scale_gravity_and_every_dead_load_only() {
        let section = Section::try_explicit(3e4, 1e4, 1.0, 1.0, 0.5, 0.0).unwrap();
        let mut end = End::free().with_force(Vector3::new(1.0, 2.0, 3.0));
        end.load.moment = Vector3::new(0.5, 0.0, -1.0);
        let system = System {
            rods: vec![RodSpec {
                name: "r".into(),
                rod: Rod::try_straight(section, 1.0, 4).unwrap(),
                start: End::clamped(Vector3::zeros(), UnitQuaternion::identity()),
                end,
                route: None,
            }],
            bodies: vec![],
            clips: vec![],
            gravity: Vector3::new(0.0, 0.0, -9.81),
        };
        let half = scaled_loads(&system, 0.5);
        assert_eq!(half.gravity, Vector3::new(0.0, 0.0, -4.905));
        assert_eq!(half.rods[0].end.load.force, Vector3::new(0.5, 1.0, 1.5));
        assert_eq!(half.rods[0].end.load.moment, Vector3::new(0.25, 0.0, -0.5));
        assert_eq!(half.rods[0].rod, system.rods[0].rod);
        assert_eq!(half.rods[0].start.support, system.rods[0].start.support);
    }
}
