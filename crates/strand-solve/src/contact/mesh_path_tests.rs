//! [`MeshPath::advance`] with its thresholds against every edge searched within its
//! whole reach: the same multiple bit for bit on random paths over a fine floor and a
//! coarse plate, for less search work.

use std::sync::Arc;

use nalgebra::{Point3, Vector3};
use strand_contact::{ObstacleMesh, QueryWork, query_work};

use super::Contact;
use super::advance::edge_moves;
use super::mesh_path::MeshPath;
use super::proximity_tests::floor;

/// A coarse plate (two triangles) 60 mm above the floor over `x ∈ [0.5, 0.9]` m.
fn plate() -> Arc<ObstacleMesh> {
    let vertices = vec![
        Point3::new(0.5, -0.2, 0.06),
        Point3::new(0.9, -0.2, 0.06),
        Point3::new(0.9, 0.2, 0.06),
        Point3::new(0.5, 0.2, 0.06),
    ];
    Arc::new(ObstacleMesh::try_from_triangles("plate", vertices, &[[0, 1, 2], [0, 2, 3]]).unwrap())
}

/// Uniform numbers in `[0, 1)` from a fixed seed.
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Every rod's centreline (m) and the moves of its vertices (m).
type Path = (Vec<Vec<Point3<f64>>>, Vec<Vec<Vector3<f64>>>);

/// A random two-rod path: each rod a wavy line of 30 edges 1–150 mm above the floor,
/// every vertex moving by up to 80 mm (mostly down), some rods not at all.
fn path(next: &mut impl FnMut() -> f64) -> Path {
    let mut centrelines = Vec::new();
    let mut deltas = Vec::new();
    for _ in 0..2 {
        let (x0, y0) = (next() * 0.6, next() * 0.6 - 0.3);
        let height = 0.001 + next() * 0.15;
        let heading = next() * std::f64::consts::TAU;
        let still = next() < 0.1;
        let mut line = Vec::new();
        let mut moves = Vec::new();
        for k in 0..=30 {
            let s = k as f64 * 0.02;
            let (x, y) = (x0 + s * heading.cos(), y0 + s * heading.sin());
            let z = super::proximity_tests::floor_height(x, y) + height + 0.01 * (7.0 * s).sin();
            line.push(Point3::new(x, y, z));
            let scale = if still { 0.0 } else { 0.08 * next() };
            moves.push(Vector3::new(next() - 0.5, next() - 0.5, -next()) * scale);
        }
        centrelines.push(line);
        deltas.push(moves);
    }
    (centrelines, deltas)
}

#[test]
fn thresholds_give_the_same_advancement_as_exact_bounds_for_less_work() {
    let contact = Contact::new(vec![floor(300), plate()], 0.02);
    let mut next = uniform(0x5eed_1234_abcd_0077);
    let total = |w: QueryWork| w.bvh_nodes + w.box_tests + w.exact_tests;
    let (mut with_thresholds, mut exact_only) = (0, 0);
    let mut limited = 0;
    for case in 0..150 {
        let (centrelines, deltas) = path(&mut next);
        let moves = edge_moves(&deltas);
        let radii = vec![0.01, 0.004];
        let before = query_work();
        let t = MeshPath::new(&contact, &centrelines, &deltas, &moves, radii.clone()).advance();
        let middle = query_work();
        let mut reference = MeshPath::new(&contact, &centrelines, &deltas, &moves, radii);
        reference.exact_only = true;
        let t_exact = reference.advance();
        with_thresholds += total(middle.since(&before));
        exact_only += total(query_work().since(&middle));
        assert_eq!(
            t.to_bits(),
            t_exact.to_bits(),
            "case {case}: {t} vs {t_exact}"
        );
        if t < 1.0 {
            limited += 1;
        }
    }
    println!("{limited} of 150 steps limited; work {with_thresholds} vs {exact_only}");
    // The comparison means something: many steps are cut short by the meshes.
    assert!(limited >= 30, "{limited}");
    assert!(
        (with_thresholds as f64) < 0.6 * exact_only as f64,
        "{with_thresholds} vs {exact_only}"
    );
}

#[test]
fn a_bound_found_within_a_threshold_is_exact_and_one_not_found_is_below_it() {
    let contact = Contact::new(vec![floor(200), plate()], 0.02);
    let mut next = uniform(0x0bad_cafe_1234_5678);
    let (mut lower, mut exact) = (0, 0);
    for _ in 0..60 {
        let (centrelines, deltas) = path(&mut next);
        let moves = edge_moves(&deltas);
        let mut path = MeshPath::new(&contact, &centrelines, &deltas, &moves, vec![0.01, 0.004]);
        let t = 2.0 * next();
        let threshold = 0.002 + 0.05 * next();
        let mut sample = path.sample(t, |_, _| threshold);
        let first = sample.bounds.clone();
        for (rod, edges) in first.iter().enumerate() {
            for (edge, bound) in edges.iter().enumerate() {
                path.refine(&mut sample, rod, edge);
                let refined = sample.bounds[rod][edge];
                assert!(refined.exact);
                if bound.exact {
                    exact += 1;
                    assert_eq!(bound.value.to_bits(), refined.value.to_bits());
                } else {
                    lower += 1;
                    assert!(bound.value <= refined.value, "{bound:?} above {refined:?}");
                    assert!(bound.value <= threshold);
                }
            }
        }
    }
    assert!(lower > 100 && exact > 100, "{lower} lower, {exact} exact");
}

#[test]
fn kept_lists_rule_out_meshes_without_changing_the_advancement() {
    let margin = 0.02;
    let mut next = uniform(0x7e57_1157_0bd5_2026);
    let total = |w: QueryWork| w.bvh_nodes + w.box_tests + w.exact_tests;
    let (mut with_lists, mut without_lists) = (0, 0);
    for case in 0..80 {
        let (centrelines, deltas) = path(&mut next);
        let moves = edge_moves(&deltas);
        let radii = vec![0.01, 0.004];
        // The rows' lists, searched where each edge was up to half the slack ago.
        let listed = Contact::new(vec![floor(300), plate()], margin);
        let slack = 0.5 * margin;
        {
            let mut candidates = listed.kept.begin(slack);
            for (rod, line) in centrelines.iter().enumerate() {
                let shift = Vector3::new(next() - 0.5, next() - 0.5, next() - 0.5) * slack;
                for (index, mesh) in listed.meshes.iter().enumerate() {
                    let mut lists = candidates.of(rod, index, line.len());
                    for (edge, ab) in line.windows(2).enumerate() {
                        let (a, b) = (ab[0] + shift, ab[1] + shift);
                        lists.near(true, edge, mesh, &a, &b, radii[rod] + margin);
                    }
                }
            }
        }
        let bare = Contact::new(vec![floor(300), plate()], margin);
        let before = query_work();
        let t = MeshPath::new(&listed, &centrelines, &deltas, &moves, radii.clone()).advance();
        let middle = query_work();
        let t_bare = MeshPath::new(&bare, &centrelines, &deltas, &moves, radii.clone()).advance();
        with_lists += total(middle.since(&before));
        without_lists += total(query_work().since(&middle));
        let mut reference = MeshPath::new(&listed, &centrelines, &deltas, &moves, radii);
        reference.exact_only = true;
        let t_exact = reference.advance();
        assert_eq!(
            t.to_bits(),
            t_exact.to_bits(),
            "case {case}: {t} vs {t_exact}"
        );
        assert_eq!(
            t.to_bits(),
            t_bare.to_bits(),
            "case {case}: {t} vs {t_bare}"
        );
    }
    println!("work with kept lists {with_lists}, without {without_lists}");
    // The lists rule meshes out: the advancement searches less.
    assert!(
        (with_lists as f64) < 0.95 * without_lists as f64,
        "{with_lists} vs {without_lists}"
    );
}
