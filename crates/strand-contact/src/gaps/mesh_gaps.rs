//! Rod–mesh gaps.

use super::{Gap, GapError, Obstacle, RodGeometry, validate};
use crate::ObstacleMesh;

/// One [`Gap`] per (rod edge, mesh) pair whose gap `distance − radius` is at most
/// `margin` (m): the nearest mesh point to the edge's centreline segment.
///
/// Fails if the margin is negative or not finite, a rod is invalid, or a centreline
/// touches a mesh surface (no contact direction).
pub fn mesh_gaps<M: AsRef<ObstacleMesh>>(
    rods: &[RodGeometry],
    meshes: &[M],
    margin: f64,
) -> Result<Vec<Gap>, GapError> {
    validate(rods)?;
    check_margin(margin)?;
    let mut gaps = Vec::new();
    for (rod, geometry) in rods.iter().enumerate() {
        for (edge, ends) in geometry.vertices.windows(2).enumerate() {
            for (index, mesh) in meshes.iter().enumerate() {
                let reach = geometry.radius + margin;
                let Some(near) = mesh.as_ref().segment_proximity(&ends[0], &ends[1], reach) else {
                    continue;
                };
                let Some(normal) = near.normal else {
                    return Err(GapError::CentrelineTouches {
                        rod,
                        edge,
                        what: format!("touches mesh {index} '{}'", mesh.as_ref().name()),
                        point: near.point_on_mesh,
                    });
                };
                gaps.push(Gap {
                    rod,
                    edge,
                    s: near.s,
                    with: Obstacle::Mesh(index),
                    point: near.point_on_segment,
                    witness: near.point_on_mesh,
                    normal,
                    gap: near.distance - geometry.radius,
                });
            }
        }
    }
    Ok(gaps)
}

/// The margin must be finite and ≥ 0.
pub(super) fn check_margin(margin: f64) -> Result<(), GapError> {
    if margin.is_finite() && margin >= 0.0 {
        Ok(())
    } else {
        Err(GapError::InvalidMargin { margin })
    }
}
