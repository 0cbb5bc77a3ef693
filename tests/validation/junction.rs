//! Free-hanging rigid junctions: global equilibrium of a branched system and the
//! balance of the junction body itself.

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::{Rod, Section, TubeMaterial};
use strand_system::{
    BodyHandle, BodySpec, End, EndLoad, Port, Pose, ReactionKind, RodSpec, Support, System,
};

use crate::common::solve_converged;

fn port_end(port: usize, clamped: bool) -> End {
    End {
        support: Support::Port {
            body: BodyHandle(0),
            port,
            clamped,
        },
        load: EndLoad::default(),
        twist_turns: 0,
    }
}

/// A rubber T-branch: three hoses from connectors to a free 1 kg junction, under gravity.
fn tee_system() -> System {
    let rubber = TubeMaterial {
        youngs_modulus: 5e6,
        poisson_ratio: 0.5,
        density: 1100.0,
    };
    let section = Section::try_tube(&rubber, 0.0094, 0.0129).unwrap();
    let frame_towards = |direction: Vector3<f64>| {
        UnitQuaternion::rotation_between(&Vector3::z(), &direction).unwrap()
    };
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
            position: Vector3::new(0.0, 0.0, -0.05),
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
    System {
        rods: vec![
            RodSpec {
                name: "west".into(),
                rod: rod(0.40),
                start: End::clamped(Vector3::new(-0.35, 0.0, 0.0), frame_towards(Vector3::x())),
                end: port_end(0, true),
                route: None,
            },
            RodSpec {
                name: "east".into(),
                rod: rod(0.38),
                start: port_end(1, true),
                end: End::clamped(Vector3::new(0.34, 0.0, 0.02), frame_towards(Vector3::x())),
                route: None,
            },
            RodSpec {
                name: "north".into(),
                rod: rod(0.30),
                start: port_end(2, false),
                end: End::pinned(Vector3::new(0.0, 0.27, 0.05)),
                route: None,
            },
        ],
        bodies: vec![tee],
        clips: vec![],
        gravity: Vector3::new(0.0, 0.0, -9.81),
    }
}

#[test]
fn branched_system_is_in_global_equilibrium() {
    let (model, solution) = solve_converged(tee_system());
    let system = model.system();
    let reactions = model.reactions(&solution.state);
    let weight: Vector3<f64> = system.rods.iter().map(|r| r.rod.mass()).sum::<f64>()
        * system.gravity
        + system.bodies[0].mass * system.gravity;
    // Connectors carry everything: rods and junction hang from them.
    let connector_force: Vector3<f64> = reactions
        .iter()
        .filter(|r| r.kind == ReactionKind::Connector)
        .map(|r| r.force)
        .sum();
    assert!(
        (connector_force + weight).norm() <= 1e-9 * weight.norm(),
        "{connector_force:?} vs {weight:?}"
    );
    // Moment balance about two points: connector reactions, rod weights, body weight.
    let body_pose = solution.state.bodies[0];
    let body_com = body_pose.transform_point(&system.bodies[0].center_of_mass);
    for point in [Vector3::zeros(), Vector3::new(0.2, -0.4, 0.7)] {
        let mut moment = (body_com - point).cross(&(system.bodies[0].mass * system.gravity));
        for r in reactions
            .iter()
            .filter(|r| r.kind == ReactionKind::Connector)
        {
            moment += (r.position - point).cross(&r.force) + r.moment;
        }
        for (spec, rod_state) in system.rods.iter().zip(&solution.state.rods) {
            for (j, p) in rod_state.positions.iter().enumerate() {
                moment += (p - point).cross(&(spec.rod.vertex_mass(j) * system.gravity));
            }
        }
        assert!(
            moment.norm() <= 1e-9 * weight.norm(),
            "moment imbalance about {point:?}: {moment:?}"
        );
    }
}

#[test]
fn junction_ports_balance_its_weight() {
    let (model, solution) = solve_converged(tee_system());
    let system = model.system();
    let body = &system.bodies[0];
    let pose = solution.state.bodies[0];
    let ports: Vec<_> = model
        .reactions(&solution.state)
        .into_iter()
        .filter(|r| r.kind == ReactionKind::Port)
        .collect();
    assert_eq!(ports.len(), 3);
    // The rods push back on the body with −reaction at each port.
    let weight = body.mass * system.gravity;
    let force: Vector3<f64> = ports.iter().map(|r| -r.force).sum::<Vector3<f64>>() + weight;
    assert!(
        force.norm() <= 1e-9 * weight.norm(),
        "force on the junction {force:?}"
    );
    let com = pose.transform_point(&body.center_of_mass);
    let moment: Vector3<f64> = ports
        .iter()
        .map(|r| (r.position - pose.position).cross(&-r.force) - r.moment)
        .sum::<Vector3<f64>>()
        + (com - pose.position).cross(&weight);
    assert!(
        moment.norm() <= 1e-9 * weight.norm() * 0.05,
        "moment on the junction {moment:?}"
    );
    // The ball-joint port transmits no moment; the clamped ones do.
    let north = ports.iter().find(|r| r.name == "tee.north").unwrap();
    assert_eq!(north.moment, Vector3::zeros());
    assert!(
        ports
            .iter()
            .filter(|r| r.name != "tee.north")
            .all(|r| r.moment.norm() > 1e-4)
    );
    // Each port sits where the body pose puts it.
    for r in &ports {
        let port = body
            .ports
            .iter()
            .find(|p| r.name == format!("tee.{}", p.name))
            .unwrap();
        assert!((pose.transform_point(&port.position) - r.position).norm() < 1e-12);
    }
}
