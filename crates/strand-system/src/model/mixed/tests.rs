use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::tests::{perturbed, test_system};
use crate::{EdgeStresses, Model};

#[test]
fn the_mixed_hessian_with_the_states_own_stresses_is_the_hessian() {
    let model = Model::try_new(test_system()).unwrap();
    let state = perturbed(&model, &mut ChaCha8Rng::seed_from_u64(7));
    let mut plain = model.new_evaluation();
    model.evaluate(&state, &mut plain, true);
    let mut mixed = model.new_evaluation();
    model.evaluate_mixed(&state, &mut mixed, &model.edge_stresses(&state));
    assert_eq!(plain.energy, mixed.energy);
    assert_eq!(plain.gradient, mixed.gradient);
    assert_eq!(plain.hessian, mixed.hessian);
    // Another stress changes the Hessian, but neither energy nor gradient.
    let mut doubled = model.edge_stresses(&state);
    doubled.0.iter_mut().flatten().for_each(|f| *f *= 2.0);
    model.evaluate_mixed(&state, &mut mixed, &doubled);
    assert_eq!(plain.gradient, mixed.gradient);
    assert_ne!(plain.hessian, mixed.hessian);
}

/// Largest difference of two stress sets, N.
fn largest_difference(a: &EdgeStresses, b: &EdgeStresses) -> f64 {
    a.0.iter()
        .flatten()
        .zip(b.0.iter().flatten())
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max)
}

#[test]
fn the_linearised_stress_prediction_is_exact_to_first_order() {
    // Along a random step `t·d`, the prediction made at `t = 0` misses the stress at
    // `t` by O(t²): halving t quarters the error (observed order 2), and at t = 0 it is
    // the state's own stress.
    let model = Model::try_new(test_system()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let state = perturbed(&model, &mut rng);
    let at_zero = largest_difference(
        &model.linearised_edge_stresses(&state, &state),
        &model.edge_stresses(&state),
    );
    assert!(at_zero < 1e-13, "{at_zero:e} N");
    let direction: Vec<f64> = (0..model.dofs().len())
        .map(|_| rng.random_range(-1.0..1.0))
        .collect();
    let error = |t: f64| {
        let step: Vec<f64> = direction.iter().map(|d| t * d).collect();
        let moved = model.retract(&state, &step);
        largest_difference(
            &model.linearised_edge_stresses(&state, &moved),
            &model.edge_stresses(&moved),
        )
    };
    let (coarse, fine) = (error(1e-2), error(5e-3));
    let order = (coarse / fine).log2();
    assert!(
        (order - 2.0).abs() < 0.1,
        "order {order} ({coarse:e}, {fine:e})"
    );
}
