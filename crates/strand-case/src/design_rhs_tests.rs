//! The right-hand sides of a case design's sensitivities evaluate only the elements a
//! parameter changes ([`strand_system::Model::gradient_difference`]): a junction's
//! mass and a connector's position touch a fixed number of elements however finely
//! the hoses are cut, a hose's length that hose's elements; and the derivatives are
//! those of the whole models' gradients (the reference path) to round-off. The
//! closed-form right-hand sides along affine parameters
//! ([`strand_system::Model::gradient_derivative`]) agree with those differences for
//! every kind of parameter, build no design and evaluate each changed element once.

use strand_solve::sensitivity::{Sensitivities, SensitivitySettings};

use crate::{Case, CaseDesign, DesignParameter};

/// The cooler hose with every hose cut into `factor` times its segments.
fn cooler(factor: usize) -> Case {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/cooler_hose.ron");
    let mut text = std::fs::read_to_string(&path).unwrap();
    for segments in [40, 19, 35] {
        let line = format!("segments: {segments},");
        assert!(text.contains(&line), "{line}");
        text = text.replace(&line, &format!("segments: {},", factor * segments));
    }
    Case::from_str(&text, &path.to_string_lossy()).unwrap()
}

/// The T's mass, the oil cooler's height and hose 2's length.
fn parameters() -> Vec<DesignParameter> {
    let param = |item: &str, component, scale| DesignParameter {
        item: item.into(),
        component,
        scale,
    };
    vec![
        param("junctions.tee.mass", None, 100.0),
        param("connectors.oil_cooler.position", Some(2), 1000.0),
        param("rods.hose2.length", None, 1000.0),
    ]
}

/// Per parameter, the right-hand side's elements with the element differences and
/// with the whole gradients; the derivatives of the two paths agree to 1e-12 of their
/// largest entry.
fn elements_at(factor: usize) -> (Vec<usize>, Vec<usize>) {
    let case = cooler(factor);
    let built = case.build(None).unwrap();
    let solution = built
        .solve_from(built.initial.clone(), &built.settings)
        .unwrap();
    assert!(solution.report.converged);
    let compute = |element_differences| {
        let design = CaseDesign::new(&case, parameters()).starting_from(&solution.state);
        // The differences of built designs (not the closed forms, which build none).
        let settings = SensitivitySettings {
            element_differences,
            exact_right_hand_sides: false,
            ..SensitivitySettings::default()
        };
        Sensitivities::compute(&design, &solution, &settings).unwrap()
    };
    let (fast, full) = (compute(true), compute(false));
    for (j, (a, b)) in fast.parameters.iter().zip(&full.parameters).enumerate() {
        let inf = |x: &[f64]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let scale = inf(&b.state);
        assert!(scale > 0.0, "parameter {j} moves nothing");
        for (k, (x, y)) in a.state.iter().zip(&b.state).enumerate() {
            assert!(
                (x - y).abs() <= 1e-12 * scale,
                "×{factor}, parameter {j}, unknown {k}: {x} (differences) vs {y} (whole gradients)"
            );
        }
        let m_scale = inf(&b.multipliers).max(1e-300);
        for (x, y) in a.multipliers.iter().zip(&b.multipliers) {
            assert!(
                (x - y).abs() <= 1e-12 * m_scale,
                "parameter {j}: dμ/dp {x} vs {y}"
            );
        }
    }
    let count = |s: &Sensitivities| s.parameters.iter().map(|p| p.rhs_elements).collect();
    (count(&fast), count(&full))
}

#[test]
fn a_mass_or_a_connector_evaluates_a_fixed_number_of_elements_at_any_segment_count() {
    let (coarse, coarse_full) = elements_at(1);
    let (fine, fine_full) = elements_at(2);
    // The mass enters linearly: one difference, the T's weight alone.
    assert_eq!(coarse[0], 1);
    assert_eq!(fine[0], 1);
    // The connector: two differences (Richardson), each the hose's end edge there.
    assert_eq!(coarse[1], 2);
    assert_eq!(fine[1], 2);
    // Hose 2's length: its own elements (19 and 38 edges), per difference, and no
    // more than a few beyond them; the whole gradients evaluate every element.
    for (elements, edges) in [(coarse[2], 19), (fine[2], 38)] {
        assert!(
            (2 * 2 * edges..=2 * (2 * edges + 8)).contains(&elements),
            "{elements} elements for {edges} edges"
        );
    }
    assert!(coarse_full[2] > 3 * coarse[2]);
    assert!(2 * fine_full[0] > 3 * coarse_full[0]);
}

/// A case from `cases/`.
fn shipped(name: &str) -> Case {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../cases")
        .join(name);
    Case::from_path(&path).unwrap()
}

/// Solves `case` and computes its sensitivities for `parameters` with the
/// closed-form right-hand sides (the default) and with the differences of built
/// designs (the reference path); checks that `dδ/dp` agree to `1e-7` of each
/// parameter's largest entry (the differences' own truncation and round-off), and
/// returns both.
fn exact_against_differences(
    case: &Case,
    parameters: Vec<DesignParameter>,
) -> (Sensitivities, Sensitivities) {
    let built = case.build(None).unwrap();
    let solution = built
        .solve_from(built.initial.clone(), &built.settings)
        .unwrap();
    assert!(solution.report.converged);
    let compute = |exact_right_hand_sides| {
        let design = CaseDesign::new(case, parameters.clone()).starting_from(&solution.state);
        let settings = SensitivitySettings {
            exact_right_hand_sides,
            ..SensitivitySettings::default()
        };
        Sensitivities::compute(&design, &solution, &settings).unwrap()
    };
    let (exact, differenced) = (compute(true), compute(false));
    for (j, (a, b)) in exact
        .parameters
        .iter()
        .zip(&differenced.parameters)
        .enumerate()
    {
        let inf = |x: &[f64]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let scale = inf(&b.state);
        assert!(scale > 0.0, "{}: parameter {j} moves nothing", case.origin);
        let error = a
            .state
            .iter()
            .zip(&b.state)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        println!(
            "{} {}: |dδ/dp| {scale:.3e}, closed form against differences {:.2e} relative ({} designs, {} elements; differences {} designs, {} elements)",
            case.origin,
            parameters[j].item,
            error / scale,
            a.rhs_designs,
            a.rhs_elements,
            b.rhs_designs,
            b.rhs_elements
        );
        assert!(
            error <= 1e-7 * scale,
            "{} {}: closed form against differences {error:.3e} of {scale:.3e}",
            case.origin,
            parameters[j].item
        );
        assert!(b.rhs_designs > 0, "the reference path builds designs");
    }
    (exact, differenced)
}

fn param(item: &str, component: Option<usize>, scale: f64) -> DesignParameter {
    DesignParameter {
        item: item.into(),
        component,
        scale,
    }
}

/// Every kind of parameter of the cooler hose: the affine ones (lengths, connector
/// positions, the T's mass, gravity, a tube's Young's modulus) take the closed form
/// and build no design; a port's position (the T's geometry) and a connector's
/// direction (a turn: not affine) take the differences; all agree with the
/// differences of built designs.
#[test]
fn closed_form_right_hand_sides_match_the_differences_on_the_cooler_hose() {
    let case = cooler(1);
    let parameters = vec![
        param("rods.hose2.length", None, 1000.0),
        param("rods.hose1.length", None, 1000.0),
        param("connectors.oil_cooler.position", Some(2), 1000.0),
        param("connectors.radiator_outlet.position", Some(0), 1000.0),
        param("junctions.tee.mass", None, 100.0),
        param("gravity", Some(2), 10.0),
        param("sections.hose_small.youngs_modulus", None, 5e8),
        param("junctions.tee.ports.hose3.position", Some(1), 1000.0),
        param("connectors.oil_cooler.direction", Some(0), 90.0),
    ];
    let (exact, _) = exact_against_differences(&case, parameters);
    let designs: Vec<usize> = exact.parameters.iter().map(|p| p.rhs_designs).collect();
    assert_eq!(
        &designs[..7],
        &[0; 7],
        "the affine parameters build no design"
    );
    assert!(designs[7] > 0 && designs[8] > 0, "{designs:?}");
}

/// The moulded clipped hose (rest curvatures, a fixed and a revolute clip): the
/// section's stiffness and gravity take the closed form (the clip half cells
/// included) and agree with the differences; a clip's station, which moves and turns
/// a clip without a base of its own, takes the differences. (A clip's base moves the
/// chain of the elements at the clip: the closed forms leave it to the differences,
/// `strand_system`'s tests.)
#[test]
fn closed_form_right_hand_sides_match_the_differences_with_clips() {
    let case = shipped("moulded_clipped_hose.ron");
    let parameters = vec![
        param("clips.clip_a.at", None, 1000.0),
        param("sections.rubber.youngs_modulus", None, 5e6),
        param("gravity", Some(2), 10.0),
    ];
    let (exact, _) = exact_against_differences(&case, parameters);
    let designs: Vec<usize> = exact.parameters.iter().map(|p| p.rhs_designs).collect();
    // The clip sits at the nominal frame at its station: moving the station moves
    // and turns the clip itself (not affine), so it takes the differences.
    assert_eq!(designs, vec![4, 0, 0], "{designs:?}");
}

/// The work of the closed-form right-hand sides: no design built for any affine
/// parameter, one element for the T's mass and for a connector's position however
/// finely the hoses are cut, a hose's own elements for its length (half the
/// differences' count, which evaluate them at two steps).
#[test]
fn closed_form_right_hand_sides_evaluate_each_changed_element_once() {
    for factor in [1, 2] {
        let case = cooler(factor);
        let (exact, differenced) = exact_against_differences(&case, parameters());
        let elements: Vec<usize> = exact.parameters.iter().map(|p| p.rhs_elements).collect();
        let designs: Vec<usize> = exact.parameters.iter().map(|p| p.rhs_designs).collect();
        assert_eq!(designs, vec![0, 0, 0], "×{factor}");
        assert_eq!(&elements[..2], &[1, 1], "×{factor}: {elements:?}");
        assert_eq!(
            2 * elements[2],
            differenced.parameters[2].rhs_elements,
            "×{factor}: a length's elements once, not at two steps"
        );
    }
}

/// With active contact rows the closed form takes the rows' part from the rows near
/// the active ones at the model moved along the line, and none at all where the line
/// moves nothing they read: it agrees with the differences of built designs on the
/// contact cases and builds no design; it evaluates rows only for a connector whose
/// held end is next to a contact (the groove's hose laid straight along the crease,
/// touching both flanks from its first free vertex on), at `±h` and `±2h`.
#[test]
fn closed_form_right_hand_sides_match_the_differences_with_active_contact_rows() {
    let evaluations = |case: &Case, parameters: Vec<DesignParameter>| {
        let (exact, _) = exact_against_differences(case, parameters);
        assert!(!exact.active.is_empty(), "{}: no contact", case.origin);
        let designs: Vec<usize> = exact.parameters.iter().map(|p| p.rhs_designs).collect();
        assert!(designs.iter().all(|&d| d == 0), "{designs:?}");
        exact
            .parameters
            .iter()
            .map(|p| p.rhs_row_evaluations)
            .collect::<Vec<_>>()
    };
    // Hose 3 rests on its support far from its ends: no parameter moves its rows.
    let contact = shipped("cooler_hose_contact.ron");
    let parameters = vec![
        param("rods.hose3.length", None, 1000.0),
        param("connectors.engine_stub.position", Some(2), 1000.0),
        param("junctions.tee.mass", None, 100.0),
        param("gravity", Some(2), 10.0),
    ];
    assert_eq!(evaluations(&contact, parameters), vec![0; 4]);
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/hose_in_groove.ron");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut straight = text.clone();
    for (from, to) in [
        ("(0, 0, 150)", "(0, 0, 14.1425)"),
        ("(1000, 0, 150)", "(1000, 0, 14.1425)"),
        ("length: 1060", "length: 1000.2"),
    ] {
        assert!(straight.contains(from), "{from}");
        straight = straight.replace(from, to);
    }
    let straight = Case::from_str(&straight, &path.to_string_lossy()).unwrap();
    let parameters = vec![
        param("connectors.a.position", Some(2), 1000.0),
        param("rods.hose.length", None, 1000.0),
    ];
    assert_eq!(evaluations(&straight, parameters), vec![4, 0]);
}
