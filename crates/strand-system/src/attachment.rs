//! Elimination of attached coordinates: how an element's local 3-blocks depend on the
//! unknowns, and the chain rule that carries element derivatives to them.
//!
//! A rod end held by a port of a free body is not an unknown: its vertex is
//! `r = x + R(q ⊗ exp(θ)) l` and its boundary frame `Q = q ⊗ exp(θ) ⊗ o` for the
//! body's translation `x` and rotation increment `θ` (DESIGN §2). A vertex held by a
//! clip follows the clip's joint in the same way. With the Jacobian
//! `T = ∂(local)/∂(globals)` the element's gradient becomes `Tᵀ g` and its Hessian
//! `Tᵀ H T + Σ gᵢ ∇²(localᵢ)`; only point maps have second derivatives.

use nalgebra::{DMatrix, Matrix3, UnitQuaternion, Vector3};
use strand_rod::so3::skew;

use crate::dofs::Dofs;
use crate::system::{ClipSpec, Joint, JointState, System, SystemState};

/// How one local 3-block of an element depends on the unknowns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum LocalBlock {
    /// Absent, or fixed in space (a connector, a fixed clip).
    Fixed,
    /// An unknown block of its own.
    Free(usize),
    /// A point of free body `body` at `lever` (body coordinates, m).
    BodyPoint { body: usize, lever: Vector3<f64> },
    /// A frame of free body `body`: `q_body ⊗ offset`.
    BodyFrame {
        body: usize,
        offset: UnitQuaternion<f64>,
    },
    /// The output origin of clip `clip` (a joint with freedom).
    ClipPoint { clip: usize },
    /// The output frame of clip `clip` (a joint with freedom).
    ClipFrame { clip: usize },
}

impl LocalBlock {
    /// Whether the block maps one-to-one to an unknown (or to nothing).
    pub(crate) fn is_direct(&self) -> bool {
        matches!(self, LocalBlock::Fixed | LocalBlock::Free(_))
    }

    /// The global blocks this local block depends on.
    pub(crate) fn globals(&self, dofs: &Dofs, system: &System) -> Vec<usize> {
        match *self {
            LocalBlock::Fixed => vec![],
            LocalBlock::Free(g) => vec![g],
            LocalBlock::BodyPoint { body, .. } => {
                let (t, r) = dofs.body(body).expect("free body");
                vec![t, r]
            }
            LocalBlock::BodyFrame { body, .. } => vec![dofs.body(body).expect("free body").1],
            LocalBlock::ClipPoint { clip } => {
                let mut blocks = vec![];
                if let Some((t, r)) = system.clips[clip].body.and_then(|b| dofs.body(b.0)) {
                    blocks.extend([t, r]);
                }
                blocks.extend(dofs.clip(clip));
                blocks
            }
            LocalBlock::ClipFrame { clip } => {
                let mut blocks = vec![];
                if let Some((_, r)) = system.clips[clip].body.and_then(|b| dofs.body(b.0)) {
                    blocks.push(r);
                }
                blocks.extend(dofs.clip(clip));
                blocks
            }
        }
    }
}

/// The second-order term `½(g lᵀ + l gᵀ) − (g·l) I` of `gᵀ R exp(θ) l` in `θ`, for the
/// force `g` expressed in the rotated frame.
fn lever_curvature(g: &Vector3<f64>, lever: &Vector3<f64>) -> Matrix3<f64> {
    0.5 * (g * lever.transpose() + lever * g.transpose()) - g.dot(lever) * Matrix3::identity()
}

/// `T` (rows: local scalars, columns: the element's global blocks) and the curvature
/// term `Σ gᵢ ∇²(localᵢ)` for the local gradient `local_gradient`.
pub(crate) fn chain_rule(
    locals: &[LocalBlock],
    globals: &[usize],
    dofs: &Dofs,
    system: &System,
    state: &SystemState,
    local_gradient: &[f64],
    with_curvature: bool,
) -> (DMatrix<f64>, DMatrix<f64>) {
    let columns = 3 * globals.len();
    let mut jacobian = DMatrix::zeros(3 * locals.len(), columns);
    let mut curvature = DMatrix::zeros(columns, columns);
    let column = |g: usize| {
        3 * globals
            .iter()
            .position(|&x| x == g)
            .expect("global block of element")
    };
    let gradient_of = |a: usize| {
        Vector3::new(
            local_gradient[3 * a],
            local_gradient[3 * a + 1],
            local_gradient[3 * a + 2],
        )
    };
    for (a, local) in locals.iter().enumerate() {
        let row = 3 * a;
        match *local {
            LocalBlock::Fixed => {}
            LocalBlock::Free(g) => {
                jacobian
                    .fixed_view_mut::<3, 3>(row, column(g))
                    .copy_from(&Matrix3::identity());
            }
            LocalBlock::BodyPoint { body, lever } => {
                let (t, r) = dofs.body(body).expect("free body");
                let rotation = state.bodies[body]
                    .orientation
                    .to_rotation_matrix()
                    .into_inner();
                jacobian
                    .fixed_view_mut::<3, 3>(row, column(t))
                    .copy_from(&Matrix3::identity());
                jacobian
                    .fixed_view_mut::<3, 3>(row, column(r))
                    .copy_from(&(-rotation * skew(&lever)));
                if with_curvature {
                    let c = column(r);
                    let term = lever_curvature(&(rotation.transpose() * gradient_of(a)), &lever);
                    let mut view = curvature.fixed_view_mut::<3, 3>(c, c);
                    view += term;
                }
            }
            LocalBlock::BodyFrame { body, offset } => {
                let r = dofs.body(body).expect("free body").1;
                let offset_matrix = offset.to_rotation_matrix().into_inner();
                jacobian
                    .fixed_view_mut::<3, 3>(row, column(r))
                    .copy_from(&offset_matrix.transpose());
            }
            LocalBlock::ClipPoint { clip } => {
                let g = gradient_of(a);
                let map = ClipMap::new(system, dofs, state, clip);
                let joint_columns = point_columns(&system.clips[clip], &state.clips[clip]);
                if let Some((t, r)) = map.body_blocks {
                    // r = x + R_b exp(θ) ρ(φ) with ρ the output origin in body coordinates.
                    let rho = system.clips[clip].output_in_carrier(&state.clips[clip]);
                    let (t, r) = (column(t), column(r));
                    jacobian
                        .fixed_view_mut::<3, 3>(row, t)
                        .copy_from(&Matrix3::identity());
                    jacobian
                        .fixed_view_mut::<3, 3>(row, r)
                        .copy_from(&(-map.carrier * skew(&rho)));
                    if with_curvature {
                        let body_force = map.carrier.transpose() * g;
                        let mut view = curvature.fixed_view_mut::<3, 3>(r, r);
                        view += lever_curvature(&body_force, &rho);
                        if let Some(j) = map.joint_block {
                            // ∂²/∂θ∂φ_m of gᵀ R_b exp(θ) ρ(φ) is ∂ρ/∂φ_m × R_bᵀ g.
                            let j = column(j);
                            for (m, rho_m) in joint_columns.iter().enumerate() {
                                let mixed = rho_m.cross(&body_force);
                                add_symmetric(&mut curvature, r, j + m, &mixed);
                            }
                        }
                    }
                }
                if let Some(j) = map.joint_block {
                    let c = column(j);
                    for (m, rho_m) in joint_columns.iter().enumerate() {
                        jacobian
                            .fixed_view_mut::<3, 1>(row, c + m)
                            .copy_from(&(map.carrier * rho_m));
                    }
                    if with_curvature {
                        add_joint_point_curvature(
                            &system.clips[clip],
                            &state.clips[clip],
                            &(map.carrier.transpose() * g),
                            c,
                            &mut curvature,
                        );
                    }
                }
            }
            LocalBlock::ClipFrame { clip } => {
                let map = ClipMap::new(system, dofs, state, clip);
                let spec = &system.clips[clip];
                let offset = spec.offset.orientation.to_rotation_matrix().into_inner();
                let joint_columns = frame_columns(spec, &offset);
                if let Some((_, r)) = map.body_blocks {
                    // Q = q_b exp(θ) q_B J q_o = Q exp(Aθ) with A = (R_B R_J R_o)ᵀ.
                    let (_, joint_rotation) = spec.joint_motion(&state.clips[clip]);
                    let to_output = (spec.base.orientation * joint_rotation)
                        .to_rotation_matrix()
                        .into_inner()
                        * offset;
                    let r = column(r);
                    jacobian
                        .fixed_view_mut::<3, 3>(row, r)
                        .copy_from(&to_output.transpose());
                    if with_curvature && let Some(j) = map.joint_block {
                        // exp(Aθ) exp(b δ) = exp(Aθ + bδ + ½ Aθ × bδ + …) (BCH).
                        let g = gradient_of(a);
                        let j = column(j);
                        for (m, b) in joint_columns.iter().enumerate() {
                            let mixed = 0.5 * to_output * b.cross(&g);
                            add_symmetric(&mut curvature, r, j + m, &mixed);
                        }
                    }
                }
                if let Some(j) = map.joint_block {
                    let c = column(j);
                    for (m, b) in joint_columns.iter().enumerate() {
                        jacobian.fixed_view_mut::<3, 1>(row, c + m).copy_from(b);
                    }
                }
            }
        }
    }
    (jacobian, curvature)
}

/// Adds `v` to the rows `r..r+3` of column `c` and to the columns `r..r+3` of row `c`.
fn add_symmetric(matrix: &mut DMatrix<f64>, r: usize, c: usize, v: &Vector3<f64>) {
    for k in 0..3 {
        matrix[(r + k, c)] += v[k];
        matrix[(c, r + k)] += v[k];
    }
}

/// Right-increment directions of a clip's output frame per joint coordinate.
fn frame_columns(spec: &ClipSpec, offset: &Matrix3<f64>) -> Vec<Vector3<f64>> {
    match spec.joint {
        Joint::Fixed | Joint::Prismatic { .. } => vec![],
        // Q = q_B Rot(a, φ) q_o: a right increment R_oᵀ a δφ of Q.
        Joint::Revolute { axis } => vec![offset.transpose() * axis],
        Joint::Spherical => {
            let t = offset.transpose();
            vec![t.column(0).into(), t.column(1).into(), t.column(2).into()]
        }
    }
}

/// How a clip's output depends on its carrier body and its joint.
struct ClipMap {
    /// Rotation of the carrier (the body, or the identity for the world).
    carrier: Matrix3<f64>,
    /// Translation and rotation blocks of a free carrier body.
    body_blocks: Option<(usize, usize)>,
    /// The joint's block.
    joint_block: Option<usize>,
}

impl ClipMap {
    fn new(system: &System, dofs: &Dofs, state: &SystemState, clip: usize) -> Self {
        let spec = &system.clips[clip];
        let (carrier, body_blocks) = match spec.body {
            Some(body) => (
                state.bodies[body.0]
                    .orientation
                    .to_rotation_matrix()
                    .into_inner(),
                dofs.body(body.0),
            ),
            None => (Matrix3::identity(), None),
        };
        Self {
            carrier,
            body_blocks,
            joint_block: dofs.clip(clip),
        }
    }
}

/// `∂ρ/∂φ_m`: how the output origin moves per joint coordinate, in the coordinates of
/// the clip's carrier (world or body).
fn point_columns(spec: &ClipSpec, joint: &JointState) -> Vec<Vector3<f64>> {
    let base = spec.base.orientation.to_rotation_matrix().into_inner();
    let lever = spec.offset.position;
    match spec.joint {
        Joint::Fixed => vec![],
        // ρ = p_B + R_B Rot(a, φ) o: ∂ρ/∂φ = R_B Rot (a × o).
        Joint::Revolute { axis } => {
            let turn = UnitQuaternion::from_scaled_axis(axis * joint.value);
            vec![base * (turn * axis.cross(&lever))]
        }
        Joint::Prismatic { axis } => vec![base * axis],
        // ρ = p_B + R_B R_s exp(ψ) o: ∂ρ/∂ψ = −R_B R_s [o]×.
        Joint::Spherical => {
            let m = -base * joint.rotation.to_rotation_matrix().into_inner() * skew(&lever);
            vec![m.column(0).into(), m.column(1).into(), m.column(2).into()]
        }
    }
}

/// Adds `Σ gᵢ ∂²ρᵢ/∂φ∂φ` for the carrier-frame force `force` at joint column `c`.
fn add_joint_point_curvature(
    spec: &ClipSpec,
    joint: &JointState,
    force: &Vector3<f64>,
    c: usize,
    curvature: &mut DMatrix<f64>,
) {
    let base = spec.base.orientation.to_rotation_matrix().into_inner();
    let lever = spec.offset.position;
    match spec.joint {
        Joint::Fixed | Joint::Prismatic { .. } => {}
        Joint::Revolute { axis } => {
            let turn = UnitQuaternion::from_scaled_axis(axis * joint.value);
            curvature[(c, c)] += force.dot(&(base * (turn * axis.cross(&axis.cross(&lever)))));
        }
        Joint::Spherical => {
            let rotation = base * joint.rotation.to_rotation_matrix().into_inner();
            let mut view = curvature.fixed_view_mut::<3, 3>(c, c);
            view += lever_curvature(&(rotation.transpose() * force), &lever);
        }
    }
}
