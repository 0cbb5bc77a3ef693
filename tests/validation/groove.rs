//! A heavy straight hose lying in a concave crease, with the faces in ONE mesh and
//! split over several meshes (issue 10): every face it touches gets its own
//! constraint, so the hose rests on both flanks without sinking in and the flank
//! loads match statics:
//! - a V-groove of opening angle α (90°, 60°) with its bisector vertical: each flank
//!   carries `w / (2 sin(α/2))` per unit length (w the weight per length);
//! - a three-face corner (a 90° groove tilted by β down to an end wall, the hose
//!   clamped at its upper end and resting its free end on the wall): each flank carries
//!   `W cos β / (2 sin 45°)` of the weight of the unclamped vertices, and the wall
//!   `W sin β / 2` (axial compatibility of the straight rod between clamp and wall).

use std::sync::Arc;

use nalgebra::{Point3, UnitQuaternion, Vector3};
use strand_assets::{TriangleMesh, merge, parallelogram};
use strand_contact::ObstacleMesh;
use strand_rod::{Rod, Section};
use strand_solve::contact::{Contact, ContactForce};
use strand_solve::{Solution, SolverSettings, solve_constrained};
use strand_system::{End, Model, RodSpec, System, initial_state};

const RADIUS: f64 = 0.01;
const G: f64 = 9.81;
const SEGMENTS: usize = 20;

/// The heavy hose of the floor test: 1 m, radius 10 mm, 2 kg/m.
fn section() -> Section {
    Section::try_explicit(1e5, 5e4, 0.5, 0.4, 2.0, RADIUS).unwrap()
}

/// The meshes: all `faces` in one mesh, or one mesh per face.
fn meshes(faces: &[TriangleMesh], one_mesh: bool) -> Vec<Arc<ObstacleMesh>> {
    let build = |name: String, m: TriangleMesh| {
        Arc::new(ObstacleMesh::try_from_triangles(name, m.vertices, &m.triangles).unwrap())
    };
    if one_mesh {
        vec![build("faces".into(), merge(faces))]
    } else {
        faces
            .iter()
            .enumerate()
            .map(|(i, f)| build(format!("face{i}"), f.clone()))
            .collect()
    }
}

/// Solves with default settings from the straight start lifted by `lift` (m); asserts
/// convergence within 30 iterations, stability, no penetration of any row and the same
/// answer as with a full mesh search at every evaluation (issue 11).
fn solve_in(
    model: &Model,
    contact: &Contact,
    lift: Vector3<f64>,
    label: &str,
) -> (Solution, Vec<ContactForce>) {
    let mut start = initial_state(model.system());
    for j in 1..=SEGMENTS {
        let p = start.rods[0].positions[j] + lift;
        start.rods[0].set_position(j, p);
    }
    let settings = SolverSettings::default();
    let solution = solve_constrained(model, contact, start.clone(), &settings).unwrap();
    crate::common::assert_same_as_full_queries(model, contact, start, &settings, &solution, label);
    let report = &solution.report;
    println!(
        "{label}: converged {} in {} iterations (+{} coarse, {} continuation), residual {:.2e} N",
        report.converged,
        report.iterations,
        report.coarse_iterations,
        report.continuation_iterations,
        report.residual.combined_n
    );
    assert!(report.converged, "{label}: not converged: {report:?}");
    // The target with default settings.
    assert!(
        report.iterations <= 30,
        "{label}: {} iterations",
        report.iterations
    );
    assert!(report.stable, "{label}: not stable");
    let forces = contact
        .forces(model, &solution.state, &solution.constraints)
        .unwrap();
    let deepest = forces.iter().map(|f| -f.gap.gap).fold(0.0, f64::max);
    println!("{label}: deepest row penetration {deepest:.2e} m");
    assert!(deepest <= 1e-9, "{label}: penetration {deepest} m");
    (solution, forces)
}

/// Sum of the contact forces whose normal is `normal` (within 1e-6).
fn load_on(forces: &[ContactForce], normal: &Vector3<f64>) -> f64 {
    forces
        .iter()
        .filter(|f| (f.gap.normal.into_inner() - normal).norm() < 1e-6)
        .map(|f| f.force_n)
        .sum()
}

/// Smallest distance of the centreline vertices to the plane through `point` with
/// unit `normal`, minus the radius (the true clearance to an unbounded flank).
fn plane_clearance(solution: &Solution, point: &Point3<f64>, normal: &Vector3<f64>) -> f64 {
    solution.state.rods[0]
        .positions
        .iter()
        .map(|p| (p - point.coords).dot(normal) - RADIUS)
        .fold(f64::INFINITY, f64::min)
}

/// A hose clamped at both ends along a V-groove of opening `alpha` along x.
fn v_groove(alpha_deg: f64, one_mesh: bool) {
    let label = format!(
        "{alpha_deg}° groove, {}",
        if one_mesh { "one mesh" } else { "two meshes" }
    );
    let half = 0.5 * alpha_deg.to_radians();
    let (width, cells) = (0.1, 3);
    let along = Vector3::new(1.4, 0.0, 0.0);
    let origin = Point3::new(-0.2, 0.0, 0.0);
    let left = Vector3::new(0.0, -half.sin(), half.cos()) * width;
    let right = Vector3::new(0.0, half.sin(), half.cos()) * width;
    let faces = [
        parallelogram(origin, left, along, cells, 14),
        parallelogram(origin, along, right, 14, cells),
    ];
    let normals = [
        Vector3::new(0.0, half.cos(), half.sin()),
        Vector3::new(0.0, -half.cos(), half.sin()),
    ];
    // The centreline rests at r / sin(α/2) above the crease.
    let height = RADIUS / half.sin();
    let along_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let system = System {
        rods: vec![RodSpec {
            name: "hose".into(),
            rod: Rod::try_straight(section(), 1.0, SEGMENTS).unwrap(),
            start: End::clamped(Vector3::new(0.0, 0.0, height), along_x),
            end: End::clamped(Vector3::new(1.0, 0.0, height), along_x),
            route: None,
        }],
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::new(0.0, 0.0, -G),
    };
    let model = Model::try_new(system).unwrap();
    let contact = Contact::new(meshes(&faces, one_mesh), 0.02);
    let (solution, forces) = solve_in(&model, &contact, Vector3::new(0.0, 3e-4, 1e-3), &label);
    for n in &normals {
        let clearance = plane_clearance(&solution, &origin, n);
        assert!(
            clearance >= -1e-9,
            "{label}: sinks {clearance} m into a flank"
        );
    }
    // Statics: the flanks carry the interior vertices' weight (the clamps their own
    // vertices'), each w / (2 sin(α/2)) per unit length.
    let rod = &model.system().rods[0].rod;
    let carried = (rod.mass() - rod.vertex_mass(0) - rod.vertex_mass(SEGMENTS)) * G;
    let expected = carried / (2.0 * half.sin());
    for n in &normals {
        let load = load_on(&forces, n);
        let error = (load - expected).abs() / expected;
        println!("{label}: flank load {load:.9} N, analytic {expected:.9} N, error {error:.1e}");
        assert!(error <= 1e-10, "{label}: {load} N vs {expected} N");
    }
    let total: f64 = forces.iter().map(|f| f.force_n).sum();
    assert!(
        (total - 2.0 * expected).abs() <= 1e-8 * expected,
        "{label}: no other contact carries load ({total} N)"
    );
}

#[test]
fn a_heavy_hose_rests_in_a_90_degree_groove_of_one_mesh() {
    v_groove(90.0, true);
}

#[test]
fn a_heavy_hose_rests_in_a_90_degree_groove_of_two_meshes() {
    v_groove(90.0, false);
}

#[test]
fn a_heavy_hose_rests_in_a_60_degree_groove_of_one_mesh() {
    v_groove(60.0, true);
}

#[test]
fn a_heavy_hose_rests_in_a_60_degree_groove_of_two_meshes() {
    v_groove(60.0, false);
}

/// A 90° groove tilted down by `beta` towards an end wall; the hose is clamped at its
/// upper end and rests its free lower end against the wall.
fn corner(one_mesh: bool) {
    let label = format!(
        "three-face corner, {}",
        if one_mesh { "one mesh" } else { "three meshes" }
    );
    let beta = 20f64.to_radians();
    // Down the crease towards the wall, and the upward normal of the crease's
    // vertical plane.
    let e = Vector3::new(beta.cos(), 0.0, -beta.sin());
    let up = Vector3::new(beta.sin(), 0.0, beta.cos());
    let y = Vector3::y();
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let corner = Point3::new(1.0, 0.0, 0.0);
    let (width, length) = (0.1, 1.3);
    let faces = [
        parallelogram(corner, -e * length, (up - y) * s * width, 13, 3),
        parallelogram(corner, (up + y) * s * width, -e * length, 3, 13),
        parallelogram(corner - y * width, y * 2.0 * width, up * width, 4, 2),
    ];
    let normals = [(up + y) * s, (up - y) * s, -e];
    let height = RADIUS * std::f64::consts::SQRT_2;
    // Stress-free, the free end touches the wall.
    let end = corner - e * RADIUS + up * height;
    let start = end - e * 1.0;
    let frame = UnitQuaternion::rotation_between(&Vector3::z(), &e).unwrap();
    let system = System {
        rods: vec![RodSpec {
            name: "hose".into(),
            rod: Rod::try_straight(section(), 1.0, SEGMENTS).unwrap(),
            start: End::clamped(start.coords, frame),
            end: End::free(),
            // Straight down the crease (a free end would otherwise hang).
            route: Some(vec![start.coords, end.coords]),
        }],
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::new(0.0, 0.0, -G),
    };
    let model = Model::try_new(system).unwrap();
    let contact = Contact::new(meshes(&faces, one_mesh), 0.02);
    let (solution, forces) = solve_in(&model, &contact, up * 1e-3 + y * 3e-4, &label);
    for n in &normals {
        let clearance = plane_clearance(&solution, &corner, n);
        assert!(
            clearance >= -1e-9,
            "{label}: sinks {clearance} m into a face"
        );
    }
    let rod = &model.system().rods[0].rod;
    let weight = rod.mass() * G;
    let carried = (rod.mass() - rod.vertex_mass(0)) * G;
    let checks = [
        ("flank", carried * beta.cos() / (2.0 * s), normals[0]),
        ("flank", carried * beta.cos() / (2.0 * s), normals[1]),
        ("wall", weight * beta.sin() / 2.0, normals[2]),
    ];
    for (name, expected, n) in checks {
        let load = load_on(&forces, &n);
        let error = (load - expected).abs() / expected;
        println!("{label}: {name} load {load:.9} N, analytic {expected:.9} N, error {error:.1e}");
        assert!(error <= 1e-9, "{label}: {name} {load} N vs {expected} N");
    }
}

#[test]
fn a_heavy_hose_rests_in_a_three_face_corner_of_one_mesh() {
    corner(true);
}

#[test]
fn a_heavy_hose_rests_in_a_three_face_corner_of_three_meshes() {
    corner(false);
}
