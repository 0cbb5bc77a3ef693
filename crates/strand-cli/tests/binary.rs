//! The real `strand` executable: exit codes through the process boundary, messages on
//! stderr, no panic output on bad input.

mod common;

use common::{case, read_json, strand};

#[test]
fn binary_reports_exit_codes_and_errors() {
    let (code, out, _) = strand(&["check", &case("elastica_fig2.ron")]);
    assert_eq!(code, Some(0), "{out}");

    let tmp = tempfile::tempdir().unwrap();
    let bad = tmp.path().join("bad.ron");
    std::fs::write(&bad, "(units: (length: \"mm\"),,)").unwrap();
    let out_dir = tmp.path().join("out");
    let (code, out, err) = strand(&[
        "solve",
        bad.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(2), "{out}{err}");
    assert!(
        err.starts_with(&format!("error: {}:1:", bad.display())),
        "{err}"
    );
    assert!(!err.contains("panicked") && !out_dir.exists(), "{err}");

    let (code, _, err) = strand(&["solve"]);
    assert_eq!(code, Some(2), "{err}");

    let stopped = tmp.path().join("stopped.ron");
    let text = std::fs::read_to_string(case("elastica_fig3_load.ron")).unwrap();
    std::fs::write(
        &stopped,
        text.replace("solver: (tolerance_n: 1e-9)", "solver: (max_iterations: 1)"),
    )
    .unwrap();
    let (code, _, err) = strand(&[
        "solve",
        stopped.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(3), "{err}");
    assert!(out_dir.join("result.json").exists() && out_dir.join("rod.csv").exists());
}

#[test]
fn check_and_solve_agree_on_a_start_bowed_around_a_part() {
    // The bundled cable whose hanging guess passes through a box under its connectors:
    // `check` accepts it and `solve` converges, both saying which start they take.
    let file = case("cable_over_box.ron");
    let start = "start       bowed sideways";
    let (code, out, err) = strand(&["check", &file]);
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(out.contains(start), "{out}");
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let (code, out, err) = strand(&["solve", &file, "--out", dir.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(out.contains(start), "{out}");
    assert!(out.contains("converged   yes"), "{out}");
}

#[test]
fn the_bundled_groove_case_rests_on_both_flanks_in_balance() {
    // cases/hose_in_groove.ron: a 2 kg/m, r = 10 mm hose, 1.06 m, hanging from two
    // connectors into a 90° V-groove (crease along x at y = z = 0). Checked from
    // result.json alone, against statics and the groove's geometry.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let (code, out, err) = strand(&[
        "solve",
        &case("hose_in_groove.ron"),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{out}{err}");
    let text = std::fs::read_to_string(dir.join("result.json")).unwrap();
    let result: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(result["converged"], true);
    let vector = |v: &serde_json::Value| -> [f64; 3] {
        let a = v.as_array().unwrap();
        [0, 1, 2].map(|i| a[i].as_f64().unwrap())
    };
    // Connectors (forces on the rod) + contacts (force along the normal, on the rod)
    // balance the weight 2 kg/m · 1.06 m · 9.81 m/s².
    let weight = 2.0 * 1.06 * 9.81;
    let mut total = [0.0, 0.0, -weight];
    for reaction in result["reactions"].as_array().unwrap() {
        let f = vector(&reaction["force_N"]);
        (0..3).for_each(|i| total[i] += f[i]);
    }
    let (mut left, mut right) = (0.0, 0.0);
    for contact in result["contacts"].as_array().unwrap() {
        let n = vector(&contact["normal"]);
        let f = contact["force_N"].as_f64().unwrap();
        (0..3).for_each(|i| total[i] += f * n[i]);
        // Every contact is on a flank: normal (0, ±sin 45°, cos 45°).
        let s = std::f64::consts::FRAC_1_SQRT_2;
        assert!(n[0].abs() < 1e-9 && (n[1].abs() - s).abs() < 1e-9 && (n[2] - s).abs() < 1e-9);
        if n[1] > 0.0 {
            left += f;
        } else {
            right += f;
        }
    }
    for (i, t) in total.iter().enumerate() {
        assert!(t.abs() <= 1e-9 * weight, "net force {i}: {t} N");
    }
    // Both flanks carry load, equally (the case is mirror-symmetric about y = 0).
    assert!(left > 0.1 * weight, "{left} N");
    assert!((left - right).abs() <= 1e-9 * left, "{left} N vs {right} N");
    // No centreline vertex closer than the radius to either flank's plane.
    let s = std::f64::consts::FRAC_1_SQRT_2;
    for p in result["rods"][0]["position_m"].as_array().unwrap() {
        let p = vector(p);
        let nearest = ((p[1] + p[2]) * s).min((p[2] - p[1]) * s);
        assert!(nearest >= 0.01 - 1e-12, "{p:?} is {nearest} m from a flank");
    }
}

#[test]
fn a_cable_along_a_groove_lists_its_largest_contacts_and_a_count_per_rod() {
    // Hundreds of contacts along a fine hose: the terminal shows the twelve largest
    // forces and one line per rod, not a line per contact.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let (code, out, err) = strand(&[
        "solve",
        &case("hose_in_groove.ron"),
        "--segments",
        "1000",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{out}{err}");
    let result = read_json(&dir.join("result.json"));
    let contacts = result["contacts"].as_array().unwrap();
    assert!(contacts.len() > 100, "{} contacts", contacts.len());
    let listed: Vec<&str> = out
        .lines()
        .filter(|l| l.starts_with("  hose at s ="))
        .collect();
    assert_eq!(listed.len(), 12, "{out}");
    assert!(
        out.contains(&format!("contacts    {}, the 12 largest", contacts.len())),
        "{out}"
    );
    // The twelve are the largest forces of result.json.
    let mut forces: Vec<f64> = contacts
        .iter()
        .map(|c| c["force_N"].as_f64().unwrap())
        .collect();
    forces.sort_by(|a, b| b.total_cmp(a));
    let least_listed = listed
        .iter()
        .map(|l| {
            // "… mm  1.9876 N along (…)": the number before " N along".
            let before = l.split(" N along").next().unwrap();
            before.rsplit(' ').next().unwrap().parse::<f64>().unwrap()
        })
        .fold(f64::INFINITY, f64::min);
    assert!(
        (least_listed - forces[11]).abs() <= 1e-5 * forces[11],
        "{least_listed} vs {}",
        forces[11]
    );
    let total: f64 = forces.iter().sum();
    let per_rod = out
        .lines()
        .find(|l| l.starts_with(&format!("  hose: {} contacts from s =", contacts.len())))
        .unwrap_or_else(|| panic!("no count line:\n{out}"));
    assert!(per_rod.contains("(all in result.json)"), "{per_rod}");
    let summed: f64 = per_rod
        .split("summing to ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(
        (summed - total).abs() <= 1e-5 * total,
        "{summed} vs {total}"
    );
}

#[test]
fn a_rod_too_short_for_its_supports_is_solved_with_a_warning_that_it_is_stretched() {
    // The bundled 800 mm cable between pins 640 mm apart hangs slack: no warning. At
    // 590 mm it must stretch 8.5 % to reach them, at a tension no cable carries by
    // design: solved (the ends are within the 10 % the input check allows), warned.
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(case("pinned_cable.ron")).unwrap();
    assert!(text.contains("length: 800,"));
    let short = tmp.path().join("short.ron");
    std::fs::write(&short, text.replace("length: 800,", "length: 590,")).unwrap();
    let run = |file: &str| {
        let dir = tmp.path().join("out");
        strand(&["solve", file, "--out", dir.to_str().unwrap()])
    };
    let (code, out, err) = run(&case("pinned_cable.ron"));
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(!err.contains("stretched"), "{err}");
    let (code, out, err) = run(short.to_str().unwrap());
    assert_eq!(code, Some(0), "{out}{err}");
    let warning = err
        .lines()
        .find(|l| l.contains("rod 'cable' is stretched"))
        .unwrap_or_else(|| panic!("no warning:\n{err}"));
    // The centreline is at least the 640 mm between the pins: 8.5 % or more.
    let percent: f64 = warning
        .split("centreline is ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .unwrap()
        .parse()
        .unwrap();
    assert!(percent >= 100.0 * (640.0 / 590.0 - 1.0) - 1e-6, "{warning}");
}

#[test]
fn an_out_that_is_a_file_is_an_input_error_before_any_work() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("afile");
    std::fs::write(&file, "keep me").unwrap();
    let out = file.to_str().unwrap();
    let cooler = case("cooler_hose.ron");
    for args in [
        vec!["solve", cooler.as_str(), "--out", out],
        vec![
            "batch",
            cooler.as_str(),
            "--vary",
            "hose2.length=+0mm..+10mm:10mm",
            "--out",
            out,
        ],
        vec!["merge", tmp.path().to_str().unwrap(), "--out", out],
    ] {
        let (code, stdout, err) = strand(&args);
        assert_eq!(code, Some(2), "{args:?}: {stdout}{err}");
        assert!(
            err.contains("is a file, not a directory"),
            "{args:?}: {err}"
        );
        // Nothing solved, nothing written.
        assert!(!stdout.contains("converged"), "{stdout}");
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep me");
    }
}

#[test]
fn an_optimisation_whose_constraint_no_design_meets_ends_infeasible_without_an_optimum() {
    // A 10 m minimum bend radius: no length of hose 2 meets it. The run stops as
    // infeasible (it said "non_smooth" when the trust region collapsed with the
    // constraint violated), exit 3, and its case file does not claim to be optimal.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("opt");
    let (code, out, err) = strand(&[
        "optimize",
        &case("cooler_hose.ron"),
        "--vary",
        "hose2.length=150mm..300mm",
        "--subject-to",
        "bend_radius>=10000mm",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(3), "{out}{err}");
    let doc = read_json(&dir.join("optimum.json"));
    assert_eq!(doc["converged"], false);
    assert_eq!(doc["termination"], "infeasible", "{doc}");
    let text = std::fs::read_to_string(dir.join("cooler_hose_optimum.ron")).unwrap();
    assert!(text.starts_with("// NOT an optimum"), "{}", &text[..200]);
    // Bounds whose start cannot be built: an input error naming the file once.
    let file = case("cooler_hose.ron");
    let (code, out, err) = strand(&[
        "optimize",
        &file,
        "--vary",
        "hose2.length=10mm..20mm",
        "--out",
        tmp.path().join("short").to_str().unwrap(),
    ]);
    assert_eq!(code, Some(2), "{out}{err}");
    assert_eq!(err.matches(file.as_str()).count(), 1, "{err}");
}

#[test]
fn a_connector_within_the_hose_radius_of_a_part_is_named_with_the_support_to_move() {
    // The engine stub of `cooler_hose_contact` 15 mm up, into the engine's underside
    // by less than the hose's radius: the end vertex is outside the part but the hose
    // at its held end overlaps it whatever the route, so the error says to move the
    // support (it said to give the rod a route; found by a batch over the stub's
    // position).
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(case("cooler_hose_contact.ron")).unwrap();
    let from = r#""engine_stub": (position: (80, 265, 60),"#;
    assert_eq!(text.matches(from).count(), 1, "the case changed");
    let assets = std::path::Path::new(&case("cooler_hose_contact.ron"))
        .parent()
        .unwrap()
        .join("../assets");
    let moved = text
        .replace(from, r#""engine_stub": (position: (80, 265, 75),"#)
        .replace("\"../assets/", &format!("\"{}/", assets.display()));
    let file = tmp.path().join("stub_up.ron");
    std::fs::write(&file, moved).unwrap();
    let (code, out, err) = strand(&["check", file.to_str().unwrap()]);
    assert_eq!(code, Some(2), "{out}{err}");
    assert!(
        err.contains("rod 'hose3' starts inside mesh 'engine'"),
        "{err}"
    );
    assert!(err.contains("the hose surface overlaps it by"), "{err}");
    assert!(
        err.contains("closer to the part than the hose's radius"),
        "{err}"
    );
    assert!(!err.contains("give the rod a `route`"), "{err}");
}

#[test]
fn a_connector_inside_a_closed_part_is_named_with_the_support_to_move() {
    // The box of `cable_over_box` moved around connector 'a': no route can help, so
    // the error says the end is held inside the part (it said to give a route).
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(case("cable_over_box.ron")).unwrap();
    let box_obj = std::path::Path::new(&case("cable_over_box.ron"))
        .parent()
        .unwrap()
        .join("../assets/parts/box.obj");
    let moved = text.replace(
        r#"(name: "box", obj: "../assets/parts/box.obj", unit: "mm"),"#,
        &format!(
            r#"(name: "box", obj: "{}", unit: "mm", position: (-200, 0, 100)),"#,
            box_obj.display()
        ),
    );
    assert_ne!(moved, text);
    let file = tmp.path().join("inside.ron");
    std::fs::write(&file, moved).unwrap();
    let (code, out, err) = strand(&["check", file.to_str().unwrap()]);
    assert_eq!(code, Some(2), "{out}{err}");
    assert!(err.contains("starts inside mesh 'box'"), "{err}");
    assert!(err.contains("at s = 0.0 mm"), "{err}");
    assert!(err.contains("move its connector"), "{err}");
    assert!(!err.contains("give the rod a `route`"), "{err}");
}
