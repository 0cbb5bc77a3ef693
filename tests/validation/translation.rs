//! Issue 9: invariance under a rigid translation. A harness-like system — three rubber
//! hoses from connectors (clamp, clamp, pin) to a free 1 kg T-junction (two clamped
//! ports, one ball port), one hose held by a fixed clip and one by a hinge clip, under
//! gravity — is solved at the origin and shifted by 1 km. Same iteration count, same
//! relative positions (to 1e-9 of the system size) and same reactions (to 1e-9 of
//! the weight; moments to 1e-9 of weight × size). Round-off grows with the
//! coordinates, so this checks that residuals and steps are measured where they are
//! meaningful, and that no decision on the way depends on round-off: the west hose
//! arrives at its port turned by exactly half a turn, whose shortest twist is ±π by
//! the round-off of the shifted input; it used to start from +π at the origin and −π
//! 1 km away and end 5.5 cm apart in another stable equilibrium.

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::{Rod, Section, TubeMaterial};
use strand_solve::{SolverSettings, solve};
use strand_system::{
    BodyHandle, BodySpec, ClipSpec, End, Joint, Model, Port, Pose, RodHandle, RodSpec, Support,
    System, initial_state,
};

/// 1 km, in a direction with all three components.
const OFFSET: [f64; 3] = [480.0, -600.0, 640.0];

fn frame_towards(direction: Vector3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::rotation_between(&Vector3::z(), &direction).unwrap()
}

fn port_end(port: usize, clamped: bool) -> End {
    End {
        support: Support::Port {
            body: BodyHandle(0),
            port,
            clamped,
        },
        ..End::free()
    }
}

/// The harness with every position shifted by `o` (m).
fn harness(o: Vector3<f64>) -> System {
    let rubber = TubeMaterial {
        youngs_modulus: 5e6,
        poisson_ratio: 0.5,
        density: 1100.0,
    };
    let section = Section::try_tube(&rubber, 0.0094, 0.0129).unwrap();
    let port = |name: &str, direction: Vector3<f64>| Port {
        name: name.into(),
        position: 0.03 * direction,
        frame: frame_towards(direction),
    };
    let tee = BodySpec {
        name: "tee".into(),
        mass: 1.0,
        center_of_mass: Vector3::new(0.0, 0.0, -0.01),
        pose: Pose {
            position: o + Vector3::new(0.0, 0.0, -0.05),
            orientation: UnitQuaternion::identity(),
        },
        fixed: false,
        ports: vec![
            port("west", -Vector3::x()),
            port("east", Vector3::x()),
            port("north", Vector3::y()),
        ],
    };
    let rod = |length| Rod::try_straight(section, length, 30).unwrap();
    let clip = |name: &str, rod: usize, position: Vector3<f64>, joint| ClipSpec {
        name: name.into(),
        body: None,
        parent: None,
        base: Pose {
            position: o + position,
            orientation: frame_towards(Vector3::x()),
        },
        joint,
        offset: Pose {
            position: Vector3::zeros(),
            orientation: UnitQuaternion::identity(),
        },
        rod: RodHandle(rod),
        vertex: 15,
        limits: None,
    };
    System {
        rods: vec![
            RodSpec {
                name: "west".into(),
                rod: rod(0.40),
                start: End::clamped(
                    o + Vector3::new(-0.35, 0.0, 0.0),
                    frame_towards(Vector3::x()),
                ),
                end: port_end(0, true),
                route: None,
            },
            RodSpec {
                name: "east".into(),
                rod: rod(0.38),
                start: port_end(1, true),
                end: End::clamped(
                    o + Vector3::new(0.34, 0.0, 0.02),
                    frame_towards(Vector3::x()),
                ),
                route: None,
            },
            RodSpec {
                name: "north".into(),
                rod: rod(0.30),
                start: port_end(2, false),
                end: End::pinned(o + Vector3::new(0.0, 0.27, 0.05)),
                route: Some(vec![
                    o + Vector3::new(0.0, 0.03, -0.05),
                    o + Vector3::new(0.0, 0.15, -0.08),
                    o + Vector3::new(0.0, 0.27, 0.05),
                ]),
            },
        ],
        bodies: vec![tee],
        clips: vec![
            clip("fixed", 0, Vector3::new(-0.17, 0.0, -0.06), Joint::Fixed),
            clip(
                "hinge",
                1,
                Vector3::new(0.17, 0.0, -0.05),
                Joint::Revolute { axis: Vector3::y() },
            ),
        ],
        gravity: Vector3::new(0.0, 0.0, -9.81),
    }
}

#[test]
fn shifting_a_harness_by_one_kilometre_changes_nothing() {
    let o = Vector3::from(OFFSET);
    assert!((o.norm() - 1000.0).abs() < 1e-12);
    let settings = SolverSettings::default();
    let mut results = vec![];
    for shift in [Vector3::zeros(), o] {
        let model = Model::try_new(harness(shift)).unwrap();
        let solution = solve(&model, initial_state(model.system()), &settings).unwrap();
        let report = &solution.report;
        println!(
            "harness at {shift:?}: converged {} stable {} iterations {} (fine {}, coarse {}, \
             continuation {}) residual {:.3e} N floor {:.3e} N, {:.3} s",
            report.converged,
            report.stable,
            report.iterations,
            report.fine_iterations,
            report.coarse_iterations,
            report.continuation_iterations,
            report.residual.combined_n,
            report.residual_floor_n,
            report.solve_seconds
        );
        let reactions = model.reactions(&solution.state);
        results.push((solution, reactions));
    }
    let (base, shifted) = (&results[0], &results[1]);
    for (solution, _) in [base, shifted] {
        let report = &solution.report;
        assert!(report.converged, "not converged: {report:?}");
        assert!(report.stable, "not stable: {report:?}");
    }
    assert_eq!(
        base.0.report.iterations, shifted.0.report.iterations,
        "same iterations"
    );
    let size = 1.0; // m: the harness spans ≈ 0.7 m
    let mut worst_position: f64 = 0.0;
    for (a, b) in base.0.state.rods.iter().zip(&shifted.0.state.rods) {
        for (p, q) in a.positions.iter().zip(&b.positions) {
            worst_position = worst_position.max((q - o - p).norm());
        }
    }
    let body = (shifted.0.state.bodies[0].position - o - base.0.state.bodies[0].position).norm();
    let weight = 9.81
        * (1.0
            + harness(Vector3::zeros())
                .rods
                .iter()
                .map(|r| r.rod.mass())
                .sum::<f64>());
    let (mut worst_force, mut worst_moment): (f64, f64) = (0.0, 0.0);
    for (ra, rb) in base.1.iter().zip(&shifted.1) {
        assert_eq!(ra.name, rb.name);
        worst_force = worst_force.max((ra.force - rb.force).norm());
        worst_moment = worst_moment.max((ra.moment - rb.moment).norm());
    }
    println!(
        "shift by 1 km: positions {worst_position:.3e} m, body {body:.3e} m, reaction forces \
         {worst_force:.3e} N, moments {worst_moment:.3e} N·m (weight {weight:.3} N)"
    );
    assert!(
        worst_position <= 1e-9 * size && body <= 1e-9 * size,
        "positions differ by {worst_position:e} m, body by {body:e} m"
    );
    assert!(
        worst_force <= 1e-9 * weight,
        "reaction forces differ by {worst_force:e} N"
    );
    assert!(
        worst_moment <= 1e-9 * weight * size,
        "reaction moments differ by {worst_moment:e} N·m"
    );
}
