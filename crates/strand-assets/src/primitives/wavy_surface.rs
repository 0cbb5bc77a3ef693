//! Wavy tessellated surface with an exact triangle count (benchmark meshes).

use std::f64::consts::TAU;

use nalgebra::Point3;

use super::require_positive;
use crate::TriangleMesh;

/// Height of the wavy surface at `(x, y)` for a given `extent` (m): amplitude
/// `extent/50`, wavelength `extent/5` in both directions.
pub fn wavy_height(extent: f64, x: f64, y: f64) -> f64 {
    let wavelength = extent / 5.0;
    extent / 50.0 * (TAU * x / wavelength).sin() * (TAU * y / wavelength).cos()
}

/// An open wavy surface `z = wavy_height(extent, x, y)` over (about) the square
/// `[−extent/2, extent/2]²` (m) with exactly `triangle_count` triangles (≥ 1): a grid
/// of `nx = ⌈√⌈N/2⌉⌉` square cells per row, filled row by row from `y = −extent/2`;
/// the last row may be partial and an odd count ends with one half cell. Normals
/// point up (`+z` side). Meant for large benchmark meshes (1M–4M triangles).
///
/// # Panics
/// Unless `extent` is finite and positive and `triangle_count ≥ 1`.
pub fn wavy_surface(extent: f64, triangle_count: usize) -> TriangleMesh {
    require_positive("wavy_surface extent", extent);
    assert!(
        triangle_count >= 1,
        "wavy_surface triangle_count = 0: must be ≥ 1"
    );
    let cells = triangle_count / 2;
    let half_cell = triangle_count % 2 == 1;
    let nx = (((cells + usize::from(half_cell)) as f64).sqrt().ceil() as usize).max(1);
    let full_rows = cells / nx;
    let partial = cells % nx;
    let cell = extent / nx as f64;
    // Vertices: full_rows + 1 complete rows, then the top of the partial row.
    let top_row = if partial > 0 || half_cell {
        partial + 1
    } else {
        0
    };
    let mut mesh = TriangleMesh {
        vertices: Vec::with_capacity((full_rows + 1) * (nx + 1) + top_row),
        triangles: Vec::with_capacity(triangle_count),
    };
    let push_row = |mesh: &mut TriangleMesh, j: usize, count: usize| {
        let y = -extent / 2.0 + cell * j as f64;
        for i in 0..count {
            let x = -extent / 2.0 + cell * i as f64;
            mesh.push_vertex(Point3::new(x, y, wavy_height(extent, x, y)));
        }
    };
    for j in 0..=full_rows {
        push_row(&mut mesh, j, nx + 1);
    }
    push_row(&mut mesh, full_rows + 1, top_row);
    let v = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    for j in 0..full_rows {
        for i in 0..nx {
            mesh.push_quad(v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
        }
    }
    // The partial row's top vertices follow the complete rows (index v(i, full_rows + 1)).
    let j = full_rows;
    for i in 0..partial {
        mesh.push_quad(v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
    }
    if half_cell {
        mesh.push_triangle(v(partial, j), v(partial + 1, j), v(partial, j + 1));
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::{wavy_height, wavy_surface};

    #[test]
    fn wavy_surface_has_exactly_the_requested_triangles_and_no_stray_vertices() {
        for count in [1, 2, 3, 17, 1000, 1001, 20_000] {
            let m = wavy_surface(2.0, count);
            assert_eq!(m.triangles.len(), count);
            let mut used = vec![false; m.vertices.len()];
            for t in &m.triangles {
                for &v in t {
                    used[v as usize] = true;
                }
            }
            assert!(
                used.iter().all(|&u| u),
                "count {count}: unreferenced vertices"
            );
            let report = m.edge_report();
            assert_eq!(report.misoriented_edges + report.non_manifold_edges, 0);
            assert_eq!(report.degenerate_triangles, 0);
            for t in 0..m.triangles.len() {
                let [a, b, c] = m.triangle_points(t);
                assert!(
                    (b - a).cross(&(c - a)).z > 0.0,
                    "count {count}: triangle {t} faces down"
                );
            }
            for v in &m.vertices {
                assert_eq!(v.z, wavy_height(2.0, v.x, v.y));
                assert!(v.x.abs() <= 1.0 + 1e-12 && v.y.abs() <= 1.0 + 1e-12);
            }
        }
        // A full square grid (20 000 = 2·100²) has the (projected) area of the square.
        let m = wavy_surface(2.0, 20_000);
        let (lo, hi) = m.aabb().unwrap();
        assert!((hi.x - lo.x - 2.0).abs() < 1e-12 && (hi.y - lo.y - 2.0).abs() < 1e-12);
        assert!(hi.z <= 0.04 && lo.z >= -0.04 && hi.z > 0.039);
    }
}
