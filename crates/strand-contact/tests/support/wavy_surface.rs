//! A generated test and benchmark surface, shared by the integration tests and the
//! benches of this crate (`#[path]`-included: not part of the library's API).

use nalgebra::Point3;

/// A wavy square surface `z = amplitude · sin(kx) · cos(ky)` over `[0, size]²` (m),
/// tessellated into `2 n²` triangles with `n = ⌈√(triangles / 2)⌉` (so at least
/// `triangles` triangles).
pub fn wavy_surface(
    triangles: usize,
    size: f64,
    amplitude: f64,
) -> (Vec<Point3<f64>>, Vec<[u32; 3]>) {
    let n = ((triangles as f64 / 2.0).sqrt().ceil() as usize).max(1);
    let k = 2.0 * std::f64::consts::PI * 3.0 / size;
    let step = size / n as f64;
    let mut vertices = Vec::with_capacity((n + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64 * step, j as f64 * step);
            vertices.push(Point3::new(x, y, amplitude * (k * x).sin() * (k * y).cos()));
        }
    }
    let index = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut faces = Vec::with_capacity(2 * n * n);
    for j in 0..n {
        for i in 0..n {
            faces.push([index(i, j), index(i + 1, j), index(i + 1, j + 1)]);
            faces.push([index(i, j), index(i + 1, j + 1), index(i, j + 1)]);
        }
    }
    (vertices, faces)
}
