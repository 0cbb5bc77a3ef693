//! The real `strand` executable: exit codes through the process boundary, messages on
//! stderr, no panic output on bad input.

use std::path::Path;
use std::process::Command;

fn case(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../cases")
        .join(name)
        .to_str()
        .unwrap()
        .to_string()
}

fn strand(args: &[&str]) -> (Option<i32>, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_strand"))
        .args(args)
        .env_remove("RUST_BACKTRACE")
        .output()
        .unwrap();
    let text = |b: Vec<u8>| String::from_utf8(b).unwrap();
    (
        output.status.code(),
        text(output.stdout),
        text(output.stderr),
    )
}

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
