//! [`super::KeptTriangles`] against independent references: the contacts of a full
//! search ([`crate::ObstacleMesh::local_contacts`]) for segments moved within the slack, those
//! of the whole kept list for points of them, and the box tests of a later query at
//! two densities.

use nalgebra::{Isometry3, Point3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::near_scan_tests::{corner, fine_drum, moved, segment, wavy};
use super::work::query_work;

#[test]
fn the_part_that_can_matter_gives_the_contacts_of_a_full_search() {
    // Kept lists listed whatever their length, and never listed (the BVH searched near
    // the contacts at each later evaluation).
    for max_listed in [usize::MAX, 0] {
        the_part_that_can_matter_with(max_listed);
    }
}

fn the_part_that_can_matter_with(max_listed: usize) {
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
            let kept = mesh.keep_triangles_listing(&a, &b, reach, slack, max_listed);
            let whole_list = mesh.triangles_near(&a, &b, reach, slack);
            let listed = kept.all();
            assert!(listed.is_none_or(|listed| listed == whole_list));
            assert_eq!(listed.is_some(), whole_list.len() <= max_listed);
            for step in [0.1 * slack, slack] {
                let (p, q) = (moved(&mut rng, &a, step), moved(&mut rng, &b, step));
                let q = if a == b { p } else { q };
                assert!(kept.covers(&p, &q, reach));
                let by = kept.moved_by(&p, &q);
                let full = mesh.local_contacts(&p, &q, reach);
                let before = query_work();
                let part = mesh.local_contacts_kept(&p, &q, reach, &kept, by);
                let middle = query_work();
                let among = mesh.local_contacts_among(&p, &q, reach, &whole_list);
                part_boxes += middle.since(&before).box_tests;
                all_boxes += query_work().since(&middle).box_tests;
                assert_eq!(part, full, "segment {p} {q} moved from {a} {b}");
                assert_eq!(among, full);
                // A point of the moved segment (as an edge's nearest point), with the
                // segment's move and a shorter reach: as the whole kept list.
                let point = p + (q - p) * 0.3;
                let near = mesh.local_contacts_kept(&point, &point, 0.5 * reach, &kept, by);
                let whole = mesh.local_contacts_among(&point, &point, 0.5 * reach, &whole_list);
                assert_eq!(near, whole);
            }
        }
    }
    // The part left out something (else the test would not test the pruning): half
    // of the whole lists' box tests for a listed part; fewer, with the BVH's nodes on
    // the way, for the triangles near the contacts of an unlisted one.
    let part_work = if max_listed == 0 {
        part_boxes
    } else {
        2 * part_boxes
    };
    assert!(
        part_work < all_boxes,
        "listing at most {max_listed}: {part_boxes} box tests vs {all_boxes}"
    );
}

/// The work of 50 points 15 mm above the wavy surface of `2 n²` triangles, kept with
/// 2 mm of slack and moved 0.3 mm: the box tests and BVH nodes of
/// [`crate::ObstacleMesh::local_contacts_kept`] after the move, the length of the whole
/// kept lists, and the box tests and nodes of keeping them.
struct LaterWork {
    later: u64,
    whole_lists: u64,
    keeping: u64,
}

fn later_work(n: usize, max_listed: usize) -> LaterWork {
    let mesh = wavy(n);
    let mut rng = ChaCha8Rng::seed_from_u64(22);
    let mut work = LaterWork {
        later: 0,
        whole_lists: 0,
        keeping: 0,
    };
    let boxes_and_nodes = |w: crate::QueryWork| w.box_tests + w.bvh_nodes;
    for _ in 0..50 {
        let [p, _] = segment(&mut rng, Point3::new(0.0, 0.0, 0.0), 0.3);
        let z = 0.02 * (6.0 * p.x).sin() * (5.0 * p.y).cos() + 0.015;
        let p = Point3::new(p.x, p.y, z);
        let before = query_work();
        let kept = mesh.keep_triangles_listing(&p, &p, 0.04, 0.002, max_listed);
        work.keeping += boxes_and_nodes(query_work().since(&before));
        let q = moved(&mut rng, &p, 3e-4);
        let by = kept.moved_by(&q, &q);
        let before = query_work();
        let found = mesh.local_contacts_kept(&q, &q, 0.04, &kept, by);
        work.later += boxes_and_nodes(query_work().since(&before));
        assert_eq!(found, mesh.local_contacts(&q, &q, 0.04));
        assert_eq!(found.len(), 1);
        work.whole_lists += mesh.triangles_near(&p, &p, 0.04, 0.002).len() as u64;
    }
    work
}

#[test]
fn box_tests_of_a_later_query_grow_far_less_than_the_triangles() {
    // 2 · 40² and 2 · 400² triangles (100×). The whole kept list is a disc of the
    // triangles whose boxes lie within the nearest distance `d` plus twice the slack
    // (radius about `√(4 d σ)`); the part looked at after a move `δ` one of radius about
    // `√(2 d δ)` around the nearest point (at least the triangles there).
    use super::kept_triangles::MAX_LISTED;
    let mut measured = Vec::new();
    for max_listed in [usize::MAX, MAX_LISTED, 0] {
        let (coarse, fine) = (later_work(40, max_listed), later_work(400, max_listed));
        println!(
            "listing at most {max_listed}: box tests and nodes later {} -> {}, keeping {} -> {}; \
             whole kept lists {} -> {}",
            coarse.later,
            fine.later,
            coarse.keeping,
            fine.keeping,
            coarse.whole_lists,
            fine.whole_lists
        );
        assert!(fine.whole_lists > 10 * coarse.whole_lists);
        measured.push((coarse, fine));
    }
    let [
        (listed, listed_fine),
        (default, default_fine),
        (unlisted, unlisted_fine),
    ] = measured.try_into().ok().expect("three settings");
    // Listed whole: a later query looks at the part (about 2.4× for 100×), but keeping
    // lists the disc (about 4×, the disc's box tests under the BVH's nodes).
    assert!(listed_fine.later <= 6 * listed.later);
    assert!(5 * listed_fine.later < listed_fine.whole_lists);
    assert!(
        listed_fine.keeping > 3 * listed.keeping,
        "the disc is listed"
    );
    // Never listed: keeping and later queries both grow far less than the triangles
    // (about 2× for 100×): the BVH's nodes above the contact and the triangles near it.
    assert!(unlisted_fine.keeping <= 3 * unlisted.keeping);
    assert!(unlisted_fine.later <= 3 * unlisted.later);
    // The default lists the coarse surface's short discs and not the fine one's: its
    // whole work grows like the unlisted one's, from the listed coarse cost.
    let total = |w: &LaterWork| w.keeping + w.later;
    assert!(total(&default) <= total(&unlisted));
    assert!(total(&default_fine) <= 4 * total(&default));
    assert!(total(&default_fine) < total(&listed_fine));
}

/// A feature walking within its slack, its kept patches following its contacts
/// ([`super::KeptTriangles::follow`]): at every step the contacts of a full search, whatever
/// triangle of its patch each kept patch holds by then (the nearest at the search, at
/// the previous step, or at a point of the segment).
#[test]
fn following_the_contacts_keeps_the_answers_of_a_full_search() {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let (reach, slack) = (0.04, 0.01);
    for max_listed in [usize::MAX, 0] {
        for mesh in [wavy(80), corner()] {
            for _ in 0..60 {
                let [a, b] = segment(&mut rng, Point3::new(0.05, 0.05, 0.04), 0.06);
                let mut kept = mesh.keep_triangles_listing(&a, &b, reach, slack, max_listed);
                let (mut p, mut q) = (a, b);
                for step in 0..8 {
                    // Each step stays within the slack of the search.
                    let (p1, q1) = (
                        moved(&mut rng, &p, 0.3 * slack),
                        moved(&mut rng, &q, 0.3 * slack),
                    );
                    if (p1 - a).norm() > slack || (q1 - b).norm() > slack {
                        continue;
                    }
                    (p, q) = (p1, if a == b { p1 } else { q1 });
                    let by = kept.moved_by(&p, &q);
                    let found = mesh.local_contacts_kept(&p, &q, reach, &kept, by);
                    assert_eq!(found, mesh.local_contacts(&p, &q, reach), "step {step}");
                    // Follow the segment's contacts, or a point's (as an edge's points).
                    if step % 3 == 2 {
                        let point = p + (q - p) * 0.7;
                        let at = mesh.local_contacts_kept(&point, &point, reach, &kept, by);
                        assert_eq!(at, mesh.local_contacts(&point, &point, reach));
                        kept.follow(&mesh, &at);
                    } else {
                        kept.follow(&mesh, &found);
                    }
                }
            }
        }
    }
}

/// The box tests and BVH nodes of a point sliding over a finely faceted drum (94,500
/// facets of 3.3 µm, the hose-over-drum case of issue 11) in steps of 20 µm within
/// its slack, its kept patches following its contacts or not.
fn sliding_work(follow: bool) -> u64 {
    let (radius, mesh) = (0.05, fine_drum(94_500));
    let (reach, slack) = (0.015, 0.005);
    let mut work = 0;
    // On the drum's slope (60° from its top), touching (5 mm from it), sliding along.
    let at = |angle: f64| (radius + 0.005) * Point3::new(angle.cos(), 0.0, angle.sin());
    let start = at(0.5);
    let mut kept = mesh.keep_triangles_near(&start, &start, reach, slack);
    for k in 1..=100 {
        let p = at(0.5 + 20e-6 * k as f64 / radius);
        let before = query_work();
        let found = mesh.local_contacts_kept(&p, &p, reach, &kept, kept.moved_by(&p, &p));
        let w = query_work().since(&before);
        work += w.box_tests + w.bvh_nodes;
        assert_eq!(found, mesh.local_contacts(&p, &p, reach));
        if follow {
            kept.follow(&mesh, &found);
        }
    }
    work
}

#[test]
fn a_point_sliding_over_a_fine_drum_looks_near_its_contact_when_its_patches_follow() {
    let (fixed, following) = (sliding_work(false), sliding_work(true));
    println!("box tests and nodes: {fixed} from the search's triangles, {following} following");
    assert!(4 * following < fixed, "{following} vs {fixed}");
}
