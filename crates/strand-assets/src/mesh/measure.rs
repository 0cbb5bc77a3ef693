//! Volume, area and bounding box.

use nalgebra::Point3;

use super::TriangleMesh;

impl TriangleMesh {
    /// Signed enclosed volume `Σ a · (b × c) / 6` (unit³). For a closed mesh with
    /// outward (counter-clockwise) triangles it is the enclosed volume, positive; an
    /// inside-out mesh gives the negative. Open meshes give an origin-dependent number.
    pub fn signed_volume(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.triangle_points(t);
                a.coords.dot(&b.coords.cross(&c.coords))
            })
            .sum::<f64>()
            / 6.0
    }

    /// Total triangle area (unit²).
    pub fn surface_area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.triangle_points(t);
                0.5 * (b - a).cross(&(c - a)).norm()
            })
            .sum()
    }

    /// Axis-aligned bounding box `(min, max)` of the vertices; `None` when empty.
    pub fn aabb(&self) -> Option<(Point3<f64>, Point3<f64>)> {
        let first = *self.vertices.first()?;
        Some(
            self.vertices
                .iter()
                .fold((first, first), |(lo, hi), v| (lo.inf(v), hi.sup(v))),
        )
    }
}
