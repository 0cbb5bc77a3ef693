//! Axis-aligned box.

use nalgebra::Point3;

use crate::TriangleMesh;

/// The closed box `[min, max]` (m): 8 vertices, 12 outward triangles.
///
/// # Panics
/// If `max` is not above `min` on every axis (or a coordinate is not finite).
pub fn axis_box(min: Point3<f64>, max: Point3<f64>) -> TriangleMesh {
    for k in 0..3 {
        assert!(
            min[k].is_finite() && max[k].is_finite() && max[k] > min[k],
            "axis_box: max[{k}] = {} must be above min[{k}] = {}",
            max[k],
            min[k]
        );
    }
    let mut mesh = TriangleMesh::new();
    // Vertex i has x from bit 0, y from bit 1, z from bit 2 (0 = min, 1 = max).
    for i in 0..8u32 {
        let pick = |bit: u32, k: usize| if i & bit == 0 { min[k] } else { max[k] };
        mesh.push_vertex(Point3::new(pick(1, 0), pick(2, 1), pick(4, 2)));
    }
    // Faces, counter-clockwise seen from outside.
    mesh.push_quad(0, 2, 3, 1); // z = min, normal -z
    mesh.push_quad(4, 5, 7, 6); // z = max, normal +z
    mesh.push_quad(0, 1, 5, 4); // y = min, normal -y
    mesh.push_quad(2, 6, 7, 3); // y = max, normal +y
    mesh.push_quad(0, 4, 6, 2); // x = min, normal -x
    mesh.push_quad(1, 3, 7, 5); // x = max, normal +x
    mesh
}

#[cfg(test)]
mod tests {
    use nalgebra::{Point3, Vector3};

    use super::axis_box;

    #[test]
    fn box_is_watertight_outward_and_has_its_volume() {
        let b = axis_box(Point3::new(-0.1, 0.2, 0.3), Point3::new(0.4, 0.5, 1.3));
        assert_eq!(b.triangles.len(), 12);
        assert!(b.edge_report().is_closed_and_oriented());
        assert!((b.signed_volume() - 0.5 * 0.3 * 1.0).abs() < 1e-14);
        assert!((b.surface_area() - 2.0 * (0.5 * 0.3 + 0.5 * 1.0 + 0.3 * 1.0)).abs() < 1e-14);
        // Every triangle's normal points away from the centre.
        let centre = Point3::new(0.15, 0.35, 0.8);
        for t in 0..b.triangles.len() {
            let [p, q, r] = b.triangle_points(t);
            let n: Vector3<f64> = (q - p).cross(&(r - p));
            assert!(n.dot(&(p - centre)) > 0.0, "triangle {t} faces inwards");
        }
        assert!(b.contains_point(&centre));
        assert!(!b.contains_point(&Point3::new(0.5, 0.35, 0.8)));
        assert!((b.distance_to_point(&Point3::new(0.15, 0.35, 2.3)).unwrap() - 1.0).abs() < 1e-14);
    }

    #[test]
    #[should_panic(expected = "must be above")]
    fn inverted_box_is_refused() {
        axis_box(Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 1.0));
    }
}
