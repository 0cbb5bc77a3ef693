//! Paper Figs. 2 and 3: the Elastica under a dead tip load and with its tip position
//! prescribed, against an independent shooting solution of the planar Reissner rod.

use nalgebra::Vector3;
use strand_rod::sectional::sectional;
use strand_solve::SolverSettings;
use strand_system::End;
use strand_tests::reference::reissner_planar::{PlanarRod, dead_load_tip};

use crate::common::{clamped_rod, observed_orders, solve_converged, solve_converged_with};

const LOADS: [[f64; 2]; 2] = [[2.0, 1.0], [17.8, -12.8]];
const MESHES: [usize; 4] = [19, 38, 76, 152];

fn reference_rod() -> PlanarRod {
    PlanarRod::new(1.0, 1.0, 1e4, 3e4)
}

#[test]
fn dead_load_tip_converges_to_reissner_at_second_order() {
    for load in LOADS {
        let reference = dead_load_tip(&reference_rod(), load);
        let (mut errors, mut moment_errors) = (vec![], vec![]);
        for n in MESHES {
            let end = End::free().with_force(Vector3::new(load[0], load[1], 0.0));
            let (model, solution) = solve_converged(clamped_rod(n, end));
            let tip = solution.state.rods[0].positions[n];
            assert!(tip.z.abs() < 1e-12, "stays in the plane");
            errors.push(
                ((tip.x - reference.tip[0]).powi(2) + (tip.y - reference.tip[1]).powi(2)).sqrt(),
            );
            // The clamp carries the load and the moment of the reference.
            let clamp = &model.reactions(&solution.state)[0];
            assert!((clamp.force + Vector3::new(load[0], load[1], 0.0)).norm() < 1e-8);
            moment_errors.push(
                (clamp.moment.z + reference.clamp_moment).abs() / reference.clamp_moment.abs(),
            );
        }
        let moment_orders = observed_orders(&moment_errors);
        assert!(
            moment_errors[0] < 1e-2,
            "clamp moment errors {moment_errors:?}"
        );
        assert!(
            moment_orders.iter().all(|p| (1.8..2.2).contains(p)),
            "clamp moment errors {moment_errors:?}"
        );
        let orders = observed_orders(&errors);
        assert!(
            errors[0] < 1e-3,
            "load {load:?}: error at 19 edges {}",
            errors[0]
        );
        assert!(
            orders.iter().all(|p| (1.8..2.2).contains(p)),
            "load {load:?}: errors {errors:?} orders {orders:?}"
        );
    }
}

#[test]
fn position_controlled_end_force_converges_to_the_load_at_second_order() {
    for load in LOADS {
        let tip = dead_load_tip(&reference_rod(), load).tip;
        let mut errors = vec![];
        for n in MESHES {
            let (model, solution) = solve_converged(clamped_rod(
                n,
                End::pinned(Vector3::new(tip[0], tip[1], 0.0)),
            ));
            let pin = &model.reactions(&solution.state)[1];
            assert_eq!(pin.name, "rod.end");
            assert!(pin.moment.norm() == 0.0, "a pin transmits no moment");
            errors.push((pin.force - Vector3::new(load[0], load[1], 0.0)).norm());
        }
        let orders = observed_orders(&errors);
        assert!(
            orders.iter().all(|p| (1.8..2.2).contains(p)),
            "load {load:?}: errors {errors:?} orders {orders:?}"
        );
    }
}

#[test]
fn position_controlled_equilibrium_conserves_force_and_total_moment() {
    // The paper's Fig. 3 solution drifted in M̄; an exact equilibrium must not.
    let settings = SolverSettings {
        tolerance_n: 1e-10,
        ..Default::default()
    };
    for load in LOADS {
        let tip = dead_load_tip(&reference_rod(), load).tip;
        for n in [19, 152] {
            let (model, solution) = solve_converged_with(
                clamped_rod(n, End::pinned(Vector3::new(tip[0], tip[1], 0.0))),
                &settings,
            );
            let out = sectional(
                &model.system().rods[0].rod,
                &solution.state.rods[0],
                &model.boundary_frames(0, &solution.state),
            );
            let f0 = out.edge_forces[0];
            let force_drift = out
                .edge_forces
                .iter()
                .map(|f| (f - f0).norm())
                .fold(0.0, f64::max)
                / f0.norm();
            assert!(
                force_drift <= 1e-9,
                "N={n}: sectional force varies by {force_drift:e} (relative)"
            );
            let m0 = out.total_moment[0];
            let scale = out
                .total_moment
                .iter()
                .map(|m| m.norm())
                .fold(0.0, f64::max);
            let moment_drift = out
                .total_moment
                .iter()
                .map(|m| (m - m0).norm())
                .fold(0.0, f64::max)
                / scale;
            assert!(
                moment_drift <= 1e-9,
                "N={n}: M̄ varies by {moment_drift:e} (relative)"
            );
            // At the pin m_N = 0, so M̄ = r_N × f: the clamp moment follows from the tip.
            assert!((m0.z - (tip[0] * f0.y - tip[1] * f0.x)).abs() < 1e-8);
        }
    }
}

#[test]
fn hamiltonian_is_constant_up_to_discretisation_error() {
    // H̄ is conserved only by the continuum; its spread must shrink at second order.
    let load = LOADS[1];
    let tip = dead_load_tip(&reference_rod(), load).tip;
    let spreads: Vec<f64> = [38, 76, 152]
        .iter()
        .map(|&n| {
            let (model, solution) = solve_converged(clamped_rod(
                n,
                End::pinned(Vector3::new(tip[0], tip[1], 0.0)),
            ));
            let out = sectional(
                &model.system().rods[0].rod,
                &solution.state.rods[0],
                &model.boundary_frames(0, &solution.state),
            );
            // Interior vertices: the end half-cells use one-sided averages.
            let h = &out.hamiltonian[1..n];
            h.iter().cloned().fold(f64::MIN, f64::max) - h.iter().cloned().fold(f64::MAX, f64::min)
        })
        .collect();
    let orders = observed_orders(&spreads);
    assert!(
        orders.iter().all(|p| *p > 1.7),
        "spreads {spreads:?} orders {orders:?}"
    );
}

#[test]
fn nested_iteration_reaches_the_same_equilibrium_in_fewer_fine_iterations() {
    let tip = dead_load_tip(&reference_rod(), LOADS[1]).tip;
    let system = clamped_rod(152, End::pinned(Vector3::new(tip[0], tip[1], 0.0)));
    let plain = SolverSettings {
        nested_iteration: false,
        ..Default::default()
    };
    let (_, direct) = solve_converged_with(system.clone(), &plain);
    let (_, nested) = solve_converged(system);
    assert!(
        nested.report.coarse_iterations > 0,
        "the coarse model was used"
    );
    assert!(
        nested.report.fine_iterations < direct.report.fine_iterations,
        "{} vs {}",
        nested.report.fine_iterations,
        direct.report.fine_iterations
    );
    for (a, b) in direct.state.rods[0]
        .positions
        .iter()
        .zip(&nested.state.rods[0].positions)
    {
        // Both states meet the 1e-9 N residual; along the softest mode (EI/L³ = 1 N/m)
        // that fixes positions to ~1e-9 m, so 1e-10 m is a strict bound (1e-12 m, the
        // bound of stop 7, held by luck of round-off: 1.0002e-12 m was measured).
        assert!(
            (a - b).norm() < 1e-10,
            "same equilibrium: {:e} m apart",
            (a - b).norm()
        );
    }
}
