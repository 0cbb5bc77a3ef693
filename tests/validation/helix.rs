//! Paper Fig. 4: a straight rod clamped at both ends to a helix (Kirchhoff, Love
//! Art. 270), and the same with extra twist, which needs an axial force.

use nalgebra::Vector3;
use strand_rod::Rod;
use strand_rod::sectional::{Sectional, sectional};
use strand_rod::{RodState, Section};
use strand_solve::{SolverSettings, solve};
use strand_system::{End, Model, RodSpec, System, SystemState, initial_state};
use strand_tests::reference::kirchhoff_helix::Helix;

use crate::common::{frame_from_matrix, observed_orders, paper_section};

const RADIUS: f64 = 0.2;
const PITCH_ANGLE: f64 = std::f64::consts::PI / 8.0;

fn helix_system(helix: &Helix, segments: usize, section: Section) -> System {
    let length = helix_length();
    let route = (0..=48)
        .map(|i| helix.centreline(length * i as f64 / 48.0))
        .collect();
    System {
        rods: vec![RodSpec {
            name: "helix".into(),
            rod: Rod::try_straight(section, length, segments).unwrap(),
            start: End::clamped(
                helix.centreline(0.0),
                frame_from_matrix(helix.material_frame(0.0)),
            ),
            end: End::clamped(
                helix.centreline(length),
                frame_from_matrix(helix.material_frame(length)),
            ),
            route: Some(route),
        }],
        bodies: vec![],
        clips: Vec::new(),
        gravity: Vector3::zeros(),
    }
}

/// The analytic helix sampled on the rod's grid (edge frames at edge midpoints), with
/// every vertex moved by up to `noise` m, as an initial guess.
fn perturbed_helix_state(helix: &Helix, segments: usize, noise: f64) -> SystemState {
    let h = helix_length() / segments as f64;
    let positions = (0..=segments)
        .map(|j| {
            helix.centreline(h * j as f64)
                + noise * Vector3::new((j as f64).sin(), (2.0 * j as f64).cos(), 0.5)
        })
        .collect();
    let frames = (0..segments)
        .map(|e| frame_from_matrix(helix.material_frame(h * (e as f64 + 0.5))))
        .collect();
    SystemState {
        rods: vec![RodState::new(positions, frames)],
        bodies: vec![],
        clips: Vec::new(),
    }
}

fn helix_length() -> f64 {
    2.0 * std::f64::consts::PI * RADIUS / PITCH_ANGLE.cos()
}

/// Solves (from the case's route hint, or from `initial`) and returns the sectional
/// quantities.
fn solve_helix(
    helix: &Helix,
    segments: usize,
    section: Section,
    initial: Option<SystemState>,
) -> Sectional {
    let model = Model::try_new(helix_system(helix, segments, section)).unwrap();
    let initial = initial.unwrap_or_else(|| initial_state(model.system()));
    // Round-off floor of the force residual: about EA · 1e-16 times the conditioning.
    // Below it, a tenth of the 1e-9 N the forces are checked against: a force is a sum
    // of vertex residuals, so a solve stopped just under 1e-9 N could miss the check
    // by where its last iterate happened to land.
    let tolerance_n = if section.axial_stiffness > 1e6 {
        1e-6
    } else {
        1e-10
    };
    let solution = solve(
        &model,
        initial,
        &SolverSettings {
            tolerance_n,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        solution.report.converged && solution.report.stable,
        "{:?}",
        solution.report
    );
    sectional(
        &model.system().rods[0].rod,
        &solution.state.rods[0],
        &model.boundary_frames(0, &solution.state),
    )
}

fn max_over<T>(items: &[T], f: impl Fn(&T) -> f64) -> f64 {
    items.iter().map(f).fold(0.0, f64::max)
}

#[test]
fn helix_equilibrium_is_uniform_and_matches_kirchhoff() {
    let helix = Helix::new(RADIUS, PITCH_ANGLE, 1.0, 1.0);
    let expected_curvature = Vector3::new(
        0.0,
        PITCH_ANGLE.cos().powi(2) / RADIUS,
        PITCH_ANGLE.sin() * PITCH_ANGLE.cos() / RADIUS,
    );
    let (bending, torsion) = (helix.bending_moment(), helix.torsional_moment());
    assert!(
        helix.axial_force().abs() < 1e-12,
        "EI = GJ: Kirchhoff needs no force"
    );
    for n in [19, 38, 76] {
        let out = solve_helix(&helix, n, paper_section(), None);
        // The clamps fix the total rotation and the discrete equilibrium is screw
        // symmetric, so the vertex curvature is the continuum one to round-off.
        let curvature_error = max_over(&out.curvatures, |k| (k - expected_curvature).norm())
            / expected_curvature.norm();
        let bending_error = max_over(&out.bending_moment, |m| (m - bending).abs()) / bending;
        let torsion_error = max_over(&out.torsion, |m| (m - torsion).abs()) / torsion;
        assert!(
            curvature_error < 1e-9,
            "N={n}: curvature error {curvature_error:e}"
        );
        assert!(
            bending_error < 1e-9 && torsion_error < 1e-9,
            "N={n}: moments {bending_error:e} {torsion_error:e}"
        );
        // Kirchhoff's force is zero, and so is the discrete one.
        let force = max_over(&out.forces, |f| f.norm());
        assert!(force < 1e-9, "N={n}: force {force:e} N");
    }
}

/// Largest relative deviation of the vertex forces from Kirchhoff's for meshes of
/// 19, 38 and 76 edges, solved from a perturbed analytic helix (clamps fix frames only
/// modulo a full turn: without a start near the twisted branch the solver may find the
/// lower-energy equilibrium of the opposite winding).
fn twisted_force_errors(section: Section) -> Vec<f64> {
    let helix = Helix::new(RADIUS, PITCH_ANGLE, 1.0, 1.0).with_extra_twist(1.0);
    let expected = helix.internal_force();
    assert!(
        expected.z > 4.0,
        "the twist needs {expected:?} N along the axis"
    );
    [19, 38, 76]
        .iter()
        .map(|&n| {
            let out = solve_helix(
                &helix,
                n,
                section,
                Some(perturbed_helix_state(&helix, n, 0.01)),
            );
            max_over(&out.forces, |f| (f - expected).norm()) / expected.norm()
        })
        .collect()
}

#[test]
fn twisted_helix_carries_kirchhoffs_axial_force() {
    // The paper's section: discretisation error plus the (tiny) difference between a
    // shearable, extensible Cosserat rod and Kirchhoff's inextensible one.
    let errors = twisted_force_errors(paper_section());
    assert!(errors.iter().all(|e| *e < 1e-2), "errors {errors:?}");
    assert!(errors.windows(2).all(|w| w[1] < w[0]), "errors {errors:?}");
    // Nearly inextensible and unshearable (GA = EA = 1e8 N): only the discretisation
    // error remains, and it falls at second order.
    let stiff = Section::try_explicit(1e8, 1e8, 1.0, 1.0, 0.0, 0.0).unwrap();
    let errors = twisted_force_errors(stiff);
    let orders = observed_orders(&errors);
    assert!(
        errors[2] < 1e-3 && orders.iter().all(|p| (1.8..2.2).contains(p)),
        "errors {errors:?} orders {orders:?}"
    );
}

#[test]
fn discrete_balance_equations_hold_exactly_in_space() {
    // Eq. (15)–(16) with the exact vertex moments: f_{j+1/2} − f_{j−1/2} = 0 and
    // m_{j+1} − m_j + (r_{j+1} − r_j) × f_{j+1/2} = 0, for a genuinely 3D equilibrium.
    let helix = Helix::new(RADIUS, PITCH_ANGLE, 1.0, 1.0).with_extra_twist(1.0);
    let model = Model::try_new(helix_system(&helix, 19, paper_section())).unwrap();
    let solution = solve(
        &model,
        perturbed_helix_state(&helix, 19, 0.01),
        &SolverSettings::default(),
    )
    .unwrap();
    assert!(solution.report.converged);
    let state = &solution.state.rods[0];
    let out = sectional(
        &model.system().rods[0].rod,
        state,
        &model.boundary_frames(0, &solution.state),
    );
    for j in 0..19 {
        let moment_balance = out.moments[j + 1] - out.moments[j]
            + (state.positions[j + 1] - state.positions[j]).cross(&out.edge_forces[j]);
        assert!(moment_balance.norm() < 1e-9, "edge {j}: {moment_balance:?}");
    }
    for j in 1..19 {
        assert!((out.edge_forces[j] - out.edge_forces[j - 1]).norm() < 1e-9);
    }
}
