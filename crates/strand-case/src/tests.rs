//! Unit tests: a valid case, and one test per kind of error.

use nalgebra::Vector3;
use strand_system::Support;

use crate::{Case, CaseError};

const ORIGIN: &str = "cases/test.ron";

/// A valid cantilever; tests replace pieces of it.
const BASE: &str = r#"// a comment
(
    units: (length: "mm"),
    sections: {
        "paper": Explicit(ea: 30e3, ga: 10e3, ei: 1, gj: 1, mass_per_length: 0),
    },
    rods: [
        (
            name: "rod",
            section: "paper",
            length: 1000,
            segments: 19,
            start: Clamp(position: (0, 0, 0), tangent: (1, 0, 0), normal: (0, 1, 0)),
            end: Free(force: (2, 1, 0)),
        ),
    ],
    gravity: (0, 0, 0),
)
"#;

fn with(from: &str, to: &str) -> String {
    assert!(BASE.contains(from), "test bug: {from:?} not in BASE");
    BASE.replacen(from, to, 1)
}

fn build_err(text: &str) -> CaseError {
    match Case::from_str(text, ORIGIN).and_then(|c| c.build(None)) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    }
}

fn message(text: &str) -> String {
    let e = build_err(text);
    let m = e.to_string();
    assert!(m.starts_with(ORIGIN), "message must name the file: {m}");
    assert!(m.contains("hint: "), "message must carry a hint: {m}");
    m
}

fn syntax(text: &str) -> (usize, usize, String) {
    match build_err(text) {
        CaseError::Syntax {
            line,
            column,
            message,
            ..
        } => (line, column, message),
        other => panic!("expected a syntax error, got {other}"),
    }
}

#[test]
fn valid_case_builds_in_si_units() {
    let case = Case::from_str(BASE, ORIGIN).unwrap();
    assert_eq!(case.name, "test");
    let built = case.build(None).unwrap();
    let spec = &built.model.system().rods[0];
    assert!((spec.rod.length() - 1.0).abs() < 1e-15);
    assert_eq!(spec.rod.segments(), 19);
    assert_eq!(spec.end.load.force, Vector3::new(2.0, 1.0, 0.0));
    assert_eq!(built.initial.rods[0].positions.len(), 20);
    assert_eq!(built.settings, strand_solve::SolverSettings::default());
    assert_eq!(
        case.build(Some(7)).unwrap().model.system().rods[0]
            .rod
            .segments(),
        7
    );
}

#[test]
fn metres_tubes_pins_routes_and_settings() {
    let text = r#"(
        units: (length: "m"),
        sections: { "rubber": Tube(youngs_modulus: 5e6, poisson_ratio: 0.5, density: 1100,
                                   inner_radius: 0.0144, outer_radius: 0.0184) },
        rods: [(name: "hose-1", section: "rubber", length: 0.4, segments: 8,
                start: Pin(position: (0, 0, 0)),
                end: Clamp(position: (0.3, 0, 0), tangent: (1, 0, 0), normal: (0, 0, 1), moment: (0, 0, 0.1)),
                route: [(0, 0, 0.001), (0.15, 0, -0.1), (0.3, 0, 0)])],
        gravity: (0, 0, -9.81),
        solver: (tolerance_n: 1e-8),
    )"#;
    let built = Case::from_str(text, "x.ron").unwrap().build(None).unwrap();
    let spec = &built.model.system().rods[0];
    assert!(spec.rod.section().mass_per_length > 0.0);
    assert!((spec.rod.section().outer_radius - 0.0184).abs() < 1e-15);
    assert_eq!(
        spec.route.as_ref().unwrap()[0],
        Vector3::zeros(),
        "route start snapped onto the pin"
    );
    assert!(matches!(spec.start.support, Support::Pinned { .. }));
    assert_eq!(built.settings.tolerance_n, 1e-8);
    assert_eq!(built.model.system().gravity.z, -9.81);
}

#[test]
fn malformed_ron_gives_line_and_column() {
    let (line, column, _) = syntax(&with("segments: 19,", "segments: 19,,"));
    assert_eq!(line, 12);
    assert!(column > 1);
    let m = message(&with("length: 1000,", "length: 1000"));
    assert!(m.starts_with("cases/test.ron:12:"), "{m}");
}

#[test]
fn missing_field_is_named() {
    let (_, _, m) = syntax(&with("segments: 19,", ""));
    assert!(m.contains("segments"), "{m}");
    assert!(message(&with("segments: 19,", "")).contains("add the field `segments`"));
}

#[test]
fn unknown_field_is_rejected() {
    let (line, _, m) = syntax(&with("segments: 19,", "segments: 19, colour: \"red\","));
    assert_eq!(line, 12);
    assert!(m.contains("colour"), "{m}");
    let (_, _, m) = syntax(&with("end: Free(force", "end: Free(forse"));
    assert!(m.contains("forse"), "{m}");
    let (_, _, m) = syntax(&with("Explicit(", "Explicit(density: 1, "));
    assert!(m.contains("density"), "{m}");
}

#[test]
fn non_positive_length_is_rejected() {
    for bad in ["-5", "0"] {
        let m = message(&with("length: 1000", &format!("length: {bad}")));
        assert!(
            m.contains("rods[0] 'rod'.length: must be a finite number > 0"),
            "{m}"
        );
        assert!(m.contains("mm"), "the message uses the file's unit: {m}");
    }
}

#[test]
fn zero_stiffness_is_rejected() {
    let m = message(&with("ei: 1,", "ei: 0,"));
    assert!(
        m.contains("sections 'paper'.ei: must be a finite number > 0 (got 0 N·m²)"),
        "{m}"
    );
}

#[test]
fn nan_and_infinity_are_rejected() {
    let m = message(&with("length: 1000", "length: NaN"));
    assert!(
        m.contains("rods[0] 'rod'.length: must be a finite number (got NaN mm)"),
        "{m}"
    );
    assert!(m.contains("hint: replace NaN/inf by a number"), "{m}");
    let m = message(&with("force: (2, 1, 0)", "force: (2, inf, 0)"));
    assert!(m.contains("rods[0] 'rod'.end.force"), "{m}");
    let m = message(&with("gravity: (0, 0, 0)", "gravity: (0, 0, NaN)"));
    assert!(m.contains("gravity"), "{m}");
}

#[test]
fn unknown_section_lists_defined_ones() {
    let m = message(&with("section: \"paper\"", "section: \"steel\""));
    assert!(
        m.starts_with(
            "cases/test.ron: rods[0] 'rod': section 'steel' is not defined (defined: paper)"
        ),
        "{m}"
    );
}

#[test]
fn duplicate_names_are_rejected() {
    let rod = &BASE[BASE.find("        (\n").unwrap()..BASE.find("    ],").unwrap()];
    let m = message(&BASE.replacen(rod, &format!("{rod}{rod}"), 1));
    assert!(
        m.contains("rods[1] 'rod': duplicate rod name (also used by rods[0])"),
        "{m}"
    );
    let section = "\"paper\": Explicit(ea: 30e3, ga: 10e3, ei: 1, gj: 1, mass_per_length: 0),";
    let (_, _, m) = syntax(&with(section, &format!("{section}\n{section}")));
    assert!(m.contains("section 'paper' is defined twice"), "{m}");
}

#[test]
fn bad_units_names_and_frames_are_rejected() {
    assert!(
        message(&with("\"mm\"", "\"cm\"")).contains("units.length: unknown length unit \"cm\"")
    );
    assert!(
        message(&with("name: \"rod\"", "name: \"a/b\""))
            .contains("rods[0].name: invalid rod name 'a/b'")
    );
    let m = message(&with("normal: (0, 1, 0)", "normal: (-3, 0, 0)"));
    assert!(
        m.contains("rods[0] 'rod'.start: the normal must not be zero or parallel to the tangent"),
        "{m}"
    );
    let m = message(&with("tangent: (1, 0, 0)", "tangent: (0, 0, 0)"));
    assert!(m.contains("tangent must be a non-zero direction"), "{m}");
}

#[test]
fn zero_segments_and_bad_settings_are_rejected() {
    assert!(message(&with("segments: 19", "segments: 0")).contains("rods[0] 'rod'.segments"));
    let m = Case::from_str(BASE, ORIGIN)
        .unwrap()
        .build(Some(0))
        .unwrap_err()
        .to_string();
    assert!(m.contains("--segments"), "{m}");
    let m = message(&with(
        "gravity: (0, 0, 0),",
        "gravity: (0, 0, 0), solver: (tolerance_n: -1),",
    ));
    assert!(
        m.contains("test.ron: solver setting 'tolerance_n' = -1"),
        "{m}"
    );
    let (_, _, m) = syntax(&with(
        "gravity: (0, 0, 0),",
        "gravity: (0, 0, 0), solver: (tolerence_n: 1),",
    ));
    assert!(m.contains("tolerence_n"), "{m}");
}

#[test]
fn tube_radii_are_checked() {
    let tube = "Tube(youngs_modulus: 5e6, poisson_ratio: 0.5, density: 1100, inner_radius: 20, outer_radius: 10)";
    let m = message(&with(
        "Explicit(ea: 30e3, ga: 10e3, ei: 1, gj: 1, mass_per_length: 0)",
        tube,
    ));
    assert!(
        m.contains("inner_radius 20 mm must be smaller than outer_radius 10 mm"),
        "{m}"
    );
    let tube = tube
        .replace("0.5", "0.7")
        .replace("inner_radius: 20", "inner_radius: 0");
    let m = message(&with(
        "Explicit(ea: 30e3, ga: 10e3, ei: 1, gj: 1, mass_per_length: 0)",
        &tube,
    ));
    assert!(m.contains("Poisson's ratio"), "{m}");
}

#[test]
fn unreachable_end_is_a_system_error_with_the_file() {
    let e = build_err(&with(
        "end: Free(force: (2, 1, 0))",
        "end: Pin(position: (2000, 0, 0))",
    ));
    assert!(matches!(e, CaseError::System { .. }));
    let m = e.to_string();
    assert!(
        m.starts_with(
            "cases/test.ron: rod 'rod' is 1.000000 m long but its ends are held 2.000000 m apart"
        ),
        "{m}"
    );
    let free_free = with(
        "start: Clamp(position: (0, 0, 0), tangent: (1, 0, 0), normal: (0, 1, 0))",
        "start: Free()",
    );
    assert!(
        build_err(&free_free)
            .to_string()
            .contains("free at both ends")
    );
}

#[test]
fn route_must_start_at_the_held_end() {
    let route = "end: Free(force: (2, 1, 0)), route: [(50, 0, 0), (1000, 0, 0)],";
    let m = message(&with("end: Free(force: (2, 1, 0)),", route));
    assert!(
        m.contains("rods[0] 'rod'.route[0]: the route's start point is 50.000000 mm away"),
        "{m}"
    );
}

#[test]
fn end_moment_is_measured_from_the_initial_end_frame() {
    let built = Case::from_str(
        &with("Free(force: (2, 1, 0))", "Free(moment: (0, 0, 0.5))"),
        ORIGIN,
    )
    .unwrap()
    .build(None)
    .unwrap();
    let load = built.model.system().rods[0].end.load;
    assert_eq!(load.moment, Vector3::new(0.0, 0.0, 0.5));
    assert!((load.moment_reference * Vector3::z() - Vector3::x()).norm() < 1e-12);
}

#[test]
fn missing_file_is_a_read_error() {
    let e = Case::from_path("cases/does_not_exist.ron").unwrap_err();
    assert!(matches!(e, CaseError::Read { .. }));
    assert_eq!(e.origin(), "cases/does_not_exist.ron");
    assert!(
        e.to_string()
            .starts_with("cases/does_not_exist.ron: cannot read the case file"),
        "{e}"
    );
}

#[test]
fn reads_from_disk() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("disk_case.ron");
    std::fs::write(&path, BASE).unwrap();
    let case = Case::from_path(&path).unwrap();
    assert_eq!(case.name, "disk_case");
    assert!(case.build(None).is_ok());
}

/// `twist_turns` reaches the end of a rod clamped at both ends.
#[test]
fn twist_turns_reach_the_clamped_end() {
    let text = with(
        "            end: Free(force: (2, 1, 0)),\n",
        "            end: Clamp(position: (1000, 0, 0), tangent: (1, 0, 0), normal: (0, 0, 1)),\n            twist_turns: -2,\n",
    );
    let built = Case::from_str(&text, ORIGIN).unwrap().build(None).unwrap();
    let spec = &built.model.system().rods[0];
    assert_eq!(spec.end.twist_turns, -2);
    assert_eq!(spec.start.twist_turns, 0);
}

/// Extra turns at a free end, a fractional number of turns and too many turns for the
/// segments are errors that say what to do.
#[test]
fn nonsense_twist_turns_are_rejected() {
    let m = message(&with(
        "            segments: 19,\n",
        "            segments: 19,\n            twist_turns: 1,\n",
    ));
    assert!(
        m.contains("twist_turns") && m.contains("both ends clamped"),
        "{m}"
    );
    let (_, _, m) = syntax(&with(
        "            segments: 19,\n",
        "            segments: 19,\n            twist_turns: 1.5,\n",
    ));
    assert!(!m.is_empty());
    let text = with(
        "            end: Free(force: (2, 1, 0)),\n",
        "            end: Clamp(position: (1000, 0, 0), tangent: (1, 0, 0), normal: (0, 0, 1)),\n            twist_turns: 5,\n",
    );
    let e = build_err(&text).to_string();
    assert!(e.contains("at least 22 segments"), "{e}");
}
