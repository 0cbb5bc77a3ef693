//! Clips: what each joint kind transmits, and a fixed clip as the junction of two rods.

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::sectional::sectional;
use strand_rod::{Rod, Section};
use strand_system::{ClipSpec, End, Joint, Pose, ReactionKind, RodHandle, RodSpec, System};

use crate::common::{frame_along_x, solve_converged};

fn hose_section() -> Section {
    Section::try_explicit(3e4, 1e4, 0.05, 0.04, 0.4, 0.01).unwrap()
}

/// A hose clamped at the origin along +x, loaded at its free end and by gravity, held
/// at its middle vertex by a clip with `joint` whose base is tilted.
fn clipped_hose(joint: Joint, limits: Option<(f64, f64)>) -> System {
    let base = Pose {
        position: Vector3::new(0.5, 0.05, -0.03),
        orientation: UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.4),
    };
    System {
        rods: vec![RodSpec {
            name: "hose".into(),
            rod: Rod::try_straight(hose_section(), 1.0, 40).unwrap(),
            start: End::clamped(Vector3::zeros(), frame_along_x()),
            end: End::free().with_force(Vector3::new(0.2, -0.3, 0.1)),
            route: None,
        }],
        bodies: vec![],
        clips: vec![ClipSpec {
            parent: None,
            body: None,
            name: "clip".into(),
            base,
            joint,
            offset: Pose {
                position: Vector3::zeros(),
                orientation: base.orientation.inverse() * frame_along_x(),
            },
            rod: RodHandle(0),
            vertex: 20,
            limits,
        }],
        gravity: Vector3::new(0.0, 0.0, -9.81),
    }
}

/// Solves and returns the clip reaction (force N, moment N·m on the rod) and the
/// world axis of the joint.
fn clip_reaction(joint: Joint, axis: Vector3<f64>) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let system = clipped_hose(joint, None);
    let world_axis = system.clips[0].base.orientation * axis;
    let (model, solution) = solve_converged(system);
    let clip = model
        .reactions(&solution.state)
        .into_iter()
        .find(|r| r.kind == ReactionKind::Clip)
        .unwrap();
    (clip.force, clip.moment, world_axis)
}

#[test]
fn a_revolute_clip_transmits_no_moment_about_its_axis() {
    let axis = Vector3::new(0.0, 0.6, 0.8);
    let (force, moment, world_axis) = clip_reaction(Joint::Revolute { axis }, axis);
    assert!(
        moment.norm() > 1e-3 && force.norm() > 1e-2,
        "the clip carries load"
    );
    assert!(
        moment.dot(&world_axis).abs() <= 1e-9 * moment.norm().max(1.0),
        "{moment:?}"
    );
}

#[test]
fn a_prismatic_clip_transmits_no_force_along_its_rail() {
    let axis = Vector3::new(0.0, 0.0, 1.0);
    let (force, moment, world_axis) = clip_reaction(Joint::Prismatic { axis }, axis);
    assert!(
        moment.norm() > 1e-3 && force.norm() > 1e-2,
        "the clip carries load"
    );
    assert!(
        force.dot(&world_axis).abs() <= 1e-9 * force.norm().max(1.0),
        "{force:?}"
    );
}

#[test]
fn a_spherical_clip_transmits_no_moment() {
    let (force, moment, _) = clip_reaction(Joint::Spherical, Vector3::z());
    assert!(force.norm() > 1e-2, "the clip carries load");
    assert!(moment.norm() <= 1e-9, "{moment:?}");
}

#[test]
fn a_fixed_clip_at_mid_length_splits_a_rod_into_two_clamped_rods() {
    // One rod clamped at both ends and held at its middle vertex by a fixed clip ...
    let clip_frame = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.3) * frame_along_x();
    let clip_pose = Pose {
        position: Vector3::new(0.45, 0.1, 0.02),
        orientation: clip_frame,
    };
    let (a, b) = (Vector3::zeros(), Vector3::new(0.9, 0.05, 0.0));
    let clipped = System {
        rods: vec![RodSpec {
            name: "whole".into(),
            rod: Rod::try_straight(hose_section(), 1.0, 40).unwrap(),
            start: End::clamped(a, frame_along_x()),
            end: End::clamped(b, frame_along_x()),
            route: None,
        }],
        bodies: vec![],
        clips: vec![ClipSpec {
            parent: None,
            body: None,
            name: "clip".into(),
            base: clip_pose,
            joint: Joint::Fixed,
            offset: Pose {
                position: Vector3::zeros(),
                orientation: UnitQuaternion::identity(),
            },
            rod: RodHandle(0),
            vertex: 20,
            limits: None,
        }],
        gravity: Vector3::new(0.0, 0.0, -9.81),
    };
    // ... is the same as two rods clamped at the clip frame.
    let half = |name: &str, start: End, end: End| RodSpec {
        name: name.into(),
        rod: Rod::try_straight(hose_section(), 0.5, 20).unwrap(),
        start,
        end,
        route: None,
    };
    let split = System {
        rods: vec![
            half(
                "first",
                End::clamped(a, frame_along_x()),
                End::clamped(clip_pose.position, clip_frame),
            ),
            half(
                "second",
                End::clamped(clip_pose.position, clip_frame),
                End::clamped(b, frame_along_x()),
            ),
        ],
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::new(0.0, 0.0, -9.81),
    };
    let (clipped_model, whole) = solve_converged(clipped);
    let (split_model, halves) = solve_converged(split);
    let positions = &whole.state.rods[0].positions;
    for j in 0..=20 {
        assert!(
            (positions[j] - halves.state.rods[0].positions[j]).norm() < 1e-10,
            "vertex {j}"
        );
        assert!(
            (positions[20 + j] - halves.state.rods[1].positions[j]).norm() < 1e-10,
            "vertex {}",
            20 + j
        );
    }
    // Sectional moments: at the clip, the moment just beyond it (the second rod's start).
    let whole_out = sectional(
        &clipped_model.system().rods[0].rod,
        &whole.state.rods[0],
        &clipped_model.boundary_frames(0, &whole.state),
    );
    let second_out = sectional(
        &split_model.system().rods[1].rod,
        &halves.state.rods[1],
        &split_model.boundary_frames(1, &halves.state),
    );
    for j in 0..=20 {
        assert!(
            (whole_out.moments[20 + j] - second_out.moments[j]).norm() < 1e-9,
            "moment at vertex {}",
            20 + j
        );
    }
    // The clip carries what the two inner clamps carry together.
    let clip = clipped_model
        .reactions(&whole.state)
        .into_iter()
        .find(|r| r.kind == ReactionKind::Clip)
        .unwrap();
    let inner: Vec<_> = split_model
        .reactions(&halves.state)
        .into_iter()
        .filter(|r| r.name == "first.end" || r.name == "second.start")
        .collect();
    let (force, moment) = inner
        .iter()
        .fold((Vector3::zeros(), Vector3::zeros()), |(f, m), r| {
            (f + r.force, m + r.moment)
        });
    assert!(
        (clip.force - force).norm() < 1e-9 && (clip.moment - moment).norm() < 1e-9,
        "{clip:?} vs {force:?} {moment:?}"
    );
}

#[test]
fn a_clip_at_its_limit_carries_a_reaction_of_the_right_sign_and_none_once_released() {
    let axis = Vector3::new(0.0, 0.6, 0.8);
    let joint = Joint::Revolute { axis };
    // Free: the joint settles at some angle with no moment about its axis.
    let (model, free) = solve_converged(clipped_hose(joint, None));
    let free_angle = free.state.clips[0].value;
    let world_axis = model.system().clips[0].base.orientation * axis;
    assert!(
        free_angle.abs() > 0.02,
        "the load turns the joint ({free_angle} rad)"
    );
    // A stop at a third of that angle holds the joint there and carries a moment that
    // opposes the turn: the rod pushes the joint towards `free_angle`.
    let stop = free_angle / 3.0;
    let limits = if stop > 0.0 {
        (-1.0, stop)
    } else {
        (stop, 1.0)
    };
    let (model, held) = solve_converged(clipped_hose(joint, Some(limits)));
    assert!(
        (held.state.clips[0].value - stop).abs() < 1e-12,
        "at the stop: {}",
        held.state.clips[0].value
    );
    let reaction = model
        .reactions(&held.state)
        .into_iter()
        .find(|r| r.kind == ReactionKind::Clip)
        .unwrap();
    let about_axis = reaction.moment.dot(&world_axis);
    assert!(about_axis.abs() > 1e-4, "the stop carries a moment");
    assert!(
        about_axis * free_angle < 0.0,
        "the stop's moment on the rod opposes the turn: {about_axis} vs {free_angle}"
    );
    // Limits wider than the free angle change nothing.
    let wide = (-2.0 * free_angle.abs(), 2.0 * free_angle.abs());
    let (model, released) = solve_converged(clipped_hose(joint, Some(wide)));
    assert!((released.state.clips[0].value - free_angle).abs() < 1e-9);
    let reaction = model
        .reactions(&released.state)
        .into_iter()
        .find(|r| r.kind == ReactionKind::Clip)
        .unwrap();
    assert!(
        reaction.moment.dot(&world_axis).abs() < 1e-9,
        "no stop moment once released"
    );
}

#[test]
fn nested_iteration_keeps_clipped_vertices() {
    // 100 segments trigger the coarse-to-fine start; the clip must hold the same vertex
    // on the coarse copy, and the result must equal the plain Newton solve.
    let mut system = clipped_hose(
        Joint::Revolute {
            axis: Vector3::new(0.0, 0.6, 0.8),
        },
        None,
    );
    system.rods[0].rod = Rod::try_straight(hose_section(), 1.0, 100).unwrap();
    system.clips[0].vertex = 50;
    let plain = strand_solve::SolverSettings {
        nested_iteration: false,
        ..Default::default()
    };
    let (_, direct) = crate::common::solve_converged_with(system.clone(), &plain);
    let (_, nested) = solve_converged(system);
    assert!(nested.report.coarse_iterations > 0);
    for (a, b) in direct.state.rods[0]
        .positions
        .iter()
        .zip(&nested.state.rods[0].positions)
    {
        assert!((a - b).norm() < 1e-9);
    }
    assert!((direct.state.clips[0].value - nested.state.clips[0].value).abs() < 1e-9);
}
