//! Load continuation: when a direct solve fails, gravity and the dead end loads are
//! ramped up from zero with an adaptive step, each step warm-started from the previous
//! equilibrium, and the full model is finally solved from the last step (DESIGN §3,
//! robustness). A step that does not converge is retried at a quarter of its size; a
//! step that converges quickly doubles the next one.

use strand_system::{Model, System, SystemState};

use crate::constraints::Constraints;
use crate::newton::Solver;
use crate::report::Solution;
use crate::{SolveError, SolverSettings};

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

/// What a ramp (of the loads, or of the stiffness in [`crate::stiffness`]) produced.
pub(crate) struct Ramp {
    /// The solution of the full model from the last step, `None` if the ramp stalled.
    pub solution: Option<Solution>,
    /// Steps taken (accepted and rejected).
    pub steps: usize,
    /// Newton iterations of the steps (not counting the final solve of the full model).
    pub iterations: usize,
}

/// Ramps the loads from `initial` and solves `model` from the last ramp step.
pub(crate) fn ramp(
    model: &Model,
    constraints: Option<&dyn Constraints>,
    initial: SystemState,
    settings: &SolverSettings,
) -> Result<Ramp, SolveError> {
    // A load step that needs many iterations is better split: each gets a bounded
    // budget, so a failing step costs little before it is retried at a quarter size.
    let step_settings = SolverSettings {
        nested_iteration: false,
        load_continuation: false,
        max_iterations: settings
            .max_iterations
            .min(settings.continuation_step_iterations),
        ..settings.clone()
    };
    let mut state = initial;
    let (mut factor, mut increment) = (0.0f64, settings.continuation_first_step);
    let (mut steps, mut iterations) = (0, 0);
    while factor < 1.0 && steps < settings.max_continuation_steps {
        let target = (factor + increment).min(1.0);
        steps += 1;
        let solution = if target >= 1.0 {
            solve_at(model, constraints, state.clone(), &step_settings)?
        } else {
            let scaled = Model::try_new(scaled_loads(model.system(), target))
                .map_err(crate::InitialStateError::from)?;
            solve_at(&scaled, constraints, state.clone(), &step_settings)?
        };
        if solution.report.converged {
            if target >= 1.0 {
                return Ok(Ramp {
                    solution: Some(solution),
                    steps,
                    iterations,
                });
            }
            iterations += solution.report.iterations;
            if solution.report.iterations <= settings.continuation_easy_iterations {
                increment *= 2.0;
            }
            factor = target;
            state = solution.state;
        } else {
            iterations += solution.report.iterations;
            increment *= 0.25;
            if increment < settings.continuation_smallest_step {
                break;
            }
        }
    }
    Ok(Ramp {
        solution: None,
        steps,
        iterations,
    })
}

/// One solve of `model` from `state` with its own [`Solver`] (contact if any).
pub(crate) fn solve_at(
    model: &Model,
    constraints: Option<&dyn Constraints>,
    state: SystemState,
    settings: &SolverSettings,
) -> Result<Solution, SolveError> {
    let mut solver = Solver::try_new(model)?;
    if let Some(c) = constraints {
        solver = solver.with_constraints(c);
    }
    solver.solve(state, settings)
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
