//! Warm starts: a solved state of one model carried onto another model with the same
//! rods but other lengths or discretisations (a variant of the case).
//!
//! Each rod's state is resampled by **reference arc-length fraction** `s / L`: the
//! vertex at fraction `u` of the new rod is placed where the vertex at fraction `u` of
//! the solved rod would be (linear interpolation between the solved vertices), and the
//! frame of the edge whose midpoint is at fraction `u` is slerped between the solved
//! edge frames around `u` (the first and last solved frames are kept beyond the
//! outermost edge midpoints). Supports are not applied here: the solver puts held
//! vertices onto their supports before it starts.

use nalgebra::UnitQuaternion;
use strand_rod::{Rod, RodState, so3};
use strand_system::{Model, SystemState, initial_state};

/// Arc-length fractions `s_j / L` of a rod's vertices (the last exactly 1).
fn fractions(rod: &Rod) -> Vec<f64> {
    let s = rod.arc_lengths();
    let length = *s.last().expect("a rod has vertices");
    let mut u: Vec<f64> = s.iter().map(|s| s / length).collect();
    *u.last_mut().expect("vertices") = 1.0;
    u
}

/// The interval `k` with `grid[k] <= u < grid[k + 1]` (clamped to the grid) and the
/// interpolation weight of `grid[k + 1]`; the weight is exactly 0 where `u` is a grid
/// point, so a state resampled onto its own grid is copied exactly.
fn locate(grid: &[f64], u: f64) -> (usize, f64) {
    let last = grid.len() - 1;
    if last == 0 || u <= grid[0] {
        return (0, 0.0);
    }
    if u >= grid[last] {
        return (last, 0.0);
    }
    let k = grid.partition_point(|g| *g <= u) - 1;
    (k, (u - grid[k]) / (grid[k + 1] - grid[k]))
}

/// Slerp from `a` to `b` by `t` (exactly `a` at `t = 0`).
fn slerp(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>, t: f64) -> UnitQuaternion<f64> {
    if t == 0.0 {
        *a
    } else {
        a * so3::exp(&(t * so3::relative_rotation_vector(a, b)))
    }
}

/// `state` (a configuration of `from`) resampled onto the vertices and edges of `to`
/// by reference arc-length fraction: positions linearly, frames by slerp.
pub fn resample_rod_state(from: &Rod, state: &RodState, to: &Rod) -> RodState {
    let u_from = fractions(from);
    let u_to = fractions(to);
    let positions = u_to
        .iter()
        .map(|&u| {
            let (k, t) = locate(&u_from, u);
            let a = state.positions[k];
            if t == 0.0 {
                a
            } else {
                a + (state.positions[k + 1] - a) * t
            }
        })
        .collect();
    let mid = |u: &[f64]| -> Vec<f64> { u.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect() };
    let mid_from = mid(&u_from);
    let frames = mid(&u_to)
        .iter()
        .map(|&u| {
            let (k, t) = locate(&mid_from, u);
            if t == 0.0 {
                state.frames[k]
            } else {
                slerp(&state.frames[k], &state.frames[k + 1], t)
            }
        })
        .collect();
    RodState::new(positions, frames)
}

/// The initial state of `target` warm-started from `solved`, a state of `base`: every
/// rod of `target` takes the resampled state of the `base` rod of the same name (a rod
/// without one keeps the target's default initial guess). Everything else in the
/// state is carried over from `solved`.
pub fn warm_start(base: &Model, solved: &SystemState, target: &Model) -> SystemState {
    let base_rods = &base.system().rods;
    let mut fallback: Option<SystemState> = None;
    let rods = target
        .system()
        .rods
        .iter()
        .enumerate()
        .map(
            |(r, spec)| match base_rods.iter().position(|b| b.name == spec.name) {
                Some(b) => resample_rod_state(&base_rods[b].rod, &solved.rods[b], &spec.rod),
                None => fallback
                    .get_or_insert_with(|| initial_state(target.system()))
                    .rods[r]
                    .clone(),
            },
        )
        .collect();
    let mut state = solved.clone();
    state.rods = rods;
    state
}

#[cfg(test)]
mod tests {
    use nalgebra::{UnitQuaternion, Vector3};
    use strand_rod::{Rod, RodState, Section};

    use super::*;

    fn section() -> Section {
        Section::try_explicit(3e4, 1e4, 1.0, 1.0, 0.0, 0.0).unwrap()
    }

    /// A curved, twisted state of a 1 m rod with `n` edges.
    fn curved(n: usize) -> (Rod, RodState) {
        let rod = Rod::try_straight(section(), 1.0, n).unwrap();
        let positions = rod
            .arc_lengths()
            .iter()
            .map(|s| Vector3::new(s.sin(), 1.0 - s.cos(), 0.1 * s * s))
            .collect();
        let frames = (0..n)
            .map(|e| UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -0.2 * e as f64, 0.1)))
            .collect();
        (rod, RodState::new(positions, frames))
    }

    #[test]
    fn resampling_onto_the_same_grid_is_the_identity() {
        for n in [1, 2, 7, 19] {
            let (rod, state) = curved(n);
            let again = resample_rod_state(&rod, &state, &rod);
            assert_eq!(again.positions, state.positions, "{n} edges");
            assert_eq!(again.frames, state.frames, "{n} edges");
        }
    }

    #[test]
    fn resampling_a_straight_rod_onto_a_finer_grid_gives_the_straight_rod() {
        let frame = UnitQuaternion::from_scaled_axis(Vector3::new(0.2, 0.7, -0.4));
        let start = Vector3::new(0.1, -0.3, 2.0);
        let coarse = Rod::try_straight(section(), 0.4, 5).unwrap();
        let state = RodState::straight(&coarse, start, frame);
        for (length, n) in [(0.4, 37), (0.4, 5 * 8), (0.45, 41)] {
            let fine = Rod::try_straight(section(), length, n).unwrap();
            let resampled = resample_rod_state(&coarse, &state, &fine);
            // The same straight line from the same start, stretched onto the new rod's
            // fractions (the base rod's length is kept: it is a warm start).
            let expected =
                RodState::straight(&Rod::try_straight(section(), 0.4, n).unwrap(), start, frame);
            assert_eq!(resampled.positions.len(), n + 1);
            assert_eq!(resampled.frames.len(), n);
            for (p, q) in resampled.positions.iter().zip(&expected.positions) {
                assert!((p - q).norm() < 1e-15, "{length} m, {n} edges: {p} vs {q}");
            }
            for q in &resampled.frames {
                assert!(q.angle_to(&frame) < 1e-14, "{length} m, {n} edges");
            }
        }
    }

    #[test]
    fn frames_are_interpolated_on_the_geodesic() {
        let rod = Rod::try_straight(section(), 1.0, 2).unwrap();
        let a = UnitQuaternion::identity();
        let b = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 1.0);
        let state = RodState::new(
            vec![Vector3::zeros(), Vector3::z() * 0.5, Vector3::z()],
            vec![a, b],
        );
        // Four edges: midpoints at 1/8, 3/8, 5/8, 7/8; solved midpoints at 1/4 and 3/4.
        let fine = Rod::try_straight(section(), 1.0, 4).unwrap();
        let frames = resample_rod_state(&rod, &state, &fine).frames;
        let angles: Vec<f64> = frames.iter().map(|q| q.angle_to(&a)).collect();
        let expected = [0.0, 0.25, 0.75, 1.0];
        for (got, want) in angles.iter().zip(expected) {
            assert!((got - want).abs() < 1e-14, "{angles:?}");
        }
    }
}
