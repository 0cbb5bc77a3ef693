//! Support reactions from the gradient with respect to eliminated coordinates.
//!
//! A held vertex is a coordinate the minimisation does not move; at equilibrium the
//! support supplies exactly the generalised force the potential exerts there:
//! `force = ∂W/∂r_end` and, for a clamped boundary frame, `moment = R_end ∂W/∂θ_end`
//! (spatial, about the end vertex).

use nalgebra::Vector3;
use serde::Serialize;
use strand_rod::element::stretch_shear;
use strand_rod::sectional::edge_element;

use crate::model::Model;
use crate::system::SystemState;

/// Force and moment a support exerts on a rod end, in the world frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Reaction {
    /// `"<rod>.start"` or `"<rod>.end"`.
    pub name: String,
    /// Index of the rod.
    pub rod: usize,
    /// Whether this is the end at vertex N.
    pub at_end: bool,
    /// Where the support acts (the end vertex), m.
    pub position: Vector3<f64>,
    /// Force on the rod in N.
    pub force: Vector3<f64>,
    /// Moment on the rod about `position` in N·m (zero for a pin).
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
            for (at_end, end) in [(false, &spec.start), (true, &spec.end)] {
                if end.support.position().is_none() {
                    continue;
                }
                let (vertex, edge, local) = if at_end { (n, n - 1, 3) } else { (0, 0, 0) };
                let edge_derivatives = stretch_shear(&edge_element(&spec.rod, rod_state, &c, edge));
                let force = edge_derivatives
                    .gradient
                    .fixed_rows::<3>(local)
                    .into_owned()
                    - spec.rod.vertex_mass(vertex) * system.gravity
                    - end.load.force;
                let moment = match end.support.frame() {
                    Some(frame) => {
                        let (rotation_gradient, block) =
                            self.boundary_rotation_gradient(state, r, at_end);
                        debug_assert!(block.is_none());
                        frame * rotation_gradient
                    }
                    None => Vector3::zeros(),
                };
                out.push(Reaction {
                    name: format!("{}.{}", spec.name, if at_end { "end" } else { "start" }),
                    rod: r,
                    at_end,
                    position: rod_state.positions[vertex],
                    force,
                    moment,
                });
            }
        }
        out
    }

    /// Material gradient of the end vertex element with respect to the boundary frame's
    /// increment (N·m), and the block of that frame (`None`: it is eliminated).
    fn boundary_rotation_gradient(
        &self,
        state: &SystemState,
        rod: usize,
        at_end: bool,
    ) -> (Vector3<f64>, Option<usize>) {
        use strand_rod::element::{BendTwist, bend_twist};
        let spec = &self.system().rods[rod];
        let n = spec.rod.segments();
        let vertex = if at_end { n } else { 0 };
        let boundary = self.boundary_frames(rod);
        let (q_a, q_b) = strand_rod::sectional::vertex_frames(&state.rods[rod], boundary, vertex)
            .expect("clamped end has a frame");
        let c = spec.rod.section().curvature_stiffness();
        let d = bend_twist(&BendTwist {
            frame_a: q_a,
            frame_b: q_b,
            weight: spec.rod.vertex_weight(vertex),
            stiffness: &c,
            rest_curvature: spec.rod.rest_curvature(vertex),
        });
        let local = if at_end { 3 } else { 0 };
        (d.gradient.fixed_rows::<3>(local).into_owned(), None)
    }
}
