//! Elimination of attached coordinates: how an element's local 3-blocks depend on the
//! unknowns, and the chain rule that carries element derivatives to them.
//!
//! A rod end held by a port of a free body is not an unknown: its vertex is
//! `r = x + R(q ⊗ exp(θ)) l` and its boundary frame `Q = q ⊗ exp(θ) ⊗ o` for the
//! body's translation `x` and rotation increment `θ` (DESIGN §2). With the Jacobian
//! `T = ∂(local)/∂(globals)` the element's gradient becomes `Tᵀ g` and its Hessian
//! `Tᵀ H T + Σ gᵢ ∇²(localᵢ)`; only the point map has a second derivative.

use nalgebra::{DMatrix, Matrix3, UnitQuaternion, Vector3};
use strand_rod::so3::skew;

use crate::dofs::Dofs;
use crate::system::Pose;

/// How one local 3-block of an element depends on the unknowns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum LocalBlock {
    /// Absent, or fixed in space (a connector).
    Fixed,
    /// An unknown block of its own.
    Free(usize),
    /// A point of free body `body` at `lever` (body coordinates, m).
    BodyPoint { body: usize, lever: Vector3<f64> },
    /// A frame of free body `body`: `q_body ⊗ offset`.
    BodyFrame { body: usize, offset: UnitQuaternion<f64> },
}

impl LocalBlock {
    /// Whether the block maps one-to-one to an unknown (or to nothing).
    pub(crate) fn is_direct(&self) -> bool {
        matches!(self, LocalBlock::Fixed | LocalBlock::Free(_))
    }

    /// The global blocks this local block depends on.
    pub(crate) fn globals(&self, dofs: &Dofs) -> Vec<usize> {
        match *self {
            LocalBlock::Fixed => vec![],
            LocalBlock::Free(g) => vec![g],
            LocalBlock::BodyPoint { body, .. } => {
                let (t, r) = dofs.body(body).expect("free body");
                vec![t, r]
            }
            LocalBlock::BodyFrame { body, .. } => vec![dofs.body(body).expect("free body").1],
        }
    }
}

/// `T` (rows: local scalars, columns: the element's global blocks) and the curvature
/// term `Σ gᵢ ∇²(localᵢ)` for the local gradient `local_gradient`.
pub(crate) fn chain_rule(
    locals: &[LocalBlock],
    globals: &[usize],
    dofs: &Dofs,
    poses: &[Pose],
    local_gradient: &[f64],
    with_curvature: bool,
) -> (DMatrix<f64>, DMatrix<f64>) {
    let columns = 3 * globals.len();
    let mut jacobian = DMatrix::zeros(3 * locals.len(), columns);
    let mut curvature = DMatrix::zeros(columns, columns);
    let column = |g: usize| 3 * globals.iter().position(|&x| x == g).expect("global block of element");
    for (a, local) in locals.iter().enumerate() {
        match *local {
            LocalBlock::Fixed => {}
            LocalBlock::Free(g) => {
                jacobian.fixed_view_mut::<3, 3>(3 * a, column(g)).copy_from(&Matrix3::identity());
            }
            LocalBlock::BodyPoint { body, lever } => {
                let (t, r) = dofs.body(body).expect("free body");
                let rotation = poses[body].orientation.to_rotation_matrix().into_inner();
                jacobian.fixed_view_mut::<3, 3>(3 * a, column(t)).copy_from(&Matrix3::identity());
                jacobian.fixed_view_mut::<3, 3>(3 * a, column(r)).copy_from(&(-rotation * skew(&lever)));
                if with_curvature {
                    let g = Vector3::new(local_gradient[3 * a], local_gradient[3 * a + 1], local_gradient[3 * a + 2]);
                    let g_body = rotation.transpose() * g;
                    let term = 0.5 * (g_body * lever.transpose() + lever * g_body.transpose())
                        - g_body.dot(&lever) * Matrix3::identity();
                    let c = column(r);
                    let mut view = curvature.fixed_view_mut::<3, 3>(c, c);
                    view += term;
                }
            }
            LocalBlock::BodyFrame { body, offset } => {
                let r = dofs.body(body).expect("free body").1;
                let offset_matrix = offset.to_rotation_matrix().into_inner();
                jacobian.fixed_view_mut::<3, 3>(3 * a, column(r)).copy_from(&offset_matrix.transpose());
            }
        }
    }
    (jacobian, curvature)
}
