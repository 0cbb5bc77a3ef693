//! Second derivatives of a contact gap with respect to the positions of the rod
//! vertices it involves: the constraint curvature of the SQP model's Lagrangian
//! (`−λ ∇²g`). A gap is the distance `D(x) = min_σ d(P(x, σ))` from a point
//! `P = Σ_i w_i(σ) x_i` on the rod (a vertex, a point of an edge, or the difference of
//! two edges' points) to the nearest feature of the obstacle, less the radii; the
//! parameters `σ` (the edge parameters strictly inside their edges) are eliminated at
//! the minimum: `∇²D = f_xx − f_xσ f_σσ⁻¹ f_σx`.

use nalgebra::{DMatrix, Matrix3, Point3, Unit, Vector3};
use strand_contact::{Gap, Obstacle, ObstacleMesh};
use strand_system::{Model, SystemState};

use crate::constraints::RowCurvature;

/// What the nearest obstacle point is, for the curvature of the distance to it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Feature {
    /// The inside of a face (or a point whose normal is the face's): the distance is
    /// flat across it.
    Flat,
    /// A point on a ridge line of unit direction `e`: the distance is curved across it.
    Line(Vector3<f64>),
    /// A single point (a mesh vertex, or the nearest point of another rod's edge).
    Point,
}

/// Relative tolerance of the feature classification (barycentric coordinates, normals).
const FEATURE_TOLERANCE: f64 = 1e-9;

impl Feature {
    /// The feature of the nearest point of `mesh` on triangle `triangle` at
    /// `barycentric`, seen along the unit `normal` (from the mesh to the rod).
    pub(crate) fn on_mesh(
        mesh: &ObstacleMesh,
        triangle: usize,
        barycentric: [f64; 3],
        normal: &Unit<Vector3<f64>>,
    ) -> Self {
        let corners = mesh.triangle(triangle);
        let face = (corners[1] - corners[0]).cross(&(corners[2] - corners[0]));
        let norm = face.norm();
        if norm == 0.0 || face.dot(normal).abs() >= (1.0 - FEATURE_TOLERANCE) * norm {
            return Self::Flat;
        }
        let inside: Vec<usize> = (0..3)
            .filter(|&k| barycentric[k] > FEATURE_TOLERANCE)
            .collect();
        match inside.as_slice() {
            [i, j] => Self::Line((corners[*j] - corners[*i]).normalize()),
            [_] => Self::Point,
            _ => Self::Flat,
        }
    }

    /// The Hessian (m⁻¹) of the distance to this feature at a point `distance` (m, > 0)
    /// away along the unit `normal`.
    pub(crate) fn distance_hessian(&self, normal: &Vector3<f64>, distance: f64) -> Matrix3<f64> {
        let across = Matrix3::identity() - normal * normal.transpose();
        match self {
            Self::Flat => Matrix3::zeros(),
            Self::Point => across / distance,
            Self::Line(e) => (across - e * e.transpose()) / distance,
        }
    }
}

/// A gap's point `P = Σ_i w_i x_i` on the rod(s), with `w_i = weight_i + Σ_k
/// slope_ik σ_k` affine in the free parameters `σ` (the edge parameters strictly
/// inside their edges).
pub(crate) struct GapPoint<'a> {
    /// The vertex positions `x_i`, m.
    pub vertices: &'a [Point3<f64>],
    /// The weights `w_i` at the minimum.
    pub weights: &'a [f64],
    /// Per free parameter: `∂w_i/∂σ_k` for every vertex.
    pub slopes: &'a [Vec<f64>],
}

/// The Hessian of the gap with respect to the vertex positions (3 per vertex, in the
/// order of `point.vertices`), m⁻¹, at the minimum with unit `normal` (the gap's
/// gradient is `w_i normal`), `distance` (m) from the feature.
pub(crate) fn gap_hessian(
    point: &GapPoint,
    feature: Feature,
    normal: &Vector3<f64>,
    distance: f64,
) -> DMatrix<f64> {
    let m = point.vertices.len();
    let h = feature.distance_hessian(normal, distance);
    let mut hessian = DMatrix::zeros(3 * m, 3 * m);
    if feature == Feature::Flat {
        return hessian;
    }
    for i in 0..m {
        for j in 0..m {
            let block = h * (point.weights[i] * point.weights[j]);
            hessian
                .fixed_view_mut::<3, 3>(3 * i, 3 * j)
                .copy_from(&block);
        }
    }
    // ∂P/∂σ_k, the mixed derivatives f_xσ (one column per parameter) and f_σσ.
    let along: Vec<Vector3<f64>> = point
        .slopes
        .iter()
        .map(|slope| {
            point
                .vertices
                .iter()
                .zip(slope)
                .fold(Vector3::zeros(), |sum, (x, c)| sum + x.coords * *c)
        })
        .collect();
    let p = along.len();
    if p == 0 {
        return hessian;
    }
    let mixed = DMatrix::from_fn(3 * m, p, |r, k| {
        let (i, c) = (r / 3, r % 3);
        point.slopes[k][i] * normal[c] + point.weights[i] * (h * along[k])[c]
    });
    let parameters = DMatrix::from_fn(p, p, |k, l| along[k].dot(&(h * along[l])));
    // A parameter along which the distance is flat (an edge parallel to a ridge) is
    // not determined by the minimum: it does not move the gap at second order.
    let scale = parameters.diagonal().max().max(0.0);
    let Some(inverse) = parameters
        .clone()
        .cholesky()
        .filter(|_| parameters.determinant() > 1e-12 * scale.powi(p as i32))
        .map(|c| c.inverse())
    else {
        return hessian;
    };
    hessian -= &mixed * inverse * mixed.transpose();
    hessian
}

/// The curvature of `gap`'s row with respect to the position unknowns of the free
/// vertices it involves (vertices held by supports, bodies or clips are left out), or
/// `None` when it is flat or involves no free vertex.
pub(crate) fn row_curvature(
    model: &Model,
    state: &SystemState,
    gap: &Gap,
    feature: Feature,
) -> Option<RowCurvature> {
    if feature == Feature::Flat {
        return None;
    }
    let interior = |s: f64| s > 0.0 && s < 1.0;
    // (rod, vertex) of every vertex involved, its weight in P, its slopes.
    let mut involved: Vec<(usize, usize)> = Vec::with_capacity(4);
    let mut weights = Vec::with_capacity(4);
    let mut slopes: Vec<Vec<f64>> = Vec::with_capacity(2);
    if interior(gap.s) {
        involved.extend([(gap.rod, gap.edge), (gap.rod, gap.edge + 1)]);
        weights.extend([1.0 - gap.s, gap.s]);
        slopes.push(vec![-1.0, 1.0]);
    } else {
        let vertex = if gap.s == 0.0 { gap.edge } else { gap.edge + 1 };
        involved.push((gap.rod, vertex));
        weights.push(1.0);
    }
    if let Obstacle::Rod { rod, edge, t } = gap.with {
        let own = involved.len();
        involved.extend([(rod, edge), (rod, edge + 1)]);
        weights.extend([-(1.0 - t), -t]);
        for slope in &mut slopes {
            slope.extend([0.0, 0.0]);
        }
        if interior(t) {
            let mut slope = vec![0.0; own];
            slope.extend([1.0, -1.0]);
            slopes.push(slope);
        }
    }
    let vertices: Vec<Point3<f64>> = involved
        .iter()
        .map(|&(rod, vertex)| Point3::from(state.rods[rod].positions[vertex]))
        .collect();
    let distance = (gap.point - gap.witness).norm();
    if distance <= 0.0 {
        return None;
    }
    let point = GapPoint {
        vertices: &vertices,
        weights: &weights,
        slopes: &slopes,
    };
    let full = gap_hessian(&point, feature, &gap.normal, distance);
    let free: Vec<(usize, usize)> = involved
        .iter()
        .enumerate()
        .filter_map(|(i, &(rod, vertex))| model.dofs().vertex(rod, vertex).map(|b| (i, b)))
        .collect();
    if free.is_empty() {
        return None;
    }
    let hessian = DMatrix::from_fn(3 * free.len(), 3 * free.len(), |r, c| {
        full[(3 * free[r / 3].0 + r % 3, 3 * free[c / 3].0 + c % 3)]
    });
    Some(RowCurvature {
        blocks: free.iter().map(|&(_, b)| b).collect(),
        hessian,
    })
}

#[cfg(test)]
mod tests;
