//! Tests of [`crate::CaseDesign`]'s affine path: the base model moved along a
//! parameter is the model the case builder builds there, for every parameter kind it
//! covers; frame turns are left to the builder; and the sensitivities of N parameters
//! run the builder a fixed number of times per parameter.

use strand_solve::sensitivity::{Design, Sensitivities, SensitivitySettings};
use strand_system::Model;

use crate::{Case, CaseDesign, DesignParameter};

fn case(name: &str) -> Case {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../cases")
        .join(name);
    Case::from_path(&path).unwrap()
}

fn param(item: &str, component: Option<usize>, scale: f64) -> DesignParameter {
    DesignParameter {
        item: item.into(),
        component,
        scale,
    }
}

/// The gradient of `model` at `state` (its held vertices on its supports).
fn gradient(model: &Model, state: &strand_system::SystemState) -> Vec<f64> {
    let mut state = state.clone();
    model.enforce_supports(&mut state);
    let mut eval = model.new_evaluation();
    model.evaluate(&state, &mut eval, false);
    eval.gradient
}

/// For every parameter of `params` on `case`: the design moved along it (at the
/// sensitivities' steps and one off the probes' grid) against a fresh design that
/// builds only through the case builder — the same real numbers to 1e-12 of their
/// size, the same gradient at the base state to 1e-9 of its largest entry, the same
/// environment.
fn affine_path_matches_the_builder(case: &Case, params: &[DesignParameter]) {
    for p in params {
        let design = CaseDesign::new(case, vec![p.clone()]);
        assert!(design.is_affine(0).unwrap(), "{}: not affine", p.item);
        let base = design.build(&[0.0]).unwrap();
        let state = &base.built.initial;
        let clip_vertices: Vec<usize> = base
            .built
            .model
            .system()
            .clips
            .iter()
            .map(|c| c.vertex)
            .collect();
        for t in [1.0, -1.0, 2.0, -2.0, 0.37, 1e-2] {
            let offset = t * 1e-4 * p.scale;
            let fast = design.build(&[offset]).unwrap();
            // A design that has never probed: every build runs the case builder.
            let reference = CaseDesign::new(case, vec![p.clone()]).starting_from(state);
            let before = reference.full_builds();
            let full = {
                let changes = reference.changes(&[offset]);
                case.build_with_changes_reusing("full", &changes, state, Some(&clip_vertices), None)
                    .unwrap()
            };
            assert_eq!(reference.full_builds(), before);
            let (a, b) = (
                fast.built.model.system().reals(),
                full.model.system().reals(),
            );
            assert_eq!(a.len(), b.len(), "{}", p.item);
            let moved = a
                .iter()
                .zip(&base.built.model.system().reals())
                .any(|(x, y)| x != y);
            assert!(moved, "{} at {offset}: the model did not move", p.item);
            for (k, (x, y)) in a.iter().zip(&b).enumerate() {
                let size = x.abs().max(y.abs());
                assert!(
                    (x - y).abs() <= 1e-12 * size,
                    "{} at {offset}: real {k}: {x} (affine) vs {y} (builder)",
                    p.item
                );
            }
            let (ga, gb) = (
                gradient(&fast.built.model, state),
                gradient(&full.model, state),
            );
            let largest = gb.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for (x, y) in ga.iter().zip(&gb) {
                assert!(
                    (x - y).abs() <= 1e-9 * largest,
                    "{} at {offset}: gradient {x} vs {y} (largest {largest})",
                    p.item
                );
            }
            assert_eq!(
                fast.built.environment.len(),
                full.environment.len(),
                "{}",
                p.item
            );
        }
    }
}

#[test]
fn the_affine_path_is_the_builders_model_for_every_kind_it_covers() {
    // Rod length, junction mass, connector position, port position, gravity, a tube's
    // Young's modulus.
    affine_path_matches_the_builder(
        &case("cooler_hose.ron"),
        &[
            param("rods.hose2.length", None, 1000.0),
            param("junctions.tee.mass", None, 100.0),
            param("connectors.oil_cooler.position", Some(2), 1000.0),
            param("junctions.tee.ports.hose3.position", Some(0), 1000.0),
            param("gravity", Some(2), 10.0),
            param("sections.hose_small.youngs_modulus", None, 5e8),
        ],
    );
    // Clip stations and clip base positions; a length of a rod with clips.
    affine_path_matches_the_builder(
        &case("harness_clips.ron"),
        &[
            param("clips.grommet.at", None, 1000.0),
            param("clips.ball.base.position", Some(1), 1000.0),
            param("rods.left.length", None, 1000.0),
        ],
    );
}

#[test]
fn frame_turns_and_mesh_positions_are_left_to_the_builder() {
    let cooler = case("cooler_hose.ron");
    let turns = [
        param("connectors.oil_cooler.direction", Some(0), 572.96),
        param("junctions.tee.ports.hose2.direction", Some(2), 572.96),
    ];
    for p in turns {
        let design = CaseDesign::new(&cooler, vec![p.clone()]);
        assert!(!design.is_affine(0).unwrap(), "{}", p.item);
        // Every step then runs the builder.
        let before = design.full_builds();
        design.build(&[1e-2]).unwrap();
        assert_eq!(design.full_builds(), before + 1, "{}", p.item);
    }
    let contact = case("cooler_hose_contact.ron");
    let mesh = contact.file.environment.first().map(|m| m.name.clone());
    if let Some(name) = mesh {
        let design = CaseDesign::new(
            &contact,
            vec![param(
                &format!("environment.{name}.position"),
                Some(2),
                1000.0,
            )],
        );
        assert!(!design.is_affine(0).unwrap());
    }
}

/// Full builds of the cooler hose's sensitivities with respect to its first `count`
/// parameters (lengths, T mass, connector heights and x positions).
fn builds_for(count: usize) -> (usize, usize) {
    let case = case("cooler_hose.ron");
    let built = case.build(None).unwrap();
    let solution = built
        .solve_from(built.initial.clone(), &built.settings)
        .unwrap();
    assert!(solution.report.converged);
    let mut params: Vec<DesignParameter> = ["hose1", "hose2", "hose3"]
        .iter()
        .map(|r| param(&format!("rods.{r}.length"), None, 1000.0))
        .collect();
    params.push(param("junctions.tee.mass", None, 100.0));
    for c in [2, 0] {
        for n in ["radiator_outlet", "oil_cooler", "engine_stub"] {
            params.push(param(&format!("connectors.{n}.position"), Some(c), 1000.0));
        }
    }
    params.truncate(count);
    let design = CaseDesign::new(&case, params).starting_from(&solution.state);
    let sens = Sensitivities::compute(&design, &solution, &SensitivitySettings::default()).unwrap();
    assert_eq!(sens.parameters.len(), count);
    // The first-order path of every parameter as the outputs' differences walk it.
    for j in 0..count {
        for t in [1.0, -1.0, 2.0, -2.0, 0.1, 0.01] {
            let mut offsets = vec![0.0; count];
            offsets[j] = t * sens.parameters[j].output_step;
            design.build(&offsets).unwrap();
        }
    }
    (design.full_builds(), count)
}

#[test]
fn sensitivities_run_the_case_builder_twice_per_parameter() {
    // One base build and two probes per parameter, however many steps the
    // differences take (before: four builds per parameter for the right-hand sides,
    // twelve more per parameter for the outputs).
    for count in [3, 10] {
        let (builds, n) = builds_for(count);
        assert_eq!(builds, 1 + 2 * n, "{n} parameters");
    }
}

#[test]
fn a_recentred_design_takes_over_the_probes_where_the_model_stays_affine() {
    let cooler = case("cooler_hose.ron");
    let params = vec![
        param("rods.hose2.length", None, 1000.0),
        param("junctions.tee.mass", None, 100.0),
        param("connectors.oil_cooler.position", Some(2), 1000.0),
    ];
    let design = CaseDesign::new(&cooler, params.clone());
    assert!(!design.is_analysed());
    design.analyse().unwrap();
    assert!(design.is_analysed());
    // Every parameter moved at once, far beyond the probes' steps.
    let next = design.recentred(vec![25.0, 0.3, -12.0]).unwrap();
    assert!(next.is_analysed(), "the probes were not taken over");
    let builds = next.full_builds();
    let base = next.build(&[0.0; 3]).unwrap();
    let state = &base.built.initial;
    for (j, p) in params.iter().enumerate() {
        for t in [1.0, -2.0, 0.37] {
            let mut offsets = [0.0; 3];
            offsets[j] = t * 1e-4 * p.scale;
            let fast = next.build(&offsets).unwrap();
            let full = cooler
                .build_with_changes_reusing("full", &next.changes(&offsets), state, Some(&[]), None)
                .unwrap();
            let (a, b) = (
                fast.built.model.system().reals(),
                full.model.system().reals(),
            );
            assert_eq!(a.len(), b.len());
            for (k, (x, y)) in a.iter().zip(&b).enumerate() {
                assert!(
                    (x - y).abs() <= 1e-12 * x.abs().max(y.abs()),
                    "{} at {offsets:?}: real {k}: {x} (taken-over probe) vs {y} (builder)",
                    p.item
                );
            }
        }
    }
    // Only the builds of the new base: every step moved the base model.
    assert_eq!(next.full_builds(), builds);
    // A frame's turn is not affine: where it moved, the new design probes afresh;
    // where only the affine parameters moved, it takes the probes over.
    let turning = vec![
        param("rods.hose2.length", None, 1000.0),
        param("connectors.oil_cooler.direction", Some(0), 572.96),
    ];
    let design = CaseDesign::new(&cooler, turning);
    design.analyse().unwrap();
    assert!(!design.recentred(vec![0.0, 5.0]).unwrap().is_analysed());
    assert!(design.recentred(vec![10.0, 0.0]).unwrap().is_analysed());
}

#[test]
fn a_kept_moved_design_is_the_one_moved_at_that_parameter_and_offset() {
    let cooler = case("cooler_hose.ron");
    let params = vec![
        param("rods.hose2.length", None, 1000.0),
        param("rods.hose3.length", None, 1000.0),
    ];
    let design = CaseDesign::new(&cooler, params.clone());
    design.analyse().unwrap();
    // The moved model's real numbers and its gradient at the base's initial state.
    let reals = |offsets: &[f64]| {
        let built = design.build(offsets).unwrap();
        let g = gradient(&built.built.model, &built.built.initial);
        (built.built.model.system().reals(), g)
    };
    // The same offset of the two parameters, each twice (the second time taking the
    // kept design), and a second offset of the first.
    let h = 0.1;
    let first = reals(&[h, 0.0]);
    let other = reals(&[0.0, h]);
    let smaller = reals(&[h / 10.0, 0.0]);
    assert_ne!(first.0, other.0, "the key must tell the parameters apart");
    assert_ne!(first.0, smaller.0, "the key must tell the offsets apart");
    assert_eq!(reals(&[h, 0.0]), first);
    assert_eq!(reals(&[0.0, h]), other);
    // Taken once: a third build moves the base again, to the same design.
    assert_eq!(reals(&[h, 0.0]), first);
    // A fresh design that moves it anew agrees bit for bit.
    let fresh = CaseDesign::new(&cooler, params);
    let built = fresh.build(&[0.0, h]).unwrap();
    assert_eq!(built.built.model.system().reals(), other.0);
}

/// A design point whose parameters make the case invalid (the pinned cable 300 mm
/// shorter: 500 mm between studs 640 mm apart) is an error that names the point and
/// the rule, not a variant of the case — by the builder, and along the affine path of
/// an analysed design.
#[test]
fn a_design_point_the_case_forbids_is_named_as_that_point() {
    let pinned = case("pinned_cable.ron");
    let params = vec![param("rods.cable.length", None, 1000.0)];
    let fresh = CaseDesign::new(&pinned, params.clone());
    let analysed = CaseDesign::new(&pinned, params);
    analysed.analyse().unwrap();
    for design in [&fresh, &analysed] {
        let error = design.build(&[-300.0]).err().expect("a rod too short");
        let text = error.to_string();
        assert!(
            text.contains("the design at rods.cable.length -300: rod 'cable' is 0.500000 m long"),
            "{text}"
        );
        assert!(!text.contains("variant"), "{text}");
        assert!(
            error.summary().starts_with("the design at"),
            "{}",
            error.summary()
        );
        assert!(!error.summary().contains("hint"), "{}", error.summary());
        // Within the 10 % of strain the builder allows, the point builds.
        design.build(&[-170.0]).unwrap();
    }
}
