//! Incremental proximity of [`Contact`]: the rows equal those of a full search at
//! every evaluation, a feature moved beyond its slack is searched again, and the work
//! of a later evaluation (no new search, exact closest points only near the contact)
//! grows far less than the mesh density.

use std::sync::Arc;

use nalgebra::{Point3, Vector3};
use strand_contact::{ObstacleMesh, query_work};
use strand_system::{Model, SystemState, initial_state};

use super::proximity_cache::SEARCHES;
use super::{Contact, ProximitySettings};
use crate::constraints::{Constraints, Row};

/// Edges of the rod.
const SEGMENTS: usize = 10;

/// The floor's height at `(x, y)`, m: gentle waves (one smooth patch).
pub(super) fn floor_height(x: f64, y: f64) -> f64 {
    0.005 * (4.0 * x).sin() * (3.0 * y).cos()
}

/// The wavy floor `x ∈ [−0.2, 1.2]`, `y ∈ [−0.5, 0.5]` m in `2 n²` triangles.
pub(super) fn floor(n: usize) -> Arc<ObstacleMesh> {
    let mut vertices = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let x = -0.2 + 1.4 * i as f64 / n as f64;
            let y = -0.5 + j as f64 / n as f64;
            vertices.push(Point3::new(x, y, floor_height(x, y)));
        }
    }
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    Arc::new(ObstacleMesh::try_from_triangles("floor", vertices, &triangles).unwrap())
}

/// A straight 1 m rod of radius 10 mm along x, 15 mm above z = 0, clamped at both ends,
/// over the floor of `2 n²` triangles (20 mm margin).
fn scene(n: usize) -> (Model, Contact, SystemState) {
    let model = super::tests::straight_rod(SEGMENTS, 0.015);
    let state = initial_state(model.system());
    (model, Contact::new(vec![floor(n)], 0.02), state)
}

/// `state` with interior vertex `j` moved by `by` (m).
fn shifted(state: &SystemState, j: usize, by: Vector3<f64>) -> SystemState {
    let mut out = state.clone();
    let p = out.rods[0].positions[j] + by;
    out.rods[0].set_position(j, p);
    out
}

fn rows(contact: &Contact, model: &Model, state: &SystemState) -> Vec<Row> {
    let mut out = Vec::new();
    contact.rows(model, state, &mut out).unwrap();
    out
}

fn searches() -> usize {
    SEARCHES.with(|c| c.get())
}

#[test]
fn rows_equal_a_full_search_and_a_feature_moved_beyond_its_slack_is_searched_again() {
    let (model, contact, state) = scene(60);
    let full = contact
        .clone()
        .with_proximity(ProximitySettings::full_queries());
    // The default slack: 0.5 margins = 10 mm.
    assert_eq!(contact.proximity().slack_margins, 0.5);
    let first = searches();
    assert_eq!(rows(&contact, &model, &state), rows(&full, &model, &state));
    let searched = searches() - first;
    assert!(searched >= 2 * SEGMENTS - 1, "{searched} searches");
    // Vertex 5 moved 1 mm (within the slack): nothing is searched again.
    let near = shifted(&state, 5, Vector3::new(1e-3, 0.0, -0.5e-3));
    let before = searches();
    assert_eq!(rows(&contact, &model, &near), rows(&full, &model, &near));
    assert_eq!(
        searches(),
        before,
        "a feature within its slack was searched"
    );
    // Vertex 5 moved 150 mm sideways, beyond the slack, onto a spot its kept
    // triangles do not reach: it and its two edges are searched again and the rows
    // still equal those of a full search (a cache that kept the stale list would miss
    // the floor under the new spot).
    let far = shifted(&state, 5, Vector3::new(0.0, 0.15, 0.0));
    let before = searches();
    let moved = rows(&contact, &model, &far);
    assert_eq!(searches() - before, 3, "vertex 5 and edges 4, 5");
    assert_eq!(moved, rows(&full, &model, &far));
    assert!(moved.len() >= SEGMENTS - 1);
}

#[test]
fn a_later_evaluation_searches_again_nothing_and_its_work_does_not_grow_with_density() {
    // The same floor at 2 · 30² and 2 · 300² triangles (100×).
    let mut work = Vec::new();
    for n in [30, 300] {
        let (model, contact, state) = scene(n);
        rows(&contact, &model, &state);
        // A Newton iterate later: every vertex 0.5 mm lower.
        let mut later = state.clone();
        for j in 1..SEGMENTS {
            let p = later.rods[0].positions[j] - Vector3::new(0.0, 0.0, 5e-4);
            later.rods[0].set_position(j, p);
        }
        let (before, searched) = (query_work(), searches());
        let found = rows(&contact, &model, &later);
        let done = query_work().since(&before);
        assert_eq!(
            searches(),
            searched,
            "a feature within its slack was searched"
        );
        println!("2·{n}² triangles: {} rows, {done:?}", found.len());
        let full = contact
            .clone()
            .with_proximity(ProximitySettings::full_queries());
        assert_eq!(found, rows(&full, &model, &later));
        assert!(found.len() >= SEGMENTS - 1);
        work.push(done);
    }
    let (coarse, fine) = (work[0], work[1]);
    assert!(
        fine.exact_tests <= 3 * coarse.exact_tests,
        "exact tests {} -> {}",
        coarse.exact_tests,
        fine.exact_tests
    );
    // Each feature looks only at what can matter after its 0.5 mm move: the part of a
    // short kept list, or (on the fine floor, whose kept discs are not listed) the
    // triangles near its contact and the BVH's nodes above them, not the whole disc
    // kept for a 10 mm move. An edge lying along the floor is near a strip of
    // triangles under it, whose count grows as the square root of the density
    // (measured 386 -> 2996 box tests and nodes for 100× the triangles; the whole
    // discs would grow 100×).
    let boxes_and_nodes = |w: &strand_contact::QueryWork| w.box_tests + w.bvh_nodes;
    assert!(
        boxes_and_nodes(&fine) <= 10 * boxes_and_nodes(&coarse),
        "box tests and nodes {coarse:?} -> {fine:?}"
    );
}

/// Rows left out for far features ([`Constraints::rows_leaving_far`]): every row made
/// is one of [`Contact::rows`], and every row left out has each vertex it moves listed
/// far with a clearance no larger than the row's gap (so a step that keeps those
/// vertices within their clearances satisfies it: `iteration/far.rs`), while the far
/// features cost no exact closest points.
#[test]
fn rows_left_out_for_far_features_have_gaps_above_their_vertices_clearances() {
    let (model, contact, state) = scene(60);
    // Vertices 1 to 4 lifted by 12 mm: their gaps to the floor are 12 to 15 mm,
    // within the 20 mm margin (they make rows) and above a quarter of it (far).
    let lifted = (1..=4).fold(state, |s, j| shifted(&s, j, Vector3::new(0.0, 0.0, 12e-3)));
    rows(&contact, &model, &lifted);
    // A Newton iterate later: vertex 2 moved 4 mm towards the floor (within the 10 mm
    // slack: not searched again), its gap now about 9 mm. A bound that left out the
    // move would list it, and its edges, above that.
    let later = shifted(&lifted, 2, Vector3::new(1e-3, 0.0, -4e-3));
    let before = query_work();
    let (mut made, mut far) = (Vec::new(), Vec::new());
    contact
        .rows_leaving_far(&model, &later, &mut made, &mut far)
        .unwrap();
    let lazy = query_work().since(&before);
    let before = query_work();
    let every = rows(&contact, &model, &later);
    let eager = query_work().since(&before);
    assert!(made.iter().all(|row| every.contains(row)));
    let dofs = model.dofs();
    let vertex_of = |unknown: usize| {
        (0..=SEGMENTS)
            .find(|&j| dofs.vertex(0, j) == Some(unknown / 3))
            .expect("a contact row moves rod vertices only")
    };
    let left_out: Vec<&Row> = every.iter().filter(|row| !made.contains(row)).collect();
    assert!(left_out.len() >= 3, "{} rows left out", left_out.len());
    for row in left_out {
        for &(unknown, _) in &row.gradient {
            let j = vertex_of(unknown);
            let listed = far.iter().filter(|v| v.rod == 0 && v.vertex == j);
            let clearance = listed.map(|v| v.clearance_m).fold(f64::INFINITY, f64::min);
            assert!(
                clearance <= row.value,
                "vertex {j}: clearance {clearance} m above a left-out gap {} m",
                row.value
            );
        }
    }
    assert!(
        lazy.exact_tests < eager.exact_tests,
        "far features still tested: {lazy:?} vs {eager:?}"
    );
}

#[test]
fn the_start_check_finds_the_deepest_overlap_searching_no_further_than_touching() {
    // Over the fine floor (20,000 triangles), vertex 5 pressed 6 mm into it: the
    // check names the deepest overlap, the one every gap within the margin gives,
    // and does several times less work than that search (it asks only for overlaps;
    // with the margin it listed every feature near the floor, 18 times an
    // evaluation's work on the cooler hose at 2000 segments).
    let (model, _, state) = scene(100);
    let pressed = shifted(&state, 5, Vector3::new(0.0, 0.0, -0.006));
    let fresh = || Contact::new(vec![floor(100)], 0.02);
    let deepest_mm = -1e3
        * (fresh().gaps(&model, &pressed, 0.02).unwrap().iter())
            .map(|g| g.gap)
            .fold(f64::INFINITY, f64::min);
    assert!(deepest_mm > 2.0, "{deepest_mm} mm");
    let before = query_work();
    let wide = fresh().gaps(&model, &pressed, 0.02).unwrap();
    let wide_work = query_work().since(&before);
    assert!(wide.len() > SEGMENTS);
    let before = query_work();
    let error = fresh().check_start(&model, &pressed).unwrap_err();
    let check_work = query_work().since(&before);
    match error {
        crate::constraints::ConstraintError::StartsOverlapping {
            kind, overlap_mm, ..
        } => {
            assert_eq!(kind, "mesh");
            assert!(
                (overlap_mm - deepest_mm).abs() < 1e-9,
                "{overlap_mm} vs {deepest_mm} mm"
            );
        }
        other => panic!("{other:?}"),
    }
    let (wide, check) = (
        wide_work.box_tests + wide_work.exact_tests,
        check_work.box_tests + check_work.exact_tests,
    );
    assert!(
        2 * check < wide,
        "check {check_work:?}, margin search {wide_work:?}"
    );
}
