//! Tests of collecting and writing results.

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::{Rod, Section};
use strand_solve::{SolverSettings, solve};
use strand_system::{End, Model, RodSpec, System, initial_state};

use crate::*;

/// A small hand-made rod result (3 vertices along x).
pub(crate) fn sample_rod() -> RodResult {
    let v = |x: f64| [x, 0.0, 0.0];
    RodResult {
        name: "rod".into(),
        length_m: 1.0,
        segments: 2,
        s_m: vec![0.0, 0.5, 1.0],
        position_m: vec![v(0.0), v(0.5), v(1.0)],
        force_n: vec![v(1.0); 3],
        moment_nm: vec![v(0.0); 3],
        tangential_force_n: vec![1.0; 3],
        shear_force_n: vec![0.0; 3],
        bending_moment_nm: vec![0.0; 3],
        torsion_nm: vec![0.0; 3],
        total_moment_nm: vec![v(0.0); 3],
        hamiltonian_n: vec![1.0; 3],
        curvature_1pm: vec![v(0.0); 3],
        edge_force_n: vec![v(1.0); 2],
        section_frames_wxyz: Vec::new(),
        outer_radius_m: Some(0.01),
        mass_kg: Some(0.25),
        min_bend_radius_m: None,
        min_clearance_m: None,
        section: None,
        inner_radius_m: None,
        clearance_m: Vec::new(),
    }
}

/// A solved propped cantilever: clamped at the origin along +x, pinned end pushed up.
fn solved_doc() -> ResultDoc {
    let section = Section::try_explicit(3e4, 1e4, 1.0, 1.0, 0.0, 0.0).unwrap();
    let clamp = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let system = System {
        rods: vec![RodSpec {
            name: "beam".into(),
            rod: Rod::try_straight(section, 1.0, 8).unwrap(),
            start: End::clamped(Vector3::zeros(), clamp),
            end: End::pinned(Vector3::new(0.95, 0.2, 0.0)),
            route: None,
        }],
        bodies: vec![],
        clips: Vec::new(),
        gravity: Vector3::zeros(),
    };
    let model = Model::try_new(system).unwrap();
    let solution = solve(
        &model,
        initial_state(model.system()),
        &SolverSettings::default(),
    )
    .unwrap();
    collect(
        "beam_case",
        &model,
        &solution,
        Timing {
            solve: solution.report.solve_seconds,
            ..Timing::default()
        },
    )
}

fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn collected_document_is_consistent() {
    let doc = solved_doc();
    assert!(doc.converged, "{doc:?}");
    assert_eq!(doc.termination, "converged");
    assert_eq!(doc.rods.len(), 1);
    let rod = &doc.rods[0];
    assert_eq!(rod.s_m.len(), 9);
    assert_eq!(rod.position_m.len(), 9);
    assert_eq!(rod.edge_force_n.len(), 8);
    assert_eq!(doc.reactions.len(), 2);
    let (a, b) = (&doc.reactions[0], &doc.reactions[1]);
    assert_eq!(
        (a.end.as_str(), b.end.as_str(), a.kind.as_str()),
        ("start", "end", "connector")
    );
    assert_eq!(b.moment_nm, [0.0; 3], "a pin carries no moment");
    // Without distributed loads the support forces balance.
    for k in 0..3 {
        assert!((a.force_n[k] + b.force_n[k]).abs() < 1e-6, "{a:?} {b:?}");
    }
    assert!(doc.timing_s.total >= doc.timing_s.post);
}

#[test]
fn writes_json_and_csv_and_reads_back() {
    let doc = solved_doc();
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("nested/out");
    let written = write_results(&dir, &doc).unwrap();
    assert_eq!(
        written,
        vec![
            dir.join("beam.csv"),
            dir.join("rods.vtp"),
            dir.join("tubes.obj"),
            dir.join("tubes.stl"),
            dir.join("result.json")
        ]
    );
    assert_eq!(
        listing(&dir),
        vec![
            "beam.csv",
            "result.json",
            "rods.vtp",
            "tubes.obj",
            "tubes.stl"
        ],
        "no temporary files remain"
    );
    let text = std::fs::read_to_string(dir.join("result.json")).unwrap();
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    for key in [
        "case",
        "converged",
        "termination",
        "residual_N",
        "moment_residual_Nm",
        "iterations",
        "stable",
        "energy_J",
    ] {
        assert!(value.get(key).is_some(), "missing key {key}");
    }
    assert!(value["timing_s"]["solve"].is_number() && value["timing_s"]["total"].is_number());
    assert_eq!(
        value["rods"][0]["position_m"][8].as_array().unwrap().len(),
        3
    );
    // serde_json's default float parser may be 1 ulp off; the writer itself is exact.
    let back: ResultDoc = serde_json::from_str(&text).unwrap();
    assert_eq!(
        (back.case.as_str(), back.converged, back.iterations),
        ("beam_case", true, doc.iterations)
    );
    for (p, q) in back.rods[0].position_m.iter().zip(&doc.rods[0].position_m) {
        assert!((0..3).all(|k| (p[k] - q[k]).abs() <= 1e-15), "{p:?} {q:?}");
    }
    let csv = std::fs::read_to_string(dir.join("beam.csv")).unwrap();
    assert_eq!(csv.lines().count(), 10);
    assert!(csv.starts_with("s_m,x_m,y_m,z_m,fx_N,"));
}

#[test]
fn failed_write_leaves_nothing_half_written() {
    let doc = solved_doc();
    let tmp = tempfile::tempdir().unwrap();
    // A directory where the CSV should go makes the rename fail in the commit phase.
    std::fs::create_dir(tmp.path().join("beam.csv")).unwrap();
    let err = write_results(tmp.path(), &doc).unwrap_err();
    assert!(err.to_string().contains("beam.csv"), "{err}");
    assert_eq!(
        listing(tmp.path()),
        vec!["beam.csv"],
        "no result.json, no temporary files"
    );
    // A file where the directory should be fails before anything is staged.
    let blocker = tmp.path().join("file");
    std::fs::write(&blocker, "x").unwrap();
    assert!(matches!(
        write_results(&blocker.join("out"), &doc),
        Err(ReportError::Io { .. })
    ));
}

#[test]
fn unsafe_rod_names_are_refused() {
    let mut doc = solved_doc();
    doc.rods[0].name = "../evil".into();
    let tmp = tempfile::tempdir().unwrap();
    assert!(matches!(
        write_results(&tmp.path().join("o"), &doc),
        Err(ReportError::UnsafeName(_))
    ));
    assert!(!tmp.path().join("o").exists());
    assert!(is_safe_name("hose_2.a-b") && !is_safe_name(".hidden") && !is_safe_name(""));
}

#[test]
fn atomic_single_file() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("a.txt");
    write_atomic(&path, b"one").unwrap();
    write_atomic(&path, b"two").unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "two");
    assert_eq!(listing(tmp.path()), vec!["a.txt"]);
}

/// Two rods hanging a free 0.5 kg body between clamps: "in" ends at its port "a",
/// "out" starts at its port "b"; a third rod "solo" has no port.
fn junction_model() -> (Model, strand_solve::Solution) {
    use strand_system::{BodyHandle, BodySpec, EndLoad, Port, Pose, Support};
    let section = Section::try_explicit(3e4, 1e4, 1.0, 1.0, 0.1, 0.0).unwrap();
    let along_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let port = |name: &str, sign: f64| Port {
        name: name.into(),
        position: Vector3::new(sign * 0.02, 0.0, 0.0),
        frame: if sign > 0.0 {
            along_x
        } else {
            along_x * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
        },
    };
    let at_port = |port| End {
        support: Support::Port {
            body: BodyHandle(0),
            port,
            clamped: true,
        },
        load: EndLoad::default(),
        twist_turns: 0,
    };
    let rod = |length| Rod::try_straight(section, length, 6).unwrap();
    let system = System {
        rods: vec![
            RodSpec {
                name: "in".into(),
                rod: rod(0.5),
                start: End::clamped(Vector3::new(-0.5, 0.0, 0.0), along_x),
                end: at_port(0),
                route: None,
            },
            RodSpec {
                name: "out".into(),
                rod: rod(0.5),
                start: at_port(1),
                end: End::pinned(Vector3::new(0.5, 0.0, 0.0)),
                route: None,
            },
            RodSpec {
                name: "solo".into(),
                rod: rod(0.3),
                start: End::clamped(Vector3::new(0.0, 1.0, 0.0), along_x),
                end: End::free(),
                route: None,
            },
        ],
        bodies: vec![BodySpec {
            name: "tee".into(),
            mass: 0.5,
            center_of_mass: Vector3::zeros(),
            pose: Pose {
                position: Vector3::zeros(),
                orientation: UnitQuaternion::identity(),
            },
            fixed: false,
            ports: vec![port("a", -1.0), port("b", 1.0)],
        }],
        clips: Vec::new(),
        gravity: Vector3::new(0.0, 0.0, -9.81),
    };
    let model = Model::try_new(system).unwrap();
    let solution = solve(
        &model,
        initial_state(model.system()),
        &SolverSettings::default(),
    )
    .unwrap();
    assert!(solution.report.converged, "{:?}", solution.report);
    (model, solution)
}

#[test]
fn bodies_ports_and_named_connectors_are_reported() {
    let (model, solution) = junction_model();
    let mut doc = collect("tee_case", &model, &solution, Timing::default());
    assert_eq!(doc.bodies.len(), 1);
    let body = &doc.bodies[0];
    let pose = solution.state.bodies[0];
    assert_eq!(
        (body.name.as_str(), body.fixed, body.mass_kg),
        ("tee", false, 0.5)
    );
    assert_eq!(
        body.position_m,
        [pose.position.x, pose.position.y, pose.position.z]
    );
    assert!(pose.position.z < -1e-3, "the body hangs: {pose:?}");
    let [w, x, y, z] = body.orientation_quaternion_wxyz;
    assert!(((w * w + x * x + y * y + z * z) - 1.0).abs() < 1e-12);
    let matrix = pose.orientation.to_rotation_matrix().into_inner();
    for (i, row) in body.rotation_matrix.iter().enumerate() {
        for (k, value) in row.iter().enumerate() {
            assert_eq!(*value, matrix[(i, k)]);
        }
    }
    let kinds: Vec<(&str, &str)> = doc
        .reactions
        .iter()
        .map(|r| (r.name.as_str(), r.kind.as_str()))
        .collect();
    assert_eq!(
        kinds,
        [
            ("in.start", "connector"),
            ("tee.a", "port"),
            ("tee.b", "port"),
            ("out.end", "connector"),
            ("solo.start", "connector")
        ]
    );
    name_connectors(
        &mut doc,
        &[
            [Some("radiator".into()), None],
            [None, Some("engine".into())],
            [None, None],
        ],
    );
    let names: Vec<&str> = doc.reactions.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(
        names,
        ["radiator", "tee.a", "tee.b", "engine", "solo.start"]
    );
    // The document round-trips through JSON with its bodies.
    let json = serde_json::to_string(&doc).unwrap();
    let back: ResultDoc = serde_json::from_str(&json).unwrap();
    assert_eq!(back.bodies, doc.bodies);
    let value: serde_json::Value = serde_json::from_str(&json).unwrap();
    for key in [
        "name",
        "fixed",
        "position_m",
        "orientation_quaternion_wxyz",
        "rotation_matrix",
        "mass_kg",
    ] {
        assert!(
            value["bodies"][0].get(key).is_some(),
            "missing bodies[0].{key}"
        );
    }
}

#[test]
fn arc_length_is_measured_from_the_junction() {
    let (model, _) = junction_model();
    let origins: Vec<ArcOrigin> = (0..3).map(|r| arc_origin(&model, r)).collect();
    assert_eq!(
        origins,
        [ArcOrigin::End, ArcOrigin::Start, ArcOrigin::Start]
    );
}

/// A peak whose value at the base's place ties with the largest (to rounding) keeps
/// the base's place as its arg: only a clear change of place marks it one-sided.
#[test]
fn a_peak_tied_at_the_pinned_place_keeps_it_as_its_arg() {
    let mut doc = solved_doc();
    let rod = &mut doc.rods[0];
    let n = rod.force_n.len();
    assert!(n > 4);
    let peak = 10.0;
    rod.force_n.iter_mut().for_each(|f| *f = [1.0, 0.0, 0.0]);
    rod.force_n[1] = [peak, 0.0, 0.0];
    let name = format!("{}.peak_force_N", rod.name);
    let pins = design_outputs(&doc, None);
    let base = pins.iter().find(|o| o.name == name).unwrap().clone();
    assert_eq!(base.arg, 1);
    let arg_with = |other: f64| {
        let mut moved = doc.clone();
        moved.rods[0].force_n[3] = [other, 0.0, 0.0];
        let out = design_outputs(&moved, Some(&pins));
        let o = out.into_iter().find(|o| o.name == name).unwrap();
        assert_eq!(o.value, peak, "read at the pinned place");
        o.arg
    };
    // Larger by rounding only: the base's place; by more than `ARG_TIE`: the new one.
    assert_eq!(arg_with(peak * (1.0 + 1e-13)), 1);
    assert_eq!(arg_with(peak * (1.0 + 0.5 * ARG_TIE)), 1);
    assert_eq!(arg_with(peak * (1.0 + 10.0 * ARG_TIE)), 3);
}
