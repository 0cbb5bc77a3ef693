//! [`Model::gradient_difference`] against the difference of two full gradients, for
//! every kind of change a design makes (a mass, gravity, a held end's position, a
//! rod's length, a clip's base, an end load), and the elements it evaluates.

use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use strand_rod::Rod;

use crate::tests::{
    body_clip_system, chained_systems, clipped_system, junction_system, perturbed, test_system,
};
use crate::{Model, Support, System, SystemState};

/// The full gradient of `model` at `state` with its held vertices on its supports.
fn full_gradient(model: &Model, state: &SystemState) -> Vec<f64> {
    let mut eval = model.new_evaluation();
    model.evaluate(state, &mut eval, false);
    eval.gradient
}

/// `state` with the held vertices of `model` on its supports.
fn supported(model: &Model, state: &SystemState) -> SystemState {
    let mut state = state.clone();
    model.enforce_supports(&mut state);
    state
}

/// Builds `changed` like `base` (the design's path: [`Model::try_new_like`]), takes
/// both at a perturbed state of `base` and checks the difference against the full
/// gradients' (to 1e-13 of the gradients' largest entry: their sums' round-off).
/// Returns the elements evaluated.
fn check(base: System, changed: System, seed: u64) -> usize {
    let a = Model::try_new(base).unwrap();
    let b = Model::try_new_like(changed, &a).unwrap();
    let state = perturbed(&a, &mut ChaCha8Rng::seed_from_u64(seed));
    let (sa, sb) = (supported(&a, &state), supported(&b, &state));
    let (ga, gb) = (full_gradient(&a, &sa), full_gradient(&b, &sb));
    let difference = a.gradient_difference(&sa, &b, &sb);
    let scale = ga.iter().chain(&gb).fold(0.0f64, |m, g| m.max(g.abs()));
    let mut largest = 0.0f64;
    for (k, d) in difference.gradient.iter().enumerate() {
        let full = ga[k] - gb[k];
        largest = largest.max(full.abs());
        assert!(
            (d - full).abs() <= 1e-13 * scale,
            "entry {k}: {d} (difference) vs {full} (full gradients), scale {scale}"
        );
    }
    assert!(
        largest > 1e-6 * scale,
        "the change did not move the gradient"
    );
    difference.elements
}

#[test]
fn an_unchanged_model_evaluates_no_element() {
    for system in [test_system(), junction_system(), body_clip_system()] {
        let a = Model::try_new(system.clone()).unwrap();
        let b = Model::try_new_like(system, &a).unwrap();
        let state = supported(&a, &perturbed(&a, &mut ChaCha8Rng::seed_from_u64(3)));
        let difference = a.gradient_difference(&state, &b, &state);
        assert_eq!(difference.elements, 0);
        assert!(difference.gradient.iter().all(|g| *g == 0.0));
    }
}

#[test]
fn a_mass_evaluates_the_bodys_weight_alone() {
    let base = junction_system();
    let mut changed = base.clone();
    changed.bodies[0].mass *= 1.3;
    assert_eq!(check(base, changed, 1), 1);
    let base = body_clip_system();
    let mut changed = base.clone();
    changed.bodies[1].mass *= 0.7;
    assert_eq!(check(base, changed, 2), 1);
}

#[test]
fn a_held_ends_position_evaluates_the_elements_at_that_vertex() {
    // The clamped start of the cantilever: its first edge only (the boundary frame
    // and the first edge's frame are unchanged).
    let base = test_system();
    let mut changed = base.clone();
    if let Support::Clamped { position, .. } = &mut changed.rods[0].start.support {
        *position += Vector3::new(1e-3, -2e-3, 5e-4);
    }
    assert_eq!(check(base, changed, 4), 1);
    // The pinned end of rod c of the junction.
    let base = junction_system();
    let mut changed = base.clone();
    changed.rods[2].end.support = Support::Pinned {
        position: Vector3::new(0.5, 0.46, 0.01),
    };
    assert_eq!(check(base, changed, 5), 1);
}

#[test]
fn a_rods_length_evaluates_that_rods_elements() {
    let base = junction_system();
    let mut changed = base.clone();
    let section = *base.rods[1].rod.section();
    changed.rods[1].rod = Rod::try_straight(section, 0.52, 3).unwrap();
    // Rod b: its 3 edges, its 4 vertex elements (both ends clamped) and the weight of
    // its end vertex at the T's port (a point load on the body); nothing of rods a, c.
    let total = Model::try_new(base.clone()).unwrap().elements.len();
    assert_eq!(check(base, changed, 6), 8);
    assert!(total > 16, "{total} elements");
    // A stiffer and heavier section of rod b: the same elements.
    let base = junction_system();
    let mut changed = base.clone();
    let section = strand_rod::Section::try_explicit(40.0, 12.0, 1.5, 0.8, 0.4, 0.02).unwrap();
    changed.rods[1].rod = Rod::try_straight(section, 0.5, 3).unwrap();
    assert_eq!(check(base, changed, 7), 8);
}

#[test]
fn gravity_and_end_loads_match_the_full_gradients() {
    for (seed, base) in [test_system(), junction_system(), body_clip_system()]
        .into_iter()
        .enumerate()
    {
        let mut changed = base.clone();
        changed.gravity.z *= 1.1;
        check(base.clone(), changed, 10 + seed as u64);
        let mut changed = base.clone();
        changed.rods[0].end.load.force += Vector3::new(0.1, 0.2, -0.1);
        changed.rods[0].start.load.force += Vector3::new(-0.3, 0.0, 0.1);
        check(base, changed, 20 + seed as u64);
    }
}

#[test]
fn moved_clips_and_bodies_match_the_full_gradients() {
    let [world, on_body] = chained_systems();
    for (seed, base) in [clipped_system(), world, body_clip_system(), on_body]
        .into_iter()
        .enumerate()
    {
        let mut changed = base.clone();
        changed.clips[0].base.position += Vector3::new(2e-3, -1e-3, 3e-3);
        check(base.clone(), changed, 30 + seed as u64);
        let mut changed = base.clone();
        changed.clips[1].offset.position += Vector3::new(-1e-3, 1e-3, 2e-3);
        check(base, changed, 40 + seed as u64);
    }
    // A body's geometry (a port's lever and the centre of mass).
    let base = body_clip_system();
    let mut changed = base.clone();
    changed.bodies[0].ports[1].position += Vector3::new(3e-3, 0.0, -1e-3);
    changed.bodies[0].center_of_mass += Vector3::new(0.0, 1e-3, 0.0);
    check(base, changed, 50);
}

#[test]
fn models_of_another_structure_take_the_full_gradients() {
    let base = test_system();
    let mut changed = base.clone();
    let section = *base.rods[1].rod.section();
    changed.rods[1].rod = Rod::try_straight(section, 1.2, 4).unwrap();
    changed.rods[1].end.load.force = Vector3::new(0.0, 0.5, 0.0);
    // Another end load moment creates an end-moment element: other elements.
    changed.rods[1].end.load.moment = Vector3::new(0.05, 0.0, 0.0);
    let a = Model::try_new(base).unwrap();
    let b = Model::try_new(changed).unwrap();
    assert_ne!(a.elements.len(), b.elements.len());
    let state = supported(&a, &perturbed(&a, &mut ChaCha8Rng::seed_from_u64(60)));
    let difference = a.gradient_difference(&state, &b, &state);
    assert_eq!(difference.elements, b.element_count());
    assert!(b.element_count() > a.element_count());
    let (ga, gb) = (full_gradient(&a, &state), full_gradient(&b, &state));
    let full: Vec<f64> = ga.iter().zip(&gb).map(|(x, y)| x - y).collect();
    assert_eq!(difference.gradient, full);
}
