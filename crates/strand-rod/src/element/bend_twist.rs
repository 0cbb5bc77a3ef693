//! Bending–torsion energy of one vertex, paper eq. (6):
//! `W = h̄ ½ ΔKᵀ C_K ΔK`, `K = 2 log(q_a* q_b)/h̄`, `ΔK = K − K0`.
//!
//! At an attached end the vertex-based boundary frame (`q_0` or `q_N`) plays the role of
//! `q_a` or `q_b` and `h̄` is the half-cell weight `h/2` (DESIGN §1).

use nalgebra::{SVector, UnitQuaternion, Vector3};

use super::{ElementDerivatives, RelativeRotation};

/// Inputs of one vertex element; local unknowns `(δθ_a, δθ_b)`.
#[derive(Clone, Copy, Debug)]
pub struct BendTwist<'a> {
    /// Frame before the vertex (`q_{j-1/2}` or the boundary frame `q_0`).
    pub frame_a: &'a UnitQuaternion<f64>,
    /// Frame after the vertex (`q_{j+1/2}` or the boundary frame `q_N`).
    pub frame_b: &'a UnitQuaternion<f64>,
    /// Vertex weight `h̄_j` in m.
    pub weight: f64,
    /// `diag(C_K) = (EI1, EI2, GJ)` in N·m².
    pub stiffness: &'a Vector3<f64>,
    /// Stress-free curvature `K0` in 1/m.
    pub rest_curvature: &'a Vector3<f64>,
}

impl BendTwist<'_> {
    /// The material curvature `K` in 1/m.
    pub fn curvature(&self) -> Vector3<f64> {
        crate::so3::relative_rotation_vector(self.frame_a, self.frame_b) / self.weight
    }

    /// Element energy in J.
    pub fn energy(&self) -> f64 {
        let delta = self.curvature() - self.rest_curvature;
        0.5 * self.weight * delta.dot(&self.stiffness.component_mul(&delta))
    }
}

/// Energy, gradient and Hessian of the vertex element in `(δθ_a, δθ_b)`.
///
/// With `M = C_K ΔK` the gradient is `Jᵀ M` (`J = ∂φ/∂(α, β)`), the Hessian
/// `Jᵀ C_K J / h̄ + ∇²(M·φ)`. The `β` part of the gradient, rotated to space by `R_b`,
/// is the exact spatial moment the vertex transmits (see [`crate::sectional`]).
pub fn bend_twist(e: &BendTwist<'_>) -> ElementDerivatives<6> {
    let rel = RelativeRotation::new(e.frame_a, e.frame_b);
    let (delta, moment) = curvature_and_moment(e, &rel);
    // Jᵀ C_K J / h̄ added to the upper triangle (C_K diagonal) and mirrored.
    let mut hessian = rel.contracted_hessian(&moment);
    let j = &rel.jacobian;
    let c = e.stiffness / e.weight;
    for k in 0..6 {
        let ck = [c[0] * j[(0, k)], c[1] * j[(1, k)], c[2] * j[(2, k)]];
        for l in k..6 {
            let value = ck[0] * j[(0, l)] + ck[1] * j[(1, l)] + ck[2] * j[(2, l)];
            hessian[(k, l)] += value;
            if l != k {
                hessian[(l, k)] += value;
            }
        }
    }
    ElementDerivatives {
        energy: 0.5 * e.weight * delta.dot(&moment),
        gradient: rel.jacobian.transpose() * moment,
        hessian,
    }
}

/// [`bend_twist`] without the second derivatives (the Hessian is left zero), for an
/// evaluation that needs no Hessian; energy and gradient are the same to the last bit.
pub fn bend_twist_gradient(e: &BendTwist<'_>) -> ElementDerivatives<6> {
    let rel = RelativeRotation::new(e.frame_a, e.frame_b);
    let (delta, moment) = curvature_and_moment(e, &rel);
    ElementDerivatives {
        energy: 0.5 * e.weight * delta.dot(&moment),
        gradient: rel.jacobian.transpose() * moment,
        hessian: Default::default(),
    }
}

/// The change of the vertex element's gradient (in `(δθ_a, δθ_b)`, N·m) per unit
/// change of its inputs at fixed frames: the weight by `d_weight` (m), the
/// stiffnesses by `d_stiffness` (N·m²) and the rest curvature by `d_rest_curvature`
/// (1/m), each per unit of the parameter that moves them. Closed form: the gradient
/// is `Jᵀ M` with `J` a function of the frames alone and `M = C_K (φ/h̄ − K0)`, so it
/// changes by `Jᵀ dM`, `dM = dC (φ/h̄ − K0) − C_K (φ dh̄/h̄² + dK0)`.
pub fn bend_twist_gradient_tangent(
    e: &BendTwist<'_>,
    d_weight: f64,
    d_stiffness: &Vector3<f64>,
    d_rest_curvature: &Vector3<f64>,
) -> SVector<f64, 6> {
    let rel = RelativeRotation::new(e.frame_a, e.frame_b);
    let delta = rel.phi / e.weight - e.rest_curvature;
    let d_delta = -rel.phi * (d_weight / (e.weight * e.weight)) - d_rest_curvature;
    let d_moment = d_stiffness.component_mul(&delta) + e.stiffness.component_mul(&d_delta);
    rel.jacobian.transpose() * d_moment
}

/// `ΔK = φ/h̄ − K0` (1/m) and the moment `M = C_K ΔK` (N·m).
fn curvature_and_moment(e: &BendTwist<'_>, rel: &RelativeRotation) -> (Vector3<f64>, Vector3<f64>) {
    let delta = rel.phi / e.weight - e.rest_curvature;
    let moment = e.stiffness.component_mul(&delta);
    (delta, moment)
}
