//! The kinematic chain of a clip: its carrier (the world or a body), the clips it is
//! mounted on, and its own joint. At a state, every coordinate of the chain is a world
//! screw — a translation velocity, or an angular velocity about an anchor point — from
//! which the first and second derivatives of the clip's output point and frame follow
//! (the standard forward-kinematics formulas; `∂²r/∂q_i∂q_j = ω_i × ∂r/∂q_j` for `q_i`
//! upstream of `q_j`).

use nalgebra::{Matrix3, Vector3};

use crate::dofs::Dofs;
use crate::system::{Joint, Pose, System, SystemState};

/// How one coordinate of a chain moves everything downstream of it.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Screw {
    /// A translation with this world velocity per unit coordinate (m/m).
    Translation(Vector3<f64>),
    /// A rotation with this world angular velocity (rad per unit) about `anchor` (m).
    Rotation {
        axis: Vector3<f64>,
        anchor: Vector3<f64>,
    },
}

/// One coordinate of a clip's chain at a state.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ChainColumn {
    /// The global block holding the coordinate.
    pub block: usize,
    /// The component within the block (0 for scalar joints).
    pub component: usize,
    /// Coordinates of one exponential 3-block (a body's rotation, a spherical joint)
    /// share a group: their mixed second derivatives are symmetrised.
    pub group: usize,
    /// The coordinate's screw.
    pub screw: Screw,
}

impl ChainColumn {
    /// `∂r/∂q` for a point `r` (m) moved by the chain.
    pub fn point_velocity(&self, r: &Vector3<f64>) -> Vector3<f64> {
        match self.screw {
            Screw::Translation(v) => v,
            Screw::Rotation { axis, anchor } => axis.cross(&(r - anchor)),
        }
    }

    /// The world angular velocity (zero for a translation).
    pub fn angular(&self) -> Vector3<f64> {
        match self.screw {
            Screw::Translation(_) => Vector3::zeros(),
            Screw::Rotation { axis, .. } => axis,
        }
    }
}

/// The chain of clip `clip`, root first: `[carrier body's clips…, clip]`.
fn chain(system: &System, clip: usize) -> Vec<usize> {
    let mut chain = vec![clip];
    let mut c = clip;
    while let Some(parent) = system.clips[c].parent {
        chain.push(parent);
        c = parent;
    }
    chain.reverse();
    chain
}

/// The global blocks clip `clip`'s output depends on, root first (no state needed).
pub(crate) fn chain_blocks(system: &System, dofs: &Dofs, clip: usize) -> Vec<usize> {
    let links = chain(system, clip);
    let mut blocks = Vec::new();
    if let Some((t, r)) = system.clips[links[0]].body.and_then(|b| dofs.body(b.0)) {
        blocks.extend([t, r]);
    }
    blocks.extend(links.iter().filter_map(|&c| dofs.clip(c)));
    blocks
}

/// The coordinates of clip `clip`'s chain at `state`, root first, and its output frame.
pub(crate) fn chain_columns(
    system: &System,
    dofs: &Dofs,
    state: &SystemState,
    clip: usize,
) -> (Vec<ChainColumn>, Pose) {
    let links = chain(system, clip);
    let mut columns = Vec::new();
    let mut group = 0;
    let mut carrier = match system.clips[links[0]].body {
        Some(body) => {
            let pose = state.bodies[body.0];
            if let Some((t, r)) = dofs.body(body.0) {
                let rotation = pose.orientation.to_rotation_matrix().into_inner();
                for k in 0..3 {
                    columns.push(ChainColumn {
                        block: t,
                        component: k,
                        group,
                        screw: Screw::Translation(Vector3::ith(k, 1.0)),
                    });
                }
                group += 1;
                for k in 0..3 {
                    columns.push(ChainColumn {
                        block: r,
                        component: k,
                        group,
                        screw: Screw::Rotation {
                            axis: rotation.column(k).into(),
                            anchor: pose.position,
                        },
                    });
                }
                group += 1;
            }
            pose
        }
        None => Pose {
            position: Vector3::zeros(),
            orientation: nalgebra::UnitQuaternion::identity(),
        },
    };
    for &c in &links {
        let spec = &system.clips[c];
        let base = Pose {
            position: carrier.transform_point(&spec.base.position),
            orientation: carrier.orientation * spec.base.orientation,
        };
        let base_rotation: Matrix3<f64> = base.orientation.to_rotation_matrix().into_inner();
        if let Some(block) = dofs.clip(c) {
            let joint = state.clips[c];
            let mut push = |component, screw| {
                columns.push(ChainColumn {
                    block,
                    component,
                    group,
                    screw,
                })
            };
            match spec.joint {
                Joint::Fixed => {}
                Joint::Revolute { axis } => push(
                    0,
                    Screw::Rotation {
                        axis: base_rotation * axis,
                        anchor: base.position,
                    },
                ),
                Joint::Prismatic { axis } => push(0, Screw::Translation(base_rotation * axis)),
                Joint::Spherical => {
                    let moved = base_rotation * joint.rotation.to_rotation_matrix().into_inner();
                    for k in 0..3 {
                        push(
                            k,
                            Screw::Rotation {
                                axis: moved.column(k).into(),
                                anchor: base.position,
                            },
                        );
                    }
                }
            }
            group += 1;
        }
        let (translation, rotation) = spec.joint_motion(&state.clips[c]);
        carrier = Pose {
            position: base.transform_point(&(translation + rotation * spec.offset.position)),
            orientation: base.orientation * rotation * spec.offset.orientation,
        };
    }
    (columns, carrier)
}
