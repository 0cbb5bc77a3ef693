//! The `strand` command line end to end, through `strand_cli::run` — the function the
//! binary's `main` calls with the process's arguments, stdout and stderr.
//!
//! Bad input must give a non-zero exit code, an `error:` message on stderr naming the
//! case file (with `line:column` for syntax errors), and no output files. The happy
//! path solves the paper's position-controlled elastica (Fig. 2) and reads the written
//! files back.

use std::path::PathBuf;

use strand_cli::Exit;

use crate::common::{cases_dir, strand};

fn fig2_text() -> String {
    std::fs::read_to_string(cases_dir().join("elastica_fig2.ron")).unwrap()
}

/// `text` with `from` replaced (which must occur) by `to`.
fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "test bug: {from:?} not in the case");
    text.replacen(from, to, 1)
}

/// 1-based line of the first line containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle in text")
        + 1
}

/// Writes `text` as a case into a fresh directory, solves it with `--out`, and checks
/// the failure contract. Returns the case path and stderr.
fn solve_bad(name: &str, text: Option<&str>) -> (String, String) {
    let tmp = tempfile::tempdir().unwrap();
    let case = tmp.path().join(format!("{name}.ron"));
    if let Some(text) = text {
        std::fs::write(&case, text).unwrap();
    }
    let out_dir = tmp.path().join("out");
    let case_str = case.to_str().unwrap().to_string();
    let (exit, stdout, stderr) = strand(&["solve", &case_str, "--out", out_dir.to_str().unwrap()]);
    assert_eq!(
        exit,
        Exit::InvalidInput,
        "{name}: exit {exit:?}\n{stdout}{stderr}"
    );
    assert_ne!(exit.code(), 0);
    assert!(
        stderr.starts_with(&format!("error: {case_str}")),
        "{name}: message must name the file:\n{stderr}"
    );
    assert!(!out_dir.exists(), "{name}: no output may be written");
    let mut entries: Vec<_> = std::fs::read_dir(tmp.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    entries.retain(|n| *n != *format!("{name}.ron"));
    assert!(entries.is_empty(), "{name}: stray files {entries:?}");
    (case_str, stderr)
}

/// Asserts a syntax error at `line` (any column).
fn assert_at_line(stderr: &str, case: &str, line: usize) {
    let rest = stderr
        .strip_prefix(&format!("error: {case}:{line}:"))
        .unwrap_or_else(|| panic!("no {case}:{line}: in\n{stderr}"));
    let column: String = rest.chars().take_while(char::is_ascii_digit).collect();
    assert!(
        !column.is_empty() && rest[column.len()..].starts_with(": "),
        "no column in\n{stderr}"
    );
}

#[test]
fn malformed_ron_names_line_and_column() {
    let text = edit(&fig2_text(), "segments: 19,", "segments: 19,,");
    let (case, err) = solve_bad("malformed", Some(&text));
    assert_at_line(&err, &case, line_of(&text, "segments: 19,,"));
}

#[test]
fn missing_field_is_named() {
    let text = edit(&fig2_text(), "segments: 19,", "");
    let (case, err) = solve_bad("missing_field", Some(&text));
    assert!(err.contains("segments"), "{err}");
    assert!(err.starts_with(&format!("error: {case}:")), "{err}");
    let after = &err[format!("error: {case}:").len()..];
    assert!(
        after.chars().next().is_some_and(|c| c.is_ascii_digit()),
        "line:column expected: {err}"
    );
}

#[test]
fn unknown_field_is_rejected() {
    let text = edit(
        &fig2_text(),
        "segments: 19,",
        "segments: 19, colour: \"red\",",
    );
    let (case, err) = solve_bad("unknown_field", Some(&text));
    assert_at_line(&err, &case, line_of(&text, "colour"));
    assert!(err.contains("colour"), "{err}");
}

#[test]
fn negative_and_zero_length_are_rejected() {
    for (name, value) in [("negative_length", "-1000"), ("zero_length", "0")] {
        let text = edit(&fig2_text(), "length: 1000,", &format!("length: {value},"));
        let (case, err) = solve_bad(name, Some(&text));
        assert!(
            err.starts_with(&format!(
                "error: {case}: rods[0] 'rod'.length: must be a finite number > 0"
            )),
            "{err}"
        );
    }
}

#[test]
fn zero_stiffness_is_rejected() {
    let (case, err) = solve_bad(
        "zero_stiffness",
        Some(&edit(&fig2_text(), "ei: 1,", "ei: 0,")),
    );
    assert!(
        err.starts_with(&format!(
            "error: {case}: sections 'paper'.ei: must be a finite number > 0"
        )),
        "{err}"
    );
}

#[test]
fn nan_is_rejected() {
    let (case, err) = solve_bad(
        "nan",
        Some(&edit(&fig2_text(), "length: 1000,", "length: NaN,")),
    );
    assert!(
        err.starts_with(&format!(
            "error: {case}: rods[0] 'rod'.length: must be a finite number (got NaN mm)"
        )),
        "{err}"
    );
}

#[test]
fn unknown_section_is_rejected() {
    let (case, err) = solve_bad(
        "unknown_section",
        Some(&edit(
            &fig2_text(),
            "section: \"paper\"",
            "section: \"steel\"",
        )),
    );
    assert!(
        err.starts_with(&format!(
            "error: {case}: rods[0] 'rod': section 'steel' is not defined (defined: paper)"
        )),
        "{err}"
    );
    assert!(err.contains("hint: "), "{err}");
}

#[test]
fn pinned_end_beyond_reach_is_rejected() {
    let text = edit(
        &fig2_text(),
        "Pin(position: (980.61297, 180.66080, 0))",
        "Pin(position: (2000, 0, 0))",
    );
    let (case, err) = solve_bad("beyond_reach", Some(&text));
    assert!(
        err.starts_with(&format!(
            "error: {case}: rod 'rod' is 1.000000 m long but its ends are held 2.000000 m apart"
        )),
        "{err}"
    );
}

#[test]
fn missing_case_file_is_reported() {
    let (_, err) = solve_bad("does_not_exist", None);
    assert!(err.contains("cannot read the case file"), "{err}");
}

#[test]
fn check_accepts_every_shipped_case() {
    for name in [
        "elastica_fig2",
        "elastica_fig2_load",
        "elastica_fig3",
        "elastica_fig3_load",
        "helix_fig4",
    ] {
        let case = cases_dir().join(format!("{name}.ron"));
        let (exit, out, err) = strand(&["check", case.to_str().unwrap()]);
        assert_eq!(exit, Exit::Success, "{name}: {err}");
        assert!(out.starts_with("ok: "), "{out}");
    }
}

#[test]
fn solve_elastica_fig2_writes_consistent_results() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("fig2");
    let case = cases_dir().join("elastica_fig2.ron");
    let (exit, out, err) = strand(&[
        "solve",
        case.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(exit, Exit::Success, "{out}{err}");
    assert_eq!(exit.code(), 0);
    assert!(
        out.contains("converged   yes") && out.contains("result.json"),
        "{out}"
    );

    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("result.json")).unwrap()).unwrap();
    assert_eq!(doc["case"], "elastica_fig2");
    assert_eq!(doc["converged"], true);
    let residual = doc["residual_N"].as_f64().unwrap();
    assert!(residual <= 1e-9, "residual {residual} N");
    assert!(doc["timing_s"]["solve"].as_f64().unwrap() >= 0.0);

    let csvs: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "csv"))
        .collect();
    assert_eq!(csvs, vec![dir.join("rod.csv")]);
    let csv = std::fs::read_to_string(&csvs[0]).unwrap();
    let mut lines = csv.lines();
    assert!(
        lines
            .next()
            .unwrap()
            .starts_with("s_m,x_m,y_m,z_m,fx_N,fy_N,fz_N,")
    );
    assert_eq!(lines.count(), 20, "one data row per vertex");

    // The pin supplies the end load of the load-controlled problem, (2, 1, 0) N, up to
    // the discretisation error at 19 segments (about 7 %).
    let reactions = doc["reactions"].as_array().unwrap();
    let vector = |v: &serde_json::Value| -> [f64; 3] { [0, 1, 2].map(|k| v[k].as_f64().unwrap()) };
    let pin = reactions
        .iter()
        .find(|r| r["end"] == "end")
        .expect("reaction at the pinned end");
    assert_eq!(
        (pin["rod"].as_str(), pin["kind"].as_str()),
        (Some("rod"), Some("connector"))
    );
    let force = vector(&pin["force_N"]);
    let error = ((force[0] - 2.0).powi(2) + (force[1] - 1.0).powi(2) + force[2].powi(2)).sqrt();
    assert!(
        error <= 0.1 * 5f64.sqrt(),
        "pin reaction {force:?} N vs (2, 1, 0) N"
    );
    // No distributed load: the clamp's force balances the pin's.
    let clamp = vector(&reactions.iter().find(|r| r["end"] == "start").unwrap()["force_N"]);
    assert!(
        (0..3).all(|k| (clamp[k] + force[k]).abs() < 1e-6),
        "{clamp:?} {force:?}"
    );
}
