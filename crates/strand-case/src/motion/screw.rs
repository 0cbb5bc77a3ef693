//! Rigid motions on SE(3): the exponential and logarithm of a rigid motion (its screw
//! coordinates) and the screw interpolation between two poses, the path of constant
//! angular and linear velocity about one screw axis.
//!
//! Poses are [`Isometry3`]s `x ↦ R x + t` in any length unit (the interpolation does
//! not depend on it).

use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use strand_rod::so3;

/// Below this rotation angle (rad) the series forms of the `V` matrices are used.
const SMALL_ANGLE_RAD: f64 = 1e-6;

fn skew(w: &Vector3<f64>) -> Matrix3<f64> {
    w.cross_matrix()
}

/// `V(ω) = I + (1 − cos θ)/θ² [ω]× + (θ − sin θ)/θ³ [ω]×²`, which maps the linear
/// screw coordinate to the translation: `t = V(ω) v`.
fn v_matrix(w: &Vector3<f64>) -> Matrix3<f64> {
    let theta = w.norm();
    let k = skew(w);
    let (a, b) = if theta < SMALL_ANGLE_RAD {
        (0.5, 1.0 / 6.0)
    } else {
        let t2 = theta * theta;
        (
            (1.0 - theta.cos()) / t2,
            (theta - theta.sin()) / (t2 * theta),
        )
    };
    Matrix3::identity() + k * a + k * k * b
}

/// `V(ω)⁻¹ = I − ½[ω]× + (1/θ²)(1 − θ sin θ / (2(1 − cos θ))) [ω]×²`.
fn v_inverse(w: &Vector3<f64>) -> Matrix3<f64> {
    let theta = w.norm();
    let k = skew(w);
    let c = if theta < SMALL_ANGLE_RAD {
        1.0 / 12.0
    } else {
        (1.0 - theta * theta.sin() / (2.0 * (1.0 - theta.cos()))) / (theta * theta)
    };
    Matrix3::identity() - k * 0.5 + k * k * c
}

/// The screw coordinates `(ω, v)` of a rigid motion: rotation vector `ω` (rad) and
/// linear part `v` (length unit) with `pose = exp(ω, v)`.
pub fn log(pose: &Isometry3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let w = so3::log(&pose.rotation);
    let v = v_inverse(&w) * pose.translation.vector;
    (w, v)
}

/// The rigid motion with screw coordinates `(ω, v)` (inverse of [`log`]).
pub fn exp(w: &Vector3<f64>, v: &Vector3<f64>) -> Isometry3<f64> {
    let rotation: UnitQuaternion<f64> = so3::exp(w);
    Isometry3::from_parts(Translation3::from(v_matrix(w) * v), rotation)
}

/// The screw interpolation from `a` (`t = 0`) to `b` (`t = 1`):
/// `a · exp(t · log(a⁻¹ b))`, a rotation about and a slide along one fixed axis at
/// constant rates (exact for a rotation about a point: the interpolated poses rotate
/// about that point). `t` outside `[0, 1]` extrapolates along the same screw.
///
/// ```
/// use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
/// use strand_case::motion::screw;
///
/// // 90° about the z axis through (1, 0, 0): the midpose is 45° about the same axis.
/// let about = |deg: f64| {
///     let r = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), deg.to_radians());
///     let c = Vector3::new(1.0, 0.0, 0.0);
///     Isometry3::from_parts(Translation3::from(c - r * c), r)
/// };
/// let mid = screw::interpolate(&about(0.0), &about(90.0), 0.5);
/// let p = Point3::new(2.0, 0.0, 0.0);
/// assert!((mid * p - about(45.0) * p).norm() < 1e-12);
/// ```
pub fn interpolate(a: &Isometry3<f64>, b: &Isometry3<f64>, t: f64) -> Isometry3<f64> {
    let (w, v) = log(&(a.inverse() * b));
    a * exp(&(w * t), &(v * t))
}

#[cfg(test)]
mod tests {
    use nalgebra::Point3;

    use super::*;

    fn pose(axis: [f64; 3], deg: f64, t: [f64; 3]) -> Isometry3<f64> {
        let axis = nalgebra::Unit::new_normalize(Vector3::from(axis));
        Isometry3::from_parts(
            Translation3::new(t[0], t[1], t[2]),
            UnitQuaternion::from_axis_angle(&axis, deg.to_radians()),
        )
    }

    #[test]
    fn exp_inverts_log() {
        for (axis, deg, t) in [
            ([1.0, 2.0, 3.0], 170.0, [4.0, -5.0, 6.0]),
            ([0.0, 0.0, 1.0], 1e-9, [1.0, 0.0, 0.0]),
            ([1.0, 0.0, 0.0], 0.0, [0.0, 2.0, 0.0]),
        ] {
            let p = pose(axis, deg, t);
            let (w, v) = log(&p);
            let q = exp(&w, &v);
            assert!((q.translation.vector - p.translation.vector).norm() < 1e-12);
            assert!(q.rotation.angle_to(&p.rotation) < 1e-12);
        }
    }

    #[test]
    fn interpolation_hits_its_ends_and_follows_a_screw() {
        let a = pose([0.0, 1.0, 0.0], 10.0, [1.0, 2.0, 3.0]);
        // b: a followed by 60° about z through (5, 0, 0) and a slide of 2 along z.
        let r = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 60f64.to_radians());
        let c = Vector3::new(5.0, 0.0, 0.0);
        let screw_of = |frac: f64| {
            let r = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), frac * 60f64.to_radians());
            Isometry3::from_parts(Translation3::from(c - r * c + Vector3::z() * 2.0 * frac), r)
        };
        let b = screw_of(1.0) * a;
        assert!(r.angle_to(&(b.rotation * a.rotation.inverse())) < 1e-12);
        let p = Point3::new(0.3, -0.7, 1.1);
        assert!((interpolate(&a, &b, 0.0) * p - a * p).norm() < 1e-12);
        assert!((interpolate(&a, &b, 1.0) * p - b * p).norm() < 1e-12);
        // Right-multiplied interpolation a·exp(t·log(a⁻¹b)) equals the left screw
        // (b a⁻¹)^t · a: both are the one-parameter subgroup through a and b.
        for t in [0.25, 0.5, 0.8] {
            let expect = screw_of(t) * a;
            assert!((interpolate(&a, &b, t) * p - expect * p).norm() < 1e-12);
        }
    }
}
