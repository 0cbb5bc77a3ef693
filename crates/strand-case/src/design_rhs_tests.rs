//! The right-hand sides of a case design's sensitivities evaluate only the elements a
//! parameter changes ([`strand_system::Model::gradient_difference`]): a junction's
//! mass and a connector's position touch a fixed number of elements however finely
//! the hoses are cut, a hose's length that hose's elements; and the derivatives are
//! those of the whole models' gradients (the reference path) to round-off.

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
        let settings = SensitivitySettings {
            element_differences,
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
