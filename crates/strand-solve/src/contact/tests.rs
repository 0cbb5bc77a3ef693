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

/// A straight 1 m rod of radius 10 mm along x at `height` (m), in `segments` edges, clamped at both ends.
pub(super) fn straight_rod(segments: usize, height: f64) -> Model {
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

/// The rod–rod gaps of `state` before and after the local-minimum filter.
fn rod_gaps(
    model: &Model,
    state: &strand_system::SystemState,
) -> (Vec<strand_contact::Gap>, Vec<strand_contact::Gap>) {
    let margin = 0.02;
    let centrelines = super::centrelines(state);
    let rods = super::rod_geometries(model, &centrelines);
    let exclusion = super::exclusion::Exclusion::new(model, state);
    let all = strand_contact::rod_rod_gaps(&rods, margin, |a, ea, b, eb| {
        exclusion.excluded(a, ea, b, eb)
    })
    .unwrap();
    let kept = Contact::new(vec![], margin)
        .gaps(model, state, margin)
        .unwrap();
    (all, kept)
}

#[test]
fn a_straight_hose_gets_one_self_row_per_edge_and_side_at_any_discretisation() {
    // 2 r + margin = 40 mm reaches past the exclusion π r = 31.4 mm: every edge has
    // (40 − 31.4) mm / h partners within the margin, a number that grows with N.
    let mut counts = Vec::new();
    for segments in [200, 800] {
        let model = straight_rod(segments, 0.0);
        let (all, kept) = rod_gaps(&model, &initial_state(model.system()));
        println!(
            "{segments} segments: {} rod-rod gaps, {} kept",
            all.len(),
            kept.len()
        );
        assert!(kept.len() <= 2 * segments, "{} rows", kept.len());
        counts.push((all.len(), kept.len()));
    }
    // The unfiltered count grows about 16× for 4× the edges; the kept one linearly.
    assert!(counts[1].0 > 10 * counts[0].0, "{counts:?}");
    assert!(counts[1].1 <= 5 * counts[0].1, "{counts:?}");
}

#[test]
fn the_nearest_partner_of_every_edge_keeps_its_row() {
    // Two rods: one straight along x, one crossing over it at 30° with a 5 mm gap and
    // then running back along it (a hairpin of radius 0.1 m), so that edges have one
    // nearest partner at the crossing and others along the parallel stretch.
    let section = Section::try_explicit(1e5, 5e4, 0.5, 0.4, 2.0, 0.01).unwrap();
    let along_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let z = 0.025;
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let route = vec![
        Vector3::new(0.5 - 0.4 * c, -0.4 * s, z),
        Vector3::new(0.5, 0.0, z),
        Vector3::new(0.5 + 0.3 * c, 0.3 * s, z),
        Vector3::new(0.4, 0.03, z),
    ];
    let length: f64 = route.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let model = Model::try_new(System {
        rods: vec![
            RodSpec {
                name: "straight".into(),
                rod: Rod::try_straight(section, 1.0, 100).unwrap(),
                start: End::clamped(Vector3::zeros(), along_x),
                end: End::clamped(Vector3::new(1.0, 0.0, 0.0), along_x),
                route: None,
            },
            RodSpec {
                name: "crossing".into(),
                rod: Rod::try_straight(section, length, 120).unwrap(),
                start: End::pinned(route[0]),
                end: End::pinned(route[3]),
                route: Some(route),
            },
        ],
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::zeros(),
    })
    .unwrap();
    let state = initial_state(model.system());
    let (all, kept) = rod_gaps(&model, &state);
    assert!(kept.len() < all.len(), "{} of {}", kept.len(), all.len());
    // For every (edge, partner rod) the smallest gap of the unfiltered list is kept.
    let mut smallest = std::collections::BTreeMap::new();
    for g in &all {
        if let strand_contact::Obstacle::Rod { rod, .. } = g.with {
            let entry = smallest
                .entry((g.rod, g.edge, rod))
                .or_insert(f64::INFINITY);
            *entry = f64::min(*entry, g.gap);
        }
    }
    for ((rod, edge, partner), gap) in smallest {
        assert!(
            kept.iter().any(|g| g.rod == rod
                && g.edge == edge
                && matches!(g.with, strand_contact::Obstacle::Rod { rod: p, .. } if p == partner)
                && g.gap == gap),
            "edge {edge} of rod {rod}: nearest gap {gap} m to rod {partner} dropped"
        );
    }
    // Every kept gap is one of the unfiltered ones.
    assert!(
        kept.iter()
            .all(|k| all.iter().any(|g| g.gap == k.gap && g.edge == k.edge))
    );
}
