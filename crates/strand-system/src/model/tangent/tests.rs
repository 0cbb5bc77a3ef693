//! [`Model::gradient_derivative`] (closed forms along a line of the model's real
//! numbers) against extrapolated central differences of the full gradients of models
//! built along the line, for every kind of change a design makes along an affine
//! parameter (a mass, gravity, a held end's position, a rod's length and section, end
//! loads), and `None` where the line moves what the closed forms do not carry (a
//! clip's base, a body's geometry).

use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use strand_rod::Rod;

use crate::tests::{body_clip_system, clipped_system, junction_system, perturbed, test_system};
use crate::{Model, Support, System, SystemState};

/// `state` with the held vertices of `model` on its supports.
fn supported(model: &Model, state: &SystemState) -> SystemState {
    let mut state = state.clone();
    model.enforce_supports(&mut state);
    state
}

/// The model of `base` moved to `t` along the line from `base` (t = 0) to `changed`
/// (t = 1), in place ([`Model::set_reals_changed`]).
fn at(base: &Model, line: &(Vec<usize>, Vec<f64>, Vec<f64>), t: f64) -> Model {
    let (moved, reals, direction) = line;
    let mut model = base.clone();
    model
        .set_reals_changed(moved, &|k| reals[k] + t * direction[k])
        .unwrap();
    model
}

/// `∂∇E/∂t` along the line from `base` to `changed` in closed form, or `None`; checked
/// against the Richardson extrapolation of central differences of the full gradients
/// of the models built along the line ([`Model::try_new_like`]) to 1e-7 of its largest
/// entry. Returns the elements evaluated.
fn check(base: System, changed: System, seed: u64) -> Option<usize> {
    let model = Model::try_new(base.clone()).unwrap();
    let reals = base.reals();
    let direction: Vec<f64> = changed
        .reals()
        .iter()
        .zip(&reals)
        .map(|(c, b)| c - b)
        .collect();
    let moved: Vec<usize> = (0..reals.len()).filter(|&k| direction[k] != 0.0).collect();
    assert!(!moved.is_empty(), "the change moves no real number");
    let line = (moved, reals, direction);
    let state = supported(
        &model,
        &perturbed(&model, &mut ChaCha8Rng::seed_from_u64(seed)),
    );
    let s = 1e-3;
    let (plus, minus) = (at(&model, &line, s), at(&model, &line, -s));
    let (sp, sm) = (supported(&plus, &state), supported(&minus, &state));
    let exact = model.gradient_derivative(&state, (&plus, &sp), (&minus, &sm), s)?;
    let gradient = |t: f64| {
        let built = Model::try_new_like(at(&model, &line, t).system().clone(), &model).unwrap();
        let mut eval = built.new_evaluation();
        built.evaluate(&supported(&built, &state), &mut eval, false);
        eval.gradient
    };
    let h = 1e-3;
    let (g1p, g1m, g2p, g2m) = (
        gradient(h),
        gradient(-h),
        gradient(2.0 * h),
        gradient(-2.0 * h),
    );
    let reference: Vec<f64> = (0..g1p.len())
        .map(|k| (8.0 * (g1p[k] - g1m[k]) - (g2p[k] - g2m[k])) / (12.0 * h))
        .collect();
    let scale = reference.iter().fold(0.0f64, |m, g| m.max(g.abs()));
    assert!(scale > 0.0, "the line does not move the gradient");
    for (k, (x, y)) in exact.gradient.iter().zip(&reference).enumerate() {
        assert!(
            (x - y).abs() <= 1e-7 * scale,
            "entry {k}: {x} (closed form) vs {y} (differences), scale {scale}"
        );
    }
    Some(exact.elements)
}

#[test]
fn masses_gravity_and_end_loads_match_differences_of_the_gradients() {
    let base = junction_system();
    let mut changed = base.clone();
    changed.bodies[0].mass *= 1.3;
    assert_eq!(check(base, changed, 1), Some(1));
    for (seed, base) in [test_system(), junction_system()].into_iter().enumerate() {
        let mut changed = base.clone();
        changed.gravity.z *= 1.1;
        assert!(check(base.clone(), changed, 10 + seed as u64).is_some());
        let mut changed = base.clone();
        changed.rods[0].end.load.force += Vector3::new(0.1, 0.2, -0.1);
        changed.rods[0].start.load.force += Vector3::new(-0.3, 0.0, 0.1);
        assert!(check(base, changed, 20 + seed as u64).is_some());
    }
}

#[test]
fn a_held_ends_position_evaluates_its_edge_in_closed_form() {
    let base = test_system();
    let mut changed = base.clone();
    if let Support::Clamped { position, .. } = &mut changed.rods[0].start.support {
        *position += Vector3::new(1e-2, -2e-2, 5e-3);
    }
    assert_eq!(check(base, changed, 4), Some(1));
    let base = junction_system();
    let mut changed = base.clone();
    changed.rods[2].end.support = Support::Pinned {
        position: Vector3::new(0.5, 0.46, 0.01),
    };
    assert_eq!(check(base, changed, 5), Some(1));
}

#[test]
fn a_rods_length_and_section_evaluate_that_rods_elements_in_closed_form() {
    let base = junction_system();
    let mut changed = base.clone();
    let section = *base.rods[1].rod.section();
    changed.rods[1].rod = Rod::try_straight(section, 0.52, 3).unwrap();
    assert_eq!(check(base, changed, 6), Some(8));
    let base = junction_system();
    let mut changed = base.clone();
    let section = strand_rod::Section::try_explicit(40.0, 12.0, 1.5, 0.8, 0.4, 0.02).unwrap();
    changed.rods[1].rod = Rod::try_straight(section, 0.5, 3).unwrap();
    assert_eq!(check(base, changed, 7), Some(8));
    // A clipped rod's length: its edges, vertices and the clips' half cells.
    let base = clipped_system();
    let mut changed = base.clone();
    let rod = &base.rods[0].rod;
    let lengths: Vec<f64> = rod.edge_lengths().iter().map(|h| 1.05 * h).collect();
    changed.rods[0].rod = Rod::try_new(
        *rod.section(),
        lengths,
        (0..rod.segments()).map(|e| *rod.rest_strain(e)).collect(),
        (0..rod.vertex_count())
            .map(|j| *rod.rest_curvature(j))
            .collect(),
    )
    .unwrap();
    assert!(check(base, changed, 8).is_some());
}

#[test]
fn a_clips_base_or_a_bodys_geometry_is_left_to_the_differences() {
    let base = clipped_system();
    let mut changed = base.clone();
    changed.clips[0].base.position += Vector3::new(2e-3, -1e-3, 3e-3);
    assert_eq!(check(base, changed, 30), None);
    let base = body_clip_system();
    let mut changed = base.clone();
    changed.bodies[0].ports[1].position += Vector3::new(3e-3, 0.0, -1e-3);
    assert_eq!(check(base, changed, 50), None);
}
