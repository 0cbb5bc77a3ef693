//! [`super::node_frames`] against independent references: every node's oriented box
//! holds the vertices of the node's triangles (found by walking the tree), its distance
//! is a lower bound of the exact distance to each of them, and a search on a finely
//! faceted drum looks at far fewer nodes than its axis-aligned boxes alone would let it.

use nalgebra::{Point3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::flat_bvh::LEAF;
use super::near_scan_tests::{corner, fine_drum, wavy};
use super::work::query_work;
use crate::{ObstacleMesh, closest_segment_triangle};

/// The triangles under node `node`, by walking its subtree.
fn subtree_triangles(mesh: &ObstacleMesh, node: usize) -> Vec<u32> {
    let links = &mesh.tree.bvh.links;
    let mut pending = vec![node];
    let mut out = Vec::new();
    while let Some(n) = pending.pop() {
        let link = links[n];
        if link & LEAF != 0 {
            out.extend_from_slice(mesh.tree.cluster(link & !LEAF));
        } else {
            pending.extend([n + 1, link as usize]);
        }
    }
    out
}

#[test]
fn every_oriented_box_holds_its_triangles_and_bounds_their_distance() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for (mesh, centre, spread) in [
        (wavy(40), Point3::new(0.0, 0.0, 0.0), 0.5),
        (corner(), Point3::new(0.15, 0.15, 0.15), 0.2),
        (fine_drum(2000), Point3::new(0.0, 0.0, 0.0), 0.08),
    ] {
        let nodes = mesh.tree.bvh.links.len();
        let mut with_box = 0;
        for node in 0..nodes {
            let frame = *mesh.node_frame(node);
            let triangles = subtree_triangles(&mesh, node);
            let corners: Vec<[Point3<f64>; 3]> = triangles
                .iter()
                .map(|&t| mesh.triangle(t as usize))
                .collect();
            // Every vertex inside (distance zero up to the change of frame's rounding).
            for p in corners.iter().flatten() {
                assert!(
                    frame.distance(p, p) <= 1e-15,
                    "node {node}: vertex {p} outside"
                );
            }
            if frame.distance(
                &Point3::new(10.0, 10.0, 10.0),
                &Point3::new(10.0, 10.0, 10.0),
            ) > 0.0
            {
                with_box += 1;
            }
            // A lower bound of the exact distance of segments and points near the node.
            for _ in 0..3 {
                let offset = |rng: &mut ChaCha8Rng| {
                    Vector3::from_fn(|_, _| rng.random_range(-spread..spread))
                };
                let a = centre + offset(&mut rng);
                let b = if rng.random_bool(0.5) {
                    a
                } else {
                    a + 0.3 * offset(&mut rng)
                };
                let exact = corners
                    .iter()
                    .map(|[p, q, r]| closest_segment_triangle(&a, &b, p, q, r).distance)
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    frame.distance(&a, &b) <= exact + 1e-15,
                    "node {node}: {} > {exact}",
                    frame.distance(&a, &b)
                );
            }
        }
        // The wavy surface and the drum have boxes (their slopes make the axis-aligned
        // ones loose); the corner's faces are axis-aligned and keep none.
        println!(
            "{}: {with_box} of {nodes} nodes with an oriented box",
            mesh.name()
        );
        if mesh.name() == "corner" {
            assert_eq!(with_box, 0);
        } else {
            assert!(with_box > nodes / 4, "{with_box} of {nodes}");
        }
    }
}

/// BVH nodes visited by the local contacts of a point touching a drum of `facets`
/// faces on its slope (60° from its top), 5 mm from it, within 15 mm: by a later
/// evaluation of its kept candidates after a move of 10 µm along the drum (the
/// oriented boxes prune its search) and by a full search (axis-aligned boxes only).
fn nodes_on_the_drum(facets: usize) -> (u64, u64) {
    let mesh = fine_drum(facets);
    let at = |angle: f64| 0.055 * Point3::new(angle.cos(), 0.0, angle.sin());
    let (p, q) = (at(0.5), at(0.5 + 10e-6 / 0.05));
    let kept = mesh.keep_triangles_near(&p, &p, 0.015, 0.005);
    let before = query_work();
    let found = mesh.local_contacts_kept(&q, &q, 0.015, &kept, kept.moved_by(&q, &q));
    let later = query_work().since(&before).bvh_nodes;
    let before = query_work();
    assert_eq!(found, mesh.local_contacts(&q, &q, 0.015));
    assert_eq!(found.len(), 1);
    (later, query_work().since(&before).bvh_nodes)
}

#[test]
fn a_search_on_a_finely_faceted_drum_visits_about_as_many_nodes_at_ten_times_the_facets() {
    // The point's sphere of 5.000 mm reaches the faces within about 2 µm of its
    // nearest one: a handful at any density. Its axis-aligned boxes on the slope stick
    // out by about their size times the slope, so a search by them alone enters the
    // nodes beside the contact at every level (the full search, the contrast), while the
    // oriented boxes leave the nodes near the contact.
    let ((coarse, coarse_full), (fine, fine_full)) =
        (nodes_on_the_drum(9_450), nodes_on_the_drum(94_500));
    println!(
        "nodes visited: {coarse} at 9,450 facets, {fine} at 94,500 (full searches by \
         axis-aligned boxes {coarse_full}, {fine_full})"
    );
    assert!(fine_full > 4 * coarse_full, "{coarse_full} -> {fine_full}");
    assert!(fine <= 2 * coarse, "{coarse} -> {fine}");
    assert!(10 * fine < fine_full, "{fine} vs {fine_full}");
}
