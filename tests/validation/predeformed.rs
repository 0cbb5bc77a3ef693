//! Pre-deformed (moulded) rods: a rod whose stress-free shape is a nominal centreline
//! (paper §4). Mounted at its nominal end frames without loads it stays in its nominal
//! shape with zero sectional forces and moments; under gravity it sags and the
//! reactions balance its weight; a straight nominal shape is the straight rod.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use strand_rod::sectional::sectional;
use strand_rod::{NominalError, NominalRod, NominalShape, Rod, RodError, Section};
use strand_solve::{Solution, SolverSettings, solve};
use strand_system::{End, Model, RodSpec, System, SystemState, initial_state};

use crate::common::frame_from_matrix;

/// The paper-like section with a mass per length of 0.1 kg/m.
fn section() -> Section {
    Section::try_explicit(3e4, 1e4, 1.0, 1.0, 0.1, 0.0).unwrap()
}

/// A planar S: `y = 0.1 (1 − cos(π x / 0.8))`, leaving and arriving along +x.
fn s_bend() -> NominalShape {
    NominalShape::from_points(
        (0..9)
            .map(|k| {
                let x = 0.8 * k as f64 / 8.0;
                Vector3::new(x, 0.1 * (1.0 - (std::f64::consts::PI * x / 0.8).cos()), 0.0)
            })
            .collect(),
    )
}

/// A helical arc (radius 0.2 m, rise 0.08 m/rad, 4 rad), optionally with its frames
/// (`a1` towards the axis).
fn helical_arc(with_frames: bool) -> NominalShape {
    let (radius, rise) = (0.2, 0.08);
    let c = f64::hypot(radius, rise);
    let angles: Vec<f64> = (0..10).map(|k| 4.0 * k as f64 / 9.0).collect();
    let points = angles
        .iter()
        .map(|phi| Vector3::new(radius * phi.cos(), radius * phi.sin(), rise * phi))
        .collect();
    let frames = angles
        .iter()
        .map(|phi| {
            let t = Vector3::new(-radius * phi.sin(), radius * phi.cos(), rise) / c;
            let n = Vector3::new(-phi.cos(), -phi.sin(), 0.0);
            frame_from_matrix(Matrix3::from_columns(&[n, t.cross(&n), t]))
        })
        .collect();
    NominalShape {
        points,
        frames: with_frames.then_some(frames),
    }
}

/// The rod clamped at both nominal end frames.
fn mounted(nominal: &NominalRod, gravity: Vector3<f64>) -> Model {
    Model::try_new(System {
        rods: vec![RodSpec {
            name: "moulded".into(),
            rod: nominal.rod.clone(),
            start: End::clamped(nominal.start_position(), nominal.start_frame),
            end: End::clamped(nominal.end_position(), nominal.end_frame),
            route: None,
        }],
        bodies: Vec::new(),
        clips: Vec::new(),
        gravity,
    })
    .unwrap()
}

fn settings() -> SolverSettings {
    SolverSettings {
        tolerance_n: 1e-10,
        ..Default::default()
    }
}

fn solve_converged(model: &Model, initial: SystemState) -> Solution {
    let solution = solve(model, initial, &settings()).unwrap();
    assert!(solution.report.converged, "{:?}", solution.report);
    assert!(solution.report.stable, "{:?}", solution.report);
    solution
}

/// Largest vertex distance from the nominal shape, and largest sectional force and moment.
fn deviation(model: &Model, nominal: &NominalRod, solution: &Solution) -> (f64, f64, f64) {
    let state = &solution.state.rods[0];
    let distance = state
        .positions
        .iter()
        .zip(&nominal.state.positions)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    let out = sectional(
        &nominal.rod,
        state,
        &model.boundary_frames(0, &solution.state),
    );
    let force = out.forces.iter().map(|f| f.norm()).fold(0.0, f64::max);
    let moment = out.moments.iter().map(|m| m.norm()).fold(0.0, f64::max);
    (distance, force, moment)
}

#[test]
fn mounted_at_its_nominal_ends_a_moulded_rod_keeps_its_shape_without_stress() {
    for (name, shape, segments) in [
        ("S bend", s_bend(), 40),
        ("helical arc", helical_arc(false), 48),
        ("helical arc with frames", helical_arc(true), 48),
    ] {
        let nominal = Rod::try_from_nominal(section(), &shape, segments).unwrap();
        let model = mounted(&nominal, Vector3::zeros());

        // From the nominal state: already in equilibrium, at round-off.
        let at_rest = solve_converged(
            &model,
            SystemState {
                rods: vec![nominal.state.clone()],
                bodies: Vec::new(),
                clips: Vec::new(),
            },
        );
        assert_eq!(at_rest.report.iterations, 0, "{name}: {:?}", at_rest.report);
        assert!(
            at_rest.report.residual.combined_n < 1e-12,
            "{name}: {:?}",
            at_rest.report
        );
        let (d, f, m) = deviation(&model, &nominal, &at_rest);
        println!(
            "{name}, from the nominal state: {} iterations, residual {:.1e} N, |f| ≤ {f:.1e} N, |m| ≤ {m:.1e} N·m",
            at_rest.report.iterations, at_rest.report.residual.combined_n
        );
        assert!(
            d == 0.0 && f < 1e-11 && m < 1e-12,
            "{name}: {d} m, {f} N, {m} N·m"
        );

        // From the default guess (a Hermite curve between the clamps) it finds the
        // nominal shape again.
        let guess = initial_state(model.system());
        let start_distance = deviation(
            &model,
            &nominal,
            &Solution {
                state: guess.clone(),
                report: at_rest.report.clone(),
                constraints: Vec::new(),
                analysis: None,
                hessian: None,
            },
        )
        .0;
        assert!(
            start_distance > 0.01,
            "{name}: the guess is {start_distance} m off"
        );
        let solution = solve_converged(&model, guess);
        let (d, f, m) = deviation(&model, &nominal, &solution);
        println!(
            "{name}: {} iterations, residual {:.2e} N; off the nominal shape {d:.2e} m, \
             |f| ≤ {f:.2e} N, |m| ≤ {m:.2e} N·m",
            solution.report.iterations, solution.report.residual.combined_n
        );
        assert!(
            d <= 1e-9 && f <= 1e-9 && m <= 1e-9,
            "{name}: {d} m, {f} N, {m} N·m"
        );
        for reaction in model.reactions(&solution.state) {
            assert!(reaction.force.norm() <= 1e-9 && reaction.moment.norm() <= 1e-9);
        }
    }
}

#[test]
fn under_gravity_a_moulded_rod_sags_and_its_reactions_balance_the_weight() {
    for shape in [s_bend(), helical_arc(false)] {
        let nominal = Rod::try_from_nominal(section(), &shape, 40).unwrap();
        let gravity = Vector3::new(0.0, 0.0, -9.81);
        let model = mounted(&nominal, gravity);
        let solution = solve_converged(
            &model,
            SystemState {
                rods: vec![nominal.state.clone()],
                bodies: Vec::new(),
                clips: Vec::new(),
            },
        );
        let state = &solution.state.rods[0];
        let sag = state
            .positions
            .iter()
            .zip(&nominal.state.positions)
            .map(|(a, b)| b.z - a.z)
            .fold(0.0, f64::max);
        assert!(sag > 1e-4, "sag {sag} m");

        let weight = nominal.rod.mass() * gravity;
        let reactions = model.reactions(&solution.state);
        let force: Vector3<f64> = reactions.iter().map(|r| r.force).sum::<Vector3<f64>>() + weight;
        assert!(
            force.norm() <= 1e-9 * weight.norm(),
            "force imbalance {force:?}"
        );
        let point = Vector3::new(0.3, -1.0, 0.5);
        let mut moment = Vector3::zeros();
        for r in &reactions {
            moment += (r.position - point).cross(&r.force) + r.moment;
        }
        for (j, p) in state.positions.iter().enumerate() {
            moment += (p - point).cross(&(nominal.rod.vertex_mass(j) * gravity));
        }
        assert!(
            moment.norm() <= 1e-9 * weight.norm(),
            "moment imbalance {moment:?}"
        );
        println!(
            "sag {:.3} mm, weight {:.4} N, force imbalance {:.1e} N, moment imbalance {:.1e} N·m",
            sag * 1e3,
            weight.norm(),
            force.norm(),
            moment.norm()
        );
    }
}

#[test]
fn a_straight_nominal_shape_is_the_straight_rod() {
    let frame = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let points = [0.0, 0.13, 0.5, 0.95, 1.0]
        .map(|x| Vector3::new(x, 0.0, 0.0))
        .to_vec();
    for shape in [
        NominalShape::from_points(points.clone()),
        NominalShape::from_points(vec![points[0], points[4]]),
    ] {
        let nominal = Rod::try_from_nominal(section(), &shape, 19).unwrap();
        let straight = Rod::try_straight(section(), 1.0, 19).unwrap();
        let h = straight.edge_length(0);
        let mut worst = [0.0f64; 3];
        for e in 0..19 {
            worst[0] = worst[0].max((nominal.rod.edge_length(e) - h).abs() / h);
            worst[1] = worst[1].max((nominal.rod.rest_strain(e) - straight.rest_strain(e)).norm());
        }
        for j in 0..=19 {
            worst[2] = worst[2].max(nominal.rod.rest_curvature(j).norm());
        }
        println!(
            "straight: |Δh|/h ≤ {:.1e}, |Γ0 − e3| ≤ {:.1e}, |K0| ≤ {:.1e} 1/m",
            worst[0], worst[1], worst[2]
        );
        assert!(
            worst[0] <= 1e-13 && worst[1] <= 1e-14 && worst[2] <= 1e-12,
            "{worst:?}"
        );
        assert!(nominal.start_frame.angle_to(&frame) <= 1e-15);
        assert!(nominal.end_frame.angle_to(&frame) <= 1e-15);
        // The same cantilever under an end load: the same answer.
        let tip = |rod: Rod| {
            let model = Model::try_new(System {
                rods: vec![RodSpec {
                    name: "rod".into(),
                    rod,
                    start: End::clamped(Vector3::zeros(), frame),
                    end: End::free().with_force(Vector3::new(0.0, 2.0, 1.0)),
                    route: None,
                }],
                bodies: Vec::new(),
                clips: Vec::new(),
                gravity: Vector3::new(0.0, 0.0, -9.81),
            })
            .unwrap();
            let solution = solve_converged(&model, initial_state(model.system()));
            *solution.state.rods[0].positions.last().unwrap()
        };
        let difference = (tip(nominal.rod) - tip(straight)).norm();
        assert!(difference <= 1e-12, "tips differ by {difference} m");
    }
}

#[test]
fn bad_nominal_shapes_are_rejected() {
    let p = |x: f64, y: f64| Vector3::new(x, y, 0.0);
    let build = |shape: NominalShape| Rod::try_from_nominal(section(), &shape, 10).unwrap_err();
    assert_eq!(
        build(NominalShape::from_points(vec![])),
        NominalError::TooFewPoints(0)
    );
    assert_eq!(
        build(NominalShape::from_points(vec![p(0.0, 0.0)])),
        NominalError::TooFewPoints(1)
    );
    assert_eq!(
        build(NominalShape::from_points(vec![
            p(0.0, 0.0),
            p(0.5, 0.1),
            p(0.5, 0.1),
            p(1.0, 0.0)
        ])),
        NominalError::RepeatedPoint { index: 2 }
    );
    assert_eq!(
        build(NominalShape::from_points(vec![
            p(0.0, 0.0),
            p(f64::NAN, 0.1),
            p(1.0, 0.0)
        ])),
        NominalError::NotFinite {
            what: "points",
            index: 1
        }
    );
    let along_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let line = vec![p(0.0, 0.0), p(0.5, 0.0), p(1.0, 0.0)];
    assert_eq!(
        build(NominalShape {
            points: line.clone(),
            frames: Some(vec![along_x; 2]),
        }),
        NominalError::FrameCount {
            points: 3,
            frames: 2
        }
    );
    let nan_frame =
        UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(f64::NAN, 0.0, 0.0, 0.0));
    assert_eq!(
        build(NominalShape {
            points: line.clone(),
            frames: Some(vec![along_x, nan_frame, along_x]),
        }),
        NominalError::NotFinite {
            what: "frames",
            index: 1
        }
    );
    assert!(matches!(
        build(NominalShape {
            points: line,
            frames: Some(vec![along_x, along_x.inverse(), along_x]),
        }),
        NominalError::FrameAgainstCentreline { index: 1, .. }
    ));
    assert_eq!(
        Rod::try_from_nominal(section(), &s_bend(), 0).unwrap_err(),
        NominalError::Rod(RodError::Segments(0))
    );
    // Every message names the problem.
    assert!(
        NominalError::RepeatedPoint { index: 2 }
            .to_string()
            .contains("points[2] repeats points[1]")
    );
}

#[test]
fn a_finely_cut_moulded_rod_also_stays_in_its_nominal_shape() {
    // 200 segments: the default solve goes through a 24-segment coarse copy first
    // (nested iteration), which leaves the exact start and comes back to it.
    let nominal = Rod::try_from_nominal(section(), &helical_arc(false), 200).unwrap();
    let model = mounted(&nominal, Vector3::zeros());
    for nested_iteration in [true, false] {
        let settings = SolverSettings {
            nested_iteration,
            ..settings()
        };
        let initial = SystemState {
            rods: vec![nominal.state.clone()],
            bodies: Vec::new(),
            clips: Vec::new(),
        };
        let solution = solve(&model, initial, &settings).unwrap();
        assert!(solution.report.converged && solution.report.stable);
        let (d, f, m) = deviation(&model, &nominal, &solution);
        println!(
            "200 segments, nested iteration {nested_iteration}: {} + {} coarse iterations, \
             off the nominal shape {d:.1e} m, |f| ≤ {f:.1e} N, |m| ≤ {m:.1e} N·m",
            solution.report.iterations, solution.report.coarse_iterations
        );
        assert!(d <= 1e-9 && f <= 1e-9 && m <= 1e-9, "{d} m, {f} N, {m} N·m");
        if !nested_iteration {
            assert_eq!(solution.report.iterations, 0);
        }
    }
}
