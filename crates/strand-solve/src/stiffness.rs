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
use crate::{SolveError, SolveReport, SolverSettings};

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
    if settings.stiffness_limp_start {
        let limp = limp_start(
            model,
            constraints,
            &state,
            &SolverSettings {
                tolerance_n: settings.tolerance_n,
                ..start_settings.clone()
            },
            bending_scale,
        )?;
        if let Some(limp) = limp {
            steps += 1;
            iterations += limp.report.iterations;
            if limp.report.converged {
                state = limp.state;
            }
        }
    }
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
            settings.stiffness_step_floor_multiple * crate::iteration::strain_floor(&soft_model);
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
        trace(
            &format!("stiffening step {steps}: C h²/EI capped at {target:.1e}"),
            &solution.report,
        );
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

/// The factor `s ∈ [0, 1)` on the dead end loads at which the load floor of
/// [`softened`] meets the bending cap of every rod: `stiffness_load_ratio · (weight +
/// s · dead) = stiffness_soft_ratio · EI_min / h_min²` (the [`load_scale`] split into
/// the rods' weight and the dead end forces). `None` when the dead loads do not raise
/// the floor above that cap, or the weight alone does (the initial guess hangs the
/// cable under its weight, not under dead loads, so a softened start set by the weight
/// starts near its shape).
pub fn limp_load_factor(system: &System, soft_ratio: f64, load_ratio: f64) -> Option<f64> {
    let g = system.gravity.norm();
    let (weight, dead) = system.rods.iter().fold((0.0, 0.0), |(weight, dead), spec| {
        (
            weight + spec.rod.section().mass_per_length * g * spec.rod.length(),
            dead + spec.start.load.force.norm() + spec.end.load.force.norm(),
        )
    });
    let softest_cap = system
        .rods
        .iter()
        .map(|spec| {
            let h = spec.rod.shortest_edge();
            soft_ratio * spec.rod.section().curvature_stiffness().min() / (h * h)
        })
        .fold(f64::INFINITY, f64::min);
    let limp = load_ratio * weight <= softest_cap && softest_cap < load_ratio * (weight + dead);
    let factor = (softest_cap / load_ratio - weight) / dead;
    (limp && factor.is_finite()).then_some(factor.clamp(0.0, 1.0))
}

/// `system` with every dead end load (force and moment) scaled by `factor`; gravity
/// as it is.
fn scaled_dead_loads(system: &System, factor: f64) -> System {
    let mut scaled = system.clone();
    for spec in &mut scaled.rods {
        for end in [&mut spec.start, &mut spec.end] {
            end.load.force *= factor;
            end.load.moment *= factor;
        }
    }
    scaled
}

/// Phase "limp start" of stiffness continuation. A cable whose load dwarfs its
/// bending stiffness at the scale of its edges (a limp cable under a dead load) gets
/// its softened strain stiffness from the load floor ([`softened`]: at least
/// `stiffness_load_ratio` × the load, so that it stretches by at most the inverse),
/// not from its bending: its softened start is itself far stiffer in stretch than in
/// bending, and a large change of shape of a part that the load does not tension (the
/// slack part between a pin and a clip, which must turn its bow over) crawls along the
/// narrow valley, `√(8 EI/(C h²))` rad per step. The same system with its dead end
/// loads scaled by [`limp_load_factor`] has its cap at the bending scale with the same
/// bound on the stretch, and the shape of a limp cable does not depend on the size of
/// its load: solved first, it starts the softened start near its shape. Only dead
/// loads are scaled: the initial guess already hangs a cable under its weight (and
/// measured, a limp start at scaled gravity costs more than it saves).
///
/// Measured on grid case #110 (pin–free, `EI` = 1e-6 N·m², `EA/EI` = 1e12, 10 edges,
/// tip load of 1 N, hinge clip): the softened start at `C h²/EI` = 4.5e5 took 147
/// iterations turning the slack part's bow over (150 in all); with a limp start of 6
/// iterations at the load factor 6.7e-6 the softened start takes 30 (39 in all). At
/// that factor the tail's bending length `√(EI/F)` is 0.4 m, not yet limp (in a
/// trial at factors 1e-4 and 1e-3, a stiffer cap, 15 and 18 iterations of limp start
/// left 9 and 7 for the rest).
///
/// `start_settings` are those of the softened start with the caller's `tolerance_n`.
/// `None` when the load floor does not set the cap (no limp start needed).
fn limp_start(
    model: &Model,
    constraints: Option<&dyn Constraints>,
    initial: &SystemState,
    start_settings: &SolverSettings,
    bending_scale: f64,
) -> Result<Option<crate::Solution>, SolveError> {
    let system = model.system();
    let Some(factor) = limp_load_factor(
        system,
        start_settings.stiffness_soft_ratio,
        start_settings.stiffness_load_ratio,
    ) else {
        return Ok(None);
    };
    let scaled = scaled_dead_loads(system, factor);
    let Some(soft) = softened(
        &scaled,
        start_settings.stiffness_soft_ratio,
        start_settings.stiffness_load_ratio,
    ) else {
        return Ok(None);
    };
    let soft_model = Model::try_new(soft).map_err(crate::InitialStateError::from)?;
    // An intermediate step at its own force scale: the scaled load and the bending.
    let tolerance = start_settings
        .tolerance_n
        .max(start_settings.stiffness_step_tolerance * (load_scale(&scaled) + bending_scale));
    let floor_tolerance =
        start_settings.stiffness_step_floor_multiple * crate::iteration::strain_floor(&soft_model);
    let settings = SolverSettings {
        tolerance_n: tolerance.max(floor_tolerance),
        ..start_settings.clone()
    };
    let solution = solve_at(&soft_model, constraints, initial.clone(), &settings)?;
    trace(
        &format!("limp start at load factor {factor:.2e}"),
        &solution.report,
    );
    Ok(Some(solution))
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

/// With `STRAND_TRACE` set, one line on standard error for the continuation step
/// `what`: how its solve ended, in how many iterations, its residual and floor (N).
fn trace(what: &str, report: &SolveReport) {
    if std::env::var_os("STRAND_TRACE").is_some() {
        eprintln!(
            "strand-solve: {what}: {} ({:?}) in {} iterations, residual {:.2e} N (floor {:.2e} N)",
            if report.converged {
                "converged"
            } else {
                "failed"
            },
            report.termination,
            report.iterations,
            report.residual.combined_n,
            report.residual_floor_n
        );
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{UnitQuaternion, Vector3};
    use strand_rod::{Rod, Section};
    use strand_system::{End, RodSpec, initial_state};

    use super::*;

    /// Solves `model` from `start` with the default settings changed by `with(true)`
    /// and by `with(false)`: the solutions with the feature on and off.
    fn on_and_off(
        model: &Model,
        start: &SystemState,
        with: impl Fn(bool) -> SolverSettings,
    ) -> (crate::Solution, crate::Solution) {
        let solve = |on| crate::solve(model, start.clone(), &with(on)).unwrap();
        (solve(true), solve(false))
    }

    /// Asserts that rod 0's vertices of `a` and `b` agree within `tolerance_m`.
    fn assert_same_positions(a: &crate::Solution, b: &crate::Solution, tolerance_m: f64) {
        for (p, q) in a.state.rods[0]
            .positions
            .iter()
            .zip(&b.state.rods[0].positions)
        {
            assert!((p - q).norm() < tolerance_m, "{p} vs {q}");
        }
    }

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
    fn a_limp_start_scales_only_dead_loads_and_only_when_they_set_the_cap() {
        // EI = 1e-6 N·m², h = 0.1 m: the bending cap at ratio 3 is 3e-4 N.
        let mut weightless = cantilever(1e6, 1e-6, 10, 0.0);
        assert_eq!(limp_load_factor(&weightless, 3.0, 30.0), None, "no load");
        weightless.rods[0].end = End::free().with_force(Vector3::new(0.0, 0.0, -2.0));
        let factor = limp_load_factor(&weightless, 3.0, 30.0).unwrap();
        assert!((30.0 * 2.0 * factor - 3e-4).abs() < 1e-15, "{factor}");
        // The weight alone sets the floor: the guess already hangs the cable.
        let heavy = cantilever(1e6, 1e-6, 10, 9.81);
        assert_eq!(limp_load_factor(&heavy, 3.0, 30.0), None);
        // A stiff rod: the bending cap (3e4 N) is above the floor (60 N).
        let mut stiff = cantilever(1e10, 100.0, 10, 0.0);
        stiff.rods[0].end = End::free().with_force(Vector3::new(0.0, 0.0, -2.0));
        assert_eq!(limp_load_factor(&stiff, 3.0, 30.0), None);
    }

    #[test]
    fn a_limp_start_turns_a_slack_part_over_in_fewer_iterations_to_the_same_equilibrium() {
        // Convergence-map case #110 (here GJ = EI): a limp weightless cable (EI =
        // 1e-6 N·m², EA = 1e6 N, 10 edges) pinned at the origin, through a hinge clip
        // (about y) at its middle vertex, a dead force of 1 N at its free end. The
        // slack pin–clip part starts bowed down and ends bowed up (the hinge turns
        // about 1 rad towards the load): measured 168 iterations without the limp
        // start, 31 with it.
        use strand_system::{ClipSpec, Joint, Pose, RodHandle};
        let along_x =
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
        let mut system = cantilever(1e6, 1e-6, 10, 0.0);
        system.rods[0].start = End::pinned(Vector3::zeros());
        system.rods[0].end = End::free().with_force(Vector3::new(0.3, 0.4, -0.866));
        system.clips.push(ClipSpec {
            name: "clip".into(),
            body: None,
            parent: None,
            base: Pose {
                position: Vector3::new(0.45, 0.0, -0.6 * 0.0475f64.sqrt()),
                orientation: along_x,
            },
            joint: Joint::Revolute { axis: Vector3::y() },
            offset: Pose {
                position: Vector3::zeros(),
                orientation: UnitQuaternion::identity(),
            },
            rod: RodHandle(0),
            vertex: 5,
            limits: None,
        });
        let model = Model::try_new(system).unwrap();
        let start = initial_state(model.system());
        let (limp, plain) = on_and_off(&model, &start, |stiffness_limp_start| SolverSettings {
            stiffness_limp_start,
            ..SolverSettings::default()
        });
        println!(
            "limp start {} vs without {} iterations",
            limp.report.iterations, plain.report.iterations
        );
        assert!(limp.report.converged && plain.report.converged);
        assert!(limp.report.stable && plain.report.stable);
        assert!(
            2 * limp.report.iterations < plain.report.iterations,
            "limp start {} vs without {} iterations",
            limp.report.iterations,
            plain.report.iterations
        );
        assert_same_positions(&limp, &plain, 1e-8);
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
        let (mixed, plain) = on_and_off(&model, &start, |mixed_newton| SolverSettings {
            mixed_newton,
            ..SolverSettings::default()
        });
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
        assert_same_positions(&mixed, &plain, 1e-9);
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
        assert_same_positions(&stiffened, &direct, 1e-9);
    }
}
