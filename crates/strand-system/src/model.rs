//! The assembled model: symbolic phase at construction, numeric phase per evaluation.

use std::ops::Range;
use std::sync::Arc;

use nalgebra::{DVector, UnitQuaternion, Vector3};
use strand_rod::element::{
    BendTwist, ElementDerivatives, bend_twist, bend_twist_gradient, dead_moment, stretch_shear,
    stretch_shear_gradient,
};
use strand_rod::sectional::{BoundaryFrames, edge_element, vertex_frames};
use strand_rod::so3;

use crate::attachment::{LocalBlock, chain_rule};
use crate::dofs::{BlockKind, Dofs};
use crate::pattern::{HessianPattern, ScatterBlock, add_blocks};
use crate::system::{Joint, Support, System, SystemError, SystemState};

mod difference;
mod mixed;
mod tangent;

pub use difference::GradientDifference;
pub use mixed::EdgeStresses;

#[derive(Clone, Copy, Debug, PartialEq)]
enum ElementKind {
    /// Stretch–shear energy of an edge; blocks `(r_a, r_b, θ)`.
    Edge { rod: usize, edge: usize },
    /// Bend–twist energy of a vertex; blocks `(θ_a, θ_b)`.
    Vertex { rod: usize, vertex: usize },
    /// Dead moment at the start (`false`) or end (`true`) edge; block `(θ)`.
    EndMoment { rod: usize, at_end: bool },
    /// Weight and dead end load of a vertex attached to a free body; block `(r)`.
    PointLoad { rod: usize, vertex: usize },
    /// Weight of a free body at its centre of mass; block `(r_com)`.
    BodyWeight { body: usize },
    /// Half-cell bend–twist energy between an edge and a clip's output frame, before
    /// (`after == false`: blocks `(θ_{j−1/2}, Q)`) or after the clip (`(Q, θ_{j+1/2})`).
    ClipHalf {
        rod: usize,
        vertex: usize,
        clip: usize,
        after: bool,
    },
    /// Unit stiffness on the two spare components of a scalar joint's block.
    JointPadding,
}

#[derive(Clone, Debug)]
struct Element {
    kind: ElementKind,
    locals: [LocalBlock; 3],
    /// The global blocks the element couples (in scatter order).
    globals: Vec<usize>,
    /// Whether every local block maps one-to-one (no chain rule needed).
    direct: bool,
    scatter: Range<usize>,
}

/// A validated system with its unknowns numbered and its Hessian pattern fixed.
#[derive(Clone, Debug)]
pub struct Model {
    system: System,
    dofs: Dofs,
    /// Shared by the models of one design moved along its parameters
    /// ([`Model::try_new_like`]).
    pattern: Arc<HessianPattern>,
    elements: Arc<Vec<Element>>,
    scatter: Arc<Vec<ScatterBlock>>,
    /// Per rod and vertex: whether the vertex moves with a free body or a clip joint
    /// (its loads then act through a `PointLoad` element).
    moving_vertex: Vec<Vec<bool>>,
}

/// Energy, gradient and (optionally) Hessian values of one configuration.
#[derive(Clone, Debug, Default)]
pub struct Evaluation {
    /// Total potential energy in J.
    pub energy: f64,
    /// Gradient (N for position blocks, N·m for rotation blocks).
    pub gradient: Vec<f64>,
    /// Hessian values in the model's [`HessianPattern`] (upper triangle).
    pub hessian: Vec<f64>,
    /// Whether `hessian` belongs to the configuration last evaluated into this value
    /// (`false` after an evaluation without the Hessian: then it is stale).
    pub has_hessian: bool,
}

/// Size of a gradient, in physical units.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Residual {
    /// Largest out-of-balance vertex or body force in N (eq. 15).
    pub force_n: f64,
    /// Largest out-of-balance edge or body moment in N·m (eq. 16).
    pub moment_nm: f64,
    /// The convergence measure in N: the larger of `force_n` and every edge's moment
    /// residual divided by its rod's length (see [`Dofs::force_scale`]).
    pub combined_n: f64,
}

impl Model {
    /// Validates the system and performs the symbolic phase.
    pub fn try_new(system: System) -> Result<Self, SystemError> {
        system.validate()?;
        let dofs = Dofs::new(&system);
        let mut elements = elements_of(&system, &dofs);
        let pattern = HessianPattern::new(
            dofs.block_count(),
            elements.iter().map(|e| e.globals.as_slice()),
        );
        let mut scatter = Vec::new();
        for element in &mut elements {
            let start = scatter.len();
            let blocks: Vec<Option<usize>> = if element.direct {
                element
                    .locals
                    .iter()
                    .map(|l| {
                        if let LocalBlock::Free(g) = l {
                            Some(*g)
                        } else {
                            None
                        }
                    })
                    .collect()
            } else {
                element.globals.iter().map(|&g| Some(g)).collect()
            };
            scatter.extend(pattern.scatter(&blocks));
            element.scatter = start..scatter.len();
        }
        let moving_vertex = moving_vertices(&system, &dofs);
        Ok(Self {
            system,
            dofs,
            pattern: Arc::new(pattern),
            elements: Arc::new(elements),
            scatter: Arc::new(scatter),
            moving_vertex,
        })
    }

    /// Validates `system` and performs the symbolic phase like [`Model::try_new`],
    /// reusing `like`'s Hessian pattern and scatter map where `system` has the same
    /// unknowns and elements coupling the same blocks (a design moved along a
    /// parameter: the same rods, segments, bodies and clips with other lengths,
    /// positions, masses or stiffnesses). The result is the model `try_new` builds.
    pub fn try_new_like(system: System, like: &Model) -> Result<Self, SystemError> {
        system.validate()?;
        let dofs = Dofs::new(&system);
        // The elements depend on the system's values only through the bodies' centres
        // of mass and ports (levers and frame offsets).
        let same_bodies = system.bodies.len() == like.system.bodies.len()
            && system.bodies.iter().zip(&like.system.bodies).all(|(a, b)| {
                a.center_of_mass == b.center_of_mass && a.ports == b.ports && a.fixed == b.fixed
            });
        if same_bodies && dofs.same_numbering(&like.dofs) {
            return Ok(Self {
                system,
                dofs,
                pattern: Arc::clone(&like.pattern),
                elements: Arc::clone(&like.elements),
                scatter: Arc::clone(&like.scatter),
                moving_vertex: like.moving_vertex.clone(),
            });
        }
        let mut elements = elements_of(&system, &dofs);
        let same = dofs.len() == like.dofs.len()
            && dofs.block_count() == like.dofs.block_count()
            && elements.len() == like.elements.len()
            && elements
                .iter()
                .zip(like.elements.iter())
                .all(|(a, b)| a.direct == b.direct && a.globals == b.globals);
        if !same {
            return Self::try_new(system);
        }
        for (element, base) in elements.iter_mut().zip(like.elements.iter()) {
            element.scatter = base.scatter.clone();
        }
        let moving_vertex = moving_vertices(&system, &dofs);
        Ok(Self {
            system,
            dofs,
            pattern: Arc::clone(&like.pattern),
            elements: Arc::new(elements),
            scatter: Arc::clone(&like.scatter),
            moving_vertex,
        })
    }

    /// The system this model was built from.
    pub fn system(&self) -> &System {
        &self.system
    }

    /// The numbering of unknowns.
    pub fn dofs(&self) -> &Dofs {
        &self.dofs
    }

    /// The Hessian's sparsity pattern.
    pub fn pattern(&self) -> &HessianPattern {
        &self.pattern
    }

    /// Boundary frames of rod `rod` in `state` (a port's frame moves with its body).
    pub fn boundary_frames(&self, rod: usize, state: &SystemState) -> BoundaryFrames {
        let mut frames = self.system.ends_boundary(rod, &state.bodies);
        frames.clips = self
            .dofs
            .clips()
            .on_rod(rod)
            .iter()
            .map(|&(vertex, c)| {
                let output = self.system.clip_output(c, &state.clips, &state.bodies);
                (vertex, output.orientation)
            })
            .collect();
        frames
    }

    /// An evaluation buffer of the right sizes.
    pub fn new_evaluation(&self) -> Evaluation {
        Evaluation {
            energy: 0.0,
            gradient: vec![0.0; self.dofs.len()],
            hessian: vec![0.0; self.pattern.nnz()],
            has_hessian: false,
        }
    }

    /// Energy, gradient and, if `with_hessian`, Hessian of `state` into `out`.
    pub fn evaluate(&self, state: &SystemState, out: &mut Evaluation, with_hessian: bool) {
        self.evaluate_with_stresses(state, out, with_hessian, None);
    }

    /// [`Model::evaluate`], with the stress terms of the edge elements' Hessians taken
    /// from `stresses` when given (see [`Model::evaluate_mixed`]).
    fn evaluate_with_stresses(
        &self,
        state: &SystemState,
        out: &mut Evaluation,
        with_hessian: bool,
        stresses: Option<&EdgeStresses>,
    ) {
        out.energy = 0.0;
        out.gradient.iter_mut().for_each(|g| *g = 0.0);
        if with_hessian {
            out.hessian.iter_mut().for_each(|h| *h = 0.0);
        }
        out.has_hessian = with_hessian;
        let boundary = self.all_boundary_frames(state);
        for element in self.elements.iter() {
            self.accumulate_element(state, &boundary, element, out, with_hessian, stresses);
        }
        self.add_free_vertex_loads(state, out);
    }

    /// Adds one element's energy, gradient and, if `with_hessian`, Hessian at `state`
    /// into `out` (`boundary`: every rod's boundary frames at `state`). The one place
    /// an element is evaluated: the whole model's evaluation and
    /// [`Model::gradient_difference`] both go through it.
    fn accumulate_element(
        &self,
        state: &SystemState,
        boundary: &[BoundaryFrames],
        element: &Element,
        out: &mut Evaluation,
        with_hessian: bool,
        stresses: Option<&EdgeStresses>,
    ) {
        match element.kind {
            ElementKind::Edge { rod, edge } => {
                let d = match stresses {
                    _ if !with_hessian => self.edge_derivatives(state, rod, edge, false),
                    Some(s) => self.mixed_edge_derivatives(state, rod, edge, &s.0[rod][edge]),
                    None => self.edge_derivatives(state, rod, edge, with_hessian),
                };
                self.accumulate(state, out, element, &d, with_hessian);
            }
            ElementKind::Vertex { rod, vertex } => {
                let d = self.vertex_derivatives(state, &boundary[rod], rod, vertex, with_hessian);
                self.accumulate(state, out, element, &d, with_hessian);
            }
            ElementKind::EndMoment { rod, at_end } => {
                let d = self.end_moment_derivatives(state, rod, at_end);
                self.accumulate(state, out, element, &d, with_hessian);
            }
            ElementKind::PointLoad { .. } | ElementKind::BodyWeight { .. } => {
                let d = self.point_load_derivatives(state, element.kind);
                self.accumulate(state, out, element, &d, with_hessian);
            }
            ElementKind::ClipHalf {
                rod,
                vertex,
                clip,
                after,
            } => {
                let half = self.clip_half(state, rod, vertex, clip, after);
                let d = if with_hessian {
                    bend_twist(&half.element())
                } else {
                    bend_twist_gradient(&half.element())
                };
                self.accumulate(state, out, element, &d, with_hessian);
            }
            ElementKind::JointPadding => {
                let hessian = nalgebra::Matrix3::from_diagonal(&Vector3::new(0.0, 1.0, 1.0));
                let d = ElementDerivatives::<3> {
                    energy: 0.0,
                    gradient: Default::default(),
                    hessian,
                };
                self.accumulate(state, out, element, &d, with_hessian);
            }
        }
    }

    /// Total potential energy of `state` in J (no derivatives).
    pub fn energy(&self, state: &SystemState) -> f64 {
        let boundary = self.all_boundary_frames(state);
        let mut energy = 0.0;
        for element in self.elements.iter() {
            energy += match element.kind {
                ElementKind::Edge { rod, edge } => {
                    let spec = &self.system.rods[rod];
                    let c = spec.rod.section().strain_stiffness();
                    edge_element(&spec.rod, &state.rods[rod], &c, edge).energy()
                }
                ElementKind::Vertex { rod, vertex } => {
                    let spec = &self.system.rods[rod];
                    let c = spec.rod.section().curvature_stiffness();
                    let (q_a, q_b) = vertex_frames(&state.rods[rod], &boundary[rod], vertex)
                        .expect("vertex element");
                    BendTwist {
                        frame_a: q_a,
                        frame_b: q_b,
                        weight: spec.rod.vertex_weight(vertex),
                        stiffness: &c,
                        rest_curvature: spec.rod.rest_curvature(vertex),
                    }
                    .energy()
                }
                ElementKind::EndMoment { rod, at_end } => {
                    self.end_moment_derivatives(state, rod, at_end).energy
                }
                kind @ (ElementKind::PointLoad { .. } | ElementKind::BodyWeight { .. }) => {
                    self.point_load_derivatives(state, kind).energy
                }
                ElementKind::ClipHalf {
                    rod,
                    vertex,
                    clip,
                    after,
                } => self.clip_half(state, rod, vertex, clip, after).energy(),
                ElementKind::JointPadding => 0.0,
            };
        }
        for (r, rod_state) in state.rods.iter().enumerate() {
            for (j, p) in rod_state.positions.iter().enumerate() {
                if !self.is_on_free_body(r, j) {
                    energy -= self.vertex_load(r, j).dot(p);
                }
            }
        }
        energy
    }

    fn all_boundary_frames(&self, state: &SystemState) -> Vec<BoundaryFrames> {
        (0..self.system.rods.len())
            .map(|r| self.boundary_frames(r, state))
            .collect()
    }

    /// Gravity plus dead end load on vertex `j` of rod `r`, N.
    fn vertex_load(&self, r: usize, j: usize) -> Vector3<f64> {
        let spec = &self.system.rods[r];
        let mut force = spec.rod.vertex_mass(j) * self.system.gravity;
        if j == 0 {
            force += spec.start.load.force;
        }
        if j == spec.rod.segments() {
            force += spec.end.load.force;
        }
        force
    }

    /// Whether vertex `j` of rod `r` moves with a free body or a clip joint (its loads
    /// then act through a `PointLoad` element).
    fn is_on_free_body(&self, r: usize, j: usize) -> bool {
        self.moving_vertex[r][j]
    }

    /// The half-cell element on one side of clip `clip` at vertex `vertex` of rod `rod`.
    pub(crate) fn clip_half(
        &self,
        state: &SystemState,
        rod: usize,
        vertex: usize,
        clip: usize,
        after: bool,
    ) -> ClipHalfElement {
        let spec = &self.system.rods[rod];
        let output = self
            .system
            .clip_output(clip, &state.clips, &state.bodies)
            .orientation;
        let frames = &state.rods[rod].frames;
        let (frame_a, frame_b, edge) = if after {
            (output, frames[vertex], vertex)
        } else {
            (frames[vertex - 1], output, vertex - 1)
        };
        ClipHalfElement {
            frame_a,
            frame_b,
            weight: 0.5 * spec.rod.edge_length(edge),
            stiffness: spec.rod.section().curvature_stiffness(),
            rest_curvature: *spec.rod.rest_curvature(vertex),
        }
    }

    fn edge_derivatives(
        &self,
        state: &SystemState,
        rod: usize,
        edge: usize,
        with_hessian: bool,
    ) -> ElementDerivatives<9> {
        let spec = &self.system.rods[rod];
        let c = spec.rod.section().strain_stiffness();
        let element = edge_element(&spec.rod, &state.rods[rod], &c, edge);
        if with_hessian {
            stretch_shear(&element)
        } else {
            stretch_shear_gradient(&element)
        }
    }

    fn vertex_derivatives(
        &self,
        state: &SystemState,
        boundary: &BoundaryFrames,
        rod: usize,
        vertex: usize,
        with_hessian: bool,
    ) -> ElementDerivatives<6> {
        let spec = &self.system.rods[rod];
        let c = spec.rod.section().curvature_stiffness();
        let (q_a, q_b) = vertex_frames(&state.rods[rod], boundary, vertex).expect("vertex element");
        let element = BendTwist {
            frame_a: q_a,
            frame_b: q_b,
            weight: spec.rod.vertex_weight(vertex),
            stiffness: &c,
            rest_curvature: spec.rod.rest_curvature(vertex),
        };
        if with_hessian {
            bend_twist(&element)
        } else {
            bend_twist_gradient(&element)
        }
    }

    fn end_moment_derivatives(
        &self,
        state: &SystemState,
        rod: usize,
        at_end: bool,
    ) -> ElementDerivatives<3> {
        let spec = &self.system.rods[rod];
        let frames = &state.rods[rod].frames;
        let (frame, load) = if at_end {
            (frames.last(), &spec.end.load)
        } else {
            (frames.first(), &spec.start.load)
        };
        dead_moment(frame.expect("edges"), &load.moment_reference, &load.moment)
    }

    /// Potential `−F·r` of a constant force on a point that moves with a body.
    fn point_load_derivatives(
        &self,
        state: &SystemState,
        kind: ElementKind,
    ) -> ElementDerivatives<3> {
        let (force, point) = match kind {
            ElementKind::PointLoad { rod, vertex } => (
                self.vertex_load(rod, vertex),
                state.rods[rod].positions[vertex],
            ),
            ElementKind::BodyWeight { body } => {
                let spec = &self.system.bodies[body];
                (
                    spec.mass * self.system.gravity,
                    state.bodies[body].transform_point(&spec.center_of_mass),
                )
            }
            _ => unreachable!("not a point load"),
        };
        ElementDerivatives {
            energy: -force.dot(&point),
            gradient: -force,
            hessian: Default::default(),
        }
    }

    fn accumulate<const D: usize>(
        &self,
        state: &SystemState,
        out: &mut Evaluation,
        element: &Element,
        d: &ElementDerivatives<D>,
        with_hessian: bool,
    ) {
        out.energy += d.energy;
        let scatter = &self.scatter[element.scatter.clone()];
        if element.direct {
            for (local, block) in element.locals.iter().enumerate().take(D / 3) {
                if let LocalBlock::Free(b) = block {
                    for i in 0..3 {
                        out.gradient[3 * b + i] += d.gradient[3 * local + i];
                    }
                }
            }
            if with_hessian {
                add_blocks(&mut out.hessian, scatter, d.hessian.as_slice(), D);
            }
            return;
        }
        let locals = &element.locals[..D / 3];
        let (jacobian, curvature) = chain_rule(
            locals,
            &element.globals,
            &self.dofs,
            &self.system,
            state,
            d.gradient.as_slice(),
            with_hessian,
        );
        let local_gradient = DVector::from_column_slice(d.gradient.as_slice());
        let gradient = jacobian.transpose() * local_gradient;
        for (k, &g) in element.globals.iter().enumerate() {
            for i in 0..3 {
                out.gradient[3 * g + i] += gradient[3 * k + i];
            }
        }
        if with_hessian {
            let local_hessian = nalgebra::DMatrix::from_column_slice(D, D, d.hessian.as_slice());
            let hessian = jacobian.transpose() * local_hessian * &jacobian + curvature;
            add_blocks(
                &mut out.hessian,
                scatter,
                hessian.as_slice(),
                hessian.nrows(),
            );
        }
    }

    /// Gravity and dead end loads of vertices that are unknowns (linear: gradient only).
    fn add_free_vertex_loads(&self, state: &SystemState, out: &mut Evaluation) {
        for (r, rod_state) in state.rods.iter().enumerate() {
            for (j, p) in rod_state.positions.iter().enumerate() {
                if self.is_on_free_body(r, j) {
                    continue; // a PointLoad element carries it to the body
                }
                let force = self.vertex_load(r, j);
                out.energy -= force.dot(p);
                if let Some(b) = self.dofs.vertex(r, j) {
                    for i in 0..3 {
                        out.gradient[3 * b + i] -= force[i];
                    }
                }
            }
        }
    }

    /// Puts every held vertex of `state` at its support or port (an initial guess from
    /// elsewhere, e.g. a previous solution of a variant, may not satisfy the supports).
    pub fn enforce_supports(&self, state: &mut SystemState) {
        for (b, body) in self.system.bodies.iter().enumerate() {
            if body.fixed {
                state.bodies[b] = body.pose;
            }
        }
        self.place_clipped_vertices(state);
        for (spec, rod_state) in self.system.rods.iter().zip(&mut state.rods) {
            let last = rod_state.positions.len() - 1;
            for (vertex, at_end, end) in [(0, false, &spec.start), (last, true, &spec.end)] {
                if let (Some(position), _) = self.system.end_placement(end, at_end, &state.bodies) {
                    rod_state.set_position(vertex, position);
                }
            }
        }
    }

    /// Puts every clipped vertex at its clip's output origin.
    fn place_clipped_vertices(&self, state: &mut SystemState) {
        for (c, clip) in self.system.clips.iter().enumerate() {
            let position = self
                .system
                .clip_output(c, &state.clips, &state.bodies)
                .position;
            state.rods[clip.rod.0].set_position(clip.vertex, position);
        }
    }

    /// The configuration moved by `step` (positions added, frames `q ⊗ exp(δθ/2)`).
    pub fn retract(&self, state: &SystemState, step: &[f64]) -> SystemState {
        let mut next = state.clone();
        self.retract_into(state, step, 1.0, &mut next);
        next
    }

    /// Writes `state` moved by `scale · step` into `out` (same shape as `state`),
    /// without allocating.
    pub fn retract_into(
        &self,
        state: &SystemState,
        step: &[f64],
        scale: f64,
        out: &mut SystemState,
    ) {
        out.clone_from(state);
        let block = |b: usize| scale * Vector3::new(step[3 * b], step[3 * b + 1], step[3 * b + 2]);
        for (r, rod_state) in out.rods.iter_mut().enumerate() {
            for j in 0..rod_state.positions.len() {
                if let Some(b) = self.dofs.vertex(r, j) {
                    rod_state.translate_vertex(j, &block(b));
                }
            }
            for (e, q) in rod_state.frames.iter_mut().enumerate() {
                *q *= so3::exp(&block(self.dofs.edge(r, e)));
                q.renormalize_fast();
            }
        }
        for (c, clip) in self.system.clips.iter().enumerate() {
            if let Some(b) = self.dofs.clip(c) {
                let joint = &mut out.clips[c];
                match clip.joint {
                    Joint::Fixed => {}
                    Joint::Revolute { .. } | Joint::Prismatic { .. } => {
                        joint.value += scale * step[3 * b];
                        if let Some((lower, upper)) = clip.limits {
                            joint.value = joint.value.clamp(lower, upper);
                        }
                    }
                    Joint::Spherical => {
                        joint.rotation *= so3::exp(&block(b));
                        joint.rotation.renormalize_fast();
                    }
                }
            }
        }
        if self.system.bodies.is_empty() {
            if !self.system.clips.is_empty() {
                self.place_clipped_vertices(out);
            }
            return;
        }
        for (b, pose) in out.bodies.iter_mut().enumerate() {
            if let Some((t, r)) = self.dofs.body(b) {
                pose.position += block(t);
                pose.orientation *= so3::exp(&block(r));
                pose.orientation.renormalize_fast();
            }
        }
        // Vertices held by ports follow their bodies.
        for (spec, rod_state) in self.system.rods.iter().zip(&mut out.rods) {
            let last = rod_state.positions.len() - 1;
            for (vertex, at_end, end) in [(0, false, &spec.start), (last, true, &spec.end)] {
                if let Support::Port { .. } = end.support {
                    let position = self
                        .system
                        .end_placement(end, at_end, &out.bodies)
                        .0
                        .expect("port position");
                    rod_state.set_position(vertex, position);
                }
            }
        }
        // Clips follow their joints and carrier bodies.
        self.place_clipped_vertices(out);
    }

    /// Moves `gradient`, evaluated at `retract(state, scale · step)`, into the chart of
    /// `state`: every rotation block `g` (edge frames, ball-clip joints, body
    /// orientations, all retracted as `q ⊗ exp(θ)`) becomes `J_r(scale · θ)ᵀ g`;
    /// positions and joint angles are unchanged. Differences of pulled-back gradients
    /// along a step are then derivatives of one function (the energy pulled back to
    /// `state`), as a second-order correction of the step needs.
    pub fn pull_back_gradient(&self, step: &[f64], scale: f64, gradient: &mut [f64]) {
        let mut pull = |b: usize| {
            let theta = scale * Vector3::new(step[3 * b], step[3 * b + 1], step[3 * b + 2]);
            let g = Vector3::new(gradient[3 * b], gradient[3 * b + 1], gradient[3 * b + 2]);
            let pulled = so3::right_jacobian(&theta).transpose() * g;
            gradient[3 * b..3 * b + 3].copy_from_slice(pulled.as_slice());
        };
        for (r, spec) in self.system.rods.iter().enumerate() {
            for e in 0..spec.rod.segments() {
                pull(self.dofs.edge(r, e));
            }
        }
        for (c, clip) in self.system.clips.iter().enumerate() {
            if let (Joint::Spherical, Some(b)) = (&clip.joint, self.dofs.clip(c)) {
                pull(b);
            }
        }
        for b in 0..self.system.bodies.len() {
            if let Some((_, rotation)) = self.dofs.body(b) {
                pull(rotation);
            }
        }
    }

    /// How `direction · r` changes with the unknowns, for the position `r` of vertex
    /// `vertex` of rod `rod` at `state`: `(unknown index, ∂(direction · r)/∂unknown)`.
    /// Empty for a vertex fixed in space; through the body or clip for a held vertex.
    /// Contact constraints are linearised with it.
    pub fn vertex_direction_gradient(
        &self,
        state: &SystemState,
        rod: usize,
        vertex: usize,
        direction: &Vector3<f64>,
    ) -> Vec<(usize, f64)> {
        match vertex_local(&self.system, &self.dofs, rod, vertex) {
            LocalBlock::Fixed => vec![],
            LocalBlock::Free(b) => (0..3).map(|k| (3 * b + k, direction[k])).collect(),
            local => {
                let globals = local.globals(&self.dofs, &self.system);
                let (jacobian, _) = chain_rule(
                    &[local],
                    &globals,
                    &self.dofs,
                    &self.system,
                    state,
                    direction.as_slice(),
                    false,
                );
                let row = direction.transpose() * jacobian;
                globals
                    .iter()
                    .flat_map(|&g| (0..3).map(move |k| 3 * g + k))
                    .zip(row.iter().copied())
                    .filter(|(_, v)| *v != 0.0)
                    .collect()
            }
        }
    }

    /// The size of a gradient in physical units.
    pub fn residual(&self, gradient: &[f64]) -> Residual {
        let mut residual = Residual::default();
        for b in 0..self.dofs.block_count() {
            let norm =
                Vector3::new(gradient[3 * b], gradient[3 * b + 1], gradient[3 * b + 2]).norm();
            match self.dofs.kind(b) {
                BlockKind::Position => residual.force_n = residual.force_n.max(norm),
                BlockKind::Rotation => residual.moment_nm = residual.moment_nm.max(norm),
            }
            residual.combined_n = residual.combined_n.max(norm / self.dofs.force_scale(b));
        }
        residual
    }

    /// Largest rotation (rad) and translation (m) in a step, for step-length control.
    pub fn step_size(&self, step: &[f64]) -> (f64, f64) {
        let (mut rotation, mut translation) = (0.0f64, 0.0f64);
        for b in 0..self.dofs.block_count() {
            let norm = Vector3::new(step[3 * b], step[3 * b + 1], step[3 * b + 2]).norm();
            match self.dofs.kind(b) {
                BlockKind::Position => translation = translation.max(norm),
                BlockKind::Rotation => rotation = rotation.max(norm),
            }
        }
        (rotation, translation)
    }
}

/// The elements of `system` numbered by `dofs`, without their scatter ranges.
fn elements_of(system: &System, dofs: &Dofs) -> Vec<Element> {
    let mut elements = Vec::new();
    let mut push = |kind, locals: [LocalBlock; 3]| {
        let mut globals = Vec::new();
        for local in &locals {
            for g in local.globals(dofs, system) {
                if !globals.contains(&g) {
                    globals.push(g);
                }
            }
        }
        let direct = locals.iter().all(LocalBlock::is_direct);
        elements.push(Element {
            kind,
            locals,
            globals,
            direct,
            scatter: 0..0,
        });
    };
    for (r, spec) in system.rods.iter().enumerate() {
        let n = spec.rod.segments();
        let vertex_block = |j: usize| vertex_local(system, dofs, r, j);
        let frame_block = |at_end: bool| boundary_local(system, r, at_end);
        for e in 0..n {
            let locals = [
                vertex_block(e),
                vertex_block(e + 1),
                LocalBlock::Free(dofs.edge(r, e)),
            ];
            push(ElementKind::Edge { rod: r, edge: e }, locals);
        }
        for j in 0..=n {
            let locals = match j {
                0 => match frame_block(false) {
                    Some(a) => [a, LocalBlock::Free(dofs.edge(r, 0)), LocalBlock::Fixed],
                    None => continue,
                },
                j if j == n => match frame_block(true) {
                    Some(b) => [LocalBlock::Free(dofs.edge(r, n - 1)), b, LocalBlock::Fixed],
                    None => continue,
                },
                j => match dofs.clip_at(r, j) {
                    Some(clip) => {
                        let frame = clip_frame_local(system, dofs, clip);
                        let before = [
                            LocalBlock::Free(dofs.edge(r, j - 1)),
                            frame,
                            LocalBlock::Fixed,
                        ];
                        let after = [frame, LocalBlock::Free(dofs.edge(r, j)), LocalBlock::Fixed];
                        push(
                            ElementKind::ClipHalf {
                                rod: r,
                                vertex: j,
                                clip,
                                after: false,
                            },
                            before,
                        );
                        push(
                            ElementKind::ClipHalf {
                                rod: r,
                                vertex: j,
                                clip,
                                after: true,
                            },
                            after,
                        );
                        if let local @ LocalBlock::ClipPoint { .. } = vertex_block(j) {
                            push(
                                ElementKind::PointLoad { rod: r, vertex: j },
                                [local, LocalBlock::Fixed, LocalBlock::Fixed],
                            );
                        }
                        continue;
                    }
                    None => [
                        LocalBlock::Free(dofs.edge(r, j - 1)),
                        LocalBlock::Free(dofs.edge(r, j)),
                        LocalBlock::Fixed,
                    ],
                },
            };
            push(ElementKind::Vertex { rod: r, vertex: j }, locals);
        }
        for (at_end, end) in [(false, &spec.start), (true, &spec.end)] {
            let edge = if at_end { n - 1 } else { 0 };
            if end.load.moment != Vector3::zeros() {
                let locals = [
                    LocalBlock::Free(dofs.edge(r, edge)),
                    LocalBlock::Fixed,
                    LocalBlock::Fixed,
                ];
                push(ElementKind::EndMoment { rod: r, at_end }, locals);
            }
            let vertex = if at_end { n } else { 0 };
            if let local @ LocalBlock::BodyPoint { .. } = vertex_block(vertex) {
                push(
                    ElementKind::PointLoad { rod: r, vertex },
                    [local, LocalBlock::Fixed, LocalBlock::Fixed],
                );
            }
        }
    }
    for (b, body) in system.bodies.iter().enumerate() {
        if !body.fixed {
            let local = LocalBlock::BodyPoint {
                body: b,
                lever: body.center_of_mass,
            };
            push(
                ElementKind::BodyWeight { body: b },
                [local, LocalBlock::Fixed, LocalBlock::Fixed],
            );
        }
    }
    for (c, clip) in system.clips.iter().enumerate() {
        if let (Joint::Revolute { .. } | Joint::Prismatic { .. }, Some(block)) =
            (clip.joint, dofs.clip(c))
        {
            push(
                ElementKind::JointPadding,
                [
                    LocalBlock::Free(block),
                    LocalBlock::Fixed,
                    LocalBlock::Fixed,
                ],
            );
        }
    }
    elements
}

/// Per rod and vertex: whether the vertex moves with a free body or a clip joint.
fn moving_vertices(system: &System, dofs: &Dofs) -> Vec<Vec<bool>> {
    system
        .rods
        .iter()
        .enumerate()
        .map(|(r, spec)| {
            (0..spec.rod.vertex_count())
                .map(|j| {
                    matches!(
                        vertex_local(system, dofs, r, j),
                        LocalBlock::BodyPoint { .. } | LocalBlock::ClipPoint { .. }
                    )
                })
                .collect()
        })
        .collect()
}

/// How vertex `j` of rod `r` enters: its own block, fixed, or a point of a free body.
fn vertex_local(system: &System, dofs: &Dofs, r: usize, j: usize) -> LocalBlock {
    if let Some(b) = dofs.vertex(r, j) {
        return LocalBlock::Free(b);
    }
    if let Some(clip) = dofs.clip_at(r, j) {
        return match system.clips[clip].joint {
            Joint::Fixed if !on_free_body(system, dofs, clip) => LocalBlock::Fixed,
            _ => LocalBlock::ClipPoint { clip },
        };
    }
    let spec = &system.rods[r];
    let end = if j == 0 { &spec.start } else { &spec.end };
    match end.support {
        Support::Port { body, port, .. } if !system.bodies[body.0].fixed => LocalBlock::BodyPoint {
            body: body.0,
            lever: system.bodies[body.0].ports[port].position,
        },
        _ => LocalBlock::Fixed,
    }
}

/// How the boundary frame of rod `r` at one end enters: `None` without a boundary frame,
/// fixed, or a frame of a free body.
fn boundary_local(system: &System, r: usize, at_end: bool) -> Option<LocalBlock> {
    let spec = &system.rods[r];
    let end = if at_end { &spec.end } else { &spec.start };
    match end.support {
        Support::Clamped { .. } => Some(LocalBlock::Fixed),
        Support::Port {
            body,
            port,
            clamped: true,
        } => Some(if system.bodies[body.0].fixed {
            LocalBlock::Fixed
        } else {
            LocalBlock::BodyFrame {
                body: body.0,
                offset: system.port_offset(body, port, at_end),
            }
        }),
        _ => None,
    }
}

/// How a clip's output frame enters a half-cell element.
fn clip_frame_local(system: &System, dofs: &Dofs, clip: usize) -> LocalBlock {
    match system.clips[clip].joint {
        Joint::Fixed | Joint::Prismatic { .. } if !on_free_body(system, dofs, clip) => {
            LocalBlock::Fixed
        }
        _ => LocalBlock::ClipFrame { clip },
    }
}

/// Whether clip `clip`'s output moves with an unknown (a free carrier body or a joint
/// anywhere in its chain).
fn on_free_body(system: &System, dofs: &Dofs, clip: usize) -> bool {
    !crate::chain::chain_blocks(system, dofs, clip).is_empty()
}

/// Owned inputs of a clip half-cell (the output frame is computed, not stored).
pub(crate) struct ClipHalfElement {
    frame_a: UnitQuaternion<f64>,
    frame_b: UnitQuaternion<f64>,
    weight: f64,
    stiffness: Vector3<f64>,
    rest_curvature: Vector3<f64>,
}

impl ClipHalfElement {
    pub(crate) fn element(&self) -> BendTwist<'_> {
        BendTwist {
            frame_a: &self.frame_a,
            frame_b: &self.frame_b,
            weight: self.weight,
            stiffness: &self.stiffness,
            rest_curvature: &self.rest_curvature,
        }
    }

    fn energy(&self) -> f64 {
        self.element().energy()
    }
}
