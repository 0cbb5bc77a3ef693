//! The assembled model: symbolic phase at construction, numeric phase per evaluation.

use std::ops::Range;

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::element::{BendTwist, ElementDerivatives, bend_twist, dead_moment, stretch_shear};
use strand_rod::sectional::{BoundaryFrames, edge_element, vertex_frames};
use strand_rod::so3;

use crate::dofs::{BlockKind, Dofs};
use crate::pattern::{HessianPattern, ScatterBlock, add_blocks};
use crate::system::{System, SystemError, SystemState};

#[derive(Clone, Copy, Debug)]
enum ElementKind {
    /// Stretch–shear energy of an edge; blocks `(r_a, r_b, θ)`.
    Edge { rod: usize, edge: usize },
    /// Bend–twist energy of a vertex; blocks `(θ_a, θ_b)`.
    Vertex { rod: usize, vertex: usize },
    /// Dead moment at the start (`false`) or end (`true`) edge; block `(θ)`.
    EndMoment { rod: usize, at_end: bool },
}

#[derive(Clone, Debug)]
struct Element {
    kind: ElementKind,
    blocks: [Option<usize>; 3],
    scatter: Range<usize>,
}

/// A validated system with its unknowns numbered and its Hessian pattern fixed.
#[derive(Clone, Debug)]
pub struct Model {
    system: System,
    dofs: Dofs,
    pattern: HessianPattern,
    elements: Vec<Element>,
    scatter: Vec<ScatterBlock>,
    boundary: Vec<BoundaryFrames>,
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
}

/// Size of a gradient, in physical units.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Residual {
    /// Largest out-of-balance vertex force in N (eq. 15).
    pub force_n: f64,
    /// Largest out-of-balance edge moment in N·m (eq. 16).
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
        let mut elements = Vec::new();
        let boundary: Vec<BoundaryFrames> = system
            .rods
            .iter()
            .map(|s| BoundaryFrames {
                start: s.start.support.frame(),
                end: s.end.support.frame(),
            })
            .collect();
        for (r, spec) in system.rods.iter().enumerate() {
            let n = spec.rod.segments();
            for e in 0..n {
                let blocks = [
                    dofs.vertex(r, e),
                    dofs.vertex(r, e + 1),
                    Some(dofs.edge(r, e)),
                ];
                elements.push(Element {
                    kind: ElementKind::Edge { rod: r, edge: e },
                    blocks,
                    scatter: 0..0,
                });
            }
            for j in 0..=n {
                let (a, b) = match j {
                    0 if boundary[r].start.is_some() => (None, Some(dofs.edge(r, 0))),
                    j if j == n && boundary[r].end.is_some() => (Some(dofs.edge(r, n - 1)), None),
                    0 => continue,
                    j if j == n => continue,
                    j => (Some(dofs.edge(r, j - 1)), Some(dofs.edge(r, j))),
                };
                elements.push(Element {
                    kind: ElementKind::Vertex { rod: r, vertex: j },
                    blocks: [a, b, None],
                    scatter: 0..0,
                });
            }
            for (at_end, end) in [(false, &spec.start), (true, &spec.end)] {
                if end.load.moment != Vector3::zeros() {
                    let edge = if at_end { n - 1 } else { 0 };
                    elements.push(Element {
                        kind: ElementKind::EndMoment { rod: r, at_end },
                        blocks: [Some(dofs.edge(r, edge)), None, None],
                        scatter: 0..0,
                    });
                }
            }
        }
        let global_blocks: Vec<Vec<usize>> = elements
            .iter()
            .map(|e| e.blocks.iter().flatten().copied().collect())
            .collect();
        let pattern = HessianPattern::new(
            dofs.block_count(),
            global_blocks.iter().map(|b| b.as_slice()),
        );
        let mut scatter = Vec::new();
        for element in &mut elements {
            let start = scatter.len();
            scatter.extend(pattern.scatter(&element.blocks));
            element.scatter = start..scatter.len();
        }
        Ok(Self {
            system,
            dofs,
            pattern,
            elements,
            scatter,
            boundary,
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

    /// Boundary frames of rod `rod`.
    pub fn boundary_frames(&self, rod: usize) -> &BoundaryFrames {
        &self.boundary[rod]
    }

    /// An evaluation buffer of the right sizes.
    pub fn new_evaluation(&self) -> Evaluation {
        Evaluation {
            energy: 0.0,
            gradient: vec![0.0; self.dofs.len()],
            hessian: vec![0.0; self.pattern.nnz()],
        }
    }

    /// Energy, gradient and, if `with_hessian`, Hessian of `state` into `out`.
    pub fn evaluate(&self, state: &SystemState, out: &mut Evaluation, with_hessian: bool) {
        out.energy = 0.0;
        out.gradient.iter_mut().for_each(|g| *g = 0.0);
        if with_hessian {
            out.hessian.iter_mut().for_each(|h| *h = 0.0);
        }
        for element in &self.elements {
            let scatter = &self.scatter[element.scatter.clone()];
            match element.kind {
                ElementKind::Edge { .. } => {
                    let d = self.edge_derivatives(state, element.kind);
                    self.accumulate(out, element, scatter, &d, with_hessian);
                }
                ElementKind::Vertex { .. } => {
                    let d = self.vertex_derivatives(state, element.kind);
                    self.accumulate(out, element, scatter, &d, with_hessian);
                }
                ElementKind::EndMoment { rod, at_end } => {
                    let d = self.end_moment_derivatives(state, rod, at_end);
                    self.accumulate(out, element, scatter, &d, with_hessian);
                }
            }
        }
        self.add_linear_loads(state, out);
    }

    /// Total potential energy of `state` in J (no derivatives).
    pub fn energy(&self, state: &SystemState) -> f64 {
        let mut energy = 0.0;
        for element in &self.elements {
            energy += match element.kind {
                ElementKind::Edge { rod, edge } => {
                    let spec = &self.system.rods[rod];
                    let c = spec.rod.section().strain_stiffness();
                    edge_element(&spec.rod, &state.rods[rod], &c, edge).energy()
                }
                ElementKind::Vertex { rod, vertex } => {
                    let spec = &self.system.rods[rod];
                    let c = spec.rod.section().curvature_stiffness();
                    let (q_a, q_b) = vertex_frames(&state.rods[rod], &self.boundary[rod], vertex)
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
            };
        }
        for (r, spec) in self.system.rods.iter().enumerate() {
            let positions = &state.rods[r].positions;
            for (j, p) in positions.iter().enumerate() {
                energy -= spec.rod.vertex_mass(j) * self.system.gravity.dot(p);
            }
            energy -= spec.start.load.force.dot(&positions[0]);
            energy -= spec.end.load.force.dot(positions.last().expect("vertices"));
        }
        energy
    }

    fn edge_derivatives(&self, state: &SystemState, kind: ElementKind) -> ElementDerivatives<9> {
        let ElementKind::Edge { rod, edge } = kind else {
            unreachable!()
        };
        let spec = &self.system.rods[rod];
        let c = spec.rod.section().strain_stiffness();
        stretch_shear(&edge_element(&spec.rod, &state.rods[rod], &c, edge))
    }

    fn vertex_derivatives(&self, state: &SystemState, kind: ElementKind) -> ElementDerivatives<6> {
        let ElementKind::Vertex { rod, vertex } = kind else {
            unreachable!()
        };
        let spec = &self.system.rods[rod];
        let c = spec.rod.section().curvature_stiffness();
        let (q_a, q_b) =
            vertex_frames(&state.rods[rod], &self.boundary[rod], vertex).expect("vertex element");
        bend_twist(&BendTwist {
            frame_a: q_a,
            frame_b: q_b,
            weight: spec.rod.vertex_weight(vertex),
            stiffness: &c,
            rest_curvature: spec.rod.rest_curvature(vertex),
        })
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

    fn accumulate<const D: usize>(
        &self,
        out: &mut Evaluation,
        element: &Element,
        scatter: &[ScatterBlock],
        d: &ElementDerivatives<D>,
        with_hessian: bool,
    ) {
        out.energy += d.energy;
        for (local, block) in element.blocks.iter().enumerate().take(D / 3) {
            if let Some(b) = block {
                for i in 0..3 {
                    out.gradient[3 * b + i] += d.gradient[3 * local + i];
                }
            }
        }
        if with_hessian {
            add_blocks(&mut out.hessian, scatter, &d.hessian);
        }
    }

    fn add_linear_loads(&self, state: &SystemState, out: &mut Evaluation) {
        for (r, spec) in self.system.rods.iter().enumerate() {
            let positions = &state.rods[r].positions;
            let n = spec.rod.segments();
            for (j, p) in positions.iter().enumerate() {
                let mut force = spec.rod.vertex_mass(j) * self.system.gravity;
                if j == 0 {
                    force += spec.start.load.force;
                }
                if j == n {
                    force += spec.end.load.force;
                }
                out.energy -= force.dot(p);
                if let Some(b) = self.dofs.vertex(r, j) {
                    for i in 0..3 {
                        out.gradient[3 * b + i] -= force[i];
                    }
                }
            }
        }
    }

    /// Puts every held vertex of `state` at its support position (an initial guess from
    /// elsewhere, e.g. a previous solution of a variant, may not satisfy the supports).
    pub fn enforce_supports(&self, state: &mut SystemState) {
        for (spec, rod_state) in self.system.rods.iter().zip(&mut state.rods) {
            let last = rod_state.positions.len() - 1;
            for (vertex, end) in [(0, &spec.start), (last, &spec.end)] {
                if let Some(position) = end.support.position() {
                    rod_state.set_position(vertex, position);
                }
            }
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

    /// The boundary frame of rod `rod` at its start or end, if clamped.
    pub fn boundary_frame(&self, rod: usize, at_end: bool) -> Option<UnitQuaternion<f64>> {
        if at_end {
            self.boundary[rod].end
        } else {
            self.boundary[rod].start
        }
    }
}
