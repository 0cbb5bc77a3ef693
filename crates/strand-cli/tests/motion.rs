//! `strand motion` and `strand solve --motion` through the real executable: outputs,
//! exit codes and messages on bad input, nothing written on invalid input.

use std::path::Path;

mod common;

use common::{case, read_json, strand};

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
    let a = read_json(&single.join("result.json"));
    let b = read_json(&seq.join("steps/002/result.json"));
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

/// The largest distance (m) between the vertices of the rods of two result documents.
fn largest_vertex_distance_m(a: &serde_json::Value, b: &serde_json::Value) -> f64 {
    let rods = a["rods"].as_array().unwrap();
    assert_eq!(rods.len(), b["rods"].as_array().unwrap().len());
    let mut largest: f64 = 0.0;
    for r in 0..rods.len() {
        let pa = a["rods"][r]["position_m"].as_array().unwrap();
        let pb = b["rods"][r]["position_m"].as_array().unwrap();
        assert_eq!(pa.len(), pb.len());
        for (x, y) in pa.iter().zip(pb) {
            let d: f64 = (0..3)
                .map(|i| (x[i].as_f64().unwrap() - y[i].as_f64().unwrap()).powi(2))
                .sum();
            largest = largest.max(d.sqrt());
        }
    }
    largest
}

#[test]
fn a_batch_at_a_motion_pose_solves_every_variant_there() {
    // `strand batch --motion engine_roll=4deg`: the `+0mm` variant is the case at
    // that pose, so it must agree with `strand solve --motion engine_roll=4deg` (the
    // moved engine mesh included: the contacts differ from the unposed case), and
    // differ from the case at its own pose.
    let tmp = tempfile::tempdir().unwrap();
    let engine = case("cooler_hose_engine_roll.ron");
    let batch = tmp.path().join("batch");
    let (code, out, err) = strand(&[
        "batch",
        &engine,
        "--vary",
        "hose2.length=+0mm,+10mm",
        "--motion",
        "engine_roll=4deg",
        "--keep",
        "results",
        "--out",
        batch.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{out}{err}");
    let solve = |extra: &[&str], dir: &Path| {
        let mut args = vec!["solve", engine.as_str(), "--out", dir.to_str().unwrap()];
        args.extend_from_slice(extra);
        let (code, out, err) = strand(&args);
        assert_eq!(code, Some(0), "{out}{err}");
        read_json(&dir.join("result.json"))
    };
    let posed = solve(&["--motion", "engine_roll=4deg"], &tmp.path().join("posed"));
    let unposed = solve(&[], &tmp.path().join("unposed"));
    let variant = read_json(&batch.join("variants/hose2.length_p0mm/result.json"));
    assert_eq!(variant["converged"], true);
    assert!(largest_vertex_distance_m(&variant, &posed) < 1e-7);
    assert_eq!(
        variant["contacts"].as_array().unwrap().len(),
        posed["contacts"].as_array().unwrap().len()
    );
    assert!(
        (variant["energy_J"].as_f64().unwrap() - posed["energy_J"].as_f64().unwrap()).abs() < 1e-9
    );
    assert!(largest_vertex_distance_m(&variant, &unposed) > 1e-4);
    // A pose the case has no motion for is a clear error, with nothing written.
    let bad = tmp.path().join("bad");
    let (code, _, err) = strand(&[
        "batch",
        &engine,
        "--vary",
        "hose2.length=+0mm,+10mm",
        "--motion",
        "door=4deg",
        "--out",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("door") && err.contains("engine_roll"), "{err}");
    assert!(!bad.exists());
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

/// A cable hanging between two fixed connectors over `assets/parts/box.obj`, which
/// rises under it (motion `raise`, mm), with `more` environment entries (`BOX` in
/// them names the box file).
fn raised_cable(more: &str) -> String {
    let boxed = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/parts/box.obj");
    r#"(
        units: (length: "mm"),
        sections: { "c": Explicit(ea: 20e3, ga: 5e3, ei: 5e-3, gj: 3.8e-3, mass_per_length: 0.1, outer_radius: 3) },
        connectors: {
            "a": (position: (0, 0, 60), direction: (1, 0, 0), normal: (0, 0, 1)),
            "b": (position: (400, 0, 60), direction: (-1, 0, 0), normal: (0, 0, 1)),
        },
        rods: [(name: "c", section: "c", length: 420, segments: 42, start: Connector("a"), end: Connector("b"))],
        environment: [(name: "box", obj: "BOX", unit: "mm", moves_with: "raise"), MORE],
        gravity: (0, 0, -9.81),
        // A limp cable over a box edge stalls near 1e-8 N; 1e-6 N is far below its
        // weight (0.4 N).
        solver: (tolerance_n: 1e-6),
        motions: { "raise": (unit: "mm", moves: [Translate(direction: (0, 0, 1))]) },
    )"#
    .replace("MORE", more)
    .replace("BOX", boxed.to_str().unwrap())
}

/// Writes [`raised_cable`] with `more` into `tmp` and runs `strand motion` on it over
/// `range` into `tmp/out`: exit code, stdout, stderr and the output folder.
fn run_raised(
    tmp: &Path,
    more: &str,
    range: &str,
) -> (Option<i32>, String, String, std::path::PathBuf) {
    let path = tmp.join("raise.ron");
    std::fs::write(&path, raised_cable(more)).unwrap();
    let dir = tmp.join("out");
    let (code, out, err) = strand(&[
        "motion",
        path.to_str().unwrap(),
        "--motion",
        "raise",
        "--range",
        range,
        "--out",
        dir.to_str().unwrap(),
    ]);
    (code, out, err, dir)
}

#[test]
fn a_step_that_fails_ends_the_sequence_with_the_poses_so_far() {
    // A box raised into a hanging cable under a fixed block (the same box moved up,
    // its underside at z = 40 mm): the rising box carries the cable up until there is
    // no room for it between the two (the box top at 34 mm, a lift of 64 mm), so the
    // sequence ends there with the poses before it written.
    let tmp = tempfile::tempdir().unwrap();
    let block = r#"(name: "block", obj: "BOX", unit: "mm", position: (0, 0, 240)),"#;
    let (code, out, err, dir) = run_raised(tmp.path(), block, "0mm..80mm:10mm");
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

/// Largest `|v|` over a JSON array of 3-vectors.
fn peak_of(values: &serde_json::Value) -> f64 {
    values
        .as_array()
        .unwrap()
        .iter()
        .map(|v| {
            let v: Vec<f64> = v
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_report_of_a_motion_shows_the_worst_poses_and_plays_them() {
    // The box rising under the hanging cable (no block above): it closes contact at
    // about 29 mm and carries the cable up after.
    let tmp = tempfile::tempdir().unwrap();
    let (code, out, err, dir) = run_raised(tmp.path(), "", "0mm..40mm:10mm");
    assert_eq!(code, Some(0), "{out}{err}");
    let html = tmp.path().join("report.html");
    let (code, out, err) = strand(&[
        "report",
        dir.to_str().unwrap(),
        "--out",
        html.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(out.contains("5 result(s)"), "{out}");
    // Independent: the worst poses from the poses' result.json files.
    let csv = std::fs::read_to_string(dir.join("motion.csv")).unwrap();
    let mut peak = (f64::NEG_INFINITY, f64::NAN);
    let mut clearance = (f64::INFINITY, f64::NAN);
    for line in csv.lines().skip(1) {
        let fields: Vec<&str> = line.split(',').collect();
        let value: f64 = fields[1].parse().unwrap();
        let doc: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join("steps").join(fields[0]).join("result.json"))
                .unwrap(),
        )
        .unwrap();
        let f = peak_of(&doc["rods"][0]["force_N"]);
        if f > peak.0 {
            peak = (f, value);
        }
        for c in doc["clearance"].as_array().unwrap() {
            let d = c["distance_m"].as_f64().unwrap() * 1e3;
            if c["with"] == "box" && d < clearance.0 {
                clearance = (d, value);
            }
        }
    }
    assert!(
        clearance.0 < 1e-3,
        "the box touches the cable: {clearance:?}"
    );
    let page = std::fs::read_to_string(&html).unwrap();
    let xml = roxmltree::Document::parse(page.strip_prefix("<!DOCTYPE html>\n").unwrap()).unwrap();
    let table = xml
        .descendants()
        .find(|n| n.attribute("id") == Some("worst-poses"))
        .expect("the worst-poses table");
    let row = |quantity: &str, item: &str| -> (f64, f64) {
        let tr = table
            .descendants()
            .filter(|n| n.has_tag_name("tr"))
            .find(|tr| {
                let cells: Vec<String> = tr
                    .children()
                    .filter(|c| c.has_tag_name("td"))
                    .map(|c| c.text().unwrap_or("").to_string())
                    .collect();
                cells.len() == 4 && cells[0] == quantity && cells[1] == item
            })
            .unwrap_or_else(|| panic!("row {quantity} {item}"));
        let cells: Vec<f64> = tr
            .children()
            .filter(|c| c.has_tag_name("td"))
            .skip(2)
            .map(|c| c.text().unwrap().parse().unwrap())
            .collect();
        (cells[0], cells[1])
    };
    let (f, at) = row("peak |f| [N]", "c");
    assert!(
        (f - peak.0).abs() <= 5e-4 * peak.0 && at == peak.1,
        "{f} at {at} vs {peak:?}"
    );
    let (d, at) = row("min clearance [mm]", "box");
    assert!((d - clearance.0).abs() <= 1e-3 + 5e-4 * clearance.0 && at == clearance.1);
    // The 3D view plays the five poses, and draws the box where each pose has it.
    let slider = xml
        .descendants()
        .find(|n| n.attribute("id") == Some("v3d-pose"))
        .expect("the pose slider");
    assert_eq!(slider.attribute("max"), Some("4"));
    assert!(
        xml.descendants()
            .any(|n| n.attribute("id") == Some("v3d-play"))
    );
    let data = xml
        .descendants()
        .find(|n| n.attribute("id") == Some("v3d-data"))
        .unwrap()
        .text()
        .unwrap();
    let scene: serde_json::Value = serde_json::from_str(data).unwrap();
    assert_eq!(scene["poses"].as_array().unwrap().len(), 5);
    assert_eq!(scene["poses"][4], "raise = 40.00 mm");
    // The box's top (z = -30 mm + lift, near the cable, so always outlined).
    let top_z = |mesh: &serde_json::Value| {
        mesh["seg"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|s| [s[2].as_f64().unwrap(), s[5].as_f64().unwrap()])
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let base = top_z(&scene["env"][0]);
    assert!((base + 30.0).abs() < 1e-6, "{base}");
    for k in 1..5 {
        let own = &scene["runs"][k]["env"][0];
        assert_eq!(own["name"], "box");
        assert!(
            (top_z(own) - base - 10.0 * k as f64).abs() < 1e-6,
            "pose {k}"
        );
    }
}
