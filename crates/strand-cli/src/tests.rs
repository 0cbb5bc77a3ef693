//! Tests of the command line through [`crate::run`], the binary's only entry point.

use std::path::{Path, PathBuf};

use crate::{Exit, run};

fn case_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../cases")
        .join(name)
}

/// Runs `strand ARGS`, returning the exit status, stdout and stderr.
pub(crate) fn strand(args: &[&str]) -> (Exit, String, String) {
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let exit = run(
        std::iter::once("strand").chain(args.iter().copied()),
        &mut out,
        &mut err,
    );
    (
        exit,
        String::from_utf8(out).unwrap(),
        String::from_utf8(err).unwrap(),
    )
}

#[test]
fn exit_codes_are_stable() {
    let codes: Vec<u8> = [
        Exit::Success,
        Exit::Failure,
        Exit::InvalidInput,
        Exit::NotConverged,
    ]
    .map(Exit::code)
    .to_vec();
    assert_eq!(codes, vec![0, 1, 2, 3]);
}

#[test]
fn help_goes_to_stdout_and_usage_errors_exit_2() {
    let (exit, out, _) = strand(&["--help"]);
    assert_eq!(exit, Exit::Success);
    assert!(out.contains("solve") && out.contains("check"), "{out}");
    let (exit, _, err) = strand(&["solve"]);
    assert_eq!(exit, Exit::InvalidInput);
    assert!(err.starts_with("error:"), "{err}");
    let (exit, _, err) = strand(&["solve", "x.ron", "--segments", "0"]);
    assert_eq!(exit, Exit::InvalidInput, "{err}");
}

#[test]
fn bench_grid_is_documented_and_its_options_are_checked() {
    let (exit, out, _) = strand(&["bench", "--help"]);
    assert_eq!(exit, Exit::Success);
    for word in [
        "--grid",
        "--cases",
        "convergence map",
        "median iterations <= 20",
    ] {
        assert!(out.contains(word), "{word}: {out}");
    }
    for args in [
        &["bench", "--cases", "3"][..],
        &["bench", "--grid", "--cases", "0"],
        &["bench", "--grid", "--segments", "19"],
        &["bench", "--grid", "--repeats", "2"],
        &["bench", "cases/elastica_fig3.ron", "--grid"],
    ] {
        let (exit, _, err) = strand(args);
        assert_eq!(exit, Exit::InvalidInput, "{args:?}: {err}");
    }
}

#[test]
fn bench_grid_prints_a_line_per_case_and_the_summary() {
    // Two cases; whether they converge is the solver's business (exit 0 or 3), the
    // output's shape is ours. No timing is checked.
    let (exit, out, err) = strand(&["bench", "--grid", "--cases", "2"]);
    assert!(
        matches!(exit, Exit::Success | Exit::NotConverged),
        "{exit:?}: {err}"
    );
    let grid = crate::bench::grid::convergence_grid(2);
    for case in &grid {
        assert!(out.contains(&case.label()), "{out}");
    }
    assert!(out.contains("of 2 cases"), "{out}");
    assert!(out.contains("iterations: total "), "{out}");
    assert!(out.contains("median <= 20: "), "{out}");
    assert!(out.contains("time: median "), "{out}");
}

#[test]
fn bench_mesh_reports_the_meshes_triangles_and_a_missing_file_by_name() {
    // The engine-bay engine: the triangle count must be the mesh's own (no timing is
    // checked), the cache folder must be gone afterwards.
    let engine = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/engine_bay/engine.obj");
    let mesh = strand_contact::ObstacleMesh::load(&engine, 0.001, &nalgebra::Isometry3::identity())
        .unwrap();
    let (exit, out, err) = strand(&[
        "bench",
        "--mesh",
        engine.to_str().unwrap(),
        "--repeats",
        "2",
    ]);
    assert_eq!(exit, Exit::Success, "{err}");
    let row = out.lines().nth(2).unwrap_or_default();
    assert_eq!(
        row.split_whitespace().next(),
        Some(mesh.triangle_count().to_string().as_str()),
        "{out}"
    );
    assert!(
        out.contains("targets per 1M triangles: cold <= 400 ms"),
        "{out}"
    );
    let folder = std::env::temp_dir().join(format!("strand-bench-mesh-{}", std::process::id()));
    assert!(!folder.exists());
    let (exit, _, err) = strand(&["bench", "--mesh", "no/such/mesh.obj", "--repeats", "1"]);
    assert_eq!(exit, Exit::InvalidInput);
    assert!(err.contains("no/such/mesh.obj"), "{err}");
    let (exit, _, err) = strand(&["bench", "--mesh", "x.obj", "--grid"]);
    assert_eq!(exit, Exit::InvalidInput, "{err}");
}

#[test]
fn check_validates_without_writing() {
    let case = case_path("elastica_fig2.ron");
    let (exit, out, err) = strand(&["check", case.to_str().unwrap()]);
    assert_eq!(exit, Exit::Success, "{err}");
    assert!(
        out.starts_with("ok: ") && out.contains("111 unknowns"),
        "{out}"
    );
    let (exit, _, err) = strand(&["check", "no/such/case.ron"]);
    assert_eq!(exit, Exit::InvalidInput);
    assert!(
        err.starts_with("error: no/such/case.ron: cannot read the case file"),
        "{err}"
    );
}

#[test]
fn solve_writes_results_and_prints_a_summary() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("fig3");
    let case = case_path("elastica_fig3_load.ron");
    let (exit, out, err) = strand(&[
        "solve",
        case.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
        "--segments",
        "10",
    ]);
    assert_eq!(exit, Exit::Success, "{err}");
    for needle in [
        "case        elastica_fig3_load",
        "converged   yes",
        "stable      yes",
        " J\n",
        " ms",
        "force (-17.8, 12.8, 0) N",
        "N·m",
    ] {
        assert!(out.contains(needle), "missing {needle:?} in\n{out}");
    }
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("result.json")).unwrap()).unwrap();
    assert_eq!(doc["rods"][0]["segments"], 10);
    assert_eq!(
        std::fs::read_to_string(dir.join("rod.csv"))
            .unwrap()
            .lines()
            .count(),
        12
    );
}

#[test]
fn not_converged_exits_3_and_still_writes() {
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(case_path("elastica_fig3_load.ron")).unwrap();
    let case = tmp.path().join("stopped_early.ron");
    std::fs::write(
        &case,
        text.replace("solver: (tolerance_n: 1e-9)", "solver: (max_iterations: 1)"),
    )
    .unwrap();
    let dir = tmp.path().join("out");
    let (exit, out, err) = strand(&[
        "solve",
        case.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(exit, Exit::NotConverged, "{out}{err}");
    assert!(
        err.starts_with("warning: ") && err.contains("not converged"),
        "{err}"
    );
    assert!(out.contains("converged   no"), "{out}");
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("result.json")).unwrap()).unwrap();
    assert_eq!(doc["converged"], false);
}

#[test]
fn unwritable_output_is_exit_1() {
    let tmp = tempfile::tempdir().unwrap();
    let blocker = tmp.path().join("file");
    std::fs::write(&blocker, "x").unwrap();
    let case = case_path("elastica_fig2.ron");
    let (exit, _, err) = strand(&[
        "solve",
        case.to_str().unwrap(),
        "--out",
        blocker.join("out").to_str().unwrap(),
    ]);
    assert_eq!(exit, Exit::Failure);
    assert!(
        err.starts_with("error: ") && err.contains("results not written"),
        "{err}"
    );
}

#[test]
fn check_builds_every_variant() {
    let case = case_path("study_demo.ron");
    let (exit, out, err) = strand(&["check", case.to_str().unwrap()]);
    assert_eq!(exit, Exit::Success, "{err}");
    assert!(out.contains("; variants: plus50)"), "{out}");
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(&case).unwrap();
    let bad = tmp.path().join("bad_variant.ron");
    std::fs::write(&bad, text.replace("Add(50)", "Add(-500)")).unwrap();
    let (exit, _, err) = strand(&["check", bad.to_str().unwrap()]);
    assert_eq!(exit, Exit::InvalidInput);
    assert!(
        err.contains("variant 'plus50': rods[0] 'hose'.length: must be a finite number > 0"),
        "{err}"
    );
}
