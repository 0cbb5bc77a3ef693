//! Clips on moulded rods (issue 17): the split half-cells at a clip use the nominal
//! rest curvature on both sides, so a moulded rod clipped at its nominal clip frames is
//! stress-free; finite-difference checks of the assembled gradient and Hessian with
//! clips (fixed, revolute, spherical) on a moulded rod.

use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use strand_rod::{NominalRod, NominalShape, Rod, Section};

use crate::tests::check_derivatives_at;
use crate::*;

/// A moulded rod along a 3-D curve (a bend and a rise), 12 segments.
fn moulded() -> NominalRod {
    let section = Section::try_explicit(30.0, 10.0, 1.0, 0.7, 0.3, 0.01).unwrap();
    let points = [
        (0.0, 0.0, 0.0),
        (0.3, 0.0, 0.0),
        (0.5, 0.1, 0.05),
        (0.6, 0.3, 0.15),
        (0.6, 0.6, 0.2),
    ]
    .map(|(x, y, z)| Vector3::new(x, y, z))
    .to_vec();
    Rod::try_from_nominal(section, &NominalShape::from_points(points), 12).unwrap()
}

/// The moulded rod clamped at its nominal start frame, held by clips at vertices 3, 6
/// and 9 at their nominal clip frames (or tilted by `tilt` rad), its end clamped at the
/// nominal end frame or free under a force, under `gravity`.
fn system(
    nominal: &NominalRod,
    joints: [Joint; 3],
    tilt: f64,
    end_clamped: bool,
    gravity: f64,
) -> System {
    let turn = nalgebra::UnitQuaternion::from_axis_angle(&Vector3::x_axis(), tilt);
    let clips = [3, 6, 9]
        .into_iter()
        .zip(joints)
        .enumerate()
        .map(|(k, (vertex, joint))| ClipSpec {
            parent: None,
            body: None,
            name: format!("c{k}"),
            base: Pose {
                position: nominal.state.positions[vertex],
                orientation: nominal.clip_frame(vertex) * turn,
            },
            joint,
            offset: Pose {
                position: Vector3::zeros(),
                orientation: nalgebra::UnitQuaternion::identity(),
            },
            rod: RodHandle(0),
            vertex,
            limits: None,
        })
        .collect();
    let end = if end_clamped {
        End::clamped(nominal.end_position(), nominal.end_frame)
    } else {
        End::free().with_force(Vector3::new(0.3, -0.5, 0.2))
    };
    System {
        rods: vec![RodSpec {
            name: "moulded".into(),
            rod: nominal.rod.clone(),
            start: End::clamped(nominal.start_position(), nominal.start_frame),
            end,
            route: None,
        }],
        bodies: vec![],
        clips,
        gravity: Vector3::new(0.0, 0.0, -gravity),
    }
}

#[test]
fn a_moulded_rod_clipped_at_its_nominal_frames_is_stress_free() {
    let nominal = moulded();
    let joints = [
        Joint::Fixed,
        Joint::Revolute {
            axis: Vector3::new(0.0, 0.0, 1.0),
        },
        Joint::Spherical,
    ];
    let model = Model::try_new(system(&nominal, joints, 0.0, true, 0.0)).unwrap();
    let mut state = initial_state(model.system());
    state.rods[0] = nominal.state.clone();
    let mut eval = model.new_evaluation();
    model.evaluate(&state, &mut eval, false);
    let largest = eval.gradient.iter().fold(0.0f64, |m, g| m.max(g.abs()));
    assert!(largest < 1e-12, "gradient {largest}");
    assert!(eval.energy.abs() < 1e-24, "energy {}", eval.energy);
    // Each half-cell alone is at its rest curvature: a clip frame a little off the
    // nominal one (0.01 rad) stresses the rod.
    let tilted = Model::try_new(system(&nominal, joints, 0.01, true, 0.0)).unwrap();
    tilted.evaluate(&state, &mut eval, false);
    assert!(eval.gradient.iter().any(|g| g.abs() > 1e-4));
}

#[test]
fn clips_on_a_moulded_rod_match_finite_differences() {
    let nominal = moulded();
    let joints = [
        Joint::Fixed,
        Joint::Spherical,
        Joint::Revolute {
            axis: Vector3::new(1.0, 0.0, 0.0),
        },
    ];
    let model = Model::try_new(system(&nominal, joints, 0.2, false, 9.81)).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    for _ in 0..2 {
        let mut start = initial_state(model.system());
        start.rods[0] = nominal.state.clone();
        let step: Vec<f64> = (0..model.dofs().len())
            .map(|_| rng.random_range(-0.2..0.2))
            .collect();
        let state = model.retract(&start, &step);
        check_derivatives_at(&model, &state);
    }
}
