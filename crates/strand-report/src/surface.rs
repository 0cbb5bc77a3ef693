//! The surfaces of the environment meshes near the hoses, for the report's shaded 3D
//! view (`result.json`: `environment[*].surface_m`): the triangles whose bounding box
//! meets the box around the hoses (see [`crate::region_around`]), each clipped to the
//! box (a convex polygon of 3 to 9 corners), m.
//!
//! A mesh with more than [`MAX_SURFACE_TRIANGLES`] triangles there is first decimated
//! by vertex clustering (Rossignac & Borrel 1993): every corner moves to the centre of
//! its cell of a cubic grid, triangles that lose a corner that way vanish and
//! duplicates are dropped; the cell grows by half until the count fits. The surface
//! then lies within half a cell diagonal (`surface_cell_m` · √3 / 2) of the mesh. The
//! cost follows the triangles near the hoses, not the size of the mesh, so a
//! million-triangle part far from the hoses adds nothing.

use std::collections::HashSet;

use nalgebra::Point3;
use strand_contact::ObstacleMesh;

use crate::outline::Aabb;

/// Most triangles of one mesh drawn shaded; beyond it the mesh is decimated.
pub const MAX_SURFACE_TRIANGLES: usize = 3000;

/// Polygons (corners in m) of the surface of `mesh` within `region` (see the module
/// docs), and the clustering cell size (m) if the mesh was decimated.
pub fn mesh_surface(mesh: &ObstacleMesh, region: &Aabb) -> (Vec<Vec<[f64; 3]>>, Option<f64>) {
    let near: Vec<[[f64; 3]; 3]> = (0..mesh.triangle_count())
        .map(|t| mesh.triangle(t).map(|p: Point3<f64>| [p.x, p.y, p.z]))
        .filter(|tri| meets(tri, region))
        .collect();
    let (triangles, cell) = if near.len() <= MAX_SURFACE_TRIANGLES {
        (near, None)
    } else {
        let extent = (0..3)
            .map(|i| region[1][i] - region[0][i])
            .fold(0.0, f64::max);
        let mut cell = extent / 512.0;
        loop {
            let clustered = cluster(&near, region, cell);
            if clustered.len() <= MAX_SURFACE_TRIANGLES {
                break (clustered, Some(cell));
            }
            cell *= 1.5;
        }
    };
    let polygons = triangles
        .iter()
        .filter_map(|tri| clip_polygon(tri.to_vec(), region))
        .collect();
    (polygons, cell)
}

fn meets(tri: &[[f64; 3]; 3], region: &Aabb) -> bool {
    (0..3).all(|i| {
        let lo = tri.iter().map(|p| p[i]).fold(f64::INFINITY, f64::min);
        let hi = tri.iter().map(|p| p[i]).fold(f64::NEG_INFINITY, f64::max);
        lo <= region[1][i] && hi >= region[0][i]
    })
}

/// Vertex clustering of `triangles` on a grid of `cell` (m) anchored at the region's
/// low corner: corners snapped to cell centres, degenerate and repeated triangles
/// dropped (orientation kept).
fn cluster(triangles: &[[[f64; 3]; 3]], region: &Aabb, cell: f64) -> Vec<[[f64; 3]; 3]> {
    let key = |p: &[f64; 3]| [0, 1, 2].map(|i| ((p[i] - region[0][i]) / cell).floor() as i64);
    let centre = |k: [i64; 3]| [0, 1, 2].map(|i| region[0][i] + (k[i] as f64 + 0.5) * cell);
    let mut seen: HashSet<[[i64; 3]; 3]> = HashSet::new();
    let mut out = Vec::new();
    for tri in triangles {
        let k = tri.map(|p| key(&p));
        if k[0] == k[1] || k[1] == k[2] || k[0] == k[2] {
            continue;
        }
        // The same triangle in any rotation of its corners counts once.
        let first = (0..3).min_by_key(|&i| k[i]).unwrap_or(0);
        let canonical = [k[first], k[(first + 1) % 3], k[(first + 2) % 3]];
        if seen.insert(canonical) {
            out.push(k.map(centre));
        }
    }
    out
}

/// The part of the convex polygon `polygon` inside `region` (Sutherland–Hodgman
/// against the six faces), if it keeps at least three corners.
fn clip_polygon(mut polygon: Vec<[f64; 3]>, region: &Aabb) -> Option<Vec<[f64; 3]>> {
    for axis in 0..3 {
        for (bound, keep_below) in [(region[1][axis], true), (region[0][axis], false)] {
            let inside = |p: &[f64; 3]| {
                if keep_below {
                    p[axis] <= bound
                } else {
                    p[axis] >= bound
                }
            };
            let mut next = Vec::with_capacity(polygon.len() + 1);
            for (i, a) in polygon.iter().enumerate() {
                let b = &polygon[(i + 1) % polygon.len()];
                if inside(a) {
                    next.push(*a);
                }
                if inside(a) != inside(b) {
                    let t = (bound - a[axis]) / (b[axis] - a[axis]);
                    next.push([0, 1, 2].map(|k| a[k] + t * (b[k] - a[k])));
                }
            }
            polygon = next;
            if polygon.len() < 3 {
                return None;
            }
        }
    }
    Some(polygon)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_keeps_the_part_inside_and_its_area() {
        let region: Aabb = [[0.0, 0.0, -1.0], [1.0, 1.0, 1.0]];
        // A right triangle with legs 2 in the z = 0 plane: inside the unit square it
        // covers the square's lower-left half and more: the square minus the corner
        // beyond x + y = 2, i.e. the whole square (area 1).
        let big = vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        let clipped = clip_polygon(big, &region).unwrap();
        assert!((area(&clipped) - 1.0).abs() < 1e-12, "{clipped:?}");
        assert!(
            clipped
                .iter()
                .all(|p| (0..3)
                    .all(|i| p[i] >= region[0][i] - 1e-15 && p[i] <= region[1][i] + 1e-15))
        );
        // Legs 1.5: the square minus the corner triangle of legs 0.5 (area 1 − 0.125).
        let mid = vec![[0.0, 0.0, 0.0], [1.5, 0.0, 0.0], [0.0, 1.5, 0.0]];
        let clipped = clip_polygon(mid, &region).unwrap();
        assert!((area(&clipped) - 0.875).abs() < 1e-12);
        // Entirely outside.
        assert!(
            clip_polygon(
                vec![[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [2.0, 1.0, 0.0]],
                &region
            )
            .is_none()
        );
    }

    /// Area of a planar polygon, by the cross products from its first corner.
    fn area(polygon: &[[f64; 3]]) -> f64 {
        let p = |i: usize| nalgebra::Vector3::from(polygon[i]);
        let mut sum = nalgebra::Vector3::zeros();
        for i in 1..polygon.len() - 1 {
            sum += (p(i) - p(0)).cross(&(p(i + 1) - p(0)));
        }
        0.5 * sum.norm()
    }

    #[test]
    fn clustering_drops_what_collapses_and_moves_corners_at_most_half_a_cell_diagonal() {
        let region: Aabb = [[0.0; 3], [1.0; 3]];
        // A fine strip of 200 triangles along x in the plane z = 0.5.
        let n = 100;
        let h = 1.0 / n as f64;
        let mut triangles = Vec::new();
        for i in 0..n {
            let x = i as f64 * h;
            triangles.push([[x, 0.2, 0.5], [x + h, 0.2, 0.5], [x + h, 0.8, 0.5]]);
            triangles.push([[x, 0.2, 0.5], [x + h, 0.8, 0.5], [x, 0.8, 0.5]]);
        }
        let cell = 0.1;
        let clustered = cluster(&triangles, &region, cell);
        assert!(clustered.len() < triangles.len() / 5, "{}", clustered.len());
        assert!(!clustered.is_empty());
        for tri in &clustered {
            for p in tri {
                // On a cell centre, and within half a cell diagonal of the strip's plane.
                for i in 0..3 {
                    let k = p[i] / cell - 0.5;
                    assert!((k - k.round()).abs() < 1e-9);
                }
                assert!((p[2] - 0.5).abs() <= 0.5 * cell * 3f64.sqrt());
            }
            let [a, b, c] = tri.map(nalgebra::Vector3::from);
            assert!(
                (b - a).cross(&(c - a)).norm() > 0.0,
                "no degenerate triangle"
            );
        }
        // A cell larger than the strip collapses everything.
        assert!(cluster(&triangles, &region, 2.0).is_empty());
    }

    /// A finely tessellated wavy sheet (2 × 300² = 180 000 triangles) inside the
    /// region is decimated to at most the cap but not far below it, and every corner
    /// stays within half a cell diagonal of the sheet; a sheet far from the region
    /// adds nothing.
    #[test]
    fn a_fine_mesh_is_decimated_to_the_cap_and_stays_near_its_surface() {
        let n = 300;
        let height = |x: f64, y: f64| 0.05 * (6.0 * x).sin() * (4.0 * y).cos();
        let sheet = |offset: f64| {
            let vertices: Vec<Point3<f64>> = (0..=n)
                .flat_map(|i| {
                    (0..=n).map(move |j| {
                        let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
                        Point3::new(x, y, 0.5 + height(x, y) + offset)
                    })
                })
                .collect();
            let at = |i: usize, j: usize| (i * (n + 1) + j) as u32;
            let triangles: Vec<[u32; 3]> = (0..n)
                .flat_map(|i| {
                    (0..n).flat_map(move |j| {
                        [
                            [at(i, j), at(i + 1, j), at(i + 1, j + 1)],
                            [at(i, j), at(i + 1, j + 1), at(i, j + 1)],
                        ]
                    })
                })
                .collect();
            ObstacleMesh::try_from_triangles("sheet", vertices, &triangles).unwrap()
        };
        let region: Aabb = [[0.0; 3], [1.0; 3]];
        let (polygons, cell) = mesh_surface(&sheet(0.0), &region);
        let cell = cell.expect("decimated");
        assert!(
            polygons.len() <= MAX_SURFACE_TRIANGLES,
            "{}",
            polygons.len()
        );
        assert!(
            polygons.len() >= MAX_SURFACE_TRIANGLES / 4,
            "{}",
            polygons.len()
        );
        // A corner moves to its cell's centre: by at most half a cell along z and
        // across, so its height above the sheet at its own (x, y) is at most
        // cell/2 + |∇h|·cell/√2 (|∇h| ≤ 0.05·√52 here), within half a cell diagonal.
        let reach = 0.5 * cell * 3f64.sqrt();
        let worst = polygons
            .iter()
            .flatten()
            .map(|p| (p[2] - 0.5 - height(p[0], p[1])).abs())
            .fold(0.0f64, f64::max);
        assert!(
            worst <= reach,
            "corner {worst} from the sheet, allowed {reach}"
        );
        assert!(worst > 0.05 * reach, "the corners did move: {worst}");
        let (far, _) = mesh_surface(&sheet(5.0), &region);
        assert!(far.is_empty());
    }
}
