//! `strand motion` and `strand solve --motion` through the real executable: outputs,
//! exit codes and messages on bad input, nothing written on invalid input.

use std::path::Path;

mod common;

use common::{case, strand};

#[test]
fn hinge_motion_writes_every_output() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("hinge");
    let (code, out, err) = strand(&[
        "motion",
        &case("door_hinge_cable.ron"),
        "--motion",
        "door",
        "--range",
        "0deg..90deg:15deg",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{out}{err}");
    let csv = std::fs::read_to_string(dir.join("motion.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(&header[..3], ["id", "door [deg]", "status"]);
    assert!(header.contains(&"door |F| [N]") && header.contains(&"cable min bend radius [mm]"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 7);
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(row[1].parse::<f64>().unwrap(), 15.0 * k as f64);
        assert_eq!(row[2], "ok");
        assert!(dir.join("steps").join(row[0]).join("result.json").is_file());
    }
    let svg = std::fs::read_to_string(dir.join("motion.svg")).unwrap();
    assert!(svg.contains("door [deg]") && svg.contains("class=\"curve\""));
    let obj = std::fs::read_to_string(dir.join("envelope.obj")).unwrap();
    assert!(obj.contains("o cable_envelope") && obj.lines().any(|l| l.starts_with("f ")));
    assert!(dir.join("events.csv").is_file());
    // One pose solved cold (`solve --motion`) agrees with the sequence's pose to
    // the solver's tolerance (the engine roll, where the cold start finds the same
    // equilibrium; on the hinge a cold start at 45° finds another one).
    let engine = case("cooler_hose_engine_roll.ron");
    let seq = tmp.path().join("roll");
    let (code, out, err) = strand(&[
        "motion",
        &engine,
        "--motion",
        "engine_roll",
        "--range",
        "0deg..4deg:2deg",
        "--out",
        seq.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{out}{err}");
    let single = tmp.path().join("single");
    let (code, out, err) = strand(&[
        "solve",
        &engine,
        "--motion",
        "engine_roll=4deg",
        "--out",
        single.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{out}{err}");
    let read = |p: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
    };
    let a = read(&single.join("result.json"));
    let b = read(&seq.join("steps/002/result.json"));
    assert_eq!(a["variant"], "engine_roll=4deg");
    assert_eq!(b["variant"], "engine_roll=4deg");
    for r in 0..3 {
        let pa = a["rods"][r]["position_m"].as_array().unwrap();
        let pb = b["rods"][r]["position_m"].as_array().unwrap();
        for (x, y) in pa.iter().zip(pb) {
            for i in 0..3 {
                assert!((x[i].as_f64().unwrap() - y[i].as_f64().unwrap()).abs() < 1e-7);
            }
        }
    }
}

#[test]
fn bad_motion_input_is_a_clear_error_with_nothing_written() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let d = dir.to_str().unwrap();
    let hinge = case("door_hinge_cable.ron");
    for (args, expect) in [
        (
            vec![
                "motion", &hinge, "--motion", "lid", "--range", "0..10:1", "--out", d,
            ],
            "no motion named 'lid' (defined: door)",
        ),
        (
            vec![
                "motion",
                &hinge,
                "--motion",
                "door",
                "--range",
                "0mm..10mm:1mm",
                "--out",
                d,
            ],
            "is in mm, but motion 'door' is measured in deg",
        ),
        (
            vec![
                "motion", &hinge, "--motion", "door", "--range", "0..90", "--out", d,
            ],
            "is not a range",
        ),
        (
            vec!["solve", &hinge, "--motion", "door", "--out", d],
            "write NAME=VALUE",
        ),
    ] {
        let (code, out, err) = strand(&args);
        assert_eq!(code, Some(2), "{args:?}: {out}{err}");
        assert!(err.contains(expect), "{args:?}: {err}");
        assert!(!dir.exists(), "{args:?} wrote {dir:?}");
    }
    // A part riding on an unknown motion, a range outside the keyframes, a pose out of
    // the rod's reach.
    let text = std::fs::read_to_string(&hinge).unwrap();
    let write = |name: &str, text: String| {
        let p = tmp.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let unknown = write(
        "unknown.ron",
        text.replace("moves_with: \"door\"", "moves_with: \"lid\""),
    );
    let (code, _, err) = strand(&["check", &unknown]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("connectors 'door'.moves_with: no motion named 'lid'"),
        "{err}"
    );
    let keyed = write(
        "keyed.ron",
        text.replace(
            "moves: [Rotate(axis: (0, 0, 1), point: (0, 0, 0))]",
            "moves: [Keyframes(frames: [(at: 0), (at: 45, rotation: (axis: (0, 0, 1), angle_deg: 45))])]",
        ),
    );
    let (code, _, err) = strand(&[
        "motion",
        &keyed,
        "--motion",
        "door",
        "--range",
        "0deg..90deg:5deg",
        "--out",
        d,
    ]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("90 deg is outside motion 'door''s keyframes (0..45 deg)"),
        "{err}"
    );
    let far = write(
        "far.ron",
        text.replace(
            "moves: [Rotate(axis: (0, 0, 1), point: (0, 0, 0))]",
            "moves: [Translate(direction: (1, 0, 0))]",
        )
        .replace(
            "unit: \"deg\", moves: [Translate",
            "unit: \"mm\", moves: [Translate",
        ),
    );
    let (code, _, err) = strand(&[
        "motion",
        &far,
        "--motion",
        "door",
        "--range",
        "0mm..200mm:10mm",
        "--out",
        d,
    ]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("at motion pose door = ") && err.contains("mm"),
        "{err}"
    );
    assert!(!dir.exists());
}

#[test]
fn a_step_that_fails_ends_the_sequence_with_the_poses_so_far() {
    // A box raised into a hanging cable under a fixed block (the same box moved up,
    // its underside at z = 40 mm): the rising box carries the cable up until there is
    // no room for it between the two (the box top at 34 mm, a lift of 64 mm), so the
    // sequence ends there with the poses before it written.
    let tmp = tempfile::tempdir().unwrap();
    let boxed = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/parts/box.obj");
    let text = r#"(
        units: (length: "mm"),
        sections: { "c": Explicit(ea: 20e3, ga: 5e3, ei: 5e-3, gj: 3.8e-3, mass_per_length: 0.1, outer_radius: 3) },
        connectors: {
            "a": (position: (0, 0, 60), direction: (1, 0, 0), normal: (0, 0, 1)),
            "b": (position: (400, 0, 60), direction: (-1, 0, 0), normal: (0, 0, 1)),
        },
        rods: [(name: "c", section: "c", length: 420, segments: 42, start: Connector("a"), end: Connector("b"))],
        environment: [
            (name: "box", obj: "BOX", unit: "mm", moves_with: "raise"),
            (name: "block", obj: "BOX", unit: "mm", position: (0, 0, 240)),
        ],
        gravity: (0, 0, -9.81),
        // A limp cable over a box edge stalls near 1e-8 N; 1e-6 N is far below its
        // weight (0.4 N).
        solver: (tolerance_n: 1e-6),
        motions: { "raise": (unit: "mm", moves: [Translate(direction: (0, 0, 1))]) },
    )"#
    .replace("BOX", boxed.to_str().unwrap());
    let path = tmp.path().join("raise.ron");
    std::fs::write(&path, text).unwrap();
    let dir = tmp.path().join("out");
    let (code, out, err) = strand(&[
        "motion",
        path.to_str().unwrap(),
        "--motion",
        "raise",
        "--range",
        "0mm..80mm:10mm",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(3), "{out}{err}");
    assert!(
        err.contains("motion 'raise' ended at") && err.contains("inside mesh 'block'"),
        "{err}"
    );
    let csv = std::fs::read_to_string(dir.join("motion.csv")).unwrap();
    let status: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(2).unwrap())
        .collect();
    assert_eq!(status.last(), Some(&"failed"), "{csv}");
    // Carried up by the box: every pose up to 60 mm is solved, the crush (no room
    // left under the block) comes before 64 mm.
    assert_eq!(status.iter().filter(|s| **s == "ok").count(), 7, "{csv}");
    let failed_at: f64 = csv
        .lines()
        .last()
        .unwrap()
        .split(',')
        .nth(1)
        .unwrap()
        .parse()
        .unwrap();
    assert!(failed_at > 60.0 && failed_at <= 64.0, "{csv}");
    for id in csv
        .lines()
        .skip(1)
        .filter(|l| l.contains(",ok,"))
        .map(|l| l.split(',').next().unwrap())
    {
        assert!(dir.join("steps").join(id).join("result.json").is_file());
    }
}
