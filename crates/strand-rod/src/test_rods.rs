//! Rod configurations shared by the unit tests of the sectional quantities and their
//! tangents.

use nalgebra::{UnitQuaternion, Vector3};

use crate::RodState;
use crate::sectional::BoundaryFrames;

/// A bent and twisted state over edges of `lengths` (m): frame `e` turned by
/// `(0.2 e, 0.1 e², 0.3 − 0.05 e)` rad, each edge stretched by 1 % and sheared a little
/// off its frame's axis.
pub(crate) fn bent_twisted_state(lengths: &[f64]) -> RodState {
    let frames: Vec<UnitQuaternion<f64>> = (0..lengths.len())
        .map(|e| {
            let s = e as f64;
            UnitQuaternion::from_scaled_axis(Vector3::new(0.2 * s, 0.1 * s * s, 0.3 - 0.05 * s))
        })
        .collect();
    let mut positions = vec![Vector3::new(0.01, -0.02, 0.03)];
    for (e, q) in frames.iter().enumerate() {
        let step = q * Vector3::new(0.003, -0.002, 1.01) * lengths[e];
        positions.push(positions[e] + step);
    }
    RodState::new(positions, frames)
}

/// Boundary frames at both ends of [`bent_twisted_state`], with `clips` and `end_loads`
/// (N).
pub(crate) fn turned_ends(
    clips: Vec<(usize, UnitQuaternion<f64>)>,
    end_loads: [Vector3<f64>; 2],
) -> BoundaryFrames {
    BoundaryFrames {
        start: Some(UnitQuaternion::from_scaled_axis(Vector3::new(
            -0.1, 0.05, 0.2,
        ))),
        end: Some(UnitQuaternion::from_scaled_axis(Vector3::new(
            1.4, 0.6, -0.3,
        ))),
        clips,
        end_loads,
    }
}
