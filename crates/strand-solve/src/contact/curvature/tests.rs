//! The curvature of contact rows against central differences of the rows' gradients:
//! a vertex over a face (flat), over a ridge line and over a mesh vertex, an edge
//! over a ridge and over a mesh vertex (the edge parameter eliminated), and an edge of
//! one rod over an edge of another (both parameters eliminated).

use std::sync::Arc;

use nalgebra::{Point3, UnitQuaternion, Vector3};
use strand_contact::ObstacleMesh;
use strand_rod::{Rod, Section};
use strand_system::{End, Model, RodSpec, System, SystemState, initial_state};

use crate::constraints::{Constraints, Row, RowKey};
use crate::contact::Contact;

/// Outer radius of the test rods, m.
const RADIUS: f64 = 0.01;

/// Central-difference step of a vertex position, m.
const STEP: f64 = 1e-6;

/// A rod of 4 edges clamped at `start` and `end` (m).
fn rod(name: &str, start: Vector3<f64>, end: Vector3<f64>, segments: usize) -> RodSpec {
    let section = Section::try_explicit(1e5, 5e4, 0.5, 0.4, 2.0, RADIUS).unwrap();
    let along = UnitQuaternion::rotation_between(&Vector3::z(), &(end - start)).unwrap();
    RodSpec {
        name: name.into(),
        rod: Rod::try_straight(section, (end - start).norm(), segments).unwrap(),
        start: End::clamped(start, along),
        end: End::clamped(end, along),
        route: None,
    }
}

fn model(rods: Vec<RodSpec>) -> Model {
    Model::try_new(System {
        rods,
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::zeros(),
    })
    .unwrap()
}

/// A mesh from corner points and triangles.
fn mesh(name: &str, vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> Arc<ObstacleMesh> {
    let vertices = vertices.iter().map(|v| Point3::from(*v)).collect();
    Arc::new(ObstacleMesh::try_from_triangles(name, vertices, triangles).unwrap())
}

/// A convex roof along y with its ridge at x = 0.5, z = 0, flanks z = −|x − 0.5|/2.
fn roof() -> Arc<ObstacleMesh> {
    mesh(
        "roof",
        &[
            [0.2, -1.0, -0.15],
            [0.5, -1.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.2, 1.0, -0.15],
            [0.8, -1.0, -0.15],
            [0.8, 1.0, -0.15],
        ],
        &[[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]],
    )
}

/// A square pyramid with its apex at (0.5, 0, 0) and 45° faces.
fn pyramid() -> Arc<ObstacleMesh> {
    mesh(
        "pyramid",
        &[
            [0.5, 0.0, 0.0],
            [0.3, -0.2, -0.2],
            [0.7, -0.2, -0.2],
            [0.7, 0.2, -0.2],
            [0.3, 0.2, -0.2],
        ],
        &[[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]],
    )
}

/// A floor at z = 0.
fn floor() -> Arc<ObstacleMesh> {
    mesh(
        "floor",
        &[
            [-1.0, -1.0, 0.0],
            [2.0, -1.0, 0.0],
            [2.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
        ],
        &[[0, 1, 2], [0, 2, 3]],
    )
}

/// The contact rows of `state`.
fn rows_at(model: &Model, contact: &Contact, state: &SystemState) -> Vec<Row> {
    let mut rows = Vec::new();
    contact.rows(model, state, &mut rows).unwrap();
    rows.retain(|r| matches!(r.key, RowKey::Contact(_)));
    rows
}

/// Every free (rod, vertex) of `model` with its position block.
fn free_vertices(model: &Model, state: &SystemState) -> Vec<(usize, usize, usize)> {
    let mut free = Vec::new();
    for (r, rod) in state.rods.iter().enumerate() {
        for j in 0..rod.positions.len() {
            if let Some(block) = model.dofs().vertex(r, j) {
                free.push((r, j, block));
            }
        }
    }
    free
}

/// The gradient of the row `key` at `state` as a dense vector over the unknowns.
fn gradient_of(
    model: &Model,
    contact: &Contact,
    state: &SystemState,
    key: RowKey,
) -> (f64, Vec<f64>) {
    let rows = rows_at(model, contact, state);
    let row = rows
        .iter()
        .find(|r| r.key == key)
        .expect("the row persists under a small move");
    let mut dense = vec![0.0; model.dofs().len()];
    for &(k, a) in &row.gradient {
        dense[k] += a;
    }
    (row.value, dense)
}

/// Checks every contact row of `state` whose curvature `expected` counts the blocks of
/// (1: a vertex, 2: an edge, 4: two edges; 0: flat, no curvature): its gradient
/// against central differences of its value, its curvature against central
/// differences of its gradient. Returns the number of rows checked.
fn check_rows(model: &Model, contact: &Contact, state: &SystemState, expected: usize) -> usize {
    let rows = rows_at(model, contact, state);
    assert!(!rows.is_empty(), "the configuration must touch");
    let free = free_vertices(model, state);
    let n = model.dofs().len();
    let moved = |rod: usize, vertex: usize, axis: usize, by: f64| {
        let mut s = state.clone();
        let mut p = s.rods[rod].positions[vertex];
        p[axis] += by;
        s.rods[rod].set_position(vertex, p);
        s
    };
    for row in &rows {
        let blocks = row.curvature.as_ref().map_or(0, |c| c.blocks.len());
        assert_eq!(blocks, expected, "{row:#?}");
        // The analytic Hessian, dense over the unknowns.
        let mut analytic = vec![vec![0.0; n]; n];
        if let Some(c) = &row.curvature {
            for (a, &ba) in c.blocks.iter().enumerate() {
                for (b, &bb) in c.blocks.iter().enumerate() {
                    for i in 0..3 {
                        for k in 0..3 {
                            analytic[3 * ba + i][3 * bb + k] = c.hessian[(3 * a + i, 3 * b + k)];
                        }
                    }
                }
            }
        }
        let scale = analytic
            .iter()
            .flatten()
            .fold(1.0 / RADIUS, |m: f64, v| m.max(v.abs()));
        let dense = gradient_of(model, contact, state, row.key).1;
        for &(rod, vertex, block) in &free {
            for axis in 0..3 {
                let (plus_value, plus) =
                    gradient_of(model, contact, &moved(rod, vertex, axis, STEP), row.key);
                let (minus_value, minus) =
                    gradient_of(model, contact, &moved(rod, vertex, axis, -STEP), row.key);
                let k = 3 * block + axis;
                let slope = (plus_value - minus_value) / (2.0 * STEP);
                assert!(
                    (slope - dense[k]).abs() <= 1e-7,
                    "∂gap/∂x_{k}: {} against {slope}",
                    dense[k]
                );
                for l in 0..n {
                    let fd = (plus[l] - minus[l]) / (2.0 * STEP);
                    assert!(
                        (fd - analytic[l][k]).abs() <= 1e-6 * scale,
                        "∂²gap/∂x_{l}∂x_{k}: {} against {fd} (rod {rod}, vertex {vertex})",
                        analytic[l][k]
                    );
                }
            }
        }
    }
    rows.len()
}

/// A 4-edge rod along x from (0, 0, 0.05) to (1, 0, 0.05) with vertices 1..=3 at
/// `inner` (m), and the contact against `mesh`.
fn bent(mesh: Arc<ObstacleMesh>, inner: [[f64; 3]; 3]) -> (Model, Contact, SystemState) {
    let model = model(vec![rod(
        "hose",
        Vector3::new(0.0, 0.0, 0.05),
        Vector3::new(1.0, 0.0, 0.05),
        4,
    )]);
    let mut state = initial_state(model.system());
    for (j, p) in inner.iter().enumerate() {
        state.rods[0].set_position(j + 1, Vector3::from(*p));
    }
    (model, Contact::new(vec![mesh], 0.02), state)
}

#[test]
fn a_vertex_over_a_face_has_a_flat_gap() {
    let (model, contact, state) = bent(
        floor(),
        [[0.25, 0.0, 0.2], [0.5, 0.01, 0.015], [0.75, 0.0, 0.2]],
    );
    assert_eq!(check_rows(&model, &contact, &state, 0), 1);
}

#[test]
fn the_curvature_of_a_vertex_over_a_ridge_matches_central_differences() {
    let (model, contact, state) = bent(
        roof(),
        [[0.25, 0.0, 0.2], [0.503, 0.01, 0.016], [0.75, 0.0, 0.2]],
    );
    assert_eq!(check_rows(&model, &contact, &state, 1), 1);
}

#[test]
fn the_curvature_of_a_vertex_over_a_mesh_vertex_matches_central_differences() {
    let (model, contact, state) = bent(
        pyramid(),
        [[0.25, 0.0, 0.2], [0.502, 0.003, 0.016], [0.75, 0.0, 0.2]],
    );
    assert_eq!(check_rows(&model, &contact, &state, 1), 1);
}

#[test]
fn the_curvature_of_an_edge_over_a_ridge_matches_central_differences() {
    let (model, contact, state) = bent(
        roof(),
        [[0.4, 0.0, 0.034], [0.6, 0.03, 0.022], [0.75, 0.0, 0.2]],
    );
    assert!(check_rows(&model, &contact, &state, 2) >= 1);
}

#[test]
fn the_curvature_of_an_edge_over_a_mesh_vertex_matches_central_differences() {
    let (model, contact, state) = bent(
        pyramid(),
        [[0.4, 0.01, 0.03], [0.62, -0.01, 0.022], [0.75, 0.0, 0.2]],
    );
    assert!(check_rows(&model, &contact, &state, 2) >= 1);
}

#[test]
fn the_curvature_of_two_crossing_edges_matches_central_differences() {
    // Rod "b" crosses over the middle of edge 1 of rod "a" at the middle of its own
    // edge 2, slightly skew.
    let lift = 2.0 * RADIUS + 0.004;
    let model = model(vec![
        rod(
            "a",
            Vector3::new(0.0, 0.0, 0.05),
            Vector3::new(1.0, 0.0, 0.05),
            4,
        ),
        rod(
            "b",
            Vector3::new(0.37, -0.5, 0.05 + lift - 0.002),
            Vector3::new(0.43, 0.5, 0.05 + lift + 0.002),
            5,
        ),
    ]);
    let state = initial_state(model.system());
    let contact = Contact::new(vec![], 0.02);
    assert!(check_rows(&model, &contact, &state, 4) >= 1);
}
