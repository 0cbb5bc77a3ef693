//! The mixed-integration-point Newton method (Magisano, Leonetti & Garcea, 2017) for
//! the shear–extension energy: the stress of every edge is carried from one iterate to
//! the next as its linearised prediction, and the Hessian's stress terms use it.
//!
//! A Newton step that turns the frames of a stiff rod (`C·h²/EI` large: a steel cable,
//! a thin wire, a hose at fine discretisation) by `θ` strains its edges at second order
//! (`θ²/2`) where the linear step predicted no strain. The strain computed from the new
//! positions then carries a spurious force `C θ²/2`, large against everything else, and
//! the stress terms of the next Hessian (the geometric stiffness) are dominated by it:
//! the next step is mispredicted, and so on. The linearised force `C (Γ + δΓ)` of the
//! step has no such part. The gradient is the exact one, so the iteration converges to
//! the same equilibrium, where both forces agree.

use nalgebra::Vector3;
use strand_rod::element::{ElementDerivatives, stretch_shear_mixed};
use strand_rod::sectional::edge_element;
use strand_rod::so3;

use super::{Evaluation, Model};
use crate::system::SystemState;

/// Material edge forces `F = C_Γ (Γ − Γ0)` of every rod (N), per rod and per edge: the
/// independent stresses of the mixed Newton method.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EdgeStresses(pub Vec<Vec<Vector3<f64>>>);

impl Model {
    /// The material edge forces of `state` (N), `C_Γ (Γ − Γ0)` per rod and edge.
    pub fn edge_stresses(&self, state: &SystemState) -> EdgeStresses {
        EdgeStresses(
            self.system
                .rods
                .iter()
                .zip(&state.rods)
                .map(|(spec, rod_state)| {
                    let c = spec.rod.section().strain_stiffness();
                    (0..spec.rod.segments())
                        .map(|e| edge_element(&spec.rod, rod_state, &c, e).material_force())
                        .collect()
                })
                .collect(),
        )
    }

    /// The linearised prediction of the material edge forces (N) at `to`, made from
    /// `from`: `C_Γ (Γ − Γ0 + δΓ)` with the strain's first-order change
    /// `δΓ = Rᵀ δe / h − δθ × Γ` (`δe` the change of the edge vector, `δθ` the material
    /// rotation vector from the frame at `from` to the one at `to`), all at `from`.
    /// `from` and `to` have the same shape (`to` a step of the iteration from `from`).
    pub fn linearised_edge_stresses(&self, from: &SystemState, to: &SystemState) -> EdgeStresses {
        EdgeStresses(
            self.system
                .rods
                .iter()
                .zip(from.rods.iter().zip(&to.rods))
                .map(|(spec, (a, b))| {
                    let c = spec.rod.section().strain_stiffness();
                    (0..spec.rod.segments())
                        .map(|e| {
                            let element = edge_element(&spec.rod, a, &c, e);
                            let gamma = element.strain();
                            let frame = &a.frames[e];
                            let turn = so3::log(&(frame.inverse() * b.frames[e]));
                            let stretch = frame
                                .inverse_transform_vector(&(b.edge_vector(e) - a.edge_vector(e)))
                                / element.length;
                            let predicted = gamma + stretch - turn.cross(&gamma);
                            c.component_mul(&(predicted - element.rest_strain))
                        })
                        .collect()
                })
                .collect(),
        )
    }

    /// Energy, gradient and Hessian of `state` into `out`, the Hessian's stress terms
    /// of every edge element taken with the independent `stresses` (of the same shape
    /// as [`Model::edge_stresses`]). Energy and gradient are those of
    /// [`Model::evaluate`]; with `stresses = edge_stresses(state)` so is the Hessian.
    pub fn evaluate_mixed(
        &self,
        state: &SystemState,
        out: &mut Evaluation,
        stresses: &EdgeStresses,
    ) {
        self.evaluate_with_stresses(state, out, true, Some(stresses));
    }

    pub(super) fn mixed_edge_derivatives(
        &self,
        state: &SystemState,
        rod: usize,
        edge: usize,
        stress: &Vector3<f64>,
    ) -> ElementDerivatives<9> {
        let spec = &self.system.rods[rod];
        let c = spec.rod.section().strain_stiffness();
        stretch_shear_mixed(&edge_element(&spec.rod, &state.rods[rod], &c, edge), stress)
    }
}

#[cfg(test)]
mod tests;
