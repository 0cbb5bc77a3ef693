//! Stiffness continuation: a rod whose axial and shear stiffness dwarfs its bending
//! stiffness at the scale of its edges (`C·h²/EI` of 1e4 and more: a steel cable, a
//! thin wire) has an energy valley so narrow and curved that Newton steps turning its
//! frames by more than `√(8 EI/(C h²))` rad are mispredicted, and a large change of
//! shape takes hundreds of tiny steps. The same system with the strain stiffness capped
//! at `stiffness_soft_ratio·EI/h²` finds its shape in a few steps; the cap is then
//! raised by an adaptive factor (first `stiffness_first_growth`, squared after an easy
//! step, square-rooted after a failed one), each step warm-started from the last
//! equilibrium, and the true system is solved from the last step. Every constant is a
//! field of [`SolverSettings`] (`stiffness_*`). Near the valley's floor every step is a small
//! correction of the strains, which Newton takes in a few iterations.

use strand_system::{EdgeStresses, Model, System, SystemState};

use crate::constraints::Constraints;
use crate::continuation::{Ramp, solve_at};
use crate::{SolveError, SolverSettings};

/// The largest `C·h²/EI` of any rod of `system` (its stiffest strain component, its
/// softest bending or twisting component and its shortest edge).
pub fn stiffness_ratio(system: &System) -> f64 {
    system
        .rods
        .iter()
        .map(|spec| {
            let section = spec.rod.section();
            let strain = section.strain_stiffness().max();
            let bending = section.curvature_stiffness().min();
            let h = spec.rod.shortest_edge();
            strain * h * h / bending.max(f64::MIN_POSITIVE)
        })
        .fold(0.0, f64::max)
}

/// The load that strains the rods, N: the total weight of the rods and the dead
/// forces at their ends.
pub fn load_scale(system: &System) -> f64 {
    let g = system.gravity.norm();
    system
        .rods
        .iter()
        .map(|spec| {
            spec.rod.section().mass_per_length * g * spec.rod.length()
                + spec.start.load.force.norm()
                + spec.end.load.force.norm()
        })
        .sum()
}

/// `system` with every rod's strain stiffnesses (`GA1`, `GA2`, `EA`) capped at
/// `ratio · EI_min / h_min²`, but not below `load_ratio` times the [`load_scale`];
/// `None` when no rod is above the cap (the system itself).
pub fn softened(system: &System, ratio: f64, load_ratio: f64) -> Option<System> {
    let floor = load_ratio * load_scale(system);
    let mut softened = system.clone();
    let mut changed = false;
    for spec in &mut softened.rods {
        let mut section = *spec.rod.section();
        let h = spec.rod.shortest_edge();
        let cap = (ratio * section.curvature_stiffness().min() / (h * h)).max(floor);
        for c in [
            &mut section.shear_stiffness_1,
            &mut section.shear_stiffness_2,
            &mut section.axial_stiffness,
        ] {
            if *c > cap {
                *c = cap;
                changed = true;
            }
        }
        spec.rod = spec.rod.with_section(section);
    }
    changed.then_some(softened)
}

/// Solves `model` by stiffness continuation from `initial`: the [`Ramp`]'s solution is
/// that of the true system from the last step (`None` if a step failed at the smallest
/// growth), its steps count the softened start and every stiffening step.
pub(crate) fn stiffen(
    model: &Model,
    constraints: Option<&dyn Constraints>,
    initial: SystemState,
    settings: &SolverSettings,
) -> Result<Ramp, SolveError> {
    let bending_scale: f64 = model
        .system()
        .rods
        .iter()
        .map(|spec| spec.rod.section().curvature_stiffness().max() / spec.rod.length().powi(2))
        .sum();
    let step_tolerance = settings
        .tolerance_n
        .max(settings.stiffness_step_tolerance * (load_scale(model.system()) + bending_scale));
    let step_settings = SolverSettings {
        tolerance_n: step_tolerance,
        nested_iteration: false,
        load_continuation: false,
        support_continuation: false,
        stiffness_continuation: false,
        escape_min_shift: settings.stiffness_step_escape_shift,
        max_iterations: settings
            .max_iterations
            .min(settings.stiffness_step_iterations),
        ..settings.clone()
    };
    // The softened start may need the whole machinery (nested, load continuation).
    let start_settings = SolverSettings {
        tolerance_n: step_tolerance,
        stiffness_continuation: false,
        support_continuation: false,
        escape_saddles: false,
        ..settings.clone()
    };
    let system = model.system();
    let (mut steps, mut iterations) = (0, 0);
    let final_settings = SolverSettings {
        tolerance_n: settings.tolerance_n,
        ..step_settings.clone()
    };
    let mut state = initial;
    let mut ratio = settings.stiffness_soft_ratio;
    let mut growth = settings.stiffness_first_growth;
    let mut first = true;
    // The edge forces of the last converged step (N).
    let mut stresses = None;
    while steps < settings.max_continuation_steps {
        steps += 1;
        let target = if first { ratio } else { ratio * growth };
        let Some(soft) = softened(system, target, settings.stiffness_load_ratio) else {
            if first {
                // Nothing to soften (the loads alone stiffen the rods): the direct
                // path is the better solve.
                break;
            }
            let solution = solve_step(
                model,
                constraints,
                state,
                &final_settings,
                stresses.as_ref(),
            )?;
            return Ok(Ramp {
                solution: Some(solution),
                steps,
                iterations,
            });
        };
        let soft_model = Model::try_new(soft).map_err(crate::InitialStateError::from)?;
        // No iterations at the round-off floor of a step that is not the last.
        let floor_tolerance =
            settings.stiffness_step_floor_multiple * crate::iteration::residual_floor(&soft_model);
        let settings_of_step = SolverSettings {
            tolerance_n: step_tolerance.max(floor_tolerance),
            ..if first {
                start_settings.clone()
            } else {
                step_settings.clone()
            }
        };
        let solution = solve_step(
            &soft_model,
            constraints,
            state.clone(),
            &settings_of_step,
            stresses.as_ref(),
        )?;
        iterations += solution.report.iterations;
        if std::env::var_os("STRAND_TRACE").is_some() {
            eprintln!(
                "strand-solve: stiffening step {steps}: C h²/EI capped at {target:.1e}: {} ({:?}) in {} iterations, residual {:.2e} N (floor {:.2e} N)",
                if solution.report.converged {
                    "converged"
                } else {
                    "failed"
                },
                solution.report.termination,
                solution.report.iterations,
                solution.report.residual.combined_n,
                solution.report.residual_floor_n
            );
        }
        if solution.report.converged {
            if !first && solution.report.iterations <= settings.stiffness_easy_iterations {
                growth = (growth * growth).min(settings.stiffness_max_growth);
            }
            ratio = target;
            stresses = Some(soft_model.edge_stresses(&solution.state));
            state = solution.state;
            first = false;
        } else if first {
            break;
        } else {
            growth = growth.sqrt();
            if growth < settings.stiffness_min_growth {
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

/// One step of the ramp from `state`: the first Newton step takes its Hessian's stress
/// terms from `stresses`, the edge forces of the last step (mixed Newton): the start's
/// strains times the raised stiffness would be a force many times too large, and its
/// geometric stiffness would mislead the first steps.
fn solve_step(
    model: &Model,
    constraints: Option<&dyn Constraints>,
    state: SystemState,
    settings: &SolverSettings,
    stresses: Option<&EdgeStresses>,
) -> Result<crate::Solution, SolveError> {
    let Some(stresses) = stresses else {
        return solve_at(model, constraints, state, settings);
    };
    let mut solver = crate::Solver::try_new(model)?.with_initial_stresses(stresses.clone());
    if let Some(c) = constraints {
        solver = solver.with_constraints(c);
    }
    solver.solve(state, settings)
}

#[cfg(test)]
mod tests {
    use nalgebra::{UnitQuaternion, Vector3};
    use strand_rod::{Rod, Section};
    use strand_system::{End, RodSpec, initial_state};

    use super::*;

    /// A 1 m rod of `segments` edges clamped at the origin along +x, free at the other
    /// end, 0.5 kg/m, under `gravity` m/s² along −z.
    fn cantilever(ea: f64, ei: f64, segments: usize, gravity: f64) -> System {
        let section = Section::try_explicit(ea, ea / 3.0, ei, ei, 0.5, 0.0).unwrap();
        System {
            rods: vec![RodSpec {
                name: "wire".into(),
                rod: Rod::try_straight(section, 1.0, segments).unwrap(),
                start: End::clamped(Vector3::zeros(), UnitQuaternion::identity()),
                end: End::free(),
                route: None,
            }],
            bodies: vec![],
            clips: vec![],
            gravity: Vector3::new(0.0, 0.0, -gravity),
        }
    }

    #[test]
    fn softening_caps_every_strain_stiffness_and_keeps_the_rest() {
        // h = 0.1 m, EI = 1e-2 N·m²: the cap at ratio 3 is 3 N; no load.
        let system = cantilever(1e6, 1e-2, 10, 0.0);
        assert!((stiffness_ratio(&system) - 1e6 * 0.01 / 1e-2).abs() < 1e-6);
        let soft = softened(&system, 3.0, 100.0).unwrap();
        let section = soft.rods[0].rod.section();
        for c in section.strain_stiffness().iter() {
            assert!((c - 3.0).abs() < 1e-12, "{c}");
        }
        assert_eq!(
            section.curvature_stiffness(),
            system.rods[0].rod.section().curvature_stiffness()
        );
        assert_eq!(section.mass_per_length, 0.5);
        assert_eq!(soft.rods[0].rod.edge_length(3), 0.1);
        // A cap above every stiffness changes nothing.
        assert!(softened(&system, 1e9, 100.0).is_none());
    }

    #[test]
    fn the_cap_never_falls_below_a_hundred_times_the_load() {
        // Weight 0.5 kg/m · 9.81 m/s² · 1 m = 4.905 N: the cap is at least 490.5 N.
        let system = cantilever(1e6, 1e-2, 10, 9.81);
        assert!((load_scale(&system) - 4.905).abs() < 1e-12);
        let soft = softened(&system, 3.0, 100.0).unwrap();
        let ea = soft.rods[0].rod.section().axial_stiffness;
        assert!((ea - 490.5).abs() < 1e-9, "{ea}");
    }

    #[test]
    fn mixed_newton_reaches_the_same_equilibrium_in_fewer_iterations() {
        // A pinned–clamped steel-like wire (C h²/EI = 1e10 · 0.01 / 1 = 1e8) sagging
        // over a span of 0.9 L. Raising the capped stiffness multiplies the start's
        // strain force by the growth; with the last step's forces in the first
        // Hessian (mixed Newton) every stiffening step needs fewer iterations, and the
        // equilibrium is the same (it does not depend on how the Hessian was made).
        let mut system = cantilever(1e10, 1.0, 10, 9.81);
        system.rods[0].end = End::pinned(Vector3::new(0.9, 0.0, 0.0));
        let model = Model::try_new(system).unwrap();
        let start = initial_state(model.system());
        let solve = |mixed_newton| {
            let settings = SolverSettings {
                mixed_newton,
                ..SolverSettings::default()
            };
            crate::solve(&model, start.clone(), &settings).unwrap()
        };
        let (mixed, plain) = (solve(true), solve(false));
        println!(
            "mixed {} vs plain {} iterations",
            mixed.report.iterations, plain.report.iterations
        );
        assert!(mixed.report.converged && plain.report.converged);
        assert!(mixed.report.continuation_steps >= 2, "{:?}", mixed.report);
        assert!(
            mixed.report.iterations < plain.report.iterations,
            "mixed {} vs plain {} iterations",
            mixed.report.iterations,
            plain.report.iterations
        );
        for (a, b) in mixed.state.rods[0]
            .positions
            .iter()
            .zip(&plain.state.rods[0].positions)
        {
            assert!((a - b).norm() < 1e-9, "{a} vs {b}");
        }
    }

    #[test]
    fn continuation_reaches_the_equilibrium_of_the_direct_solve() {
        // A stiff heavy cantilever (C h²/EI = 1e8 · 0.0025 / 1 ≈ 2.5e5) has one
        // equilibrium; the direct solve (no continuation, a generous budget) and the
        // default solve through the softened system must both find it.
        let system = cantilever(1e8, 1.0, 20, 9.81);
        let model = Model::try_new(system).unwrap();
        let default = SolverSettings::default();
        let direct_settings = SolverSettings {
            stiffness_continuation: false,
            max_iterations: 5000,
            ..SolverSettings::default()
        };
        let start = initial_state(model.system());
        let stiffened = crate::solve(&model, start.clone(), &default).unwrap();
        let direct = crate::solve(&model, start, &direct_settings).unwrap();
        assert!(stiffened.report.converged && direct.report.converged);
        assert!(
            stiffened.report.continuation_steps >= 2,
            "{:?}",
            stiffened.report
        );
        assert_eq!(direct.report.continuation_steps, 0);
        for (a, b) in stiffened.state.rods[0]
            .positions
            .iter()
            .zip(&direct.state.rods[0].positions)
        {
            assert!((a - b).norm() < 1e-9, "{a} vs {b}");
        }
    }
}
