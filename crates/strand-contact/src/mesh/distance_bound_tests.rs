//! [`ObstacleMesh::segment_distance_bound`] against references: the grid floor of a scan
//! of every triangle's exact distance bit for bit, between 15/16 of the exact distance of
//! [`ObstacleMesh::segment_proximity`] and that distance, the same bound for the same
//! geometry in meshes whose trees differ, and the work at two densities of a floor.

use nalgebra::{Point3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::distance_bound::distance_grid_floor;
use super::flat_bvh_query_tests::{meshes, query};
use super::grid_surface_tests::grid_surface;
use super::near_scan_tests::wavy;
use super::work::{QueryWork, query_work};
use crate::ObstacleMesh;

#[test]
fn the_grid_floor_is_a_lower_bound_within_a_sixteenth() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..100_000 {
        let d = 10f64.powf(rng.random_range(-12.0..3.0));
        let floor = distance_grid_floor(d);
        assert!(floor <= d && floor > d * 15.0 / 16.0, "{d} -> {floor}");
        // A grid point is its own floor, and the floor is monotone.
        assert_eq!(distance_grid_floor(floor), floor);
        let e = d * rng.random_range(1.0..1.2);
        assert!(distance_grid_floor(e) >= floor);
    }
    assert_eq!(distance_grid_floor(0.0), 0.0);
    assert_eq!(distance_grid_floor(1.0), 1.0);
    // 2^(1/12) = 1.05946…, 2^(11/12) = 1.88775…
    assert_eq!(distance_grid_floor(1.0594), 1.0);
    assert_eq!(distance_grid_floor(1.0595), 2f64.powf(1.0 / 12.0));
    assert_eq!(distance_grid_floor(0.99), 0.5 * 2f64.powf(11.0 / 12.0));
    assert_eq!(distance_grid_floor(3.0), 2.0 * 2f64.powf(7.0 / 12.0));
    assert_eq!(distance_grid_floor(f64::INFINITY), f64::INFINITY);
}

#[test]
fn the_bound_is_the_grid_floor_of_every_triangles_distance_bit_for_bit() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let (mut found, mut hinted) = (0, 0);
    for mesh in meshes() {
        for _ in 0..1500 {
            let (a, b, reach) = query(&mut rng, &mesh);
            let bound = mesh.segment_distance_bound(&a, &b, reach);
            let scanned = mesh.distance_bound_by_scan(&a, &b, reach);
            assert_eq!(
                bound.map(f64::to_bits),
                scanned.map(f64::to_bits),
                "{a} {b} {reach}: {bound:?} vs {scanned:?}"
            );
            // The same from any starting triangle: a random one, and the nearest one
            // the search tested.
            let count = mesh.triangle_count();
            for hint in [
                rng.random_range(0..count),
                rng.random_range(0..count),
                count,
            ] {
                let hinted = mesh.segment_distance_bound_from(&a, &b, reach, Some(hint));
                assert_eq!(hinted.map(|h| h.bound.to_bits()), bound.map(f64::to_bits));
            }
            if let Some(first) = mesh.segment_distance_bound_from(&a, &b, reach, None) {
                let again =
                    mesh.segment_distance_bound_from(&a, &b, reach, Some(first.nearest_tested));
                assert_eq!(again.map(|h| h.bound), Some(first.bound));
                hinted += 1;
            }
            // Against the exact nearest point: found within the same reach, never
            // above its distance, never below 15/16 of it (to within rounding).
            let exact = mesh.segment_proximity(&a, &b, reach);
            assert_eq!(bound.is_some(), exact.is_some(), "{a} {b} {reach}");
            if let (Some(bound), Some(exact)) = (bound, exact) {
                let d = exact.distance;
                let rounding = 1e-12 * (1.0 + d);
                assert!(bound <= d + rounding, "{bound} above {d}");
                assert!(
                    bound >= 15.0 / 16.0 * d - rounding,
                    "{bound} below 15/16 of {d}"
                );
                found += 1;
            }
        }
    }
    assert!(found > 2000, "the queries must find the meshes ({found})");
    assert_eq!(hinted, found);
}

/// The square `x, y ∈ [0, 1]` m of `2 n²` triangles over a wave, and, with `extra`,
/// a second such square 3 m farther along x and 0.4 m higher: the first square's
/// triangles then sit in other clusters and another tree.
fn patch(n: usize, extra: bool) -> ObstacleMesh {
    let height = |x: f64, y: f64| 0.03 * (7.0 * x).sin() * (4.0 * y).cos();
    let alone = grid_surface("patch", n, 0.0, |_, _, x, y| height(x, y));
    if !extra {
        return alone;
    }
    let far = grid_surface("far", n, 0.0, |_, _, x, y| height(x, y) + 0.4);
    let mut vertices: Vec<Point3<f64>> = (0..alone.vertex_count())
        .map(|v| Point3::from(alone.tree.vertices[v]))
        .collect();
    let offset = vertices.len() as u32;
    vertices.extend(
        (0..far.vertex_count()).map(|v| Point3::from(far.tree.vertices[v]) + Vector3::x() * 3.0),
    );
    let mut triangles: Vec<[u32; 3]> = alone.tree.indices.clone();
    triangles.extend(far.tree.indices.iter().map(|t| t.map(|i| i + offset)));
    ObstacleMesh::try_from_triangles("two patches", vertices, &triangles).unwrap()
}

#[test]
fn identical_geometry_gets_identical_bounds_whatever_else_the_mesh_holds() {
    // The same wavy square alone and next to a second one: the Morton codes of its
    // triangles, its clusters and its tree differ, so the searches meet its triangles
    // in another order (their work differs), but every bound is the same bit for bit.
    let (n, queries) = (40, 2000);
    let (alone, with_more) = (patch(n, false), patch(n, true));
    assert_eq!(with_more.triangle_count(), 2 * alone.triangle_count());
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut other_work, mut found) = (0, 0);
    for _ in 0..queries {
        // Segments 5–60 mm long, 1–40 mm above the wave, some lying along it.
        let (x, y): (f64, f64) = (rng.random_range(0.1..0.9), rng.random_range(0.1..0.9));
        let height = 0.03 * (7.0 * x).sin() * (4.0 * y).cos() + rng.random_range(0.001..0.04);
        let a = Point3::new(x, y, height);
        let length = rng.random_range(0.005..0.06);
        let angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let b = a + Vector3::new(
            length * angle.cos(),
            length * angle.sin(),
            rng.random_range(-0.01..0.01),
        );
        let before = query_work();
        let one = alone.segment_distance_bound(&a, &b, 0.1);
        let middle = query_work();
        let two = with_more.segment_distance_bound(&a, &b, 0.1);
        let after = query_work();
        assert_eq!(one.map(f64::to_bits), two.map(f64::to_bits), "{a} {b}");
        found += usize::from(one.is_some());
        other_work += usize::from(middle.since(&before) != after.since(&middle));
    }
    assert!(found > queries * 9 / 10, "{found} of {queries} found");
    assert!(
        other_work > queries / 10,
        "the trees must differ for the test to mean anything ({other_work})"
    );
}

/// Segments 20 mm long lying 5–15 mm above the floor of [`wavy`], along it (their ends
/// at the same height over the surface), in random directions, and the reach 30 mm.
fn along_the_floor(rng: &mut ChaCha8Rng) -> (Point3<f64>, Point3<f64>) {
    let surface = |x: f64, y: f64| 0.02 * (6.0 * x).sin() * (5.0 * y).cos();
    let (x, y) = (rng.random_range(-0.3..0.3), rng.random_range(-0.3..0.3));
    let angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
    let (u, v) = (x + 0.02 * angle.cos(), y + 0.02 * angle.sin());
    let above = rng.random_range(0.005..0.015);
    (
        Point3::new(x, y, surface(x, y) + above),
        Point3::new(u, v, surface(u, v) + above),
    )
}

#[test]
fn the_bound_costs_little_more_on_a_ten_times_denser_floor() {
    // The wavy floor at 2 · 300² and 2 · 950² triangles (180k and 1.8M): the exact
    // search descends to every box nearer than the nearest triangle (a strip under a
    // segment lying along the floor, which narrows less than its boxes shrink), the
    // bound only to the boxes nearer than the grid point below it.
    let mut counts = Vec::new();
    for n in [300, 950] {
        let mesh = wavy(n);
        let mut rng = ChaCha8Rng::seed_from_u64(17);
        let segments: Vec<_> = (0..300).map(|_| along_the_floor(&mut rng)).collect();
        let before = query_work();
        for (a, b) in &segments {
            assert!(mesh.segment_distance_bound(a, b, 0.03).is_some());
        }
        let middle = query_work();
        for (a, b) in &segments {
            assert!(mesh.segment_proximity(a, b, 0.03).is_some());
        }
        let (bound, exact) = (middle.since(&before), query_work().since(&middle));
        println!("2·{n}² triangles: bound {bound:?}, exact {exact:?}");
        counts.push((bound, exact));
    }
    let total = |w: QueryWork| (w.bvh_nodes + w.box_tests + w.exact_tests) as f64;
    let [(bound_coarse, exact_coarse), (bound_fine, exact_fine)] = [counts[0], counts[1]];
    let grows = |fine: QueryWork, coarse: QueryWork| total(fine) / total(coarse);
    println!(
        "10x the triangles: bound {:.2}x, exact search {:.2}x",
        grows(bound_fine, bound_coarse),
        grows(exact_fine, exact_coarse)
    );
    // The exact closest points stay near the nearest triangle: the exact search's
    // grow with the strip (the contrast that makes the test mean something).
    let exact_tests =
        |fine: QueryWork, coarse: QueryWork| fine.exact_tests as f64 / coarse.exact_tests as f64;
    assert!(exact_tests(bound_fine, bound_coarse) < 1.5);
    assert!(exact_tests(exact_fine, exact_coarse) > 2.5);
    // All of the work: about the tree's depth more (17 → 19 levels) and the queries
    // whose distance lies just above a grid point, where the bound's search is exact.
    assert!(grows(bound_fine, bound_coarse) < 2.2);
    assert!(total(bound_fine) < 0.6 * total(exact_fine));
}
