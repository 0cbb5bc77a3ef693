//! [`super::KeptTriangles`] against independent references: the contacts of a full
//! search ([`crate::ObstacleMesh::local_contacts`]) for segments moved within the slack, those
//! of the whole kept list for points of them, and the box tests of a later query at
//! two densities.

use nalgebra::{Isometry3, Point3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::near_scan_tests::{corner, moved, segment, wavy};
use super::work::query_work;

#[test]
fn the_part_that_can_matter_gives_the_contacts_of_a_full_search() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let (reach, slack) = (0.04, 0.01);
    let placed = wavy(60).placed(&Isometry3::new(
        Vector3::new(0.1, -0.05, 0.02),
        Vector3::new(0.1, 0.2, -0.3),
    ));
    let (mut part_boxes, mut all_boxes) = (0, 0);
    for mesh in [wavy(80), corner(), placed] {
        for _ in 0..200 {
            let [a, b] = segment(&mut rng, Point3::new(0.05, 0.05, 0.04), 0.06);
            let kept = mesh.keep_triangles_near(&a, &b, reach, slack);
            assert_eq!(kept.all(), mesh.triangles_near(&a, &b, reach, slack));
            for step in [0.1 * slack, slack] {
                let (p, q) = (moved(&mut rng, &a, step), moved(&mut rng, &b, step));
                let q = if a == b { p } else { q };
                assert!(kept.covers(&p, &q, reach));
                let by = kept.moved_by(&p, &q);
                let full = mesh.local_contacts(&p, &q, reach);
                let before = query_work();
                let part = mesh.local_contacts_kept(&p, &q, reach, &kept, by);
                let middle = query_work();
                let among = mesh.local_contacts_among(&p, &q, reach, kept.all());
                part_boxes += middle.since(&before).box_tests;
                all_boxes += query_work().since(&middle).box_tests;
                assert_eq!(part, full, "segment {p} {q} moved from {a} {b}");
                assert_eq!(among, full);
                // A point of the moved segment (as an edge's nearest point), with the
                // segment's move and a shorter reach: as the whole kept list.
                let point = p + (q - p) * 0.3;
                let near = mesh.local_contacts_kept(&point, &point, 0.5 * reach, &kept, by);
                let whole = mesh.local_contacts_among(&point, &point, 0.5 * reach, kept.all());
                assert_eq!(near, whole);
            }
        }
    }
    // The part left out something (else the test would not test the pruning).
    assert!(
        2 * part_boxes < all_boxes,
        "{part_boxes} box tests vs {all_boxes}"
    );
}

/// The box tests of [`crate::ObstacleMesh::local_contacts_kept`] for 50 points 15 mm above the
/// wavy surface of `2 n²` triangles, kept with 2 mm of slack and moved 0.3 mm, and
/// those of the whole kept lists.
fn later_box_tests(n: usize) -> (u64, u64) {
    let mesh = wavy(n);
    let mut rng = ChaCha8Rng::seed_from_u64(22);
    let (mut part, mut all) = (0, 0);
    for _ in 0..50 {
        let [p, _] = segment(&mut rng, Point3::new(0.0, 0.0, 0.0), 0.3);
        let z = 0.02 * (6.0 * p.x).sin() * (5.0 * p.y).cos() + 0.015;
        let p = Point3::new(p.x, p.y, z);
        let kept = mesh.keep_triangles_near(&p, &p, 0.04, 0.002);
        let q = moved(&mut rng, &p, 3e-4);
        let by = kept.moved_by(&q, &q);
        let before = query_work();
        let found = mesh.local_contacts_kept(&q, &q, 0.04, &kept, by);
        part += query_work().since(&before).box_tests;
        assert_eq!(found, mesh.local_contacts(&q, &q, 0.04));
        assert_eq!(found.len(), 1);
        all += kept.all().len() as u64;
    }
    (part, all)
}

#[test]
fn box_tests_of_a_later_query_grow_far_less_than_the_triangles() {
    // 2 · 40² and 2 · 400² triangles (100×). The whole kept list is a disc of the
    // triangles whose boxes lie within the nearest distance `d` plus twice the slack
    // (radius about `√(4 d σ)`); the part looked at after a move `δ` one of radius about
    // `√(2 d δ)` around the nearest point (at least the triangles there).
    let (coarse, coarse_all) = later_box_tests(40);
    let (fine, fine_all) = later_box_tests(400);
    println!("box tests {coarse} -> {fine}; whole kept lists {coarse_all} -> {fine_all}");
    assert!(fine_all > 10 * coarse_all, "{coarse_all} -> {fine_all}");
    assert!(fine <= 6 * coarse, "box tests {coarse} -> {fine}");
    assert!(5 * fine < fine_all, "box tests {fine} of {fine_all} kept");
}
