//! Thick-walled tube (a ring such as a fan shroud).

use std::f64::consts::TAU;

use nalgebra::Point3;

use super::require_positive;
use crate::TriangleMesh;

/// A closed tube (annular solid) with its axis on the z axis, centred at the origin:
/// walls between `inner_radius` and `outer_radius` (m), `z ∈ [−length/2, length/2]`,
/// both circles regular `segments`-gons with a vertex on `+x`. Watertight, outward
/// (the inner wall faces the axis), `8·segments` triangles, volume
/// `segments/2 · (ro² − ri²) sin(2π/segments) · length`.
///
/// # Panics
/// Unless `0 < inner_radius < outer_radius`, `length > 0` and `segments ≥ 3`.
pub fn tube(inner_radius: f64, outer_radius: f64, length: f64, segments: usize) -> TriangleMesh {
    require_positive("tube inner_radius", inner_radius);
    require_positive("tube length", length);
    assert!(
        outer_radius.is_finite() && outer_radius > inner_radius,
        "tube outer_radius = {outer_radius}: must be above inner_radius = {inner_radius}"
    );
    assert!(segments >= 3, "tube segments = {segments}: must be ≥ 3");
    let n = segments as u32;
    let mut mesh = TriangleMesh::new();
    // Rings in the order: outer bottom, outer top, inner bottom, inner top.
    for radius in [outer_radius, inner_radius] {
        for z in [-length / 2.0, length / 2.0] {
            for i in 0..segments {
                let angle = TAU * i as f64 / segments as f64;
                mesh.push_vertex(Point3::new(radius * angle.cos(), radius * angle.sin(), z));
            }
        }
    }
    let ring = |k: u32| move |i: u32| k * n + i % n;
    let (outer_bottom, outer_top, inner_bottom, inner_top) = (ring(0), ring(1), ring(2), ring(3));
    for i in 0..n {
        let j = i + 1;
        mesh.push_quad(outer_bottom(i), outer_bottom(j), outer_top(j), outer_top(i));
        mesh.push_quad(inner_bottom(i), inner_top(i), inner_top(j), inner_bottom(j));
        mesh.push_quad(outer_top(i), outer_top(j), inner_top(j), inner_top(i));
        mesh.push_quad(
            outer_bottom(i),
            inner_bottom(i),
            inner_bottom(j),
            outer_bottom(j),
        );
    }
    mesh
}

#[cfg(test)]
mod tests {
    use std::f64::consts::TAU;

    use nalgebra::Point3;

    use super::tube;

    #[test]
    fn tube_is_watertight_with_the_annulus_volume() {
        let n = 40;
        let t = tube(0.14, 0.15, 0.06, n);
        assert_eq!(t.triangles.len(), 8 * n);
        assert!(t.edge_report().is_closed_and_oriented());
        let expected =
            n as f64 / 2.0 * (0.15f64.powi(2) - 0.14f64.powi(2)) * (TAU / n as f64).sin() * 0.06;
        assert!((t.signed_volume() - expected).abs() < 1e-15);
        // The bore is empty, the wall is solid.
        assert!(!t.contains_point(&Point3::origin()));
        assert!(t.contains_point(&Point3::new(0.0, 0.145, 0.0)));
    }
}
