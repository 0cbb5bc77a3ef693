//! A conservative end moment on a frame: `W = −(R_refᵀ m)·log(R_refᵀ R)`.
//!
//! For rotations about the axis of `m` (every planar problem) the generated moment is
//! exactly the dead moment `m`; for general spatial rotations it is the conservative
//! moment whose rotation-vector work is `m·ψ` with `ψ` the spatial rotation vector
//! from the reference frame (a constant spatial couple is not conservative in 3D).

use nalgebra::{SMatrix, SVector, UnitQuaternion, Vector3};

use super::{ElementDerivatives, RelativeRotation};

/// Energy, gradient and Hessian in the increment `δθ` of `frame` of the potential of an
/// end moment `moment` (N·m, spatial) measured from `reference`.
pub fn dead_moment(
    frame: &UnitQuaternion<f64>,
    reference: &UnitQuaternion<f64>,
    moment: &Vector3<f64>,
) -> ElementDerivatives<3> {
    let rel = RelativeRotation::new(reference, frame);
    let mu = -reference.inverse_transform_vector(moment);
    let jacobian_b = rel.jacobian.fixed_columns::<3>(3).into_owned();
    let hessian_full = rel.contracted_hessian(&mu);
    let hessian: SMatrix<f64, 3, 3> = hessian_full.fixed_view::<3, 3>(3, 3).into_owned();
    let gradient: SVector<f64, 3> = jacobian_b.transpose() * mu;
    ElementDerivatives {
        energy: mu.dot(&rel.phi),
        gradient,
        hessian,
    }
}
