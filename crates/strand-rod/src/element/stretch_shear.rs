//! Shear–extension energy of one edge, paper eq. (5):
//! `W = h ½ ΔΓᵀ C_Γ ΔΓ`, `Γ = Rᵀ (r_b − r_a)/h`, `ΔΓ = Γ − Γ0`.

use nalgebra::{Matrix3, SMatrix, SVector, UnitQuaternion, Vector3};

use super::ElementDerivatives;
use crate::so3::skew;

/// Inputs of one edge element; local unknowns `(r_a, r_b, δθ)`.
#[derive(Clone, Copy, Debug)]
pub struct StretchShear<'a> {
    /// Edge vector `r_j − r_{j-1}` in m.
    pub edge_vector: Vector3<f64>,
    /// Edge frame `q_{j-1/2}`.
    pub frame: &'a UnitQuaternion<f64>,
    /// Reference edge length `h_{j-1/2}` in m.
    pub length: f64,
    /// `diag(C_Γ) = (GA1, GA2, EA)` in N.
    pub stiffness: &'a Vector3<f64>,
    /// Stress-free strain `Γ0` (dimensionless; `e3` for a straight rod).
    pub rest_strain: &'a Vector3<f64>,
}

impl StretchShear<'_> {
    /// The material strain `Γ`.
    pub fn strain(&self) -> Vector3<f64> {
        self.frame.inverse_transform_vector(&self.edge_vector) / self.length
    }

    /// The material sectional force `F = C_Γ (Γ − Γ0)` in N.
    pub fn material_force(&self) -> Vector3<f64> {
        self.stiffness
            .component_mul(&(self.strain() - self.rest_strain))
    }

    /// Element energy in J.
    pub fn energy(&self) -> f64 {
        let delta = self.strain() - self.rest_strain;
        0.5 * self.length * delta.dot(&self.stiffness.component_mul(&delta))
    }
}

/// Energy, gradient and Hessian of the edge element in the unknowns `(r_a, r_b, δθ)`.
///
/// Gradient: `(−f, f, h F × Γ)` with the spatial force `f = R F`; Hessian blocks
/// `∂²/∂r² = R C Rᵀ / h`, `∂²/∂r_b∂θ = R (C [Γ]× − [F]×)` and
/// `∂²/∂θ² = h ([Γ]×ᵀ C [Γ]× + ½(F Γᵀ + Γ Fᵀ) − (F·Γ) I)`.
pub fn stretch_shear(e: &StretchShear<'_>) -> ElementDerivatives<9> {
    stretch_shear_with_stress(e, None)
}

/// [`stretch_shear`] with the Hessian's stress terms (the second derivatives of `Γ`
/// weighted by the material force: `−[F]×` in `∂²/∂r_b∂θ`, `½(F Γᵀ + Γ Fᵀ) − (F·Γ) I`
/// in `∂²/∂θ²`) taken with an independent material force `stress` (N) instead of
/// `C_Γ (Γ − Γ0)`; energy and gradient are unchanged.
///
/// This is the mixed-integration-point Newton method (Magisano, Leonetti & Garcea,
/// 2017): after a step that turns a stiff rod's frames, its strain computed from the
/// new positions carries a spurious second-order part (`C θ²`, huge where `C·h²/EI` is),
/// which the stress terms would turn into a spurious geometric stiffness; the
/// linearised prediction of the force from the last step is free of it. At an
/// equilibrium both forces agree, so the iteration converges to the same state.
pub fn stretch_shear_mixed(e: &StretchShear<'_>, stress: &Vector3<f64>) -> ElementDerivatives<9> {
    stretch_shear_with_stress(e, Some(stress))
}

fn stretch_shear_with_stress(
    e: &StretchShear<'_>,
    stress: Option<&Vector3<f64>>,
) -> ElementDerivatives<9> {
    let h = e.length;
    let rotation = e.frame.to_rotation_matrix().into_inner();
    let gamma = e.strain();
    let delta = gamma - e.rest_strain;
    let c = Matrix3::from_diagonal(e.stiffness);
    let force_material = c * delta;
    let force = rotation * force_material;
    let stress = stress.copied().unwrap_or(force_material);

    let mut gradient = SVector::<f64, 9>::zeros();
    gradient.fixed_rows_mut::<3>(0).copy_from(&(-force));
    gradient.fixed_rows_mut::<3>(3).copy_from(&force);
    gradient
        .fixed_rows_mut::<3>(6)
        .copy_from(&(h * force_material.cross(&gamma)));

    let k_rr = rotation * c * rotation.transpose() / h;
    let gamma_x = skew(&gamma);
    let k_rt = rotation * (c * gamma_x - skew(&stress));
    let k_tt = h
        * (gamma_x.transpose() * c * gamma_x
            + 0.5 * (stress * gamma.transpose() + gamma * stress.transpose())
            - stress.dot(&gamma) * Matrix3::identity());

    let mut hessian = SMatrix::<f64, 9, 9>::zeros();
    hessian.fixed_view_mut::<3, 3>(0, 0).copy_from(&k_rr);
    hessian.fixed_view_mut::<3, 3>(3, 3).copy_from(&k_rr);
    hessian.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-k_rr));
    hessian.fixed_view_mut::<3, 3>(3, 0).copy_from(&(-k_rr));
    hessian.fixed_view_mut::<3, 3>(3, 6).copy_from(&k_rt);
    hessian
        .fixed_view_mut::<3, 3>(6, 3)
        .copy_from(&k_rt.transpose());
    hessian.fixed_view_mut::<3, 3>(0, 6).copy_from(&(-k_rt));
    hessian
        .fixed_view_mut::<3, 3>(6, 0)
        .copy_from(&(-k_rt.transpose()));
    hessian.fixed_view_mut::<3, 3>(6, 6).copy_from(&k_tt);

    ElementDerivatives {
        energy: 0.5 * h * delta.dot(&force_material),
        gradient,
        hessian,
    }
}

/// [`stretch_shear`]'s energy and gradient alone (the Hessian left zero): the same
/// numbers, for evaluations that need no Hessian.
pub fn stretch_shear_gradient(e: &StretchShear<'_>) -> ElementDerivatives<9> {
    let h = e.length;
    let rotation = e.frame.to_rotation_matrix().into_inner();
    let gamma = e.strain();
    let delta = gamma - e.rest_strain;
    let c = Matrix3::from_diagonal(e.stiffness);
    let force_material = c * delta;
    let force = rotation * force_material;
    let mut gradient = SVector::<f64, 9>::zeros();
    gradient.fixed_rows_mut::<3>(0).copy_from(&(-force));
    gradient.fixed_rows_mut::<3>(3).copy_from(&force);
    gradient
        .fixed_rows_mut::<3>(6)
        .copy_from(&(h * force_material.cross(&gamma)));
    ElementDerivatives {
        energy: 0.5 * h * delta.dot(&force_material),
        gradient,
        hessian: SMatrix::zeros(),
    }
}
