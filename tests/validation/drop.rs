//! Drop tests (issue 10): hoses of several stiffnesses and slacks, held at both ends
//! above a cluttered scene (a pipe, a box with sharp edges, a thin fin, a V-groove, a
//! U-channel, a floor), start from random poses (their hanging shape swung sideways
//! about the chord, fixed seeds) and fall onto it. For every case, with default
//! settings:
//! - the solve converges;
//! - nothing penetrates, by an independent brute-force distance of every rod edge (a
//!   segment, with its end vertices) to every triangle of the scene, written here and
//!   not calling the contact code: at least the outer radius less 1e-9 m;
//! - contact forces and support reactions balance the total weight to 1e-8 relative.
//!
//! The table of iterations, contacts, residual and time is printed; the median
//! iteration count is the speed target.

use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::{Arc, OnceLock};
use std::time::Instant;

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use strand_assets::{TriangleMesh, axis_box, cylinder, parallelogram, plane};
use strand_contact::ObstacleMesh;
use strand_rod::{Rod, Section};
use strand_solve::contact::Contact;
use strand_solve::{SolverSettings, solve_constrained};
use strand_system::{End, Model, RodSpec, System, SystemState, initial_state};

/// Gravitational acceleration, m/s².
const G: f64 = 9.81;
/// Horizontal distance between the two held ends (along x), m.
const SPAN: f64 = 0.9;
/// Number of cases of the family (seeds 0..CASES).
const CASES: u64 = 12;

/// A U-channel along x: the lower half of a circular cylinder of `radius` (m) with its
/// axis through `axis` (m), from `axis.x` to `axis.x + length`, as `segments` facets
/// around and `cells` along, normals pointing inwards (up, towards the axis).
fn u_channel(
    axis: Point3<f64>,
    radius: f64,
    length: f64,
    segments: usize,
    cells: usize,
) -> TriangleMesh {
    let mut mesh = TriangleMesh::new();
    for i in 0..=cells {
        let x = axis.x + length * i as f64 / cells as f64;
        for k in 0..=segments {
            // From the +y lip (angle 0) down through the bottom to the −y lip (angle π).
            let angle = PI * k as f64 / segments as f64;
            mesh.push_vertex(Point3::new(
                x,
                axis.y + radius * angle.cos(),
                axis.z - radius * angle.sin(),
            ));
        }
    }
    let at = |i: usize, k: usize| (i * (segments + 1) + k) as u32;
    for i in 0..cells {
        for k in 0..segments {
            mesh.push_quad(at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k + 1));
        }
    }
    mesh
}

/// The scene under the span `x ∈ [0, SPAN]` (m), one mesh per object:
/// - a pipe (capped cylinder, radius 30 mm) across the span, its top at z = −30 mm;
/// - a box with sharp edges, its top at z = −130 mm;
/// - a thin fin (5 mm plate standing on edge) across the span, its top edge at
///   z = −100 mm;
/// - a 90° V-groove along the span, crease at z = −220 mm;
/// - a U-channel (radius 40 mm) along the span, lips at z = −120 mm;
/// - a floor at z = −300 mm.
fn scene() -> Vec<(&'static str, TriangleMesh)> {
    let across_y = Isometry3::from_parts(
        Translation3::new(0.15, 0.0, -0.06),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -FRAC_PI_2),
    );
    let pipe = cylinder(0.03, 0.9, 48, true).transformed(&across_y);
    let block = axis_box(Point3::new(0.26, -0.3, -0.3), Point3::new(0.40, 0.3, -0.13));
    let fin = axis_box(
        Point3::new(0.455, -0.3, -0.3),
        Point3::new(0.46, 0.3, -0.10),
    );
    let half = 45f64.to_radians();
    let (width, along) = (0.1, Vector3::new(0.2, 0.0, 0.0));
    let crease = Point3::new(0.50, 0.0, -0.22);
    let left = Vector3::new(0.0, -half.sin(), half.cos()) * width;
    let right = Vector3::new(0.0, half.sin(), half.cos()) * width;
    let v_groove = strand_assets::merge(&[
        parallelogram(crease, left, along, 4, 8),
        parallelogram(crease, along, right, 8, 4),
    ]);
    let channel = u_channel(Point3::new(0.72, 0.0, -0.12), 0.04, 0.18, 16, 6);
    let floor = plane(2.0, 1.5, 400).translated(&Vector3::new(SPAN / 2.0, 0.0, -0.3));
    vec![
        ("pipe", pipe),
        ("block", block),
        ("fin", fin),
        ("v_groove", v_groove),
        ("u_channel", channel),
        ("floor", floor),
    ]
}

// ---------------------------------------------------------------------------------
// Independent distance: segment to triangle, by closest points (Ericson, Real-Time
// Collision Detection, 5.1.5 and 5.1.9), not using the code under test.

/// The point of triangle `abc` nearest to `p` (all in m).
fn closest_on_triangle(
    p: &Point3<f64>,
    a: &Point3<f64>,
    b: &Point3<f64>,
    c: &Point3<f64>,
) -> Point3<f64> {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Distance between the segments `p1 q1` and `p2 q2` (m).
fn segment_segment_distance(
    p1: &Point3<f64>,
    q1: &Point3<f64>,
    p2: &Point3<f64>,
    q2: &Point3<f64>,
) -> f64 {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.norm_squared(), d2.norm_squared(), d2.dot(&r));
    let (s, t);
    if a <= f64::EPSILON * f64::EPSILON && e <= f64::EPSILON * f64::EPSILON {
        return r.norm();
    }
    if a <= f64::EPSILON * f64::EPSILON {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if e <= f64::EPSILON * f64::EPSILON {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let s0 = if denom > 0.0 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            } else {
                t = t0;
                s = s0;
            }
        }
    }
    ((p1 + d1 * s) - (p2 + d2 * t)).norm()
}

/// Distance between the segment `p q` and the triangle `tri` (m): zero where the
/// segment pierces the triangle, otherwise the least of its end points to the triangle
/// and of the segment to the triangle's three edges.
fn segment_triangle_distance(p: &Point3<f64>, q: &Point3<f64>, tri: &[Point3<f64>; 3]) -> f64 {
    let [a, b, c] = tri;
    let point = |x: &Point3<f64>| (x - closest_on_triangle(x, a, b, c)).norm();
    let mut best = point(p).min(point(q));
    for (u, v) in [(a, b), (b, c), (c, a)] {
        best = best.min(segment_segment_distance(p, q, u, v));
    }
    // Where the segment crosses the triangle's plane, the crossing point's distance
    // (zero inside the triangle).
    let n = (b - a).cross(&(c - a));
    let (dp, dq) = (n.dot(&(p - a)), n.dot(&(q - a)));
    if n.norm() > 0.0 && dp * dq <= 0.0 && dp != dq {
        let x = p + (q - p) * (dp / (dp - dq));
        best = best.min(point(&x));
    }
    best
}

/// The smallest distance (m) of the centreline of `state`'s rod 0 (vertices and
/// edges) to any triangle of `scene`, and the name of the object where it occurs.
fn brute_force_clearance(
    positions: &[Vector3<f64>],
    scene: &[(&'static str, TriangleMesh)],
) -> (f64, &'static str) {
    let mut best = (f64::INFINITY, "");
    for (name, mesh) in scene {
        for t in 0..mesh.triangles.len() {
            let tri = mesh.triangle_points(t);
            for e in positions.windows(2) {
                let d = segment_triangle_distance(&Point3::from(e[0]), &Point3::from(e[1]), &tri);
                if d < best.0 {
                    best = (d, name);
                }
            }
        }
    }
    best
}

// ---------------------------------------------------------------------------------
// The family.

/// One drop case: the hose and how it is held and started.
#[derive(Clone, Debug)]
struct DropCase {
    seed: u64,
    /// Bending stiffness EI, N·m².
    bending: f64,
    /// Length over the distance between the held ends.
    slack: f64,
    /// Mass per length, kg/m.
    mass_per_length: f64,
    /// Outer radius, m.
    radius: f64,
    segments: usize,
    /// Clamped at both ends (otherwise pinned).
    clamped: bool,
}

impl DropCase {
    /// The case of `seed`: stiffness and slack cycle through {1e-3, 1e-2, 1e-1} N·m²
    /// and {1.05, 1.2, 1.4, 1.3} (all 12 pairs over seeds 0..12), clamped for seeds
    /// 0..6 and pinned after; mass, radius and segments drawn from the seed.
    fn new(seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        Self {
            seed,
            bending: [1e-3, 1e-2, 1e-1][(seed % 3) as usize],
            slack: [1.05, 1.2, 1.4, 1.3][(seed % 4) as usize],
            mass_per_length: rng.random_range(0.1..=0.5),
            radius: rng.random_range(0.004..=0.012),
            segments: rng.random_range(20..=80),
            clamped: seed < CASES / 2,
        }
    }
}

/// What one solve gave.
#[derive(Clone, Debug)]
struct Outcome {
    case: DropCase,
    converged: bool,
    termination: String,
    iterations: usize,
    coarse_iterations: usize,
    continuation_iterations: usize,
    /// Iterations whose Hessian needed damping (not positive definite, or rejected).
    shifted_iterations: usize,
    /// Contact rows carrying force.
    contacts: usize,
    /// Final residual, N.
    residual_n: f64,
    /// Wall time of the solve, s.
    seconds: f64,
    /// Brute-force clearance less the outer radius, m (negative: penetration).
    clearance_m: f64,
    /// Object nearest to the hose.
    nearest: &'static str,
    /// |Σ contact + Σ reactions + weight| / |weight|.
    imbalance: f64,
    /// Brute-force clearance of the start, less the radius, m.
    start_clearance_m: f64,
}

/// The model of `case`: ends at x = 0 and x = SPAN, 20–60 mm above z = 0 and up to
/// 40 mm off the x axis (drawn from the seed); clamps point along the chord, tilted
/// down at the start and up at the end by up to 20°.
fn model_of(case: &DropCase, rng: &mut ChaCha8Rng) -> Model {
    let a = Vector3::new(
        0.0,
        rng.random_range(-0.04..=0.04),
        rng.random_range(0.02..=0.06),
    );
    let b = Vector3::new(
        SPAN,
        rng.random_range(-0.04..=0.04),
        rng.random_range(0.02..=0.06),
    );
    let length = case.slack * (b - a).norm();
    let (ea, ga) = (1e4, 4e3);
    let section = Section::try_explicit(
        ea,
        ga,
        case.bending,
        case.bending / 1.3,
        case.mass_per_length,
        case.radius,
    )
    .unwrap();
    let chord = (b - a).normalize();
    let side = chord.cross(&Vector3::z()).normalize();
    let tilted = |angle: f64| {
        let d =
            UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(side), angle) * chord;
        UnitQuaternion::rotation_between(&Vector3::z(), &d).unwrap()
    };
    let (start, end) = if case.clamped {
        let (down, up) = (
            rng.random_range(0.0..=20f64.to_radians()),
            rng.random_range(0.0..=20f64.to_radians()),
        );
        // Rotating the chord about `side = chord × z` by a positive angle turns it
        // up (towards `side × chord ≈ z`).
        (End::clamped(a, tilted(-down)), End::clamped(b, tilted(up)))
    } else {
        (End::pinned(a), End::pinned(b))
    };
    let system = System {
        rods: vec![RodSpec {
            name: "hose".into(),
            rod: Rod::try_straight(section, length, case.segments).unwrap(),
            start,
            end,
            route: None,
        }],
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::new(0.0, 0.0, -G),
    };
    Model::try_new(system).unwrap()
}

/// The random start: the default guess (the hanging shape) swung about the chord by
/// 75°–105° to either side, the first such swing (drawn from the seed) that clears
/// the scene by 2 mm.
fn random_pose(
    model: &Model,
    rng: &mut ChaCha8Rng,
    scene: &[(&'static str, TriangleMesh)],
) -> SystemState {
    let hanging = initial_state(model.system());
    let positions = &hanging.rods[0].positions;
    let (a, b) = (positions[0], *positions.last().unwrap());
    let axis = nalgebra::Unit::new_normalize(b - a);
    let radius = model.system().rods[0].rod.section().outer_radius;
    for _ in 0..100 {
        let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
        let swing = UnitQuaternion::from_axis_angle(
            &axis,
            sign * rng.random_range(75f64.to_radians()..=105f64.to_radians()),
        );
        let mut state = hanging.clone();
        let rod = &mut state.rods[0];
        for j in 0..rod.positions.len() {
            let p = a + swing * (positions[j] - a);
            rod.set_position(j, p);
        }
        for frame in rod.frames.iter_mut() {
            *frame = swing * *frame;
        }
        let (clearance, _) = brute_force_clearance(&state.rods[0].positions, scene);
        if clearance >= radius + 0.002 {
            return state;
        }
    }
    panic!("no swing of the hanging shape clears the scene");
}

/// Solves one case with default settings and checks it independently.
fn drop_one(case: &DropCase, scene: &[(&'static str, TriangleMesh)]) -> Outcome {
    let (model, start, contact) = drop_setup(case, scene);
    let (start_clearance, _) = brute_force_clearance(&start.rods[0].positions, scene);
    let settings = SolverSettings::default();
    let started = Instant::now();
    let solution = solve_constrained(&model, &contact, start, &settings).unwrap();
    let seconds = started.elapsed().as_secs_f64();
    let report = &solution.report;
    let positions = &solution.state.rods[0].positions;
    let (clearance, nearest) = brute_force_clearance(positions, scene);
    let forces = contact
        .forces(&model, &solution.state, &solution.constraints)
        .unwrap();
    let rod = &model.system().rods[0].rod;
    let weight = model.system().gravity * rod.mass();
    let mut total = weight;
    for f in &forces {
        total += f.force_n * f.gap.normal.into_inner();
    }
    for r in model.reactions(&solution.state) {
        total += r.force;
    }
    Outcome {
        case: case.clone(),
        converged: report.converged,
        termination: format!("{:?}", report.termination),
        iterations: report.iterations,
        coarse_iterations: report.coarse_iterations,
        continuation_iterations: report.continuation_iterations,
        shifted_iterations: report.shifted_iterations,
        contacts: forces.iter().filter(|f| f.force_n > 0.0).count(),
        residual_n: report.residual.combined_n,
        seconds,
        clearance_m: clearance - case.radius,
        nearest,
        imbalance: total.norm() / weight.norm(),
        start_clearance_m: start_clearance - case.radius,
    }
}

/// The hose of `case`, its random start above the scene and contact with the scene.
fn drop_setup(
    case: &DropCase,
    scene: &[(&'static str, TriangleMesh)],
) -> (Model, SystemState, Contact) {
    // A second stream for the poses, so that changing the pose draws does not change
    // the hose.
    let mut rng = ChaCha8Rng::seed_from_u64(1000 + case.seed);
    let model = model_of(case, &mut rng);
    let start = random_pose(&model, &mut rng, scene);
    let meshes = scene
        .iter()
        .map(|(name, m)| {
            Arc::new(
                ObstacleMesh::try_from_triangles(*name, m.vertices.clone(), &m.triangles).unwrap(),
            )
        })
        .collect();
    let contact = Contact::new(meshes, Contact::default_margin_m(&model));
    (model, start, contact)
}

/// Issue 11: incremental proximity (each feature's candidate triangles kept while it
/// moves less than the slack) gives the same solve as a full mesh search at every
/// evaluation, on drops that fall, swing and slide (a third of the family: clamped and
/// pinned, coarse and fine).
#[test]
fn dropped_hoses_solve_the_same_with_incremental_proximity_as_with_full_queries() {
    let scene = scene();
    for seed in [0, 4, 7, 11] {
        let case = DropCase::new(seed);
        let (model, start, contact) = drop_setup(&case, &scene);
        let settings = SolverSettings::default();
        let solution = solve_constrained(&model, &contact, start.clone(), &settings).unwrap();
        let label = format!("drop case {seed}");
        crate::common::assert_same_as_full_queries(
            &model, &contact, start, &settings, &solution, &label,
        );
    }
}

/// The family, solved once per test binary and shared by the tests below; prints the
/// table.
fn family() -> &'static [Outcome] {
    static OUTCOMES: OnceLock<Vec<Outcome>> = OnceLock::new();
    OUTCOMES.get_or_init(|| {
        let scene = scene();
        // `STRAND_DROP_CASE=<seed>` solves one case only (to trace it).
        let only: Option<u64> = std::env::var("STRAND_DROP_CASE")
            .ok()
            .and_then(|v| v.parse().ok());
        let outcomes: Vec<Outcome> = (0..CASES)
            .filter(|seed| only.is_none_or(|o| o == *seed))
            .map(|seed| drop_one(&DropCase::new(seed), &scene))
            .collect();
        println!(
            "case  EI [N·m²]  slack  ends     ρL [kg/m]  r [mm]  edges  start gap [mm]  converged  iterations (coarse, cont., shifted)  contacts  residual [N]  clearance−r [m]  nearest    imbalance  time [s]  termination"
        );
        for o in &outcomes {
            let c = &o.case;
            println!(
                "{:>4}  {:>9.0e}  {:>5.2}  {:<7}  {:>9.3}  {:>6.1}  {:>5}  {:>14.1}  {:>9}  {:>10} ({:>3}, {:>3}, {:>3})              {:>8}  {:>12.2e}  {:>15.2e}  {:<9}  {:>9.1e}  {:>8.3}  {}",
                c.seed,
                c.bending,
                c.slack,
                if c.clamped { "clamped" } else { "pinned" },
                c.mass_per_length,
                c.radius * 1e3,
                c.segments,
                o.start_clearance_m * 1e3,
                if o.converged { "yes" } else { "NO" },
                o.iterations,
                o.coarse_iterations,
                o.continuation_iterations,
                o.shifted_iterations,
                o.contacts,
                o.residual_n,
                o.clearance_m,
                o.nearest,
                o.imbalance,
                o.seconds,
                o.termination,
            );
        }
        outcomes
    })
}

fn median_iterations(outcomes: &[Outcome]) -> usize {
    let mut iterations: Vec<usize> = outcomes.iter().map(|o| o.iterations).collect();
    iterations.sort_unstable();
    iterations[iterations.len() / 2]
}

#[test]
fn dropped_hoses_that_converge_rest_on_the_scene_without_penetration_and_in_balance() {
    let outcomes = family();
    for o in outcomes.iter().filter(|o| o.converged) {
        let seed = o.case.seed;
        assert!(
            o.clearance_m >= -1e-9,
            "case {seed}: penetrates {} by {:.3e} m",
            o.nearest,
            -o.clearance_m
        );
        assert!(
            o.imbalance <= 1e-8,
            "case {seed}: weight not balanced, {:.2e} relative",
            o.imbalance
        );
    }
    // The scene is in the way: most hoses rest on something (a taut, stiff one may
    // hang clear of it).
    let resting = outcomes.iter().filter(|o| o.contacts > 0).count();
    assert!(
        4 * resting >= 3 * outcomes.len(),
        "only {resting} of {} hoses touch the scene",
        outcomes.len()
    );
    // Most of the family converges (the target, every case within a median of
    // 25 iterations, is the test below).
    let converged = outcomes.iter().filter(|o| o.converged).count();
    assert!(
        4 * converged >= 3 * outcomes.len(),
        "only {converged} of {} converge",
        outcomes.len()
    );
}

#[test]
fn every_dropped_hose_converges_within_a_median_of_25_iterations() {
    let outcomes = family();
    let failed: Vec<u64> = outcomes
        .iter()
        .filter(|o| !o.converged)
        .map(|o| o.case.seed)
        .collect();
    let median = median_iterations(outcomes);
    println!("median iterations {median}, not converged: {failed:?}");
    assert!(failed.is_empty(), "not converged: cases {failed:?}");
    assert!(median <= 25, "median {median} iterations");
}
