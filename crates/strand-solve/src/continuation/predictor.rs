//! Continuation predictor: the start of the next equilibrium on a parameter path
//! extrapolated from the solved states before it.
//!
//! Given states of one model solved at parameter values `x_i` (nearest first), the
//! start at `x` is their Lagrange extrapolation: positions, body positions and joint
//! values as `Σ w_i p_i`, rotations as `q_0 exp(Σ w_i log(q_0⁻¹ q_i))` about the
//! nearest state's `q_0` (`Σ w_i = 1`). Along a smooth solution path the error of the
//! start drops from `O(h)` (the nearest state itself) to `O(h²)` or `O(h³)` in the
//! step `h`, which is what saves Newton iterations along a sweep. A pure function of
//! states: carrying a state from another model onto this one (another rod length or
//! segment count) is the caller's (`strand_case::warm_start`).
//!
//! ```
//! use nalgebra::{UnitQuaternion, Vector3};
//! use strand_rod::RodState;
//! use strand_system::SystemState;
//! use strand_solve::continuation::predictor::{extrapolate, lagrange_weights};
//!
//! // Two weights of a secant from x = 10 and x = 0 to x = 20.
//! assert_eq!(lagrange_weights(&[10.0, 0.0], 20.0), vec![2.0, -1.0]);
//! // A one-edge rod whose tip moved 1 mm per unit of x: extrapolated linearly.
//! let at = |x: f64| SystemState {
//!     rods: vec![RodState::new(
//!         vec![Vector3::zeros(), Vector3::new(1.0, 0.0, 1e-3 * x)],
//!         vec![UnitQuaternion::identity()],
//!     )],
//!     bodies: Vec::new(),
//!     clips: Vec::new(),
//! };
//! let next = extrapolate(&[at(10.0), at(0.0)], &[10.0, 0.0], 20.0);
//! assert!((next.rods[0].positions[1].z - 0.020).abs() < 1e-15);
//! ```

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::{RodState, so3};
use strand_system::SystemState;

/// Lagrange weights of the points `xs` for extrapolating to `x` (they sum to 1).
pub fn lagrange_weights(xs: &[f64], x: f64) -> Vec<f64> {
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

/// The start at parameter value `x` extrapolated from `states` of one model (same
/// rods, segments, bodies and clips; nearest first) solved at the values `xs` (m,
/// kg, … — any unit, the same for `x`). One state: that state itself.
///
/// # Panics
/// If `states` is empty, or `xs` is shorter than `states` when there are two or more.
pub fn extrapolate(states: &[SystemState], xs: &[f64], x: f64) -> SystemState {
    if states.len() < 2 {
        return states.first().expect("at least one state").clone();
    }
    let w = lagrange_weights(&xs[..states.len()], x);
    let mut state = states[0].clone();
    for (r, rod) in state.rods.iter_mut().enumerate() {
        let positions = (0..rod.positions.len())
            .map(|j| {
                states
                    .iter()
                    .zip(&w)
                    .map(|(c, wi)| *wi * c.rods[r].positions[j])
                    .sum()
            })
            .collect();
        let frames = (0..rod.frames.len())
            .map(|e| {
                let q: Vec<&UnitQuaternion<f64>> =
                    states.iter().map(|c| &c.rods[r].frames[e]).collect();
                blend(&q, &w)
            })
            .collect();
        *rod = RodState::new(positions, frames);
    }
    for (b, body) in state.bodies.iter_mut().enumerate() {
        body.position = states
            .iter()
            .zip(&w)
            .map(|(c, wi)| *wi * c.bodies[b].position)
            .sum();
        let q: Vec<&UnitQuaternion<f64>> =
            states.iter().map(|c| &c.bodies[b].orientation).collect();
        body.orientation = blend(&q, &w);
    }
    for (k, clip) in state.clips.iter_mut().enumerate() {
        clip.value = states
            .iter()
            .zip(&w)
            .map(|(c, wi)| wi * c.clips[k].value)
            .sum();
        let q: Vec<&UnitQuaternion<f64>> = states.iter().map(|c| &c.clips[k].rotation).collect();
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
