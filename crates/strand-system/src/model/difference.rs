//! The difference of two models' gradients over the elements whose inputs differ.
//!
//! A design moved along one parameter (a rod's length, a connector's position, a
//! junction's mass) changes the inputs of a few elements only — the rest lengths of
//! one rod's elements, the elements at one held vertex, one body's weight. The
//! difference of the whole models' gradients then needs only those elements: every
//! other element sees bit for bit the same numbers in both models and contributes the
//! same gradient.

use strand_rod::sectional::{BoundaryFrames, vertex_frames};

use super::{Element, ElementKind, Evaluation, Model};
use crate::system::{BodySpec, SystemState};

/// `∇E_self(state) − ∇E_other(other_state)` and the work it took.
#[derive(Clone, Debug, PartialEq)]
pub struct GradientDifference {
    /// The difference of the gradients, entry by entry (N for position blocks, N·m for
    /// rotation blocks), in the numbering of unknowns both models share.
    pub gradient: Vec<f64>,
    /// How many elements were evaluated in each model: those whose inputs differ, or,
    /// where the models' elements do not correspond, all of them (the larger model's
    /// [`Model::element_count`]).
    pub elements: usize,
}

impl Model {
    /// Number of energy elements (edges, vertices, clip half-cells, point loads, …)
    /// one evaluation goes through.
    pub fn element_count(&self) -> usize {
        self.elements.len()
    }

    /// The gradient of this model at `state` minus that of `other` at `other_state`,
    /// evaluated only over the elements whose inputs differ between the two (their
    /// parameters — rest lengths, strains and curvatures, stiffnesses, loads, masses,
    /// levers — and the parts of the states they read). Equal, to the round-off of
    /// the gradients' sums, to the difference of the two models' full gradients
    /// ([`Model::evaluate`]); every element goes through the one evaluation the full
    /// gradient uses. Where the two models do not have the same unknowns and
    /// elements (another structure, not a design moved along a parameter), it is
    /// that difference of the full gradients.
    pub fn gradient_difference(
        &self,
        state: &SystemState,
        other: &Model,
        other_state: &SystemState,
    ) -> GradientDifference {
        let n = self.dofs.len();
        let mut plus = gradient_buffer(n);
        let mut minus = gradient_buffer(n);
        if !self.corresponds(state, other, other_state) {
            self.evaluate(state, &mut plus, false);
            other.evaluate(other_state, &mut minus, false);
            return GradientDifference {
                gradient: subtract(&plus.gradient, &minus.gradient),
                elements: self.element_count().max(other.element_count()),
            };
        }
        let boundary = self.all_boundary_frames(state);
        let other_boundary = other.all_boundary_frames(other_state);
        let sides = Sides {
            a: self,
            b: other,
            state_a: state,
            state_b: other_state,
            boundary_a: &boundary,
            boundary_b: &other_boundary,
            chain_same: self.same_chains(state, other, other_state),
            same_section: (self.system.rods.iter().zip(&other.system.rods))
                .map(|(a, b)| a.rod.section() == b.rod.section())
                .collect(),
        };
        let mut elements = 0;
        for (a, b) in self.elements.iter().zip(other.elements.iter()) {
            if !sides.same_inputs(a) {
                elements += 1;
                self.accumulate_element(state, &boundary, a, &mut plus, false, None);
                other.accumulate_element(other_state, &other_boundary, b, &mut minus, false, None);
            }
        }
        self.free_vertex_load_difference(other, &mut plus.gradient, &mut minus.gradient);
        GradientDifference {
            gradient: subtract(&plus.gradient, &minus.gradient),
            elements,
        }
    }

    /// Whether `other` has this model's unknowns and elements (kinds, blocks and
    /// levers), and the states the same shape.
    pub(super) fn corresponds(
        &self,
        state: &SystemState,
        other: &Model,
        other_state: &SystemState,
    ) -> bool {
        let same_elements = std::sync::Arc::ptr_eq(&self.elements, &other.elements)
            || (self.elements.len() == other.elements.len()
                && self
                    .elements
                    .iter()
                    .zip(other.elements.iter())
                    .all(|(a, b)| {
                        a.kind == b.kind
                            && a.locals == b.locals
                            && a.globals == b.globals
                            && a.direct == b.direct
                    }));
        let same_shape = |s: &SystemState, t: &SystemState| {
            s.rods.len() == t.rods.len()
                && s.bodies.len() == t.bodies.len()
                && s.clips.len() == t.clips.len()
                && s.rods.iter().zip(&t.rods).all(|(x, y)| {
                    x.positions.len() == y.positions.len() && x.frames.len() == y.frames.len()
                })
        };
        same_elements
            && self.dofs.len() == other.dofs.len()
            && self.dofs.same_numbering(&other.dofs)
            && self.moving_vertex == other.moving_vertex
            && self.system.rods.len() == other.system.rods.len()
            && same_shape(state, other_state)
            && state.rods.len() == self.system.rods.len()
    }

    /// Whether everything the chain rule of an element attached to a body or a clip
    /// reads is the same in both: the clips, the bodies' geometry (not their masses)
    /// and the bodies' poses and joints' coordinates in the states.
    pub(super) fn same_chains(
        &self,
        state: &SystemState,
        other: &Model,
        other_state: &SystemState,
    ) -> bool {
        let same_geometry = |a: &BodySpec, b: &BodySpec| {
            a.center_of_mass == b.center_of_mass
                && a.pose == b.pose
                && a.fixed == b.fixed
                && a.ports == b.ports
        };
        self.system.clips == other.system.clips
            && self.system.bodies.len() == other.system.bodies.len()
            && self
                .system
                .bodies
                .iter()
                .zip(&other.system.bodies)
                .all(|(a, b)| same_geometry(a, b))
            && state.bodies == other_state.bodies
            && state.clips == other_state.clips
    }

    /// The gravity and dead end loads of the vertices that are unknowns, where they
    /// differ: `−F_self` into `plus`, `−F_other` into `minus`.
    pub(super) fn free_vertex_load_difference(
        &self,
        other: &Model,
        plus: &mut [f64],
        minus: &mut [f64],
    ) {
        for (r, (a, b)) in self.system.rods.iter().zip(&other.system.rods).enumerate() {
            let same_rod = a.rod.section().mass_per_length == b.rod.section().mass_per_length
                && a.rod.edge_lengths() == b.rod.edge_lengths()
                && a.start.load.force == b.start.load.force
                && a.end.load.force == b.end.load.force;
            if same_rod && self.system.gravity == other.system.gravity {
                continue;
            }
            for j in 0..a.rod.vertex_count() {
                let Some(block) = self.dofs.vertex(r, j) else {
                    continue;
                };
                if self.is_on_free_body(r, j) {
                    continue; // a PointLoad element carries it
                }
                let (fa, fb) = (self.vertex_load(r, j), other.vertex_load(r, j));
                if fa != fb {
                    for i in 0..3 {
                        plus[3 * block + i] -= fa[i];
                        minus[3 * block + i] -= fb[i];
                    }
                }
            }
        }
    }
}

/// The two models and states being differenced.
pub(super) struct Sides<'a> {
    pub(super) a: &'a Model,
    pub(super) b: &'a Model,
    pub(super) state_a: &'a SystemState,
    pub(super) state_b: &'a SystemState,
    pub(super) boundary_a: &'a [BoundaryFrames],
    pub(super) boundary_b: &'a [BoundaryFrames],
    /// [`Model::same_chains`].
    pub(super) chain_same: bool,
    /// Per rod: whether its section (stiffnesses, mass per length) is the same.
    pub(super) same_section: Vec<bool>,
}

impl Sides<'_> {
    /// Whether element `x` (of `a`, and its counterpart of `b`: the same kind, blocks
    /// and levers, [`Model::corresponds`]) reads the same numbers in both: then their
    /// gradients are equal bit for bit. Conservative: `false` where unsure (an element
    /// attached to a body or clip whose chain differs).
    pub(super) fn same_inputs(&self, x: &Element) -> bool {
        if !x.direct && !self.chain_same {
            return false;
        }
        let (sa, sb) = (&self.a.system, &self.b.system);
        match x.kind {
            ElementKind::Edge { rod, edge } => {
                let (ra, rb) = (&sa.rods[rod].rod, &sb.rods[rod].rod);
                let (pa, pb) = (&self.state_a.rods[rod], &self.state_b.rods[rod]);
                ra.edge_length(edge) == rb.edge_length(edge)
                    && ra.rest_strain(edge) == rb.rest_strain(edge)
                    && self.same_section[rod]
                    && pa.positions[edge] == pb.positions[edge]
                    && pa.positions[edge + 1] == pb.positions[edge + 1]
                    && pa.frames[edge] == pb.frames[edge]
            }
            ElementKind::Vertex { rod, vertex } => {
                let (ra, rb) = (&sa.rods[rod].rod, &sb.rods[rod].rod);
                let frames = |state: &SystemState, boundary: &[BoundaryFrames]| {
                    vertex_frames(&state.rods[rod], &boundary[rod], vertex).map(|(p, q)| (*p, *q))
                };
                ra.vertex_weight(vertex) == rb.vertex_weight(vertex)
                    && ra.rest_curvature(vertex) == rb.rest_curvature(vertex)
                    && self.same_section[rod]
                    && frames(self.state_a, self.boundary_a)
                        == frames(self.state_b, self.boundary_b)
            }
            ElementKind::EndMoment { rod, at_end } => {
                let (ea, eb) = if at_end {
                    (&sa.rods[rod].end, &sb.rods[rod].end)
                } else {
                    (&sa.rods[rod].start, &sb.rods[rod].start)
                };
                let frame = |state: &SystemState| {
                    let frames = &state.rods[rod].frames;
                    if at_end {
                        frames.last().copied()
                    } else {
                        frames.first().copied()
                    }
                };
                ea.load.moment == eb.load.moment
                    && ea.load.moment_reference == eb.load.moment_reference
                    && frame(self.state_a) == frame(self.state_b)
            }
            ElementKind::PointLoad { rod, vertex } => {
                self.a.vertex_load(rod, vertex) == self.b.vertex_load(rod, vertex)
                    && self.state_a.rods[rod].positions[vertex]
                        == self.state_b.rods[rod].positions[vertex]
            }
            ElementKind::BodyWeight { body } => {
                let (ba, bb) = (&sa.bodies[body], &sb.bodies[body]);
                ba.mass == bb.mass
                    && sa.gravity == sb.gravity
                    && ba.center_of_mass == bb.center_of_mass
                    && self.state_a.bodies[body] == self.state_b.bodies[body]
            }
            ElementKind::ClipHalf {
                rod,
                vertex,
                clip,
                after,
            } => {
                let ha = self.a.clip_half(self.state_a, rod, vertex, clip, after);
                let hb = self.b.clip_half(self.state_b, rod, vertex, clip, after);
                ha.frame_a == hb.frame_a
                    && ha.frame_b == hb.frame_b
                    && ha.weight == hb.weight
                    && ha.stiffness == hb.stiffness
                    && ha.rest_curvature == hb.rest_curvature
            }
            // Its gradient is zero in every model.
            ElementKind::JointPadding => true,
        }
    }
}

/// A gradient-only evaluation buffer of `n` unknowns.
pub(super) fn gradient_buffer(n: usize) -> Evaluation {
    Evaluation {
        energy: 0.0,
        gradient: vec![0.0; n],
        hessian: Vec::new(),
        has_hessian: false,
    }
}

/// `a − b`, entry by entry.
fn subtract(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

#[cfg(test)]
mod tests;
