//! Unit tests of contact rows: the cost of the self-contact exclusion and the rows of
//! a vertex in a groove.

use std::sync::Arc;

use nalgebra::{Point3, UnitQuaternion, Vector3};
use strand_contact::ObstacleMesh;
use strand_rod::{Rod, Section};
use strand_system::{End, Model, RodSpec, System, initial_state};

use super::Contact;
use super::exclusion::{ARC_LENGTH_VISITS, EXCLUSION_QUERIES};
use crate::constraints::{Constraints, Row};

/// A straight 1 m rod of radius 10 mm in `segments` edges, clamped at both ends.
fn straight_rod(segments: usize, height: f64) -> Model {
    let section = Section::try_explicit(1e5, 5e4, 0.5, 0.4, 2.0, 0.01).unwrap();
    let along_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    Model::try_new(System {
        rods: vec![RodSpec {
            name: "rod".into(),
            rod: Rod::try_straight(section, 1.0, segments).unwrap(),
            start: End::clamped(Vector3::new(0.0, 0.0, height), along_x),
            end: End::clamped(Vector3::new(1.0, 0.0, height), along_x),
            route: None,
        }],
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::zeros(),
    })
    .unwrap()
}

/// (arc-length vertex visits, exclusion queries) of one evaluation of the rows.
fn work(segments: usize) -> (usize, usize) {
    let model = straight_rod(segments, 0.0);
    let contact = Contact::new(vec![], 0.02);
    let state = initial_state(model.system());
    ARC_LENGTH_VISITS.with(|c| c.set(0));
    EXCLUSION_QUERIES.with(|c| c.set(0));
    let mut rows: Vec<Row> = Vec::new();
    contact.rows(&model, &state, &mut rows).unwrap();
    // Pieces more than π r apart along the rod are within the margin, but clear.
    assert!(
        rows.iter().all(|r| r.value > 0.0),
        "a straight rod does not touch itself"
    );
    (
        ARC_LENGTH_VISITS.with(|c| c.get()),
        EXCLUSION_QUERIES.with(|c| c.get()),
    )
}

#[test]
fn the_self_contact_exclusion_measures_arc_lengths_once_per_evaluation() {
    // Each edge meets its neighbours within the margin in the broad phase: the
    // exclusion is asked O(segments · (2 r + margin) / h) times. Measuring the arc
    // lengths for every query (the old cost) would visit queries × vertices.
    for segments in [200, 800] {
        let (visits, queries) = work(segments);
        println!("{segments} segments: {visits} arc-length visits for {queries} queries");
        assert!(
            queries >= segments,
            "{queries} queries: the test must exercise the exclusion"
        );
        assert_eq!(visits, segments + 1, "one pass over the vertices");
    }
}

#[test]
fn a_vertex_in_a_groove_gets_one_row_per_flank_with_stable_keys() {
    // A 90° groove along x of one mesh, crease at z = 0: flanks z = |y|.
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for (k, side) in [-1.0, 1.0].into_iter().enumerate() {
        let base = 4 * k as u32;
        for (x, t) in [(-0.5, 0.0), (1.5, 0.0), (1.5, 0.1), (-0.5, 0.1)] {
            vertices.push(Point3::new(x, side * t, t));
        }
        triangles.push([base, base + 1, base + 2]);
        triangles.push([base, base + 2, base + 3]);
    }
    let mesh = Arc::new(ObstacleMesh::try_from_triangles("groove", vertices, &triangles).unwrap());
    let model = straight_rod(10, 0.01 * std::f64::consts::SQRT_2 + 1e-4);
    let contact = Contact::new(vec![mesh], 0.02);
    let mut state = initial_state(model.system());
    let rows_at = |state: &strand_system::SystemState| {
        let mut rows = Vec::new();
        contact.rows(&model, state, &mut rows).unwrap();
        rows
    };
    let rows = rows_at(&state);
    // Interior vertices 1..9 move: two rows each (the clamped end vertices have none).
    assert_eq!(rows.len(), 18, "{rows:#?}");
    let gap = 1e-4 * std::f64::consts::FRAC_1_SQRT_2;
    assert!(
        rows.iter().all(|r| (r.value - gap).abs() < 1e-15),
        "{rows:#?}"
    );
    // Moving a vertex sideways within the groove keeps the keys.
    let mut p = state.rods[0].positions[5];
    p.y += 2e-5;
    state.rods[0].set_position(5, p);
    let mut before: Vec<_> = rows.iter().map(|r| r.key).collect();
    let mut after: Vec<_> = rows_at(&state).iter().map(|r| r.key).collect();
    before.sort();
    after.sort();
    assert_eq!(before, after);
}
