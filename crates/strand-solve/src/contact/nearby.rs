//! The meshes a rod can reach: only those asked per vertex and edge, so that a scene
//! of many bays (each hose near its own parts) costs in proportion to its size.

use nalgebra::Point3;
use strand_contact::gaps::Aabb;

use super::Contact;

/// Added to every reach when choosing the meshes to ask, m: a mesh's bounding box and
/// a distance measured in its own frame may differ by rounding, so the choice errs on
/// the side of asking (more meshes asked, never a nearer one missed).
const REACH_SLACK_M: f64 = 1e-9;

#[cfg(test)]
thread_local! {
    /// (feature, mesh) pairs looked at on this thread: bounding-box tests of vertices
    /// and edges against a mesh while finding gaps, and nearest-point searches while
    /// limiting a step (a work counter for the test that a scene of many bays costs
    /// in proportion to its bays, not to bays²).
    pub(crate) static MESH_PAIRS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Counts one (feature, mesh) pair looked at (tests only).
pub(super) fn count_mesh_pair() {
    #[cfg(test)]
    MESH_PAIRS.with(|c| c.set(c.get() + 1));
}

impl Contact {
    /// The indices (ascending) of the meshes that may lie within `reach` (m) of some
    /// point of `points` (a rod's vertices): every mesh whose bounding box overlaps
    /// the points' box grown by `reach`. Any mesh left out is farther than `reach`
    /// from every point and every segment between them.
    pub(super) fn meshes_near<'a>(
        &self,
        points: impl IntoIterator<Item = &'a Point3<f64>>,
        reach: f64,
    ) -> Vec<usize> {
        match Aabb::of_points(points, reach + REACH_SLACK_M) {
            Some(region) => self.index.overlapping(&region),
            None => Vec::new(),
        }
    }
}
