//! Continuation predictor: the initial state of a variant extrapolated from the
//! solved variants before it on its parameter line.
//!
//! Each solved state is first carried onto the new variant's rods
//! ([`strand_case::warm_start`], by arc-length fraction). With one solved neighbour
//! that is the start; with two or three on the same line (values `x_i`), the start
//! is their Lagrange extrapolation to the new value `x`: positions, body positions
//! and joint values as `Σ w_i p_i`, rotations as `q_0 exp(Σ w_i log(q_0⁻¹ q_i))`
//! about the nearest neighbour's `q_0` (`Σ w_i = 1`). Along a smooth solution path
//! the error of the start drops from `O(h)` to `O(h²)` or `O(h³)` in the step `h`,
//! which is what saves Newton iterations along a sweep.

use nalgebra::{UnitQuaternion, Vector3};
use strand_case::{BuiltCase, warm_start};
use strand_rod::{RodState, so3};
use strand_system::{Model, SystemState};

/// A solved variant (or the case itself, `n = None`).
pub(crate) struct Solved {
    /// The variant's index in the plan (`None`: the case itself).
    pub n: Option<usize>,
    /// Its built case.
    pub built: BuiltCase,
    /// Its equilibrium.
    pub state: SystemState,
}

/// Lagrange weights of the points `xs` for extrapolating to `x` (they sum to 1).
pub(crate) fn lagrange_weights(xs: &[f64], x: f64) -> Vec<f64> {
    (0..xs.len())
        .map(|i| {
            (0..xs.len())
                .filter(|&j| j != i)
                .map(|j| (x - xs[j]) / (xs[i] - xs[j]))
                .product()
        })
        .collect()
}

/// `Σ w_i q_i` of rotations as `q_0 exp(Σ w_i log(q_0⁻¹ q_i))`.
fn blend(q: &[&UnitQuaternion<f64>], w: &[f64]) -> UnitQuaternion<f64> {
    let sum: Vector3<f64> = q
        .iter()
        .zip(w)
        .skip(1)
        .map(|(qi, wi)| *wi * so3::relative_rotation_vector(q[0], qi))
        .sum();
    q[0] * so3::exp(&sum)
}

/// The start of `target` from the solved `samples` (nearest first) at parameter
/// values `xs`, extrapolated to `x`. One sample: the plain warm start.
pub(crate) fn predicted_start(
    samples: &[&Solved],
    xs: &[f64],
    x: f64,
    target: &Model,
) -> SystemState {
    let carried: Vec<SystemState> = samples
        .iter()
        .map(|s| warm_start(&s.built.model, &s.state, target))
        .collect();
    if carried.len() < 2 {
        return carried.into_iter().next().expect("at least one sample");
    }
    let w = lagrange_weights(xs, x);
    let mut state = carried[0].clone();
    for (r, rod) in state.rods.iter_mut().enumerate() {
        let positions = (0..rod.positions.len())
            .map(|j| {
                carried
                    .iter()
                    .zip(&w)
                    .map(|(c, wi)| *wi * c.rods[r].positions[j])
                    .sum()
            })
            .collect();
        let frames = (0..rod.frames.len())
            .map(|e| {
                let q: Vec<&UnitQuaternion<f64>> =
                    carried.iter().map(|c| &c.rods[r].frames[e]).collect();
                blend(&q, &w)
            })
            .collect();
        *rod = RodState::new(positions, frames);
    }
    for (b, body) in state.bodies.iter_mut().enumerate() {
        body.position = carried
            .iter()
            .zip(&w)
            .map(|(c, wi)| *wi * c.bodies[b].position)
            .sum();
        let q: Vec<&UnitQuaternion<f64>> =
            carried.iter().map(|c| &c.bodies[b].orientation).collect();
        body.orientation = blend(&q, &w);
    }
    for (k, clip) in state.clips.iter_mut().enumerate() {
        clip.value = carried
            .iter()
            .zip(&w)
            .map(|(c, wi)| wi * c.clips[k].value)
            .sum();
        let q: Vec<&UnitQuaternion<f64>> = carried.iter().map(|c| &c.clips[k].rotation).collect();
        clip.rotation = blend(&q, &w);
    }
    state
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lagrange_weights_reproduce_polynomials_of_their_degree() {
        let xs = [30.0, 20.0, 10.0];
        let w = lagrange_weights(&xs, 40.0);
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        // A quadratic is extrapolated exactly by three points.
        let f = |x: f64| 2.0 - 0.3 * x + 0.01 * x * x;
        let got: f64 = xs.iter().zip(&w).map(|(x, w)| w * f(*x)).sum();
        assert!((got - f(40.0)).abs() < 1e-12, "{got} vs {}", f(40.0));
        // Two points: the secant.
        assert_eq!(lagrange_weights(&[10.0, 0.0], 20.0), vec![2.0, -1.0]);
    }

    #[test]
    fn rotations_on_one_geodesic_are_extrapolated_along_it() {
        let axis = Vector3::new(0.2, -0.5, 0.8).normalize();
        let at = |t: f64| UnitQuaternion::from_scaled_axis(axis * (0.3 + 0.1 * t));
        let (a, b) = (at(2.0), at(1.0));
        let q = blend(&[&a, &b], &lagrange_weights(&[2.0, 1.0], 3.0));
        assert!(q.angle_to(&at(3.0)) < 1e-14);
    }
}
