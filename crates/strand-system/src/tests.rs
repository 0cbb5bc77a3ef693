//! Finite-difference checks of the assembled gradient and Hessian.

use nalgebra::{DMatrix, DVector, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use strand_rod::{Rod, Section};

use crate::*;

pub(crate) fn test_system() -> System {
    let section = Section::try_explicit(30.0, 10.0, 1.0, 0.7, 0.3, 0.01).unwrap();
    let clamp = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let mut cantilever = End::free().with_force(Vector3::new(0.5, 1.0, -0.3));
    cantilever.load.moment = Vector3::new(0.1, -0.2, 0.3);
    cantilever.load.moment_reference = clamp;
    System {
        rods: vec![
            RodSpec {
                name: "cantilever".into(),
                rod: Rod::try_straight(section, 1.0, 5).unwrap(),
                start: End::clamped(Vector3::zeros(), clamp),
                end: cantilever,
                route: None,
            },
            RodSpec {
                name: "bridge".into(),
                rod: Rod::try_straight(section, 1.2, 4).unwrap(),
                start: End::pinned(Vector3::new(0.0, 1.0, 0.0)),
                end: End::clamped(Vector3::new(1.0, 1.0, 0.0), clamp),
                route: None,
            },
        ],
        bodies: vec![],
        clips: Vec::new(),
        gravity: Vector3::new(0.0, 0.0, -9.81),
    }
}

/// Three rods joined at a free T-junction (two clamped ports, one ball-joint port),
/// their outer ends at connectors, under gravity.
pub(crate) fn junction_system() -> System {
    let section = Section::try_explicit(30.0, 10.0, 1.0, 0.7, 0.3, 0.01).unwrap();
    let along_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let along_y = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -std::f64::consts::FRAC_PI_2);
    let port = |name: &str, position: Vector3<f64>, frame| Port {
        name: name.into(),
        position,
        frame,
    };
    let body = BodySpec {
        name: "tee".into(),
        mass: 0.4,
        center_of_mass: Vector3::new(0.01, -0.02, 0.005),
        pose: Pose {
            position: Vector3::new(0.5, 0.1, 0.0),
            orientation: UnitQuaternion::identity(),
        },
        fixed: false,
        ports: vec![
            port(
                "left",
                Vector3::new(-0.05, 0.0, 0.0),
                UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -std::f64::consts::FRAC_PI_2),
            ),
            port("right", Vector3::new(0.05, 0.0, 0.0), along_x),
            port("down", Vector3::new(0.0, 0.05, 0.0), along_y),
        ],
    };
    let tee = BodyHandle(0);
    let rod = |length: f64, segments| Rod::try_straight(section, length, segments).unwrap();
    System {
        rods: vec![
            RodSpec {
                name: "a".into(),
                rod: rod(0.5, 4),
                start: End::clamped(Vector3::zeros(), along_x),
                end: End {
                    support: Support::Port {
                        body: tee,
                        port: 0,
                        clamped: true,
                    },
                    load: EndLoad::default(),
                    twist_turns: 0,
                },
                route: None,
            },
            RodSpec {
                name: "b".into(),
                rod: rod(0.5, 3),
                start: End {
                    support: Support::Port {
                        body: tee,
                        port: 1,
                        clamped: true,
                    },
                    load: EndLoad::default(),
                    twist_turns: 0,
                },
                end: End::clamped(Vector3::new(1.0, 0.0, 0.0), along_x),
                route: None,
            },
            RodSpec {
                name: "c".into(),
                rod: rod(0.4, 3),
                start: End {
                    support: Support::Port {
                        body: tee,
                        port: 2,
                        clamped: false,
                    },
                    load: EndLoad::default(),
                    twist_turns: 0,
                },
                end: End::pinned(Vector3::new(0.5, 0.45, 0.0)),
                route: None,
            },
        ],
        bodies: vec![body],
        clips: vec![],
        gravity: Vector3::new(0.0, 0.0, -9.81),
    }
}

/// One rod held by a revolute clip, a prismatic clip and a spherical clip (with offsets
/// and tilted bases), clamped at its start, loaded at its free end, under gravity.
pub(crate) fn clipped_system() -> System {
    let section = Section::try_explicit(30.0, 10.0, 1.0, 0.7, 0.3, 0.01).unwrap();
    let along_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let tilt = |angle: f64| UnitQuaternion::from_axis_angle(&Vector3::x_axis(), angle);
    let clip = |name: &str, x: f64, joint, vertex| ClipSpec {
        parent: None,
        body: None,
        name: name.into(),
        base: Pose {
            position: Vector3::new(x, 0.02, 0.0),
            orientation: tilt(0.3),
        },
        joint,
        offset: Pose {
            position: Vector3::new(0.01, -0.005, 0.02),
            orientation: tilt(-0.3) * along_x,
        },
        rod: RodHandle(0),
        vertex,
        limits: None,
    };
    System {
        rods: vec![RodSpec {
            name: "hose".into(),
            rod: Rod::try_straight(section, 1.2, 8).unwrap(),
            start: End::clamped(Vector3::zeros(), along_x),
            end: End::free().with_force(Vector3::new(0.3, -0.5, 0.2)),
            route: None,
        }],
        bodies: vec![],
        clips: vec![
            clip(
                "hinge",
                0.3,
                Joint::Revolute {
                    axis: Vector3::new(0.0, 0.6, 0.8),
                },
                2,
            ),
            clip(
                "rail",
                0.6,
                Joint::Prismatic {
                    axis: Vector3::new(0.0, 0.0, 1.0),
                },
                4,
            ),
            clip("ball", 0.9, Joint::Spherical, 6),
        ],
        gravity: Vector3::new(0.0, 0.0, -9.81),
    }
}

/// The T-junction system with clips carried by bodies: a revolute, a prismatic, a
/// spherical and a fixed clip on the free T, and a light free "hose-to-hose" clip body
/// that holds rods `a` and `b` through a fixed and a revolute clip.
pub(crate) fn body_clip_system() -> System {
    let mut system = junction_system();
    let tilt = |angle: f64| UnitQuaternion::from_axis_angle(&Vector3::x_axis(), angle);
    let along = |d: Vector3<f64>| {
        UnitQuaternion::rotation_between(&Vector3::z(), &d).expect("not antiparallel")
    };
    let clip = |name: &str, body, position, joint, rod, vertex, direction| ClipSpec {
        parent: None,
        name: String::from(name),
        body: Some(BodyHandle(body)),
        base: Pose {
            position,
            orientation: tilt(0.2),
        },
        joint,
        offset: Pose {
            position: Vector3::new(0.01, -0.004, 0.015),
            orientation: tilt(-0.2) * along(direction),
        },
        rod: RodHandle(rod),
        vertex,
        limits: None,
    };
    system.bodies.push(BodySpec {
        name: "pair".into(),
        mass: 0.02,
        center_of_mass: Vector3::new(0.003, 0.0, -0.002),
        pose: Pose {
            position: Vector3::new(0.3, 0.05, 0.0),
            orientation: UnitQuaternion::identity(),
        },
        fixed: false,
        ports: vec![],
    });
    let x = Vector3::x();
    system.clips = vec![
        clip(
            "hinge",
            0,
            Vector3::new(-0.25, 0.0, 0.0),
            Joint::Revolute {
                axis: Vector3::new(0.0, 0.6, 0.8),
            },
            0,
            2,
            x,
        ),
        clip(
            "rail",
            0,
            Vector3::new(0.17, 0.0, 0.0),
            Joint::Prismatic { axis: x },
            1,
            1,
            x,
        ),
        clip(
            "ball",
            0,
            Vector3::new(0.0, 0.15, 0.0),
            Joint::Spherical,
            2,
            1,
            Vector3::y(),
        ),
        clip(
            "bracket",
            0,
            Vector3::new(0.0, 0.28, 0.0),
            Joint::Fixed,
            2,
            2,
            Vector3::y(),
        ),
        clip(
            "pair_a",
            1,
            Vector3::new(0.0, -0.05, 0.0),
            Joint::Fixed,
            0,
            1,
            x,
        ),
        clip(
            "pair_b",
            1,
            Vector3::new(0.0, 0.05, 0.0),
            Joint::Revolute { axis: x },
            1,
            2,
            x,
        ),
    ];
    system
}

/// Chains of clips: on the world-based clips of [`clipped_system`], a revolute
/// "elbow" on the hinge, a spherical "wrist" on the elbow and a prismatic "slide" on
/// the rail; on the free T of [`body_clip_system`], a revolute "forearm" on its hinge.
pub(crate) fn chained_systems() -> [System; 2] {
    let tilt = |angle: f64| UnitQuaternion::from_axis_angle(&Vector3::x_axis(), angle);
    let link = |name: &str, parent, joint, vertex, rod| ClipSpec {
        name: name.into(),
        body: None,
        parent: Some(parent),
        base: Pose {
            position: Vector3::new(0.004, 0.003, 0.15),
            orientation: tilt(0.1),
        },
        joint,
        offset: Pose {
            position: Vector3::new(-0.002, 0.005, 0.01),
            orientation: tilt(-0.1),
        },
        rod: RodHandle(rod),
        vertex,
        limits: None,
    };
    let mut world = clipped_system();
    world.clips.extend([
        link(
            "elbow",
            0,
            Joint::Revolute {
                axis: Vector3::new(0.6, 0.0, 0.8),
            },
            3,
            0,
        ),
        link("wrist", 3, Joint::Spherical, 5, 0),
        link(
            "slide",
            1,
            Joint::Prismatic {
                axis: Vector3::new(0.0, 1.0, 0.0),
            },
            7,
            0,
        ),
    ]);
    let mut on_body = body_clip_system();
    on_body.clips.push(link(
        "forearm",
        0,
        Joint::Revolute {
            axis: Vector3::new(0.0, 0.8, 0.6),
        },
        3,
        0,
    ));
    [world, on_body]
}

pub(crate) fn perturbed(model: &Model, rng: &mut ChaCha8Rng) -> SystemState {
    let state = initial_state(model.system());
    let step: Vec<f64> = (0..model.dofs().len())
        .map(|_| rng.random_range(-0.2..0.2))
        .collect();
    model.retract(&state, &step)
}

/// The gradient at chart point `x` of the chart at `state`.
fn chart_gradient(model: &Model, state: &SystemState, x: &DVector<f64>) -> DVector<f64> {
    let moved = model.retract(state, x.as_slice());
    let mut eval = model.new_evaluation();
    model.evaluate(&moved, &mut eval, false);
    let mut g = eval.gradient;
    model.pull_back_gradient(x.as_slice(), 1.0, &mut g);
    DVector::from_vec(g)
}

fn dense_hessian(model: &Model, values: &[f64]) -> DMatrix<f64> {
    let p = model.pattern();
    let mut h = DMatrix::zeros(p.dim(), p.dim());
    for c in 0..p.dim() {
        for k in p.col_ptr[c]..p.col_ptr[c + 1] {
            let r = p.row_idx[k];
            h[(r, c)] += values[k];
            if r != c {
                h[(c, r)] += values[k];
            }
        }
    }
    h
}

#[test]
fn assembled_gradient_and_hessian_match_finite_differences() {
    check_assembly(test_system());
}

#[test]
fn junction_coupling_matches_finite_differences() {
    check_assembly(junction_system());
}

#[test]
fn clip_coupling_matches_finite_differences() {
    check_assembly(clipped_system());
}

#[test]
fn clips_on_free_bodies_match_finite_differences() {
    check_assembly(body_clip_system());
}

#[test]
fn chains_of_clips_match_finite_differences() {
    for system in chained_systems() {
        check_assembly(system);
    }
}

/// Scalar joints occupy the first component of a 3-block; the two spare components
/// have a unit stiffness but no coordinate, so finite differences do not see them.
fn spare_components(model: &Model) -> Vec<usize> {
    let system = model.system();
    (0..system.clips.len())
        .filter(|&c| {
            matches!(
                system.clips[c].joint,
                Joint::Revolute { .. } | Joint::Prismatic { .. }
            )
        })
        .filter_map(|c| model.dofs().clip(c))
        .flat_map(|b| [3 * b + 1, 3 * b + 2])
        .collect()
}

fn check_assembly(system: System) {
    let model = Model::try_new(system).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..3 {
        let state = perturbed(&model, &mut rng);
        check_derivatives_at(&model, &state);
    }
}

/// Central finite differences (step 1e-6) of the energy and of the chart gradient at
/// `state` against the assembled gradient (1e-6 absolute) and Hessian (1e-5
/// relative); the spare components of one-axis joints must carry a unit diagonal.
pub(crate) fn check_derivatives_at(model: &Model, state: &SystemState) {
    let mut eval = model.new_evaluation();
    model.evaluate(state, &mut eval, true);
    assert!((eval.energy - model.energy(state)).abs() < 1e-12 * (1.0 + eval.energy.abs()));
    let hessian = dense_hessian(model, &eval.hessian);
    let n = model.dofs().len();
    let spare = spare_components(model);
    let h = 1e-6;
    for k in 0..n {
        let mut e = DVector::zeros(n);
        e[k] = h;
        let plus = model.energy(&model.retract(state, e.as_slice()));
        let minus = model.energy(&model.retract(state, (-&e).as_slice()));
        let fd = (plus - minus) / (2.0 * h);
        assert!(
            (fd - eval.gradient[k]).abs() < 1e-6,
            "gradient {k}: fd {fd} vs {}",
            eval.gradient[k]
        );
        let column =
            (chart_gradient(model, state, &e) - chart_gradient(model, state, &-&e)) / (2.0 * h);
        if spare.contains(&k) {
            assert_eq!(hessian[(k, k)], 1.0, "spare joint component {k}");
            continue;
        }
        for l in (0..n).filter(|l| !spare.contains(l)) {
            assert!(
                (column[l] - hessian[(l, k)]).abs() < 1e-5 * (1.0 + hessian[(l, k)].abs()),
                "hessian ({l},{k}): fd {} vs {}",
                column[l],
                hessian[(l, k)]
            );
        }
    }
}

#[test]
fn an_evaluation_without_the_hessian_has_the_same_energy_and_gradient_to_the_bit() {
    // The solver evaluates trial states without the Hessian and assembles it only when
    // a step needs it: energy and gradient must not depend on that choice, or the
    // acceptance of a step would.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for system in [
        test_system(),
        junction_system(),
        clipped_system(),
        body_clip_system(),
    ] {
        let model = Model::try_new(system).unwrap();
        let state = perturbed(&model, &mut rng);
        let mut full = model.new_evaluation();
        model.evaluate(&state, &mut full, true);
        assert!(full.has_hessian);
        let mut first = model.new_evaluation();
        model.evaluate(&state, &mut first, false);
        assert!(!first.has_hessian);
        assert_eq!(first.energy.to_bits(), full.energy.to_bits());
        assert!(
            first
                .gradient
                .iter()
                .zip(&full.gradient)
                .all(|(a, b)| a.to_bits() == b.to_bits())
        );
        // Evaluated again with the Hessian into the same buffers: the same Hessian.
        model.evaluate(&state, &mut first, true);
        assert!(first.has_hessian && first.hessian == full.hessian);
    }
}

#[test]
fn validation_rejects_unreachable_ends_and_free_rods() {
    let mut system = test_system();
    system.rods[1].end.support = Support::Pinned {
        position: Vector3::new(5.0, 1.0, 0.0),
    };
    assert!(matches!(
        Model::try_new(system).unwrap_err(),
        SystemError::TooShort { .. }
    ));
    let mut system = test_system();
    system.rods[0].start = End::free();
    assert!(matches!(
        Model::try_new(system).unwrap_err(),
        SystemError::Unsupported { .. }
    ));
    let mut system = test_system();
    system.rods[0].end.load.force.x = f64::NAN;
    assert!(matches!(
        Model::try_new(system).unwrap_err(),
        SystemError::NotFinite { .. }
    ));
}

#[test]
fn validation_rejects_a_clip_out_of_reach_of_its_neighbours_along_the_rod() {
    // The clipped hose: clamped start, the hinge 0.3 m along it (vertex 2 of 8 on
    // 1.2 m) with its base 0.3 m from the start. Within reach as built.
    assert!(Model::try_new(clipped_system()).is_ok());
    // The hinge's base 2 m away: 0.45 m of hose cannot reach it from the start.
    let mut system = clipped_system();
    system.clips[0].base.position = Vector3::new(0.3, 0.02, 2.0);
    match Model::try_new(system).unwrap_err() {
        SystemError::ClipOutOfReach(reach) => {
            let pair = (reach.from.as_str(), reach.to.as_str());
            assert_eq!(pair, ("its start", "clip 'hinge'"));
            assert!((reach.arc_m - 0.3).abs() < 1e-12, "{reach}");
            assert!(reach.distance_m > 1.9, "{reach}");
        }
        other => panic!("{other}"),
    }
    // The ball 0.6 m along the hose from the hinge (the rail between them, which may
    // carry its vertex anywhere, is not a holder) but about 1 m away from it: rejected.
    let mut system = clipped_system();
    system.clips[2].base.position = Vector3::new(0.3, 0.02, 1.0);
    assert!(matches!(
        Model::try_new(system).unwrap_err(),
        SystemError::ClipOutOfReach(_)
    ));
}

/// A rod held at both ends and by three clips laid along four given pieces (each
/// bent once sideways between its stations): every station's vertex at the station,
/// every vertex between two stations at its share of the rod's arc length along its
/// piece (the point at that fraction of the piece's own length, found here
/// independently), frames along the edges; a wrong number of pieces lays nothing.
/// With its end free, its last stretch runs from the last clip to the free end: the
/// same pieces lay it the same way.
#[test]
fn a_rod_laid_along_pieces_between_its_stations_keeps_its_stations_and_spreads_its_vertices() {
    let mut system = clipped_system();
    let along_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    system.rods[0].end = End::clamped(Vector3::new(1.1, 0.1, 0.0), along_x);
    let poses = system.body_poses();
    let stations = rod_stations(&system, 0, &poses);
    assert_eq!(
        stations.iter().map(|s| s.vertex).collect::<Vec<_>>(),
        [0, 2, 4, 6, 8]
    );
    let pieces: Vec<Vec<Vector3<f64>>> = stations
        .windows(2)
        .map(|w| {
            let bend = (w[0].position + w[1].position) / 2.0 + Vector3::new(0.0, 0.05, 0.03);
            vec![w[0].position, bend, w[1].position]
        })
        .collect();
    let state = rod_state_along(&system, 0, &poses, &pieces).expect("laid");
    let arc = system.rods[0].rod.arc_lengths();
    for (pair, piece) in stations.windows(2).zip(&pieces) {
        let (a, b) = (&pair[0], &pair[1]);
        let legs = [(piece[1] - piece[0]).norm(), (piece[2] - piece[1]).norm()];
        for v in a.vertex..=b.vertex {
            let along = (arc[v] - a.s) / (b.s - a.s) * (legs[0] + legs[1]);
            let expected = if along <= legs[0] {
                piece[0] + (piece[1] - piece[0]) * (along / legs[0])
            } else {
                piece[1] + (piece[2] - piece[1]) * ((along - legs[0]) / legs[1])
            };
            let error = (state.positions[v] - expected).norm();
            assert!(error < 1e-12, "vertex {v}: {error} m from its place");
        }
    }
    for (e, q) in state.frames.iter().enumerate() {
        let t = (state.positions[e + 1] - state.positions[e]).normalize();
        assert!(((q * Vector3::z()) - t).norm() < 1e-9, "edge {e}");
    }
    assert!(rod_state_along(&system, 0, &poses, &pieces[1..]).is_none());
    system.rods[0].end = End::free();
    let free = rod_state_along(&system, 0, &poses, &pieces).expect("laid to the free end");
    assert_eq!(free.positions, state.positions);
    assert!(rod_state_along(&system, 0, &poses, &pieces[1..]).is_none());
}

#[test]
fn initial_guess_meets_held_ends_with_the_rod_length() {
    let mut system = test_system();
    system.rods[1].rod = Rod::try_straight(*system.rods[1].rod.section(), 1.2, 40).unwrap();
    let state = initial_state(&system);
    let bridge = &state.rods[1];
    assert!((bridge.positions[0] - Vector3::new(0.0, 1.0, 0.0)).norm() < 1e-12);
    assert!((bridge.positions[40] - Vector3::new(1.0, 1.0, 0.0)).norm() < 1e-12);
    let polyline: f64 = bridge
        .positions
        .windows(2)
        .map(|w| (w[1] - w[0]).norm())
        .sum();
    assert!((polyline - 1.2).abs() < 0.01, "length {polyline}");
    // Frames follow the curve: a3 parallel to each edge.
    for (e, q) in bridge.frames.iter().enumerate() {
        let t = (bridge.positions[e + 1] - bridge.positions[e]).normalize();
        assert!(((q * Vector3::z()) - t).norm() < 1e-9);
    }
}
