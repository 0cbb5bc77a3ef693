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

use crate::chain::{ChainColumn, chain_blocks, chain_columns};
use crate::dofs::Dofs;
use crate::system::{System, SystemState};

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
            LocalBlock::ClipPoint { clip } | LocalBlock::ClipFrame { clip } => {
                chain_blocks(system, dofs, clip)
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
                // r moved by each chain coordinate: ∂r/∂q_i = v_i or ω_i × (r − p_i);
                // ∂²r/∂q_i∂q_j = ω_i × ∂r/∂q_j for q_i upstream of q_j (symmetrised
                // within one exponential block).
                let (columns, output) = chain_columns(system, dofs, state, clip);
                let r = output.position;
                let g = gradient_of(a);
                let velocities: Vec<Vector3<f64>> =
                    columns.iter().map(|c| c.point_velocity(&r)).collect();
                let index = |c: &ChainColumn| column(c.block) + c.component;
                for (c, v) in columns.iter().zip(&velocities) {
                    jacobian.fixed_view_mut::<3, 1>(row, index(c)).copy_from(v);
                }
                if with_curvature {
                    for i in 0..columns.len() {
                        for j in i..columns.len() {
                            let (ci, cj) = (&columns[i], &columns[j]);
                            let value = if ci.group == cj.group {
                                0.5 * (g.dot(&ci.angular().cross(&velocities[j]))
                                    + g.dot(&cj.angular().cross(&velocities[i])))
                            } else {
                                g.dot(&ci.angular().cross(&velocities[j]))
                            };
                            add_pair(&mut curvature, index(ci), index(cj), value);
                        }
                    }
                }
            }
            LocalBlock::ClipFrame { clip } => {
                // Q = Q₀ Π exp(u_i q_i), root first, with u_i = R_Qᵀ ω_i (exact at the
                // state); BCH gives ½ g·(u_i × u_j) for q_i upstream of q_j.
                let (columns, output) = chain_columns(system, dofs, state, clip);
                let to_output = output
                    .orientation
                    .to_rotation_matrix()
                    .into_inner()
                    .transpose();
                let g = gradient_of(a);
                let increments: Vec<Vector3<f64>> =
                    columns.iter().map(|c| to_output * c.angular()).collect();
                let index = |c: &ChainColumn| column(c.block) + c.component;
                for (c, u) in columns.iter().zip(&increments) {
                    jacobian.fixed_view_mut::<3, 1>(row, index(c)).copy_from(u);
                }
                if with_curvature {
                    for i in 0..columns.len() {
                        for j in i + 1..columns.len() {
                            if columns[i].group != columns[j].group {
                                let value = 0.5 * g.dot(&increments[i].cross(&increments[j]));
                                add_pair(
                                    &mut curvature,
                                    index(&columns[i]),
                                    index(&columns[j]),
                                    value,
                                );
                            }
                        }
                    }
                }
            }
        }
    }
    (jacobian, curvature)
}

/// Adds `value` at `(i, j)` and, off the diagonal, at `(j, i)`.
fn add_pair(matrix: &mut DMatrix<f64>, i: usize, j: usize, value: f64) {
    matrix[(i, j)] += value;
    if i != j {
        matrix[(j, i)] += value;
    }
}
