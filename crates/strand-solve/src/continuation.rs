//! Load and support continuation: when a direct solve fails, gravity and the dead end
//! loads are ramped up from zero, or the supports moved from where a start from another
//! design holds the ends, with an adaptive step, each step warm-started from the
//! previous equilibrium, and the full model is finally solved from the last step
//! (DESIGN §3, robustness). A step that does not converge is retried at a quarter of
//! its size; a step that converges quickly doubles the next one.

pub mod predictor;

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

impl Ramp {
    /// Every Newton iteration the ramp performed: its steps and the final solve
    /// (converged or not).
    pub(crate) fn spent(&self) -> usize {
        self.iterations + self.solution.as_ref().map_or(0, |s| s.report.iterations)
    }

    /// A fallback's outcome for `solution` (the best so far, not converged): a
    /// converged ramp replaces it (whose final solve's iterations it brings along, and
    /// the replaced attempt's fine iterations go to `replaced`); the ramp's steps and
    /// their iterations count in `continuation_*` either way, a failed final solve too.
    pub(crate) fn adopt_into(
        self,
        solution: &mut Solution,
        replaced: &mut usize,
        continuation_iterations: &mut usize,
        continuation_steps: &mut usize,
    ) {
        *continuation_steps += self.steps;
        match self.solution {
            Some(ramped) if ramped.report.converged => {
                *continuation_iterations += self.iterations;
                *replaced += solution.report.fine_iterations;
                *solution = ramped;
            }
            _ => *continuation_iterations += self.spent(),
        }
    }
}

/// Ramps the loads from `initial` and solves `model` from the last ramp step.
pub(crate) fn ramp(
    model: &Model,
    constraints: Option<&dyn Constraints>,
    initial: SystemState,
    settings: &SolverSettings,
) -> Result<Ramp, SolveError> {
    ramp_systems(model, constraints, initial, settings, |factor| {
        scaled_loads(model.system(), factor)
    })
}

/// Ramps the supports from where `initial` holds the rod ends (and fixed bodies) to
/// where `model` holds them ([`System::supports_from`]), and solves `model` from the
/// last ramp step: continuation in prescribed end positions, for a start taken from
/// another design.
pub(crate) fn ramp_supports(
    model: &Model,
    constraints: Option<&dyn Constraints>,
    initial: SystemState,
    settings: &SolverSettings,
) -> Result<Ramp, SolveError> {
    let start = initial.clone();
    ramp_systems(model, constraints, initial, settings, |factor| {
        model.system().supports_from(&start, factor)
    })
}

/// The adaptive ramp over the systems `system_at(factor)`, `factor` from 0 to 1 (the
/// last step solves `model` itself), each step warm-started from the last equilibrium.
fn ramp_systems(
    model: &Model,
    constraints: Option<&dyn Constraints>,
    initial: SystemState,
    settings: &SolverSettings,
    system_at: impl Fn(f64) -> System,
) -> Result<Ramp, SolveError> {
    // A load step that needs many iterations is better split: each gets a bounded
    // budget, so a failing step costs little before it is retried at a quarter size.
    let step_settings = SolverSettings {
        nested_iteration: false,
        load_continuation: false,
        support_continuation: false,
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
            let scaled =
                Model::try_new(system_at(target)).map_err(crate::InitialStateError::from)?;
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

#[cfg(test)]
mod adopt_tests {
    use nalgebra::{UnitQuaternion, Vector3};
    use strand_rod::{Rod, Section};
    use strand_system::{End, RodSpec, initial_state};

    use super::*;

    /// Copies of a solved cantilever's solution with the given report figures
    /// (converged, iterations, fine iterations).
    fn solutions() -> impl Fn(bool, usize, usize) -> Solution {
        let section = Section::try_explicit(3e4, 1e4, 1.0, 1.0, 0.5, 0.0).unwrap();
        let model = Model::try_new(System {
            rods: vec![RodSpec {
                name: "r".into(),
                rod: Rod::try_straight(section, 1.0, 4).unwrap(),
                start: End::clamped(Vector3::zeros(), UnitQuaternion::identity()),
                end: End::free(),
                route: None,
            }],
            bodies: vec![],
            clips: vec![],
            gravity: Vector3::new(0.0, 0.0, -9.81),
        })
        .unwrap();
        let solved = crate::solve(
            &model,
            initial_state(model.system()),
            &SolverSettings::default(),
        )
        .unwrap();
        move |converged: bool, iterations: usize, fine: usize| {
            let mut s = solved.clone();
            s.report.converged = converged;
            s.report.iterations = iterations;
            s.report.fine_iterations = fine;
            s
        }
    }

    #[test]
    fn a_failed_ramp_counts_its_steps_and_its_final_solve_and_keeps_the_best_so_far() {
        let with = solutions();
        let mut best = with(false, 200, 200);
        let (mut replaced, mut iterations, mut steps) = (0, 0, 0);
        let ramp = Ramp {
            solution: Some(with(false, 37, 37)),
            steps: 4,
            iterations: 55,
        };
        ramp.adopt_into(&mut best, &mut replaced, &mut iterations, &mut steps);
        assert_eq!((replaced, iterations, steps), (0, 55 + 37, 4));
        assert!(!best.report.converged);
        assert_eq!(best.report.iterations, 200);
        // A ramp that stalled before its final solve.
        let stalled = Ramp {
            solution: None,
            steps: 2,
            iterations: 9,
        };
        stalled.adopt_into(&mut best, &mut replaced, &mut iterations, &mut steps);
        assert_eq!((replaced, iterations, steps), (0, 55 + 37 + 9, 6));
    }

    #[test]
    fn a_converged_ramp_replaces_the_attempt_whose_fine_iterations_still_count() {
        let with = solutions();
        let mut best = with(false, 200, 180);
        let (mut replaced, mut iterations, mut steps) = (0, 0, 0);
        let ramp = Ramp {
            solution: Some(with(true, 12, 12)),
            steps: 3,
            iterations: 21,
        };
        ramp.adopt_into(&mut best, &mut replaced, &mut iterations, &mut steps);
        assert!(best.report.converged);
        // The final solve's 12 iterations come with the adopted solution's report.
        assert_eq!(best.report.iterations, 12);
        assert_eq!((replaced, iterations, steps), (180, 21, 3));
    }
}

#[cfg(test)]
mod support_tests {
    use nalgebra::{UnitQuaternion, Vector3};
    use strand_rod::{Rod, Section};
    use strand_system::{End, RodSpec, initial_state};

    use super::*;

    /// A 1.2 m rubber hose, 1 kg/m, clamped at the origin along +x and at `end`
    /// with boundary frame `frame`, under gravity.
    fn hose(end: Vector3<f64>, frame: UnitQuaternion<f64>) -> Model {
        let section = Section::try_explicit(2e4, 1e4, 0.05, 0.04, 1.0, 0.0).unwrap();
        let along_x =
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
        Model::try_new(System {
            rods: vec![RodSpec {
                name: "hose".into(),
                rod: Rod::try_straight(section, 1.2, 40).unwrap(),
                start: End::clamped(Vector3::zeros(), along_x),
                end: End::clamped(end, frame),
                route: None,
            }],
            bodies: vec![],
            clips: vec![],
            gravity: Vector3::new(0.0, 0.0, -9.81),
        })
        .unwrap()
    }

    #[test]
    fn a_support_ramp_from_another_design_reaches_the_cold_solution() {
        let along_x =
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
        let settings = SolverSettings::default();
        // Design A: the far end 1 m along x. Design B: moved by 0.64 m and turned by
        // 120° about z (the hose now arrives from the side).
        let a = hose(Vector3::new(1.0, 0.0, 0.0), along_x);
        let turned =
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 2.0 * std::f64::consts::FRAC_PI_3)
                * along_x;
        let b = hose(Vector3::new(0.6, 0.5, 0.15), turned);
        let solved_a = crate::solve(&a, initial_state(a.system()), &settings).unwrap();
        assert!(solved_a.report.converged);
        let cold_b = crate::solve(&b, initial_state(b.system()), &settings).unwrap();
        assert!(
            cold_b.report.converged && cold_b.report.stable,
            "{:?}",
            cold_b.report
        );
        let (offset_m, offset_rad) = b.system().support_offset(&solved_a.state);
        assert!(
            offset_m > 0.6 && offset_rad > 2.0,
            "{offset_m} m, {offset_rad} rad"
        );
        let ramped = ramp_supports(&b, None, solved_a.state.clone(), &settings).unwrap();
        let solution = ramped.solution.expect("the ramp reaches the end");
        assert!(solution.report.converged, "{:?}", solution.report);
        assert!(ramped.steps >= 2, "{} steps", ramped.steps);
        for (p, q) in solution.state.rods[0]
            .positions
            .iter()
            .zip(&cold_b.state.rods[0].positions)
        {
            assert!((p - q).norm() < 1e-8, "{p} vs {q}");
        }
        // Through the solver: the warm start from design A (ends away from B's
        // supports) converges to the same state, whichever path it takes.
        let warm = crate::solve(&b, solved_a.state, &settings).unwrap();
        println!(
            "warm start from A: {:?}",
            (warm.report.iterations, warm.report.continuation_steps)
        );
        assert!(warm.report.converged);
        for (p, q) in warm.state.rods[0]
            .positions
            .iter()
            .zip(&cold_b.state.rods[0].positions)
        {
            assert!((p - q).norm() < 1e-8, "{p} vs {q}");
        }
    }
}
