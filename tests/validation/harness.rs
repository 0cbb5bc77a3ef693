//! The clipped cable harness `cases/harness_clips.ron`: a trunk and two branches on a
//! free breakout, held by connectors and by clips of every joint kind, under gravity.
//!
//! Checks that it converges to a stable equilibrium; that connectors and clips fixed in
//! space carry the whole weight (≤ 1e-9 relative) and each free body (the breakout, with
//! a clip mounted on it, and the hose-to-hose clip) balances its own weight with its
//! ports and clips; that every joint transmits nothing along its
//! freedom (a revolute clip no moment about its axis, the rail no force along it, the
//! ball no moment); that the limited hinge is either inside its limits with no moment
//! about its axis or at a limit with a moment that holds it there; and that
//! `result.json`'s `clips` agree with the model.

use nalgebra::Vector3;
use strand_case::Case;
use strand_report::{Timing, collect};
use strand_solve::solve;
use strand_system::{Joint, ReactionKind};

use crate::common::cases_dir;

#[test]
fn the_clipped_harness_is_in_equilibrium_and_its_joints_transmit_what_they_should() {
    let built = Case::from_path(cases_dir().join("harness_clips.ron"))
        .unwrap()
        .build(None)
        .unwrap();
    let solution = solve(&built.model, built.initial.clone(), &built.settings).unwrap();
    let report = &solution.report;
    assert!(report.converged, "not converged: {report:?}");
    assert!(
        report.residual.combined_n <= 1e-9,
        "residual {} N",
        report.residual.combined_n
    );
    assert!(report.stable, "equilibrium not stable");

    let system = built.model.system();
    let state = &solution.state;
    let reactions = built.model.reactions(state);
    let kinds = |kind| reactions.iter().filter(|r| r.kind == kind).count();
    assert_eq!(
        (
            kinds(ReactionKind::Connector),
            kinds(ReactionKind::Port),
            kinds(ReactionKind::Clip)
        ),
        (3, 3, 9)
    );

    // Global balance: connectors and the clips fixed in space carry the cables, the
    // breakout and the twin clip (clips on bodies are internal).
    let mass: f64 = system.rods.iter().map(|r| r.rod.mass()).sum::<f64>()
        + system.bodies.iter().map(|b| b.mass).sum::<f64>();
    let weight = mass * system.gravity;
    // The body a clip's chain is mounted on (`None`: the chain starts in the world).
    let on_body = |name: &str| {
        let c = system.clips.iter().position(|c| c.name == name)?;
        system.clips[system.chain_root(c)].body
    };
    let external: Vec<_> = reactions
        .iter()
        .filter(|r| {
            r.kind == ReactionKind::Connector
                || (r.kind == ReactionKind::Clip && on_body(&r.name).is_none())
        })
        .collect();
    let force = external.iter().map(|r| r.force).sum::<Vector3<f64>>() + weight;
    assert!(
        force.norm() <= 1e-9 * weight.norm(),
        "force imbalance {force:?} (weight {weight:?})"
    );
    // ... and in moment, about the origin.
    let mut moment = external
        .iter()
        .map(|r| r.moment + r.position.cross(&r.force))
        .sum::<Vector3<f64>>();
    for (r, spec) in system.rods.iter().enumerate() {
        for (j, p) in state.rods[r].positions.iter().enumerate() {
            moment += p.cross(&(spec.rod.vertex_mass(j) * system.gravity));
        }
    }
    for (b, body) in system.bodies.iter().enumerate() {
        moment += state.bodies[b]
            .transform_point(&body.center_of_mass)
            .cross(&(body.mass * system.gravity));
    }
    let scale = weight.norm() * 1.4;
    assert!(moment.norm() <= 1e-9 * scale, "moment imbalance {moment:?}");

    // Each free body (the breakout and the twin clip) balances its weight with what
    // its ports and its clips exert on the rods (the body feels the opposite).
    for (b, body) in system.bodies.iter().enumerate() {
        let name = body.name.as_str();
        let carried: Vec<_> = reactions
            .iter()
            .filter(|r| match r.kind {
                ReactionKind::Port => r.name.starts_with(&format!("{name}.")),
                ReactionKind::Clip => on_body(&r.name).is_some_and(|h| h.0 == b),
                ReactionKind::Connector => false,
            })
            .collect();
        assert!(!carried.is_empty(), "{name} holds rods");
        let weight = body.mass * system.gravity;
        let force = weight - carried.iter().map(|r| r.force).sum::<Vector3<f64>>();
        let centre = state.bodies[b].transform_point(&body.center_of_mass);
        let moment = centre.cross(&weight)
            - carried
                .iter()
                .map(|r| r.moment + r.position.cross(&r.force))
                .sum::<Vector3<f64>>();
        let scale = carried.iter().map(|r| r.force.norm()).sum::<f64>();
        assert!(
            force.norm() <= 1e-9 * scale,
            "{name}: force imbalance {force:?}"
        );
        assert!(
            moment.norm() <= 1e-9 * scale * 1.4,
            "{name}: moment imbalance {moment:?}"
        );
    }

    // What each joint transmits: everything its clip and the clips mounted on it (its
    // chain's downstream part) exert on the cables, about the joint's base origin.
    let clip_reaction = |name: &str| {
        reactions
            .iter()
            .find(|r| r.kind == ReactionKind::Clip && r.name == name)
            .unwrap()
    };
    let downstream = |c: usize| {
        (0..system.clips.len()).filter(move |&k| {
            let mut link = Some(k);
            while let Some(l) = link {
                if l == c {
                    return true;
                }
                link = system.clips[l].parent;
            }
            false
        })
    };
    let mut seen = Vec::new();
    for (c, clip) in system.clips.iter().enumerate() {
        assert!(
            clip_reaction(&clip.name).force.norm() > 1e-3,
            "clip '{}' carries the cable",
            clip.name
        );
        let origin = system.clip_base(c, &state.clips, &state.bodies).position;
        let (mut force, mut moment) = (Vector3::zeros(), Vector3::zeros());
        for k in downstream(c) {
            let r = clip_reaction(&system.clips[k].name);
            force += r.force;
            moment += r.moment + (r.position - origin).cross(&r.force);
        }
        let value = state.clips[c].value;
        match clip.joint {
            Joint::Fixed => seen.push("fixed"),
            Joint::Spherical => {
                assert!(moment.norm() <= 1e-9, "ball '{}': {moment:?}", clip.name);
                seen.push("spherical");
            }
            Joint::Prismatic { axis } => {
                let base = system.clip_base(c, &state.clips, &state.bodies).orientation;
                let along = force.dot(&(base * axis));
                assert!(
                    along.abs() <= 1e-9 * force.norm().max(1.0),
                    "rail '{}': {along} N along",
                    clip.name
                );
                assert!(value.abs() > 1e-5, "the rail slides: {value} m");
                seen.push("prismatic");
            }
            Joint::Revolute { axis } => {
                let base = system.clip_base(c, &state.clips, &state.bodies).orientation;
                let about = moment.dot(&(base * axis));
                let tolerance = 1e-9 * moment.norm().max(1.0);
                match clip.limits {
                    None => {
                        assert!(
                            about.abs() <= tolerance,
                            "revolute '{}': {about} N·m about its axis",
                            clip.name
                        );
                        seen.push("revolute");
                    }
                    Some((lower, upper)) => {
                        assert!(
                            (lower..=upper).contains(&value),
                            "hinge '{}' at {value} rad",
                            clip.name
                        );
                        let near = |limit: f64| (value - limit).abs() <= 1e-12;
                        if near(lower) || near(upper) {
                            // The stop holds the joint: the rod pushes the joint beyond the
                            // limit, so the moment on the rod about the axis points back
                            // into the range (opposes the rotation beyond it).
                            assert!(about.abs() > 1e-6, "the stop carries a moment: {about}");
                            let into_range = if near(upper) { -1.0 } else { 1.0 };
                            assert!(
                                about * into_range > 0.0,
                                "hinge '{}' at {value}: moment {about} about the axis",
                                clip.name
                            );
                            seen.push("hinge at limit");
                        } else {
                            assert!(
                                about.abs() <= tolerance,
                                "hinge '{}' inside its limits: {about}",
                                clip.name
                            );
                            seen.push("hinge inside");
                        }
                    }
                }
            }
        }
        // The clipped vertex sits at the clip's output origin.
        let output = system.clip_output(c, &state.clips, &state.bodies);
        assert!((state.rods[clip.rod.0].positions[clip.vertex] - output.position).norm() < 1e-12);
    }
    seen.sort_unstable();
    assert_eq!(seen.len(), 9);
    for kind in ["fixed", "prismatic", "revolute", "spherical"] {
        assert!(seen.contains(&kind), "{kind} missing: {seen:?}");
    }
    assert!(seen.iter().any(|s| s.starts_with("hinge")), "{seen:?}");

    // result.json: the clips section agrees with the model.
    let doc = collect(&built.name, &built.model, &solution, Timing::default());
    assert_eq!(doc.clips.len(), 9);
    let json = serde_json::to_value(&doc).unwrap();
    for (c, (clip, result)) in system.clips.iter().zip(&doc.clips).enumerate() {
        assert_eq!(result.name, clip.name);
        assert_eq!(result.rod, system.rods[clip.rod.0].name);
        assert_eq!(
            result.s_m,
            system.rods[clip.rod.0].rod.arc_lengths()[clip.vertex]
        );
        let reaction = reactions
            .iter()
            .find(|r| r.kind == ReactionKind::Clip && r.name == clip.name)
            .unwrap();
        assert_eq!(
            result.force_n,
            [reaction.force.x, reaction.force.y, reaction.force.z]
        );
        let entry = &json["clips"][c];
        match clip.joint {
            Joint::Fixed | Joint::Spherical => assert!(entry["value"].is_null(), "{entry}"),
            Joint::Revolute { .. } | Joint::Prismatic { .. } => {
                assert_eq!(entry["value"].as_f64(), Some(state.clips[c].value))
            }
        }
        assert_eq!(
            entry["rotation_wxyz"].is_null(),
            clip.joint != Joint::Spherical,
            "{entry}"
        );
        let value = state.clips[c].value;
        let at_limit = clip
            .limits
            .is_some_and(|(l, u)| (value - l).abs() <= 1e-12 || (value - u).abs() <= 1e-12);
        assert_eq!(result.at_limit, at_limit, "{}", clip.name);
        assert!(entry["force_N"].is_array() && entry["moment_Nm"].is_array());
    }
    // The trunk's clips sit where the file says (mm → m).
    let s = |name: &str| doc.clips.iter().find(|c| c.name == name).unwrap().s_m;
    for (name, at) in [
        ("grommet", 0.25),
        ("bracket", 0.5),
        ("hinge", 0.2),
        ("ball", 0.45),
        ("rail", 0.3),
        ("sleeve", 0.34),
        ("strain_relief", 0.7),
        ("twin_left", 0.04),
        ("twin_right", 0.04),
    ] {
        assert!((s(name) - at).abs() <= 1e-15, "{name}: {}", s(name));
    }
}
