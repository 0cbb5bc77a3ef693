//! A variant built for its warm start is the cold build's model without the guess, and
//! a warm start that fails falls back to exactly the cold solve.

use strand_case::schema::{Amount, Change, VariantChange};
use strand_case::{BuiltCase, Case, Start};
use strand_system::SystemState;

use super::{WarmStart, build_and_solve};
use crate::batch::predict::{Solved, predicted_start};

fn cooler() -> Case {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/cooler_hose.ron");
    Case::from_path(path).unwrap()
}

/// hose 2 longer by `mm` (the case file's unit).
fn longer(mm: f64) -> Vec<VariantChange> {
    vec![VariantChange {
        item: "rods.hose2.length".into(),
        change: Change::Add(Amount::Number(mm)),
    }]
}

/// The solved case itself, as a batch's root.
fn solved_base(case: &Case) -> Solved {
    let built = case.build(None).unwrap();
    let solution = built
        .solve_from(built.initial.clone(), &built.settings)
        .unwrap();
    assert!(solution.report.converged);
    Solved {
        n: None,
        built,
        state: solution.state,
    }
}

/// The cooler hose solved, hose 2 longer by 5 mm as the variant's changes, and the
/// variant's cold build.
fn variant_of_solved_cooler() -> (Case, Solved, Vec<VariantChange>, BuiltCase) {
    let case = cooler();
    let base = solved_base(&case);
    let changes = longer(5.0);
    let cold = case.build_with_changes("v", &changes, None).unwrap();
    (case, base, changes, cold)
}

fn evaluation(built: &BuiltCase, state: &SystemState) -> (f64, Vec<f64>) {
    let mut eval = built.model.new_evaluation();
    built.model.evaluate(state, &mut eval, false);
    (eval.energy, eval.gradient)
}

#[test]
fn a_variant_built_for_its_warm_start_has_the_cold_builds_model_and_no_guess() {
    let (case, base, changes, cold) = variant_of_solved_cooler();
    let warm = case
        .build_with_changes_for_start("v", &changes, None, &base.state, Some(&base.built.model))
        .unwrap();
    assert_eq!(warm.start, Start::Given);
    assert_eq!(
        warm.initial, base.state,
        "the placeholder, not a computed guess"
    );
    assert_ne!(cold.initial, base.state);
    // The same model: energy and gradient bit for bit at the cold guess and at the
    // base equilibrium carried over.
    let carried = predicted_start(&[&base], &[0.0], 5.0, &cold.model);
    for state in [&cold.initial, &carried] {
        assert_eq!(evaluation(&warm, state), evaluation(&cold, state));
    }
    let (built, solution, from_warm) = build_and_solve(
        &case,
        "v",
        &changes,
        None,
        Some(WarmStart {
            neighbour: &base,
            predict: |b: &BuiltCase| predicted_start(&[&base], &[0.0], 5.0, &b.model),
        }),
    )
    .unwrap();
    assert!(from_warm && solution.report.converged);
    let again = cold.solve_from(carried, &built.settings).unwrap();
    assert_eq!(solution.state, again.state);
}

#[test]
fn a_warm_start_that_does_not_converge_falls_back_to_the_cold_solve() {
    let (case, base, changes, cold) = variant_of_solved_cooler();
    let reference = cold
        .solve_from(cold.initial.clone(), &cold.settings)
        .unwrap();
    assert!(reference.report.converged);
    // A start no solve can use: every position not a number.
    let broken = |b: &BuiltCase| {
        let mut state = predicted_start(&[&base], &[0.0], 5.0, &b.model);
        for rod in &mut state.rods {
            for p in &mut rod.positions {
                p.x = f64::NAN;
            }
        }
        state
    };
    let (_, solution, from_warm) = build_and_solve(
        &case,
        "v",
        &changes,
        None,
        Some(WarmStart {
            neighbour: &base,
            predict: broken,
        }),
    )
    .unwrap();
    assert!(!from_warm && solution.report.converged);
    assert_eq!(solution.state, reference.state);
    assert!(solution.report.iterations >= reference.report.iterations);
}
