//! The derivative of the gradient with respect to a parameter that moves the model's
//! real numbers along a line, in closed form: no moved model is evaluated, no ladder
//! of difference steps.
//!
//! A design moved along one affine parameter (a rod's length, a connector's position,
//! a junction's mass, a stiffness) changes the reference data of a few elements —
//! edge lengths and vertex weights, stiffnesses, rest strains and curvatures, loads,
//! the held vertices the supports place — each affinely in the parameter. The
//! gradient of an edge or vertex element is a closed-form function of those data
//! ([`stretch_shear_gradient_tangent`], [`bend_twist_gradient_tangent`]); the other
//! elements (point loads, body weights, dead end moments, the free vertices' loads)
//! are at most quadratic in the data along the line (a mass times gravity), so one
//! central difference of theirs is exact.

use nalgebra::SMatrix;
use strand_rod::element::{
    ElementDerivatives, bend_twist_gradient_tangent, stretch_shear_gradient_tangent,
};
use strand_rod::sectional::{edge_element, vertex_frames};

use super::ElementKind;
use super::Model;
use super::difference::{GradientDifference, Sides, gradient_buffer};
use crate::system::{SystemError, SystemState};

impl Model {
    /// Sets the system's real numbers at the indices `changed` (in the order of
    /// [`crate::System::reals`], ascending, each once) to `value(index)` in place: the model
    /// [`Model::try_new_like`] builds from [`crate::System::with_reals_changed`], without a
    /// copy of the system or a new numbering of the unknowns (a scratch model moved
    /// along one parameter after another). Where the change moves a body's centre of
    /// mass or ports (the elements' levers), the elements are rebuilt as
    /// [`Model::try_new_like`] does.
    pub fn set_reals_changed(
        &mut self,
        changed: &[usize],
        value: &dyn Fn(usize) -> f64,
    ) -> Result<(), SystemError> {
        let bodies = self.system.bodies.clone();
        self.system.set_reals_changed(changed, value)?;
        let same_bodies = bodies.iter().zip(&self.system.bodies).all(|(a, b)| {
            a.center_of_mass == b.center_of_mass && a.ports == b.ports && a.fixed == b.fixed
        });
        if !same_bodies {
            let system = self.system.clone();
            *self = Model::try_new_like(system, self)?;
        }
        Ok(())
    }

    /// `∂∇E/∂p` at `state`: the derivative of this model's gradient (N, N·m per unit of
    /// the parameter) with respect to a parameter that moves the model's real numbers
    /// along a line, `plus` and `minus` being this model moved by `±step` along it
    /// with their states (this `state` with the supports of each placed,
    /// [`Model::enforce_supports`]). Only the elements whose inputs differ between the
    /// two sides are evaluated: an edge or vertex element (and a clip's half cell) in
    /// closed form at this model and `state`, along the change of its reference data
    /// and held vertices (`(plus − minus) / 2 step`: exact, the data being affine along
    /// the line); the loads, weights and end moments by their central difference
    /// (exact: at most quadratic along the line). `None` where the line moves what the
    /// closed forms do not carry: a boundary frame or an edge frame, a body's geometry
    /// or a clip (the chain rule of the elements attached there), or models that do
    /// not correspond (another structure).
    pub fn gradient_derivative(
        &self,
        state: &SystemState,
        plus: (&Model, &SystemState),
        minus: (&Model, &SystemState),
        step: f64,
    ) -> Option<GradientDifference> {
        let ((a, state_a), (b, state_b)) = (plus, minus);
        let comparable = self.corresponds(state, a, state_a)
            && a.corresponds(state_a, b, state_b)
            && a.same_chains(state_a, b, state_b)
            && self.same_chains(state, a, state_a)
            && step > 0.0;
        if !comparable {
            return None;
        }
        let boundary = self.all_boundary_frames(state);
        let (boundary_a, boundary_b) = (
            a.all_boundary_frames(state_a),
            b.all_boundary_frames(state_b),
        );
        let sides = Sides {
            a,
            b,
            state_a,
            state_b,
            boundary_a: &boundary_a,
            boundary_b: &boundary_b,
            chain_same: true,
            same_section: (a.system.rods.iter().zip(&b.system.rods))
                .map(|(x, y)| x.rod.section() == y.rod.section())
                .collect(),
        };
        // The rods whose specification (reference data, section, supports, loads)
        // differs: with the bodies and clips the same (checked above), the states
        // differ only at their held vertices, so the other rods' edge, vertex, end
        // moment and clip half-cell elements read the same numbers in both.
        let touched: Vec<bool> = (a.system.rods.iter().zip(&b.system.rods))
            .map(|(x, y)| x != y)
            .collect();
        let n = self.dofs.len();
        let (mut exact, mut plus, mut minus) =
            (gradient_buffer(n), gradient_buffer(n), gradient_buffer(n));
        let per = 1.0 / (2.0 * step);
        let mut elements = 0;
        let zero9 = SMatrix::<f64, 9, 9>::zeros();
        let zero6 = SMatrix::<f64, 6, 6>::zeros();
        for ((x, xa), xb) in self
            .elements
            .iter()
            .zip(a.elements.iter())
            .zip(b.elements.iter())
        {
            let untouched = match x.kind {
                ElementKind::Edge { rod, .. }
                | ElementKind::Vertex { rod, .. }
                | ElementKind::EndMoment { rod, .. }
                | ElementKind::ClipHalf { rod, .. } => !touched[rod],
                _ => false,
            };
            if untouched || sides.same_inputs(xa) {
                continue;
            }
            elements += 1;
            match x.kind {
                ElementKind::Edge { rod, edge } => {
                    let stiffness = |m: &Model| m.system.rods[rod].rod.section().strain_stiffness();
                    let (c, ca, cb) = (stiffness(self), stiffness(a), stiffness(b));
                    let (e, ea, eb) = (
                        edge_element(&self.system.rods[rod].rod, &state.rods[rod], &c, edge),
                        edge_element(&a.system.rods[rod].rod, &state_a.rods[rod], &ca, edge),
                        edge_element(&b.system.rods[rod].rod, &state_b.rods[rod], &cb, edge),
                    );
                    if ea.frame != e.frame || eb.frame != e.frame {
                        return None;
                    }
                    let gradient = stretch_shear_gradient_tangent(
                        &e,
                        &((ea.edge_vector - eb.edge_vector) * per),
                        (ea.length - eb.length) * per,
                        &((ca - cb) * per),
                        &((ea.rest_strain - eb.rest_strain) * per),
                    );
                    let d = ElementDerivatives {
                        energy: 0.0,
                        gradient,
                        hessian: zero9,
                    };
                    self.accumulate(state, &mut exact, x, &d, false);
                }
                ElementKind::Vertex { rod, vertex } => {
                    let frames = |s: &SystemState, bf: &[strand_rod::sectional::BoundaryFrames]| {
                        vertex_frames(&s.rods[rod], &bf[rod], vertex).map(|(p, q)| (*p, *q))
                    };
                    let here = frames(state, &boundary)?;
                    if frames(state_a, &boundary_a) != Some(here)
                        || frames(state_b, &boundary_b) != Some(here)
                    {
                        return None;
                    }
                    let data = |m: &Model| {
                        let r = &m.system.rods[rod].rod;
                        (
                            r.vertex_weight(vertex),
                            r.section().curvature_stiffness(),
                            *r.rest_curvature(vertex),
                        )
                    };
                    let ((w, c, k0), (wa, ca, ka), (wb, cb, kb)) = (data(self), data(a), data(b));
                    let element = strand_rod::element::BendTwist {
                        frame_a: &here.0,
                        frame_b: &here.1,
                        weight: w,
                        stiffness: &c,
                        rest_curvature: &k0,
                    };
                    let gradient = bend_twist_gradient_tangent(
                        &element,
                        (wa - wb) * per,
                        &((ca - cb) * per),
                        &((ka - kb) * per),
                    );
                    let d = ElementDerivatives {
                        energy: 0.0,
                        gradient,
                        hessian: zero6,
                    };
                    self.accumulate(state, &mut exact, x, &d, false);
                }
                ElementKind::ClipHalf {
                    rod,
                    vertex,
                    clip,
                    after,
                } => {
                    let half = self.clip_half(state, rod, vertex, clip, after);
                    let ha = a.clip_half(state_a, rod, vertex, clip, after);
                    let hb = b.clip_half(state_b, rod, vertex, clip, after);
                    let same_frames = |h: &super::ClipHalfElement| {
                        h.frame_a == half.frame_a && h.frame_b == half.frame_b
                    };
                    if !(same_frames(&ha) && same_frames(&hb)) {
                        return None;
                    }
                    let gradient = bend_twist_gradient_tangent(
                        &half.element(),
                        (ha.weight - hb.weight) * per,
                        &((ha.stiffness - hb.stiffness) * per),
                        &((ha.rest_curvature - hb.rest_curvature) * per),
                    );
                    let d = ElementDerivatives {
                        energy: 0.0,
                        gradient,
                        hessian: zero6,
                    };
                    self.accumulate(state, &mut exact, x, &d, false);
                }
                // At most quadratic along the line: the central difference is exact.
                _ => {
                    a.accumulate_element(state_a, &boundary_a, xa, &mut plus, false, None);
                    b.accumulate_element(state_b, &boundary_b, xb, &mut minus, false, None);
                }
            }
        }
        a.free_vertex_load_difference(b, &mut plus.gradient, &mut minus.gradient);
        let gradient = exact
            .gradient
            .iter()
            .zip(plus.gradient.iter().zip(&minus.gradient))
            .map(|(e, (p, m))| e + (p - m) * per)
            .collect();
        Some(GradientDifference { gradient, elements })
    }
}

#[cfg(test)]
mod tests;
