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

/// [`stretch_shear`] without the second derivatives (the Hessian is left zero), for an
/// evaluation that needs no Hessian; energy and gradient are the same to the last bit.
pub fn stretch_shear_gradient(e: &StretchShear<'_>) -> ElementDerivatives<9> {
    let first = first_order(e);
    ElementDerivatives {
        energy: first.energy,
        gradient: first.gradient,
        hessian: Default::default(),
    }
}

/// The change of the edge element's gradient (in `(r_a, r_b, δθ)`: N, N, N·m) per
/// unit change of its inputs at a fixed frame: the edge vector by `d_edge_vector`
/// (m), the reference length by `d_length` (m), the stiffnesses by `d_stiffness` (N)
/// and the rest strain by `d_rest_strain` (dimensionless), each per unit of the
/// parameter that moves them. Closed form (the derivative of `(−f, f, h F × Γ)` with
/// `Γ = Rᵀ e / h`, `F = C_Γ (Γ − Γ0)`, `f = R F`):
/// `dΓ = Rᵀ de / h − Γ dh / h`, `dF = dC (Γ − Γ0) + C_Γ (dΓ − dΓ0)`, and the gradient
/// changes by `(−R dF, R dF, dh F × Γ + h (dF × Γ + F × dΓ))`.
pub fn stretch_shear_gradient_tangent(
    e: &StretchShear<'_>,
    d_edge_vector: &Vector3<f64>,
    d_length: f64,
    d_stiffness: &Vector3<f64>,
    d_rest_strain: &Vector3<f64>,
) -> SVector<f64, 9> {
    let h = e.length;
    let gamma = e.strain();
    let delta = gamma - e.rest_strain;
    let force_material = e.stiffness.component_mul(&delta);
    let d_gamma = e.frame.inverse_transform_vector(d_edge_vector) / h - gamma * (d_length / h);
    let d_force =
        d_stiffness.component_mul(&delta) + e.stiffness.component_mul(&(d_gamma - d_rest_strain));
    let d_spatial = e.frame.transform_vector(&d_force);
    let mut out = SVector::<f64, 9>::zeros();
    out.fixed_rows_mut::<3>(0).copy_from(&(-d_spatial));
    out.fixed_rows_mut::<3>(3).copy_from(&d_spatial);
    out.fixed_rows_mut::<3>(6).copy_from(
        &(d_length * force_material.cross(&gamma)
            + h * (d_force.cross(&gamma) + force_material.cross(&d_gamma))),
    );
    out
}

/// The strain, material force, rotation, energy and gradient of an edge element.
struct FirstOrder {
    rotation: Matrix3<f64>,
    gamma: Vector3<f64>,
    c: Matrix3<f64>,
    force_material: Vector3<f64>,
    energy: f64,
    gradient: SVector<f64, 9>,
}

fn first_order(e: &StretchShear<'_>) -> FirstOrder {
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
    FirstOrder {
        rotation,
        gamma,
        c,
        force_material,
        energy: 0.5 * h * delta.dot(&force_material),
        gradient,
    }
}

fn stretch_shear_with_stress(
    e: &StretchShear<'_>,
    stress: Option<&Vector3<f64>>,
) -> ElementDerivatives<9> {
    let h = e.length;
    let FirstOrder {
        rotation,
        gamma,
        c,
        force_material,
        energy,
        gradient,
    } = first_order(e);
    let stress = stress.copied().unwrap_or(force_material);

    // Blocks written entry by entry (C_Γ diagonal): k_rr = R C Rᵀ / h,
    // k_rt = R (C [Γ]× − [σ]×), k_tt = h ([Γ]×ᵀ C [Γ]× + ½(σ Γᵀ + Γ σᵀ) − (σ·Γ) I).
    let r = &rotation;
    let cd = [c[(0, 0)], c[(1, 1)], c[(2, 2)]];
    let gamma_x = skew(&gamma);
    let stress_x = skew(&stress);
    let stress_dot_gamma = stress.dot(&gamma);
    let mut hessian = SMatrix::<f64, 9, 9>::zeros();
    for i in 0..3 {
        for j in i..3 {
            let k_rr = (r[(i, 0)] * cd[0] * r[(j, 0)]
                + r[(i, 1)] * cd[1] * r[(j, 1)]
                + r[(i, 2)] * cd[2] * r[(j, 2)])
                / h;
            for (row, col, value) in [(i, j, k_rr), (3 + i, 3 + j, k_rr), (i, 3 + j, -k_rr)] {
                hessian[(row, col)] = value;
                hessian[(col, row)] = value;
            }
            hessian[(3 + i, j)] = -k_rr;
            hessian[(j, 3 + i)] = -k_rr;
            let k_tt = h
                * (cd[0] * gamma_x[(0, i)] * gamma_x[(0, j)]
                    + cd[1] * gamma_x[(1, i)] * gamma_x[(1, j)]
                    + cd[2] * gamma_x[(2, i)] * gamma_x[(2, j)]
                    + 0.5 * (stress[i] * gamma[j] + gamma[i] * stress[j])
                    - if i == j { stress_dot_gamma } else { 0.0 });
            hessian[(6 + i, 6 + j)] = k_tt;
            hessian[(6 + j, 6 + i)] = k_tt;
        }
    }
    // B = C [Γ]× − [σ]×, then k_rt = R B.
    let mut b = [[0.0; 3]; 3];
    for (m, b_row) in b.iter_mut().enumerate() {
        for (n, b_value) in b_row.iter_mut().enumerate() {
            *b_value = cd[m] * gamma_x[(m, n)] - stress_x[(m, n)];
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            let k_rt = r[(i, 0)] * b[0][j] + r[(i, 1)] * b[1][j] + r[(i, 2)] * b[2][j];
            hessian[(3 + i, 6 + j)] = k_rt;
            hessian[(6 + j, 3 + i)] = k_rt;
            hessian[(i, 6 + j)] = -k_rt;
            hessian[(6 + j, i)] = -k_rt;
        }
    }

    ElementDerivatives {
        energy,
        gradient,
        hessian,
    }
}
