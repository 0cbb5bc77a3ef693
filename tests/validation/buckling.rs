//! Issue 9: buckling and the stability report, default solver settings.
//!
//! * Clamped–clamped post-buckling: the end force against the shooting solution of the
//!   extensible, shearable rod (`strand_tests::reference::buckling`), second order in
//!   the mesh; the buckled state is a stable equilibrium at every mesh.
//! * The straight state beyond buckling is an equilibrium (zero iterations from the
//!   exact straight, untwisted guess) and is reported unstable.
//! * Greenhill: a straight clamped rod twisted by `φ` (one clamp frame turned about the
//!   axis) is stable below `φ_c = x EI/GJ`, `tan(x/2) = (x/2)/(1 + βx²)` (`x = 8.9868`
//!   for `β = EI/(GA L²) = 0`), unstable above; the threshold read from the stability
//!   flag converges to `φ_c` at second order; past it the solver lands on the buckled
//!   (stable) branch.
//!
//! The rod: `L = 1 m`, `EA = 30 kN`, `GA = 10 kN`, `EI = 1 N·m²`; `GJ = 1 N·m²` for
//! compression and `GJ = 5 N·m²` for twist (so that `φ_c ≈ 1.80 rad < π` and one clamp
//! frame can state it without extra turns).

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::{Rod, RodState, Section};
use strand_solve::{Solution, SolverSettings, solve};
use strand_system::{End, Model, RodSpec, System, initial_state};
use strand_tests::reference::buckling::{
    clamped_buckled, euler_clamped, greenhill_clamped, greenhill_critical_rotation,
    inextensible_end_force,
};
use strand_tests::reference::reissner_planar::PlanarRod;

use crate::common::{frame_along_x, observed_orders, sci};

const MESHES: [usize; 5] = [10, 20, 40, 80, 160];
const EA: f64 = 3e4;
const GA: f64 = 1e4;
const EI: f64 = 1.0;
/// Torsional stiffness of the twist tests (N·m²).
const GJ_TWIST: f64 = 5.0;

/// A rod clamped at the origin along `+x` and at `(L − Δ, 0, 0)` with the end frame
/// turned by `phi` about `+x`.
fn clamped_clamped(segments: usize, gj: f64, delta: f64, phi: f64) -> System {
    let section = Section::try_explicit(EA, GA, EI, gj, 0.0, 0.0).unwrap();
    let end_frame = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), phi) * frame_along_x();
    System {
        rods: vec![RodSpec {
            name: "rod".into(),
            rod: Rod::try_straight(section, 1.0, segments).unwrap(),
            start: End::clamped(Vector3::zeros(), frame_along_x()),
            end: End::clamped(Vector3::new(1.0 - delta, 0.0, 0.0), end_frame),
            route: None,
        }],
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::zeros(),
    }
}

/// The straight equilibrium: uniformly compressed to `L − Δ` and uniformly twisted by
/// `phi` (edge frames turned by `φ s/L` at the edge midpoints; both half cells at the
/// ends then carry the same twist rate `φ/L` as the interior).
fn straight_state(segments: usize, delta: f64, phi: f64) -> RodState {
    let h = (1.0 - delta) / segments as f64;
    let positions = (0..=segments)
        .map(|j| Vector3::new(j as f64 * h, 0.0, 0.0))
        .collect();
    let frames = (0..segments)
        .map(|e| {
            let angle = phi * (e as f64 + 0.5) / segments as f64;
            frame_along_x() * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), angle)
        })
        .collect();
    RodState::new(positions, frames)
}

fn solve_from(system: System, start: Option<RodState>) -> (Model, Solution) {
    let model = Model::try_new(system).unwrap();
    let mut initial = initial_state(model.system());
    // A given start is a state to examine: the solver must not leave it for another
    // branch.
    let settings = SolverSettings {
        escape_saddles: start.is_none(),
        ..SolverSettings::default()
    };
    if let Some(rod) = start {
        initial.rods[0] = rod;
    }
    let solution = solve(&model, initial, &settings).unwrap();
    (model, solution)
}

fn largest_deflection(state: &RodState) -> f64 {
    state
        .positions
        .iter()
        .map(|p| p.y.hypot(p.z))
        .fold(0.0, f64::max)
}

#[test]
fn clamped_clamped_end_force_converges_to_the_post_buckling_reference() {
    let rod = PlanarRod::new(1.0, EI, GA, EA);
    // Euler's load is the onset: the inextensible force at a tiny shortening.
    let euler = euler_clamped(1.0, EI);
    assert!((inextensible_end_force(1.0, EI, 1e-9) / euler - 1.0).abs() < 1e-8);
    for delta in [0.1, 0.3] {
        let reference = clamped_buckled(&rod, delta);
        assert!(reference.force > euler);
        let (mut errors, mut iterations, mut failures) = (vec![], vec![], vec![]);
        for n in MESHES {
            let (model, solution) = solve_from(clamped_clamped(n, EI, delta, 0.0), None);
            let report = &solution.report;
            iterations.push(report.iterations);
            if !(report.converged && report.stable) {
                failures.push(format!(
                    "N={n}: converged {} stable {} (negative {}, neutral {}) residual {:e} N \
                     after {} iterations ({:?})",
                    report.converged,
                    report.stable,
                    report.negative_directions,
                    report.neutral_directions,
                    report.residual.combined_n,
                    report.iterations,
                    report.termination
                ));
                errors.push(f64::NAN);
                continue;
            }
            // The clamp at the end pushes the rod back with P.
            let end = &model.reactions(&solution.state)[1];
            assert_eq!(end.name, "rod.end");
            errors.push((-end.force.x - reference.force).abs() / reference.force);
            assert!(
                largest_deflection(&solution.state.rods[0]) > 0.1 * reference.mid_deflection,
                "N={n}: the buckled branch, not the straight one"
            );
        }
        println!(
            "clamped buckling Δ = {delta}: P = {:.9} N (Euler {euler:.6}); errors {}, \
             iterations {iterations:?}",
            reference.force,
            sci(&errors)
        );
        assert!(failures.is_empty(), "Δ = {delta}: {failures:#?}");
        // Order from 20 edges on (10 edges resolve a rod bent by up to 90° poorly).
        let orders = observed_orders(&errors[1..]);
        assert!(errors[1] < 1e-2, "Δ = {delta}: errors {errors:?}");
        assert!(
            orders.iter().all(|p| (1.8..2.2).contains(p)),
            "Δ = {delta}: errors {errors:?} orders {orders:?}"
        );
    }
}

#[test]
fn straight_state_beyond_buckling_is_an_equilibrium_reported_unstable() {
    // Compressed straight by Δ = 0.05 L: P = EA Δ/L = 1500 N ≫ 4π² EI/L².
    for n in MESHES {
        let delta = 0.05;
        let (_, solution) = solve_from(
            clamped_clamped(n, EI, delta, 0.0),
            Some(straight_state(n, delta, 0.0)),
        );
        let report = &solution.report;
        assert!(report.converged, "N={n}: {report:?}");
        assert_eq!(report.iterations, 0, "N={n}: an equilibrium already");
        assert!(
            !report.stable,
            "N={n}: straight beyond buckling reported stable"
        );
        assert!(
            report.negative_directions > 0,
            "N={n}: negative directions {}",
            report.negative_directions
        );
    }
}

#[test]
fn a_saddle_is_escaped_only_when_its_negative_curvature_reaches_the_escape_shift() {
    // The straight state compressed by 5 % (P = 1500 N, 38× the buckling load) is a
    // saddle whose most negative curvature is a sizeable fraction of the bending
    // stiffness scale: the escape leaves it for the buckled branch at the default
    // shift (0) and at the stiffness-continuation steps' 1e-3, and keeps it (reported
    // unstable) when the shift asks for more negative curvature than there is.
    let n = 40;
    let delta = 0.05;
    let solve_with = |escape_min_shift: f64| {
        let model = Model::try_new(clamped_clamped(n, EI, delta, 0.0)).unwrap();
        let mut initial = initial_state(model.system());
        initial.rods[0] = straight_state(n, delta, 0.0);
        let settings = SolverSettings {
            escape_min_shift,
            ..SolverSettings::default()
        };
        solve(&model, initial, &settings).unwrap()
    };
    for shift in [0.0, SolverSettings::default().stiffness_step_escape_shift] {
        let escaped = solve_with(shift);
        let report = &escaped.report;
        assert!(
            report.converged && report.stable,
            "shift {shift}: {report:?}"
        );
        assert!(
            largest_deflection(&escaped.state.rods[0]) > 0.05,
            "shift {shift}: still straight"
        );
    }
    let kept = solve_with(1e3);
    assert!(
        kept.report.converged && !kept.report.stable,
        "{:?}",
        kept.report
    );
    assert!(largest_deflection(&kept.state.rods[0]) < 1e-9);
}

#[test]
fn greenhill_threshold_from_the_stability_flag_converges_at_second_order() {
    let beta = EI / (GA * 1.0);
    let critical = greenhill_critical_rotation(1.0, EI, GJ_TWIST, GA);
    // The constant itself, from the root solve (not a copied number): Timoshenko &
    // Gere's 2.86π for an unshearable rod.
    let x0 = greenhill_clamped(0.0);
    assert!((x0 / std::f64::consts::PI - 2.86).abs() < 5e-3, "{x0}");
    assert!(critical < std::f64::consts::PI, "one clamp frame states it");
    let stable_at = |n: usize, phi: f64| {
        let (_, solution) = solve_from(
            clamped_clamped(n, GJ_TWIST, 0.0, phi),
            Some(straight_state(n, 0.0, phi)),
        );
        let report = &solution.report;
        assert!(report.converged, "N={n}, φ={phi}: {report:?}");
        assert_eq!(
            report.iterations, 0,
            "N={n}, φ={phi}: an equilibrium already"
        );
        report.stable
    };
    let mut errors = vec![];
    for n in MESHES {
        let (mut lo, mut hi) = (0.6 * critical, 1.5 * critical);
        assert!(stable_at(n, lo), "N={n}: stable at 0.6 φ_c");
        assert!(!stable_at(n, hi), "N={n}: unstable at 1.5 φ_c");
        while hi - lo > 1e-10 * critical {
            let mid = 0.5 * (lo + hi);
            if stable_at(n, mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        errors.push((0.5 * (lo + hi) - critical).abs() / critical);
    }
    println!(
        "Greenhill: x = {:.10} (β = {beta:e}; {x0:.10} unshearable), φ_c = {critical:.10} rad; \
         relative errors of the discrete threshold {}",
        critical * GJ_TWIST / EI,
        sci(&errors)
    );
    let orders = observed_orders(&errors);
    assert!(errors[0] < 5e-2, "errors {errors:?}");
    assert!(
        orders.iter().all(|p| (1.8..2.2).contains(p)),
        "errors {errors:?} orders {orders:?}"
    );
}

#[test]
fn rod_twisted_past_greenhill_lands_on_the_stable_buckled_branch() {
    let critical = greenhill_critical_rotation(1.0, EI, GJ_TWIST, GA);
    let phi = 1.3 * critical;
    let mut failures = vec![];
    for n in MESHES {
        let (_, solution) = solve_from(clamped_clamped(n, GJ_TWIST, 0.0, phi), None);
        let report = &solution.report;
        let deflection = largest_deflection(&solution.state.rods[0]);
        println!(
            "twisted φ = 1.3 φ_c, N={n}: converged {} stable {} negative {} neutral {} \
             iterations {} residual {:.2e} N, largest deflection {deflection:.3e} m",
            report.converged,
            report.stable,
            report.negative_directions,
            report.neutral_directions,
            report.iterations,
            report.residual.combined_n
        );
        if !(report.converged && report.stable && deflection > 1e-3) {
            failures.push(format!(
                "N={n}: converged {} stable {} deflection {deflection:e} m ({:?})",
                report.converged, report.stable, report.termination
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
