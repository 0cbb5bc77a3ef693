//! Axis-aligned box with all twelve edges chamfered (bevelled at 45°).

use nalgebra::Point3;

use crate::TriangleMesh;

/// The box `[min, max]` (m) with every edge cut by a 45° chamfer of leg `chamfer` (m)
/// and every corner by a triangle: 24 vertices, 44 outward triangles (6 faces, 12
/// edge bevels, 8 corner triangles). `chamfer = 0` is not allowed (use
/// [`crate::axis_box`]). Enclosed volume, with inner half-extents `a, b, d` (the half
/// sizes minus `chamfer`) and `c = chamfer`:
/// `8abd + 8c(ab + bd + ad) + 4c²(a + b + d) + 4c³/3`.
///
/// # Panics
/// Unless `0 < chamfer < half of the smallest size` and `max > min` on every axis.
pub fn chamfered_box(min: Point3<f64>, max: Point3<f64>, chamfer: f64) -> TriangleMesh {
    let half = (max - min) / 2.0;
    let centre = min + half;
    assert!(
        chamfer.is_finite() && chamfer > 0.0 && chamfer < half.min(),
        "chamfered_box: chamfer = {chamfer} must be > 0 and below half the smallest size ({})",
        half.min()
    );
    let mut mesh = TriangleMesh::new();
    // Vertex 3*corner + axis: the corner's point on the face normal to `axis`
    // (that coordinate at the full half-extent, the other two inset by `chamfer`).
    // Corner index: bit 0 = sign of x, bit 1 = sign of y, bit 2 = sign of z (1 = +).
    let sign = |corner: usize, k: usize| if corner >> k & 1 == 1 { 1.0 } else { -1.0 };
    for corner in 0..8 {
        for axis in 0..3 {
            let mut p = centre;
            for k in 0..3 {
                let reach = if k == axis {
                    half[k]
                } else {
                    half[k] - chamfer
                };
                p[k] += sign(corner, k) * reach;
            }
            mesh.push_vertex(p);
        }
    }
    let v = |corner: usize, axis: usize| (3 * corner + axis) as u32;
    // Emits a polygon, flipping it if its normal points towards the centre (all
    // polygons are convex and the solid is convex, so this orients them outwards).
    let polygon = |mesh: &mut TriangleMesh, ids: &[u32]| {
        let p = |i: usize| mesh.vertices[ids[i] as usize];
        let normal = (p(1) - p(0)).cross(&(p(2) - p(0)));
        let outward = normal.dot(&(p(0) - centre)) > 0.0;
        for i in 1..ids.len() - 1 {
            if outward {
                mesh.push_triangle(ids[0], ids[i], ids[i + 1]);
            } else {
                mesh.push_triangle(ids[0], ids[i + 1], ids[i]);
            }
        }
    };
    for axis in 0..3 {
        let (j, k) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0usize, 1] {
            // Face normal to `axis` on `side`: its four corners in cyclic order.
            let corners: Vec<usize> = [(0, 0), (1, 0), (1, 1), (0, 1)]
                .iter()
                .map(|&(sj, sk)| side << axis | sj << j | sk << k)
                .collect();
            let ids: Vec<u32> = corners.iter().map(|&c| v(c, axis)).collect();
            polygon(&mut mesh, &ids);
        }
        // Bevels along `axis`: between the faces normal to j and k.
        for sj in [0usize, 1] {
            for sk in [0usize, 1] {
                let lo = sj << j | sk << k;
                let hi = lo | 1 << axis;
                polygon(&mut mesh, &[v(lo, j), v(hi, j), v(hi, k), v(lo, k)]);
            }
        }
    }
    for corner in 0..8 {
        polygon(&mut mesh, &[v(corner, 0), v(corner, 1), v(corner, 2)]);
    }
    mesh
}

#[cfg(test)]
mod tests {
    use nalgebra::Point3;

    use super::chamfered_box;

    #[test]
    fn chamfered_box_is_watertight_with_the_closed_form_volume() {
        let (min, max, c) = (Point3::new(0.0, 0.0, 0.0), Point3::new(0.4, 0.3, 0.2), 0.03);
        let m = chamfered_box(min, max, c);
        assert_eq!(m.triangles.len(), 44);
        assert!(m.edge_report().is_closed_and_oriented());
        let (a, b, d) = (0.2 - c, 0.15 - c, 0.1 - c);
        let expected = 8.0 * a * b * d
            + 8.0 * c * (a * b + b * d + a * d)
            + 4.0 * c * c * (a + b + d)
            + 4.0 * c * c * c / 3.0;
        assert!(
            (m.signed_volume() - expected).abs() < 1e-14,
            "{}",
            m.signed_volume()
        );
        // Fits the box exactly, and the corner is cut off.
        let (lo, hi) = m.aabb().unwrap();
        assert!((lo - min).norm() < 1e-15 && (hi - max).norm() < 1e-15);
        assert!(!m.contains_point(&Point3::new(0.005, 0.005, 0.005)));
        assert!(m.contains_point(&Point3::new(0.2, 0.15, 0.1)));
    }
}
