//! Global equilibrium: reactions balance gravity and loads exactly (force and moment
//! about any point), and a non-converged solve says so.

use nalgebra::Vector3;
use strand_rod::{Rod, Section};
use strand_solve::{SolverSettings, Termination, solve};
use strand_system::{End, Model, RodSpec, System, initial_state};

use crate::common::{frame_along_x, solve_converged};

fn sagging_hose() -> System {
    let section = Section::try_explicit(3e4, 1e4, 0.05, 0.04, 0.4, 0.01).unwrap();
    System {
        rods: vec![RodSpec {
            name: "hose".into(),
            rod: Rod::try_straight(section, 1.0, 40).unwrap(),
            start: End::clamped(Vector3::zeros(), frame_along_x()),
            end: End::clamped(Vector3::new(0.8, 0.1, 0.05), frame_along_x()),
            route: None,
        }],
        bodies: vec![],
        clips: Vec::new(),
        gravity: Vector3::new(0.0, 0.0, -9.81),
    }
}

#[test]
fn reactions_balance_the_weight_in_force_and_moment() {
    for system in [sagging_hose(), {
        let mut cantilever = sagging_hose();
        cantilever.rods[0].end = End::free();
        cantilever
    }] {
        let (model, solution) = solve_converged(system);
        let rod = &model.system().rods[0];
        let weight = rod.rod.mass() * model.system().gravity;
        let reactions = model.reactions(&solution.state);
        let total_force: Vector3<f64> =
            reactions.iter().map(|r| r.force).sum::<Vector3<f64>>() + weight;
        assert!(
            total_force.norm() <= 1e-9 * weight.norm(),
            "force imbalance {total_force:?}"
        );
        for point in [Vector3::zeros(), Vector3::new(0.3, -2.0, 1.0)] {
            let mut moment = Vector3::zeros();
            for r in &reactions {
                moment += (r.position - point).cross(&r.force) + r.moment;
            }
            for (j, p) in solution.state.rods[0].positions.iter().enumerate() {
                moment += (p - point).cross(&(rod.rod.vertex_mass(j) * model.system().gravity));
            }
            assert!(
                moment.norm() <= 1e-9 * weight.norm() * 2.0,
                "moment imbalance about {point:?}: {moment:?}"
            );
        }
    }
}

#[test]
fn an_unconverged_solve_is_reported_as_such() {
    let model = Model::try_new(sagging_hose()).unwrap();
    let settings = SolverSettings {
        max_iterations: 2,
        ..Default::default()
    };
    let solution = solve(&model, initial_state(model.system()), &settings).unwrap();
    assert!(!solution.report.converged);
    assert_eq!(solution.report.termination, Termination::MaxIterations);
    assert!(solution.report.residual.combined_n > settings.tolerance_n);
}
