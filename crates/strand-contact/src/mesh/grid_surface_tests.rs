//! A tessellated square for the mesh tests: the one grid the search tests share.

use nalgebra::Point3;

use crate::ObstacleMesh;

/// The square `x, y ∈ [lowest, lowest + 1]` m cut into `n × n` cells of two triangles
/// each (`2 n²` triangles), at the height `height(i, j, x, y)` m of grid point `(i, j)`.
pub(super) fn grid_surface(
    name: &str,
    n: usize,
    lowest: f64,
    height: impl Fn(usize, usize, f64, f64) -> f64,
) -> ObstacleMesh {
    let mut vertices = Vec::with_capacity((n + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (lowest + i as f64 / n as f64, lowest + j as f64 / n as f64);
            vertices.push(Point3::new(x, y, height(i, j, x, y)));
        }
    }
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut triangles = Vec::with_capacity(2 * n * n);
    for j in 0..n {
        for i in 0..n {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    ObstacleMesh::try_from_triangles(name, vertices, &triangles).unwrap()
}
