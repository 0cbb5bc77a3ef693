//! Motion sequences (`strand_case::motion`): path following against cold solves, the
//! door-hinge reaction against a planar Reissner shooting solution written here, a
//! contact closing where the clearance extrapolates to zero, a snap-through reported,
//! and the swept envelope containing every pose's tube.

use std::path::{Path, PathBuf};

use nalgebra::{Point3, Vector3};
use strand_case::Case;
use strand_case::motion::tangent::{along, tangent};
use strand_case::motion::{
    FollowSettings, MotionEvent, MotionRange, MotionStep, Predictor, follow, jump_m,
};
use strand_report::motion::envelope_of;
use strand_report::{ResultDoc, Timing, collect, name_connectors};
use strand_tests::reference::reissner_planar::{PlanarRod, integrate_ivp};

fn cases() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases")
}

/// Every requested pose of `motion` over `range`, in the order solved.
fn run(
    case: &Case,
    motion: &str,
    range: &str,
) -> (Vec<MotionStep>, strand_case::motion::FollowEnd) {
    run_with(case, motion, range, &FollowSettings::default())
}

/// [`run`] with `settings`.
fn run_with(
    case: &Case,
    motion: &str,
    range: &str,
    settings: &FollowSettings,
) -> (Vec<MotionStep>, strand_case::motion::FollowEnd) {
    let unit = case.motion(motion).unwrap().unit;
    let range = MotionRange::parse(range, motion, &unit).unwrap();
    let mut steps = Vec::new();
    let end = follow(
        case,
        motion,
        &range.values(),
        range.step,
        None,
        settings,
        &mut |s| steps.push(s),
    )
    .unwrap();
    (steps, end)
}

#[test]
fn every_engine_roll_step_equals_a_cold_solve_at_its_pose() {
    let case = Case::from_path(cases().join("cooler_hose_engine_roll.ron")).unwrap();
    let (steps, end) = run(&case, "engine_roll", "-8deg..8deg:0.5deg");
    engine_roll_matches_cold_solves(&case, &steps, &end);
}

/// With the tangent predictor (the exact tangent combined with the previous pose, a
/// second-order prediction) every pose is the same equilibrium, in fewer Newton
/// iterations than with the secant (112 against 153 when written).
#[test]
fn the_tangent_predictor_follows_the_engine_roll_in_fewer_iterations() {
    let case = Case::from_path(cases().join("cooler_hose_engine_roll.ron")).unwrap();
    let tangent = FollowSettings {
        predictor: Predictor::Tangent,
        ..FollowSettings::default()
    };
    let (steps, end) = run_with(&case, "engine_roll", "-8deg..8deg:0.5deg", &tangent);
    engine_roll_matches_cold_solves(&case, &steps, &end);
    // The tangent is used wherever it can be computed; the secant stands in where
    // the sensitivity fails (an active contact lost within its difference step).
    let warm: Vec<(f64, usize)> = steps
        .iter()
        .filter(|s| s.warm)
        .map(|s| (s.value, s.tangent_starts))
        .collect();
    let with_tangent = warm.iter().filter(|(_, n)| *n > 0).count();
    assert!(
        4 * with_tangent >= 3 * warm.len(),
        "tangent starts per pose {warm:?}"
    );
    let secant = FollowSettings {
        predictor: Predictor::Secant,
        ..FollowSettings::default()
    };
    let (secant_steps, _) = run_with(&case, "engine_roll", "-8deg..8deg:0.5deg", &secant);
    let total = |s: &[MotionStep]| s.iter().map(|s| s.iterations).sum::<usize>();
    assert!(
        4 * total(&steps) < 5 * total(&secant_steps),
        "tangent {} vs secant {} iterations",
        total(&steps),
        total(&secant_steps)
    );
}

/// The tangent of the path at 2° against central differences of full solves at
/// 2° ± 0.01°: the first-order prediction over 0.01° misses the solved pose by a small
/// fraction of how far the pose moves.
#[test]
fn the_path_tangent_matches_differences_of_full_solves() {
    let case = Case::from_path(cases().join("cooler_hose_engine_roll.ron")).unwrap();
    let (motion, p, h) = ("engine_roll", 2.0, 0.01);
    let solve_at = |value: f64, from: &strand_system::SystemState| {
        let built = case.build_motion_from(motion, value, None, from).unwrap();
        let s = built.solve_from(from.clone(), &built.settings).unwrap();
        assert!(s.report.converged, "{value}: {:?}", s.report);
        (built, s)
    };
    let (steps, _) = run(&case, motion, "0deg..2deg:0.5deg");
    let base = steps.iter().find(|s| s.value == p).unwrap();
    let tangent = tangent(&case, motion, "deg", p, None, &base.solution).expect("a tangent");
    for sign in [1.0, -1.0] {
        let (built, solved) = solve_at(p + sign * h, &base.solution.state);
        let predicted = along(&built.model, &base.solution.state, &tangent, sign * h);
        let mut predicted = predicted;
        built.model.enforce_supports(&mut predicted);
        let moved = jump_m(&base.solution.state, &solved.state);
        let missed = jump_m(&predicted, &solved.state);
        assert!(moved > 1e-5, "the pose moves ({moved} m)");
        assert!(missed < 0.02 * moved, "missed {missed} m of {moved} m");
    }
}

/// Every pose of `steps` converged and equals a cold solve of the case built at its
/// pose (its own default guess), to 1e-7 m; most warm steps take at most 3 iterations.
fn engine_roll_matches_cold_solves(
    case: &Case,
    steps: &[MotionStep],
    end: &strand_case::motion::FollowEnd,
) {
    assert!(end.failed.is_empty(), "{:?}", end.failed);
    assert_eq!(steps.len(), 33);
    // Both directions were followed from the case's pose.
    assert!(steps.iter().any(|s| s.value < 0.0 && s.warm));
    assert!(steps.iter().any(|s| s.value > 0.0 && s.warm));
    for step in steps {
        let report = &step.solution.report;
        assert!(
            report.converged && report.residual.combined_n <= report.tolerance_n,
            "{}: {report:?}",
            step.value
        );
        let built = case.build_motion("engine_roll", step.value, None).unwrap();
        let cold = built
            .solve_from(built.initial.clone(), &built.settings)
            .unwrap();
        assert!(cold.report.converged, "cold solve at {}", step.value);
        // Equal equilibria within what the residual tolerance allows (1e-9 N against
        // stiffnesses of at least ~1 N/m).
        let d = jump_m(&cold.state, &step.solution.state);
        assert!(
            d < 1e-7,
            "pose {} deg: warm and cold states differ by {d} m",
            step.value
        );
    }
    // Warm-started steps are cheap: most take at most 3 Newton iterations.
    let warm: Vec<usize> = steps
        .iter()
        .filter(|s| s.warm)
        .map(|s| s.iterations)
        .collect();
    let easy = warm.iter().filter(|&&n| n <= 3).count();
    assert!(2 * easy > warm.len(), "iterations per step {warm:?}");
}

/// The planar Reissner solution clamped at the origin along +x whose end is at `tip`
/// with director angle `angle`: shooting on the internal force and the clamp moment
/// (Newton with a finite-difference Jacobian) from `guess = [n_x, n_y, m0]`.
fn shoot(rod: &PlanarRod, tip: [f64; 2], angle: f64, guess: [f64; 3]) -> [f64; 3] {
    let residual = |u: [f64; 3]| {
        let s = integrate_ivp(rod, [u[0], u[1]], u[2]);
        [s.tip[0] - tip[0], s.tip[1] - tip[1], s.tip_angle - angle]
    };
    let mut u = guess;
    for _ in 0..50 {
        let r = residual(u);
        if r[0].abs().max(r[1].abs()) < 1e-13 && r[2].abs() < 1e-12 {
            return u;
        }
        let mut j = nalgebra::Matrix3::zeros();
        for k in 0..3 {
            let mut v = u;
            let h = 1e-7 * u[k].abs().max(1e-3);
            v[k] += h;
            let rv = residual(v);
            for i in 0..3 {
                j[(i, k)] = (rv[i] - r[i]) / h;
            }
        }
        let du = j.lu().solve(&-Vector3::from(r)).expect("regular Jacobian");
        for k in 0..3 {
            u[k] += du[k];
        }
    }
    panic!("shooting did not converge from {guess:?}");
}

#[test]
fn door_hinge_reaction_matches_a_planar_shooting_solution() {
    // The bundled hinge case without gravity: a planar clamped–clamped elastica.
    let text = std::fs::read_to_string(cases().join("door_hinge_cable.ron")).unwrap();
    let text = text.replace("gravity: (0, 0, -9.81)", "gravity: (0, 0, 0)");
    assert!(text.contains("gravity: (0, 0, 0)"));
    let origin = cases().join("door_hinge_planar.ron");
    let case = Case::from_str(&text, origin.to_str().unwrap()).unwrap();
    let (steps, end) = run(&case, "door", "0deg..90deg:10deg");
    assert!(end.failed.is_empty(), "{:?}", end.failed);
    assert_eq!(steps.len(), 10);
    let spec = &steps[0].built.model.system().rods[0];
    let (gamma, kappa) = (
        spec.rod.section().strain_stiffness(),
        spec.rod.section().curvature_stiffness(),
    );
    let rod = PlanarRod::new(spec.rod.length(), kappa[0], gamma[0], gamma[2]);
    let mut sorted: Vec<&MotionStep> = steps.iter().collect();
    sorted.sort_by(|a, b| a.value.total_cmp(&b.value));
    for step in sorted {
        let doc = collect("door", &step.built.model, &step.solution, Timing::default());
        let mut doc = doc;
        name_connectors(&mut doc, &step.built.connector_names);
        let reaction = |name: &str| {
            doc.reactions
                .iter()
                .find(|r| r.name == name)
                .unwrap()
                .clone()
        };
        let (body, door) = (reaction("body"), reaction("door"));
        // Body clamp at (-50, 20) mm along +x; the door clamp turned by the angle about
        // the hinge at the origin, the cable entering it along the turned +x.
        let a = step.value.to_radians();
        let (s, c) = a.sin_cos();
        let door_at = [c * 0.050 - s * 0.020, s * 0.050 + c * 0.020];
        let tip = [door_at[0] + 0.050, door_at[1] - 0.020];
        // Guess: strand's start reaction (the converged reference does not depend on
        // it, but selects the equilibrium branch: from the previous angle's reference,
        // shooting across 10° can land on another equilibrium).
        let first = [-body.force_n[0], -body.force_n[1], -body.moment_nm[2]];
        let u = shoot(&rod, tip, a, first);
        // The door clamp holds the end: its force on the rod is the internal force n.
        let scale = u[0].hypot(u[1]);
        let error = (door.force_n[0] - u[0]).hypot(door.force_n[1] - u[1]);
        assert!(
            door.force_n[2].abs() < 1e-6 * scale,
            "out of plane at {}°: {:?}",
            step.value,
            door.force_n
        );
        // 60 segments: the discretisation error of the forces is O(h²) ~ 1e-3.
        assert!(
            error < 2e-3 * scale,
            "door reaction at {}°: strand ({:.6}, {:.6}) N, reference ({:.6}, {:.6}) N",
            step.value,
            door.force_n[0],
            door.force_n[1],
            u[0],
            u[1]
        );
    }
}

/// A cable hanging between two connectors above a box, lowered onto it.
const LOWERED: &str = r#"(
    units: (length: "mm"),
    sections: { "cable6": Explicit(ea: 20e3, ga: 5e3, ei: 5e-3, gj: 3.8e-3, mass_per_length: 0.1, outer_radius: 3) },
    connectors: {
        "a": (position: (0, 0, 60), direction: (1, 0, 0), normal: (0, 0, 1), moves_with: "lower"),
        "b": (position: (400, 0, 60), direction: (-1, 0, 0), normal: (0, 0, 1), moves_with: "lower"),
    },
    rods: [(name: "cable", section: "cable6", length: 420, segments: 42, start: Connector("a"), end: Connector("b"))],
    environment: [(name: "box", obj: "BOX", unit: "mm")],
    gravity: (0, 0, -9.81),
    // Contact closing on a box edge stalls near 1e-8 N; 1e-6 N is far below the
    // cable's weight (0.4 N).
    solver: (tolerance_n: 1e-6),
    motions: { "lower": (unit: "mm", moves: [Translate(direction: (0, 0, -1))]) },
)"#;

#[test]
fn contact_closes_where_the_clearance_extrapolates_to_zero() {
    let boxed = cases().join("../assets/parts/box.obj");
    let text = LOWERED.replace("BOX", boxed.to_str().unwrap());
    let case = Case::from_str(&text, cases().join("lowered.ron").to_str().unwrap()).unwrap();
    let step_mm = 5.0;
    let (steps, end) = run(&case, "lower", "0mm..80mm:5mm");
    assert!(end.failed.is_empty(), "{:?}", end.failed);
    let mut docs: Vec<(f64, ResultDoc)> = steps
        .iter()
        .map(|s| {
            let mut doc = collect("lowered", &s.built.model, &s.solution, Timing::default());
            let contact = s.built.contact().unwrap();
            strand_report::collect_contacts(&mut doc, &s.built.model, &s.solution, &contact)
                .unwrap();
            (s.value, doc)
        })
        .collect();
    docs.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Independent: the gap of the pose-0 centreline over the box top (z = -30 mm,
    // x 150..250 mm) less the radius; lowering translates the hanging cable rigidly
    // until it touches, so contact closes at that lowering.
    let p0 = &docs[0].1.rods[0].position_m;
    let gap_mm = p0
        .iter()
        .filter(|p| (0.150..=0.250).contains(&p[0]))
        .map(|p| (p[2] + 0.030) * 1e3 - 3.0)
        .fold(f64::INFINITY, f64::min);
    assert!(
        gap_mm > 2.0 * step_mm && gap_mm < 80.0 - 2.0 * step_mm,
        "gap {gap_mm} mm"
    );
    let mut events = Vec::new();
    for k in 1..docs.len() {
        let earlier = (k >= 2).then(|| (docs[k - 2].0, &docs[k - 2].1));
        events.extend(strand_report::motion::doc_events(
            earlier,
            (docs[k - 1].0, &docs[k - 1].1),
            (docs[k].0, &docs[k].1),
        ));
    }
    let closed: Vec<_> = events
        .iter()
        .filter(|e| e.kind == "contact_closed")
        .collect();
    assert_eq!(closed.len(), 1, "{events:?}");
    let e = closed[0];
    assert_eq!(e.what, "cable / box");
    assert!(
        e.between[0] < gap_mm && gap_mm <= e.between[1],
        "{e:?} vs gap {gap_mm} mm"
    );
    assert!(
        (e.at - gap_mm).abs() <= step_mm,
        "closing at {} mm, expected {gap_mm} mm",
        e.at
    );
}

/// The cable of [`LOWERED`] held still while the box below it rises into it.
const LIFTED: &str = r#"(
    units: (length: "mm"),
    sections: { "cable6": Explicit(ea: 20e3, ga: 5e3, ei: 5e-3, gj: 3.8e-3, mass_per_length: 0.1, outer_radius: 3) },
    connectors: {
        "a": (position: (0, 0, 60), direction: (1, 0, 0), normal: (0, 0, 1)),
        "b": (position: (400, 0, 60), direction: (-1, 0, 0), normal: (0, 0, 1)),
    },
    rods: [(name: "cable", section: "cable6", length: 420, segments: 42, start: Connector("a"), end: Connector("b"))],
    environment: [(name: "box", obj: "BOX", unit: "mm", moves_with: "lift")],
    gravity: (0, 0, -9.81),
    solver: (tolerance_n: 1e-6),
    motions: { "lift": (unit: "mm", moves: [Translate(direction: (0, 0, 1))]) },
)"#;

/// A moving mesh that pushes the hose: the box rises 80 mm into the hanging cable
/// (contact closes after about 40 mm, the last 40 mm the box carries the cable up).
/// Each step's last state lies inside the risen box; without carrying the cable
/// along the sequence ends there, with it every pose converges clear of the box with
/// the cable resting on its top.
#[test]
fn a_mesh_that_pushes_the_hose_carries_it_along() {
    let boxed = cases().join("../assets/parts/box.obj");
    let text = LIFTED.replace("BOX", boxed.to_str().unwrap());
    let case = Case::from_str(&text, cases().join("lifted.ron").to_str().unwrap()).unwrap();
    let stay = FollowSettings {
        carry: false,
        ..FollowSettings::default()
    };
    let (_, end) = run_with(&case, "lift", "0mm..80mm:5mm", &stay);
    assert_eq!(end.failed.len(), 1, "{:?}", end.failed);
    assert!(end.failed[0].reason.contains("inside"), "{:?}", end.failed);
    let (mut steps, end) = run(&case, "lift", "0mm..80mm:5mm");
    assert!(end.failed.is_empty(), "{:?}", end.failed);
    assert_eq!(steps.len(), 17);
    steps.sort_by(|a, b| a.value.total_cmp(&b.value));
    for s in &steps {
        assert!(
            s.solution.report.converged,
            "{}: {:?}",
            s.value, s.solution.report
        );
        // The box top is at z = -30 mm + lift; the cable (radius 3 mm) over the
        // box (x 150..250 mm) is not below it.
        let top = (-30.0 + s.value) * 1e-3;
        let over: Vec<f64> = s.solution.state.rods[0]
            .positions
            .iter()
            .filter(|p| (0.150..=0.250).contains(&p.x))
            .map(|p| p.z)
            .collect();
        let lowest = over.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(
            lowest >= top + 3e-3 - 1e-6,
            "{} mm: lowest {lowest} m, top {top} m",
            s.value
        );
        // At the last poses the box holds the cable up: it rests on the top.
        if s.value >= 70.0 {
            assert!(
                lowest <= top + 3e-3 + 1e-6,
                "{} mm: lowest {lowest} m, top {top} m",
                s.value
            );
        }
    }
}

/// A cable across the door hinge whose route comes from a CSV file (`route_file`):
/// the route's end moves with the door, so every pose builds, and the motion is the
/// one of the same route written inline.
#[test]
fn a_route_file_on_a_rod_held_by_a_moving_part_moves_with_it() {
    let inline_text = std::fs::read_to_string(cases().join("door_hinge_cable.ron")).unwrap();
    let route = "route: [(-50, 20, 0), (-30, 50, 0), (0, 62, 0), (30, 50, 0), (50, 20, 0)],";
    assert!(inline_text.contains(route));
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("route.csv"),
        "x_mm,y_mm,z_mm\n-50,20,0\n-30,50,0\n0,62,0\n30,50,0\n50,20,0\n",
    )
    .unwrap();
    let file_text = inline_text.replace(route, r#"route_file: (file: "route.csv"),"#);
    let origin = dir.path().join("door.ron");
    let from_file = Case::from_str(&file_text, origin.to_str().unwrap()).unwrap();
    let inline = Case::from_str(&inline_text, origin.to_str().unwrap()).unwrap();
    // One pose, cold: its guess ends at the moved door connector.
    let built = from_file.build_motion("door", 40.0, None).unwrap();
    let door = Vector3::new(50.0, 20.0, 0.0) * 1e-3;
    let turned =
        nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), 40f64.to_radians()) * door;
    let end = built.initial.rods[0].positions.last().unwrap();
    assert!((end - turned).norm() < 1e-9, "{end} vs {turned}");
    let (a, end_a) = run(&from_file, "door", "0deg..40deg:10deg");
    let (b, end_b) = run(&inline, "door", "0deg..40deg:10deg");
    assert!(end_a.failed.is_empty() && end_b.failed.is_empty());
    assert_eq!(a.len(), 5);
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.value, y.value);
        assert!(
            jump_m(&x.solution.state, &y.solution.state) < 1e-9,
            "{}",
            x.value
        );
    }
}

/// A strip buckled between two clamps (4 % end shortening), its right clamp turned
/// about its own point: the arch snaps through from up to down.
const SNAP: &str = r#"(
    units: (length: "mm"),
    sections: { "strip": Explicit(ea: 3e4, ga: 1e4, ei: 0.1, gj: 0.1, mass_per_length: 0, outer_radius: 1) },
    connectors: {
        "left": (position: (0, 0, 0), direction: (1, 0, 0), normal: (0, 0, 1)),
        "right": (position: (96, 0, 0), direction: (-1, 0, 0), normal: (0, 0, 1), moves_with: "turn"),
    },
    rods: [(name: "strip", section: "strip", length: 100, segments: 50,
            start: Connector("left"), end: Connector("right"),
            route: [(0, 0, 0), (24, 12, 0), (48, 16, 0), (72, 12, 0), (96, 0, 0)])],
    gravity: (0, 0, 0),
    motions: { "turn": (unit: "deg", moves: [Rotate(axis: (0, 0, 1), point: (96, 0, 0))]) },
)"#;

#[test]
fn a_snap_through_is_reported_not_jumped_silently() {
    let case = Case::from_str(SNAP, cases().join("snap.ron").to_str().unwrap()).unwrap();
    let (mut steps, end) = run(&case, "turn", "0deg..10deg:1deg");
    assert!(end.failed.is_empty(), "{:?}", end.failed);
    steps.sort_by(|a, b| a.value.total_cmp(&b.value));
    let mid_y = |s: &MotionStep| s.solution.state.rods[0].positions[25].y;
    assert!(mid_y(&steps[0]) > 0.005, "arch up at the start");
    assert!(
        mid_y(steps.last().unwrap()) < -0.005,
        "arch down at the end"
    );
    let snaps: Vec<(f64, f64, f64)> = steps
        .iter()
        .flat_map(|s| s.events.iter())
        .filter_map(|e| match e {
            MotionEvent::SnapThrough { from, to, jump_m } => Some((*from, *to, *jump_m)),
            _ => None,
        })
        .collect();
    assert_eq!(snaps.len(), 1, "{snaps:?}");
    let (from, to, jump) = snaps[0];
    // The jump is localised to the smallest step and is the arch flipping (≥ twice
    // the rise of about 10 mm).
    assert!((to - from) <= 1.0 / 64.0 + 1e-12, "{from}..{to}");
    assert!(jump > 0.015, "jump {jump} m");
    // Every pose before the snap has the arch up, every pose after it down.
    for s in &steps {
        if s.value <= from {
            assert!(mid_y(s) > 0.0, "{}", s.value);
        } else if s.value >= to {
            assert!(mid_y(s) < 0.0, "{}", s.value);
        }
    }
}

/// Whether `p` is inside the closed triangle mesh (ray parity along a skewed ray).
fn inside(p: &Vector3<f64>, vertices: &[[f64; 3]], triangles: &[[usize; 3]]) -> bool {
    let dir = Vector3::new(0.5772, 0.3319, 0.7522).normalize();
    let mut crossings = 0;
    for t in triangles {
        let [a, b, c] = t.map(|i| Vector3::from(vertices[i]));
        // Möller–Trumbore.
        let (e1, e2) = (b - a, c - a);
        let q = dir.cross(&e2);
        let det = e1.dot(&q);
        if det.abs() < 1e-18 {
            continue;
        }
        let s = p - a;
        let u = s.dot(&q) / det;
        let r = s.cross(&e1);
        let v = dir.dot(&r) / det;
        let t = e2.dot(&r) / det;
        if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0 {
            crossings += 1;
        }
    }
    crossings % 2 == 1
}

#[test]
fn envelope_is_closed_and_contains_every_tube() {
    let case = Case::from_path(cases().join("door_hinge_cable.ron")).unwrap();
    let (steps, end) = run(&case, "door", "0deg..90deg:15deg");
    assert!(end.failed.is_empty());
    let mut docs: Vec<(f64, ResultDoc)> = steps
        .iter()
        .map(|s| {
            (
                s.value,
                collect("door", &s.built.model, &s.solution, Timing::default()),
            )
        })
        .collect();
    docs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let refs: Vec<&ResultDoc> = docs.iter().map(|(_, d)| d).collect();
    let radius = 0.004;
    let env = envelope_of(&refs, "cable", radius, radius / 2.0).unwrap();
    // Closed and consistently oriented: every directed edge once, its reverse once.
    let mut edges = std::collections::HashMap::new();
    for t in &env.triangles {
        for k in 0..3 {
            *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    assert!(
        edges
            .iter()
            .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
    );
    // Every pose's tube surface, sampled on 8 generators at every vertex.
    for (value, doc) in &docs {
        let p = &doc.rods[0].position_m;
        for j in 0..p.len() {
            let (a, b) = (
                Vector3::from(p[j.saturating_sub(1)]),
                Vector3::from(p[(j + 1).min(p.len() - 1)]),
            );
            let t = (b - a).normalize();
            let n = t.cross(&Vector3::z()).normalize();
            let m = t.cross(&n);
            for k in 0..8 {
                let phi = k as f64 * std::f64::consts::FRAC_PI_4;
                let q = Vector3::from(p[j]) + (n * phi.cos() + m * phi.sin()) * radius;
                assert!(
                    inside(&q, &env.vertices, &env.triangles),
                    "pose {value}°, vertex {j}: {:?} outside",
                    Point3::from(q)
                );
            }
        }
    }
}
