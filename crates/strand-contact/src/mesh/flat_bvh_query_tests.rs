//! The BVH searches of the mesh queries against scans of every triangle in the cluster
//! order: the same nearest triangle and closest points bit for bit (ties to the first
//! in that order), the same candidates in the same order with the same box distances,
//! the same tie intervals, local contacts and ray crossings. On random triangle soups
//! and on a tessellated surface whose shared vertices and edges make exact ties.

use nalgebra::{Point3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::grid_surface_tests::grid_surface;
use super::segment_proximity::SegmentBound;
use crate::ObstacleMesh;
use crate::closest::segment_triangle_candidate;

/// `n` random triangles in `[−1, 1]³` of sizes 0.01 to 0.5 m, a third of them sharing a
/// corner with the one before.
pub(super) fn soup(rng: &mut ChaCha8Rng, n: usize) -> ObstacleMesh {
    let mut vertices: Vec<Point3<f64>> = Vec::new();
    let mut triangles = Vec::new();
    for t in 0..n {
        let size = rng.random_range(0.01..0.5);
        let start = vertices.len() as u32;
        let centre = Point3::from(Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0)));
        for _ in 0..3 {
            let offset = Vector3::from_fn(|_, _| rng.random_range(-size..size));
            vertices.push(centre + offset);
        }
        let mut corners = [start, start + 1, start + 2];
        if t > 0 && rng.random_bool(1.0 / 3.0) {
            corners[0] = start - 1;
        }
        triangles.push(corners);
    }
    ObstacleMesh::try_from_triangles("soup", vertices, &triangles).unwrap()
}

/// A tessellated wavy square of `2 n²` triangles, `x, y ∈ [0, 1]` m (every seventh
/// diagonal of grid points flat, so that shared edges make exact ties).
pub(super) fn surface(n: usize) -> ObstacleMesh {
    grid_surface("surface", n, 0.0, |i, j, x, y| {
        if (i + j) % 7 == 0 {
            0.0
        } else {
            0.05 * (5.0 * x).sin() * (3.0 * y).cos()
        }
    })
}

/// A query: a segment (a point a quarter of the time, often right above a vertex of
/// the mesh so that the nearest points tie) and a reach.
pub(super) fn query(rng: &mut ChaCha8Rng, mesh: &ObstacleMesh) -> (Point3<f64>, Point3<f64>, f64) {
    let a = if rng.random_bool(0.3) {
        let vertex = mesh.tree.vertices[rng.random_range(0..mesh.vertex_count())];
        Point3::from(vertex) + Vector3::new(0.0, 0.0, rng.random_range(0.0..0.2))
    } else {
        Point3::from(Vector3::from_fn(|_, _| rng.random_range(-1.2..1.2)))
    };
    let b = if rng.random_bool(0.25) {
        a
    } else {
        a + Vector3::from_fn(|_, _| rng.random_range(-0.3..0.3))
    };
    let reach = match rng.random_range(0..10) {
        0 => f64::INFINITY,
        1 => 0.0,
        _ => rng.random_range(0.0..0.6),
    };
    (a, b, reach)
}

/// The hull of the closest-point intervals within `limit`, over every triangle.
fn tie_interval_by_scan(
    mesh: &ObstacleMesh,
    p0: &Point3<f64>,
    p1: &Point3<f64>,
    limit: f64,
) -> (f64, f64) {
    let bound = SegmentBound::new(p0, p1, &mesh.bounding_box);
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for &t in &mesh.tree.order {
        let corners = mesh.local_triangle(t as usize);
        if bound.triangle_distance(&corners, limit) > limit {
            continue;
        }
        let [a, b, c] = corners;
        let candidate = segment_triangle_candidate(p0, p1, &a, &b, &c);
        if candidate.squared <= limit * limit {
            let half = 0.5 * candidate.interval;
            low = low.min(candidate.value.0 - half);
            high = high.max(candidate.value.0 + half);
        }
    }
    (low, high)
}

pub(super) fn meshes() -> Vec<ObstacleMesh> {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    vec![
        soup(&mut rng, 7),
        soup(&mut rng, 1500),
        surface(30),
        surface(3),
    ]
}

#[test]
fn the_nearest_triangle_is_that_of_a_scan_bit_for_bit() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut ties = 0;
    for mesh in meshes() {
        for _ in 0..1500 {
            let (a, b, reach) = query(&mut rng, &mesh);
            let searched = mesh.nearest(&a, &b, reach);
            let scanned = mesh.nearest_by_scan(&a, &b, reach);
            assert_eq!(
                format!("{searched:?}"),
                format!("{scanned:?}"),
                "{a} {b} {reach}"
            );
            // Count the queries whose nearest distance is shared by several triangles.
            if let Some((_, best)) = scanned {
                let equal = (0..mesh.triangle_count())
                    .filter(|&t| {
                        let [p, q, r] = mesh.local_triangle(t);
                        segment_triangle_candidate(&a, &b, &p, &q, &r).squared == best.squared
                    })
                    .count();
                ties += usize::from(equal > 1);
            }
            let (low, high) = mesh.tie_interval(&a, &b, reach.next_up());
            let (scan_low, scan_high) = tie_interval_by_scan(&mesh, &a, &b, reach.next_up());
            assert_eq!(
                (low.to_bits(), high.to_bits()),
                (scan_low.to_bits(), scan_high.to_bits())
            );
        }
    }
    assert!(ties > 50, "the queries must exercise exact ties ({ties})");
}

#[test]
fn the_candidates_within_reach_are_those_of_a_scan_in_cluster_order() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for mesh in meshes() {
        let order = mesh.tree.order.clone();
        for _ in 0..1500 {
            let (a, b, reach) = query(&mut rng, &mesh);
            let bound = SegmentBound::new(&a, &b, &mesh.bounding_box);
            let key = |list: &[super::near_scan::Reachable]| -> Vec<(usize, usize, u64)> {
                list.iter()
                    .map(|r| (r.position, r.triangle, r.bound.to_bits()))
                    .collect()
            };
            let searched = mesh.reachable(&bound, reach, None);
            let scanned = mesh.reachable(&bound, reach, Some(&order));
            assert_eq!(key(&searched), key(&scanned), "{a} {b} {reach}");
            let contacts = mesh.local_contacts(&a, &b, reach);
            let among = mesh.local_contacts_among(&a, &b, reach, &order);
            assert_eq!(format!("{contacts:?}"), format!("{among:?}"));
        }
    }
}

#[test]
fn ray_crossings_are_those_of_a_scan() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut crossed = 0;
    for mesh in meshes() {
        for _ in 0..1000 {
            let point = Point3::from(Vector3::from_fn(|_, _| rng.random_range(-1.2..1.2)));
            let d = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0)).normalize();
            let searched = mesh.winding_along(&point, &d);
            assert_eq!(searched, mesh.winding_by_scan(&point, &d));
            crossed += usize::from(searched.is_some_and(|w| w != 0));
        }
    }
    assert!(crossed > 100, "the rays must cross the meshes ({crossed})");
}
