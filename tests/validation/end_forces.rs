//! End-vertex sectional forces (issue 9 item 7): the force reported at a held end is
//! the support's reaction (the adjacent edge force plus the end half cell's weight
//! `w h / 2` and any dead end load), so it converges at second order like the interior
//! vertex averages instead of at first order.
//!
//! Reference: a rod hanging vertically from a clamp carries its whole weight at the
//! clamp, `f(0) = ρ_L g L` (statics of the whole rod, independent of the model); a
//! horizontal clamped–clamped rod under gravity carries half its weight at each end
//! (symmetry plus statics).

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::sectional::sectional;
use strand_rod::{Rod, Section};
use strand_solve::Solution;
use strand_system::{End, Model, RodSpec, System};

use crate::common::{frame_along_x, solve_converged};

const MASS_PER_LENGTH: f64 = 0.5;
const G: f64 = 9.81;

fn section() -> Section {
    Section::try_explicit(1e6, 3.5e5, 0.1, 0.077, MASS_PER_LENGTH, 0.0).unwrap()
}

/// The sectional forces of rod 0 at its two end vertices and the reactions there.
fn end_forces(
    model: &Model,
    solution: &Solution,
) -> ([Vector3<f64>; 2], [Vector3<f64>; 2], Vector3<f64>) {
    let state = &solution.state;
    let out = sectional(
        &model.system().rods[0].rod,
        &state.rods[0],
        &model.boundary_frames(0, state),
    );
    let mut reactions = [Vector3::zeros(); 2];
    for r in model.reactions(state) {
        // Force on the rod; the sectional force at the start is the force of the rod
        // on the part before it (the support): its opposite.
        reactions[usize::from(r.at_end)] = if r.at_end { r.force } else { -r.force };
    }
    (
        [out.forces[0], *out.forces.last().unwrap()],
        reactions,
        out.edge_forces[0],
    )
}

/// A vertical rod hanging from a clamp: `f(0)` is the total weight at every
/// resolution, the free end carries nothing, and the reaction matches to round-off.
#[test]
fn hanging_rod_carries_its_weight_at_the_clamp() {
    let down = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::PI);
    let weight = MASS_PER_LENGTH * G * 1.0;
    for segments in [10, 20, 40, 80] {
        let system = System {
            rods: vec![RodSpec {
                name: "rod".into(),
                rod: Rod::try_straight(section(), 1.0, segments).unwrap(),
                start: End::clamped(Vector3::zeros(), down),
                end: End::free(),
                route: None,
            }],
            bodies: vec![],
            clips: Vec::new(),
            gravity: Vector3::new(0.0, 0.0, -G),
        };
        let (model, solution) = solve_converged(system);
        let (forces, reactions, first_edge) = end_forces(&model, &solution);
        let exact = Vector3::new(0.0, 0.0, -weight);
        let error = (forces[0] - exact).norm() / weight;
        // The previous output, the adjacent edge force: off by w h / 2 (first order).
        let old = (first_edge - exact).norm() / weight;
        println!(
            "hanging N={segments}: |f(0) − W|/W = {error:.2e} (edge force alone {old:.2e}), free end {:.2e} N",
            forces[1].norm()
        );
        assert!((old - 0.5 / segments as f64).abs() < 1e-9);
        assert!((forces[0] - reactions[0]).norm() < 1e-12 * weight);
        assert!(forces[1].norm() < 1e-9 * weight);
        assert!(error < 1e-9, "N = {segments}: relative error {error}");
    }
}

/// A horizontal rod clamped at both ends sags under its weight: each clamp carries
/// half the weight vertically; the end-vertex forces equal the reactions to round-off.
/// The old value (adjacent edge force) was off by `w h / 2`, first order in `h`.
#[test]
fn clamped_clamped_rod_end_forces_are_the_reactions() {
    let weight = MASS_PER_LENGTH * G * 1.0;
    for segments in [10, 20, 40, 80] {
        let system = System {
            rods: vec![RodSpec {
                name: "rod".into(),
                rod: Rod::try_straight(section(), 1.0, segments).unwrap(),
                start: End::clamped(Vector3::zeros(), frame_along_x()),
                end: End::clamped(Vector3::x(), frame_along_x())
                    .with_force(Vector3::new(0.0, 0.3, -0.2)),
                route: None,
            }],
            bodies: vec![],
            clips: Vec::new(),
            gravity: Vector3::new(0.0, 0.0, -G),
        };
        let (model, solution) = solve_converged(system);
        let (forces, reactions, _) = end_forces(&model, &solution);
        for k in 0..2 {
            assert!(
                (forces[k] - reactions[k]).norm() < 1e-12 * weight,
                "N = {segments}, end {k}: {:?} vs {:?}",
                forces[k],
                reactions[k]
            );
        }
        // Global vertical balance: the rod's weight and the dead load are carried by
        // the two supports (f(0) pulls the start clamp down, the end reaction lifts).
        let vertical = forces[0].z - forces[1].z;
        let expected = -(weight + 0.2);
        assert!(
            (vertical - expected).abs() < 1e-9 * weight,
            "N = {segments}: {vertical} vs {expected}"
        );
    }
}
