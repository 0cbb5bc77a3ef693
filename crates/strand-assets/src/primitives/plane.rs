//! Flat tessellated rectangle (a floor).

use nalgebra::Point3;

use super::require_positive;
use crate::TriangleMesh;

/// The rectangle `[−size_x/2, size_x/2] × [−size_y/2, size_y/2]` in the plane `z = 0`
/// (m), normal `+z`, split into `nx × ny` cells of two triangles each. The grid is the
/// one whose triangle count `2·nx·ny` is closest to `triangles_target` among grids
/// with cell aspect ratios between ½ and 2 (ties: the squarest cells); the count is
/// exact whenever such a grid exists (e.g. 200 on a 2 × 1 rectangle) and never below 2.
///
/// # Panics
/// Unless both sizes are finite and positive.
pub fn plane(size_x: f64, size_y: f64, triangles_target: usize) -> TriangleMesh {
    require_positive("plane size_x", size_x);
    require_positive("plane size_y", size_y);
    let (nx, ny) = grid_for(size_x, size_y, (triangles_target / 2).max(1));
    grid(size_x, size_y, nx, ny, |_, _| 0.0)
}

/// The `(nx, ny)` with `nx·ny` closest to `cells` and cell aspect in [½, 2].
fn grid_for(size_x: f64, size_y: f64, cells: usize) -> (usize, usize) {
    let mut best = (1, cells, usize::MAX, f64::INFINITY);
    for nx in 1..=cells {
        let ny = ((cells as f64 / nx as f64).round() as usize).max(1);
        let skew = ((size_x / nx as f64) / (size_y / ny as f64)).ln().abs();
        if skew > std::f64::consts::LN_2 + 1e-12 {
            continue;
        }
        let miss = (nx * ny).abs_diff(cells);
        if miss < best.2 || (miss == best.2 && skew < best.3) {
            best = (nx, ny, miss, skew);
        }
    }
    if best.2 == usize::MAX {
        // No grid has cells within 2:1 (a very long strip): square-ish cells.
        let nx = ((cells as f64 * size_x / size_y).sqrt().round() as usize).max(1);
        return (nx, (cells / nx).max(1));
    }
    (best.0, best.1)
}

/// An `nx × ny` grid over the centred rectangle with heights `z = height(x, y)`.
pub(crate) fn grid(
    size_x: f64,
    size_y: f64,
    nx: usize,
    ny: usize,
    height: impl Fn(f64, f64) -> f64,
) -> TriangleMesh {
    let mut mesh = TriangleMesh {
        vertices: Vec::with_capacity((nx + 1) * (ny + 1)),
        triangles: Vec::with_capacity(2 * nx * ny),
    };
    for j in 0..=ny {
        let y = size_y * (j as f64 / ny as f64 - 0.5);
        for i in 0..=nx {
            let x = size_x * (i as f64 / nx as f64 - 0.5);
            mesh.push_vertex(Point3::new(x, y, height(x, y)));
        }
    }
    let v = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    for j in 0..ny {
        for i in 0..nx {
            mesh.push_quad(v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use nalgebra::{Point3, Vector3};

    use super::plane;

    #[test]
    fn plane_has_the_requested_count_area_and_upward_normals() {
        for (sx, sy, target) in [(2.0, 1.0, 200), (1.0, 1.0, 2), (3.0, 1.0, 6000)] {
            let p = plane(sx, sy, target);
            assert_eq!(p.triangles.len(), target, "{sx} x {sy}, {target}");
            assert!((p.surface_area() - sx * sy).abs() < 1e-12);
            let report = p.edge_report();
            assert_eq!(report.misoriented_edges + report.non_manifold_edges, 0);
            for t in 0..p.triangles.len() {
                let [a, b, c] = p.triangle_points(t);
                let n: Vector3<f64> = (b - a).cross(&(c - a));
                assert!(n.z > 0.0 && n.x == 0.0 && n.y == 0.0);
            }
            let (lo, hi) = p.aabb().unwrap();
            assert_eq!(lo, Point3::new(-sx / 2.0, -sy / 2.0, 0.0));
            assert_eq!(hi, Point3::new(sx / 2.0, sy / 2.0, 0.0));
        }
        // 97 cells on a square only fit as 1 × 97 (too skewed): the count is approximate.
        let p = plane(1.0, 1.0, 2 * 97);
        assert!(
            p.triangles.len().abs_diff(194) <= 2 * 10,
            "{}",
            p.triangles.len()
        );
    }
}
