//! Element energies of the discrete rod with exact gradients and Hessians.
//!
//! Every element is a pure function of a handful of vertex positions and edge frames.
//! Rotational unknowns are *right increments*: a frame `q` is perturbed as
//! `q ⊗ exp(δθ/2)` (material rotation vector `δθ`), and derivatives are taken at
//! `δθ = 0`. This chart is what the Newton solver uses, so its Hessian is the one Newton
//! needs; the gradient with respect to `δθ` is the material torque of the element.

mod bend_twist;
mod dead_moment;
mod relative_rotation;
mod stretch_shear;

pub use bend_twist::{BendTwist, bend_twist, bend_twist_gradient, bend_twist_gradient_tangent};
pub use dead_moment::dead_moment;
pub use relative_rotation::RelativeRotation;
pub use stretch_shear::{
    StretchShear, stretch_shear, stretch_shear_gradient, stretch_shear_gradient_tangent,
    stretch_shear_mixed,
};

use nalgebra::{SMatrix, SVector};

/// Energy (J), gradient and Hessian of one element with `D` local unknowns.
#[derive(Clone, Debug)]
pub struct ElementDerivatives<const D: usize> {
    /// Element energy in J.
    pub energy: f64,
    /// Gradient: N for position unknowns, N·m for rotation increments.
    pub gradient: SVector<f64, D>,
    /// Hessian (symmetric): N/m, N, N·m blocks.
    pub hessian: SMatrix<f64, D, D>,
}

#[cfg(test)]
mod tests;
