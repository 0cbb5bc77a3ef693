//! Finite-difference checks of every element's gradient and Hessian at random
//! configurations, in the chart of right rotation increments.

use nalgebra::{DVector, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::*;
use crate::so3::{exp, right_jacobian};

/// Which kind each 3-block of local unknowns is.
#[derive(Clone, Copy)]
enum Block {
    Position,
    Rotation,
}

/// Checks `derivatives(x)` at `x = 0` against central differences of the energy and of
/// the chart gradient `J_rᵀ g_local` at `x = ±h e_k`.
fn check<const D: usize>(
    blocks: &[Block],
    eval: impl Fn(&DVector<f64>) -> ElementDerivatives<D>,
    scale: f64,
) {
    let zero = DVector::zeros(D);
    let at0 = eval(&zero);
    let chart_gradient = |x: &DVector<f64>| -> DVector<f64> {
        let d = eval(x);
        let mut g = DVector::zeros(D);
        for (b, kind) in blocks.iter().enumerate() {
            let local = d.gradient.fixed_rows::<3>(3 * b).into_owned();
            let chart = match kind {
                Block::Position => local,
                Block::Rotation => {
                    right_jacobian(&x.fixed_rows::<3>(3 * b).into_owned()).transpose() * local
                }
            };
            g.fixed_rows_mut::<3>(3 * b).copy_from(&chart);
        }
        g
    };
    let h = 1e-6;
    for k in 0..D {
        let mut xp = zero.clone();
        xp[k] = h;
        let mut xm = zero.clone();
        xm[k] = -h;
        let fd_gradient = (eval(&xp).energy - eval(&xm).energy) / (2.0 * h);
        assert!(
            (fd_gradient - at0.gradient[k]).abs() < 1e-6 * scale,
            "gradient {k}: fd {fd_gradient} vs {}",
            at0.gradient[k]
        );
        let column = (chart_gradient(&xp) - chart_gradient(&xm)) / (2.0 * h);
        for l in 0..D {
            assert!(
                (column[l] - at0.hessian[(l, k)]).abs() < 1e-6 * scale,
                "hessian ({l},{k}): fd {} vs {}",
                column[l],
                at0.hessian[(l, k)]
            );
        }
    }
    assert!(
        (at0.hessian - at0.hessian.transpose()).norm() < 1e-9 * scale,
        "hessian symmetric"
    );
}

fn random_vector(rng: &mut ChaCha8Rng, scale: f64) -> Vector3<f64> {
    Vector3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    ) * scale
}

fn rotated(q: &UnitQuaternion<f64>, x: &DVector<f64>, at: usize) -> UnitQuaternion<f64> {
    q * exp(&x.fixed_rows::<3>(at).into_owned())
}

#[test]
fn stretch_shear_derivatives() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for _ in 0..20 {
        let (ra, rb) = (random_vector(&mut rng, 0.3), random_vector(&mut rng, 0.3));
        let q = exp(&random_vector(&mut rng, 2.0));
        let stiffness = Vector3::new(2.0, 3.0, 5.0);
        let rest = Vector3::new(0.1, -0.05, 0.9);
        let h = rng.random_range(0.1..0.5);
        check::<9>(
            &[Block::Position, Block::Position, Block::Rotation],
            |x| {
                let a = ra + x.fixed_rows::<3>(0);
                let b = rb + x.fixed_rows::<3>(3);
                let frame = rotated(&q, x, 6);
                let e = StretchShear {
                    edge_vector: b - a,
                    frame: &frame,
                    length: h,
                    stiffness: &stiffness,
                    rest_strain: &rest,
                };
                let d = stretch_shear(&e);
                assert!((d.energy - e.energy()).abs() < 1e-12);
                // The gradient-only evaluation gives the same numbers, bit for bit.
                let g = stretch_shear_gradient(&e);
                assert_eq!((g.energy, g.gradient), (d.energy, d.gradient));
                d
            },
            10.0,
        );
    }
}

#[test]
fn bend_twist_derivatives() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for i in 0..20 {
        let qa = exp(&random_vector(&mut rng, 2.0));
        // Relative rotations from tiny (series branch) to large.
        let qb = qa
            * exp(&random_vector(
                &mut rng,
                if i % 2 == 0 { 1.2 } else { 0.01 },
            ));
        let stiffness = Vector3::new(1.0, 2.0, 0.7);
        let rest = random_vector(&mut rng, 1.0);
        let weight = rng.random_range(0.1..0.5);
        check::<6>(
            &[Block::Rotation, Block::Rotation],
            |x| {
                let (a, b) = (rotated(&qa, x, 0), rotated(&qb, x, 3));
                let e = BendTwist {
                    frame_a: &a,
                    frame_b: &b,
                    weight,
                    stiffness: &stiffness,
                    rest_curvature: &rest,
                };
                let d = bend_twist(&e);
                assert!((d.energy - e.energy()).abs() < 1e-12);
                let g = bend_twist_gradient(&e);
                assert_eq!((g.energy, g.gradient), (d.energy, d.gradient));
                d
            },
            10.0,
        );
    }
}

#[test]
fn dead_moment_derivatives_and_planar_exactness() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..10 {
        let reference = exp(&random_vector(&mut rng, 2.0));
        let q = reference * exp(&random_vector(&mut rng, 1.0));
        let moment = random_vector(&mut rng, 3.0);
        check::<3>(
            &[Block::Rotation],
            |x| dead_moment(&rotated(&q, x, 0), &reference, &moment),
            10.0,
        );
    }
    // Rotating about the moment axis by θ: the energy is −|m| θ, the torque exactly m.
    let moment = Vector3::new(0.0, 0.0, 2.5);
    let reference = UnitQuaternion::identity();
    let q = exp(&Vector3::new(0.0, 0.0, 1.1));
    let d = dead_moment(&q, &reference, &moment);
    assert!((d.energy + 2.5 * 1.1).abs() < 1e-14);
    assert!(
        ((q * d.gradient) + moment).norm() < 1e-14,
        "spatial torque −m"
    );
}

/// The entry-by-entry Hessian of the edge element equals its block formulas written
/// as nalgebra matrix products (the first implementation), with the element's own
/// force and with an independent mixed-method stress.
#[test]
fn stretch_shear_hessian_equals_the_block_formulas() {
    use crate::so3::skew;
    use nalgebra::{Matrix3, SMatrix};
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    for _ in 0..50 {
        let frame = exp(&random_vector(&mut rng, 3.0));
        let stiffness = Vector3::new(
            rng.random_range(1.0..1e3),
            rng.random_range(1.0..1e3),
            rng.random_range(1e3..1e6),
        );
        let rest = Vector3::new(0.02, -0.01, 1.0);
        let h = rng.random_range(1e-3..0.5);
        let e = StretchShear {
            edge_vector: random_vector(&mut rng, h),
            frame: &frame,
            length: h,
            stiffness: &stiffness,
            rest_strain: &rest,
        };
        let stress = random_vector(&mut rng, 1e3);
        for (d, stress) in [
            (stretch_shear(&e), e.material_force()),
            (stretch_shear_mixed(&e, &stress), stress),
        ] {
            let r = frame.to_rotation_matrix().into_inner();
            let c = Matrix3::from_diagonal(&stiffness);
            let gamma = e.strain();
            let k_rr = r * c * r.transpose() / h;
            let k_rt = r * (c * skew(&gamma) - skew(&stress));
            let k_tt = h
                * (skew(&gamma).transpose() * c * skew(&gamma)
                    + 0.5 * (stress * gamma.transpose() + gamma * stress.transpose())
                    - stress.dot(&gamma) * Matrix3::identity());
            let mut expected = SMatrix::<f64, 9, 9>::zeros();
            let blocks = [
                (0, 0, k_rr),
                (3, 3, k_rr),
                (0, 3, -k_rr),
                (3, 0, -k_rr),
                (3, 6, k_rt),
                (6, 3, k_rt.transpose()),
                (0, 6, -k_rt),
                (6, 0, -k_rt.transpose()),
                (6, 6, k_tt),
            ];
            for (row, col, block) in blocks {
                expected.fixed_view_mut::<3, 3>(row, col).copy_from(&block);
            }
            let scale = expected.abs().max();
            let error = (d.hessian - expected).abs().max();
            assert!(error <= 1e-14 * scale, "error {error:e} of {scale:e}");
            assert_eq!(
                d.hessian,
                d.hessian.transpose(),
                "symmetric by construction"
            );
        }
    }
}

/// The closed-form changes of the edge and vertex elements' gradients along a change
/// of their inputs (reference length or weight, stiffnesses, rest strain or
/// curvature, edge vector) match central differences of the gradients to 1e-8 of
/// their size.
#[test]
fn gradient_tangents_match_differences_of_the_gradients() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let mut vector = |size: f64| {
        Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        ) * size
    };
    for _ in 0..20 {
        let frame = UnitQuaternion::from_scaled_axis(vector(1.0));
        let edge_vector = Vector3::new(0.0, 0.0, 0.01) + vector(1e-3);
        let (length, stiffness, rest_strain) = (0.011, Vector3::new(2e4, 3e4, 5e4), vector(0.1));
        let (de, dh, dc, dg0) = (vector(1.0), 0.3, vector(1e4), vector(1.0));
        let edge = |t: f64| {
            let (c, g0) = (stiffness + t * dc, rest_strain + t * dg0);
            stretch_shear_gradient(&StretchShear {
                edge_vector: edge_vector + t * de,
                frame: &frame,
                length: length + t * dh,
                stiffness: &c,
                rest_strain: &g0,
            })
            .gradient
        };
        let t = 1e-6;
        let fd = (edge(t) - edge(-t)) / (2.0 * t);
        let exact = stretch_shear_gradient_tangent(
            &StretchShear {
                edge_vector,
                frame: &frame,
                length,
                stiffness: &stiffness,
                rest_strain: &rest_strain,
            },
            &de,
            dh,
            &dc,
            &dg0,
        );
        assert!(
            (fd - exact).norm() <= 1e-8 * fd.norm().max(exact.norm()),
            "edge: fd {fd} vs {exact}"
        );

        let (a, b) = (
            UnitQuaternion::from_scaled_axis(vector(1.0)),
            UnitQuaternion::from_scaled_axis(vector(1.0)),
        );
        let b = a * UnitQuaternion::from_scaled_axis(b.scaled_axis() * 0.1);
        let (weight, k_stiffness, k0) = (0.012, Vector3::new(0.3, 0.4, 0.2), vector(5.0));
        let (dw, dk, dk0) = (0.4, vector(0.1), vector(10.0));
        let vertex = |t: f64| {
            let (c, r) = (k_stiffness + t * dk, k0 + t * dk0);
            bend_twist_gradient(&BendTwist {
                frame_a: &a,
                frame_b: &b,
                weight: weight + t * dw,
                stiffness: &c,
                rest_curvature: &r,
            })
            .gradient
        };
        let fd = (vertex(t) - vertex(-t)) / (2.0 * t);
        let exact = bend_twist_gradient_tangent(
            &BendTwist {
                frame_a: &a,
                frame_b: &b,
                weight,
                stiffness: &k_stiffness,
                rest_curvature: &k0,
            },
            dw,
            &dk,
            &dk0,
        );
        assert!(
            (fd - exact).norm() <= 1e-8 * fd.norm().max(exact.norm()),
            "vertex: fd {fd} vs {exact}"
        );
    }
}
