//! Leaving an unstable equilibrium: a converged state with a direction of negative
//! curvature (a straight rod compressed or twisted beyond buckling, found from a
//! perfectly straight start) is perturbed along that direction and solved again, so
//! that the solver returns the stable branch a real hose would take.
//!
//! The direction is the generalised eigenvector of `(H, D)` with the most negative
//! eigenvalue (`D` the per-unknown damping scale of [`crate::iteration`]), found by
//! inverse iteration with the shifted matrix `H + σD`, `σ` the smallest shift that makes
//! it positive definite.

use strand_system::{Model, SystemState};

use crate::iteration::{Workspace, damping_scale};

/// Inverse-iteration steps for the direction of negative curvature.
const INVERSE_ITERATIONS: usize = 40;
/// Largest rotation of the perturbation, rad.
pub const PERTURBATION_ROTATION_RAD: f64 = 0.05;
/// Largest translation of the perturbation, as a fraction of the longest rod.
pub const PERTURBATION_TRANSLATION: f64 = 0.01;

/// A unit direction of negative curvature at `state`, scaled to the perturbation size;
/// `None` if the Hessian there is positive definite, or if its most negative
/// curvature is smaller than `min_shift` times the damping scale (`H + min_shift·D`
/// positive definite: a nearly neutral direction).
pub(crate) fn negative_direction(
    model: &Model,
    work: &mut Workspace,
    state: &SystemState,
    min_shift: f64,
) -> Option<Vec<f64>> {
    model.evaluate(state, &mut work.eval, true);
    let scale = damping_scale(
        &work.eval.hessian,
        &work.diagonal,
        &work.rotation,
        &work.bending_scale,
    );
    work.damped.copy_from_slice(&work.eval.hessian);
    work.gauge.fix_matrix(&mut work.damped);
    if work.cholesky.factor(&work.damped) {
        return None;
    }
    let shifted_factor = |work: &mut Workspace, sigma: f64| {
        work.damped.copy_from_slice(&work.eval.hessian);
        for (&k, d) in work.diagonal.iter().zip(&scale) {
            work.damped[k] += sigma * d;
        }
        work.gauge.fix_matrix(&mut work.damped);
        work.cholesky.factor(&work.damped)
    };
    if min_shift > 0.0 && shifted_factor(work, min_shift) {
        return None;
    }
    let mut sigma = 1e-12;
    loop {
        if shifted_factor(work, sigma) {
            break;
        }
        sigma *= 2.0;
        if sigma > 1e6 {
            return None;
        }
    }
    let mut x = generic_start(work.step.len());
    inverse_iteration(work, &scale, &mut x, INVERSE_ITERATIONS)?;
    let (rotation, translation) = model.step_size(&x);
    let longest = model
        .system()
        .rods
        .iter()
        .map(|r| r.rod.length())
        .fold(0.0, f64::max);
    let factor = (PERTURBATION_ROTATION_RAD / rotation.max(1e-300))
        .min(PERTURBATION_TRANSLATION * longest / translation.max(1e-300));
    Some(x.into_iter().map(|v| v * factor).collect())
}

/// A deterministic start vector with no special direction.
pub(crate) fn generic_start(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| ((i as f64 + 1.0) * 0.618_033_988_749_895).fract() - 0.5)
        .collect()
}

/// `steps` steps of inverse iteration `x ← (H + σD)⁻¹ D x / ‖·‖_D` with the factor
/// currently in `work.cholesky` (gauge held): `x` tends to the generalised eigenvector
/// of `(H, D)` whose eigenvalue is nearest `−σ`. `None` if a step degenerates.
pub(crate) fn inverse_iteration(
    work: &mut Workspace,
    scale: &[f64],
    x: &mut [f64],
    steps: usize,
) -> Option<()> {
    for _ in 0..steps {
        for (y, (xi, d)) in work.rhs.iter_mut().zip(x.iter().zip(scale)) {
            *y = xi * d;
        }
        work.gauge.fix_vector(&mut work.rhs);
        work.cholesky.solve_in_place(&mut work.rhs);
        let norm = work
            .rhs
            .iter()
            .zip(scale)
            .map(|(y, d)| y * y * d)
            .sum::<f64>()
            .sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            return None;
        }
        for (xi, y) in x.iter_mut().zip(&work.rhs) {
            *xi = y / norm;
        }
    }
    Some(())
}
