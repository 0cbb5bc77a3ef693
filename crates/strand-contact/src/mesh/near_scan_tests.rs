//! The pruned scan of the local contacts and the kept candidates of
//! [`ObstacleMesh::triangles_near`] against independent references: brute-force
//! distances to every triangle, the full search, and counted work at two densities.

use nalgebra::{Point3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::grid_surface_tests::grid_surface;
use super::work::query_work;
use crate::{ObstacleMesh, closest_segment_triangle};

/// A wavy square `x, y ∈ [−0.5, 0.5]` m, `z = 0.02 sin(6x) cos(5y)` m, of `2 n²`
/// triangles (one smooth patch: the slopes stay below 0.15).
pub(super) fn wavy(n: usize) -> ObstacleMesh {
    grid_surface("wavy", n, -0.5, |_, _, x, y| {
        0.02 * (6.0 * x).sin() * (5.0 * y).cos()
    })
}

/// A drum of radius 50 mm along y (`y ∈ [−0.2, 0.2]` m, open ends) of `facets` flat
/// faces, two triangles each: one smooth patch (the hose-over-drum case of issue 11).
pub(super) fn fine_drum(facets: usize) -> ObstacleMesh {
    let radius = 0.05;
    let ring = |i: usize| {
        let angle = std::f64::consts::TAU * i as f64 / facets as f64;
        [-0.2, 0.2].map(|y| Point3::new(radius * angle.cos(), y, radius * angle.sin()))
    };
    let vertices: Vec<Point3<f64>> = (0..facets).flat_map(ring).collect();
    let n = facets as u32;
    let triangles: Vec<[u32; 3]> = (0..n)
        .flat_map(|i| {
            let (a, b) = (2 * i, 2 * ((i + 1) % n));
            [[a, b, b + 1], [a, b + 1, a + 1]]
        })
        .collect();
    ObstacleMesh::try_from_triangles("drum", vertices, &triangles).expect("a valid drum")
}

/// A faceted box corner: many patches (a floor and two walls meeting), for the scan's
/// patch bookkeeping.
pub(super) fn corner() -> ObstacleMesh {
    let vertices = vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(0.3, 0.0, 0.0),
        Point3::new(0.3, 0.3, 0.0),
        Point3::new(0.0, 0.3, 0.0),
        Point3::new(0.0, 0.0, 0.3),
        Point3::new(0.3, 0.0, 0.3),
        Point3::new(0.0, 0.3, 0.3),
    ];
    let triangles = [
        [0, 1, 2],
        [0, 2, 3],
        [0, 1, 5],
        [0, 5, 4],
        [0, 3, 6],
        [0, 6, 4],
    ];
    ObstacleMesh::try_from_triangles("corner", vertices, &triangles).unwrap()
}

/// A random segment (a point half the time) near `centre`, within `spread` (m).
pub(super) fn segment(rng: &mut ChaCha8Rng, centre: Point3<f64>, spread: f64) -> [Point3<f64>; 2] {
    let offset = |rng: &mut ChaCha8Rng| Vector3::from_fn(|_, _| rng.random_range(-spread..spread));
    let a = centre + offset(rng);
    let b = if rng.random_bool(0.5) {
        a
    } else {
        a + 0.5 * offset(rng)
    };
    [a, b]
}

/// A random move of at most `length` (m).
pub(super) fn moved(rng: &mut ChaCha8Rng, p: &Point3<f64>, length: f64) -> Point3<f64> {
    let d = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
    p + d.normalize() * rng.random_range(0.0..length)
}

#[test]
fn the_nearest_local_contact_is_the_brute_force_nearest_triangle() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for mesh in [wavy(60), corner()] {
        for _ in 0..300 {
            let [a, b] = segment(&mut rng, Point3::new(0.05, 0.05, 0.06), 0.08);
            let brute = (0..mesh.triangle_count())
                .map(|t| {
                    let [p, q, r] = mesh.triangle(t);
                    closest_segment_triangle(&a, &b, &p, &q, &r).distance
                })
                .fold(f64::INFINITY, f64::min);
            let contacts = mesh.local_contacts(&a, &b, 0.1);
            if brute > 0.1 {
                assert!(contacts.is_empty());
                continue;
            }
            let nearest = contacts.first().expect("a contact within reach").proximity;
            assert!(
                (nearest.distance - brute).abs() <= 1e-12,
                "{} vs {brute}",
                nearest.distance
            );
        }
    }
}

#[test]
fn kept_candidates_give_the_contacts_of_a_full_search_while_within_the_slack() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let (reach, slack) = (0.04, 0.01);
    for mesh in [wavy(80), corner()] {
        for _ in 0..200 {
            let [a, b] = segment(&mut rng, Point3::new(0.05, 0.05, 0.04), 0.06);
            let kept = mesh.triangles_near(&a, &b, reach, slack);
            for _ in 0..5 {
                let (p, q) = (moved(&mut rng, &a, slack), moved(&mut rng, &b, slack));
                let q = if a == b { p } else { q };
                let full = mesh.local_contacts(&p, &q, reach);
                let among = mesh.local_contacts_among(&p, &q, reach, &kept);
                assert_eq!(among, full, "segment {p} {q} moved from {a} {b}");
            }
        }
    }
}

#[test]
fn a_segment_moved_beyond_the_slack_can_miss_what_the_kept_candidates_lack() {
    // The reference the cache relies on: 10 mm above the floor, then moved 60 mm
    // sideways, beyond the 5 mm slack: the kept list has no triangle under the new
    // spot, so only a new search finds its contact.
    let mesh = wavy(80);
    let above = |x: f64| Point3::new(x, 0.0, 0.02 * (6.0 * x).sin() + 0.01);
    let a = above(-0.3);
    let kept = mesh.triangles_near(&a, &a, 0.04, 0.005);
    assert!(!kept.is_empty());
    let far = above(-0.24);
    let full = mesh.local_contacts(&far, &far, 0.04);
    assert!(!full.is_empty());
    let stale = mesh.local_contacts_among(&far, &far, 0.04, &kept);
    assert_ne!(stale, full, "the kept list should not reach 60 mm away");
    let fresh = mesh.triangles_near(&far, &far, 0.04, 0.005);
    assert_eq!(mesh.local_contacts_among(&far, &far, 0.04, &fresh), full);
}

#[test]
fn exact_tests_per_query_do_not_grow_with_the_mesh_density() {
    // The same surface at 2 · 40² and 2 · 400² triangles (100×): a point 15 mm above
    // it with a 40 mm reach has about 100× more triangles within reach on the fine
    // one; exact closest points are computed only near its nearest point.
    let mut counts = Vec::new();
    for n in [40, 400] {
        let mesh = wavy(n);
        let mut rng = ChaCha8Rng::seed_from_u64(13);
        let before = query_work();
        let mut boxes = 0;
        for _ in 0..50 {
            let p: Point3<f64> = Point3::new(
                rng.random_range(-0.3..0.3),
                rng.random_range(-0.3..0.3),
                0.0,
            );
            let z = 0.02 * (6.0 * p.x).sin() * (5.0 * p.y).cos() + 0.015;
            let p = Point3::new(p.x, p.y, z);
            let kept = mesh.triangles_near(&p, &p, 0.04, 0.002);
            boxes += kept.len();
            assert_eq!(mesh.local_contacts(&p, &p, 0.04).len(), 1);
        }
        let work = query_work().since(&before);
        println!("2·{n}² triangles: {work:?}, {boxes} kept in all");
        counts.push((work, boxes));
    }
    let (coarse, fine) = (counts[0].0, counts[1].0);
    assert!(
        fine.exact_tests <= 3 * coarse.exact_tests,
        "exact tests grow with density: {} -> {}",
        coarse.exact_tests,
        fine.exact_tests
    );
    // The box tests of full searches do grow: `local_contacts` box-tests every
    // triangle within reach, and the kept list of `triangles_near` (a disc of the
    // triangles within the nearest distance plus twice the slack) grows with the
    // density too (since the search finds each patch's nearest triangle first it no
    // longer box-tests all within reach: 15× here for 100× the triangles, was 23×).
    // That is what the kept candidates spare the later evaluations.
    assert!(fine.box_tests > 10 * coarse.box_tests);
}
