//! Centrelines from CSV and OBJ files equal the same centreline given inline.

use std::path::Path;

use crate::{BuiltCase, Case};

/// The moulded L hose of `cases/moulded_hose.ron` (mm).
const POINTS: [[f64; 3]; 9] = [
    [0.0, 0.0, 0.0],
    [105.0, 0.0, 0.0],
    [120.5291, 2.0445, 0.0],
    [135.0, 8.0385, 0.0],
    [147.4264, 17.5736, 0.0],
    [156.9615, 30.0, 0.0],
    [162.9555, 44.4709, 0.0],
    [165.0, 60.0, 0.0],
    [165.0, 160.0, 0.0],
];

fn case(nominal: &str, extra: &str) -> String {
    format!(
        r#"(
            units: (length: "mm"),
            sections: {{ "rubber": Tube(youngs_modulus: 5e6, poisson_ratio: 0.5, density: 1100,
                                        inner_radius: 9.4, outer_radius: 12.9) }},
            rods: [(name: "hose", section: "rubber", segments: 30, nominal: {nominal},
                    start: NominalClamp(), end: NominalClamp(){extra})],
            gravity: (0, 0, -9.81),
        )"#
    )
}

fn inline() -> String {
    let points: Vec<String> = POINTS
        .iter()
        .map(|p| format!("({}, {}, {})", p[0], p[1], p[2]))
        .collect();
    format!("(points: [{}])", points.join(", "))
}

fn build_in(dir: &Path, text: &str) -> Result<BuiltCase, crate::CaseError> {
    let path = dir.join("case.ron");
    std::fs::write(&path, text).unwrap();
    Case::from_path(&path)?.build(None)
}

fn assert_same(a: &BuiltCase, b: &BuiltCase) {
    let (ra, rb) = (&a.model.system().rods[0], &b.model.system().rods[0]);
    assert_eq!(ra.rod.edge_lengths(), rb.rod.edge_lengths());
    for j in 0..=ra.rod.segments() {
        assert_eq!(ra.rod.rest_curvature(j), rb.rod.rest_curvature(j));
    }
    assert_eq!(a.initial.rods[0].positions, b.initial.rods[0].positions);
    assert_eq!(
        ra.end.support.frame().map(|q| q.coords),
        rb.end.support.frame().map(|q| q.coords)
    );
}

#[test]
fn csv_and_obj_polyline_centrelines_equal_the_inline_one() {
    let dir = tempfile::tempdir().unwrap();
    let reference = build_in(dir.path(), &case(&inline(), "")).unwrap();

    let mut csv = String::from("# hose centreline from CAD\nx_mm, y_mm, z_mm\n");
    for p in POINTS {
        csv += &format!("{},{},{}\n", p[0], p[1], p[2]);
    }
    std::fs::write(dir.path().join("hose.csv"), &csv).unwrap();
    let from_csv = build_in(dir.path(), &case(r#"(file: "hose.csv")"#, "")).unwrap();
    assert_same(&reference, &from_csv);

    // The same points in m, header `x [m]`, semicolons: equal to round-off of the unit.
    let mut metres = String::from("x [m];y [m];z [m]\n");
    for p in POINTS {
        metres += &format!("{:?};{:?};{:?}\n", p[0] / 1e3, p[1] / 1e3, p[2] / 1e3);
    }
    std::fs::write(dir.path().join("hose_m.csv"), &metres).unwrap();
    let from_m = build_in(dir.path(), &case(r#"(file: "hose_m.csv")"#, "")).unwrap();
    let (a, b) = (&reference.initial.rods[0], &from_m.initial.rods[0]);
    let worst = a
        .positions
        .iter()
        .zip(&b.positions)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max);
    assert!(worst < 1e-15, "{worst}");

    // An OBJ with another object first and the centreline as one `l` per segment.
    let mut obj = String::from("o bracket\nv 0 0 -50\nv 10 0 -50\nv 0 10 -50\nf 1 2 3\nl 1 2\n");
    obj += "o hose_centreline\n";
    for p in POINTS {
        obj += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for k in 0..POINTS.len() - 1 {
        obj += &format!("l {} {}\n", k + 4, k + 5);
    }
    std::fs::write(dir.path().join("routes.obj"), &obj).unwrap();
    let from_obj = build_in(
        dir.path(),
        &case(
            r#"(file: "routes.obj", object: "hose_centreline", unit: "mm")"#,
            "",
        ),
    )
    .unwrap();
    assert_same(&reference, &from_obj);
    // One `l` element with all points, negative (relative) indices.
    let mut single = String::from("o hose_centreline\n");
    for p in POINTS {
        single += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    let indices: Vec<String> = (1..=POINTS.len()).rev().map(|k| format!("-{k}")).collect();
    single += &format!("l {}\n", indices.join(" "));
    std::fs::write(dir.path().join("single.obj"), &single).unwrap();
    let from_single = build_in(
        dir.path(),
        &case(
            r#"(file: "single.obj", object: "hose_centreline", unit: "mm")"#,
            "",
        ),
    )
    .unwrap();
    assert_same(&reference, &from_single);

    // A route from the file equals the inline route.
    let route: Vec<String> = POINTS
        .iter()
        .map(|p| format!("({}, {}, {})", p[0], p[1], p[2]))
        .collect();
    let inline_route = build_in(
        dir.path(),
        &case(&inline(), &format!(", route: [{}]", route.join(", "))),
    )
    .unwrap();
    let file_route = build_in(
        dir.path(),
        &case(&inline(), r#", route_file: (file: "hose.csv")"#),
    )
    .unwrap();
    assert_eq!(
        inline_route.model.system().rods[0].route,
        file_route.model.system().rods[0].route
    );
    assert!(file_route.model.system().rods[0].route.is_some());
}

fn error_in(dir: &Path, nominal: &str, files: &[(&str, &str)]) -> String {
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let message = build_in(dir, &case(nominal, "")).unwrap_err().to_string();
    assert!(
        message.contains("case.ron") && message.contains("hint:"),
        "{message}"
    );
    message
}

#[test]
fn broken_centreline_files_are_errors_naming_the_field_the_file_and_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let message = error_in(
        d,
        r#"(file: "a.csv")"#,
        &[("a.csv", "x,y,z\n0,0,0\n1,0,0\n")],
    );
    assert!(
        message.contains("'hose'.nominal.file")
            && message.contains("a.csv:1")
            && message.contains("unit"),
        "{message}"
    );
    let message = error_in(
        d,
        r#"(file: "b.csv")"#,
        &[("b.csv", "x_mm,y_mm,z_mm\n0,0,0\n1,zero,0\n")],
    );
    assert!(
        message.contains("b.csv:3") && message.contains("three numbers"),
        "{message}"
    );
    let message = error_in(
        d,
        r#"(file: "c.csv")"#,
        &[("c.csv", "x_mm,y_mm,z_mm\n0,0,0\nNaN,0,0\n")],
    );
    assert!(
        message.contains("c.csv:3") && message.contains("not finite"),
        "{message}"
    );
    let message = error_in(d, r#"(file: "missing.csv")"#, &[]);
    assert!(
        message.contains("cannot read the centreline file"),
        "{message}"
    );

    let obj = "o one\nv 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nl 1 2\nl 3 4\n";
    let message = error_in(
        d,
        r#"(file: "r.obj", object: "two", unit: "mm")"#,
        &[("r.obj", obj)],
    );
    assert!(
        message.contains("object 'two'") && message.contains("objects in the file: one"),
        "{message}"
    );
    let message = error_in(d, r#"(file: "r.obj", object: "one", unit: "mm")"#, &[]);
    assert!(
        message.contains("r.obj:7") && message.contains("not connected"),
        "{message}"
    );
    let message = error_in(d, r#"(file: "r.obj", object: "one")"#, &[]);
    assert!(
        message.contains("nominal.unit") && message.contains("OBJ files carry no unit"),
        "{message}"
    );
    let message = error_in(d, r#"(points: [(0, 0, 0), (1, 0, 0)], file: "a.csv")"#, &[]);
    assert!(message.contains("both `points` and `file`"), "{message}");
}

/// The bundled moulded clipped hose with its clips placed by `at` or `at_point`.
fn clipped(clips: &str) -> Result<BuiltCase, crate::CaseError> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/moulded_clipped_hose.ron");
    let text = std::fs::read_to_string(&path).unwrap();
    let start = text.find("    clips: {").unwrap();
    let end = start + text[start..].find("    },\n").unwrap() + "    },\n".len();
    let text = format!(
        "{}    clips: {{ {clips} }},\n{}",
        &text[..start],
        &text[end..]
    );
    Case::from_str(&text, path.to_str().unwrap())?.build(None)
}

#[test]
fn clip_points_are_projected_onto_the_nominal_centreline() {
    // On the second leg (x = 210 mm, along +y from y = 60 mm, which starts at arc length
    // 150 + 30π mm): 5 mm off the centreline, at y = 150 mm.
    let station = 150.0 + 30.0 * std::f64::consts::PI + 90.0;
    let by_station = clipped(&format!(
        r#""c": (rod: "hose", at: {station:?}, joint: Fixed)"#
    ))
    .unwrap();
    let by_point = clipped(r#""c": (rod: "hose", at_point: (213, 150, 4), joint: Fixed)"#).unwrap();
    assert_eq!(by_point.clip_projections.len(), 1);
    let (name, distance) = &by_point.clip_projections[0];
    assert_eq!(name, "c");
    assert!((distance - 5e-3).abs() < 1e-9, "{distance}");
    let (a, b) = (
        &by_station.model.system().clips[0],
        &by_point.model.system().clips[0],
    );
    assert_eq!(a.vertex, b.vertex);
    // The clip holds the nearest point of the curve: 5 mm from the given point, the
    // offset normal to the curve's tangent there.
    let offset = nalgebra::Vector3::new(0.213, 0.150, 0.004) - b.base.position;
    assert!((offset.norm() - 5e-3).abs() < 1e-9, "{offset}");
    let tangent = b.base.orientation * nalgebra::Vector3::z();
    // (a3 of the clip frame: the discrete nominal frame, along the curve to 1e-7.)
    assert!(
        offset.dot(&tangent).abs() < 1e-6 * offset.norm(),
        "{}",
        offset.dot(&tangent)
    );
    // The same place as the CAD arc length (the smooth curve's arc length through the
    // bend given every 15° differs from the CAD arc's 30π mm by a few µm).
    assert!((a.base.position - b.base.position).norm() < 1e-5);
    assert!(a.base.orientation.angle_to(&b.base.orientation) < 1e-4);
    // 20 mm off: outside the hose (outer radius 12.9 mm).
    let message = clipped(r#""c": (rod: "hose", at_point: (230, 150, 0), joint: Fixed)"#)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("clips 'c'.at_point")
            && message.contains("20.000000 mm from the nominal centreline"),
        "{message}"
    );
}
