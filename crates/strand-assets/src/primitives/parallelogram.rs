//! Flat tessellated parallelogram (a flank of a groove, a face of a corner).

use nalgebra::{Point3, Vector3};

use crate::TriangleMesh;

/// The parallelogram `origin + a·u + b·v`, `a, b ∈ [0, 1]` (m), split into `nu × nv`
/// cells of two triangles each, with normal along `u × v` (counter-clockwise seen from
/// that side). Building blocks for grooves and corners: two parallelograms sharing an
/// edge form a V-groove, three sharing a vertex a corner.
///
/// # Panics
/// If `nu` or `nv` is 0, or `u`, `v` are parallel or not finite.
pub fn parallelogram(
    origin: Point3<f64>,
    u: Vector3<f64>,
    v: Vector3<f64>,
    nu: usize,
    nv: usize,
) -> TriangleMesh {
    assert!(
        nu > 0 && nv > 0,
        "parallelogram: nu = {nu}, nv = {nv} must be ≥ 1"
    );
    let area = u.cross(&v).norm();
    assert!(
        area.is_finite() && area > 0.0,
        "parallelogram: u = {u:?} and v = {v:?} must span a plane"
    );
    let mut mesh = TriangleMesh::new();
    for j in 0..=nv {
        for i in 0..=nu {
            let (a, b) = (i as f64 / nu as f64, j as f64 / nv as f64);
            mesh.push_vertex(origin + u * a + v * b);
        }
    }
    let at = |i: usize, j: usize| (j * (nu + 1) + i) as u32;
    for j in 0..nv {
        for i in 0..nu {
            mesh.push_quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_cover_the_parallelogram_with_the_right_normal() {
        let (u, v) = (Vector3::new(2.0, 0.0, 0.0), Vector3::new(0.5, 1.0, 0.0));
        let mesh = parallelogram(Point3::origin(), u, v, 4, 3);
        assert_eq!((mesh.vertices.len(), mesh.triangles.len()), (20, 24));
        let mut area = 0.0;
        for t in 0..mesh.triangles.len() {
            let [a, b, c] = mesh.triangle_points(t);
            let n = (b - a).cross(&(c - a));
            assert!(n.z > 0.0 && n.x.abs() < 1e-15 && n.y.abs() < 1e-15);
            area += 0.5 * n.norm();
        }
        assert!((area - u.cross(&v).norm()).abs() < 1e-12);
    }
}
