//! Frictionless contact against meshes and between rods, checked against closed forms
//! and balance laws:
//! - a heavy rod clamped at both ends onto a flat floor lies straight on it and the
//!   floor carries each vertex's weight;
//! - a cantilever propped at its tip by a small cylinder: the prop reaction converges
//!   to Euler–Bernoulli's 3wL/8 at order 2;
//! - a hose pulled over a cylinder: equal tension on both free spans and a contact
//!   load that integrates to `T φ` (line load `T/ρ` over the wrap angle `φ`);
//! - two hoses pressed across each other touch at one point with opposite forces that
//!   balance each rod's clamp reactions;
//! - two cables crossing over a floor, one swinging down across the other, converge
//!   with the weight balanced and no overlap between them.

use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::Arc;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use strand_assets::{TriangleMesh, cylinder, plane};
use strand_contact::{Obstacle, ObstacleMesh};
use strand_rod::sectional::sectional;
use strand_rod::{Rod, Section};
use strand_solve::contact::{Contact, ContactForce};
use strand_solve::{Solution, SolverSettings, solve_constrained};
use strand_system::{End, Model, RodSpec, System, SystemState, initial_state};

fn obstacle(name: &str, mesh: TriangleMesh) -> Arc<ObstacleMesh> {
    Arc::new(ObstacleMesh::try_from_triangles(name, mesh.vertices, &mesh.triangles).unwrap())
}

/// A cylinder of `radius` along the world y axis through `centre` (a ridge of the
/// inscribed polygon on top).
fn cylinder_along_y(radius: f64, centre: Vector3<f64>) -> TriangleMesh {
    faceted_cylinder_along_y(radius, centre, 512)
}

/// A closed cylinder of `facets` flat faces around its axis, 0.4 m long along y.
fn faceted_cylinder_along_y(radius: f64, centre: Vector3<f64>, facets: usize) -> TriangleMesh {
    let pose = Isometry3::from_parts(
        Translation3::from(centre),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -FRAC_PI_2),
    );
    cylinder(radius, 0.4, facets, true).transformed(&pose)
}

fn along_x() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::y_axis(), FRAC_PI_2)
}

fn solved(model: &Model, contact: &Contact, initial: SystemState) -> (Solution, Vec<ContactForce>) {
    let settings = SolverSettings::default();
    let solution = solve_constrained(model, contact, initial, &settings).unwrap();
    let report = &solution.report;
    println!(
        "solve: converged {} ({:?}) in {} iterations ({} coarse, {} continuation), residual {:.2e} N, {:.3} s",
        report.converged,
        report.termination,
        report.iterations,
        report.coarse_iterations,
        report.continuation_iterations,
        report.residual.combined_n,
        report.solve_seconds
    );
    assert!(report.converged, "not converged: {report:?}");
    assert!(report.residual.combined_n <= settings.tolerance_n);
    assert!(report.stable, "not stable");
    let forces = contact
        .forces(model, &solution.state, &solution.constraints)
        .unwrap();
    for f in &forces {
        assert!(f.gap.gap >= -1e-9, "penetration {} m", -f.gap.gap);
        assert!(f.force_n >= 0.0);
        assert!(f.force_n == 0.0 || f.gap.gap.abs() <= 1e-9, "{f:?}");
    }
    (solution, forces)
}

fn total_contact_force(forces: &[ContactForce], rod: usize) -> Vector3<f64> {
    let mut total = Vector3::zeros();
    for f in forces {
        let push = f.force_n * f.gap.normal.into_inner();
        if f.gap.rod == rod {
            total += push;
        }
        if let Obstacle::Rod { rod: other, .. } = f.gap.with
            && other == rod
        {
            total -= push;
        }
    }
    total
}

/// A heavy 1 m rod (20 edges, radius 10 mm, 2 kg/m) clamped at both ends on a floor
/// mesh at z = 0 (its centreline at z = r), and the contact with the floor.
fn rod_on_a_floor() -> (Model, Contact, f64) {
    let radius = 0.01;
    let section = Section::try_explicit(1e5, 5e4, 0.5, 0.4, 2.0, radius).unwrap();
    let system = System {
        rods: vec![RodSpec {
            name: "rod".into(),
            rod: Rod::try_straight(section, 1.0, 20).unwrap(),
            start: End::clamped(Vector3::new(0.0, 0.0, radius), along_x()),
            end: End::clamped(Vector3::new(1.0, 0.0, radius), along_x()),
            route: None,
        }],
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::new(0.0, 0.0, -9.81),
    };
    let model = Model::try_new(system).unwrap();
    let floor = plane(3.0, 1.0, 200).translated(&Vector3::new(0.5, 0.0, 0.0));
    (
        model,
        Contact::new(vec![obstacle("floor", floor)], 0.02),
        radius,
    )
}

#[test]
fn a_heavy_rod_lies_straight_on_a_floor_that_carries_its_weight() {
    let (model, contact, radius) = rod_on_a_floor();
    // Start 1 mm above the floor.
    let mut start = initial_state(model.system());
    for j in 1..20 {
        let mut p = start.rods[0].positions[j];
        p.z += 1e-3;
        start.rods[0].set_position(j, p);
    }
    let (solution, forces) = solved(&model, &contact, start);
    let rod = &model.system().rods[0].rod;
    for (j, p) in solution.state.rods[0].positions.iter().enumerate() {
        assert!((p.z - radius).abs() <= 1e-9, "vertex {j} at z = {}", p.z);
        assert!(p.y.abs() <= 1e-12, "vertex {j} off the line: {}", p.y);
    }
    // The floor carries each interior vertex's weight, straight up.
    let weight = rod.mass() * 9.81;
    let on_floor = total_contact_force(&forces, 0);
    let expected = (rod.mass() - rod.vertex_mass(0) - rod.vertex_mass(20)) * 9.81;
    assert!((on_floor - Vector3::new(0.0, 0.0, expected)).norm() <= 1e-9 * weight);
    let reactions: Vector3<f64> = model
        .reactions(&solution.state)
        .iter()
        .map(|r| r.force)
        .sum();
    let balance = on_floor + reactions - Vector3::new(0.0, 0.0, weight);
    assert!(balance.norm() <= 1e-9 * weight, "imbalance {balance:?}");
}

/// The relative error of the prop reaction of a clamped cantilever (length 0.3 m,
/// EI = 0.5 N·m², 1 kg/m) resting with its tip on a thin rod (a 0.5 mm cylinder), for
/// `segments` edges. EA = GA = 1e5 N: shear
/// changes the reaction by a relative EI/(GA L²) ≈ 6e-5.
fn prop_reaction_error(segments: usize) -> f64 {
    let radius = 0.005;
    let section = Section::try_explicit(1e5, 1e5, 0.5, 0.4, 1.0, radius).unwrap();
    let length = 0.3;
    let system = System {
        rods: vec![RodSpec {
            name: "cantilever".into(),
            rod: Rod::try_straight(section, length, segments).unwrap(),
            start: End::clamped(Vector3::zeros(), along_x()),
            end: End::free(),
            route: None,
        }],
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::new(0.0, 0.0, -9.81),
    };
    let model = Model::try_new(system).unwrap();
    let prop_radius = 0.5e-3;
    let prop = cylinder_along_y(
        prop_radius,
        Vector3::new(length, 0.0, -radius - prop_radius - 1e-12),
    );
    let contact = Contact::new(vec![obstacle("prop", prop)], 0.01);
    // Start straight, above the prop: the default guess lets a free end droop under
    // its weight, which for this rod passes the prop on the wrong side (the guess does
    // not see obstacles).
    let mut start = initial_state(model.system());
    start.rods[0] =
        strand_rod::RodState::straight(&model.system().rods[0].rod, Vector3::zeros(), along_x());
    let (_, forces) = solved(&model, &contact, start);
    let active: Vec<_> = forces.iter().filter(|f| f.force_n > 0.0).collect();
    assert_eq!(active.len(), 1, "one contact point: {active:?}");
    let total = total_contact_force(&forces, 0);
    // Frictionless: the force is normal to the tube, which meets the prop at the
    // Euler–Bernoulli slope wL³/(48 EI) of a propped cantilever.
    let slope = 9.81 * length.powi(3) / (48.0 * 0.5);
    assert!(
        (total.x / total.z + slope).abs() <= 0.05 * slope,
        "prop force {total:?}, slope {slope}"
    );
    // Euler–Bernoulli with the prop where the force acts (a little before the tip: the
    // tube rolls on the prop): R = w (6L² − 4La + a²) / (8a).
    let a = active[0].gap.point.x;
    let w = 9.81;
    let reference = w * (6.0 * length * length - 4.0 * length * a + a * a) / (8.0 * a);
    (total.z - reference) / reference
}

#[test]
fn a_propped_cantilever_matches_euler_bernoulli() {
    let errors: Vec<f64> = [10, 20, 40]
        .iter()
        .map(|&n| prop_reaction_error(n).abs())
        .collect();
    println!("propped cantilever: relative errors {errors:?}");
    assert!(errors[2] < 1e-3, "{errors:?}");
    for pair in errors.windows(2) {
        assert!(
            pair[1] < pair[0] / 3.0,
            "not converging at order 2: {errors:?}"
        );
    }
}

#[test]
fn a_hose_pulled_over_a_cylinder_has_equal_tension_and_load_t_over_rho() {
    // The spans' tensions differ by a discretisation error (vertex contacts on the
    // faceted drum) that shrinks as the hose is refined: 160 -> 320 edges.
    let coarse = hose_over_drum(160);
    let fine = hose_over_drum(320);
    let order = (coarse / fine).log2();
    println!(
        "tension difference {coarse:.2e} (160 edges), {fine:.2e} (320 edges): observed order {order:.2}"
    );
    assert!(coarse <= 1e-3, "tension differs by {coarse:.2e} relative");
    assert!(
        fine <= coarse / 2.0,
        "no tightening with refinement: {coarse:.2e} -> {fine:.2e}"
    );
}

/// At 80 edges (started from a 40-edge solution by nested iteration) the hose used to
/// stall at 8.7e-2 N: where an edge's nearest points on the faceted drum became a
/// stretch, one contact row became two of equal value, the summed violation of the
/// merit jumped, and every trial, however short, was rejected. With the ℓ∞ merit it
/// converges, and its tension equality tightens on the way to 320 edges.
#[test]
fn a_hose_pulled_over_a_cylinder_converges_at_80_edges() {
    let coarse = hose_over_drum(80);
    assert!(coarse <= 2e-3, "tension differs by {coarse:.2e}");
    let fine = hose_over_drum(320);
    println!("tension difference {coarse:.2e} (80 edges), {fine:.2e} (320 edges)");
    assert!(
        fine <= coarse / 2.0,
        "no tightening with refinement: {coarse:.2e} -> {fine:.2e}"
    );
}

/// Solves the hose over the drum with `segments` edges, checks the contact load and
/// returns the relative difference of the two spans' tensions.
fn hose_over_drum(segments: usize) -> f64 {
    hose_over_faceted_drum(segments, 512).tension_difference
}

/// What [`hose_over_faceted_drum`] measured.
struct DrumSolve {
    /// Relative difference of the two free spans' tensions.
    tension_difference: f64,
    /// Newton iterations of the solve (all levels).
    iterations: usize,
    /// Solve time, s.
    solve_s: f64,
}

/// Solves the hose (`segments` edges) over a drum of `facets` flat faces and checks
/// convergence, stability and no penetration (in `solved`) and, from 512 facets on (a
/// coarser drum's corners carry the load unevenly), the contact load `T φ`.
fn hose_over_faceted_drum(segments: usize, facets: usize) -> DrumSolve {
    let radius = 0.005;
    let (ea, ei) = (1e4, 1e-4);
    let section = Section::try_explicit(ea, ea, ei, ei, 0.0, radius).unwrap();
    let cylinder_radius = 0.05;
    let rho = cylinder_radius + radius;
    let (a, b) = (
        Vector3::new(-0.15, 0.0, -0.1),
        Vector3::new(0.12, 0.0, -0.05),
    );
    // The taut path: tangent from each pin to the circle of radius ρ, and the arc over
    // the top between the tangent points.
    let tangent_angle = |p: &Vector3<f64>, side: f64| {
        let d = (p.x * p.x + p.z * p.z).sqrt();
        (
            p.z.atan2(p.x) + side * (rho / d).acos(),
            (d * d - rho * rho).sqrt(),
        )
    };
    let (angle_a, tangent_a) = tangent_angle(&a, -1.0);
    let (angle_b, tangent_b) = tangent_angle(&b, 1.0);
    let angle_a = angle_a + 2.0 * PI;
    let wrap = angle_a - angle_b;
    assert!(wrap > 1.5 && wrap < 1.9, "wrap {wrap}");
    let path = tangent_a + tangent_b + rho * wrap;
    let length = path / (1.0 + 20.0 / ea);
    // Route over the top on a circle of 62 mm.
    let mut route = vec![a];
    for k in 0..=24 {
        let t = angle_a + (angle_b - angle_a) * k as f64 / 24.0;
        route.push(0.062 * Vector3::new(t.cos(), 0.0, t.sin()));
    }
    route.push(b);
    // Clamped along the free spans (pins would leave the twist about the hose free).
    let point_on = |angle: f64| rho * Vector3::new(angle.cos(), 0.0, angle.sin());
    let frame = |d: Vector3<f64>| UnitQuaternion::rotation_between(&Vector3::z(), &d).unwrap();
    let system = System {
        rods: vec![RodSpec {
            name: "hose".into(),
            rod: Rod::try_straight(section, length, segments).unwrap(),
            start: End::clamped(a, frame(point_on(angle_a) - a)),
            end: End::clamped(b, frame(b - point_on(angle_b))),
            route: Some(route),
        }],
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::zeros(),
    };
    let model = Model::try_new(system).unwrap();
    let contact = Contact::new(
        vec![obstacle(
            "drum",
            faceted_cylinder_along_y(cylinder_radius, Vector3::zeros(), facets),
        )],
        0.01,
    );
    let (solution, forces) = solved(&model, &contact, initial_state(model.system()));
    let state = &solution.state.rods[0];
    let spec = &model.system().rods[0];
    let cut = sectional(&spec.rod, state, &model.boundary_frames(0, &solution.state));
    // Mid-spans: the vertices nearest to the middle of each free span.
    let s = spec.rod.arc_lengths();
    let nearest = |target: f64| {
        (0..=segments)
            .min_by(|&i, &j| (s[i] - target).abs().total_cmp(&(s[j] - target).abs()))
            .unwrap()
    };
    let left = cut.forces[nearest(0.5 * tangent_a)].norm();
    let right = cut.forces[nearest(length - 0.5 * tangent_b)].norm();
    println!("hose over a drum ({segments} edges): tension {left} N and {right} N");
    let total: f64 = forces.iter().map(|f| f.force_n).sum();
    let expected = left * wrap;
    println!(
        "contact load {total} N, T φ = {expected} N (line load T/ρ = {} N/m)",
        left / rho
    );
    if facets >= 512 {
        assert!(
            (total - expected).abs() <= 0.01 * expected,
            "{total} vs {expected}"
        );
    }
    DrumSolve {
        tension_difference: (left - right).abs() / left,
        iterations: solution.report.iterations,
        solve_s: solution.report.solve_seconds,
    }
}

/// Issue 11 goal 3 (a measurement, not a timed test: run with `--ignored
/// --nocapture`): the hose over drums from 32 to 94,500 facets (128 to 378,000
/// triangles) converges at every density; the table of iterations and solve times is
/// README's "Contact vs mesh size". Every solve is checked as the drum test checks it.
#[test]
#[ignore = "measurement (about a minute): cargo test --release -p strand-tests --test validation hose_over_finely_faceted_drums -- --ignored --nocapture"]
fn hose_over_finely_faceted_drums_iterations() {
    println!("facets  triangles  iterations  solve [s]  tension difference");
    for facets in [32, 256, 1000, 10_000, 94_500] {
        let drum = hose_over_faceted_drum(160, facets);
        println!(
            "{facets:>6}  {:>9}  {:>10}  {:>9.3}  {:.2e}",
            4 * facets,
            drum.iterations,
            drum.solve_s,
            drum.tension_difference
        );
    }
}

/// The hose over a 256-facet drum (1.2 mm faces) converges about as fast as over the
/// 32-facet one: its coarse edges come to lie on faces, and before the next ridges of
/// a narrow face were rows of their own (`LocalContact::near_tie`) every step that
/// turned an edge past the face cut into its far ridge at first order, so the trust
/// region crept towards the face for 20 iterations (39 in all; 20 with them).
#[test]
fn hose_over_a_256_facet_drum_converges_without_creeping_onto_faces() {
    let drum = hose_over_faceted_drum(160, 256);
    assert!(drum.iterations <= 22, "{} iterations", drum.iterations);
}

/// The hose over the 94,500-facet drum (378,000 triangles, 3.3 µm faces) converges in
/// about as many iterations as over the 32-facet one (12). Before, its coarse stage
/// stopped twice at its 40-iteration limit (112 in all): a Newton step of nanometres
/// cut a nearly tied ridge's row by 1e-12 m, within the 1e-10 m the exact QP step
/// tolerated, and the exact penalty rejected every trial for it (`sqp::violation_by`).
#[test]
fn hose_over_a_94500_facet_drum_converges_in_about_as_many_iterations_as_a_coarse_one() {
    let drum = hose_over_faceted_drum(160, 94_500);
    assert!(drum.iterations <= 23, "{} iterations", drum.iterations);
}

#[test]
fn two_hoses_pressed_across_each_other_touch_once_with_balancing_forces() {
    let radius = 0.008;
    let section = Section::try_explicit(2e4, 1e4, 0.05, 0.04, 0.0, radius).unwrap();
    let along_y = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -FRAC_PI_2);
    // `lower` runs along x at z = 0; `upper` along y, clamped 6 mm lower than it would
    // need to pass clear, and routed over it at the start.
    let z = 2.0 * radius - 0.006;
    let route = vec![
        Vector3::new(0.0, -0.2, z),
        Vector3::new(0.0, -0.05, 0.03),
        Vector3::new(0.0, 0.05, 0.03),
        Vector3::new(0.0, 0.2, z),
    ];
    let system = System {
        rods: vec![
            RodSpec {
                name: "lower".into(),
                rod: Rod::try_straight(section, 0.4, 11).unwrap(),
                start: End::clamped(Vector3::new(-0.2, 0.0, 0.0), along_x()),
                end: End::clamped(Vector3::new(0.2, 0.0, 0.0), along_x()),
                route: None,
            },
            RodSpec {
                name: "upper".into(),
                rod: Rod::try_straight(section, 0.4, 11).unwrap(),
                start: End::clamped(Vector3::new(0.0, -0.2, z), along_y),
                end: End::clamped(Vector3::new(0.0, 0.2, z), along_y),
                route: Some(route),
            },
        ],
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::zeros(),
    };
    let model = Model::try_new(system).unwrap();
    let contact = Contact::new(vec![], 0.02);
    let (solution, forces) = solved(&model, &contact, initial_state(model.system()));
    let active: Vec<_> = forces.iter().filter(|f| f.force_n > 0.0).collect();
    assert_eq!(active.len(), 1, "{active:?}");
    let on_lower = total_contact_force(&forces, 0);
    let on_upper = total_contact_force(&forces, 1);
    assert!(on_lower.norm() > 0.1, "pressed together: {on_lower:?}");
    assert!((on_lower + on_upper).norm() <= 1e-12 * on_lower.norm());
    // Each rod's clamps balance its contact force.
    let reactions = model.reactions(&solution.state);
    for (rod, on_rod) in [(0, on_lower), (1, on_upper)] {
        let held: Vector3<f64> = reactions
            .iter()
            .filter(|r| r.rod == rod)
            .map(|r| r.force)
            .sum();
        assert!(
            (held + on_rod).norm() <= 1e-9 * on_rod.norm(),
            "rod {rod}: {held:?} + {on_rod:?}"
        );
    }
}

/// Two cables between random connectors crossing over a floor (a generated case: a
/// soft 13.9 mm cable of 11 segments and a stiff 5 mm one of 15, both far longer than
/// their connectors' distance). Their starts, bowed sideways, put the stiff cable across
/// the soft one, and it must swing down past it: the advancement let two hoses within
/// the search margin of each other move relative to each other by only half the
/// margin (2.5 mm) per step, so the solve crept and ended not converged after 2800
/// iterations (exit 3). Sampled along the step (as against the meshes) the hoses slide
/// past each other and it converges; the connectors and the floor carry the weight,
/// and the hoses do not overlap.
#[test]
fn two_cables_crossing_over_a_floor_slide_past_each_other_and_converge() {
    let dir = tempfile::tempdir().unwrap();
    let z = 202.82236290542858;
    std::fs::write(
        dir.path().join("floor.obj"),
        format!(
            "v -3000 -3000 {z}\nv 4000 -3000 {z}\nv 4000 4000 {z}\nv -3000 4000 {z}\nf 1 2 3\nf 1 3 4\n"
        ),
    )
    .unwrap();
    let path = dir.path().join("crossing.ron");
    std::fs::write(
        &path,
        r#"(
    units: (length: "mm"),
    sections: {
        "s0": Tube(youngs_modulus: 3.008e+07, poisson_ratio: 0.45, density: 2014, inner_radius: 0, outer_radius: 6.934),
        "s1": Tube(youngs_modulus: 1.904e+09, poisson_ratio: 0.45, density: 2354, inner_radius: 0, outer_radius: 2.494),
    },
    connectors: {
        "a0": (position: (-218.216, -373.885, 283.839), direction: (-0.810, 0.538, -0.234), normal: (0.553, 0.833, -0.000)),
        "b0": (position: (295.777, 321.802, 385.184), direction: (-0.154, 0.657, 0.738), normal: (0.974, 0.229, -0.000)),
        "a1": (position: (425.287, 48.595, 433.762), direction: (-0.454, -0.513, 0.729), normal: (-0.749, 0.663, 0.000)),
        "b1": (position: (-388.639, -132.150, 332.566), direction: (0.044, -0.518, -0.854), normal: (-0.996, -0.084, 0.000)),
    },
    rods: [
        (name: "c0", section: "s0", length: 1347.71, segments: 11, start: Connector("a0"), end: ConnectorPin("b0")),
        (name: "c1", section: "s1", length: 1334.55, segments: 15, start: ConnectorPin("a1"), end: Connector("b1")),
    ],
    environment: [(name: "floor", obj: "floor.obj", unit: "mm")],
    gravity: (0, 0, -9.81),
)"#,
    )
    .unwrap();
    let built = strand_case::Case::from_path(&path)
        .unwrap()
        .build(None)
        .unwrap();
    let solution = built
        .solve_from(built.initial.clone(), &built.settings)
        .unwrap();
    let report = &solution.report;
    assert!(report.converged, "{report:?}");
    let contact = built.contact().unwrap();
    let forces = contact
        .forces(&built.model, &solution.state, &solution.constraints)
        .unwrap();
    // The connectors and the floor carry the weight (the hoses' forces on each other
    // cancel).
    let system = built.model.system();
    let weight: Vector3<f64> = system
        .rods
        .iter()
        .map(|r| system.gravity * r.rod.section().mass_per_length * r.rod.length())
        .sum();
    let mut total = weight;
    for f in forces
        .iter()
        .filter(|f| !matches!(f.gap.with, Obstacle::Rod { .. }))
    {
        total += f.force_n * f.gap.normal.into_inner();
    }
    for r in built.model.reactions(&solution.state) {
        total += r.force;
    }
    assert!(
        total.norm() <= 1e-8 * weight.norm(),
        "imbalance {total:?} of {weight:?}"
    );
    // No overlap: every pair of edges of the two hoses at least the sum of the radii
    // apart (centrelines).
    let radii = [0.006934, 0.002494];
    let [first, second] = [
        &solution.state.rods[0].positions,
        &solution.state.rods[1].positions,
    ];
    for a in first.windows(2) {
        for b in second.windows(2) {
            let d = strand_contact::closest_segment_segment(
                &a[0].into(),
                &a[1].into(),
                &b[0].into(),
                &b[1].into(),
            )
            .distance;
            assert!(d >= radii[0] + radii[1] - 1e-9, "overlap: {d} m");
        }
    }
}

#[test]
fn a_hose_starting_inside_an_obstacle_is_reported_with_its_location() {
    let (model, contact, _) = rod_on_a_floor();
    let mut start = initial_state(model.system());
    let mut p = start.rods[0].positions[10];
    p.z -= 0.002;
    start.rods[0].set_position(10, p);
    let error = solve_constrained(&model, &contact, start, &SolverSettings::default())
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("rod 'rod' starts inside mesh 'floor'")
            && error.contains("overlaps it by 2.000 mm")
            && error.contains("s = 500.0 mm"),
        "{error}"
    );
}

#[test]
fn the_cooler_hoses_rest_on_their_bracket_in_balance_and_report_clearances() {
    let built =
        strand_case::Case::from_path(crate::common::cases_dir().join("cooler_hose_contact.ron"))
            .unwrap()
            .build(None)
            .unwrap();
    let contact = built.contact().expect("the case has an environment");
    let (solution, forces) = solved(&built.model, &contact, built.initial.clone());
    let system = built.model.system();
    let active: Vec<_> = forces.iter().filter(|f| f.force_n > 0.0).collect();
    assert!(!active.is_empty(), "hose 3 rests on the bracket");
    assert!(
        active
            .iter()
            .all(|f| contact.obstacle_name(&built.model, &f.gap.with) == "brackets"),
        "{active:?}"
    );
    // Connectors and contacts carry the hoses and the T, in force and moment.
    let weight_of = |mass: f64| mass * system.gravity;
    let reactions = built.model.reactions(&solution.state);
    let connectors: Vec<_> = reactions
        .iter()
        .filter(|r| r.kind == strand_system::ReactionKind::Connector)
        .collect();
    let mut force = connectors.iter().map(|r| r.force).sum::<Vector3<f64>>();
    let mut moment = connectors
        .iter()
        .map(|r| r.moment + r.position.cross(&r.force))
        .sum::<Vector3<f64>>();
    for f in &forces {
        let push = f.force_n * f.gap.normal.into_inner();
        force += push;
        moment += f.gap.point.coords.cross(&push);
    }
    let mut weight = Vector3::zeros();
    for (r, spec) in system.rods.iter().enumerate() {
        for (j, p) in solution.state.rods[r].positions.iter().enumerate() {
            let w = weight_of(spec.rod.vertex_mass(j));
            weight += w;
            moment += p.cross(&w);
        }
    }
    for (b, body) in system.bodies.iter().enumerate() {
        let w = weight_of(body.mass);
        weight += w;
        moment += solution.state.bodies[b]
            .transform_point(&body.center_of_mass)
            .cross(&w);
    }
    force += weight;
    assert!(
        force.norm() <= 1e-9 * weight.norm(),
        "force imbalance {force:?}"
    );
    assert!(
        moment.norm() <= 1e-9 * weight.norm(),
        "moment imbalance {moment:?}"
    );
    // result.json: the contacts and a clearance for every hose.
    let mut doc = strand_report::collect(
        &built.name,
        &built.model,
        &solution,
        strand_report::Timing::default(),
    );
    strand_report::collect_contacts(&mut doc, &built.model, &solution, &contact).unwrap();
    assert_eq!(doc.contacts.len(), active.len());
    let total: f64 = doc.contacts.iter().map(|c| c.force_n).sum();
    let expected: f64 = active.iter().map(|f| f.force_n).sum();
    assert!((total - expected).abs() <= 1e-12 * expected);
    for hose in ["hose1", "hose2", "hose3"] {
        assert!(
            doc.clearance
                .iter()
                .any(|c| c.rod == hose && c.with != hose),
            "{hose} has a clearance"
        );
    }
    let resting = doc
        .clearance
        .iter()
        .find(|c| c.rod == "hose3" && c.with == "brackets")
        .unwrap();
    assert!(resting.distance_m <= 1e-9, "{resting:?}");
    assert!(doc.clearance.iter().all(|c| c.distance_m >= 0.0));
}

#[test]
fn the_longer_hose_variant_of_the_contact_case_converges_without_penetration() {
    let case =
        strand_case::Case::from_path(crate::common::cases_dir().join("cooler_hose_contact.ron"))
            .unwrap();
    let built = case.build_variant("hose2_plus50", None).unwrap();
    let contact = built.contact().expect("the case has an environment");
    let (_, forces) = solved(&built.model, &contact, built.initial.clone());
    assert!(forces.iter().any(|f| f.force_n > 0.0), "hose 3 still rests");
}
