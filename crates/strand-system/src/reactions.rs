//! Support reactions from the gradient with respect to eliminated coordinates.
//!
//! A held vertex is a coordinate the minimisation does not move on its own; at
//! equilibrium its support (a connector or a body's port) supplies exactly the
//! generalised force the rod's potential exerts there: `force = ∂W/∂r_end` and, for a
//! clamped boundary frame, `moment = Q_end ∂W/∂θ_end` (spatial, about the end vertex).
//! Only the elements' gradients are evaluated (the same to the last bit as with their
//! second derivatives): a sensitivity reads the reactions at every point of its paths.

use nalgebra::Vector3;
use serde::Serialize;
use strand_rod::RodState;
use strand_rod::element::{BendTwist, bend_twist_gradient, stretch_shear_gradient};
use strand_rod::sectional::{BoundaryFrames, edge_element, vertex_frames};

use crate::model::Model;
use crate::system::{Support, System, SystemState};

/// What holds a rod end.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ReactionKind {
    /// A fixed frame in space (clamp or pin).
    Connector,
    /// A port of a rigid body (junction).
    Port,
    /// A clip holding an interior vertex.
    Clip,
}

/// Force and moment a support exerts on a rod end, in the world frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Reaction {
    /// `"<rod>.start"`/`"<rod>.end"` for a connector, `"<body>.<port>"` for a port, the
    /// clip's name for a clip.
    pub name: String,
    /// What holds the end.
    pub kind: ReactionKind,
    /// Index of the rod.
    pub rod: usize,
    /// Whether this is the end at vertex N (false for a clip).
    pub at_end: bool,
    /// The vertex held.
    pub vertex: usize,
    /// Where the support acts (the end vertex), m.
    pub position: Vector3<f64>,
    /// Force on the rod in N.
    pub force: Vector3<f64>,
    /// Moment on the rod about `position` in N·m (zero for a pin or ball joint).
    pub moment: Vector3<f64>,
}

impl System {
    /// The force (N) and moment (N·m, about the end vertex) the support of rod `rod`'s
    /// start (`at_end == false`) or end exerts on it, in the world frame, with the rod in
    /// `rod_state` and its `boundary` frames ([`System::ends_boundary`]): the end edge's
    /// and end vertex's elements only. Zero moment where the end has no boundary frame.
    pub fn end_reaction(
        &self,
        rod: usize,
        at_end: bool,
        rod_state: &RodState,
        boundary: &BoundaryFrames,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let spec = &self.rods[rod];
        let n = spec.rod.segments();
        let end = if at_end { &spec.end } else { &spec.start };
        let c = spec.rod.section().strain_stiffness();
        let (vertex, edge, local) = if at_end { (n, n - 1, 3) } else { (0, 0, 0) };
        let edge_derivatives =
            stretch_shear_gradient(&edge_element(&spec.rod, rod_state, &c, edge));
        let force = edge_derivatives
            .gradient
            .fixed_rows::<3>(local)
            .into_owned()
            - spec.rod.vertex_mass(vertex) * self.gravity
            - end.load.force;
        let moment = match vertex_frames(rod_state, boundary, vertex) {
            Some((q_a, q_b)) => {
                let curvature_stiffness = spec.rod.section().curvature_stiffness();
                let d = bend_twist_gradient(&BendTwist {
                    frame_a: q_a,
                    frame_b: q_b,
                    weight: spec.rod.vertex_weight(vertex),
                    stiffness: &curvature_stiffness,
                    rest_curvature: spec.rod.rest_curvature(vertex),
                });
                // The boundary frame is q_a at the start, q_b at the end.
                let (frame, local) = if at_end { (q_b, 3) } else { (q_a, 0) };
                frame * d.gradient.fixed_rows::<3>(local).into_owned()
            }
            None => Vector3::zeros(),
        };
        (force, moment)
    }
}

impl Model {
    /// The reactions of every support of `state`.
    pub fn reactions(&self, state: &SystemState) -> Vec<Reaction> {
        let system = self.system();
        let mut out = Vec::new();
        for (r, spec) in system.rods.iter().enumerate() {
            let rod_state = &state.rods[r];
            let n = spec.rod.segments();
            let boundary = self.boundary_frames(r, state);
            for (at_end, end) in [(false, &spec.start), (true, &spec.end)] {
                let (kind, name) = match end.support {
                    Support::Free => continue,
                    Support::Pinned { .. } | Support::Clamped { .. } => (
                        ReactionKind::Connector,
                        format!("{}.{}", spec.name, if at_end { "end" } else { "start" }),
                    ),
                    Support::Port { body, port, .. } => {
                        let body = &system.bodies[body.0];
                        (
                            ReactionKind::Port,
                            format!("{}.{}", body.name, body.ports[port].name),
                        )
                    }
                };
                let vertex = if at_end { n } else { 0 };
                let (force, moment) = system.end_reaction(r, at_end, rod_state, &boundary);
                out.push(Reaction {
                    name,
                    kind,
                    rod: r,
                    at_end,
                    vertex,
                    position: rod_state.positions[vertex],
                    force,
                    moment,
                });
            }
        }
        for (c, clip) in system.clips.iter().enumerate() {
            let (r, j) = (clip.rod.0, clip.vertex);
            let spec = &system.rods[r];
            let rod_state = &state.rods[r];
            let c_gamma = spec.rod.section().strain_stiffness();
            let before =
                stretch_shear_gradient(&edge_element(&spec.rod, rod_state, &c_gamma, j - 1));
            let after = stretch_shear_gradient(&edge_element(&spec.rod, rod_state, &c_gamma, j));
            let force = before.gradient.fixed_rows::<3>(3).into_owned()
                + after.gradient.fixed_rows::<3>(0).into_owned()
                - spec.rod.vertex_mass(j) * system.gravity;
            let half_before = bend_twist_gradient(&self.clip_half(state, r, j, c, false).element());
            let half_after = bend_twist_gradient(&self.clip_half(state, r, j, c, true).element());
            let output = system
                .clip_output(c, &state.clips, &state.bodies)
                .orientation;
            let moment = output
                * (half_before.gradient.fixed_rows::<3>(3).into_owned()
                    + half_after.gradient.fixed_rows::<3>(0).into_owned());
            out.push(Reaction {
                name: clip.name.clone(),
                kind: ReactionKind::Clip,
                rod: r,
                at_end: false,
                vertex: j,
                position: rod_state.positions[j],
                force,
                moment,
            });
        }
        out
    }
}
