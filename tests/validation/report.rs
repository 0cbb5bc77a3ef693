//! `strand report` end to end: solves `cases/cooler_hose.ron` and its variant
//! `hose2_plus50` with `strand solve`, writes the design review of both with
//! `strand report`, and checks that the page is well-formed XHTML naming every hose and
//! result, that its peak table equals the maxima of `|force_N|` and `|moment_Nm|`
//! read from each `result.json`, and that each `rods.vtp` carries the `result.json`
//! values. Bad input (a directory without `result.json`) fails without output.

use std::path::Path;

use serde_json::Value;
use strand_cli::Exit;

use crate::common::{cases_dir, strand};

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

fn solve(dir: &Path, variant: Option<&str>) {
    let case = cases_dir().join("cooler_hose.ron");
    let mut args = vec![
        "solve",
        case.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ];
    if let Some(v) = variant {
        args.extend(["--variant", v]);
    }
    let (exit, out, err) = strand(&args);
    assert_eq!(exit, Exit::Success, "{out}{err}");
}

#[test]
fn report_of_the_cooler_hoses_matches_their_results() {
    let tmp = tempfile::tempdir().unwrap();
    let (base, longer) = (tmp.path().join("base"), tmp.path().join("plus50"));
    solve(&base, None);
    solve(&longer, Some("hose2_plus50"));
    let html_path = tmp.path().join("review/report.html");
    let (exit, out, err) = strand(&[
        "report",
        base.to_str().unwrap(),
        longer.to_str().unwrap(),
        "--out",
        html_path.to_str().unwrap(),
    ]);
    assert_eq!(exit, Exit::Success, "{out}{err}");
    assert!(out.contains("report.html"), "{out}");
    let html = std::fs::read_to_string(&html_path).unwrap();
    let xml = roxmltree::Document::parse(html.strip_prefix("<!DOCTYPE html>\n").unwrap())
        .expect("well-formed XHTML");
    let text: String = xml
        .descendants()
        .filter(|n| n.is_text())
        .filter_map(|n| n.text())
        .collect();
    // Labels: the directory name of the base, the variant's name for the other.
    let labels = ["base", "hose2_plus50"];
    let docs = [
        read_json(&base.join("result.json")),
        read_json(&longer.join("result.json")),
    ];
    for needle in labels
        .iter()
        .chain(&["hose1", "hose2", "hose3", "cooler_hose"])
    {
        assert!(text.contains(needle), "missing {needle}");
    }
    // A plot per hose, a side, top and front view per result, one 3D view.
    let svgs: Vec<_> = xml
        .descendants()
        .filter(|n| n.has_tag_name("svg"))
        .collect();
    let of_class = |class: &str| {
        svgs.iter()
            .filter(|n| n.attribute("class") == Some(class))
            .count()
    };
    assert_eq!(of_class("hose-plot"), 3, "a plot per hose");
    for result in labels {
        let mut views: Vec<&str> = svgs
            .iter()
            .filter(|n| {
                n.attribute("class") == Some("projection")
                    && n.attribute("data-result") == Some(result)
            })
            .filter_map(|n| n.attribute("data-view"))
            .collect();
        views.sort_unstable();
        assert_eq!(views, ["front", "side", "top"], "views of result {result}");
    }
    let three_d = svgs
        .iter()
        .filter(|n| n.attribute("id") == Some("v3d-svg"))
        .count();
    assert_eq!(three_d, 1, "one 3D view");
    assert_eq!(svgs.len(), 3 + 2 * 3 + 1, "no other drawing");

    // The peak table against result.json.
    let table = xml
        .descendants()
        .find(|n| n.attribute("id") == Some("peaks"))
        .expect("peak table");
    let cell_text = |n: roxmltree::Node| -> String {
        n.descendants()
            .filter(|t| t.is_text())
            .filter_map(|t| t.text())
            .collect()
    };
    let headers: Vec<String> = table
        .descendants()
        .filter(|n| n.has_tag_name("th"))
        .map(cell_text)
        .collect();
    let column = |name: &str| headers.iter().position(|h| h == name).unwrap();
    let rows: Vec<_> = table
        .descendants()
        .filter(|n| n.has_tag_name("tr") && n.attribute("data-rod").is_some())
        .collect();
    assert_eq!(rows.len(), 6, "3 hoses × 2 results");
    for row in rows {
        let cells: Vec<String> = row
            .children()
            .filter(|n| n.has_tag_name("td"))
            .map(cell_text)
            .collect();
        let k = labels
            .iter()
            .position(|l| Some(*l) == row.attribute("data-result"))
            .unwrap();
        let rod = docs[k]["rods"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["name"].as_str() == row.attribute("data-rod"))
            .unwrap();
        for (header, key) in [("peak |f| [N]", "force_N"), ("peak |m| [N·m]", "moment_Nm")] {
            let expected = rod[key]
                .as_array()
                .unwrap()
                .iter()
                .map(norm)
                .fold(0.0, f64::max);
            let shown: f64 = cells[column(header)].parse().unwrap();
            assert!(
                (shown - expected).abs() <= 5e-4 * expected,
                "{} {}: {header} shown {shown}, result.json {expected}",
                labels[k],
                rod["name"]
            );
        }
    }
    // The paper's observation, visible in the report: hose 2's peak force drops.
    assert!(html.contains("id=\"differences\""));

    // rods.vtp: the force magnitudes of every vertex, in rod order.
    for (dir, doc) in [(&base, &docs[0]), (&longer, &docs[1])] {
        let vtp = std::fs::read_to_string(dir.join("rods.vtp")).unwrap();
        let xml = roxmltree::Document::parse(&vtp).expect("well-formed VTK XML");
        let array = xml
            .descendants()
            .find(|n| n.attribute("Name") == Some("force_magnitude_N"))
            .unwrap();
        let values: Vec<f64> = array
            .text()
            .unwrap()
            .split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect();
        let expected: Vec<f64> = doc["rods"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|r| r["force_N"].as_array().unwrap().iter().map(norm))
            .collect();
        assert_eq!(values.len(), expected.len());
        for (v, e) in values.iter().zip(&expected) {
            assert!((v - e).abs() <= 1e-12 * e.max(1.0), "{v} {e}");
        }
        let obj = std::fs::read_to_string(dir.join("tubes.obj")).unwrap();
        // One tube per hose, then the T's body and the three connectors.
        let objects: Vec<&str> = obj.lines().filter_map(|l| l.strip_prefix("o ")).collect();
        assert_eq!(objects.len(), 7, "{objects:?}");
        assert_eq!(
            objects
                .iter()
                .filter(|o| o.starts_with("junction_"))
                .count(),
            1
        );
        assert_eq!(
            objects
                .iter()
                .filter(|o| o.starts_with("connector_"))
                .count(),
            3
        );
    }
}

#[test]
fn report_of_a_directory_without_results_fails_cleanly() {
    let tmp = tempfile::tempdir().unwrap();
    let html = tmp.path().join("report.html");
    let missing = tmp.path().join("nothing");
    let (exit, _, err) = strand(&[
        "report",
        missing.to_str().unwrap(),
        "--out",
        html.to_str().unwrap(),
    ]);
    assert_eq!(exit, Exit::InvalidInput, "{err}");
    assert!(
        err.starts_with("error: ") && err.contains("nothing/result.json"),
        "{err}"
    );
    assert!(!html.exists());
    // A result.json that is not one names its line and column.
    std::fs::create_dir(&missing).unwrap();
    std::fs::write(missing.join("result.json"), "{\n  \"case\": 3\n}").unwrap();
    let (exit, _, err) = strand(&[
        "report",
        missing.to_str().unwrap(),
        "--out",
        html.to_str().unwrap(),
    ]);
    assert_eq!(exit, Exit::InvalidInput, "{err}");
    assert!(err.contains("result.json:2:"), "{err}");
    assert!(!html.exists());
}
