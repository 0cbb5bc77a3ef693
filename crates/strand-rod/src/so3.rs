//! Rotation helpers on SO(3) and unit quaternions (Hamilton convention, as nalgebra).

use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// The skew-symmetric matrix `[v]×` with `[v]× u = v × u`.
#[inline]
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// The rotation `exp([θ]×)` as a unit quaternion `exp(θ/2)`; `θ` in rad.
#[inline]
pub fn exp(theta: &Vector3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_scaled_axis(*theta)
}

/// The right Jacobian `J_r(θ)` of SO(3): `exp(θ + δ) ≈ exp(θ) exp(J_r(θ) δ)`.
///
/// Used to move gradients between the chart at `q` and the chart at `q ⊗ exp(θ/2)`.
pub fn right_jacobian(theta: &Vector3<f64>) -> Matrix3<f64> {
    let angle2 = theta.norm_squared();
    let x = skew(theta);
    let (a, b) = if angle2 < 1e-8 {
        (0.5 - angle2 / 24.0, 1.0 / 6.0 - angle2 / 120.0)
    } else {
        let angle = angle2.sqrt();
        (
            (1.0 - angle.cos()) / angle2,
            (angle - angle.sin()) / (angle2 * angle),
        )
    };
    Matrix3::identity() - a * x + b * x * x
}

/// The rotation vector `2 log(q)` of the representative of `q` with non-negative real
/// part, i.e. the rotation angle lies in `[0, π]`.
#[inline]
pub fn log(q: &UnitQuaternion<f64>) -> Vector3<f64> {
    let q = q.quaternion();
    let (w, v) = if q.w < 0.0 {
        (-q.w, -q.vector())
    } else {
        (q.w, q.vector().into_owned())
    };
    let n = v.norm();
    if n < 1e-300 {
        return Vector3::zeros();
    }
    v * (2.0 * n.atan2(w) / n)
}

/// The relative rotation vector `log(q_aᵀ q_b)` (material in frame `a`), the discrete
/// curvature times the vertex weight, paper §2.3: `K_j h̄_j = 2 log(q*_{j-1/2} q_{j+1/2})`.
#[inline]
pub fn relative_rotation_vector(
    q_a: &UnitQuaternion<f64>,
    q_b: &UnitQuaternion<f64>,
) -> Vector3<f64> {
    log(&(q_a.inverse() * q_b))
}

/// The geodesic mid frame `q_a ⊗ exp(φ/2)` between two frames, `φ = log(q_aᵀ q_b)`.
pub fn mid_frame(q_a: &UnitQuaternion<f64>, q_b: &UnitQuaternion<f64>) -> UnitQuaternion<f64> {
    q_a * exp(&(0.5 * relative_rotation_vector(q_a, q_b)))
}

/// A frame whose third director `a3` is the given direction, with the least rotation
/// from `reference` (used to build frames along a route).
pub fn frame_with_tangent(
    tangent: &Vector3<f64>,
    reference: &UnitQuaternion<f64>,
) -> UnitQuaternion<f64> {
    let a3 = reference * Vector3::z();
    let t = tangent.normalize();
    let turn = UnitQuaternion::rotation_between(&a3, &t).unwrap_or_else(|| {
        // Antiparallel: turn by π about the first director.
        UnitQuaternion::from_axis_angle(&(reference * Vector3::x_axis()), std::f64::consts::PI)
    });
    turn * reference
}

/// `A(z) = atan(√z)/√z` and its first two derivatives in `z ≥ 0`.
///
/// `2 S v` with `S = A(|v|²/w²)/w` is the quaternion logarithm `2 log(w, v)`; the
/// series branch keeps full precision for small rotations.
pub(crate) fn atan_ratio(z: f64) -> (f64, f64, f64) {
    if z < 1e-2 {
        // A = Σ_k (−z)^k/(2k+1), differentiated term by term; ten terms leave a
        // truncation below z^10/21 < 1e-21.
        let (mut a, mut d1, mut d2) = (0.0, 0.0, 0.0);
        let mut z_pow = [1.0; 11]; // z^k
        for k in 1..11 {
            z_pow[k] = z_pow[k - 1] * z;
        }
        for k in 0..10 {
            let kf = k as f64;
            let c = if k % 2 == 0 { 1.0 } else { -1.0 } / (2.0 * kf + 1.0);
            a += c * z_pow[k];
            if k >= 1 {
                d1 += c * kf * z_pow[k - 1];
            }
            if k >= 2 {
                d2 += c * kf * (kf - 1.0) * z_pow[k - 2];
            }
        }
        (a, d1, d2)
    } else {
        let s = z.sqrt();
        let at = s.atan();
        let n = s / (1.0 + s * s) - at;
        let dn = -2.0 * s * s / ((1.0 + s * s) * (1.0 + s * s));
        let d1 = n / (2.0 * s * s * s);
        let d2 = dn / (4.0 * s.powi(4)) - 3.0 * n / (4.0 * s.powi(5));
        (at / s, d1, d2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atan_ratio_branches_agree_with_finite_differences() {
        for &z in &[0.0, 1e-6, 3e-3, 0.0099, 0.0101, 0.3, 2.0, 40.0] {
            let (a, d1, d2) = atan_ratio(z);
            let exact = if z == 0.0 {
                1.0
            } else {
                z.sqrt().atan() / z.sqrt()
            };
            assert!((a - exact).abs() < 1e-15, "A({z})");
            let h = 1e-5 * (1.0 + z);
            if z > h {
                let (ap, d1p, _) = atan_ratio(z + h);
                let (am, d1m, _) = atan_ratio(z - h);
                assert!(
                    (d1 - (ap - am) / (2.0 * h)).abs() < 1e-8 * (1.0 + d1.abs()),
                    "A'({z})"
                );
                assert!(
                    (d2 - (d1p - d1m) / (2.0 * h)).abs() < 1e-7 * (1.0 + d2.abs()),
                    "A''({z})"
                );
            }
        }
        let (_, d1, d2) = atan_ratio(0.0);
        assert!((d1 + 1.0 / 3.0).abs() < 1e-15 && (d2 - 0.4).abs() < 1e-15);
    }

    #[test]
    fn log_inverts_exp() {
        for theta in [
            Vector3::new(0.1, -0.2, 0.3),
            Vector3::new(0.0, 3.0, 0.0),
            Vector3::new(1e-9, 0.0, 0.0),
        ] {
            assert!((log(&exp(&theta)) - theta).norm() < 1e-14);
        }
    }
}
