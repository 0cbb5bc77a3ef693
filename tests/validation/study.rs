//! Variant studies end to end: `strand study` on `cases/study_demo.ron` (a rubber hose
//! clamped at both ends, and the same hose 50 mm longer), through `strand_cli::run`.
//!
//! Checks that both variants converge; that `study.svg` is well-formed XML with one
//! curve per rod per variant in each panel; that the peaks in `study.csv` are the
//! maxima of `|force_N|` and `|moment_Nm|` in the variants' `result.json`; and that the
//! warm-started variant is the equilibrium a cold solve of the variant finds (to
//! 1e-9 m), reached in fewer Newton iterations.

use std::path::{Path, PathBuf};

use serde_json::Value;
use strand_case::Case;
use strand_cli::Exit;
use strand_solve::solve;

use crate::common::strand;

const VARIANTS: [&str; 2] = ["base", "plus50"];

fn demo_case() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/study_demo.ron")
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn norm(v: &Value) -> f64 {
    let v: Vec<f64> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn max_norm(values: &Value) -> f64 {
    values
        .as_array()
        .unwrap()
        .iter()
        .map(norm)
        .fold(0.0, f64::max)
}

/// Runs the study into a fresh directory; returns it (kept alive) and stdout.
fn run_study() -> (tempfile::TempDir, PathBuf, String) {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("study");
    let case = demo_case();
    let (exit, out, err) = strand(&[
        "study",
        case.to_str().unwrap(),
        "--variants",
        &VARIANTS.join(","),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(exit, Exit::Success, "{out}{err}");
    assert!(err.is_empty(), "{err}");
    (tmp, dir, out)
}

#[test]
fn study_writes_converged_results_a_plot_and_peaks() {
    let (_tmp, dir, out) = run_study();
    let docs: Vec<Value> = VARIANTS
        .iter()
        .map(|v| read_json(&dir.join(v).join("result.json")))
        .collect();
    for (variant, doc) in VARIANTS.iter().zip(&docs) {
        assert_eq!(doc["converged"], true, "{variant}");
        assert_eq!(doc["stable"], true, "{variant}");
        assert_eq!(doc["variant"], *variant);
        assert!(dir.join(variant).join("hose.csv").is_file());
    }
    assert_eq!(docs[0]["warm_start"], false);
    assert!(docs[0].get("base_iterations").is_none());
    assert_eq!(docs[1]["warm_start"], true);
    assert_eq!(docs[1]["base_iterations"], docs[0]["iterations"]);
    // The longer hose is really longer.
    let length = |d: &Value| d["rods"][0]["length_m"].as_f64().unwrap();
    assert!((length(&docs[1]) - length(&docs[0]) - 0.05).abs() < 1e-12);

    // The plot: well-formed XML, one curve per rod per variant in each panel.
    let svg = std::fs::read_to_string(dir.join("study.svg")).unwrap();
    let xml = roxmltree::Document::parse(&svg).expect("study.svg is well-formed XML");
    assert_eq!(xml.root_element().tag_name().name(), "svg");
    let rods: Vec<&str> = docs[0]["rods"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["name"].as_str().unwrap())
        .collect();
    let curves: Vec<_> = xml
        .descendants()
        .filter(|n| n.has_tag_name("path") && n.attribute("class") == Some("curve"))
        .collect();
    assert_eq!(curves.len(), 2 * rods.len() * VARIANTS.len());
    for panel in ["force", "moment"] {
        for variant in VARIANTS {
            for rod in &rods {
                let matching = curves
                    .iter()
                    .filter(|n| {
                        n.attribute("data-panel") == Some(panel)
                            && n.attribute("data-variant") == Some(variant)
                            && n.attribute("data-rod") == Some(rod)
                    })
                    .count();
                assert_eq!(matching, 1, "{panel} {variant} {rod}");
            }
        }
    }

    // The peaks table: the maxima of |force_N| and |moment_Nm| in result.json.
    let csv = std::fs::read_to_string(dir.join("study.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), rods.len() * VARIANTS.len());
    let mut peaks = Vec::new();
    for row in &rows {
        let k = VARIANTS.iter().position(|v| *v == row[0]).unwrap();
        let rod = docs[k]["rods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["name"] == row[1])
            .unwrap();
        let value = |name: &str| row[column(name)].parse::<f64>().unwrap();
        let (force, moment) = (max_norm(&rod["force_N"]), max_norm(&rod["moment_Nm"]));
        assert!(
            (value("peak_force_N") - force).abs() <= 1e-12 * force,
            "{row:?}"
        );
        assert!(
            (value("peak_moment_Nm") - moment).abs() <= 1e-12 * moment,
            "{row:?}"
        );
        peaks.push((force, moment));
    }
    // Changes against the first variant, in %.
    let change = |new: f64, old: f64| 100.0 * (new - old) / old;
    let longer = &rows[1];
    assert_eq!(rows[0][column("force_change_pct")], "");
    let force_change: f64 = longer[column("force_change_pct")].parse().unwrap();
    assert!((force_change - change(peaks[1].0, peaks[0].0)).abs() < 1e-9);
    let moment_change: f64 = longer[column("moment_change_pct")].parse().unwrap();
    assert!((moment_change - change(peaks[1].1, peaks[0].1)).abs() < 1e-9);

    // The terminal table shows the same.
    for needle in [
        "plus50   warm (base: ",
        "peak |f| [N]",
        "peak |m| [N·m]",
        " %",
        "study.svg",
    ] {
        assert!(out.contains(needle), "missing {needle:?} in\n{out}");
    }
}

#[test]
fn warm_started_variant_equals_a_cold_solve_in_fewer_iterations() {
    let (_tmp, dir, _) = run_study();
    let warm = read_json(&dir.join("plus50").join("result.json"));
    let case = Case::from_path(demo_case()).unwrap();
    let built = case.build_variant("plus50", None).unwrap();
    let cold = solve(&built.model, built.initial.clone(), &built.settings).unwrap();
    assert!(cold.report.converged);
    let warm_positions = warm["rods"][0]["position_m"].as_array().unwrap();
    let cold_positions = &cold.state.rods[0].positions;
    assert_eq!(warm_positions.len(), cold_positions.len());
    let mut largest = 0.0f64;
    for (w, c) in warm_positions.iter().zip(cold_positions) {
        for i in 0..3 {
            largest = largest.max((w[i].as_f64().unwrap() - c[i]).abs());
        }
    }
    assert!(
        largest <= 1e-9,
        "warm and cold solutions differ by {largest:e} m"
    );
    let warm_iterations = warm["iterations"].as_u64().unwrap() as usize;
    assert!(
        warm_iterations < cold.report.iterations,
        "warm start: {warm_iterations} iterations, cold start: {}",
        cold.report.iterations
    );
}

#[test]
fn solve_variant_records_the_warm_start_and_bad_names_list_the_variants() {
    let tmp = tempfile::tempdir().unwrap();
    let case = demo_case();
    let dir = tmp.path().join("plus50");
    let (exit, out, err) = strand(&[
        "solve",
        case.to_str().unwrap(),
        "--variant",
        "plus50",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(exit, Exit::Success, "{out}{err}");
    assert!(
        out.contains("variant     plus50 (warm start from the case's solution"),
        "{out}"
    );
    let doc = read_json(&dir.join("result.json"));
    assert_eq!(doc["variant"], "plus50");
    assert_eq!(doc["warm_start"], true);
    assert!(doc["base_iterations"].as_u64().unwrap() >= 1);

    let missing = tmp.path().join("missing");
    for args in [
        vec!["solve", case.to_str().unwrap(), "--variant", "plus60"],
        vec!["study", case.to_str().unwrap(), "--variants", "base,plus60"],
    ] {
        let mut args = args;
        args.extend(["--out", missing.to_str().unwrap()]);
        let (exit, _, err) = strand(&args);
        assert_eq!(exit, Exit::InvalidInput, "{args:?}: {err}");
        assert!(
            err.contains("no variant named 'plus60' (defined: plus50)"),
            "{args:?}: {err}"
        );
        assert!(!missing.exists(), "{args:?} wrote output");
    }
    let (exit, _, err) = strand(&[
        "study",
        case.to_str().unwrap(),
        "--variants",
        "plus50,plus50",
    ]);
    assert_eq!(exit, Exit::InvalidInput);
    assert!(err.contains("listed twice"), "{err}");
}
