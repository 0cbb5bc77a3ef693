//! The predictor of the path following: the secant extrapolation of two solved
//! states to the next parameter value.

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::{RodState, so3};
use strand_system::{JointState, Pose, SystemState};

fn line(a: &Vector3<f64>, b: &Vector3<f64>, ratio: f64) -> Vector3<f64> {
    b + (b - a) * ratio
}

fn turn(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>, ratio: f64) -> UnitQuaternion<f64> {
    b * so3::exp(&(ratio * so3::relative_rotation_vector(a, b)))
}

/// The state `ratio` secant steps beyond `last` along the secant from `previous`:
/// positions, joint values and body positions `b + ratio (b − a)`; frames, body
/// orientations and spherical joints `q_b exp(ratio · log(q_aᵀ q_b))`. Both states
/// must be of the same model; `ratio = 0` returns `last`.
///
/// ```
/// use nalgebra::{UnitQuaternion, Vector3};
/// use strand_rod::RodState;
/// use strand_system::SystemState;
/// use strand_case::motion::extrapolate;
///
/// let rod = |x: f64| RodState::new(vec![Vector3::zeros(), Vector3::new(x, 0.0, 0.0)],
///                                  vec![UnitQuaternion::identity()]);
/// let state = |x: f64| SystemState { rods: vec![rod(x)], bodies: vec![], clips: vec![] };
/// let next = extrapolate(&state(1.0), &state(1.5), 2.0);
/// assert!((next.rods[0].positions[1].x - 2.5).abs() < 1e-15);
/// ```
pub fn extrapolate(previous: &SystemState, last: &SystemState, ratio: f64) -> SystemState {
    let rods = previous
        .rods
        .iter()
        .zip(&last.rods)
        .map(|(a, b)| {
            RodState::new(
                a.positions
                    .iter()
                    .zip(&b.positions)
                    .map(|(p, q)| line(p, q, ratio))
                    .collect(),
                a.frames
                    .iter()
                    .zip(&b.frames)
                    .map(|(p, q)| turn(p, q, ratio))
                    .collect(),
            )
        })
        .collect();
    let bodies = previous
        .bodies
        .iter()
        .zip(&last.bodies)
        .map(|(a, b)| Pose {
            position: line(&a.position, &b.position, ratio),
            orientation: turn(&a.orientation, &b.orientation, ratio),
        })
        .collect();
    let clips = previous
        .clips
        .iter()
        .zip(&last.clips)
        .map(|(a, b)| JointState {
            value: b.value + (b.value - a.value) * ratio,
            rotation: turn(&a.rotation, &b.rotation, ratio),
        })
        .collect();
    SystemState {
        rods,
        bodies,
        clips,
    }
}
