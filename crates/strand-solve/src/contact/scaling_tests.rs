//! Counted-work test of contact in a scene that grows by whole bays (a rod and the
//! mesh under it per bay): the rows and the step limit look at (feature, mesh) pairs
//! in proportion to the bays, not to bays², and find the same contacts.

use std::sync::Arc;

use nalgebra::{Point3, UnitQuaternion, Vector3};
use strand_contact::{Obstacle, ObstacleMesh};
use strand_rod::{Rod, Section};
use strand_system::{End, Model, RodSpec, System, SystemState, initial_state};

use super::Contact;
use super::nearby::MESH_PAIRS;
use crate::constraints::Constraints;

/// Edges per rod.
const SEGMENTS: usize = 10;

/// Bay `k`: a floor square x ∈ [2k − 0.2, 2k + 1.2] m, y ∈ [−0.5, 0.5] m at z = 0.
fn floor(k: usize) -> Arc<ObstacleMesh> {
    let x = 2.0 * k as f64;
    let vertices = vec![
        Point3::new(x - 0.2, -0.5, 0.0),
        Point3::new(x + 1.2, -0.5, 0.0),
        Point3::new(x + 1.2, 0.5, 0.0),
        Point3::new(x - 0.2, 0.5, 0.0),
    ];
    Arc::new(
        ObstacleMesh::try_from_triangles(format!("floor{k}"), vertices, &[[0, 1, 2], [0, 2, 3]])
            .unwrap(),
    )
}

/// `bays` bays: in bay `k` a straight 1 m rod of radius 10 mm along x from
/// (2k, 0, h) m, clamped at both ends, 0.1 mm above its floor.
fn bays(bays: usize) -> (Model, Contact) {
    let section = Section::try_explicit(1e5, 5e4, 0.5, 0.4, 2.0, 0.01).unwrap();
    let along_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let height = 0.01 + 1e-4;
    let rods = (0..bays)
        .map(|k| {
            let x = 2.0 * k as f64;
            RodSpec {
                name: format!("rod{k}"),
                rod: Rod::try_straight(section, 1.0, SEGMENTS).unwrap(),
                start: End::clamped(Vector3::new(x, 0.0, height), along_x),
                end: End::clamped(Vector3::new(x + 1.0, 0.0, height), along_x),
                route: None,
            }
        })
        .collect();
    let model = Model::try_new(System {
        rods,
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::zeros(),
    })
    .unwrap();
    let contact = Contact::new((0..bays).map(floor).collect(), 0.02);
    (model, contact)
}

/// The state with every interior vertex 5 cm lower (through the floor: the step
/// limit must stop the centrelines before it).
fn lowered(state: &SystemState) -> SystemState {
    let mut target = state.clone();
    for rod in &mut target.rods {
        for j in 1..SEGMENTS {
            let mut p = rod.positions[j];
            p.z -= 0.05;
            rod.set_position(j, p);
        }
    }
    target
}

/// (feature–mesh pairs looked at, rows, step limit) of one evaluation of the rows and
/// one of the step limit towards [`lowered`].
fn work(count: usize) -> (usize, usize, f64) {
    let (model, contact) = bays(count);
    let state = initial_state(model.system());
    // Every gap of rod k is on floor k, the one under it.
    let gaps = contact.gaps(&model, &state, 0.02).unwrap();
    assert!(
        gaps.iter().all(|g| g.with == Obstacle::Mesh(g.rod)),
        "{gaps:#?}"
    );
    MESH_PAIRS.with(|c| c.set(0));
    let mut rows = Vec::new();
    contact.rows(&model, &state, &mut rows).unwrap();
    let limit = contact
        .advancement(&model, &state, &lowered(&state))
        .unwrap();
    (MESH_PAIRS.with(|c| c.get()), rows.len(), limit)
}

#[test]
fn contact_in_a_scene_of_many_bays_costs_in_proportion_to_its_bays() {
    let (pairs_one, rows_one, limit_one) = work(1);
    // The interior vertices 1..9 rest on the floor: one row each.
    assert_eq!(rows_one, SEGMENTS - 1);
    // The step takes the centrelines 5 cm down; they would reach the floor, 10.1 mm
    // below, at t = 0.202 of it: the limit stops them before.
    assert!(
        limit_one > 0.0 && limit_one < 0.0101 / 0.05,
        "step limit {limit_one}"
    );
    let (pairs_four, rows_four, limit_four) = work(4);
    let (pairs_sixteen, rows_sixteen, limit_sixteen) = work(16);
    println!("pairs looked at: 1 bay {pairs_one}, 4 bays {pairs_four}, 16 bays {pairs_sixteen}");
    // The same contacts and the same limit in every bay.
    assert_eq!((rows_four, rows_sixteen), (4 * rows_one, 16 * rows_one));
    assert_eq!((limit_four, limit_sixteen), (limit_one, limit_one));
    // Each rod looks at its own floor only: asking every mesh would be 4× and 16×
    // the pairs per bay (16 and 256 times one bay's).
    assert!(pairs_one > 0);
    assert_eq!(pairs_four, 4 * pairs_one);
    assert_eq!(pairs_sixteen, 16 * pairs_one);
}
