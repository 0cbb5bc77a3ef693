//! The patch-pruned search of a full search against independent references: every
//! node's patch against the patches of the triangles below it, the nearest triangle of
//! every patch against a scan of every triangle in cluster order (bit for bit, ties to
//! the first), and its work against the kept list it serves.

use nalgebra::Point3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::flat_bvh::LEAF;
use super::flat_bvh_query_tests::{meshes, query};
use super::near_scan::near_guard;
use super::near_scan_tests::{corner, wavy};
use super::patch_search::MIXED;
use super::segment_proximity::SegmentBound;
use super::work::query_work;
use crate::ObstacleMesh;
use crate::closest::segment_triangle_candidate;

fn all_meshes() -> Vec<ObstacleMesh> {
    let mut all = meshes();
    all.push(corner());
    all.push(wavy(20));
    all
}

/// The patches of the triangles below `node`, sorted, without repeats.
fn patches_below(mesh: &ObstacleMesh, node: usize) -> Vec<u32> {
    let link = mesh.tree.bvh.links[node];
    let mut patches: Vec<u32> = if link & LEAF != 0 {
        mesh.tree
            .cluster(link & !LEAF)
            .iter()
            .map(|&t| mesh.patch[t as usize])
            .collect()
    } else {
        let mut both = patches_below(mesh, node + 1);
        both.extend(patches_below(mesh, link as usize));
        both
    };
    patches.sort_unstable();
    patches.dedup();
    patches
}

#[test]
fn every_node_names_the_one_patch_of_its_triangles() {
    let (mut single, mut mixed) = (0, 0);
    for mesh in all_meshes() {
        let named = mesh.node_patches().to_vec();
        assert_eq!(named.len(), mesh.tree.bvh.links.len());
        for (node, &patch) in named.iter().enumerate() {
            match patches_below(&mesh, node).as_slice() {
                [only] => {
                    assert_eq!(patch, *only, "node {node}");
                    single += 1;
                }
                _ => {
                    assert_eq!(patch, MIXED, "node {node}");
                    mixed += 1;
                }
            }
        }
    }
    assert!(
        single > 100 && mixed > 100,
        "{single} single, {mixed} mixed"
    );
}

#[test]
fn the_nearest_of_every_patch_is_that_of_a_scan_of_every_triangle() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let (mut found, mut several) = (0, 0);
    for mesh in all_meshes() {
        let clusters = mesh.tree.bvh.links.len().div_ceil(2);
        for _ in 0..600 {
            let (a, b, reach) = query(&mut rng, &mesh);
            let radius = reach * rng.random_range(0.5..2.0);
            let bound = SegmentBound::new(&a, &b, &mesh.bounding_box);
            let guard = near_guard(mesh.tie_tolerance(&a, &b), radius);
            // Scan: every triangle in cluster order; per patch the least exact distance
            // within reach, the first at it.
            let mut scan: Vec<(u32, u32, f64)> = Vec::new();
            for cluster in 0..clusters as u32 {
                for &t in mesh.tree.cluster(cluster) {
                    let corners = mesh.local_triangle(t as usize);
                    if bound.triangle_distance(&corners, radius) > radius {
                        continue;
                    }
                    let [p, q, r] = corners;
                    let squared = segment_triangle_candidate(&a, &b, &p, &q, &r).squared;
                    if squared > radius * radius {
                        continue;
                    }
                    let (patch, d) = (mesh.patch[t as usize], squared.sqrt());
                    match scan.iter_mut().find(|s| s.0 == patch) {
                        Some(s) if d < s.2 => *s = (patch, t, d),
                        Some(_) => {}
                        None => scan.push((patch, t, d)),
                    }
                }
            }
            let searched = mesh.patch_nearest(&bound, &a, &b, radius, guard);
            let mut expected: Vec<(u32, u64)> = scan.iter().map(|s| (s.1, s.2.to_bits())).collect();
            let mut got: Vec<(u32, u64)> = searched
                .iter()
                .map(|k| (k.triangle, k.distance.to_bits()))
                .collect();
            expected.sort_unstable();
            got.sort_unstable();
            assert_eq!(got, expected, "{a} {b} within {radius}");
            found += usize::from(!got.is_empty());
            several += usize::from(got.len() > 1);
        }
    }
    assert!(
        found > 1000 && several > 100,
        "{found} found, {several} with several patches"
    );
}

#[test]
fn a_full_search_visits_about_the_kept_triangles_not_everything_within_reach() {
    // A point 15 mm above a fine wavy floor, reach 40 mm, slack 2 mm: the triangles
    // within reach form a disc of radius about 39 mm, the kept ones (within the
    // nearest distance plus twice the slack) one of about 12 mm, eleven times fewer.
    // The search box-tests the kept disc and the way to the nearest triangle.
    let mesh = wavy(400);
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let (mut kept, mut within_reach, mut search_boxes) = (0, 0, 0);
    for _ in 0..50 {
        let (x, y): (f64, f64) = (rng.random_range(-0.3..0.3), rng.random_range(-0.3..0.3));
        let p = Point3::new(x, y, 0.02 * (6.0 * x).sin() * (5.0 * y).cos() + 0.015);
        let before = query_work();
        kept += mesh.triangles_near(&p, &p, 0.04, 0.002).len();
        search_boxes += query_work().since(&before).box_tests as usize;
        within_reach += mesh
            .reachable(&SegmentBound::new(&p, &p, &mesh.bounding_box), 0.042, None)
            .len();
    }
    println!("{kept} kept, {within_reach} within reach, {search_boxes} box tests");
    assert!(
        within_reach > 8 * kept,
        "{within_reach} within reach, {kept} kept"
    );
    assert!(
        search_boxes < 3 * kept,
        "{search_boxes} box tests for {kept} kept triangles"
    );
}
