//! Brute-force clearance between a tube (a polyline with a radius) and a mesh.

use nalgebra::Point3;

use crate::TriangleMesh;

/// The smallest surface-to-surface gap between a tube and a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolylineClearance {
    /// Gap between the tube's surface and the mesh (unit of the inputs): the distance
    /// of the tube's axis to the nearest triangle minus the radius, negative when the
    /// tube sinks into the mesh (axis inside a closed mesh: minus the depth minus
    /// the radius).
    pub gap: f64,
    /// The axis point where the gap is smallest.
    pub at: Point3<f64>,
    /// Index of the polyline segment holding `at`.
    pub segment: usize,
}

/// Samples every polyline segment at spacing ≤ `spacing` and returns the smallest gap
/// between the tube of `radius` around it and `mesh` (exact point–triangle distances,
/// every triangle checked; the sampling error is below `spacing²/(8·radius)` for a
/// smooth surface). `None` for an empty mesh or a polyline of fewer than 2 points.
///
/// # Panics
/// Unless `spacing` is finite and positive.
pub fn tube_clearance(
    mesh: &TriangleMesh,
    polyline: &[Point3<f64>],
    radius: f64,
    spacing: f64,
) -> Option<PolylineClearance> {
    assert!(
        spacing.is_finite() && spacing > 0.0,
        "spacing = {spacing}: must be > 0"
    );
    let mut best: Option<PolylineClearance> = None;
    for (segment, pair) in polyline.windows(2).enumerate() {
        let (a, b) = (pair[0], pair[1]);
        let samples = ((b - a).norm() / spacing).ceil().max(1.0) as usize;
        for k in 0..=samples {
            let at = a + (b - a) * (k as f64 / samples as f64);
            let distance = mesh.distance_to_point(&at)?;
            let gap = if distance < radius && mesh.contains_point(&at) {
                -distance - radius
            } else {
                distance - radius
            };
            if best.is_none_or(|b| gap < b.gap) {
                best = Some(PolylineClearance { gap, at, segment });
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use nalgebra::Point3;

    use super::tube_clearance;
    use crate::axis_box;

    #[test]
    fn gap_of_a_tube_over_and_through_a_box() {
        let b = axis_box(Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 1.0, 1.0));
        // A horizontal tube 0.3 above the top face, radius 0.1: gap 0.2.
        let over = [Point3::new(-1.0, 0.5, 1.3), Point3::new(2.0, 0.5, 1.3)];
        let c = tube_clearance(&b, &over, 0.1, 0.01).unwrap();
        assert!((c.gap - 0.2).abs() < 1e-12);
        // A tube whose axis runs 0.05 below the top face: it sinks 0.15.
        let through = [Point3::new(-1.0, 0.5, 0.95), Point3::new(2.0, 0.5, 0.95)];
        let c = tube_clearance(&b, &through, 0.1, 0.01).unwrap();
        assert!((c.gap + 0.15).abs() < 1e-12, "{}", c.gap);
        assert_eq!(c.segment, 0);
    }
}
