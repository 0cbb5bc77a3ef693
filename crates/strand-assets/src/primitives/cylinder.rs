//! Cylinder along the z axis.

use std::f64::consts::TAU;

use nalgebra::Point3;

use super::require_positive;
use crate::TriangleMesh;

/// A cylinder of `radius` and `length` (m) with its axis on the z axis, centred at the
/// origin (`z ∈ [−length/2, length/2]`). The circle is the regular `segments`-gon
/// inscribed in it, with a vertex at angle 0 (on `+x`). `capped` closes both ends
/// with triangle fans around a centre vertex (a watertight solid, `4·segments`
/// triangles, volume `segments/2 · r² sin(2π/segments) · length`); otherwise it is the
/// open side surface (`2·segments` triangles) with normals pointing away from the axis.
///
/// # Panics
/// Unless `radius` and `length` are finite and positive and `segments ≥ 3`.
pub fn cylinder(radius: f64, length: f64, segments: usize, capped: bool) -> TriangleMesh {
    require_positive("cylinder radius", radius);
    require_positive("cylinder length", length);
    assert!(segments >= 3, "cylinder segments = {segments}: must be ≥ 3");
    let n = segments as u32;
    let mut mesh = TriangleMesh::new();
    for z in [-length / 2.0, length / 2.0] {
        for i in 0..segments {
            let angle = TAU * i as f64 / segments as f64;
            mesh.push_vertex(Point3::new(radius * angle.cos(), radius * angle.sin(), z));
        }
    }
    let (bottom, top) = (|i: u32| i % n, |i: u32| n + i % n);
    for i in 0..n {
        mesh.push_quad(bottom(i), bottom(i + 1), top(i + 1), top(i));
    }
    if capped {
        let bottom_centre = mesh.push_vertex(Point3::new(0.0, 0.0, -length / 2.0));
        let top_centre = mesh.push_vertex(Point3::new(0.0, 0.0, length / 2.0));
        for i in 0..n {
            mesh.push_triangle(bottom_centre, bottom(i + 1), bottom(i));
            mesh.push_triangle(top_centre, top(i), top(i + 1));
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use std::f64::consts::{PI, TAU};

    use nalgebra::Point3;

    use super::cylinder;

    #[test]
    fn capped_cylinder_is_watertight_with_the_polygon_volume() {
        for n in [3, 7, 48] {
            let c = cylinder(0.05, 0.3, n, true);
            assert_eq!(c.triangles.len(), 4 * n);
            assert!(c.edge_report().is_closed_and_oriented(), "n = {n}");
            let polygon = n as f64 / 2.0 * 0.05f64.powi(2) * (TAU / n as f64).sin() * 0.3;
            assert!((c.signed_volume() - polygon).abs() < 1e-15, "n = {n}");
        }
        // Discretisation error of the inscribed 256-gon: 1 − sin(2π/n)/(2π/n) ≈ 1e-4.
        let fine = cylinder(0.05, 0.3, 256, true);
        let exact = PI * 0.05f64.powi(2) * 0.3;
        assert!(((fine.signed_volume() - exact) / exact).abs() < 1.1e-4);
        let (lo, hi) = fine.aabb().unwrap();
        assert!((lo.z + 0.15).abs() < 1e-15 && (hi.z - 0.15).abs() < 1e-15);
        assert!(fine.contains_point(&Point3::new(0.0, 0.04, 0.1)));
        assert!(!fine.contains_point(&Point3::new(0.0, 0.06, 0.1)));
    }

    #[test]
    fn open_cylinder_has_two_rims_and_outward_normals() {
        let c = cylinder(0.1, 1.0, 16, false);
        assert_eq!(c.triangles.len(), 32);
        let report = c.edge_report();
        assert_eq!(report.boundary_edges, 32);
        assert_eq!(report.misoriented_edges, 0);
        for t in 0..c.triangles.len() {
            let [a, b, d] = c.triangle_points(t);
            let n = (b - a).cross(&(d - a));
            let radial = (a.coords + b.coords + d.coords) / 3.0;
            assert!(n.x * radial.x + n.y * radial.y > 0.0, "triangle {t}");
            assert!(n.z.abs() < 1e-12);
        }
    }
}
