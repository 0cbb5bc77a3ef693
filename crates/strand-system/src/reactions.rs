//! Support reactions from the gradient with respect to eliminated coordinates.
//!
//! A held vertex is a coordinate the minimisation does not move on its own; at
//! equilibrium its support (a connector or a body's port) supplies exactly the
//! generalised force the rod's potential exerts there: `force = ∂W/∂r_end` and, for a
//! clamped boundary frame, `moment = Q_end ∂W/∂θ_end` (spatial, about the end vertex).

use nalgebra::Vector3;
use serde::Serialize;
use strand_rod::element::{BendTwist, bend_twist, stretch_shear};
use strand_rod::sectional::{edge_element, vertex_frames};

use crate::model::Model;
use crate::system::{Support, SystemState};

/// What holds a rod end.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ReactionKind {
    /// A fixed frame in space (clamp or pin).
    Connector,
    /// A port of a rigid body (junction).
    Port,
}

/// Force and moment a support exerts on a rod end, in the world frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Reaction {
    /// `"<rod>.start"`/`"<rod>.end"` for a connector, `"<body>.<port>"` for a port.
    pub name: String,
    /// What holds the end.
    pub kind: ReactionKind,
    /// Index of the rod.
    pub rod: usize,
    /// Whether this is the end at vertex N.
    pub at_end: bool,
    /// Where the support acts (the end vertex), m.
    pub position: Vector3<f64>,
    /// Force on the rod in N.
    pub force: Vector3<f64>,
    /// Moment on the rod about `position` in N·m (zero for a pin or ball joint).
    pub moment: Vector3<f64>,
}

impl Model {
    /// The reactions of every support of `state`.
    pub fn reactions(&self, state: &SystemState) -> Vec<Reaction> {
        let system = self.system();
        let mut out = Vec::new();
        for (r, spec) in system.rods.iter().enumerate() {
            let rod_state = &state.rods[r];
            let n = spec.rod.segments();
            let c = spec.rod.section().strain_stiffness();
            let boundary = self.boundary_frames(r, state);
            for (at_end, end) in [(false, &spec.start), (true, &spec.end)] {
                let (kind, name) = match end.support {
                    Support::Free => continue,
                    Support::Pinned { .. } | Support::Clamped { .. } => {
                        (ReactionKind::Connector, format!("{}.{}", spec.name, if at_end { "end" } else { "start" }))
                    }
                    Support::Port { body, port, .. } => {
                        let body = &system.bodies[body.0];
                        (ReactionKind::Port, format!("{}.{}", body.name, body.ports[port].name))
                    }
                };
                let (vertex, edge, local) = if at_end { (n, n - 1, 3) } else { (0, 0, 0) };
                let edge_derivatives = stretch_shear(&edge_element(&spec.rod, rod_state, &c, edge));
                let force = edge_derivatives.gradient.fixed_rows::<3>(local).into_owned()
                    - spec.rod.vertex_mass(vertex) * system.gravity
                    - end.load.force;
                let moment = match vertex_frames(rod_state, &boundary, vertex) {
                    Some((q_a, q_b)) => {
                        let curvature_stiffness = spec.rod.section().curvature_stiffness();
                        let d = bend_twist(&BendTwist {
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
                out.push(Reaction { name, kind, rod: r, at_end, position: rod_state.positions[vertex], force, moment });
            }
        }
        out
    }
}
