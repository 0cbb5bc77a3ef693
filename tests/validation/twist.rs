//! Multi-turn twist (issue 9 item 5): a straight rod of round section clamped at both
//! ends and wound by more than half a turn. The end frames fix the twist only modulo
//! one turn; `End::twist_turns` selects the winding, and the equilibrium is the
//! uniformly twisted straight rod with the torsion moment `M = GJ φ / L` (Saint-Venant,
//! independent of the discretisation), stable below the twist-buckling threshold
//! `M L / EI = 8.9868` of clamped ends (Greenhill).

use std::f64::consts::FRAC_PI_2;

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::{Rod, Section};
use strand_system::{End, RodSpec, System};

use crate::common::{frame_along_x, solve_converged};

/// EI = 4 N·m², GJ = 1 N·m²: two turns give `M L / EI = 4π / 4 = 3.14`, well below 8.99.
const EI: f64 = 4.0;
const GJ: f64 = 1.0;
const LENGTH: f64 = 1.0;

/// A rod along x clamped at both ends, the end frame turned by `angle` (rad) about the
/// tangent, wound by `turns` extra whole turns.
fn twisted_rod(angle: f64, turns: i32, segments: usize) -> System {
    let section = Section::try_explicit(1e5, 1e5, EI, GJ, 0.0, 0.0).unwrap();
    let end_frame = frame_along_x() * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), angle);
    System {
        rods: vec![RodSpec {
            name: "rod".into(),
            rod: Rod::try_straight(section, LENGTH, segments).unwrap(),
            start: End::clamped(Vector3::zeros(), frame_along_x()),
            end: End::clamped(Vector3::x() * LENGTH, end_frame).with_twist_turns(turns),
            route: None,
        }],
        bodies: vec![],
        clips: Vec::new(),
        gravity: Vector3::zeros(),
    }
}

/// The largest relative deviation of the torsion along the rod and of the clamp
/// reactions from `M = GJ φ / L`, and the largest lateral displacement (m).
fn torsion_error(angle: f64, turns: i32, total: f64) -> (f64, f64) {
    let (model, solution) = solve_converged(twisted_rod(angle, turns, 40));
    let expected = GJ * total / LENGTH;
    let state = &solution.state;
    let out = strand_rod::sectional::sectional(
        &model.system().rods[0].rod,
        &state.rods[0],
        &model.boundary_frames(0, state),
    );
    let mut error = 0.0f64;
    for m_t in &out.torsion {
        error = error.max((m_t - expected).abs() / expected.abs());
    }
    for reaction in model.reactions(state) {
        // On the rod: −M x̂ at the start, +M x̂ at the end.
        let sign = if reaction.at_end { 1.0 } else { -1.0 };
        let moment = reaction.moment - Vector3::x() * sign * expected;
        error = error.max(moment.norm() / expected.abs());
    }
    let lateral = state.rods[0]
        .positions
        .iter()
        .map(|p| p.y.hypot(p.z))
        .fold(0.0, f64::max);
    (error, lateral)
}

/// 190° is not −170°: with one extra turn the rod carries `GJ · 190° / L`.
#[test]
fn twist_of_190_degrees_is_not_minus_170() {
    let angle = 190f64.to_radians();
    let (error, lateral) = torsion_error(angle, 1, angle);
    println!("190°: torsion error {error:.2e}, lateral {lateral:.1e} m");
    assert!(error < 1e-9, "relative torsion error {error}");
    assert!(lateral < 1e-12);
    // Without the extra turn the same end frames give the shortest twist, −170°.
    let shortest = -170f64.to_radians();
    let (error, _) = torsion_error(angle, 0, shortest);
    assert!(error < 1e-9, "relative torsion error {error}");
}

/// Two full turns: the end frames coincide, the rod carries `GJ · 4π / L`.
#[test]
fn two_full_turns_carry_their_torsion() {
    let total = 4.0 * std::f64::consts::PI;
    assert!(GJ * total / LENGTH * LENGTH / EI < 0.5 * 8.9868);
    let (error, lateral) = torsion_error(0.0, 2, total);
    println!("720°: torsion error {error:.2e}, lateral {lateral:.1e} m");
    assert!(error < 1e-9, "relative torsion error {error}");
    assert!(lateral < 1e-12);
    // And backwards.
    let (error, _) = torsion_error(0.0, -2, -total);
    assert!(error < 1e-9, "relative torsion error {error}");
}

/// A quarter turn plus three turns the other way round: −3 turns + 90°.
#[test]
fn turns_add_to_the_shortest_twist() {
    let total = FRAC_PI_2 - 3.0 * std::f64::consts::TAU;
    // 2.75 turns: M L / EI = 17.3 / 4 = 4.3 < 8.99.
    let (error, _) = torsion_error(FRAC_PI_2, -3, total);
    assert!(error < 1e-9, "relative torsion error {error}");
}
