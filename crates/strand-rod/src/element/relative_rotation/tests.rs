//! Checks of the relative rotation's derivatives: against central differences, and
//! against the first (general-product) implementation kept in `reference.rs`.

use nalgebra::{UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::RelativeRotation;
use super::reference::ReferenceRotation;
use crate::so3::{exp, log, right_jacobian};

fn phi_at(q_a: &UnitQuaternion<f64>, q_b: &UnitQuaternion<f64>, x: &[f64; 6]) -> Vector3<f64> {
    let a = q_a * exp(&Vector3::new(x[0], x[1], x[2]));
    let b = q_b * exp(&Vector3::new(x[3], x[4], x[5]));
    log(&(a.inverse() * b))
}

/// `∇(μ·φ)` at chart point `x` of the fixed chart at `(q_a, q_b)`, from the
/// analytic Jacobian at the moved frames and the right Jacobian of SO(3).
fn chart_gradient(
    q_a: &UnitQuaternion<f64>,
    q_b: &UnitQuaternion<f64>,
    x: &[f64; 6],
    mu: &Vector3<f64>,
) -> [f64; 6] {
    let (xa, xb) = (
        Vector3::new(x[0], x[1], x[2]),
        Vector3::new(x[3], x[4], x[5]),
    );
    let rel = RelativeRotation::new(&(q_a * exp(&xa)), &(q_b * exp(&xb)));
    let local = rel.jacobian.transpose() * mu;
    let ga = right_jacobian(&xa).transpose() * local.fixed_rows::<3>(0);
    let gb = right_jacobian(&xb).transpose() * local.fixed_rows::<3>(3);
    [ga[0], ga[1], ga[2], gb[0], gb[1], gb[2]]
}

#[test]
fn derivatives_match_finite_differences() {
    let cases = [
        (Vector3::new(0.3, -0.2, 0.5), Vector3::new(0.1, 0.9, -0.4)),
        (Vector3::new(0.3, -0.2, 0.5), Vector3::new(0.3, -0.2, 0.5)), // φ = 0
        (Vector3::new(0.0, 0.0, 0.0), Vector3::new(2.5, 0.3, 0.0)),   // large angle
        (Vector3::new(0.0, 0.0, 0.0), Vector3::new(0.05, 0.0, 0.02)), // series branch
    ];
    let mu = Vector3::new(0.7, -1.3, 0.4);
    for (ta, tb) in cases {
        let (q_a, q_b) = (exp(&ta), exp(&tb));
        let rel = RelativeRotation::new(&q_a, &q_b);
        assert!((rel.phi - log(&(q_a.inverse() * q_b))).norm() < 1e-14);
        let hess = rel.contracted_hessian(&mu);
        let h = 1e-6;
        for k in 0..6 {
            let mut xp = [0.0; 6];
            let mut xm = [0.0; 6];
            xp[k] = h;
            xm[k] = -h;
            let fd = (phi_at(&q_a, &q_b, &xp) - phi_at(&q_a, &q_b, &xm)) / (2.0 * h);
            assert!(
                (fd - rel.jacobian.column(k)).norm() < 1e-8,
                "jacobian column {k}"
            );
            let (gp, gm) = (
                chart_gradient(&q_a, &q_b, &xp, &mu),
                chart_gradient(&q_a, &q_b, &xm, &mu),
            );
            for l in 0..6 {
                let fd = (gp[l] - gm[l]) / (2.0 * h);
                assert!(
                    (fd - hess[(l, k)]).abs() < 1e-8,
                    "hessian ({l},{k}): fd {fd} vs {}",
                    hess[(l, k)]
                );
            }
        }
    }
}

/// The optimised kernel reproduces the general-product reference to round-off, from
/// coincident frames (series branch) to nearly a half turn and across the sign flip of
/// the quaternion representative.
#[test]
fn equals_the_reference_implementation() {
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let mut random = |scale: f64| {
        Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        ) * scale
    };
    let mut checked = 0;
    for scale in [0.0, 1e-8, 1e-3, 0.05, 0.3, 1.0, 2.0, 3.0] {
        for _ in 0..25 {
            let q_a = exp(&random(3.0));
            let turn = random(scale);
            // Keep the relative angle below π (beyond it the other representative is
            // the same rotation and both kernels flip it alike).
            let turn = if turn.norm() > 3.1 {
                turn * (3.1 / turn.norm())
            } else {
                turn
            };
            let q_b = q_a * exp(&turn);
            let mu = random(5.0);
            let (new, old) = (
                RelativeRotation::new(&q_a, &q_b),
                ReferenceRotation::new(&q_a, &q_b),
            );
            let phi_scale = 1.0 + old.phi.norm();
            assert!(
                (new.phi - old.phi).norm() <= 1e-15 * phi_scale,
                "phi at {turn}"
            );
            let jacobian_error = (new.jacobian - old.jacobian).abs().max();
            assert!(
                jacobian_error <= 1e-14 * phi_scale,
                "jacobian at {turn}: {jacobian_error:e}"
            );
            let (h_new, h_old) = (new.contracted_hessian(&mu), old.contracted_hessian(&mu));
            let hessian_error = (h_new - h_old).abs().max();
            let hessian_scale = 1.0 + h_old.abs().max();
            assert!(
                hessian_error <= 1e-13 * hessian_scale,
                "hessian at {turn}: {hessian_error:e} of {hessian_scale:e}"
            );
            assert_eq!(h_new, h_new.transpose(), "symmetric by construction");
            checked += 1;
        }
    }
    assert_eq!(checked, 200);
}
