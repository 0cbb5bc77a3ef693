//! Tests of environment meshes in case files.

use std::io::Write;

use nalgebra::Point3;

use crate::Case;

/// A case file in `dir` whose environment is `environment` (RON list).
fn case_text(environment: &str) -> String {
    format!(
        r#"(
            units: (length: "mm"),
            sections: {{ "s": Explicit(ea: 1e4, ga: 1e4, ei: 1, gj: 1, mass_per_length: 0, outer_radius: 5) }},
            rods: [(name: "rod", section: "s", length: 100, segments: 4,
                    start: Clamp(position: (0, 0, 0), tangent: (1, 0, 0), normal: (0, 0, 1)),
                    end: Free())],
            gravity: (0, 0, 0),
            environment: {environment},
        )"#
    )
}

fn write(dir: &std::path::Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::File::create(&path)
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    path
}

/// A unit square (in file units) in the plane z = 0, plus one degenerate triangle.
const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 2\n";

#[test]
fn meshes_are_placed_scaled_and_shared_by_variants() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "meshes/square.obj", SQUARE);
    let case_path = write(
        dir.path(),
        "cases/c.ron",
        &case_text(
            r#"[(name: "floor", obj: "../meshes/square.obj", unit: "m", scale: 0.5,
                 position: (100, 0, -20), rotation: (axis: (0, 0, 1), angle_deg: 90))]"#,
        ),
    );
    let case = Case::from_path(&case_path).unwrap();
    let built = case.build(None).unwrap();
    assert_eq!(built.environment.len(), 1);
    let floor = &built.environment[0];
    assert_eq!((floor.name(), floor.triangle_count()), ("floor", 2));
    // 0.5 m square rotated 90° about z (x → y, y → −x), then moved by (0.1, 0, −0.02) m.
    let [min, max] = floor.bounding_box();
    assert!(
        (min - Point3::new(-0.4, 0.0, -0.02)).norm() < 1e-12,
        "{min}"
    );
    assert!((max - Point3::new(0.1, 0.5, -0.02)).norm() < 1e-12, "{max}");
    assert_eq!(
        built.environment_warnings(),
        ["environment 'floor': 1 degenerate (zero-area) triangle(s) skipped"]
    );
    // A second build and a clone of the case reuse the same mesh.
    let again = case.clone().build(Some(8)).unwrap();
    assert!(std::sync::Arc::ptr_eq(floor, &again.environment[0]));
}

#[test]
fn defaults_and_a_case_without_environment() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "square.obj", SQUARE);
    let path = write(
        dir.path(),
        "c.ron",
        &case_text(r#"[(name: "floor", obj: "square.obj", unit: "mm")]"#),
    );
    let built = Case::from_path(&path).unwrap().build(None).unwrap();
    let [min, max] = built.environment[0].bounding_box();
    assert_eq!((min, max), (Point3::origin(), Point3::new(1e-3, 1e-3, 0.0)));
    let none = write(dir.path(), "none.ron", &case_text("[]"));
    assert!(
        Case::from_path(&none)
            .unwrap()
            .build(None)
            .unwrap()
            .environment
            .is_empty()
    );
}

fn error_of(environment: &str, files: &[(&str, &str)]) -> String {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        write(dir.path(), name, text);
    }
    let path = write(dir.path(), "case.ron", &case_text(environment));
    let case = Case::from_path(&path).unwrap();
    let message = case.build(None).unwrap_err().to_string();
    assert!(message.contains("case.ron"), "{message}");
    message
}

#[test]
fn bad_entries_are_errors_naming_the_file_the_item_and_the_path() {
    let message = error_of(r#"[(name: "e", obj: "missing.obj", unit: "mm")]"#, &[]);
    assert!(
        message.contains("environment[0].obj") && message.contains("missing.obj"),
        "{message}"
    );
    assert!(message.contains("hint:"), "{message}");

    let empty = [("empty.obj", "# nothing\nv 0 0 0\n")];
    let message = error_of(r#"[(name: "e", obj: "empty.obj", unit: "mm")]"#, &empty);
    assert!(
        message.contains("no triangles") && message.contains("empty.obj"),
        "{message}"
    );

    let nan = [("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 NaN 0\nf 1 2 3\n")];
    let message = error_of(r#"[(name: "e", obj: "nan.obj", unit: "mm")]"#, &nan);
    assert!(
        message.contains("vertex 3") && message.contains("line 3"),
        "{message}"
    );

    let ok = [("s.obj", SQUARE)];
    let message = error_of(r#"[(name: "e", obj: "s.obj", unit: "cm")]"#, &ok);
    assert!(message.contains("environment[0] 'e'.unit"), "{message}");
    let message = error_of(r#"[(name: "e", obj: "s.obj", unit: "mm", scale: 0)]"#, &ok);
    assert!(message.contains("environment[0] 'e'.scale"), "{message}");
    let message = error_of(
        r#"[(name: "e", obj: "s.obj", unit: "mm", rotation: (axis: (0, 0, 0), angle_deg: 5))]"#,
        &ok,
    );
    assert!(message.contains("rotation.axis"), "{message}");
    let message = error_of(
        r#"[(name: "e", obj: "s.obj", unit: "mm"), (name: "e", obj: "s.obj", unit: "mm")]"#,
        &ok,
    );
    assert!(
        message.contains("environment[1] 'e'") && message.contains("duplicate"),
        "{message}"
    );
}

#[test]
fn stl_entries_load_like_obj_and_broken_ones_name_the_entry_and_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let square = [
        [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
        ],
        [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ],
    ];
    let mut binary = Vec::new();
    strand_contact::write_binary_stl(&mut binary, "square", &square).unwrap();
    std::fs::write(dir.path().join("square.stl"), &binary).unwrap();
    write(dir.path(), "square.obj", SQUARE);
    let path = write(
        dir.path(),
        "c.ron",
        &case_text(
            r#"[(name: "a", stl: "square.stl", unit: "m", position: (0, 0, -10)),
                (name: "b", obj: "square.obj", unit: "m", position: (0, 0, -10))]"#,
        ),
    );
    let built = Case::from_path(&path).unwrap().build(None).unwrap();
    let (a, b) = (&built.environment[0], &built.environment[1]);
    assert_eq!(a.bounding_box(), b.bounding_box());
    assert_eq!(
        a.diagnostics().boundary_edges,
        b.diagnostics().boundary_edges
    );
    assert_eq!(a.vertex_count(), 4);

    let cut = String::from_utf8_lossy(&binary[..100]).into_owned();
    let message = error_of(
        r#"[(name: "e", mesh: "cut.stl", unit: "mm")]"#,
        &[("cut.stl", cut.as_str())],
    );
    assert!(
        message.contains("environment[0].obj")
            && message.contains("cut.stl")
            && message.contains("truncated binary STL"),
        "{message}"
    );
}
